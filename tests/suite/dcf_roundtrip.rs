//! DCF files written by `config dump` read back to the same bytes on the device, and input
//! files are bounded: the real binary on the simulated network.

use crate::common;

use common::Sim;
use std::time::Duration;

/// `sdo write` of raw bytes through a value file.
fn write_bytes(sim: &Sim, obj: &str, dtype: &str, bytes: &[u8]) {
    let file = sim.path("value.bin");
    std::fs::write(&file, bytes).unwrap();
    let at = format!("@{}", file.display());
    sim.run(&["sdo", "write", "10", obj, &at, "--type", dtype]).ok();
}

fn dump(sim: &Sim, name: &str) -> (Vec<u8>, String) {
    let path = sim.path(name);
    // The simulator's EDS has the entry of every type (0x5FF0).
    let eds = format!("10={}/eds/canctl-sim-io.eds", env!("CARGO_MANIFEST_DIR"));
    let run = sim.run(&["--eds", &eds, "config", "dump", "10", "--out", path.to_str().unwrap()]).ok();
    (std::fs::read(&path).unwrap(), run.stderr)
}

#[test]
fn dump_apply_dump_gives_the_same_file() {
    let sim = Sim::new();
    // Strings in Latin-1 and UTF-8 with `$NODEID` as text, raw octets, reals at their edges.
    write_bytes(&sim, "5FF0:12", "vs", b"Gr\xF6\xDFe / Gr\xC3\xB6\xC3\x9Fe \xE2\x82\xAC $NODEID+1 ; [x]=y");
    write_bytes(&sim, "5FF0:13", "os", b"\n\0\r[1000]\nDataType=0x0009\n");
    write_bytes(&sim, "5FF0:10", "r32", &0x7FC0_0001u32.to_le_bytes());
    write_bytes(&sim, "5FF0:11", "r64", &f64::NEG_INFINITY.to_le_bytes());
    write_bytes(&sim, "5FF0:9", "i64", &i64::MIN.to_le_bytes());
    let (first, notes) = dump(&sim, "first.dcf");
    assert!(!notes.contains("left out"), "{notes}");
    let own = b"ParameterValue=Gr\xF6\xDFe / Gr\xC3\xB6";
    assert!(first.windows(own.len()).any(|w| w == own), "the string's own bytes are in the file");

    // Change the device, then make it match the file again.
    sim.run(&["sdo", "write", "10", "5FF0:12", "other", "--type", "vs"]).ok();
    sim.run(&["sdo", "write", "10", "5FF0:13", "00", "--type", "os"]).ok();
    sim.run(&["sdo", "write", "10", "5FF0:10", "0", "--type", "r32"]).ok();
    sim.run(&["sdo", "write", "10", "5FF0:11", "1", "--type", "r64"]).ok();
    sim.run(&["sdo", "write", "10", "5FF0:9", "0", "--type", "i64"]).ok();
    let file = sim.path("first.dcf");
    let f = file.to_str().unwrap();
    assert_eq!(sim.run(&["config", "diff", "10", f, "--check"]).code, 6);
    sim.run(&["config", "apply", "10", f, "--verify"]).ok();
    sim.run(&["config", "diff", "10", f, "--check"]).ok();
    let (second, _) = dump(&sim, "first.dcf");
    assert!(first == second, "dump → apply → dump changed the file");
}

#[test]
fn a_value_no_dcf_can_carry_is_left_out_and_said_so() {
    let sim = Sim::new();
    write_bytes(&sim, "5FF0:12", "vs", b"two\nDataType=0x0007");
    let (file, notes) = dump(&sim, "io.dcf");
    assert!(
        notes.contains("note: 0x5FF0:12 left out of the DCF: it holds a line feed (0x0A), and a VISIBLE_STRING"),
        "{notes}"
    );
    // As a value (`=two`): the file's description names the EDS's path, which may hold "two".
    assert!(!file.windows(4).any(|w| w == b"=two"), "nothing of the value is written");
}

/// Runs canctl and waits for it under a generous bound: a hang fails the test.
fn run_bounded(sim: &Sim, args: &[&str]) -> common::Run {
    common::run_within(sim.command(args), Duration::from_secs(60))
}

#[test]
fn a_fifo_or_device_as_a_dcf_or_eds_is_refused_at_once() {
    let sim = Sim::new();
    let fifo = sim.path("config.fifo");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let f = fifo.to_str().unwrap();
    let run = run_bounded(&sim, &["config", "diff", "10", f]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(
        run.stderr.contains(&format!("{f}: a FIFO, not a regular file (an EDS or DCF file must be a file)")),
        "{}",
        run.stderr
    );
    let run = run_bounded(&sim, &["config", "apply", "10", "/dev/zero"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("/dev/zero: a character device, not a regular file"), "{}", run.stderr);
    let eds = format!("10={f}");
    let run = run_bounded(&sim, &["--eds", &eds, "sdo", "read", "10", "1017"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains(": a FIFO, not a regular file"), "{}", run.stderr);
}

#[test]
fn an_oversized_dcf_is_refused_naming_the_limit() {
    let sim = Sim::new();
    let big = sim.path("big.dcf");
    // Sparse: the size is what counts, not the bytes on disk.
    std::fs::File::create(&big).unwrap().set_len(canctl::input::MAX_EDS_BYTES + 1).unwrap();
    let run = run_bounded(&sim, &["config", "diff", "10", big.to_str().unwrap()]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("big.dcf: larger than 16 MiB, the limit for an EDS or DCF file"), "{}", run.stderr);
}

#[test]
fn an_endless_value_file_stops_at_the_limit() {
    let sim = Sim::new();
    let run = run_bounded(&sim, &["sdo", "write", "10", "5FF0:14", "@/dev/zero", "--type", "d"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("/dev/zero: larger than 64 MiB, the limit for a value file"), "{}", run.stderr);
}

mod properties {
    use canctl::canopen::types::ALL_TYPES;
    use canctl::canopen::{DataType, ObjAddr};
    use canctl::od::eds::{self, Header};
    use canctl::od::{Access, Dictionary, Entry, Init};
    use proptest::prelude::*;
    use std::collections::BTreeMap;

    /// Cases per property: 4096, or `PROPTEST_CASES`.
    fn cases() -> u32 {
        std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(4096)
    }

    fn value_of(dtype: DataType) -> BoxedStrategy<Vec<u8>> {
        match dtype.size() {
            Some(n) => proptest::collection::vec(any::<u8>(), n).boxed(),
            // Strings of arbitrary bytes, with the awkward ones often.
            None => proptest::collection::vec(
                prop_oneof![any::<u8>(), Just(b'\n'), Just(b' '), Just(0), Just(b'$'), 0x80u8..=0xFF],
                0..64,
            )
            .boxed(),
        }
    }

    fn type_and_value() -> impl Strategy<Value = (DataType, Vec<u8>)> {
        proptest::sample::select(ALL_TYPES.to_vec()).prop_flat_map(|t| (Just(t), value_of(t)))
    }

    /// What the writer may refuse, and nothing else: strings that are not one line of
    /// visible characters without blanks at the ends, UNICODE_STRINGs that are not UTF-16,
    /// and booleans other than 0 or 1.
    fn refusable(dtype: DataType, bytes: &[u8]) -> bool {
        let not_one_line = |bytes: &[u8]| {
            bytes.iter().any(|b| *b < 0x20 || *b == 0x7F) || bytes.first() == Some(&b' ') || bytes.last() == Some(&b' ')
        };
        match dtype {
            DataType::Vs => not_one_line(bytes),
            DataType::Unicode => {
                let units: Vec<u16> =
                    bytes.chunks(2).map(|c| u16::from_le_bytes([c[0], *c.get(1).unwrap_or(&0)])).collect();
                bytes.len() % 2 == 1 || String::from_utf16(&units).map_or(true, |t| not_one_line(t.as_bytes()))
            }
            DataType::Bool => bytes[0] > 1,
            _ => false,
        }
    }

    fn dcf(dict: &Dictionary, values: &BTreeMap<ObjAddr, Vec<u8>>, node: u8) -> Result<Vec<u8>, eds::WriteError> {
        eds::write_bytes(
            dict,
            Some(values),
            &Header { file_name: "p.dcf".into(), node_id: Some(node), ..Header::default() },
        )
    }

    /// The device's bytes the file stands for, when applied to `node`.
    fn applied(back: &eds::Eds, addr: ObjAddr, node: u8) -> Vec<u8> {
        let entry = back.dict.get(addr).expect("entry read back");
        Entry { default: back.values[&addr].clone(), ..entry.clone() }.default_for(node)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

        /// dump → apply → dump: the value reads back as the same bytes and the second file
        /// is the first, byte for byte; or the writer refuses, for a stated reason.
        #[test]
        fn every_type_round_trips((dtype, bytes) in type_and_value(), node in 1u8..=127) {
            let addr = ObjAddr::new(0x2000, 0);
            let mut dict = Dictionary::default();
            dict.var(0x2000, "Value", dtype, Access::Rw, Init::Bytes(dtype.size().map_or(Vec::new(), |n| vec![0; n])));
            let values = BTreeMap::from([(addr, bytes.clone())]);
            match dcf(&dict, &values, node) {
                Err(e) => prop_assert!(refusable(dtype, &bytes), "refused without cause: {e}"),
                Ok(first) => {
                    prop_assert!(!refusable(dtype, &bytes), "written although it cannot read back");
                    let back = eds::parse(&first, "p.dcf").map_err(|e| TestCaseError::fail(e.to_string()))?;
                    prop_assert_eq!(applied(&back, addr, node), bytes.clone());
                    let again = BTreeMap::from([(addr, applied(&back, addr, node))]);
                    let second = dcf(&back.dict, &again, node).map_err(|e| TestCaseError::fail(e.to_string()))?;
                    prop_assert_eq!(first, second);
                }
            }
        }

        /// A COB-ID of the predefined connection set is written `$NODEID+base` and gives
        /// the node it is applied to its own COB-ID, every other one exactly as read.
        #[test]
        fn cob_ids_round_trip(cob in any::<u32>(), node in 1u8..=127) {
            let addr = ObjAddr::new(0x1800, 1);
            let mut dict = Dictionary::default();
            dict.record(0x1800, "TPDO1 communication parameter", vec![(1, "COB-ID", DataType::U32, Access::Rw, Init::NodeIdPlus(0x180))]);
            let dict = &dict;
            let values = BTreeMap::from([(addr, cob.to_le_bytes().to_vec())]);
            let first = dcf(dict, &values, node).map_err(|e| TestCaseError::fail(e.to_string()))?;
            let back = eds::parse(&first, "p.dcf").map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert_eq!(applied(&back, addr, node), cob.to_le_bytes().to_vec());
            let again = BTreeMap::from([(addr, applied(&back, addr, node))]);
            prop_assert_eq!(dcf(&back.dict, &again, node).map_err(|e| TestCaseError::fail(e.to_string()))?, first);
        }
    }
}

#[test]
fn standard_input_as_a_value_is_bounded_too() {
    use std::io::Write;
    let sim = Sim::new();
    let run_with_stdin = |bytes: Vec<u8>| {
        let mut child = sim
            .command(&["sdo", "write", "10", "5FF0:13", "@-", "--type", "os"])
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let mut stdin = child.stdin.take().unwrap();
        // canctl stops reading at the limit: a broken pipe here is the expected end.
        let writer = std::thread::spawn(move || {
            let _ = stdin.write_all(&bytes);
        });
        let run = common::finish(child.wait_with_output().unwrap());
        writer.join().unwrap();
        run
    };
    run_with_stdin(b"\x01\x02\x03".to_vec()).ok();
    assert_eq!(sim.run(&["sdo", "read", "10", "5FF0:13", "--type", "os"]).ok().stdout.trim(), "010203");
    let run = run_with_stdin(vec![0; canctl::input::MAX_VALUE_BYTES as usize + 1]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("standard input: larger than 64 MiB, the limit for a value file"), "{}", run.stderr);
}

#[test]
fn a_broken_dcf_is_a_usage_error_with_file_and_line() {
    let sim = Sim::new();
    let cases = [
        (
            "[1017]\nParameterName=Producer heartbeat time\nDataType=0x10006\nAccessType=rw\nParameterValue=100\n",
            "bad.dcf:3: 0x1017:0 (Producer heartbeat time) left out: DataType 0x10006 is not a CiA 301 data type",
        ),
        (
            "[1014]\nParameterName=COB-ID EMCY\nDataType=0x0006\nAccessType=rw\nParameterValue=$NODEID+0xFFC0\n[1017]\nParameterName=Producer heartbeat time\nDataType=0x0006\nAccessType=rw\nParameterValue=100\n",
            "bad.dcf:5: ParameterValue of 0x1014:0 (COB-ID EMCY): '$NODEID+0xFFC0' exceeds u16 (at most 65535)",
        ),
    ];
    for (text, want) in cases {
        let file = sim.path("bad.dcf");
        std::fs::write(&file, text).unwrap();
        let run = sim.run(&["config", "apply", "10", file.to_str().unwrap()]);
        assert_eq!(run.code, 2, "{}", run.stderr);
        assert!(run.stderr.contains(want), "{}", run.stderr);
        // A value the file holds but canctl could not read is not silently skipped.
        assert!(run.stderr.contains("error(s) against CiA 306, so its values are not all read"), "{}", run.stderr);
        assert!(!run.stdout.contains("written"), "{}", run.stdout);
    }
}
