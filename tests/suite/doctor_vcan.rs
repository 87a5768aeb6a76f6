//! Kernel tests of doctor's look at the link on vcan (`scripts/kernel-tests.sh doctor`):
//! error frames the kernel delivers, a virtual interface's missing controller, and a
//! transmit queue too short (ENOBUFS). Without vcan0 each test says it is skipped and passes, or
//! fails where `CANCTL_REQUIRE_KERNEL` is set.

use crate::common;

use socketcan::{CanErrorFrame, CanFrame, CanSocket, Socket};
use std::process::{Command, Stdio};
use std::time::Duration;

fn doctor(iface: &str, args: &[&str]) -> Command {
    let mut c = Command::new(common::canctl_bin());
    common::isolate(&mut c);
    c.env_remove("CANCTL_BUS").args(["--bus", iface, "--timeout", "100ms", "doctor", "--format", "json"]);
    c.args(args).stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped());
    c
}

fn ip(args: &[&str]) -> bool {
    Command::new("ip").args(args).status().is_ok_and(|s| s.success())
}

/// A controller alone on its bus reports only ACK errors (CAN_ERR_ACK): doctor says
/// nothing acknowledges, with the counts; vcan0 itself is named a virtual interface, with
/// no controller state made up for it.
#[test]
fn doctor_ack_error_frames_say_nothing_acknowledges_and_vcan_has_no_controller() {
    let iface = common::vcan();
    if !common::has_interface(iface) {
        return;
    }
    let sock = CanSocket::open(iface).unwrap();
    let mut child = doctor(iface, &["--window", "1s"]).spawn().unwrap();
    // What a real controller sends while nobody acknowledges, until doctor is done.
    let ack = CanErrorFrame::new_error(nix::libc::CAN_ERR_ACK, &[0; 8]).unwrap();
    while child.try_wait().unwrap().is_none() {
        sock.write_frame(&CanFrame::Error(ack)).unwrap();
        std::thread::sleep(Duration::from_millis(50));
    }
    let r = common::finish(child.wait_with_output().unwrap());
    assert_eq!(r.code, 6, "{}{}", r.stdout, r.stderr);
    let d = r.json();
    let first = &d["findings"][0];
    assert_eq!(first["cause"], "nothing_acknowledges", "{d}");
    let counts = &first["evidence"][0]["counts"];
    assert!(counts["ack"].as_u64().unwrap() > 0 && counts["ack"] == counts["frames"], "{d}");
    assert_eq!(first["remedy"]["remedy"], "check_termination", "{d}");
    let fine = d["fine"].as_array().unwrap();
    assert!(fine.iter().any(|e| e["kind"] == "no_controller" && e["iface"] == iface), "{d}");
    assert!(!fine.iter().any(|e| e["kind"] == "controller_report"), "{d}");
}

/// A transmit queue of two frames that drains slowly, as a controller's does on a busy bus
/// (vcan itself sends at once, so its queue never fills: a token-bucket qdisc paces it):
/// doctor's read of every node-id is a burst of 127 frames, which finds the queue full
/// (ENOBUFS); the frames wait for room, and doctor names the host and the txqueuelen fix.
#[test]
fn doctor_a_full_transmit_queue_is_the_hosts_finding() {
    if !common::has_interface(common::vcan()) {
        return;
    }
    // Its own interface, whichever the other kernel tests use.
    const IFACE: &str = "vcan9";
    assert!(ip(&["link", "add", "dev", IFACE, "type", "vcan"]));
    // 32 bytes: two CAN frames; at 20 kbit/s about 150 frames a second leave it.
    let paced = ["qdisc", "add", "dev", IFACE, "root", "tbf", "rate", "20kbit", "burst", "64", "limit", "32"];
    // The VM's kernel has the qdisc as a module, under VMCAN_KROOT (scripts/run-in-vm.sh).
    let mut modprobe = Command::new("modprobe");
    if let Some(root) = std::env::var_os("VMCAN_KROOT") {
        modprobe.arg("-d").arg(root);
    }
    let _ = modprobe.arg("sch_tbf").status();
    let set_up =
        ip(&["link", "set", IFACE, "up"]) && Command::new("tc").args(paced).status().is_ok_and(|s| s.success());
    let r = common::finish(doctor(IFACE, &["--window", "100ms"]).output().unwrap());
    ip(&["link", "del", IFACE]);
    assert!(set_up);
    assert_eq!(r.code, 6, "{}{}", r.stdout, r.stderr);
    let d = r.json();
    let host = d["findings"].as_array().unwrap().iter().find(|f| f["cause"] == "host");
    let host = host.unwrap_or_else(|| panic!("{d}"));
    assert_eq!(host["problem"], "transmit_queue_full", "{d}");
    assert_eq!(host["evidence"][0]["kind"], "queue_full", "{d}");
    assert!(host["fix"].as_str().unwrap().contains("txqueuelen 1000"), "{d}");
}
