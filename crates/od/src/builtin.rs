//! Names and types that need no EDS: the CiA 301 communication objects, and the common
//! objects of the DS401 (I/O), DS402 (drives) and DS406 (encoders) profiles.

use super::{Access, Dictionary, Entry, Init, ObjectKind};
use canctl_canopen::DataType::{self, *};
use canctl_canopen::ObjAddr;
use std::sync::OnceLock;

use Access::{Const, Ro, Rw};

fn zero(t: DataType) -> Init {
    Init::Bytes(vec![0; t.size().unwrap_or(0)])
}

fn var(d: &mut Dictionary, index: u16, name: &str, t: DataType, a: Access) {
    d.var(index, name, t, a, zero(t));
}

fn members(d: &mut Dictionary, index: u16, name: &str, kind: ObjectKind, subs: &[(u8, &str, DataType, Access)]) {
    let m = subs.iter().map(|(s, n, t, a)| (*s, *n, *t, *a, zero(*t))).collect();
    match kind {
        ObjectKind::Array => d.array(index, name, m),
        _ => d.record(index, name, m),
    }
}

fn communication(d: &mut Dictionary) {
    var(d, 0x1000, "Device type", U32, Ro);
    var(d, 0x1001, "Error register", U8, Ro);
    var(d, 0x1002, "Manufacturer status register", U32, Ro);
    let errors: Vec<(u8, &str, DataType, Access)> = (1..=8).map(|s| (s, "Standard error field", U32, Ro)).collect();
    members(d, 0x1003, "Pre-defined error field", ObjectKind::Array, &errors);
    d.set_access(ObjAddr::new(0x1003, 0), Rw);
    var(d, 0x1005, "COB-ID SYNC", U32, Rw);
    var(d, 0x1006, "Communication cycle period", U32, Rw);
    var(d, 0x1007, "Synchronous window length", U32, Rw);
    var(d, 0x1008, "Manufacturer device name", Vs, Const);
    var(d, 0x1009, "Manufacturer hardware version", Vs, Const);
    var(d, 0x100A, "Manufacturer software version", Vs, Const);
    var(d, 0x100C, "Guard time", U16, Rw);
    var(d, 0x100D, "Life time factor", U8, Rw);
    let classes = ["all parameters", "communication parameters", "application parameters", "manufacturer parameters"];
    for (index, name, verb) in [(0x1010, "Store parameters", "Save"), (0x1011, "Restore default parameters", "Restore")]
    {
        let names: Vec<String> = classes.iter().map(|c| format!("{verb} {c}")).collect();
        let m: Vec<(u8, &str, DataType, Access)> =
            names.iter().zip(1..).map(|(n, s)| (s, n.as_str(), U32, Rw)).collect();
        members(d, index, name, ObjectKind::Array, &m);
    }
    var(d, 0x1012, "COB-ID time stamp", U32, Rw);
    var(d, 0x1014, "COB-ID EMCY", U32, Rw);
    var(d, 0x1015, "Inhibit time EMCY", U16, Rw);
    let consumers: Vec<(u8, &str, DataType, Access)> =
        (1..=8).map(|s| (s, "Consumer heartbeat time", U32, Rw)).collect();
    members(d, 0x1016, "Consumer heartbeat time", ObjectKind::Array, &consumers);
    var(d, 0x1017, "Producer heartbeat time", U16, Rw);
    members(
        d,
        0x1018,
        "Identity object",
        ObjectKind::Record,
        &[
            (1, "Vendor-ID", U32, Ro),
            (2, "Product code", U32, Ro),
            (3, "Revision number", U32, Ro),
            (4, "Serial number", U32, Ro),
        ],
    );
    var(d, 0x1019, "Synchronous counter overflow value", U8, Rw);
    members(
        d,
        0x1200,
        "SDO server parameter",
        ObjectKind::Record,
        &[(1, "COB-ID client to server", U32, Ro), (2, "COB-ID server to client", U32, Ro)],
    );
    // The first eight PDOs of each kind: what nearly every device has.
    for n in 0..8u16 {
        for (base, dir) in [(0x1400, "RPDO"), (0x1800, "TPDO")] {
            let mut comm = vec![
                (1, "COB-ID", U32, Rw),
                (2, "Transmission type", U8, Rw),
                (3, "Inhibit time", U16, Rw),
                (5, "Event timer", U16, Rw),
            ];
            if dir == "TPDO" {
                comm.push((6, "SYNC start value", U8, Rw));
            }
            members(d, base + n, &format!("{dir}{} communication parameter", n + 1), ObjectKind::Record, &comm);
            let map: Vec<(u8, &str, DataType, Access)> = (1..=8).map(|s| (s, "Mapped object", U32, Rw)).collect();
            let index = base + 0x200 + n;
            members(d, index, &format!("{dir}{} mapping parameter", n + 1), ObjectKind::Record, &map);
            d.set_access(ObjAddr::new(index, 0), Rw);
            // CiA 301: a PDO maps at most 64 objects (one bit each).
            d.limit(ObjAddr::new(index, 0), 0, 64);
        }
    }
}

fn ds402(d: &mut Dictionary) {
    for (index, name, t, a) in [
        (0x603F, "Error code", U16, Ro),
        (0x6040, "Controlword", U16, Rw),
        (0x6041, "Statusword", U16, Ro),
        (0x6060, "Modes of operation", I8, Rw),
        (0x6061, "Modes of operation display", I8, Ro),
        (0x6064, "Position actual value", I32, Ro),
        (0x606C, "Velocity actual value", I32, Ro),
        (0x6071, "Target torque", I16, Rw),
        (0x6077, "Torque actual value", I16, Ro),
        (0x607A, "Target position", I32, Rw),
        (0x6081, "Profile velocity", U32, Rw),
        (0x6083, "Profile acceleration", U32, Rw),
        (0x6084, "Profile deceleration", U32, Rw),
        (0x6085, "Quick stop deceleration", U32, Rw),
        (0x6098, "Homing method", I8, Rw),
        (0x60FF, "Target velocity", I32, Rw),
    ] {
        var(d, index, name, t, a);
    }
    // CiA 402: 1 to 10 are the standard modes, negative values the manufacturer's, 0 none;
    // 11 to 127 are reserved, so no drive accepts them.
    d.limit(ObjAddr::new(0x6060, 0), -128, 10);
}

fn ds406(d: &mut Dictionary) {
    var(d, 0x6000, "Operating parameters", U16, Rw);
    var(d, 0x6003, "Preset value", U32, Rw);
    var(d, 0x6004, "Position value", U32, Ro);
    members(d, 0x6020, "Position value (linear)", ObjectKind::Array, &[(1, "Channel 1", I32, Ro)]);
    members(d, 0x6030, "Speed value", ObjectKind::Array, &[(1, "Channel 1", I16, Ro)]);
    var(d, 0x6200, "Cyclic timer", U16, Rw);
    var(d, 0x6500, "Operating status", U16, Ro);
}

fn ds401(d: &mut Dictionary) {
    for (index, name, member, t, a) in [
        (0x6000, "Read input 8-bit", "Input block", U8, Ro),
        (0x6200, "Write output 8-bit", "Output block", U8, Rw),
        (0x6401, "Read analogue input 16-bit", "Analogue input", I16, Ro),
        (0x6411, "Write analogue output 16-bit", "Analogue output", I16, Rw),
    ] {
        let names: Vec<String> = (1..=8).map(|s| format!("{member} {s}")).collect();
        let m: Vec<(u8, &str, DataType, Access)> = names.iter().zip(1..).map(|(n, s)| (s, n.as_str(), t, a)).collect();
        members(d, index, name, ObjectKind::Array, &m);
    }
    var(d, 0x6423, "Analogue input global interrupt enable", Bool, Rw);
}

/// Object `index` of the CiA 301 table into `d`, named, typed and of the kind the table
/// gives it, with the members `value` gives a value, each holding it (sub 0 of a record
/// or an array counts the highest member kept). The simulated devices are built from the
/// table this way, so that the two cannot disagree.
pub fn add(d: &mut Dictionary, index: u16, value: impl Fn(&Entry) -> Option<Init>) {
    let table = dictionary(None);
    let (name, kind) = table.object_info(index).expect("an object of the CiA 301 table");
    if kind == ObjectKind::Var {
        let e = table.object_entries(index).next().expect("a variable has sub 0");
        if let Some(v) = value(e) {
            d.var(index, name, e.dtype, e.access, v);
        }
        return;
    }
    let members = table
        .object_entries(index)
        .filter(|e| e.addr.sub > 0)
        .filter_map(|e| value(e).map(|v| (e.addr.sub, e.name.as_str(), e.dtype, e.access, v)))
        .collect();
    match kind {
        ObjectKind::Array => d.array(index, name, members),
        _ => d.record(index, name, members),
    }
    let sub0 = ObjAddr::new(index, 0);
    d.set_access(sub0, table.get(sub0).expect("sub 0 of the table's object").access);
}

/// The built-in dictionary for a device of this profile (0x1000 bits 0..15: 401, 402, 406),
/// or for any device when the profile is unknown: then objects whose meaning depends on the
/// profile (0x6000 and 0x6200 are different things in DS401 and DS406) are left out.
pub fn dictionary(profile: Option<u16>) -> &'static Dictionary {
    static ANY: OnceLock<Dictionary> = OnceLock::new();
    static P401: OnceLock<Dictionary> = OnceLock::new();
    static P402: OnceLock<Dictionary> = OnceLock::new();
    static P406: OnceLock<Dictionary> = OnceLock::new();
    let build = |f: &dyn Fn(&mut Dictionary)| {
        let mut d = Dictionary::default();
        communication(&mut d);
        f(&mut d);
        d
    };
    match profile {
        Some(401) => P401.get_or_init(|| build(&ds401)),
        Some(402) => P402.get_or_init(|| build(&ds402)),
        Some(406) => P406.get_or_init(|| build(&ds406)),
        _ => ANY.get_or_init(|| {
            let (a, b) = (build(&ds401), build(&ds406));
            build(&|d: &mut Dictionary| {
                ds402(d);
                for other in [&a, &b] {
                    for (index, name, kind) in other.objects().filter(|(i, _, _)| *i >= 0x6000) {
                        let clash = [&a, &b].iter().filter(|x| x.object_info(index).is_some()).count() > 1;
                        if !clash {
                            d.object(index, name, kind);
                            for e in other.object_entries(index) {
                                d.insert(e.clone());
                            }
                        }
                    }
                }
            })
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles_and_clashes() {
        let any = dictionary(None);
        assert_eq!(any.get(ObjAddr::new(0x1017, 0)).unwrap().dtype, U16);
        assert_eq!(any.get(ObjAddr::new(0x6040, 0)).unwrap().name, "Controlword");
        assert!(any.get(ObjAddr::new(0x6000, 1)).is_none(), "DS401 and DS406 disagree on 0x6000");
        assert_eq!(any.get(ObjAddr::new(0x6401, 2)).unwrap().dtype, I16);
        assert_eq!(dictionary(Some(401)).get(ObjAddr::new(0x6000, 1)).unwrap().dtype, U8);
        assert_eq!(dictionary(Some(406)).get(ObjAddr::new(0x6000, 0)).unwrap().dtype, U16);
        assert_eq!(any.get(ObjAddr::new(0x6060, 0)).unwrap().range, Some((-128, 10)));
        assert_eq!(dictionary(Some(402)).get(ObjAddr::new(0x1A03, 0)).unwrap().range, Some((0, 64)));
        assert_eq!(
            any.display_name(ObjAddr::new(0x1A01, 0)).unwrap(),
            "TPDO2 mapping parameter: Highest sub-index supported"
        );
    }
}
