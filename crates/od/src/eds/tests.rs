use super::super::lint;
use super::values::parse_value;
use super::*;

fn fixture(name: &str) -> (Vec<u8>, String) {
    // The fixtures are the workspace's (tests/fixtures/eds), shared with the test suite.
    let path = format!("{}/../../tests/fixtures/eds/{name}", env!("CARGO_MANIFEST_DIR"));
    (std::fs::read(&path).unwrap(), name.to_string())
}

fn load(name: &str) -> Result<Eds, EdsError> {
    let (bytes, path) = fixture(name);
    parse(&bytes, &path)
}

/// The warnings as people see them.
fn said(eds: &Eds) -> Vec<String> {
    eds.warnings.iter().map(|w| w.to_string()).collect()
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
    // Latin-1 decoded; UNSIGNED24 read as itself.
    assert_eq!(eds.info["vendorname"], "MTS Sensor Technologie GmbH & Co. KG");
    assert_eq!(said(&eds), Vec::<String>::new());
    assert_eq!(d.get(ObjAddr::new(0x6021, 0)).unwrap().dtype, DataType::U24);
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
        ("broken-section.eds", "broken-section.eds:6: section header '[1001' has no closing ]"),
        ("broken-line.eds", "broken-line.eds:3: expected KEY=VALUE or [SECTION], found 'DataType 0x0007'"),
    ];
    for (file, want) in cases {
        assert_eq!(load(file).unwrap_err().to_string(), want, "{file}");
    }
    // An XML file (XDD) or any other text is not an EDS at all.
    let e = parse(b"[Settings]\nColour=blue\n", "x.ini").unwrap_err();
    assert_eq!(
        e.to_string(),
        "x.ini:1: not an EDS or DCF: it has no [FileInfo], [DeviceInfo] or object section such as [1000]"
    );
}

#[test]
fn objects_that_cannot_be_understood_are_left_out_naming_them() {
    let cases = [
        ("broken-datatype.eds", "broken-datatype.eds:3: 0x1000:0 (Device type) left out: DataType '0xZZ' is not a number"),
        (
            "broken-access.eds",
            "broken-access.eds:4: 0x1000:0 (Device type) left out: AccessType 'readwrite' is not ro, wo, rw, rwr, rww or const",
        ),
        (
            "broken-default.eds",
            "broken-default.eds:5: 0x1001:0 (Error register) left out: DefaultValue 300 is out of range for u8: use 0 to 255",
        ),
        (
            "broken-record.eds",
            "broken-record.eds:1: 1018 (Identity object) left out: an ARRAY or RECORD without any [1018subN] section or CompactSubObj",
        ),
    ];
    for (file, want) in cases {
        let eds = load(file).unwrap();
        assert_eq!(said(&eds), [want], "{file}");
        assert_eq!(eds.warnings[0].kind, lint::Kind::ObjectLeftOut);
        assert_eq!(eds.warnings[0].severity, lint::Severity::Error);
        assert_eq!(eds.dict.entries().count(), 0, "{file}");
        assert_eq!(eds.dict.objects().count(), 0, "{file}: no empty object declared");
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
    // In a VISIBLE_STRING `$NODEID` is text: node-id arithmetic is for numbers.
    assert_eq!(parse_value("$NODEID+0x180", DataType::Vs), Ok(Init::Bytes(b"$NODEID+0x180".to_vec())));
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
    let dict = crate::builtin::dictionary(None);
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
    let cob = Entry { default: back.values[&at(0x1800, 1)].clone(), ..back.dict.get(at(0x1800, 1)).unwrap().clone() };
    assert_eq!(cob.default_for(7), 0x8000_0187u32.to_le_bytes().to_vec());
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

/// A DCF of one writable entry per value, written and read back.
fn one_value_dcf(dtype: DataType, bytes: &[u8]) -> Result<(Vec<u8>, Eds), WriteError> {
    let mut d = Dictionary::default();
    d.var(0x2000, "Value", dtype, Access::Rw, Init::Bytes(dtype.size().map_or(Vec::new(), |n| vec![0; n])));
    let values = BTreeMap::from([(ObjAddr::new(0x2000, 0), bytes.to_vec())]);
    let file = write_bytes(&d, Some(&values), &Header { node_id: Some(5), ..Header::default() })?;
    let back = parse(&file, "x.dcf").unwrap_or_else(|e| panic!("{e}\n{}", String::from_utf8_lossy(&file)));
    Ok((file, back))
}

fn value_back(back: &Eds) -> Vec<u8> {
    match &back.values[&ObjAddr::new(0x2000, 0)] {
        Init::Bytes(b) => b.clone(),
        other => panic!("{other:?}"),
    }
}

#[test]
fn strings_read_back_byte_for_byte() {
    let cases: [&[u8]; 6] = [
        b"plain text",
        b"G\xF6\xDFe in Latin-1",
        "Größe € in UTF-8".as_bytes(),
        b"$NODEID is text here",
        b"; not a comment = not a key [1000]",
        b"",
    ];
    for bytes in cases {
        let (_, back) = one_value_dcf(DataType::Vs, bytes).unwrap();
        assert_eq!(value_back(&back), bytes, "{}", String::from_utf8_lossy(bytes));
    }
    // Latin-1 bytes that Rust would call white space (NBSP, NEL) are part of the value.
    let (_, back) = one_value_dcf(DataType::Vs, b"\xA0x\x85").unwrap();
    assert_eq!(value_back(&back), b"\xA0x\x85");
}

#[test]
fn strings_a_file_cannot_carry_are_refused_naming_object_and_reason() {
    let cases: [(&[u8], &str); 5] = [
        (b"two\nlines", "a line feed (0x0A)"),
        (b"EPOS2\0\0\0", "a NUL byte (0x00)"),
        (b"a\x1B[2Jb", "the control character 0x1B"),
        (b" padded", "begins or ends with a space"),
        (b"padded ", "begins or ends with a space"),
    ];
    for (bytes, why) in cases {
        let e = one_value_dcf(DataType::Vs, bytes).unwrap_err();
        assert!(e.to_string().starts_with("cannot write 0x2000:0 (Value) ParameterValue to an EDS/DCF: "), "{e}");
        assert!(e.why.contains(why), "{e}");
    }
    let e = one_value_dcf(DataType::Bool, &[2]).unwrap_err();
    assert!(e.why.contains("a BOOLEAN is 0 or 1"), "{e}");
    let e = one_value_dcf(DataType::U32, &[1, 2, 3]).unwrap_err();
    assert_eq!(e.why, "it holds 3 bytes; a u32 is 4");
}

#[test]
fn a_newline_in_a_name_does_not_inject_keys() {
    let mut d = Dictionary::default();
    d.var(0x2000, "x\nDataType=0x0009", DataType::U8, Access::Rw, Init::Bytes(vec![0]));
    let e = write_bytes(&d, None, &Header::default()).unwrap_err();
    assert!(e.to_string().contains("[2000] ParameterName 'x\\nDataType=0x0009'"), "{e}");
    let h = Header { product_name: "EPOS2\r\n[1000]".into(), ..Header::default() };
    assert!(write_bytes(&Dictionary::default(), None, &h).unwrap_err().to_string().contains("ProductName"));
}

#[test]
fn reals_keep_their_bits_infinities_and_nans_included() {
    let r32 = [0.0f32, -0.0, 1.5, f32::MIN_POSITIVE, 1e-45, f32::MAX, f32::INFINITY, f32::NEG_INFINITY, f32::NAN];
    for v in r32.iter().map(|v| v.to_bits()).chain([0x7FC0_0001, 0xFFC0_0000, 0x7F80_0001]) {
        let (_, back) = one_value_dcf(DataType::R32, &v.to_le_bytes()).unwrap();
        assert_eq!(value_back(&back), v.to_le_bytes(), "0x{v:08X}");
    }
    for v in
        [0.1f64, -2e300, 5e-324, f64::INFINITY, f64::NAN].iter().map(|v| v.to_bits()).chain([0x7FF0_0000_0000_0001])
    {
        let (_, back) = one_value_dcf(DataType::R64, &v.to_le_bytes()).unwrap();
        assert_eq!(value_back(&back), v.to_le_bytes(), "0x{v:016X}");
    }
    assert_eq!(value_text(&Init::Bytes(f32::NEG_INFINITY.to_le_bytes().to_vec()), DataType::R32).unwrap(), "-inf");
    assert_eq!(value_text(&Init::Bytes(f32::NAN.to_le_bytes().to_vec()), DataType::R32).unwrap(), "nan");
    assert_eq!(value_text(&Init::Bytes(5e-324f64.to_le_bytes().to_vec()), DataType::R64).unwrap(), "5e-324");
    // Files by other tools: any case, a sign.
    for (text, want) in [("inf", f32::INFINITY), ("-Infinity", f32::NEG_INFINITY), ("NaN", f32::NAN)] {
        assert_eq!(parse_value(text, DataType::R32), Ok(Init::Bytes(want.to_le_bytes().to_vec())), "{text}");
    }
    assert!(parse_value("0x7FC0", DataType::R32).unwrap_err().contains("0x and 8 digits"));
}

#[test]
fn node_id_arithmetic_is_checked_against_the_type() {
    assert_eq!(parse_value("$NODEID+0x80", DataType::U8), Ok(Init::NodeIdPlus(0x80)));
    assert_eq!(parse_value("0x180 + $nodeid", DataType::U32), Ok(Init::NodeIdPlus(0x180)));
    assert_eq!(parse_value("$NODEID+0x80000180", DataType::U32), Ok(Init::NodeIdPlus(0x8000_0180)));
    assert_eq!(parse_value("$NODEID+0x100000000", DataType::U64), Ok(Init::NodeIdPlus(0x1_0000_0000)));
    // 0x180 + node-id in a u8 used to be cut to its low byte without a word.
    assert_eq!(
        parse_value("$NODEID+0x180", DataType::U8).unwrap_err(),
        "'$NODEID+0x180' exceeds u8 (at most 255): node-id 127 would give 511; only offsets up to 128 fit every node-id"
    );
    assert!(parse_value("$NODEID+0xFFFFFFFF", DataType::U32).unwrap_err().contains("exceeds u32"));
    assert!(parse_value("$NODEID+0x7F", DataType::I8).unwrap_err().contains("exceeds i8"));
    for bad in ["$NODEID-1", "$NODEID+", "$NODEID+0x180+1", "2*$NODEID", "$NODEID0x180"] {
        assert!(parse_value(bad, DataType::U32).unwrap_err().contains("is not $NODEID"), "{bad}");
    }
    for t in [DataType::Bool, DataType::R32, DataType::Os] {
        assert!(parse_value("$NODEID", t).unwrap_err().contains("needs an integer type"), "{t}");
    }
    // The sum for the highest node-id fits the entry: no silent cut.
    let e = Entry {
        addr: ObjAddr::new(0x2000, 0),
        name: "x".into(),
        dtype: DataType::U8,
        access: Access::Rw,
        default: parse_value("$NODEID+0x80", DataType::U8).unwrap(),
        range: None,
    };
    assert_eq!(e.default_for(127), vec![0xFF]);
}

#[test]
fn an_unknown_data_type_leaves_its_object_out_with_its_line() {
    let file = b"[2000]\nParameterName=x\nObjectType=7\nDataType=0x10007\nAccessType=rw\n";
    assert_eq!(
        said(&parse(file, "t.eds").unwrap()),
        ["t.eds:4: 0x2000:0 (x) left out: DataType 0x10007 is not a CiA 301 data type (0x0001..0x025F; 0x0007 is UNSIGNED32)"]
    );
    for code in ["0", "0x0260", "-7"] {
        let file = format!("[2000]\nParameterName=x\nDataType={code}\nAccessType=rw\n");
        assert!(said(&parse(file.as_bytes(), "t.eds").unwrap())[0].starts_with("t.eds:3: "), "{code}");
    }
    // A complex or manufacturer type (0x0040) is no basic type: its bytes, as python-canopen reads it.
    let eds = parse(b"[2000]\nParameterName=x\nDataType=0x0040\nAccessType=rw\nDefaultValue=7\n", "t.eds").unwrap();
    assert_eq!(
        said(&eds),
        ["t.eds:3: 0x2000:0 (x) has data type 0x0040, not a CiA 301 basic type: read as DOMAIN (d), its bytes as they are, no default"]
    );
    assert_eq!(eds.dict.get(ObjAddr::new(0x2000, 0)).unwrap().dtype, DataType::D);
    assert_eq!(eds.warnings[0].severity, lint::Severity::Warning);
}

#[test]
fn bom_crlf_repeats_and_long_lines() {
    let mut file =
        b"\xEF\xBB\xBF[2000]\r\nParameterName=Gr\xC3\xB6\xC3\x9Fe\r\nDataType=0x0006\r\nAccessType=rw\r\n".to_vec();
    file.extend_from_slice(
        b"DefaultValue=1\r\ndefaultvalue = 2\r\n[2000]\r\nParameterName=again\r\nDataType=0x0009\r\n",
    );
    file.extend_from_slice(format!("AccessType=rw\r\nDefaultValue={}\r\n", "x".repeat(300)).as_bytes());
    let eds = parse(&file, "t.eds").unwrap();
    // The repeated section replaces the first one; both repeats are named with both lines.
    let e = eds.dict.get(ObjAddr::new(0x2000, 0)).unwrap();
    assert_eq!((e.name.as_str(), e.dtype, e.default.clone()), ("again", DataType::Vs, Init::Bytes(vec![b'x'; 300])));
    assert_eq!(
        said(&eds),
        [
            "t.eds:6: defaultvalue repeated in [2000] (before at line 5): the value of line 6 is used",
            "t.eds:7: section [2000] again (before at line 1): this one replaces it",
            "t.eds:11: line of 313 characters, more than the 255 CiA 306 allows (read in full)",
        ]
    );
    // A BOM says UTF-8: names are decoded so.
    let bom = b"\xEF\xBB\xBF[2000]\r\nParameterName=Gr\xC3\xB6\xC3\x9Fe\r\nDataType=0x0006\r\nAccessType=rw\r\n";
    assert_eq!(parse(bom, "t.eds").unwrap().dict.get(ObjAddr::new(0x2000, 0)).unwrap().name, "Größe");
}

#[test]
fn names_beyond_latin1_are_written_as_utf8() {
    let mut d = Dictionary::default();
    d.var(0x2000, "Drehmoment in N·m ≤ 5 €", DataType::Vs, Access::Rw, Init::Bytes(b"\xFF raw".to_vec()));
    let file = write_bytes(&d, None, &Header::default()).unwrap();
    assert!(file.starts_with(BOM), "a value's raw bytes would make the file read as Latin-1");
    let back = parse(&file, "x.eds").unwrap();
    let e = back.dict.get(ObjAddr::new(0x2000, 0)).unwrap();
    assert_eq!((e.name.as_str(), &e.default), ("Drehmoment in N·m ≤ 5 €", &Init::Bytes(b"\xFF raw".to_vec())));
}

#[test]
fn a_flood_of_repeated_keys_gives_a_bounded_list() {
    let mut file = b"[DeviceInfo]\n".to_vec();
    for _ in 0..10_000 {
        file.extend_from_slice(b"VendorName=x\n");
    }
    let eds = parse(&file, "t.eds").unwrap();
    assert_eq!(eds.warnings.len(), lint::MAX_WARNINGS + 1);
    assert_eq!(
        said(&eds)[0],
        "t.eds:3: VendorName repeated in [deviceinfo] (before at line 2): the value of line 3 is used"
    );
    assert_eq!(said(&eds)[lint::MAX_WARNINGS], "t.eds: further deviations left out (the first 200 are listed)");
}

#[test]
fn signed_limits_in_hex_are_twos_complement() {
    let file = b"[2000]\nParameterName=x\nDataType=0x0003\nAccessType=rw\nLowLimit=0x8000\nHighLimit=0x7FFF\nDefaultValue=0xFFFF\n";
    let e = parse(file, "t.eds").unwrap().dict.get(ObjAddr::new(0x2000, 0)).unwrap().clone();
    assert_eq!((e.range, e.default), (Some((-32768, 32767)), Init::Bytes(vec![0xFF, 0xFF])));
    // In decimal, 65535 is 65535: out of range for an INTEGER16, not silently -1.
    let file = b"[2000]\nParameterName=x\nDataType=0x0003\nAccessType=rw\nDefaultValue=65535\n";
    assert!(said(&parse(file, "t.eds").unwrap())[0].contains("65535 is out of range for i16"));
}

#[test]
fn domain_objects_are_single_values_read_as_d() {
    let eds = load("domain.eds").unwrap();
    let d = &eds.dict;
    let at = |i| d.get(ObjAddr::new(i, 0)).unwrap();
    assert_eq!(
        (at(0x1F50).dtype, at(0x1F50).access, at(0x1F50).default.clone()),
        (DataType::D, Access::Rw, Init::Bytes(vec![]))
    );
    assert_eq!(d.object_info(0x3D02), Some(("Error History", ObjectKind::Var)));
    assert_eq!(at(0x3D03).default, Init::Bytes(vec![0xDE, 0xAD, 0xBE, 0xEF]));
    // A DOMAIN object needs neither DataType nor AccessType.
    assert_eq!((at(0x3D04).dtype, at(0x3D04).access), (DataType::D, Access::Rw));
    // A default that is no hex is not the content: read as empty, said so.
    assert_eq!(at(0x3D05).default, Init::Bytes(vec![]));
    // NULL (or 0) says "nothing": read so, with a warning only.
    assert_eq!(at(0x3D06).default, Init::Bytes(vec![]));
    assert_eq!(
        said(&eds),
        [
            "domain.eds:45: DefaultValue of 0x3D05:0 (Notes): 'see manual' is not hex bytes: 's' is not a hex digit; read as empty",
            "domain.eds:52: DefaultValue=NULL of DOMAIN 0x3D06:0 (Storage EDS) read as empty"
        ]
    );
    let severities: Vec<lint::Severity> = eds.warnings.iter().map(|w| w.severity).collect();
    assert_eq!(severities, [lint::Severity::Error, lint::Severity::Warning]);
}

#[test]
fn compact_sub_objects_with_their_name_and_value_sections() {
    let eds = load("compact.dcf").unwrap();
    let d = &eds.dict;
    assert_eq!(d.object_info(0x1003), Some(("Pre-defined error field", ObjectKind::Array)));
    assert_eq!(d.object_entries(0x1003).count(), 255);
    let sub0 = d.get(ObjAddr::new(0x1003, 0)).unwrap();
    assert_eq!((sub0.dtype, sub0.access, sub0.default.clone()), (DataType::U8, Access::Ro, Init::Bytes(vec![254])));
    let e = d.get(ObjAddr::new(0x1003, 254)).unwrap();
    assert_eq!((e.name.as_str(), e.dtype, e.access), ("Pre-defined error field254", DataType::U32, Access::Rw));
    // [1016Name] names the members; [1016Value] gives a DCF's values, and the count.
    assert_eq!(d.display_name(ObjAddr::new(0x1016, 2)).unwrap(), "Consumer heartbeat time: Heartbeat of the encoder");
    assert_eq!(d.get(ObjAddr::new(0x1016, 3)).unwrap().name, "Consumer heartbeat time3");
    assert_eq!(eds.values[&ObjAddr::new(0x1016, 1)], Init::Bytes(0x0002_01F4u32.to_le_bytes().to_vec()));
    assert_eq!(eds.values[&ObjAddr::new(0x1016, 0)], Init::Bytes(vec![2]));
    assert!(!eds.values.contains_key(&ObjAddr::new(0x1016, 3)));
    // [DummyUsage]: the types a PDO may map as gaps.
    assert_eq!(eds.dummy_usage, BTreeSet::from([0x0002, 0x0005]));
    // A RECORD with CompactSubObj (Lely's dcfgen writes PDO mappings so): read as meant.
    assert_eq!(d.object_info(0x1A00), Some(("TPDO mapping parameter", ObjectKind::Record)));
    assert_eq!(eds.values[&ObjAddr::new(0x1A00, 1)], Init::Bytes(0x6064_0020u32.to_le_bytes().to_vec()));
    assert_eq!(eds.values[&ObjAddr::new(0x1A00, 0)], Init::Bytes(vec![1]));
    assert_eq!(
        said(&eds),
        [
            "compact.dcf:16: [DummyUsage] Dummy0007=yes is not DummyNNNN=0 or 1: ignored",
            "compact.dcf:49: 1A00 (TPDO mapping parameter) is a RECORD with CompactSubObj=1: read as an ARRAY of 1 sub-objects of its DataType"
        ]
    );
}

#[test]
fn deviations_a_reader_can_interpret_are_read_and_said() {
    let eds = load("deviations.dcf").unwrap();
    let d = &eds.dict;
    // Placeholders in [DeviceCommissioning]: no node-id from the file.
    assert_eq!(eds.node_id, None);
    // Inline comments after numbers are comments; in strings and names they are text.
    assert_eq!(eds.values[&ObjAddr::new(0x1017, 0)], Init::Bytes(vec![0xF4, 0x01]));
    assert_eq!(d.get(ObjAddr::new(0x6502, 0)).unwrap().default, Init::Bytes(0x3EDu32.to_le_bytes().to_vec()));
    assert_eq!(d.get(ObjAddr::new(0x2003, 0)).unwrap().name, "Comment ; kept in a name");
    assert_eq!(d.get(ObjAddr::new(0x2003, 0)).unwrap().default, Init::Bytes(b"a ; b".to_vec()));
    // A missing SubNumber: the sub sections there are are read.
    assert_eq!(d.object_entries(0x2000).count(), 3);
    // An array with no sub-objects at all is left out; the rest of the file is read.
    assert!(!d.has_index(0x2001) && d.object_info(0x2001).is_none());
    assert_eq!(d.object_entries(0x2002).count(), 2);
    let kinds: Vec<(usize, lint::Kind)> = eds.warnings.iter().map(|w| (w.line, w.kind)).collect();
    use lint::Kind::*;
    assert_eq!(
        kinds,
        [
            (10, PlaceholderCommissioning),
            (11, PlaceholderCommissioning),
            (19, InlineComment),
            (25, InlineComment),
            (27, MissingSubNumber),
            (49, ObjectLeftOut),
            (59, SubNumberMismatch),
        ]
    );
    let said = said(&eds);
    assert_eq!(said[2], "deviations.dcf:19: ParameterValue=500\t; half a second: the text from ';' on is read as a comment; the value is '500'");
    assert_eq!(
        said[5],
        "deviations.dcf:49: 2001 (Valve % open) left out: an ARRAY or RECORD without any [2001subN] section or CompactSubObj"
    );
    assert!(eds.warnings.iter().all(|w| !w.rule.is_empty() && w.rule.starts_with("CiA 306")));
}

#[test]
fn windows_1252_names_read_as_meant() {
    let eds = load("cp1252.eds").unwrap();
    assert_eq!(eds.info["vendorname"], "Grüße “quoted” – €");
    assert_eq!(eds.dict.get(ObjAddr::new(0x2000, 0)).unwrap().name, "Drehzahl “Soll”");
}

#[test]
fn every_cia_301_basic_type_is_read_and_written_back() {
    let eds = load("all-types.eds").unwrap();
    assert_eq!(said(&eds), Vec::<String>::new());
    let d = &eds.dict;
    let default = |i| d.get(ObjAddr::new(i, 0)).unwrap().default_for(5);
    assert_eq!(default(0x2010), [0xFF; 3]);
    assert_eq!(default(0x2013), [0, 0, 0, 0, 0, 0x80], "hex is two's complement");
    assert_eq!(default(0x2016), [0xFF; 3]);
    assert_eq!(default(0x2019), [0x05, 0x01, 0, 0, 0, 0]);
    assert_eq!(default(0x200C), [0x00, 0x2E, 0x93, 0x02, 0x12, 0x39]);
    assert_eq!(default(0x200D), [0; 6]);
    assert_eq!(default(0x200B), [0x61, 0, 0x62, 0, 0x63, 0, 0x13, 0x27]);
    let text = write(d, None, &Header::default());
    let back = parse(&to_latin1(&text), "back.eds").unwrap();
    for e in d.entries() {
        let b = back.dict.get(e.addr).unwrap();
        assert_eq!((b.dtype, b.default_for(5)), (e.dtype, e.default_for(5)), "{}", e.addr);
    }
}

#[test]
fn object_lists_that_disagree_with_the_sections_are_said() {
    let eds = load("object-lists.eds").unwrap();
    assert_eq!(eds.dict.objects().count(), 3, "the sections are read");
    assert_eq!(
        said(&eds),
        [
            "object-lists.eds:1: no [1001] section: CiA 301 makes 0x1001 mandatory for every device",
            "object-lists.eds:2: [MandatoryObjects] SupportedObjects=3 but it lists 2: the sections are read",
            "object-lists.eds:8: [OptionalObjects] lists 0x1017, which has no [1017] section: nothing to read",
            "object-lists.eds:20: [2000] is in no object list ([MandatoryObjects], [OptionalObjects], [ManufacturerObjects]): read all the same",
        ]
    );
    assert_eq!(eds.warnings[0].kind, lint::Kind::MissingMandatory);
    assert!(eds.warnings[1..].iter().all(|w| w.kind == lint::Kind::ObjectList));
    assert!(eds.warnings.iter().all(|w| w.severity == lint::Severity::Warning));
}
