//! `canctl firmware` as a user runs it, on the simulated bootloader on virtual time:
//! interrupted mid-download it says where the device is, and the same command finishes.

use crate::common;

use common::Sim;

fn image(sim: &Sim, len: usize) -> String {
    let path = sim.path("app.bin");
    std::fs::write(&path, canctl::sim::profiles::domain_pattern(len)).unwrap();
    path.display().to_string()
}

#[test]
fn interrupted_mid_download_then_the_same_command_finishes() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--bootloader", "9", "--virtual-time"]).ok();
    let app = image(&sim, 60_000);
    // SIGINT once the 20th sub-block of the image has been acknowledged.
    let mut c = common::interrupted(sim.command(&["firmware", "download", "9", &app]), "s20:INT");
    let run = common::finish(c.output().unwrap());
    assert_eq!(run.code, 130, "{}{}", run.stdout, run.stderr);
    assert!(run.stdout.contains("interrupted in"), "{}", run.stdout);
    assert!(
        run.stdout.contains("in its bootloader with no valid program; run the same command again"),
        "{}",
        run.stdout
    );
    let status = sim.run(&["firmware", "status", "9", "--format", "json"]).ok().json();
    assert_eq!(status["programs"][0]["software_id"], 0, "{status}");
    let done = sim.run(&["firmware", "download", "9", &app, "--format", "json"]).ok().json();
    assert_eq!(done["device"], "runs_image", "{done}");
    let id = canctl::canopen::program::image_id(&canctl::sim::profiles::domain_pattern(60_000));
    assert_eq!(done["id_after"], id, "{done}");
    let status = sim.run(&["firmware", "status", "9", "--format", "json"]).ok().json();
    assert_eq!(status["programs"][0]["software_id"], id, "{status}");
    assert_eq!(status["programs"][0]["control"], "start", "{status}");
    // Again: it runs the image already, and the report says how to download it anyway.
    let again = sim.run(&["firmware", "download", "9", &app, "--format", "json"]).ok().json();
    assert_eq!(again["skipped"], true, "{again}");
    let said = "it already runs the image (same identification): nothing written; --force downloads anyway";
    assert_eq!(again["state"], said, "{again}");
}

#[test]
fn a_flash_write_error_ends_with_exit_4_and_its_meaning() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--bootloader", "9", "--virtual-time"]).ok();
    sim.run(&["sdo", "write", "9", "0x5F51", "2", "--type", "u8"]).ok();
    let app = image(&sim, 3000);
    let run = sim.run(&["firmware", "download", "9", &app]);
    assert_eq!(run.code, 4, "{}{}", run.stdout, run.stderr);
    assert!(run.stderr.contains("0x1F57:1") && run.stderr.contains("flash write error"), "{}", run.stderr);
    assert!(run.stdout.contains("failed in"), "{}", run.stdout);
}

#[test]
fn several_nodes_give_one_junit_case_each() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--bootloader", "9", "--virtual-time"]).ok();
    let app = image(&sim, 2000);
    let run = sim.run(&["--timeout", "200ms", "--format", "junit", "firmware", "download", "9,42", &app]);
    assert_eq!(run.code, 3, "{}{}", run.stdout, run.stderr);
    assert_eq!(run.stdout.matches("<testcase").count(), 2, "{}", run.stdout);
    assert_eq!(run.stdout.matches("<failure").count(), 1, "{}", run.stdout);
    assert!(run.stdout.contains("node 42"), "{}", run.stdout);
}

/// Through an EPOS2 gateway no boot-up is seen, and the start that the device resets
/// before answering comes back as the gateway's SDO timeout: the device answering again
/// with its program started decides.
#[test]
fn through_an_epos2_gateway_the_start_is_confirmed_by_the_device_answering_again() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--bootloader", "9"]).ok();
    let dev = common::DeviceSide::start(&sim, "--epos2-rs232", &[]);
    let app = image(&sim, 700);
    let done = dev.run(&["firmware", "download", "9", &app, "--format", "json"]).ok().json();
    assert_eq!(done["device"], "runs_image", "{done}");
    assert_eq!(done["confirmed"], true, "{done}");
    let id = canctl::canopen::program::image_id(&canctl::sim::profiles::domain_pattern(700));
    assert_eq!(done["id_after"], id, "{done}");
}

/// `--jobs 2`: both nodes under way at once; the silent one fails, the other gets its image,
/// each its own test case, and the exit code says what failed.
#[test]
fn several_nodes_at_once_give_one_junit_case_each_and_the_silent_one_does_not_stop_the_other() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--bootloader", "9", "--virtual-time"]).ok();
    let app = image(&sim, 2000);
    let args = ["--timeout", "200ms", "--format", "junit", "firmware", "download", "42,9", &app, "--jobs", "2"];
    let run = sim.run(&args);
    assert_eq!(run.code, 3, "{}{}", run.stdout, run.stderr);
    assert_eq!(run.stdout.matches("<testcase").count(), 2, "{}", run.stdout);
    assert_eq!(run.stdout.matches("<failure").count(), 1, "{}", run.stdout);
    let status = sim.run(&["firmware", "status", "9", "--format", "json"]).ok().json();
    let id = canctl::canopen::program::image_id(&canctl::sim::profiles::domain_pattern(2000));
    assert_eq!(status["programs"][0]["software_id"], id, "{status}");
}

#[test]
fn a_failed_node_in_a_batch_is_named_once() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--bootloader", "9", "--virtual-time"]).ok();
    let app = image(&sim, 2000);
    let run = sim.run(&["--timeout", "200ms", "firmware", "download", "42,9", &app, "--no-diagnose"]);
    assert_eq!(run.code, 3, "{}{}", run.stdout, run.stderr);
    assert!(run.stdout.contains("node 42: did not answer"), "{}", run.stdout);
    assert!(!run.stdout.contains("node 42: node 42"), "{}", run.stdout);
}

/// A node named twice would get two downloads into the same program, at once with --jobs:
/// refused as `store 5,5` is, before anything is sent.
#[test]
fn a_node_named_twice_is_refused_before_anything_is_sent() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--bootloader", "9", "--virtual-time"]).ok();
    let app = image(&sim, 200);
    let run = sim.run(&["firmware", "download", "9,9", &app, "--jobs", "2"]);
    assert_eq!(run.code, 2, "{}{}", run.stdout, run.stderr);
    assert!(run.stderr.contains("node 9 is named twice"), "{}", run.stderr);
}

/// Both kinds of bootloader the field has: "start" answered before the reset (Zephyr's,
/// CANopenNode's; the sim's default) and a reset before any answer. Either way the download
/// ends with the device back, its boot-up seen only once the reset's boot time is over (an
/// image swap takes seconds), never before the start.
#[test]
fn a_start_answered_before_or_after_the_reset_ends_with_the_device_back() {
    for answered_first in ["1", "0"] {
        let sim = Sim::new();
        sim.run(&["sim", "reset", "--bootloader", "9", "--virtual-time"]).ok();
        sim.run(&["sdo", "write", "9", "0x5F53", answered_first, "--type", "u8"]).ok();
        sim.run(&["sdo", "write", "9", "0x5F52", "3000", "--type", "u16"]).ok();
        let app = image(&sim, 700);
        let done = sim.run(&["firmware", "download", "9", &app, "--format", "json"]).ok().json();
        assert_eq!(done["device"], "runs_image", "{done}");
        let at = |step: &str| {
            let steps = done["steps"].as_array().unwrap();
            steps.iter().find(|s| s["step"] == step).unwrap_or_else(|| panic!("no {step}: {done}"))["at_ms"].as_u64()
        };
        // The start is sent right after the image's id is checked; its step is said once its
        // write ended (a reset-first device never answers it: then after its timeout).
        let (sent, boot) = (at("id_checked").unwrap(), at("boot_up").unwrap());
        assert!(boot >= sent + 3000, "style {answered_first}: boot-up at {boot} ms, start sent at {sent} ms: {done}");
    }
}

/// `sim reset --bootloader N` refuses a node-id the demo network holds (two devices would
/// answer on it), and its summary says the bootloader is there.
#[test]
fn sim_reset_with_a_bootloader_says_so_and_refuses_a_node_id_in_use() {
    let sim = Sim::new();
    let taken = sim.run(&["sim", "reset", "--bootloader", "5"]);
    assert_eq!(taken.code, 2, "{}", taken.stderr);
    assert!(taken.stderr.contains("node 5 is the demo network's sensor"), "{}", taken.stderr);
    let reset = sim.run(&["sim", "reset", "--bootloader", "9"]).ok();
    assert!(reset.stdout.contains("a CiA 302-3 bootloader on node 9"), "{}", reset.stdout);
}

/// `firmware status` on a node without CiA 302-3's objects (the sensor): said as such, not
/// as a bare SDO abort on 0x1F51:0 (exit 4 still: the node has none to read).
#[test]
fn status_of_a_node_without_a_bootloader_says_so() {
    let sim = Sim::new();
    let r = sim.run(&["firmware", "status", "5"]);
    assert_eq!(r.code, 4, "{}", r.stderr);
    assert_eq!(
        r.stderr.trim(),
        "canctl: node 5 has no program-download objects 0x1F50/0x1F51/0x1F56/0x1F57: no CiA 302-3 bootloader there"
    );
}
