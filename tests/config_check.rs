//! `canctl config check FILE`: every deviation from CiA 306 with file:line, the rule and
//! what canctl does with it; exit 6 on errors, 0 on warnings only; JSON for scripts.

mod common;
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
