//! `canctl config check FILE`: every deviation from CiA 306 with file:line, the rule and
//! what canctl does with it; exit 6 on errors, 0 on warnings only; JSON for scripts.

use crate::common;
use common::{canctl_bin, finish};
use serde_json::Value as J;
use std::process::Command;

fn fixture(name: &str) -> String {
    format!("{}/tests/fixtures/eds/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn check(args: &[&str]) -> (i32, String, String) {
    let out =
        Command::new(canctl_bin()).env_remove("CANCTL_BUS").arg("config").arg("check").args(args).output().unwrap();
    let run = finish(out);
    (run.code, run.stdout, run.stderr)
}

#[test]
fn warnings_only_is_exit_0_with_each_deviation_and_its_rule() {
    let file = fixture("compact.dcf");
    let (code, stdout, stderr) = check(&[&file]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stdout.contains(&format!("{file}:16: warning: [DummyUsage] Dummy0007=yes is not DummyNNNN=0 or 1: ignored\n    CiA 306: [DummyUsage]")), "{stdout}");
    assert!(
        stdout.contains(&format!("{file}: DCF, 3 objects (261 entries) read; 0 error(s), 2 warning(s)")),
        "{stdout}"
    );
    // A value left unused is an error: a DOMAIN default that is not hex.
    let (code, stdout, stderr) = check(&[&fixture("domain.eds")]);
    assert_eq!(code, 6, "{stdout}{stderr}");
    let (code, stdout, stderr) = check(&[&fixture("all-types.eds")]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stdout.contains("all-types.eds: EDS, 11 objects (11 entries) read; 0 error(s), 0 warning(s)"), "{stdout}");
}

#[test]
fn errors_exit_6_naming_file_line_rule_and_what_is_done() {
    let file = fixture("deviations.dcf");
    let (code, stdout, stderr) = check(&[&file]);
    assert_eq!(code, 6, "{stdout}{stderr}");
    assert!(stdout.contains(&format!("{file}:25: warning: DefaultValue=0x3ED ; prevent homing: the text from ';' on is read as a comment; the value is '0x3ED'\n    CiA 306: a comment is a line of its own")), "{stdout}");
    assert!(stdout.contains(&format!("{file}:49: error: 2001 (Valve % open) left out:")), "{stdout}");
    assert!(stdout.contains(&format!("{file}: DCF, 5 objects (8 entries) read; 1 error(s), 6 warning(s)")), "{stdout}");
    assert!(stderr.contains("1 error(s) and 6 warning(s) against CiA 306"), "{stderr}");
}

#[test]
fn json_lists_typed_findings() {
    let file = fixture("deviations.dcf");
    let (code, stdout, _) = check(&[&file, "--format", "json"]);
    assert_eq!(code, 6);
    let j: J = serde_json::from_str(&stdout).unwrap();
    assert_eq!((j["format"].as_str(), j["verdict"].as_str()), (Some("DCF"), Some("errors")));
    assert_eq!((j["errors"].as_u64(), j["warnings"].as_u64()), (Some(1), Some(6)));
    let first = &j["findings"][0];
    assert_eq!(first["kind"], "placeholder-commissioning");
    assert_eq!(first["severity"], "warning");
    assert_eq!(first["line"], 10);
    assert!(first["rule"].as_str().unwrap().starts_with("CiA 306"));
}

#[test]
fn a_file_that_is_not_an_eds_is_refused_and_a_missing_one_is_a_usage_error() {
    let (code, stdout, _) = check(&[&fixture("broken-line.eds")]);
    assert_eq!(code, 6);
    assert!(stdout.contains("broken-line.eds:3: error: expected KEY=VALUE or [SECTION]"), "{stdout}");
    let (code, _, stderr) = check(&["/nonexistent/x.eds"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("/nonexistent/x.eds"), "{stderr}");
}

/// A DCF with placeholder commissioning values (`NodeID=0`, `BaudRate=0`), as vendors'
/// tools write them, is used for the node given on the command line; one with errors
/// (something left out) is not compared or applied at all.
#[test]
fn placeholder_commissioning_values_take_the_node_from_the_command_line() {
    let sim = common::Sim::new();
    let run = sim.run(&["config", "diff", "10", &fixture("placeholder.dcf")]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("placeholder.dcf:6: NodeID=0 is a placeholder"), "{}", run.stderr);
    assert!(run.stderr.contains("object(s) differ from"), "{}", run.stderr);
    let run = sim.run(&["config", "apply", "10", &fixture("deviations.dcf")]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("deviations.dcf:49: 2001 (Valve % open) left out"), "{}", run.stderr);
    assert!(run.stderr.contains("more deviation(s) from CiA 306; canctl config check"), "{}", run.stderr);
    assert!(run.stderr.contains("nothing is compared or written"), "{}", run.stderr);
}

#[test]
fn xdd_and_xdc_are_checked_as_canctl_reads_them() {
    let xdd = |name: &str| format!("{}/tests/fixtures/xdd/{name}", env!("CARGO_MANIFEST_DIR"));
    let (code, stdout, stderr) = check(&[&xdd("small.xdd")]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stdout.contains(": XDD, "), "{stdout}");
    let (code, stdout, stderr) = check(&[&xdd("small.xdc")]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stdout.contains(": XDC, "), "{stdout}");
    // Malformed XML is refused at its line and column, under CiA 311's rule, not 306's.
    let file = xdd("malformed.xdd");
    let (code, stdout, stderr) = check(&[&file]);
    assert_eq!(code, 6, "{stdout}{stderr}");
    assert!(stdout.contains(&format!("{file}:7: error: column 7: malformed XML")), "{stdout}");
    assert!(stdout.contains("CiA 311: an XDD or XDC is well-formed XML"), "{stdout}");
    assert!(stdout.contains("not read as an XDD"), "{stdout}");
}

/// A file's values are judged by its own LowLimit and HighLimit as `config apply` judges
/// them: what apply would refuse, check finds, at the value's line.
mod limits {
    use super::*;

    /// Node 5's configuration as `config dump` writes it (`dcf` or `xdc`), with the limits
    /// and the value of its heartbeat time (0x1017) set; the file's path.
    struct Dumped {
        sim: common::Sim,
        dcf: String,
        xdc: String,
    }

    impl Dumped {
        fn new() -> Dumped {
            let sim = common::Sim::new();
            let dcf = sim.run(&["config", "dump", "5"]).ok().stdout;
            let xdc = sim.run(&["config", "dump", "5", "--format", "xdc"]).ok().stdout;
            Dumped { sim, dcf, xdc }
        }

        fn with_heartbeat(&self, format: &str, low: &str, high: &str, value: &str) -> String {
            let text = match format {
                "dcf" => {
                    let at = self.dcf.find("[1017]").unwrap();
                    let from = at + self.dcf[at..].find("ParameterValue=").unwrap();
                    let to = from + self.dcf[from..].find('\n').unwrap();
                    let keys = format!("LowLimit={low}\nHighLimit={high}\nParameterValue={value}");
                    format!("{}{keys}{}", &self.dcf[..from], &self.dcf[to..])
                }
                _ => {
                    let at = self.xdc.find("index=\"1017\"").unwrap();
                    let from = at + self.xdc[at..].find(" actualValue=").unwrap();
                    let to = from + self.xdc[from..].find("/>").unwrap();
                    let keys = format!(" lowLimit=\"{low}\" highLimit=\"{high}\" actualValue=\"{value}\"");
                    format!("{}{keys}{}", &self.xdc[..from], &self.xdc[to..])
                }
            };
            let path = self.sim.path(&format!("hb-{low}-{high}-{}.{format}", value.replace('$', "")));
            std::fs::write(&path, text).unwrap();
            path.display().to_string()
        }

        fn apply_dry_run(&self, file: &str) -> common::Run {
            self.sim.run(&["config", "apply", "5", file, "--dry-run"])
        }
    }

    /// The line of the first line of `file` that holds `text`.
    fn line_of(file: &str, text: &str) -> usize {
        std::fs::read_to_string(file).unwrap().lines().position(|l| l.contains(text)).unwrap() + 1
    }

    #[test]
    fn a_value_outside_the_files_own_limits_is_an_error_at_its_line() {
        let dumped = Dumped::new();
        let file = dumped.with_heartbeat("dcf", "100", "200", "40");
        let (code, stdout, stderr) = check(&[&file]);
        assert_eq!(code, 6, "{stdout}{stderr}");
        let line = line_of(&file, "ParameterValue=40");
        let said = format!(
            "{file}:{line}: error: ParameterValue 40 of 0x1017:0 (Producer heartbeat time) is outside the \
             file's limits, 100 to 200: ignored"
        );
        assert!(stdout.contains(&said), "{stdout}");
        assert!(stdout.contains("1 error(s)"), "{stdout}");
        let apply = dumped.apply_dry_run(&file);
        assert_eq!(apply.code, 2, "{}", apply.stderr);
        assert!(apply.stderr.contains(&said[..said.find(": error").unwrap()]), "{}", apply.stderr);
    }

    #[test]
    fn inverted_limits_are_an_error_and_not_used() {
        let dumped = Dumped::new();
        let file = dumped.with_heartbeat("dcf", "200", "100", "150");
        let (code, stdout, stderr) = check(&[&file]);
        assert_eq!(code, 6, "{stdout}{stderr}");
        let line = line_of(&file, "LowLimit=200");
        assert!(
            stdout.contains(&format!(
                "{file}:{line}: error: LowLimit 200 of 0x1017:0 (Producer heartbeat time) is above its HighLimit \
                 100, which no value passes: no limits"
            )),
            "{stdout}"
        );
        let file = dumped.with_heartbeat("xdc", "200", "100", "150");
        let (code, stdout, stderr) = check(&[&file]);
        assert_eq!(code, 6, "{stdout}{stderr}");
        assert!(stdout.contains("LowLimit 200 of 0x1017:0 (Producer heartbeat time) is above"), "{stdout}");
    }

    /// A limit written as C writes it is read as it plainly means, as a value is: the value
    /// below it is then refused by it.
    #[test]
    fn limits_with_a_c_suffix_are_read_as_meant() {
        let dumped = Dumped::new();
        for format in ["dcf", "xdc"] {
            let file = dumped.with_heartbeat(format, "100U", "200UL", "40");
            let (code, stdout, stderr) = check(&[&file, "--format", "json"]);
            assert_eq!(code, 6, "{stdout}{stderr}");
            let j: J = serde_json::from_str(&stdout).unwrap();
            let kinds: Vec<&str> =
                j["findings"].as_array().unwrap().iter().map(|f| f["kind"].as_str().unwrap()).collect();
            assert_eq!(kinds, ["value-as-meant", "value-as-meant", "value-outside-limits"], "{format}: {stdout}");
            let low = j["findings"][0]["message"].as_str().unwrap();
            assert!(low.ends_with("100U of 0x1017:0 (Producer heartbeat time) read as 100"), "{format}: {low}");
        }
    }

    /// The invariant: `config check` passes a file exactly when `config apply --dry-run`
    /// accepts it, for values inside, on and outside the limits, inverted limits and a
    /// `$NODEID` value, in both an EDS-style DCF and an XDC.
    #[test]
    fn check_passes_exactly_what_apply_accepts() {
        let dumped = Dumped::new();
        let limits = [("100", "200"), ("200", "100"), ("50", "50"), ("0", "65535"), ("130", "140")];
        let values = ["40", "50", "100", "150", "200", "250", "$NODEID+128"];
        for format in ["dcf", "xdc"] {
            for (low, high) in limits {
                for value in values {
                    let file = dumped.with_heartbeat(format, low, high, value);
                    let (checked, stdout, _) = check(&[&file]);
                    let applied = dumped.apply_dry_run(&file);
                    assert_eq!(
                        checked == 0,
                        applied.code == 0,
                        "{format} {low}..{high} value {value}: check exit {checked}, apply exit {}\n{stdout}\n{}",
                        applied.code,
                        applied.stderr
                    );
                }
            }
        }
    }
}

/// An XDD (CiA 311) is held to the same policy as an EDS: the same defect is the same
/// finding, of the same severity, at the line of its element.
mod xml_like_ini {
    use super::*;

    /// Objects as (index, name, data type, access, default), each written as an EDS
    /// section and as an XDD element.
    const OBJECTS: &[(&str, &str, &str, &str, &str)] = &[
        ("1000", "Device type", "0007", "ro", "0x20192"),
        ("1001", "Error register", "0005", "ro", "0"),
        ("1018", "Identity", "0007", "ro", "0xFB"),
        ("2000", "Odd type", "00FF", "rw", "1"),
        ("2001", "Odd access", "0007", "qq", "1"),
        ("2002", "No type", "0x10000", "rw", "1"),
        ("2003", "Bad default", "0007", "rw", "banana"),
    ];

    fn eds(objects: &[(&str, &str, &str, &str, &str)]) -> String {
        let mut text = String::from("[FileInfo]\nFileName=odd.eds\n");
        for (index, name, dtype, access, default) in objects {
            text += &format!(
                "\n[{index}]\nParameterName={name}\nObjectType=0x7\nDataType=0x{dtype}\nAccessType={access}\nDefaultValue={default}\n"
            );
        }
        text
    }

    fn xdd(objects: &[(&str, &str, &str, &str, &str)]) -> String {
        let mut text = String::from("<?xml version=\"1.0\"?>\n<ISO15745ProfileContainer>\n<CANopenObjectList>\n");
        for (index, name, dtype, access, default) in objects {
            text += &format!(
                "  <CANopenObject index=\"{index}\" name=\"{name}\" objectType=\"7\" dataType=\"{dtype}\" \
                 accessType=\"{access}\" defaultValue=\"{default}\"/>\n"
            );
        }
        text + "</CANopenObjectList>\n</ISO15745ProfileContainer>\n"
    }

    /// `config check --format json` of `text` written to `name`: exit code and findings as
    /// (kind, severity, line, message) with the file named as given.
    fn findings(dir: &std::path::Path, name: &str, text: &str) -> (i32, J) {
        let file = dir.join(name);
        std::fs::write(&file, text).unwrap();
        let file = file.to_str().unwrap();
        let (code, stdout, stderr) = check(&[file, "--format", "json"]);
        let j: J = serde_json::from_str(&stdout).unwrap_or_else(|e| panic!("{e}: {stdout}{stderr}"));
        for f in j["findings"].as_array().unwrap() {
            assert_eq!(f["path"], file, "{f}");
        }
        (code, j)
    }

    fn kinds(j: &J) -> Vec<(String, String)> {
        let list = j["findings"].as_array().unwrap();
        list.iter().map(|f| (f["kind"].as_str().unwrap().into(), f["severity"].as_str().unwrap().into())).collect()
    }

    /// The line of `file`'s text that holds `text`.
    fn line_of(text: &str, needle: &str) -> u64 {
        text.lines().position(|l| l.contains(needle)).unwrap() as u64 + 1
    }

    #[test]
    fn the_same_defects_are_the_same_findings_in_an_eds_and_an_xdd() {
        let dir = tempfile::tempdir().unwrap();
        let (eds_code, eds_j) = findings(dir.path(), "odd.eds", &eds(OBJECTS));
        let text = xdd(OBJECTS);
        let (xdd_code, xdd_j) = findings(dir.path(), "odd.xdd", &text);
        assert_eq!((eds_code, xdd_code), (6, 6), "{eds_j}\n{xdd_j}");
        assert_eq!(kinds(&xdd_j), kinds(&eds_j), "{eds_j}\n{xdd_j}");
        assert_eq!((xdd_j["errors"].as_u64(), xdd_j["warnings"].as_u64()), (Some(3), Some(1)), "{xdd_j}");
        assert_eq!(xdd_j["objects"], eds_j["objects"]);
        // One whose every object is broken is read, its findings said, as an EDS is.
        let (code, j) = findings(dir.path(), "broken.xdd", &xdd(&OBJECTS[4..5]));
        assert_eq!((code, j["verdict"].as_str()), (6, Some("errors")), "{j}");
        // Each at the line of its element, without the place repeated in the message.
        let lines: Vec<u64> =
            xdd_j["findings"].as_array().unwrap().iter().map(|f| f["line"].as_u64().unwrap()).collect();
        let expected: Vec<u64> = ["2000", "2001", "2002", "2003"]
            .iter()
            .map(|index| line_of(&text, &format!("index=\"{index}\"")))
            .collect();
        assert_eq!(lines, expected, "{xdd_j}");
        let access = &xdd_j["findings"][1];
        assert_eq!(
            access["message"],
            "0x2001:0 (Odd access) left out: accessType 'qq' is not ro, wo, rw, rwr, rww or const"
        );
        assert!(access["rule"].as_str().unwrap().starts_with("CiA 306"), "{access}");
    }

    /// MAB's EDS writes a BOOLEAN's default as `false`; C programmers' generators write
    /// `0x1234567890ABCDEFLL`, `100U`: read as they plainly mean, with a warning, in both.
    #[test]
    fn a_c_suffix_or_a_boolean_word_is_read_as_meant_with_a_warning() {
        let objects = [
            ("1000", "Device type", "0007", "ro", "0x20192UL"),
            ("1001", "Error register", "0005", "ro", "0u"),
            ("1018", "Identity", "0007", "ro", "0xFB"),
            ("2002", "Suffix", "001B", "rw", "0x1234567890ABCDEFLL"),
            ("2003", "Flag", "0001", "rw", "false"),
            ("2004", "Signed", "0004", "rw", "-5L"),
            ("2005", "On", "0001", "rw", "TRUE"),
        ];
        let dir = tempfile::tempdir().unwrap();
        let (eds_code, eds_j) = findings(dir.path(), "meant.eds", &eds(&objects));
        let (xdd_code, xdd_j) = findings(dir.path(), "meant.xdd", &xdd(&objects));
        assert_eq!((eds_code, xdd_code), (0, 0), "{eds_j}\n{xdd_j}");
        assert_eq!(kinds(&eds_j), vec![("value-as-meant".to_string(), "warning".to_string()); 6], "{eds_j}");
        assert_eq!(kinds(&xdd_j), kinds(&eds_j), "{xdd_j}");
        let flag = &eds_j["findings"][3];
        assert_eq!(flag["message"], "DefaultValue false of 0x2003:0 (Flag) read as 0", "{flag}");
        assert!(flag["rule"].as_str().unwrap().contains("a BOOLEAN is 0 or 1"), "{flag}");
        for name in ["meant.eds", "meant.xdd"] {
            let read = canctl::od::read_description(&dir.path().join(name)).unwrap();
            let default = |index| read.dict.get(canctl::canopen::ObjAddr::new(index, 0)).unwrap().default_for(1);
            assert_eq!(default(0x2002), 0x1234567890ABCDEFu64.to_le_bytes(), "{name}");
            assert_eq!((default(0x2003), default(0x2005)), (vec![0], vec![1]), "{name}");
            assert_eq!(default(0x2004), (-5i32).to_le_bytes(), "{name}");
        }
        // A DCF's value so written is what the node is to hold.
        let dcf = eds(&objects) + "\n[2006]\nParameterName=Limit\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=0\nParameterValue=250U\n";
        std::fs::write(dir.path().join("meant.dcf"), dcf).unwrap();
        let read = canctl::od::read_description(&dir.path().join("meant.dcf")).unwrap();
        let value = read.values.get(&canctl::canopen::ObjAddr::new(0x2006, 0));
        assert_eq!(value, Some(&canctl::od::Init::Bytes(250u32.to_le_bytes().to_vec())));
    }

    #[test]
    fn mandatory_objects_missing_are_told_in_both_formats() {
        let dir = tempfile::tempdir().unwrap();
        let text = xdd(&OBJECTS[3..4]);
        let (code, j) = findings(dir.path(), "device.xdd", &text);
        assert_eq!(code, 0, "{j}");
        let missing: Vec<&J> =
            j["findings"].as_array().unwrap().iter().filter(|f| f["kind"] == "missing-mandatory").collect();
        assert_eq!(missing.len(), 3, "{j}");
        assert_eq!(missing[0]["message"], "no object 0x1000: CiA 301 makes 0x1000 mandatory for every device");
        assert_eq!(missing[0]["line"], line_of(&text, "<CANopenObjectList>"));
        // An EDS with object lists says the same under the same kind.
        let listed = "[MandatoryObjects]\nSupportedObjects=1\n1=0x1018\n".to_string() + &eds(&OBJECTS[2..3])[..];
        let (_, j) = findings(dir.path(), "listed.eds", &listed);
        let missing: Vec<&J> =
            j["findings"].as_array().unwrap().iter().filter(|f| f["kind"] == "missing-mandatory").collect();
        assert_eq!(missing.len(), 2, "{j}");
    }
}

/// What `config check` says about a file it cannot use names the file once, and quotes
/// no more of it than a reader can take in.
mod messages {
    use super::*;

    #[test]
    fn a_file_is_named_by_what_it_is_not_by_its_extension() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("device.xpd");
        std::fs::copy(format!("{}/tests/fixtures/xdd/small.xdd", env!("CARGO_MANIFEST_DIR")), &file).unwrap();
        let (code, stdout, stderr) = check(&[file.to_str().unwrap()]);
        assert_eq!(code, 0, "{stdout}{stderr}");
        assert!(stdout.contains("device.xpd: XDD, "), "an XML device description, read as one: {stdout}");
    }

    #[test]
    fn an_empty_file_is_refused_with_its_name() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("empty.eds");
        std::fs::write(&file, "; nothing but a comment\n").unwrap();
        let file = file.to_str().unwrap();
        let (code, stdout, stderr) = check(&[file]);
        assert_eq!(code, 6, "{stdout}{stderr}");
        assert!(stdout.contains(&format!("{file}: error: not an EDS or DCF")), "{stdout}");
        assert!(stdout.contains(&format!("{file}: not read as an EDS")), "{stdout}");
    }

    #[test]
    fn a_file_that_cannot_be_read_is_said_once() {
        let (code, _, stderr) = check(&["/nonexistent/x.eds"]);
        assert_eq!(code, 2, "{stderr}");
        assert_eq!(stderr.trim_end(), "canctl: cannot read /nonexistent/x.eds: No such file or directory (os error 2)");
        let dir = tempfile::tempdir().unwrap();
        let (code, _, stderr) = check(&[dir.path().to_str().unwrap()]);
        assert_eq!(code, 2, "{stderr}");
        assert!(!stderr.contains("cannot check"), "{stderr}");
        assert!(stderr.contains("a directory, not a regular file"), "{stderr}");
    }

    #[test]
    fn a_binary_files_line_is_quoted_short_with_its_bytes_escaped() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("garbage.eds");
        let garbage: Vec<u8> = (0..1000u32).map(|i| [0x00, 0x87, b'a', 0x1B, 0xE9][i as usize % 5]).collect();
        std::fs::write(&file, garbage).unwrap();
        let (code, stdout, stderr) = check(&[file.to_str().unwrap()]);
        assert_eq!(code, 6, "{stdout}{stderr}");
        let said = stdout.lines().next().unwrap();
        assert!(said.contains(r"found '\x00\x87a\x1Bé\x00"), "{said}");
        assert!(said.contains("…' (1000 characters)"), "{said}");
        assert!(said.chars().count() < 250, "{} characters: {said}", said.chars().count());
    }
}
