use super::*;
use crate::lint::{Severity, Warning};
use crate::Dictionary;
use std::collections::BTreeMap;

#[test]
fn xml_is_told_from_ini_by_its_first_character() {
    assert!(is_xml(b"<?xml version=\"1.0\"?><a/>"));
    assert!(is_xml(b"\xEF\xBB\xBF\r\n  <ISO15745ProfileContainer/>"));
    assert!(!is_xml(b"[FileInfo]\nFileName=x.eds\n"));
    assert!(!is_xml(b"; <comment>\n[FileInfo]\n"));
}

#[test]
fn text_that_attribute_normalisation_would_change_survives_a_round_trip() {
    let mut dict = Dictionary::default();
    dict.var(0x2000, "Label <A & B>", DataType::Vs, Access::Rw, Init::Bytes(b"x".to_vec()));
    let wanted = "\ttwo\nlines \"quoted\" & 'more' \u{20AC} ";
    let values = BTreeMap::from([(ObjAddr::new(0x2000, 0), wanted.as_bytes().to_vec())]);
    let h = Header { node_id: Some(3), ..Header::default() };
    let bytes = write_bytes(&dict, Some(&values), &h).unwrap();
    let back = parse(&bytes, "t.xdc").unwrap();
    assert_eq!(back.values[&ObjAddr::new(0x2000, 0)], Init::Bytes(wanted.as_bytes().to_vec()));
    assert_eq!(back.dict.object_info(0x2000).unwrap().0, "Label <A & B>");
    assert_eq!(back.node_id, Some(3));
}

#[test]
fn what_xml_cannot_carry_is_refused_naming_the_object() {
    let mut dict = Dictionary::default();
    dict.var(0x2000, "Raw", DataType::Vs, Access::Rw, Init::Bytes(b"a\x01b".to_vec()));
    let err = write_bytes(&dict, None, &Header::default()).unwrap_err();
    assert_eq!(err.what, "0x2000:0 (Raw) defaultValue");
    assert!(err.why.contains("0x01"), "{}", err.why);
    dict.var(0x2000, "Raw", DataType::Vs, Access::Rw, Init::Bytes(vec![0xE9]));
    let err = write_bytes(&dict, None, &Header::default()).unwrap_err();
    assert!(err.why.contains("not UTF-8"), "{}", err.why);
}

#[test]
fn bytes_that_are_not_utf8_are_refused_at_their_position_unless_declared() {
    let bad = b"<?xml version=\"1.0\"?>\n<a>caf\xE9</a>\n";
    let err = parse(bad, "x.xdd").unwrap_err();
    assert_eq!((err.line, err.column), (2, 7), "{err}");
    let latin1 = b"<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n<a>caf\xE9</a>\n";
    let err = parse(latin1, "x.xdd").unwrap_err();
    assert!(err.msg.contains("<a> is not an XDD"), "decoded, then judged as XML: {err}");
}

#[test]
fn an_object_that_cannot_be_understood_is_left_out_with_an_error_as_in_an_eds() {
    let xml = br#"<ISO15745ProfileContainer><CANopenObjectList>
<CANopenObject index="2000" name="Odd" objectType="7" dataType="0007" accessType="rw" defaultValue="banana"/>
<CANopenObject index="2001" name="Fine" objectType="7" dataType="0005" accessType="rw" defaultValue="1"/>
</CANopenObjectList></ISO15745ProfileContainer>"#;
    let e = parse(xml, "w.xdd").unwrap();
    assert!(e.dict.get(ObjAddr::new(0x2000, 0)).is_none());
    assert!(e.dict.get(ObjAddr::new(0x2001, 0)).is_some());
    let left_out: Vec<&Warning> = e.warnings.iter().filter(|w| w.severity == Severity::Error).collect();
    assert_eq!(left_out.len(), 1, "{:?}", e.warnings);
    assert_eq!(left_out[0].kind, Kind::ObjectLeftOut);
    assert_eq!(left_out[0].to_string(), "w.xdd:2: 0x2000:0 (Odd) left out: defaultValue 'banana' is not an integer");
}

#[test]
fn a_utf16_xdd_is_xml_and_reads_as_its_utf8_twin() {
    let xml = "<?xml version=\"1.0\" encoding=\"utf-16\"?>\n<ISO15745ProfileContainer><CANopenObjectList>\n\
<CANopenObject index=\"1008\" name=\"Gerätename\" objectType=\"7\" dataType=\"0009\" accessType=\"const\" defaultValue=\"Stößel\"/>\n\
</CANopenObjectList></ISO15745ProfileContainer>";
    let le: Vec<u8> = [0xFF, 0xFE].into_iter().chain(xml.encode_utf16().flat_map(u16::to_le_bytes)).collect();
    let be: Vec<u8> = [0xFE, 0xFF].into_iter().chain(xml.encode_utf16().flat_map(u16::to_be_bytes)).collect();
    for bytes in [le, be] {
        assert!(is_xml(&bytes));
        let e = parse(&bytes, "w.xdd").unwrap();
        assert_eq!(e.dict.object_info(0x1008).unwrap().0, "Gerätename");
        assert_eq!(e.dict.get(ObjAddr::new(0x1008, 0)).unwrap().default, Init::Bytes("Stößel".as_bytes().to_vec()));
    }
}
