//! Kernel tests: the same scenarios as on the sim bus, through the Linux CAN stack on
//! vcan0, with `canctl sim --socketcan vcan0` as the devices. They need a kernel with vcan
//! and vcan0 up; `scripts/kernel-tests.sh` runs them in a small VM. Without vcan0 each test
//! prints `SKIPPED name: ...` and passes, or fails where `CANCTL_REQUIRE_KERNEL` is set.

use crate::common;

use common::scenarios::{self, Under};
use common::{Run, Sim};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::{Mutex, MutexGuard};

/// One set of devices on vcan0 at a time: two would answer for the same node-ids.
static BUS: Mutex<()> = Mutex::new(());

/// The demo devices on vcan0, and canctl pointed at vcan0.
struct OnVcan {
    sim: Sim,
    devices: Child,
    _lock: MutexGuard<'static, ()>,
}

impl OnVcan {
    /// `None` (after saying so) when this kernel has no vcan0.
    fn start() -> Option<OnVcan> {
        if !common::has_interface(common::vcan()) {
            return None;
        }
        let lock = BUS.lock().unwrap_or_else(|e| e.into_inner());
        let sim = Sim::new();
        let devices = common::sim_on_interface(&sim, common::vcan());
        Some(OnVcan { sim, devices, _lock: lock })
    }
}

impl Drop for OnVcan {
    fn drop(&mut self) {
        let _ = self.devices.kill();
        let _ = self.devices.wait();
    }
}

impl Under for OnVcan {
    fn run(&self, args: &[&str]) -> Run {
        common::finish(self.command(args).output().unwrap())
    }
    fn iface(&self) -> &str {
        common::vcan()
    }
    fn path(&self, name: &str) -> PathBuf {
        self.sim.path(name)
    }
    fn command(&self, args: &[&str]) -> Command {
        let mut c = Command::new(common::canctl_bin());
        common::isolate(&mut c);
        c.env_remove("CANCTL_BUS").args(["--bus", common::vcan()]).args(args).stdin(Stdio::null());
        c
    }
    /// The kernel tests run in an emulated CPU (TCG), many times slower than hardware.
    fn lss_step(&self) -> &'static str {
        "40ms"
    }
}

macro_rules! on_vcan {
    ($($name:ident),* $(,)?) => {$(
        #[test]
        fn $name() {
            if let Some(bus) = OnVcan::start() {
                scenarios::$name(&bus);
            }
        }
    )*};
}

on_vcan!(
    scan_lists_the_demo_nodes_with_their_identities,
    every_data_type_round_trips,
    untyped_reads_show_bytes_and_the_plain_reading,
    a_long_name_comes_back_whole_by_segmented_transfer,
    the_64k_domain_moves_byte_exact_by_block_and_by_segmented,
    a_device_without_block_transfer_is_read_all_the_same,
    refusals_carry_the_abort_code_and_its_meaning,
    an_absent_node_times_out_with_exit_3,
    verify_catches_a_device_that_ignores_the_write,
    nmt_stop_state_and_reset,
    nmt_state_falls_back_to_node_guarding_with_toggle,
    nmt_all_is_the_only_broadcast,
    store_and_restore_survive_resets_as_on_hardware,
    lss_fastscan_and_assign_number_a_fresh_bus,
    lss_selective_services,
    lss_refusals,
    stream_pdo_yields_the_sensors_values,
    one_pdo_per_sync_with_transmission_type_1,
    map_reconfigures_for_the_session_and_restores,
    ctrl_c_restores_and_exits_130,
);

#[test]
fn a_missing_or_down_interface_is_a_link_failure() {
    let Some(bus) = OnVcan::start() else { return };
    let r = common::bare(&["--bus", "vcan7", "scan"]);
    assert_eq!(r.code, 5);
    assert!(r.stderr.contains("no network interface 'vcan7'"), "{}", r.stderr);
    drop(bus);
    // A second vcan that is down.
    let ip = |args: &[&str]| Command::new("ip").args(args).status().unwrap().success();
    assert!(ip(&["link", "add", "dev", "vcan8", "type", "vcan"]));
    let r = common::bare(&["--bus", "socketcan:vcan8", "scan"]);
    ip(&["link", "del", "vcan8"]);
    assert_eq!(r.code, 5);
    assert!(r.stderr.contains("vcan8 is down"), "{}", r.stderr);
}

#[test]
fn bus_off_during_a_command_is_exit_5() {
    use socketcan::{CanErrorFrame, CanFrame, CanSocket, Socket};
    let Some(bus) = OnVcan::start() else { return };
    // The test's own socket sees canctl's requests. It is open before canctl starts, so
    // none is missed.
    let sock = CanSocket::open(common::vcan()).unwrap();
    sock.set_read_timeout(std::time::Duration::from_millis(200)).unwrap();
    // A long segmented read keeps canctl busy; the controller then reports bus-off.
    let out = bus.path("d.bin");
    let child = bus
        .command(&["sdo", "read", "1", "1F50:1", "--type", "d", "--no-block", "--out"])
        .arg(&out)
        .stderr(Stdio::piped())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    // Every device on the bus sees the bus-off, the simulated ones too (they stop). So it
    // is reported only once canctl is mid-transfer, i.e. has asked for a segment
    // (0x60/0x70 on 0x601): a fixed pause was sometimes too short in the emulated VM, and
    // canctl then found no device answering (exit 3).
    wait_for_a_segment_request(&sock);
    let bus_off = CanErrorFrame::new_error(nix::libc::CAN_ERR_BUSOFF, &[0; 8]).unwrap();
    sock.write_frame(&CanFrame::Error(bus_off)).unwrap();
    let r = common::finish(child.wait_with_output().unwrap());
    assert_eq!(r.code, 5, "{}", r.stderr);
    assert!(r.stderr.contains("bus-off"), "{}", r.stderr);
    assert!(!out.exists(), "a partial upload must not be written");
}

/// --log-frames on SocketCAN: the request and the answer, named by the interface, in the
/// candump log format.
#[test]
fn log_frames_on_socketcan_names_the_interface() {
    let Some(bus) = OnVcan::start() else { return };
    let log = bus.path("frames.log");
    let r = bus.run(&["--log-frames", log.to_str().unwrap(), "sdo", "read", "1", "1018:1"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert_eq!(r.stdout.trim(), "251");
    let text = std::fs::read_to_string(&log).unwrap();
    let iface = common::vcan();
    let frames: Vec<String> = text
        .lines()
        .map(|l| {
            let (time, rest) = l.split_once(") ").unwrap_or_else(|| panic!("not a candump log line: {l}"));
            assert!(time.starts_with('(') && time.len() == 1 + 10 + 1 + 6, "{l}");
            rest.to_string()
        })
        .filter(|f| !f.starts_with(&format!("{iface} 7")))
        .collect();
    let expected = [format!("{iface} 601#4018100100000000"), format!("{iface} 581#43181001FB000000")];
    assert_eq!(frames, expected, "{text}");
}

/// An error frame that is not bus-off is a warning on stderr, once, through the diagnostics
/// (`-q` silences it), and the command goes on.
#[test]
fn an_error_frame_is_one_warning_that_quiet_silences() {
    use socketcan::{CanErrorFrame, CanFrame, CanSocket, Socket};
    let Some(bus) = OnVcan::start() else { return };
    let sock = CanSocket::open(common::vcan()).unwrap();
    sock.set_read_timeout(std::time::Duration::from_millis(200)).unwrap();
    for quiet in [false, true] {
        let out = bus.path("d.bin");
        let mut args = vec!["sdo", "read", "1", "1F50:1", "--type", "d", "--no-block", "--out"];
        if quiet {
            args.insert(0, "-q");
        }
        let child = bus.command(&args).arg(&out).stderr(Stdio::piped()).stdout(Stdio::null()).spawn().unwrap();
        // Mid-transfer (canctl has asked for a segment), the controller reports receive
        // errors: error passive, twice.
        wait_for_a_segment_request(&sock);
        let passive = [0, nix::libc::CAN_ERR_CRTL_RX_PASSIVE as u8, 0, 0, 0, 0, 0, 0];
        for _ in 0..2 {
            let frame = CanErrorFrame::new_error(nix::libc::CAN_ERR_CRTL, &passive).unwrap();
            sock.write_frame(&CanFrame::Error(frame)).unwrap();
        }
        let r = common::finish(child.wait_with_output().unwrap());
        assert_eq!(r.code, 0, "{}", r.stderr);
        assert_eq!(std::fs::read(&out).unwrap().len(), 65536);
        let warnings =
            r.stderr.lines().filter(|l| l.starts_with(&format!("canctl: warning: {}: ", common::vcan()))).count();
        assert_eq!(warnings, if quiet { 0 } else { 1 }, "quiet {quiet}: {}", r.stderr);
    }
}

/// Read the test's own socket until canctl asks node 1 for an upload segment (0x60/0x70 on
/// 0x601): it is then mid-transfer. Bounded by 60 s, which only a canctl that never gets
/// there reaches.
fn wait_for_a_segment_request(sock: &socketcan::CanSocket) {
    use socketcan::{CanFrame, EmbeddedFrame, Frame, Socket};
    let give_up = std::time::Instant::now() + std::time::Duration::from_secs(60);
    loop {
        assert!(std::time::Instant::now() < give_up, "canctl never asked for a segment");
        if let Ok(CanFrame::Data(f)) = sock.read_frame() {
            if f.raw_id() == 0x601 && matches!(f.data().first(), Some(0x60 | 0x70)) {
                return;
            }
        }
    }
}
