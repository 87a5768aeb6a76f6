//! XDD and XDC files (CiA 311): read wherever an EDS or DCF is, giving the same objects as
//! the EDS of the same device; written by `config dump --format xdc` and read back.

use crate::common;

use canctl::canopen::ObjAddr;
use canctl::od::{self, eds::Eds, Access, Init, ObjectKind};
use common::Sim;
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/xdd").join(name)
}

fn read(name: &str) -> Eds {
    od::read_description(&fixture(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// A file of the shared corpus of real files (see `common::eds_corpus`).
fn corpus(name: &str) -> Option<PathBuf> {
    let path = common::eds_corpus()?.join(name);
    assert!(path.exists(), "{} is missing from the corpus", path.display());
    Some(path)
}

/// Each entry as (index, sub, type, access, default, name), and each object's name and kind.
type Objects = (Vec<(u16, u8, String, Access, Init, String)>, Vec<(u16, String, ObjectKind)>);

fn objects(e: &Eds) -> Objects {
    let entries = e
        .dict
        .entries()
        .map(|x| (x.addr.index, x.addr.sub, x.dtype.to_string(), x.access, x.default.clone(), x.name.clone()))
        .collect();
    let objects = e.dict.objects().map(|(i, n, k)| (i, n.to_string(), k)).collect();
    (entries, objects)
}

#[test]
fn the_demo_devices_xdd_gives_the_objects_of_its_eds() {
    let (Some(xdd), Some(eds)) = (corpus("CANopenDemo__demoDevice.xdd"), corpus("CANopenDemo__demoDevice.eds")) else {
        return;
    };
    let from_xdd = od::read_description(&xdd).unwrap();
    let from_eds = od::read_description(&eds).unwrap();
    let (x, e) = (objects(&from_xdd), objects(&from_eds));
    assert!(x.0.len() > 250, "only {} entries read from the XDD", x.0.len());
    for (a, b) in x.0.iter().zip(&e.0) {
        assert_eq!(a, b, "XDD entry differs from the EDS's");
    }
    assert_eq!(x.0.len(), e.0.len(), "as many entries in the XDD as in the EDS");
    assert_eq!(x.1, e.1, "the same objects, names and kinds");
    assert_eq!(from_xdd.info.get("productname").map(String::as_str), Some("Demo device"));
}

#[test]
fn both_forms_of_an_object_are_read() {
    let e = read("small.xdd");
    let get = |i, s| e.dict.get(ObjAddr::new(i, s)).unwrap_or_else(|| panic!("{i:04X}:{s} missing"));
    // Attributes on the CANopenObject.
    let device_type = get(0x1000, 0);
    assert_eq!((device_type.dtype.to_string().as_str(), device_type.access), ("u32", Access::Ro));
    assert_eq!(device_type.default, Init::Bytes(0x0002_0192u32.to_le_bytes().to_vec()));
    assert_eq!(get(0x1008, 0).default, Init::Bytes(b"Small & simple".to_vec()));
    assert_eq!(get(0x1014, 0).default, Init::NodeIdPlus(0x80));
    // A parameter named by uniqueIDRef: type element, access attribute, defaultValue element.
    let heartbeat = get(0x1017, 0);
    assert_eq!((heartbeat.dtype.to_string().as_str(), heartbeat.access), ("u16", Access::Rw));
    assert_eq!(heartbeat.default, Init::Bytes(100u16.to_le_bytes().to_vec()));
    // A parameter without access is read-only (CiA 311's default).
    assert_eq!(get(0x1018, 1).access, Access::Ro);
    assert_eq!(get(0x1018, 1).default, Init::Bytes(0xFBu32.to_le_bytes().to_vec()));
    // BITSTRING without a default is a DOMAIN; with one, an OCTET_STRING.
    assert_eq!(get(0x2000, 0).dtype.to_string(), "d");
    assert_eq!(get(0x2001, 0).dtype.to_string(), "os");
    assert_eq!(get(0x2001, 0).default, Init::Bytes(vec![0xC8, 0x3D, 0xBB]));
    assert_eq!(get(0x2002, 0).range, Some((-100, 100)));
    assert_eq!(e.dict.object_info(0x1016), Some(("Consumer heartbeat time", ObjectKind::Array)));
    assert_eq!(e.dict.object_info(0x1018), Some(("Identity object", ObjectKind::Record)));
    assert_eq!(e.dict.object_entries(0x1016).count(), 3);
    assert!(e.values.is_empty(), "an XDD has no actual values");
    assert!(!e.dict.has_index(0x1280) && e.dict.object_info(0x1280).is_none(), "CO_disabled objects are left out");
    assert_eq!(e.info.get("vendornumber").map(String::as_str), Some("0x000000FB"));
    assert!(e.warnings.is_empty(), "{:?}", e.warnings);
}

#[test]
fn an_xdcs_actual_values_and_node_are_what_the_node_is_to_hold() {
    let e = read("small.xdc");
    assert_eq!(e.node_id, Some(7));
    let value = |i, s| e.values.get(&ObjAddr::new(i, s)).cloned();
    assert_eq!(value(0x1017, 0), Some(Init::Bytes(250u16.to_le_bytes().to_vec())), "actualValue of a parameter");
    assert_eq!(value(0x1800, 2), Some(Init::Bytes(vec![1])));
    assert_eq!(value(0x1800, 5), Some(Init::Bytes(100u16.to_le_bytes().to_vec())));
    assert_eq!(value(0x1014, 0), Some(Init::NodeIdPlus(0x80)));
    assert_eq!(value(0x1000, 0), None, "no actualValue, no value");
}

#[test]
fn a_malformed_xml_file_is_refused_with_file_line_and_column() {
    let path = fixture("malformed.xdd");
    let err = od::read_description(&path).unwrap_err().to_string();
    // Line 7 closes the list while an object is still open.
    let expected =
        format!("{}:7:7: malformed XML: expected 'CANopenObject' tag, not 'CANopenObjectList'", path.display());
    assert_eq!(err, expected);
}

#[test]
fn xml_is_told_by_content_not_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let named_eds = dir.path().join("vendor.eds");
    std::fs::copy(fixture("small.xdd"), &named_eds).unwrap();
    assert!(od::read_description(&named_eds).unwrap().dict.get(ObjAddr::new(0x1017, 0)).is_some());
    // And an XML file that is no device description says so, with its position.
    let other = dir.path().join("other.xml");
    std::fs::write(&other, "<?xml version=\"1.0\"?>\n<project/>\n").unwrap();
    let err = od::read_description(&other).unwrap_err().to_string();
    assert!(err.contains("other.xml:2:1: <project> is not an XDD or XDC"), "{err}");
}

#[test]
fn an_xdd_names_objects_on_the_command_line() {
    let sim = Sim::new();
    let eds = format!("1={}", fixture("small.xdd").display());
    // A name only the XDD has; read with the XDD's type (the drive's 0x2000 is its node-id).
    let json = sim.run(&["--eds", &eds, "--format", "json", "sdo", "read", "1", "Firmware image"]).ok().json();
    assert_eq!((json["object"].as_str(), json["type"].as_str()), (Some("0x2000:0"), Some("d")), "{json}");
}

#[test]
fn config_diff_takes_an_xdc() {
    let sim = Sim::new();
    // The drive (node 1) beats at 0 ms; the XDC wants 250: one difference.
    let run = sim.run(&["config", "diff", "1", fixture("small.xdc").to_str().unwrap(), "--check", "--format", "json"]);
    assert_eq!(run.code, 6, "{}{}", run.stdout, run.stderr);
    let json = run.json();
    let differs: Vec<&str> =
        json["differences"].as_array().unwrap().iter().map(|d| d["object"].as_str().unwrap_or_default()).collect();
    assert!(differs.iter().any(|o| o.contains("1017")), "{json}");
}

#[test]
fn a_dumped_xdc_reads_back_to_the_same_values() {
    let sim = Sim::new();
    let dir = tempfile::tempdir().unwrap();
    let (xdc, dcf) = (dir.path().join("io.xdc"), dir.path().join("io.dcf"));
    sim.run(&["config", "dump", "10", "--out", xdc.to_str().unwrap()]).ok();
    sim.run(&["config", "dump", "10", "--out", dcf.to_str().unwrap()]).ok();
    let (from_xdc, from_dcf) = (od::read_description(&xdc).unwrap(), od::read_description(&dcf).unwrap());
    assert!(std::fs::read(&xdc).unwrap().starts_with(b"<?xml"), "--out x.xdc writes XML");
    assert_eq!(from_xdc.node_id, Some(10));
    assert!(from_xdc.values.len() > 20, "{} values", from_xdc.values.len());
    assert_eq!(from_xdc.values, from_dcf.values, "the XDC holds what the DCF holds");
    assert_eq!(objects(&from_xdc), objects(&from_dcf));
    // --format xdc on standard output, and the node matches what it says.
    let stdout = sim.run(&["--format", "xdc", "config", "dump", "10"]).ok().stdout;
    assert!(stdout.starts_with("<?xml"), "{stdout}");
    let run = sim.run(&["config", "diff", "10", xdc.to_str().unwrap(), "--check"]);
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
}

#[test]
fn format_xdc_is_for_config_dump_only() {
    let sim = Sim::new();
    let run = sim.run(&["--format", "xdc", "scan"]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("--format xdc is for canctl config dump"), "{}", run.stderr);
}

#[test]
fn a_network_project_may_name_xdcs() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--profile", "instant", "--unconfigured", "0"]).ok();
    let dir = sim.path("machine");
    sim.run(&["network", "dump", dir.to_str().unwrap(), "--bit-rate", "500k"]).ok();
    let xdc = dir.join("node10.xdc");
    sim.run(&["config", "dump", "10", "--out", xdc.to_str().unwrap()]).ok();
    let cpj = std::fs::read_to_string(dir.join("nodelist.cpj")).unwrap();
    std::fs::write(dir.join("nodelist.cpj"), cpj.replace("Node10DCFName=node10.dcf", "Node10DCFName=node10.xdc"))
        .unwrap();
    std::fs::remove_file(dir.join("node10.dcf")).unwrap();
    let run = sim.run(&["network", "check", dir.to_str().unwrap(), "--format", "json"]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    // The XDC's DeviceCommissioning is held to the project as a DCF's is.
    let text = std::fs::read_to_string(&xdc).unwrap().replace("nodeID=\"10\"", "nodeID=\"11\"");
    std::fs::write(&xdc, text).unwrap();
    let run = sim.run(&["network", "check", dir.to_str().unwrap()]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("node10.xdc is for node-id 11 (DeviceCommissioning nodeID), but"), "{}", run.stderr);
}

#[test]
fn config_apply_holds_an_xdc_to_the_identity_it_names() {
    let sim = Sim::new();
    // small.xdc names product 0x1234; the drive is 0x6220.
    let run = sim.run(&["config", "apply", "1", fixture("small.xdc").to_str().unwrap()]);
    assert_eq!(run.code, 6, "{}{}", run.stdout, run.stderr);
    assert!(run.stderr.contains("is for another device") && run.stderr.contains("0x00001234"), "{}", run.stderr);
}

#[test]
fn a_settings_files_eds_may_be_an_xdd() {
    let sim = Sim::new();
    let project = sim.path("cell");
    std::fs::create_dir_all(&project).unwrap();
    let toml = format!("[nodes.1]\neds = \"{}\"\n", fixture("small.xdd").display());
    std::fs::write(project.join("canctl.toml"), toml).unwrap();
    // A name only the XDD has (the drive's 0x2000 is its node-id, read as the XDD's DOMAIN).
    let mut c = sim.command(&["--format", "json", "sdo", "read", "1", "Firmware image"]);
    let json = common::finish(c.current_dir(&project).output().unwrap()).ok().json();
    assert_eq!((json["object"].as_str(), json["type"].as_str()), (Some("0x2000:0"), Some("d")), "{json}");
}
