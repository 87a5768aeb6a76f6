//! canctl downloads into a CiA 302-3 bootloader written on python-canopen after the rules of
//! Zephyr's canopen_program.c (tests/interop/program_device.py), on vcan0. A kernel test
//! (scripts/kernel-tests.sh firmware): without vcan0 it says SKIPPED and passes, or fails
//! where CANCTL_REQUIRE_KERNEL is set.

use crate::common;

use std::io::BufRead;
use std::path::Path;
use std::process::{Command, Stdio};

#[test]
fn canctl_downloads_into_a_python_canopen_bootloader() {
    if !common::has_interface(common::vcan()) {
        return;
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/interop/program_device.py");
    let mut child = Command::new("python3")
        .arg(script)
        .args([common::vcan(), "21"])
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("python3 with canopen (pip install -r tests/interop/requirements.txt)");
    let mut lines = std::io::BufReader::new(child.stdout.take().unwrap()).lines();
    assert_eq!(lines.next().unwrap().unwrap().trim(), "READY");
    let sim = common::Sim::new();
    let image = sim.path("app.bin");
    let data = canctl::sim::profiles::domain_pattern(5000);
    std::fs::write(&image, &data).unwrap();
    let mut c = Command::new(common::canctl_bin());
    common::isolate(&mut c);
    c.env_remove("CANCTL_BUS").args(["--bus", common::vcan(), "--timeout", "2s", "firmware", "download", "21"]);
    c.arg(&image).args(["--format", "json"]).stdin(Stdio::null());
    let run = common::finish(c.output().unwrap());
    let _ = child.kill();
    let mut seen: Vec<serde_json::Value> = Vec::new();
    for line in lines.map_while(Result::ok) {
        seen.push(serde_json::from_str(&line).unwrap());
    }
    let _ = child.wait();
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    let report: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    let crc = canctl::canopen::program::image_id(&data);
    assert_eq!(report["id_after"], crc, "{report}");
    assert_eq!(report["confirmed"], true, "{report}");
    // The peer holds what canctl reports: the image whole, and the commands in order.
    let download: Vec<_> = seen.iter().filter(|l| l.get("download").is_some()).collect();
    assert_eq!(download.len(), 1, "{seen:?}");
    assert_eq!((download[0]["download"].as_u64(), download[0]["crc32"].as_u64()), (Some(5000), Some(crc.into())));
    let controls: Vec<u64> = seen.iter().filter_map(|l| l["control"].as_u64()).collect();
    assert_eq!(controls, [0, 3, 1, 0x80], "{seen:?}");
}
