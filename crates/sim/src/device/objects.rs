//! A simulated device's object values, with CiA 301 store/restore, dynamic PDO mapping
//! and a CiA 402 drive's statusword.

use crate::canopen::cia402::{self, State as DriveState};
use crate::canopen::sdo::ObjectAccess;
use crate::canopen::{abort, ObjAddr};
use crate::cia402_drive::Drive;
use crate::od::{Dictionary, ParamClass};
use crate::profiles::SUPPLY_OFF_OBJECT;
use std::collections::BTreeMap;

/// SDO aborts of CiA 301 dynamic mapping.
pub(super) const MAPPING_OBJECT_UNMAPPABLE: u32 = 0x0604_0041;
pub(super) const MAPPING_TOO_LONG: u32 = 0x0604_0042;

/// The values of a device's dictionary, with the CiA 301 store/restore behaviour.
#[derive(Default)]
pub struct ObjectStore {
    pub(super) dict: Dictionary,
    pub(super) node_id: u8,
    pub(super) values: BTreeMap<ObjAddr, Vec<u8>>,
    /// What 0x1010 saved: survives resets (and, through the state file, invocations).
    pub(super) stored: BTreeMap<ObjAddr, Vec<u8>>,
    pub(super) ignored_writes: Vec<ObjAddr>,
    pub(super) dirty: bool,
    /// A CiA 402 drive's situation; its state is the statusword's value.
    pub(super) drive: Option<Drive>,
}

impl ObjectStore {
    pub(super) fn default_of(&self, addr: ObjAddr) -> Vec<u8> {
        self.dict.get(addr).map(|e| e.default_for(self.node_id)).unwrap_or_default()
    }

    /// Reload the values of the given classes from stored values, else defaults.
    pub(super) fn reload(&mut self, class: Option<ParamClass>) {
        let addrs: Vec<ObjAddr> = self.dict.entries().map(|e| e.addr).collect();
        for addr in addrs {
            if class.is_none() || ParamClass::of(addr.index) == class {
                let v = self.stored.get(&addr).cloned().unwrap_or_else(|| self.default_of(addr));
                self.values.insert(addr, v);
            }
        }
        self.dirty = true;
    }

    pub(super) fn entry(&self, addr: ObjAddr) -> Result<&crate::od::Entry, u32> {
        self.dict.get(addr).ok_or(if self.dict.has_index(addr.index) { abort::NO_SUBINDEX } else { abort::NO_OBJECT })
    }

    /// Whether 0x1010/0x1011 sub `sub` stands for the object at `index` (sub 1: every class).
    fn covers(sub: u8, index: u16) -> bool {
        ParamClass::of(index).is_some_and(|c| sub == 1 || c.subindex() == sub)
    }

    /// CiA 301 0x1010: saves the parameters of sub's classes, on the signature "save".
    pub(super) fn store(&mut self, sub: u8, signature: &[u8]) -> Result<(), u32> {
        if signature != b"save" {
            return Err(abort::CANNOT_STORE);
        }
        for e in self.dict.entries().filter(|e| e.access.writable() && Self::covers(sub, e.addr.index)) {
            self.stored.insert(e.addr, self.values[&e.addr].clone());
        }
        self.dirty = true;
        Ok(())
    }

    /// CiA 301 0x1011, on the signature "load": the defaults apply from the next reset on.
    pub(super) fn restore(&mut self, sub: u8, signature: &[u8]) -> Result<(), u32> {
        if signature != b"load" {
            return Err(abort::CANNOT_STORE);
        }
        self.stored.retain(|a, _| !Self::covers(sub, a.index));
        self.dirty = true;
        Ok(())
    }

    pub fn value(&self, addr: ObjAddr) -> Option<&[u8]> {
        self.values.get(&addr).map(|v| v.as_slice())
    }

    /// A value the device's own firmware sets and keeps in flash, so that it survives
    /// resets (a bootloader's program state, `sim::bootloader`).
    pub(crate) fn keep(&mut self, addr: ObjAddr, v: Vec<u8>) {
        self.stored.insert(addr, v.clone());
        self.values.insert(addr, v);
        self.dirty = true;
    }

    /// CiA 305: a new node-id takes effect at once for the COB-IDs of the predefined
    /// connection set; values still at their node-id-based default follow it.
    pub(super) fn renumber(&mut self, new_id: u8) {
        let old_id = self.node_id;
        for e in self.dict.entries().filter(|e| matches!(e.default, crate::od::Init::NodeIdPlus(_))) {
            let (old, new) = (e.default_for(old_id), e.default_for(new_id));
            for map in [&mut self.values, &mut self.stored] {
                if map.get(&e.addr) == Some(&old) {
                    map.insert(e.addr, new.clone());
                }
            }
        }
        self.node_id = new_id;
        self.dirty = true;
    }

    /// CiA 301: a mapping is checked when its count is written: every entry names an
    /// object the device has, and together they fit the 64 bits of a PDO.
    pub(super) fn check_mapping(&self, index: u16, count: u8) -> Result<(), u32> {
        let mut bits = 0u32;
        for sub in 1..=count {
            let raw = self.u32_value(ObjAddr::new(index, sub)).ok_or(abort::NO_SUBINDEX)?;
            let (mapped, len) = crate::canopen::pdo::mapping_entry(raw);
            // Indices below 0x1000 are the data type dummies CiA 301 allows in a mapping.
            if mapped.index >= 0x1000 && self.dict.get(mapped).is_none() {
                return Err(MAPPING_OBJECT_UNMAPPABLE);
            }
            bits += len as u32;
        }
        if bits > 64 {
            return Err(MAPPING_TOO_LONG);
        }
        Ok(())
    }

    /// The first byte of a value (a count, a switch).
    pub(crate) fn u8_value(&self, addr: ObjAddr) -> Option<u8> {
        self.value(addr).and_then(|v| v.first().copied())
    }

    pub(crate) fn u32_value(&self, addr: ObjAddr) -> Option<u32> {
        self.value(addr).and_then(|v| v.try_into().ok()).map(u32::from_le_bytes)
    }

    pub(crate) fn u16_value(&self, addr: ObjAddr) -> Option<u16> {
        self.value(addr).filter(|v| v.len() == 2).map(|v| u16::from_le_bytes([v[0], v[1]]))
    }

    /// The CiA 402 state a drive's statusword shows (None on a device that is no drive).
    pub fn drive_state(&self) -> Option<DriveState> {
        self.drive?;
        let shown = self.u16_value(cia402::STATUSWORD).and_then(DriveState::from_statusword);
        Some(shown.unwrap_or(DriveState::SwitchOnDisabled))
    }

    pub(super) fn set_drive_state(&mut self, state: DriveState) {
        if let Some(d) = self.drive {
            self.values.insert(cia402::STATUSWORD, d.statusword(state).to_le_bytes().to_vec());
            self.dirty = true;
        }
    }

    /// Show the drive's state again with the bits its situation gives (remote, voltage).
    pub(super) fn refresh_statusword(&mut self) {
        if let Some(state) = self.drive_state() {
            self.set_drive_state(state);
        }
    }

    /// A controlword arrived (by SDO, or through the EPOS2's serial gateway).
    pub(super) fn on_controlword(&mut self, previous: u16, controlword: u16) {
        let (Some(drive), Some(state)) = (self.drive, self.drive_state()) else { return };
        let next = drive.on_controlword(state, previous, controlword);
        if state == DriveState::Fault && next != DriveState::Fault {
            // The fault is reset: the error register (and the SERS's error class in
            // 0x1002's low word) clear.
            self.values.insert(ObjAddr::new(0x1001, 0), vec![0]);
            if let Some(status) = self.u32_value(ObjAddr::new(0x1002, 0)) {
                self.values.insert(ObjAddr::new(0x1002, 0), (status & 0xFFFF_0000).to_le_bytes().to_vec());
            }
        }
        self.set_drive_state(next);
    }
}

impl ObjectAccess for ObjectStore {
    fn read(&mut self, addr: ObjAddr) -> Result<Vec<u8>, u32> {
        if !self.entry(addr)?.access.readable() {
            return Err(abort::WRITE_ONLY);
        }
        Ok(self.values[&addr].clone())
    }

    fn check_write(&self, addr: ObjAddr, size: Option<usize>) -> Result<(), u32> {
        let e = self.entry(addr)?;
        if !e.access.writable() {
            return Err(abort::READ_ONLY);
        }
        match (e.dtype.size(), size) {
            (Some(want), Some(got)) if got > want => Err(abort::LENGTH_TOO_HIGH),
            (Some(want), Some(got)) if got < want => Err(abort::LENGTH_TOO_LOW),
            _ => Ok(()),
        }
    }

    fn fixed_size(&self, addr: ObjAddr) -> Option<usize> {
        self.dict.get(addr)?.dtype.size()
    }

    fn write(&mut self, addr: ObjAddr, data: &[u8]) -> Result<(), u32> {
        self.check_write(addr, Some(data.len()))?;
        let e = self.entry(addr)?;
        let (range, dtype) = (e.range, e.dtype);
        if self.ignored_writes.contains(&addr) {
            return Ok(());
        }
        match addr.index {
            // The signatures trigger the action; the entry itself keeps reading its capability.
            0x1010 if addr.sub >= 1 => return self.store(addr.sub, data),
            0x1011 if addr.sub >= 1 => return self.restore(addr.sub, data),
            // CiA 301 dynamic PDO mapping: the mapping of a valid PDO stays as it is, and
            // its entries change only while the count in sub 0 is 0.
            0x1600..=0x17FF | 0x1A00..=0x1BFF => {
                let valid = self.u32_value(ObjAddr::new(addr.index - 0x200, 1)).is_some_and(|c| c & 0x8000_0000 == 0);
                let count = self.u8_value(ObjAddr::new(addr.index, 0)).unwrap_or(0);
                if valid || (addr.sub > 0 && count != 0) {
                    return Err(abort::WRONG_STATE);
                }
                if addr.sub == 0 {
                    self.check_mapping(addr.index, data.first().copied().unwrap_or(0))?;
                }
            }
            // A valid PDO keeps its COB-ID: it is made invalid (bit 31) before it changes.
            0x1400..=0x15FF | 0x1800..=0x19FF if addr.sub == 1 => {
                let old = self.u32_value(addr).unwrap_or(0);
                let new = u32::from_le_bytes(data.try_into().unwrap_or([0; 4]));
                if old & 0x8000_0000 == 0 && new & 0x8000_0000 == 0 && old != new {
                    return Err(abort::INVALID_VALUE);
                }
            }
            // Writing 0 to the error history's sub 0 clears it; nothing else is allowed.
            0x1003 if addr.sub == 0 => {
                if data != [0] {
                    return Err(abort::INVALID_VALUE);
                }
                let fields = self.values.range_mut(ObjAddr::new(0x1003, 1)..=ObjAddr::new(0x1003, 255));
                fields.for_each(|(_, v)| *v = vec![0; 4]);
            }
            _ => {}
        }
        if let (Some((lo, hi)), Some(v)) = (range, dtype.decode(data)) {
            let n = match v {
                crate::canopen::types::Value::Uint(u) => u as i128,
                crate::canopen::types::Value::Int(i) => i as i128,
                _ => lo,
            };
            if n < lo {
                return Err(abort::VALUE_TOO_LOW);
            }
            if n > hi {
                return Err(abort::VALUE_TOO_HIGH);
            }
        }
        let previous = self.values.insert(addr, data.to_vec());
        self.dirty = true;
        if self.drive.is_some() {
            let word = |v: &[u8]| u16::from_le_bytes([v.first().copied().unwrap_or(0), v.get(1).copied().unwrap_or(0)]);
            if addr == cia402::CONTROLWORD {
                self.on_controlword(previous.as_deref().map_or(0, word), word(data));
            } else if addr == cia402::MODES_OF_OPERATION && self.dict.get(cia402::MODES_OF_OPERATION_DISPLAY).is_some()
            {
                // Nothing moves here: the drive switches mode at once.
                self.values.insert(cia402::MODES_OF_OPERATION_DISPLAY, data.to_vec());
            } else if addr == SUPPLY_OFF_OBJECT {
                if let Some(d) = &mut self.drive {
                    d.supply_off = data == [1];
                }
                self.refresh_statusword();
            }
        }
        Ok(())
    }
}
