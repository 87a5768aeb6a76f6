//! A program-download master written on python-canopen after the sequence of Zephyr's west
//! runner (tests/interop/program_master.py) downloads into canctl's simulated CiA 302-3
//! bootloader, served behind an slcan pseudo-terminal (no kernel CAN needed); canctl then
//! reports what the peer wrote. Skipped, saying so, where python-canopen or pyserial is
//! missing (tests/interop/requirements.txt).

use crate::common;

use std::path::Path;
use std::process::Command;

fn python_has_peer() -> bool {
    Command::new("python3").args(["-c", "import canopen, serial"]).output().is_ok_and(|o| o.status.success())
}

#[test]
fn a_python_canopen_master_downloads_into_the_simulated_bootloader() {
    if !python_has_peer() {
        common::skipped("python3 with canopen and pyserial (tests/interop/requirements.txt)");
        return;
    }
    let sim = common::Sim::new();
    sim.run(&["sim", "reset", "--bootloader", "9"]).ok();
    let dev = common::DeviceSide::start(&sim, "--slcan", &[]);
    let image = sim.path("app.bin");
    std::fs::write(&image, canctl::sim::profiles::domain_pattern(3000)).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/interop/program_master.py");
    let out = Command::new("python3").arg(script).args([&dev.pty, "slcan", "9"]).arg(&image).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    let peer: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
    let crc = canctl::canopen::program::image_id(&canctl::sim::profiles::domain_pattern(3000));
    assert_eq!((peer["written"].as_u64(), peer["after"].as_u64()), (Some(crc.into()), Some(crc.into())), "{stdout}");
    assert_eq!(peer["control"], 1, "confirmed: {stdout}");
    // As Zephyr's runner does: the start answered, then the boot-up waited for, and seen (the
    // sim's bootloader resets after its answer and boots for a while, as real ones do).
    assert_eq!(peer["start"], "answered", "{stdout}");
    // canctl's report matches what the peer holds.
    let status = dev.run(&["firmware", "status", "9", "--format", "json"]).ok().json();
    assert_eq!(status["programs"][0]["software_id"], crc, "{status}");
    assert_eq!(status["programs"][0]["control"], "start", "{status}");
    assert_eq!(status["programs"][0]["flash_status"]["raw"], 0, "{status}");
}
