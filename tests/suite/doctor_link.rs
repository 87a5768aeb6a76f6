//! Doctor's look at the link itself: a listen-only bit-rate sweep through the simulated
//! slcan adapter (`canctl sim --slcan`), set to another rate than the simulated bus.

use crate::common;

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
/// adapter's bus errors, and the fix names the rate the adapter runs at and the sweep as
/// the way to find the bus's (it named neither).
#[test]
fn without_sweep_no_rate_is_tried() {
    let sim = common::Sim::new();
    let dev = common::DeviceSide::start(&sim, "--slcan", &[]);
    let r = doctor(&format!("{}@125k", dev.uri), &["--window", "300ms"]);
    assert_eq!(r.code, 6, "{}{}", r.stdout, r.stderr);
    assert!(!r.stdout.contains("listen-only at each rate"), "{}", r.stdout);
    assert!(
        r.stdout.contains("the adapter runs at 125k") && r.stdout.contains("canctl doctor --sweep"),
        "{}",
        r.stdout
    );
    let d = doctor(&format!("{}@125k", dev.uri), &["--window", "300ms", "--format", "json"]).json();
    let remedy = &d["findings"][0]["remedy"];
    assert_eq!((&remedy["remedy"], &remedy["kbit"]), (&"check_bus_or_sweep".into(), &125.into()), "{d}");
}

/// `--fault bus:off` on `--bus sim`: the link reports bus-off as a SocketCAN interface does
/// (its error, the controller's state, the bus-off error frame); doctor names it, and a
/// command that needs the bus fails as a link failure whose diagnosis is the bus-off.
#[test]
fn a_bus_off_controller_on_the_sim_bus_is_found() {
    let sim = common::Sim::new();
    sim.run(&["sim", "reset", "--virtual-time", "--fault", "bus:off"]).ok();
    let r = doctor(&sim.bus(), &["5", "--format", "json"]);
    assert_eq!(r.code, 6, "{}{}", r.stdout, r.stderr);
    let d = r.json();
    let first = &d["findings"][0];
    assert_eq!((&first["cause"], &first["state"]), (&"controller".into(), &"bus_off".into()), "{d}");
    assert_eq!(first["remedy"]["remedy"], "check_bus", "{d}");
    let evidence = first["evidence"].as_array().unwrap();
    assert!(evidence.iter().any(|e| e["kind"] == "controller_report" && e["state"] == "bus_off"), "{d}");
    assert!(evidence.iter().any(|e| e["kind"] == "error_frames" && e["counts"]["bus_off"] == 1), "{d}");
    // The sim bus shows traffic: the listen ended at the bus-off, not for want of a link
    // that shows it.
    let human = doctor(&sim.bus(), &["5"]);
    assert!(!(human.stdout.clone() + &human.stderr).contains("shows no traffic"), "{}{}", human.stdout, human.stderr);

    let read = sim.run(&["--format", "json", "sdo", "read", "5", "0x1000"]);
    assert_eq!(read.code, 5, "{}{}", read.stdout, read.stderr);
    let e: serde_json::Value = serde_json::from_str(&read.stderr).expect("the error as JSON on stderr");
    assert!(e["error"].as_str().unwrap().contains("bus-off"), "{e}");
    assert_eq!(e["diagnosis"]["state"], "bus_off", "{e}");
}

/// The same fault behind `sim --slcan`: the adapter's controller sends and hears nothing,
/// and its status flags (Lawicel has no bus-off flag) say error passive and bus error.
#[test]
fn a_bus_off_adapter_reports_its_bus_errors() {
    let sim = common::Sim::new();
    sim.run(&["sim", "reset", "--fault", "bus:off"]).ok();
    let dev = common::DeviceSide::start(&sim, "--slcan", &[]);
    let r = doctor(&dev.uri, &["--window", "300ms", "--format", "json"]);
    assert_eq!(r.code, 6, "{}{}", r.stdout, r.stderr);
    let d = r.json();
    assert_eq!(d["findings"][0]["state"], "bus_errors", "{d}");
    let seen = d["findings"][0]["evidence"][0]["message"].as_str().unwrap();
    assert!(seen.contains("error passive") && seen.contains("bus error"), "{d}");

    let read = dev.run(&["--timeout", "200ms", "sdo", "read", "5", "0x1000"]);
    assert_eq!(read.code, 5, "{}{}", read.stdout, read.stderr);
    assert!(read.stderr.contains("bus error"), "{}", read.stderr);
}

/// Behind a CAN interface or an EPOS2 the controller is not the simulator's: serving the
/// devices there with bus:off would hide the fault, so `canctl sim` refuses (a usage error).
#[test]
fn bus_off_is_served_only_where_it_is_modelled() {
    let sim = common::Sim::new();
    sim.run(&["sim", "reset", "--fault", "bus:off"]).ok();
    for how in [&["--socketcan", "nosuch0"][..], &["--epos2-usb"][..]] {
        let r = sim.run(&[&["sim"][..], how].concat());
        assert_eq!(r.code, 2, "{how:?}: {}{}", r.stdout, r.stderr);
        assert!(r.stderr.contains("bus:off"), "{how:?}: {}", r.stderr);
    }
}
