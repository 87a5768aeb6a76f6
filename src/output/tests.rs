use super::junit::junit_xml;
use super::table::fitted;
use super::text::terminal_safe;
use super::*;
use crate::canopen::pdo::Field;
use crate::canopen::pdo::Layout;
use crate::canopen::types::Value;
use crate::canopen::DataType;

/// Seed 001's TPDO1: position (0x6020:1, 32 bits) and speed (0x6030:1, 16 bits).
fn mh_tpdo1() -> Layout {
    let mapping = [(0x6020_0120, DataType::I32, "position"), (0x6030_0110, DataType::I16, "speed")];
    Layout { cob_id: 0x185, fields: mapping.iter().map(|(raw, t, name)| Field::mapped(*raw, *t, name)).collect() }
}

#[test]
fn records() {
    let l = mh_tpdo1();
    let v = l.decode(&[0x48, 0xE8, 0x01, 0x00, 0x9C, 0xFF]).unwrap();
    let mut out = String::new();
    let csv = RecordWriter::new(&l, Format::Csv);
    csv.preamble(&mut out);
    csv.record(&mut out, 1_700_000_000_123, 5, 1, &v, true);
    RecordWriter::new(&l, Format::Json).record(&mut out, 1_700_000_000_123, 5, 1, &v, true);
    assert_eq!(out, "time,pdo,position,speed\n1700000000.123,1,125000,-100\n{\"time\":1700000000.123,\"node\":5,\"pdo\":1,\"position\":125000,\"speed\":-100}\n");
    out.clear();
    let human = RecordWriter::new(&l, Format::Human);
    human.preamble(&mut out);
    human.record(&mut out, 1_700_000_000_123, 5, 1, &v, true);
    human.record(&mut out, 1_700_000_000_123, 5, 1, &v, false);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    assert!(lines[0].starts_with("time") && lines[0].ends_with("speed"), "{out}");
    assert_eq!(lines[1], lines[2]);
    assert!(lines[1].starts_with("22:13:20.123    TPDO1") && lines[1].ends_with("-100"), "{out}");
}

/// Long names do not push the values out from under their titles: the titles become
/// `#1`, `#2`, and the names stand in a legend above the table.
#[test]
fn long_field_names_go_to_a_legend() {
    let l = Layout {
        cob_id: 0x185,
        fields: vec![
            Field::mapped(0x6020_0120, DataType::I32, "Position value (linear): Channel 1"),
            Field::mapped(0x6030_0110, DataType::I16, "Speed value: Channel 1"),
        ],
    };
    let mut out = String::new();
    let human = RecordWriter::new(&l, Format::Human);
    human.record(&mut out, 1_700_000_000_123, 5, 1, &[Value::Int(121_820), Value::Int(-2000)], true);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], "  #1  Position value (linear): Channel 1");
    assert_eq!(lines[1], "  #2  Speed value: Channel 1");
    let (header, row) = (lines[2], lines[3]);
    for (title, value) in [("#1", "121820"), ("#2", "-2000")] {
        let end = |line: &str, text: &str| line.find(text).map(|at| at + text.len());
        assert_eq!(end(header, title), end(row, value), "{title} over {value}:\n{out}");
    }
}

#[test]
fn control_characters_are_escaped_for_the_terminal() {
    assert_eq!(terminal_safe("CAN-2057C"), "CAN-2057C");
    assert!(matches!(terminal_safe("plain"), std::borrow::Cow::Borrowed(_)));
    assert_eq!(terminal_safe("\u{1b}]0;pwned\u{7}"), r"\x1b]0;pwned\x07");
    assert_eq!(terminal_safe("a\nb\r\tc\u{7f}"), r"a\nb\r\tc\x7f");
    assert_eq!(terminal_safe("\u{9b}2J \u{202e}txt.exe"), r"\u{9b}2J \u{202e}txt.exe");
    assert_eq!(terminal_safe("Grüße"), "Grüße");
    assert_eq!(terminal_safe_lines("one\ntwo\u{1b}[2A"), "one\ntwo\\x1b[2A");
}

#[test]
fn junit_escapes_markup_and_what_xml_cannot_carry() {
    let suite = TestSuite {
        name: "a <b> & \"c\"".into(),
        cases: vec![
            TestCase { class: "node 5".into(), name: "present".into(), detail: "ok".into(), failure: None },
            TestCase {
                class: "node 6 ('x')".into(),
                name: "objects".into(),
                detail: "bell \u{7} here".into(),
                failure: Some("1 < 2".into()),
            },
        ],
    };
    let x = junit_xml(&suite);
    assert!(x.contains("<testsuites name=\"a &lt;b&gt; &amp; &quot;c&quot;\" tests=\"2\" failures=\"1\""), "{x}");
    assert!(x.contains("<testcase classname=\"node 6 (&apos;x&apos;)\" name=\"objects\">"), "{x}");
    assert!(x.contains("<failure message=\"1 &lt; 2\" type=\"difference\">bell \\x07 here</failure>"), "{x}");
    assert!(!x.contains('\u{7}'));
}

/// A scan's table at 80 columns: identity details dropped until it fits; at 200 whole, in
/// the same plain style; at 24 the first column still stands.
#[test]
fn tables_are_fitted_to_the_width() {
    let headers = ["node", "device_type", "vendor_id", "product_code", "revision", "serial", "name", "state"];
    let row = ["5", "0x000A0196", "0x00000040", "0x43787800", "0x312E3031", "0x09501234", "C01", "pre-operational"];
    let rows = vec![row.map(String::from).to_vec()];
    let (text, hidden) = fitted(&headers, &rows, 80);
    assert_eq!(hidden, ["revision"]);
    assert!(!text.contains("0x312E3031") && text.lines().all(|l| l.chars().count() <= 80), "{text}");
    assert!(text.starts_with(" node  device_type") && text.contains("pre-operational"), "{text}");
    let (text, hidden) = fitted(&headers, &rows, 200);
    assert!(hidden.is_empty() && text.starts_with(" node  device_type") && text.contains("0x09501234"), "{text}");
    assert!(!text.contains(['┌', '│', '─']), "one style, frames nowhere: {text}");
    // Narrower still: the droppable columns go, then the cells wrap; nothing else goes.
    let (text, hidden) = fitted(&headers, &rows, 24);
    assert_eq!(hidden, ["device_type", "vendor_id", "product_code", "revision", "serial"]);
    assert!(text.lines().all(|l| l.chars().count() <= 24), "{text}");
    assert!(text.contains("C01") && text.contains("pre-"), "{text}");
}

#[test]
fn csv_quotes_what_needs_it() {
    let rows = vec![vec!["1".to_string(), "a,b".to_string(), "say \"hi\"".to_string()]];
    assert_eq!(super::csv(&["n", "x", "y"], &rows), "n,x,y\n1,\"a,b\",\"say \"\"hi\"\"\"\n");
}
