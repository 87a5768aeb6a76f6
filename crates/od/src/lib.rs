//! CANopen object dictionaries and the files that describe them: the dictionary model (what
//! a device holds, by address, with type, access and default), EDS and DCF (CiA 306) read
//! and written, XDD and XDC (CiA 311) read, CPJ network projects (CiA 306-3), the lint of a
//! description, the built-in CiA 301 tables, object names; and bounded reads of input files.
//! canctl's simulated devices are built from it, and object names resolve through it.
//!
//! Above `canctl-canopen` (types and addresses), below canctl's bus and procedures.

// Every public item says what it is for; an item not meant for users is `pub(crate)`.
#![deny(missing_docs)]

pub mod input;

pub mod builtin;
pub mod cpj;
pub mod eds;
pub mod lint;
pub mod names;
pub mod stored;
pub mod xdd;

use canctl_canopen::{DataType, ObjAddr};
use std::collections::BTreeMap;

/// A device description that could not be used: an EDS or DCF at file:line, an XDD or XDC
/// at file:line:column.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
// Exhaustive on purpose: canctl words every variant, and the compiler says when one is new.
pub enum ReadError {
    /// An EDS or DCF (INI text) that could not be used.
    #[error(transparent)]
    Ini(#[from] eds::EdsError),
    /// An XDD or XDC (XML) that could not be used.
    #[error(transparent)]
    Xml(#[from] xdd::XmlError),
}

/// An EDS, DCF, XDD or XDC, told apart by content (XML or INI), not by the file's name:
/// vendors ship XDDs named `.eds` and tools write XDCs without an extension.
pub fn parse_description(bytes: &[u8], path: &str) -> Result<eds::Eds, ReadError> {
    Ok(if xdd::is_xml(bytes) { xdd::parse(bytes, path)? } else { eds::parse(bytes, path)? })
}

/// [`parse_description`] of a file: a regular file within `input::MAX_EDS_BYTES`.
pub fn read_description(path: &std::path::Path) -> Result<eds::Eds, ReadError> {
    parse_description(&eds::read_bytes(path)?, &path.display().to_string())
}

/// What a device holds (or is to hold), by object address: a DCF's or an XDC's values.
pub type Values = BTreeMap<ObjAddr, Vec<u8>>;

/// The objects CiA 301 makes mandatory for every device: device type, error register and
/// identity.
pub(crate) const MANDATORY: [u16; 3] = [0x1000, 0x1001, 0x1018];

/// Who may read and write an entry over SDO (EDS `AccessType`).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Access {
    /// Read only: the device may change it (a measured value).
    Ro,
    /// Write only.
    Wo,
    /// Read and write.
    Rw,
    /// Read only, and it never changes.
    Const,
}

impl Access {
    /// Whether an SDO upload may read it.
    pub fn readable(self) -> bool {
        self != Access::Wo
    }
    /// Whether an SDO download may write it.
    pub fn writable(self) -> bool {
        matches!(self, Access::Rw | Access::Wo)
    }
    /// Its EDS spelling: `ro`, `wo`, `rw`, `const`.
    pub fn name(self) -> &'static str {
        match self {
            Access::Ro => "ro",
            Access::Wo => "wo",
            Access::Rw => "rw",
            Access::Const => "const",
        }
    }
}

/// CiA 306 object types.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ObjectKind {
    /// A single value (sub-index 0 only).
    Var,
    /// Sub-entries of one data type, sub-index 0 holding their number.
    Array,
    /// Sub-entries of different data types.
    Record,
}

impl ObjectKind {
    /// Its CiA 306 `ObjectType` code: 7, 8 or 9.
    pub fn code(self) -> u8 {
        match self {
            ObjectKind::Var => 7,
            ObjectKind::Array => 8,
            ObjectKind::Record => 9,
        }
    }
}

/// A default value; COB-IDs and the like depend on the node-id (EDS `$NODEID+0x180`).
#[derive(Clone, PartialEq, Debug)]
pub enum Init {
    /// The value as the device holds it (numbers little-endian).
    Bytes(Vec<u8>),
    /// The device's node-id added to this base (COB-IDs).
    NodeIdPlus(u64),
}

impl Init {
    /// Bytes of the default; node-id-relative ones as a u64, cut to size by the entry (the
    /// EDS reader refuses offsets that would not fit the entry's type for node-id 127).
    pub fn resolve(&self, node_id: u8) -> Vec<u8> {
        match self {
            Init::Bytes(b) => b.clone(),
            Init::NodeIdPlus(base) => base.saturating_add(u64::from(node_id)).to_le_bytes().to_vec(),
        }
    }
}

/// One sub-entry of an object dictionary: what it holds and who may access it.
#[derive(Clone, Debug)]
pub struct Entry {
    /// Its index and sub-index.
    pub addr: ObjAddr,
    /// Its name, as the description gives it (`ParameterName`).
    pub name: String,
    /// The type of its value.
    pub dtype: DataType,
    /// Who may read and write it.
    pub access: Access,
    /// Its default, or a DCF's value.
    pub default: Init,
    /// Inclusive limits for integer values, beyond the type's own.
    pub range: Option<(i128, i128)>,
}

impl Entry {
    /// Sub-index 0 of an ARRAY or RECORD, read-only: the highest sub-index, `highest`.
    pub(crate) fn count(index: u16, name: &str, highest: u8) -> Entry {
        let (dtype, access, default) = (DataType::U8, Access::Ro, Init::Bytes(vec![highest]));
        Entry { addr: ObjAddr::new(index, 0), name: name.to_string(), dtype, access, default, range: None }
    }

    /// The default for a device with this node-id, in the entry's own size.
    pub fn default_for(&self, node_id: u8) -> Vec<u8> {
        self.value_for(&self.default, node_id)
    }

    /// A value of this entry (a default, a DCF's value) for a device with this node-id, in
    /// the entry's own size.
    pub fn value_for(&self, init: &Init, node_id: u8) -> Vec<u8> {
        let mut v = init.resolve(node_id);
        if let Some(size) = self.dtype.size() {
            v.resize(size, 0);
        }
        v
    }

    /// Whether the entry's limits refuse `bytes`: the one judgement `sdo write`, `config
    /// apply` and the file readers (so `config check`) share. Only integers have limits.
    pub fn outside_limits(&self, bytes: &[u8]) -> Option<OutsideLimits> {
        let (low, high) = self.range?;
        let value = match self.dtype.decode(bytes)? {
            canctl_canopen::types::Value::Uint(u) => i128::from(u),
            canctl_canopen::types::Value::Int(i) => i128::from(i),
            _ => return None,
        };
        (value < low || value > high).then_some(OutsideLimits { value, low, high, node_id: None })
    }

    /// [`Entry::outside_limits`] of a value a file gives, for every node it may be applied
    /// to: a `$NODEID` value is judged at node-ids 1 and 127, the least and most it can be.
    pub(crate) fn refuses(&self, init: &Init) -> Option<OutsideLimits> {
        match init {
            Init::Bytes(bytes) => self.outside_limits(bytes),
            Init::NodeIdPlus(_) => [1, 127].into_iter().find_map(|node| {
                let outside = self.outside_limits(&self.value_for(init, node))?;
                Some(OutsideLimits { node_id: Some(node), ..outside })
            }),
        }
    }
}

/// A value beyond an entry's inclusive limits.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct OutsideLimits {
    /// The value, as a number.
    pub value: i128,
    /// The lowest value allowed.
    pub low: i128,
    /// The highest value allowed.
    pub high: i128,
    /// The node-id the value was computed for, when the file gives it as `$NODEID+n`.
    pub node_id: Option<u8>,
}

/// An entry's limits from a file's LowLimit and HighLimit, either of which may be absent
/// (the type's own bound stands in); inverted ones, which no value passes, as an error
/// finding: the limits are not used.
pub(crate) fn limits(
    entry: &str,
    dtype: DataType,
    low: Option<i128>,
    high: Option<i128>,
) -> Result<Option<(i128, i128)>, (lint::Kind, String)> {
    let Some((type_low, type_high)) = dtype.int_range() else { return Ok(None) };
    let (low, high) = match (low, high) {
        (None, None) => return Ok(None),
        (low, high) => (low.unwrap_or(type_low), high.unwrap_or(type_high)),
    };
    if low > high {
        let why = format!("LowLimit {low} of {entry} is above its HighLimit {high}, which no value passes: no limits");
        return Err((lint::Kind::ValueIgnored, why));
    }
    Ok(Some((low, high)))
}

/// A file's value for `entry` (`key`: a DCF's ParameterValue, an XDC's actualValue), judged
/// by the file's own limits as `config apply` judges it: the value, or the error finding
/// that it is outside them (it is not used).
pub(crate) fn within_limits(entry: &Entry, init: Init, key: &str) -> Result<Init, (lint::Kind, String)> {
    let Some(outside) = entry.refuses(&init) else { return Ok(init) };
    let OutsideLimits { value, low, high, node_id } = outside;
    let shown = match node_id {
        Some(node) => format!("{} ({value} for node-id {node})", eds::format_value(&init, entry.dtype)),
        None => value.to_string(),
    };
    let who = format!("{} ({})", entry.addr, entry.name);
    Err((
        lint::Kind::ValueOutsideLimits,
        format!("{key} {shown} of {who} is outside the file's limits, {low} to {high}: ignored"),
    ))
}

/// Which `store`/`restore` class an object belongs to (CiA 301 0x1010 sub 2..4).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ParamClass {
    /// 0x1000..0x1FFF (sub 2).
    Communication,
    /// 0x6000..0x9FFF (sub 3).
    Application,
    /// 0x2000..0x5FFF (sub 4).
    Manufacturer,
}

impl ParamClass {
    /// The class of an object by its index; `None` outside the three areas.
    pub fn of(index: u16) -> Option<ParamClass> {
        match index {
            0x1000..=0x1FFF => Some(ParamClass::Communication),
            0x2000..=0x5FFF => Some(ParamClass::Manufacturer),
            0x6000..=0x9FFF => Some(ParamClass::Application),
            _ => None,
        }
    }

    /// The 0x1010/0x1011 subindex that stores or restores this class.
    pub fn subindex(self) -> u8 {
        match self {
            ParamClass::Communication => 2,
            ParamClass::Application => 3,
            ParamClass::Manufacturer => 4,
        }
    }
}

/// An object dictionary: the entries a device has, and each object's name and kind.
#[derive(Clone, Debug, Default)]
pub struct Dictionary {
    entries: BTreeMap<ObjAddr, Entry>,
    objects: BTreeMap<u16, (String, ObjectKind)>,
}

impl Dictionary {
    /// The entry at `addr`, if the dictionary has it.
    pub fn get(&self, addr: ObjAddr) -> Option<&Entry> {
        self.entries.get(&addr)
    }

    /// Whether any sub-entry of object `index` is described.
    pub fn has_index(&self, index: u16) -> bool {
        self.entries.range(ObjAddr::new(index, 0)..=ObjAddr::new(index, 255)).next().is_some()
    }

    /// Every entry, in index and sub-index order.
    pub fn entries(&self) -> impl Iterator<Item = &Entry> {
        self.entries.values()
    }

    /// Add an entry; its object must have been declared (`object`), except for a VAR.
    pub fn insert(&mut self, entry: Entry) {
        self.objects.entry(entry.addr.index).or_insert_with(|| (entry.name.clone(), ObjectKind::Var));
        self.entries.insert(entry.addr, entry);
    }

    /// Declare an object's name and kind.
    pub fn object(&mut self, index: u16, name: &str, kind: ObjectKind) {
        self.objects.insert(index, (name.to_string(), kind));
    }

    /// Name and kind of the object at `index`.
    pub fn object_info(&self, index: u16) -> Option<(&str, ObjectKind)> {
        self.objects.get(&index).map(|(n, k)| (n.as_str(), *k))
    }

    /// Every object declared: its index, name and kind, in index order.
    pub fn objects(&self) -> impl Iterator<Item = (u16, &str, ObjectKind)> {
        self.objects.iter().map(|(i, (n, k))| (*i, n.as_str(), *k))
    }

    /// The entries of one object, in subindex order.
    pub fn object_entries(&self, index: u16) -> impl Iterator<Item = &Entry> {
        self.entries.range(ObjAddr::new(index, 0)..=ObjAddr::new(index, 255)).map(|(_, e)| e)
    }

    /// `Producer heartbeat time`, or `Identity object: Vendor-ID` for a sub-entry.
    pub fn display_name(&self, addr: ObjAddr) -> Option<String> {
        let e = self.get(addr)?;
        Some(match self.object_info(addr.index) {
            Some((object, ObjectKind::Array | ObjectKind::Record)) => format!("{object}: {}", e.name),
            _ => e.name.clone(),
        })
    }

    /// A single-value object at subindex 0.
    pub fn var(&mut self, index: u16, name: &str, dtype: DataType, access: Access, default: Init) -> &mut Entry {
        let addr = ObjAddr::new(index, 0);
        self.object(index, name, ObjectKind::Var);
        self.insert(Entry { addr, name: name.to_string(), dtype, access, default, range: None });
        self.entries.get_mut(&addr).unwrap()
    }

    /// A record: sub 0 (highest subindex, u8 ro) is added from the members.
    pub fn record(&mut self, index: u16, name: &str, members: Vec<(u8, &str, DataType, Access, Init)>) {
        let highest = members.iter().map(|m| m.0).max().unwrap_or(0);
        self.object(index, name, ObjectKind::Record);
        self.insert(Entry::count(index, "Highest sub-index supported", highest));
        for (sub, member, dtype, access, default) in members {
            let addr = ObjAddr::new(index, sub);
            self.insert(Entry { addr, name: member.to_string(), dtype, access, default, range: None });
        }
    }

    /// An array: a record whose members share one type (CiA 306 object type 0x8).
    pub fn array(&mut self, index: u16, name: &str, members: Vec<(u8, &str, DataType, Access, Init)>) {
        self.record(index, name, members);
        self.object(index, name, ObjectKind::Array);
    }

    /// Make an entry writable (records are built read-only at sub 0).
    pub(crate) fn set_access(&mut self, addr: ObjAddr, access: Access) {
        self.entries.get_mut(&addr).expect("set_access on a missing entry").access = access;
    }

    /// Limit an entry's values (abort 0x06090031/32 beyond them).
    pub fn limit(&mut self, addr: ObjAddr, lo: i128, hi: i128) {
        self.entries.get_mut(&addr).expect("limit on a missing entry").range = Some((lo, hi));
    }
}

/// Little-endian bytes of a default value.
pub fn le(value: u64, dtype: DataType) -> Init {
    let size = dtype.size().expect("fixed-size type");
    Init::Bytes(value.to_le_bytes()[..size].to_vec())
}

/// A VISIBLE_STRING default holding `s`.
pub fn text(s: &str) -> Init {
    Init::Bytes(s.as_bytes().to_vec())
}
