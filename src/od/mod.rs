//! The object dictionary model: what a device holds, by address, with type, access and
//! default. The simulator's devices are built from it; EDS files will read into it.

use crate::canopen::{DataType, ObjAddr};
use std::collections::BTreeMap;

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Access {
    Ro,
    Wo,
    Rw,
    Const,
}

impl Access {
    pub fn readable(self) -> bool {
        self != Access::Wo
    }
    pub fn writable(self) -> bool {
        matches!(self, Access::Rw | Access::Wo)
    }
    pub fn name(self) -> &'static str {
        match self {
            Access::Ro => "ro",
            Access::Wo => "wo",
            Access::Rw => "rw",
            Access::Const => "const",
        }
    }
}

/// A default value; COB-IDs and the like depend on the node-id (EDS `$NODEID+0x180`).
#[derive(Clone, PartialEq, Debug)]
pub enum Init {
    Bytes(Vec<u8>),
    NodeIdPlus(u32),
}

impl Init {
    pub fn resolve(&self, node_id: u8) -> Vec<u8> {
        match self {
            Init::Bytes(b) => b.clone(),
            Init::NodeIdPlus(base) => (base + node_id as u32).to_le_bytes().to_vec(),
        }
    }
}

#[derive(Clone, Debug)]
pub struct Entry {
    pub addr: ObjAddr,
    pub name: String,
    pub dtype: DataType,
    pub access: Access,
    pub default: Init,
    /// Inclusive limits for integer values, beyond the type's own.
    pub range: Option<(i128, i128)>,
}

/// Which `store`/`restore` class an object belongs to (CiA 301 0x1010 sub 2..4).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ParamClass {
    Communication,
    Application,
    Manufacturer,
}

impl ParamClass {
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

#[derive(Clone, Debug, Default)]
pub struct Dictionary {
    entries: BTreeMap<ObjAddr, Entry>,
}

impl Dictionary {
    pub fn get(&self, addr: ObjAddr) -> Option<&Entry> {
        self.entries.get(&addr)
    }

    pub fn has_index(&self, index: u16) -> bool {
        self.entries.range(ObjAddr::new(index, 0)..=ObjAddr::new(index, 255)).next().is_some()
    }

    pub fn entries(&self) -> impl Iterator<Item = &Entry> {
        self.entries.values()
    }

    pub fn insert(&mut self, entry: Entry) {
        self.entries.insert(entry.addr, entry);
    }

    /// A single-value object at subindex 0.
    pub fn var(&mut self, index: u16, name: &str, dtype: DataType, access: Access, default: Init) -> &mut Entry {
        let addr = ObjAddr::new(index, 0);
        self.insert(Entry { addr, name: name.to_string(), dtype, access, default, range: None });
        self.entries.get_mut(&addr).unwrap()
    }

    /// A record or array: sub 0 (highest subindex, u8 ro) is added from the members.
    pub fn record(&mut self, index: u16, name: &str, members: Vec<(u8, &str, DataType, Access, Init)>) {
        let highest = members.iter().map(|m| m.0).max().unwrap_or(0);
        self.var(index, name, DataType::U8, Access::Ro, Init::Bytes(vec![highest]));
        for (sub, member, dtype, access, default) in members {
            let addr = ObjAddr::new(index, sub);
            self.insert(Entry { addr, name: format!("{name}: {member}"), dtype, access, default, range: None });
        }
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

pub fn text(s: &str) -> Init {
    Init::Bytes(s.as_bytes().to_vec())
}
