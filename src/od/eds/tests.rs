use super::*;

fn fixture(name: &str) -> (Vec<u8>, String) {
    let path = format!("{}/tests/fixtures/eds/{name}", env!("CARGO_MANIFEST_DIR"));
    (std::fs::read(&path).unwrap(), name.to_string())
}

fn load(name: &str) -> Result<Eds, EdsError> {
    let (bytes, path) = fixture(name);
    parse(&bytes, &path)
}

#[test]
fn reads_a_real_world_shaped_eds() {
    let (bytes, _) = fixture("mh-sensor.eds");
    assert!(bytes.windows(2).any(|w| w == b"\r\n"), "the fixture has CRLF");
    assert!(bytes.contains(&0xFC), "the fixture has Latin-1 bytes");
    let eds = load("mh-sensor.eds").unwrap();
    let d = &eds.dict;
    let e = d.get(ObjAddr::new(0x1000, 0)).unwrap();
    assert_eq!((e.dtype, e.access, e.default_for(5)), (DataType::U32, Access::Ro, vec![0x96, 0x01, 0x0A, 0x00]));
    // Odd case in keys and values, limits.
    let hb = d.get(ObjAddr::new(0x1017, 0)).unwrap();
    assert_eq!((hb.name.as_str(), hb.access, hb.range), ("Producer heartbeat time", Access::Rw, Some((0, 60000))));
    // A record, with a sub section in upper case, decimal and missing defaults.
    assert_eq!(d.object_info(0x1018), Some(("Identity object", ObjectKind::Record)));
    assert_eq!(d.get(ObjAddr::new(0x1018, 1)).unwrap().default_for(5), vec![0x40, 0, 0, 0]);
    assert_eq!(d.get(ObjAddr::new(0x1018, 3)).unwrap().default_for(5), 0x312E_3031u32.to_le_bytes());
    assert_eq!(d.get(ObjAddr::new(0x1018, 4)).unwrap().default_for(5), vec![0; 4]);
    assert_eq!(d.display_name(ObjAddr::new(0x1018, 2)).unwrap(), "Identity object: Product code");
    // $NODEID arithmetic follows the node the file is used for.
    let cob = d.get(ObjAddr::new(0x1800, 1)).unwrap();
    assert_eq!(cob.default, Init::NodeIdPlus(0x180));
    assert_eq!(cob.default_for(5), 0x185u32.to_le_bytes());
    // An array of signed values.
    assert_eq!(d.object_info(0x6020).unwrap().1, ObjectKind::Array);
    assert_eq!(d.get(ObjAddr::new(0x6020, 1)).unwrap().default_for(5), vec![0xFF; 4]);
    // Latin-1 decoded, a type canctl does not handle passed over with a warning.
    assert_eq!(eds.info["vendorname"], "MTS Sensor Technologie GmbH & Co. KG");
    assert_eq!(eds.warnings.len(), 1);
    assert!(eds.warnings[0].contains("mh-sensor.eds:") && eds.warnings[0].contains("0x0016"), "{:?}", eds.warnings);
    assert!(d.get(ObjAddr::new(0x6021, 0)).is_none());
}

#[test]
fn reads_a_dcf_with_parameter_values() {
    let eds = load("io-module.dcf").unwrap();
    assert_eq!(eds.node_id, Some(10));
    assert_eq!(eds.values[&ObjAddr::new(0x1017, 0)], Init::Bytes(vec![250, 0]));
    assert_eq!(eds.values[&ObjAddr::new(0x1800, 1)], Init::NodeIdPlus(0x180));
    assert_eq!(eds.dict.get(ObjAddr::new(0x1800, 1)).unwrap().default, Init::NodeIdPlus(0x180));
    assert_eq!(eds.values[&ObjAddr::new(0x6200, 1)], Init::Bytes(vec![0x0F]));
    assert_eq!(eds.dict.get(ObjAddr::new(0x6200, 1)).unwrap().access, Access::Rw);
}

#[test]
fn broken_files_are_refused_with_file_and_line() {
    let cases = [
        ("broken-datatype.eds", "broken-datatype.eds:3: DataType '0xZZ' is not a number"),
        ("broken-section.eds", "broken-section.eds:6: section header '[1001' has no closing ]"),
        ("broken-line.eds", "broken-line.eds:3: expected KEY=VALUE or [SECTION], found 'DataType 0x0007'"),
        ("broken-access.eds", "broken-access.eds:4: AccessType 'readwrite' is not ro, wo, rw, rwr, rww or const"),
        ("broken-default.eds", "broken-default.eds:5: DefaultValue of 0x1001:0: 300 is out of range for u8 (0..=255)"),
        (
            "broken-record.eds",
            "broken-record.eds:1: Identity object (1018) is an array or record without any [1018subN] section",
        ),
    ];
    for (file, want) in cases {
        assert_eq!(load(file).unwrap_err().to_string(), want, "{file}");
    }
}

#[test]
fn integers_follow_cia_306() {
    assert_eq!(parse_int("0x1F"), Some(31));
    assert_eq!(parse_int("017"), Some(15), "a leading 0 is octal");
    assert_eq!(parse_int("-5"), Some(-5));
    assert_eq!(parse_int("0"), Some(0));
    assert_eq!(parse_value("0xFFFF", DataType::I16), Ok(Init::Bytes(vec![0xFF, 0xFF])));
    assert_eq!(parse_value("$NODEID", DataType::U8), Ok(Init::NodeIdPlus(0)));
    assert!(parse_value("$NODEID+0x180", DataType::Vs).is_err());
}

#[test]
fn written_files_read_back_the_same() {
    let eds = load("mh-sensor.eds").unwrap();
    let mut values = BTreeMap::new();
    values.insert(ObjAddr::new(0x1017, 0), vec![0x64, 0]);
    let header = Header { file_name: "x.dcf".into(), node_id: Some(5), ..Header::default() };
    let text = write(&eds.dict, Some(&values), &header);
    let back = parse(text.as_bytes(), "x.dcf").unwrap();
    assert_eq!(back.node_id, Some(5));
    assert_eq!(back.values[&ObjAddr::new(0x1017, 0)], Init::Bytes(vec![0x64, 0]));
    for e in eds.dict.entries() {
        let b = back.dict.get(e.addr).unwrap();
        assert_eq!(
            (&b.name, b.dtype, b.access, &b.default, b.range),
            (&e.name, e.dtype, e.access, &e.default, e.range),
            "{}",
            e.addr
        );
        assert_eq!(back.dict.display_name(e.addr), eds.dict.display_name(e.addr));
    }
}

#[test]
fn predefined_cob_ids_are_written_relative_to_the_node() {
    let dict = crate::od::builtin::dictionary(None);
    let at = |index, sub| ObjAddr::new(index, sub);
    let mut values = BTreeMap::new();
    values.insert(at(0x1800, 1), 0x8000_0194u32.to_le_bytes().to_vec()); // invalid, node 20's
    values.insert(at(0x1014, 0), 0x94u32.to_le_bytes().to_vec());
    values.insert(at(0x1200, 1), 0x1A5u32.to_le_bytes().to_vec()); // chosen by hand: kept as it is
    let header = Header { node_id: Some(20), ..Header::default() };
    let text = write(dict, Some(&values), &header);
    assert!(text.contains("[1800sub1]") && text.contains("ParameterValue=$NODEID+0x80000180"), "{text}");
    assert!(text.contains("ParameterValue=$NODEID+0x80\n"), "{text}");
    assert!(text.contains("ParameterValue=0x1A5\n"), "{text}");
    let back = parse(text.as_bytes(), "x.dcf").unwrap();
    assert_eq!(back.values[&at(0x1800, 1)].resolve(7), 0x8000_0187u32.to_le_bytes().to_vec());
}

#[test]
fn random_bytes_never_panic() {
    let (base, _) = fixture("mh-sensor.eds");
    let mut x: u64 = 0x1234_5678_9ABC_DEF1;
    for _ in 0..3000 {
        let mut bytes = base.clone();
        for _ in 0..(x % 12) {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let i = (x as usize) % bytes.len();
            bytes[i] = (x >> 32) as u8;
        }
        let _ = parse(&bytes, "fuzz.eds");
    }
}

#[test]
fn latin1_survives_writing_and_reading() {
    let mut d = Dictionary::default();
    d.var(0x2000, "Geräteschlüssel", DataType::Vs, Access::Rw, Init::Bytes("Größe".as_bytes().to_vec()));
    let text = write(&d, None, &Header::default());
    let back = parse(&to_latin1(&text), "x.eds").unwrap();
    assert_eq!(back.dict.get(ObjAddr::new(0x2000, 0)).unwrap().name, "Geräteschlüssel");
    assert_eq!(to_latin1("ä€"), vec![0xE4, b'?']);
}
