//! Doctor's look at the link itself: a listen-only bit-rate sweep through the simulated
//! slcan adapter (`canctl sim --slcan`), set to another rate than the simulated bus.

mod common;

fn doctor(uri: &str, args: &[&str]) -> common::Run {
    let mut c = std::process::Command::new(common::canctl_bin());
    common::isolate(&mut c);
    c.env_remove("CANCTL_BUS").args(["--bus", uri, "--timeout", "200ms", "doctor"]);
    common::finish(c.args(args).output().unwrap())
}

/// An adapter opened at 125k on the 500k bus hears nothing but bus errors; the sweep
/// listens at each rate and names 500k, the one where the heartbeats decode cleanly.
#[test]
fn a_sweep_names_the_rate_the_bus_runs_at() {
    let sim = common::Sim::new();
    let dev = common::DeviceSide::start(&sim, "--slcan", &[]);
    let wrong = format!("{}@125k", dev.uri);
    let r = doctor(&wrong, &["--window", "300ms", "--sweep", "--sweep-window", "300ms", "--format", "json"]);
    assert_eq!(r.code, 6, "{}{}", r.stdout, r.stderr);
    let d = r.json();
    let found = d["findings"].as_array().unwrap();
    // First: it explains the adapter's bus errors.
    let named = &found[0];
    assert_eq!(named["cause"], "other_bit_rate", "{d}");
    assert_eq!(named["kbit"], 500, "{d}");
    assert_eq!(named["remedy"]["remedy"], "use_bit_rate", "{d}");
    let trials = named["evidence"][0]["trials"].as_array().unwrap();
    assert_eq!(trials.len(), 8, "{d}");
    for t in trials {
        let clean = t["frames"].as_u64().unwrap() > 0 && t["errors"] == false;
        assert_eq!(clean, t["kbit"] == 500, "{t}");
    }
    // After the sweep the adapter is back at its own rate, and at the right one all is well.
    let ok = doctor(&dev.uri, &["--window", "300ms", "--sweep", "--sweep-window", "300ms"]);
    assert_eq!(ok.code, 0, "{}{}", ok.stdout, ok.stderr);
    assert!(ok.stdout.contains("500k: ") && ok.stdout.contains("clean"), "{}", ok.stdout);
}

/// Without --sweep the adapter's rate is never changed: the wrong rate shows as the
/// adapter's bus errors, with the sweep named as the way to find the rate.
#[test]
fn without_sweep_no_rate_is_tried() {
    let sim = common::Sim::new();
    let dev = common::DeviceSide::start(&sim, "--slcan", &[]);
    let r = doctor(&format!("{}@125k", dev.uri), &["--window", "300ms"]);
    assert_eq!(r.code, 6, "{}{}", r.stdout, r.stderr);
    assert!(!r.stdout.contains("listen-only at each rate"), "{}", r.stdout);
}
