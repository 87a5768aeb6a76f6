use crate::canopen::lss::{FastscanError, Identity};
use crate::canopen::ObjAddr;
use crate::epos2::{Epos2Error, Epos2Problem};
use crate::error::*;
use std::time::Duration;

const OBJ: ObjAddr = ObjAddr { index: 0x1018, sub: 1 };

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

/// Every class is in `ALL` (a class added without it fails to compile here).
#[test]
fn all_lists_every_class() {
    for class in ErrorClass::ALL {
        let position = match class {
            ErrorClass::Usage => 0,
            ErrorClass::Timeout => 1,
            ErrorClass::Refused => 2,
            ErrorClass::Link => 3,
            ErrorClass::Verify => 4,
            ErrorClass::Output => 5,
            ErrorClass::Interrupted => 6,
        };
        assert_eq!(ErrorClass::ALL[position], class);
    }
}

/// The texts are the ones canctl printed when these errors were strings.
#[test]
fn messages_say_what_they_always_said() {
    let cases: Vec<(Error, &str)> = vec![
        (
            Error::NoAnswer { node: 7, what: Service::Sdo(OBJ), waited: ms(500) },
            "node 7: did not answer the SDO transfer of 0x1018:1 (waited 500 ms)",
        ),
        (
            Error::SdoUnfinished {
                node: 7,
                obj: OBJ,
                moved: Moved { bytes: 10, total: Some(100) },
                why: Unfinished::Deadline { budget: ms(2500), timeout: ms(500) },
            },
            "node 7: the SDO transfer of 0x1018:1 did not finish within its deadline of 2.5 s (10 of 100 bytes \
             moved); the deadline follows from the size and --timeout 500 ms",
        ),
        (
            Error::SdoUnfinished {
                node: 7,
                obj: OBJ,
                moved: Moved { bytes: 10, total: None },
                why: Unfinished::NoProgress { waited: ms(500), ignored: 3, last: "60 00 00".into() },
            },
            "node 7: the SDO transfer of 0x1018:1 made no progress for 500 ms (10 bytes moved): the device \
             sent 3 frame(s) that did not advance it (the last: 60 00 00)",
        ),
        (
            Error::SdoUnfinished {
                node: 7,
                obj: OBJ,
                moved: Moved { bytes: 0, total: None },
                why: Unfinished::Silent { waited: ms(500) },
            },
            "node 7: stopped answering during the SDO transfer of 0x1018:1 (waited 500 ms, 0 bytes moved)",
        ),
        (
            Error::NoAnswer { node: 4, what: Service::NmtState { heartbeat: Some(ms(1500)) }, waited: ms(500) },
            "node 4: no heartbeat within 1500 ms and no answer to node guarding within 500 ms",
        ),
        (
            Error::NoAnswer { node: 4, what: Service::NmtState { heartbeat: None }, waited: ms(500) },
            "node 4: no answer to node guarding within 500 ms",
        ),
        (
            Error::NoAnswer { node: 4, what: Service::AfterReset, waited: ms(3000) },
            "node 4: NMT reset sent, but no answer to remote requests within 3000 ms after it; not confirmed. \
             Check the node with `canctl scan`, or wait longer (--wait)",
        ),
        (Error::NoAnswer { node: 4, what: Service::BootUp, waited: ms(3000) }, "node 4: no boot-up within 3000 ms"),
        (
            Error::NoAnswer { node: 0, what: Service::BootUp, waited: ms(3000) },
            "all nodes: no boot-up within 3000 ms",
        ),
        (
            Error::StoreRefused { node: 5, command: ParameterCommand::Restore, why: StoreRefusal::NoObject { index: 0x1011 } },
            "node 5 has no object 0x1011: it cannot restore parameters",
        ),
        (
            Error::StoreRefused {
                node: 5,
                command: ParameterCommand::Store,
                why: StoreRefusal::NotOffered {
                    class: "manufacturer parameters",
                    index: 0x1010,
                    highest: 1,
                    offered: vec!["all parameters"],
                },
            },
            "node 5 cannot store manufacturer parameters (0x1010:0 = 1; it offers: all parameters)",
        ),
        (
            Error::StoreRefused {
                node: 5,
                command: ParameterCommand::Store,
                why: StoreRefusal::NotOnCommand {
                    class: "all parameters",
                    obj: ObjAddr { index: 0x1010, sub: 1 },
                    caps: 2,
                    saves_itself: true,
                },
            },
            "node 5 does not store all parameters on command (0x1010:1 = 0x00000002): it saves them by itself",
        ),
        (
            Error::ReadBackMany { node: 5, objects: vec![OBJ, ObjAddr { index: 0x2000, sub: 0 }] },
            "node 5: 0x1018:1, 0x2000:0 read back other values than written",
        ),
        (
            Error::OtherDevice {
                file: "a.dcf".into(),
                differences: vec!["vendor-ID 0x00000001 on node 5, 0x00000002 in the file".into()],
            },
            "a.dcf is for another device: vendor-ID 0x00000001 on node 5, 0x00000002 in the file. Nothing was \
             written; --force applies it anyway",
        ),
        (
            Error::NoRemoteAnswer { cob: 0x705, waited: ms(300) },
            "no answer to the remote request for 0x705 within 300 ms",
        ),
        (
            Error::NoLssAnswer { request: "set-id".into(), identity: None, waited: ms(100) },
            "no LSS device answered set-id within 100 ms",
        ),
        (
            Error::NoLssAnswer {
                request: "the selective switch".into(),
                identity: Some(Identity { vendor: 1, product: 2, revision: 3, serial: 4 }),
                waited: ms(100),
            },
            "no LSS device with identity 0x00000001:0x00000002:0x00000003:0x00000004 answered the selective \
             switch within 100 ms",
        ),
        (
            Error::LssSetIdUnknown {
                identity: Identity { vendor: 0x40, product: 2, revision: 3, serial: 4 },
                node: 20,
                tries: 3,
                waited: ms(200),
            },
            "no answer from 0x00000040:0x00000002:0x00000003:0x00000004 to set-id 20 within 200 ms, asked 3 \
             times: unknown whether it holds node 20 now (canctl lss inquire --identity \
             0x00000040:0x00000002:0x00000003:0x00000004 shows its node-id)",
        ),
        (
            Error::LssRefused { service: "store".into(), cs: 0x17, error: 1, specific: 0 },
            "LSS store: error 1: store configuration not supported",
        ),
        (
            Error::LssRefused { service: "set-id".into(), cs: 0x11, error: 255, specific: 9 },
            "LSS set-id: error 255: implementation-specific error (see the specific code) (specific code 9)",
        ),
        (
            Error::Epos2NoCanAnswer { node: 3, command: "ReadObject", obj: Some(OBJ) },
            "node 3: ReadObject of 0x1018:1: no answer on the CAN bus (the EPOS2 reports SDO timeout 0x05040000)",
        ),
        (
            Error::Epos2Refused { node: 0, command: "SendNMTService", obj: None, code: 0x0602_0000 },
            "node 0: SendNMTService: error 0x06020000: Object does not exist in the object dictionary",
        ),
        (
            Error::Epos2Refused {
                node: 2,
                command: "WriteObject",
                obj: Some(OBJ),
                code: crate::epos2::command::WRONG_NMT_STATE,
            },
            "node 2: WriteObject of 0x1018:1: EPOS2 error 0x0F00FFC0: Device is in wrong NMT state",
        ),
        (
            Error::NodeIdOutOfRange { node: 0, range: NodeIdRange::CanOpen },
            "node-id 0 is only for an EPOS2 on an epos2-rs232/epos2-usb bus; here use 1 to 127",
        ),
        (
            Error::NodeIdOutOfRange { node: 200, range: NodeIdRange::CanOpen },
            "node-id 200 is out of range: use 1 to 127",
        ),
        (
            Error::NodeIdOutOfRange { node: 200, range: NodeIdRange::Epos2 },
            "node-id 200 is out of range: use 0 (the EPOS2 itself) or 1 to 127",
        ),
        (
            Error::SlcanBitRate { port: "slcan:x".into(), kbit: 83, supported: vec!["10k".into(), "20k".into()] },
            "slcan:x: slcan has no 83 kbit/s; use one of 10k 20k",
        ),
        (
            Error::AdapterNoAnswer { port: "slcan:x".into(), command: "S6".into(), waited: ms(200) },
            "slcan:x: the adapter did not answer \"S6\" within 200 ms",
        ),
        (
            Error::NotOfType { node: 5, obj: OBJ, bytes: vec![1, 2, 3], dtype: crate::canopen::DataType::U32 },
            "node 5: 0x1018:1 holds 3 byte(s) (010203), which is not a u32 (4 bytes); try another --type",
        ),
        (
            Error::NotOfType { node: 5, obj: OBJ, bytes: vec![0, 0xD8, 0x41], dtype: crate::canopen::DataType::Unicode },
            "node 5: 0x1018:1 holds 3 byte(s) (00D841), which is not UTF-16 text (us); try another --type",
        ),
        (
            Error::NoSuchTpdo { node: 5, pdo: 9, comm: 0x1808 },
            "node 5 has no TPDO9 (no object 0x1808); without --tpdo, every TPDO it has is streamed",
        ),
        (Error::NoValidTpdo { node: 5 }, "node 5 has no valid TPDO to stream (--map makes one for the session)"),
        (
            Error::InquiryAnsweredByMany { count: 3 },
            "3 devices answered the global inquiry: address one with --identity (lss fastscan finds them)",
        ),
        (
            Error::Fastscan { error: FastscanError::Unconfirmed(2), step: ms(10) },
            "fastscan: identity part 2 was found but not confirmed, even with a 10 ms step (a device changed \
             state, or frames were lost); try again, or a longer --step",
        ),
        (
            Error::DriveStopped { node: 3, goal: "enable", state: "Fault".into(), why: DriveStop::FaultPresent },
            "node 3: enable stopped in Fault: fault present (canctl drive fault-reset NODE clears it once its cause \
             is gone)",
        ),
        (
            Error::DriveStopped { node: 3, goal: "fault-reset", state: "Fault".into(), why: DriveStop::FaultRemains },
            "node 3: fault-reset stopped in Fault: the fault remains after the reset: its cause is still there \
             (canctl drive status NODE shows the errors)",
        ),
        (
            Error::LssCrowded { identity: Identity { vendor: 1, product: 2, revision: 3, serial: 4 }, times: 2 },
            "0x00000001:0x00000002:0x00000003:0x00000004 was selected 2 time(s) with another device in LSS \
             configuration state too (one that misses the switch back to waiting); no node-id given, as both would \
             take it \
             (`canctl scan` lists the devices left in configuration state)",
        ),
        (
            Error::LssLeftInConfiguration { tries: 3 },
            "a device still answers in LSS configuration state after every device was sent back to waiting 3 \
             times (it misses the switch): `canctl scan` lists it; power-cycle it if it stays there",
        ),
        (
            Error::DcfNotReadWhole {
                first: Box::new(crate::od::lint::Warning::new("m.dcf", 9, crate::od::lint::Kind::Other, "no such type".into())),
                file: "m.dcf".into(),
                errors: 2,
            },
            "m.dcf:9: no such type; m.dcf has 2 error(s) against CiA 306, so its values are not all read: nothing \
             is compared or written (canctl config check m.dcf lists them)",
        ),
        (
            Error::NotADcf { file: "m.eds".into() },
            "m.eds has no ParameterValue: it is an EDS, not a DCF (canctl config dump makes one)",
        ),
        (
            Error::Fastscan { error: FastscanError::NoDevice, step: ms(10) },
            "no device without a node-id answered the fastscan",
        ),
        (
            Error::Fastscan { error: FastscanError::NoMatch { part: 1, value: 0x1234 }, step: ms(10) },
            "no device without a node-id has product code 0x00001234 (waited up to 10 ms a step)",
        ),
        (
            Error::NoFreeNodeId {
                start: 120,
                identity: Identity { vendor: 1, product: 2, revision: 3, serial: 4 },
            },
            "no free node-id left from 120 to 127 for 0x00000001:0x00000002:0x00000003:0x00000004: give a lower --start",
        ),
        (
            Error::ReadBack { node: 5, obj: OBJ, wrote: "7".into(), read: "8".into() },
            "node 5: 0x1018:1 reads back 8 after writing 7",
        ),
        (
            LinkError::SdoProtocol {
                node: 5,
                obj: OBJ,
                reason: "toggle bit not alternated".into(),
                aborted: Some(0x0503_0000),
            }
            .into(),
            "node 5: SDO transfer of 0x1018:1 failed: toggle bit not alternated (aborted with 0x05030000)",
        ),
        (LinkError::Io { port: "can0".into(), op: "", error: std::io::Error::other("gone").into() }.into(), "can0: gone"),
        (
            LinkError::Io { port: "can0".into(), op: "send failed", error: std::io::Error::other("gone").into() }.into(),
            "can0: send failed: gone",
        ),
        (
            LinkError::AdapterRefusedFrame { port: "slcan:x".into(), cob: Some(0), flags: vec!["bus error"] }
                .into(),
            "slcan:x: the adapter refused to send 000 (bus error)",
        ),
        (
            LinkError::AdapterRefusedFrame { port: "slcan:x".into(), cob: None, flags: vec![] }.into(),
            "slcan:x: the adapter refused a frame",
        ),
        (
            Epos2Error::Answer {
                bus: "epos2-usb:/dev/x".into(),
                problem: Epos2Problem::TooShort { command: "ReadObject" },
            }
            .into(),
            "epos2-usb:/dev/x: the answer to ReadObject is too short",
        ),
        (LinkError::Pty { op: PtyOp::Poll, detail: "EINTR".into() }.into(), "pty poll: EINTR"),
        (
            LinkError::StateFile {
                path: "/tmp/s.json".into(),
                what: "cannot read",
                detail: "denied".into(),
                afresh: false,
            }
            .into(),
            "sim state file /tmp/s.json: cannot read: denied",
        ),
        (
            LinkError::StateFile {
                path: "/tmp/s.json".into(),
                what: "has another format version",
                detail: "9".into(),
                afresh: true,
            }
            .into(),
            "sim state file /tmp/s.json: has another format version: 9 (`canctl sim reset` starts afresh)",
        ),
    ];
    for (error, text) in cases {
        // What canctl prints: the message, then the remedy it words (`output/hints.rs`).
        assert_eq!(crate::output::library_error_text(&error), text);
        if super::remedies::error_remedy(&error).is_some() {
            let message = error.to_string();
            assert!(!message.contains("--"), "the remedy is the front end's, not the message's: {error}");
            assert!(!names_a_command(&message), "the remedy is the front end's, not the message's: {error}");
        }
    }
}

/// The link failures, likewise.
#[test]
fn link_messages_say_what_they_always_said() {
    use crate::epos2::transport::Failure;
    let cases: Vec<(LinkError, &str)> = vec![
        (
            LinkError::NoInterface { iface: "can9".into(), available: vec![] },
            "there is no network interface 'can9' (CAN interfaces here: none).\n  \
             A CAN adapter: plug it in, then sudo ip link set can9 up type can bitrate 500000\n  \
             A virtual bus: sudo ip link add dev can9 type vcan && sudo ip link set up can9\n  \
             No hardware: try the demo network, --bus sim",
        ),
        (
            LinkError::NoInterface { iface: "cna0".into(), available: vec!["can0".into(), "vcan0".into()] },
            "there is no network interface 'cna0'; did you mean --bus can0? (CAN interfaces here: can0, vcan0).\n  \
             A CAN adapter: plug it in, then sudo ip link set cna0 up type can bitrate 500000\n  \
             A virtual bus: sudo ip link add dev cna0 type vcan && sudo ip link set up cna0\n  \
             No hardware: try the demo network, --bus sim",
        ),
        (
            LinkError::SimInUse { holder: "pid 7 (canctl sim)".into(), waited: Duration::from_secs(10), serving: None },
            "the sim network is in use by pid 7 (canctl sim) (waited 10 s): it serves one command at a \
             time; stop that one, or serve the network where several commands share it as on a real bus \
             (`canctl sim --socketcan vcan0`, then --bus vcan0); --bus sim:OTHER.state would be another network, \
             not this one",
        ),
        (LinkError::NotCan { iface: "eth0".into() }, "'eth0' is not a CAN interface"),
        (
            LinkError::Down { iface: "can0".into() },
            "can0 is down: bring it up first (e.g. sudo ip link set can0 up type can bitrate 500000)",
        ),
        (
            LinkError::BusOff { iface: "can0".into(), detail: "bus off".into() },
            "can0: the controller went bus-off (bus off)",
        ),
        (
            LinkError::TxQueueFull { iface: "can0".into(), waited: Duration::from_secs(2) },
            "can0: the transmit queue stayed full for 2 s (no other node acknowledging? bus-off?)",
        ),
        (
            LinkError::AdapterRefused { port: "slcan:x".into(), what: "open the channel" },
            "slcan:x: the adapter refused to open the channel; is it an slcan (Lawicel) adapter, and not in use \
             by another program?",
        ),
        (
            LinkError::AdapterBusError { port: "slcan:x".into(), flags: vec!["bus error", "error passive"] },
            "slcan:x: the adapter reports bus error, error passive: check the wiring, the termination and the \
             bit rate",
        ),
        (
            LinkError::AdapterRefusedFrame { port: "slcan:x".into(), cob: Some(0x601), flags: vec![] },
            "slcan:x: the adapter refused to send 601",
        ),
        (
            Epos2Error::Serial {
                bus: "epos2-rs232:/dev/x".into(),
                command: "ReadObject",
                failure: Failure::Timeout("to the OpCode"),
                retry: None,
            }
            .into(),
            "epos2-rs232:/dev/x: ReadObject failed: no answer to the OpCode; check the cable, the bit rate \
             (?baud=) and that no other program uses the port; a slow device may need a \
             longer --timeout",
        ),
        (
            Epos2Error::Serial {
                bus: "epos2-rs232:/dev/x".into(),
                command: "ReadObject",
                failure: Failure::Misfit(3),
                retry: Some(Failure::Io(std::io::Error::other("gone").into())),
            }
            .into(),
            "epos2-rs232:/dev/x: ReadObject failed: 3 answers in a row that do not answer this command \
             (discarded); after a resync and retry: the port failed: gone; check that the device is connected \
             and powered, then run the command again",
        ),
        (
            Epos2Error::Answer { bus: "b".into(), problem: Epos2Problem::EmptySegment }.into(),
            "b: empty SegmentRead answer",
        ),
        (
            Epos2Error::Answer { bus: "b".into(), problem: Epos2Problem::ToggleNotAlternated { node: 2, obj: OBJ } }
                .into(),
            "node 2: segmented read of 0x1018:1: toggle bit not alternated",
        ),
        (
            Epos2Error::Answer { bus: "b".into(), problem: Epos2Problem::ShortSegment { node: 2, claimed: 7 } }.into(),
            "node 2: segment claims 7 bytes but carries fewer",
        ),
        (
            Epos2Error::Answer {
                bus: "b".into(),
                problem: Epos2Problem::EmptySegments { node: 2, obj: OBJ, count: 8 },
            }
            .into(),
            "node 2: segmented read of 0x1018:1: 8 segments in a row without data that say more follow; \
             stopped. The device's SDO server is stuck: reset the node (`canctl nmt reset 2`) and read again",
        ),
        (
            Epos2Error::Answer {
                bus: "b".into(),
                problem: Epos2Problem::TooLong { node: 2, obj: OBJ, bytes: 1048576, limit_kib: 1024 },
            }
            .into(),
            "node 2: segmented read of 0x1018:1: 1048576 bytes and the device still says more follow; stopped \
             at the limit of 1024 KiB for reads through an EPOS2. A value this large is read over SocketCAN \
             (block transfer); otherwise the device is faulty: reset it",
        ),
        (
            Epos2Error::Answer { bus: "b".into(), problem: Epos2Problem::ExtraSegment { node: 2, obj: OBJ } }.into(),
            "node 2: segmented write of 0x1018:1: the EPOS2 confirmed another segment",
        ),
        (LinkError::Pty { op: PtyOp::Create, detail: "ENOSPC".into() }, "cannot create a pseudo-terminal: ENOSPC"),
    ];
    for (error, text) in cases {
        // What canctl prints: the message, then the remedy it words (`output/hints.rs`).
        let error = Error::from(error);
        assert_eq!(crate::output::library_error_text(&error), text);
        if super::remedies::error_remedy(&error).is_some() {
            let message = error.to_string();
            assert!(!message.contains("--"), "the remedy is the front end's, not the message's: {error}");
            assert!(!names_a_command(&message), "the remedy is the front end's, not the message's: {error}");
        }
    }
    let usage = [
        (
            Error::TooLargeForSdo { len: 5_000_000_000 },
            "5000000000 bytes cannot be written by SDO: CiA 301 sizes are 32-bit (at most 4294967295 bytes)",
        ),
        (
            Error::BadBusAddr { uri: "sim:".into(), reason: "sim: needs a state file path".into() },
            "bus 'sim:': sim: needs a state file path",
        ),
        (
            Error::NotOnThisBus {
                bus: "epos2-usb:/dev/x".into(),
                why: "remote frames go through RequestCANFrame; use a request",
            },
            "epos2-usb:/dev/x: remote frames go through RequestCANFrame; use a request",
        ),
        (
            Error::OutOfRange {
                object: ObjAddr::new(0x6060, 0),
                value: "99".into(),
                low: -128,
                high: 10,
                dictionary: "from the dictionary".into(),
            },
            "99 is outside the range of 0x6060:0: use -128 to 10 (from the dictionary); nothing was written",
        ),
    ];
    for (error, text) in usage {
        assert_eq!(error.exit_code(), 2);
        assert_eq!(error.to_string(), text);
    }
}

#[test]
fn advice_is_appended_and_keeps_the_exit_code() {
    let silent = || Error::NoAnswer { node: 7, what: Service::Sdo(OBJ), waited: ms(500) };
    let e = silent().advised(Advice::Near(vec!["0x1017:0".into(), "heartbeat".into()]));
    assert_eq!(
        e.to_string(),
        "node 7: did not answer the SDO transfer of 0x1018:1 (waited 500 ms); did you mean 0x1017:0, heartbeat?"
    );
    assert_eq!(e.exit_code(), 3);
    assert!(matches!(e.root(), Error::NoAnswer { node: 7, .. }));
    let stored = silent().advised(Advice::SentOnce { node: 7, command: ParameterCommand::Store });
    assert!(
        stored.to_string().ends_with(
            "; the store was sent once and may have been done: unknown whether node 7 stored its parameters"
        ),
        "{stored}"
    );
    let restored = silent().advised(Advice::SentOnce { node: 7, command: ParameterCommand::Restore });
    assert!(restored.to_string().ends_with("unknown whether node 7 restored its defaults"), "{restored}");
    let taken = Error::Link(LinkError::Open {
        port: "TCP 0.0.0.0:29536".into(),
        error: std::io::Error::from(std::io::ErrorKind::AddrInUse).into(),
    });
    let taken = taken.advised(Advice::PortTaken);
    assert!(taken.to_string().ends_with("; serve on another port, or on port 0 for any free one"), "{taken}");
    assert_eq!(taken.exit_code(), 5);
}

#[test]
fn a_fastscan_that_could_not_confirm_is_a_link_failure_the_others_are_timeouts() {
    let step = ms(10);
    assert_eq!(Error::Fastscan { error: FastscanError::Unconfirmed(2), step }.exit_code(), 5);
    assert_eq!(Error::Fastscan { error: FastscanError::Lost, step }.exit_code(), 3);
    assert_eq!(Error::Fastscan { error: FastscanError::NoDevice, step }.exit_code(), 3);
}

/// A link failure prints once: its cause is in its text, not repeated as a source.
#[test]
fn a_link_error_has_no_source_to_print_twice() {
    use std::error::Error as _;
    let e: Error = LinkError::Open { port: "/dev/x".into(), error: std::io::Error::other("gone").into() }.into();
    assert!(e.source().is_none());
    assert_eq!(e.to_string(), "cannot open /dev/x: gone");
}

/// The final error of a run on several buses names the worst bus, but not its failure
/// again: the report has said each bus's failure just before.
#[test]
fn the_worst_of_several_buses_is_named_and_its_failure_not_said_twice() {
    let state =
        LinkError::StateFile { path: "/tmp/s.json".into(), what: "cannot save", detail: "full".into(), afresh: false };
    let worst = Box::new(crate::ops::unmet::Shortfall::Failed(state.into()));
    let on = crate::ops::unmet::Shortfall::OnBuses { bus: "sim:/tmp/s.json".into(), worst, failed: 1, total: 2 };
    assert_eq!(on.exit_code(), 5, "the worst failure's exit code");
    let said = crate::output::CommandError::from(on);
    assert_eq!(said.text(), "1 of 2 buses failed, each as said for its bus; the worst was on sim:/tmp/s.json");
    assert_eq!(said.exit_code(), (5, true));
}

/// Whether a message names a canctl command (`` `canctl scan` ``, `(canctl nmt reset 2)`):
/// the command line's to say, in a remedy. A process named as data (`pid 7 (canctl sim)`)
/// is not a command to run.
fn names_a_command(message: &str) -> bool {
    message.match_indices("canctl ").any(|(i, _)| {
        let rest = &message[i + "canctl ".len()..];
        let word_then = rest.trim_start_matches(|c: char| c.is_ascii_lowercase()).chars().next();
        match message[..i].chars().last() {
            Some('`') => true,
            Some('(') => word_then != Some(')'),
            _ => false,
        }
    })
}
