//! canctl's slcan framing checked against the kernel's: Linux's own `slcand` (can-utils)
//! attaches to `canctl sim --slcan`'s pseudo-terminal and makes it the interface slcan0;
//! canctl over SocketCAN and python-canopen then commission the simulated devices through
//! it. Kernel test (scripts/kernel-tests.sh): it needs the VM's kernel modules.

use crate::common;

use common::Sim;
use std::io::BufRead;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const IFACE: &str = "slcan0";

struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn run(cmd: &str, args: &[&str]) {
    let out = Command::new(cmd).args(args).output().unwrap_or_else(|e| panic!("{cmd}: {e}"));
    assert!(out.status.success(), "{cmd} {args:?}: {}", String::from_utf8_lossy(&out.stderr));
}

/// Wait for `ok` under a bound that only a failure reaches.
fn wait_for(what: &str, mut ok: impl FnMut() -> bool) {
    let give_up = Instant::now() + Duration::from_secs(30);
    while !ok() {
        assert!(Instant::now() < give_up, "{what}: not within 30 s");
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn slcand_on_the_simulated_adapter_carries_canctl_and_python_canopen() {
    // The VM says where its kernel modules are; vcan0 marks a kernel with CAN.
    if !common::has_interface(common::vcan()) {
        return;
    }
    let kroot = std::env::var("VMCAN_KROOT").expect("the kernel-test VM sets VMCAN_KROOT");
    run("modprobe", &["-d", &kroot, "slcan"]);

    let sim = Sim::new();
    let mut adapter = sim.command(&["sim", "--slcan"]).stdout(Stdio::piped()).stderr(Stdio::null()).spawn().unwrap();
    let mut pty = String::new();
    std::io::BufReader::new(adapter.stdout.take().unwrap()).read_line(&mut pty).unwrap();
    let pty = pty.trim().to_string();
    assert!(pty.starts_with("/dev/"), "no pty path printed: '{pty}'");
    let _adapter = Killed(adapter);

    // slcand: close the channel, 500 kbit/s (S6), open; -F stays in the foreground.
    let slcand =
        Command::new("slcand").args(["-F", "-o", "-c", "-s6", &pty, IFACE]).spawn().expect("slcand (can-utils)");
    let _slcand = Killed(slcand);
    wait_for("slcand creates slcan0", || Path::new("/sys/class/net").join(IFACE).exists());
    // slcan's default transmit queue holds 10 frames; python-can's scanner sends 127 at once
    // and gives up on ENOBUFS (canctl waits for room), so the queue gets room as on a real
    // commissioning PC.
    run("ip", &["link", "set", IFACE, "txqueuelen", "1000"]);
    run("ip", &["link", "set", IFACE, "up"]);

    let canctl = |args: &[&str]| {
        let mut c = Command::new(common::canctl_bin());
        // The tests' settings: an answer timeout only a missing answer exceeds (5 s). The
        // emulated VM under load moved 0 of 64 KiB in canctl's default 500 ms.
        common::isolate(&mut c);
        c.env_remove("CANCTL_BUS").args(["--bus", IFACE]).args(args).stdin(Stdio::null());
        common::finish(c.output().unwrap())
    };
    // Through slcand and a pty on the VM's emulated CPU: a scan window only a missing node
    // exceeds.
    let scan = canctl(&["scan", "--window", "2s", "--format", "json"]).ok();
    let nodes: Vec<u64> =
        scan.json()["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect();
    assert_eq!(nodes, [1, 5, 10, 32], "{}", scan.stdout);
    assert_eq!(canctl(&["sdo", "read", "10", "1008", "--type", "vs"]).ok().stdout.trim(), "CAN-2057C");
    let file = sim.path("program.bin");
    let file = file.to_str().unwrap();
    // On failure, the frames.
    let block = canctl(&["-v", "sdo", "read", "1", "1F50:1", "--type", "d", "--out", file]);
    let trace: Vec<&str> = block.stderr.lines().collect();
    assert_eq!(
        block.code,
        0,
        "block read over slcan0 failed; the last frames:\n{}",
        trace[trace.len().saturating_sub(40)..].join("\n")
    );
    assert_eq!(std::fs::metadata(file).unwrap().len(), 65536);
    canctl(&["sdo", "write", "1", "1F50:1", &format!("@{file}"), "--type", "d"]).ok();
    canctl(&["sdo", "write", "5", "1017", "250", "--verify"]).ok();

    // The frames on slcan0 while the client runs (candump, can-utils), for its failure
    // message: a red run says what crossed the link, not only what the client concluded.
    let dump_path = sim.path("candump.log");
    let dump = std::fs::File::create(&dump_path).unwrap();
    let candump = Command::new("candump").args(["-L", IFACE]).stdout(dump).stderr(Stdio::null()).spawn();
    let candump = candump.expect("candump (can-utils)");
    let client = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/interop/client.py");
    let out = Command::new("python3").arg(client).arg(IFACE).output().expect("python3 with canopen");
    drop(Killed(candump));
    if !out.status.success() {
        let frames = std::fs::read_to_string(&dump_path).unwrap_or_default();
        let frames: Vec<&str> = frames.lines().collect();
        let link =
            Command::new("ip").args(["-s", "link", "show", IFACE]).output().map(|o| o.stdout).unwrap_or_default();
        panic!(
            "python-canopen over slcan0:\n{}\n{}\nthe last of {} frames on {IFACE} (candump -L):\n{}\n{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr),
            frames.len(),
            frames[frames.len().saturating_sub(40)..].join("\n"),
            String::from_utf8_lossy(&link)
        );
    }
}
