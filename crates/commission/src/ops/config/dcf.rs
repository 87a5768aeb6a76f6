//! A DCF and the reads of a node's values against it: each value fitted to its entry and
//! shown as the file writes it, the node's dictionary, its identity compared with the file's.

use crate::bus::{Bus, SdoOptions};
use crate::canopen::{DataType, ObjAddr};
use crate::error::{Error, Result};
use crate::od::eds::{self, Eds};
use crate::od::{builtin, Dictionary, Entry, Init};
use crate::ops::sdo_options::sized;
use crate::ops::values::le_u32;
use std::path::Path;
use std::time::Duration;

/// A DCF: the values a device is to hold (its `ParameterValue`s), with their dictionary.
#[derive(Debug, Clone)]
pub struct Dcf {
    /// The device description: its objects, each with the value the DCF gives (`ParameterValue`).
    pub(crate) eds: Eds,
}

impl Dcf {
    /// The vendor-ID and product code the file is for: `[DeviceInfo]`, else its 0x1018
    /// values; 0 where it does not say.
    pub fn identity(&self) -> (u32, u32) {
        let part = |key: &str, addr: ObjAddr| {
            let from_value = || match self.eds.values.get(&addr) {
                Some(crate::od::Init::Bytes(b)) => Some(crate::ops::values::le_u32(b)),
                _ => None,
            };
            self.info_number(key).filter(|v| *v != 0).or_else(from_value).unwrap_or(0)
        };
        (part("vendornumber", ObjAddr::VENDOR_ID), part("productnumber", ObjAddr::PRODUCT_CODE))
    }

    /// A number of its `[DeviceInfo]` (`key` in lower case).
    pub(crate) fn info_number(&self, key: &str) -> Option<u32> {
        self.eds.info.get(key).and_then(|v| eds::parse_int(v)).and_then(|v| u32::try_from(v).ok())
    }

    /// Read a DCF file; an unreadable one is a usage error citing file:line.
    pub fn read(path: &Path) -> Result<Dcf> {
        let eds = crate::od::read_description(path)?;
        Ok(Dcf { eds })
    }

    /// A DCF's text; `name` stands for its file in messages.
    pub fn parse(bytes: &[u8], name: &str) -> Result<Dcf> {
        let eds = crate::od::parse_description(bytes, name)?;
        Ok(Dcf { eds })
    }

    /// The file's name as given.
    pub fn path(&self) -> &str {
        &self.eds.path
    }

    /// Objects the file describes in a way canctl passes over, with file:line.
    pub fn warnings(&self) -> &[crate::od::lint::Warning] {
        &self.eds.warnings
    }

    /// The values for `node`, with their dictionary entries; `$NODEID` means that node.
    pub(super) fn values(&self, node: u8) -> Result<Vec<Wanted>> {
        // An EDS with an object left out still names the rest; a DCF so read would be
        // applied (or compared) without what it left out: refused, with the first reason.
        let errors: Vec<&crate::od::lint::Warning> =
            self.eds.warnings.iter().filter(|w| w.severity == crate::od::lint::Severity::Error).collect();
        if let Some(first) = errors.first() {
            let (first, file) = (Box::new((*first).clone()), self.path().to_string());
            return Err(Error::DcfNotReadWhole { first, file, errors: errors.len() });
        }
        let (dict, values) = (&self.eds.dict, self.eds.values.iter());
        let out: Vec<Wanted> =
            values.filter_map(|(addr, init)| dict.get(*addr).map(|e| (e.clone(), e.value_for(init, node)))).collect();
        if out.is_empty() {
            return Err(Error::NotADcf { file: self.path().to_string() });
        }
        Ok(out)
    }
}

/// A DCF value for a node, with its dictionary entry.
pub(super) type Wanted = (Entry, Vec<u8>);

/// Bytes as the entry holds them: an EPOS2's ReadObject answers four bytes for any short
/// object, the rest meaningless; and a device may keep an integer in fewer bytes than the
/// dictionary says (the MH sensor's 0x1002 is UNSIGNED8), which is the same number.
pub(super) fn fit(entry: &Entry, mut bytes: Vec<u8>) -> Vec<u8> {
    if let Some(size) = entry.dtype.size() {
        if let (Some((lo, _)), Some(&last)) = (entry.dtype.int_range(), bytes.last()) {
            let fill = if lo < 0 && last & 0x80 != 0 { 0xFF } else { 0 };
            bytes.resize(bytes.len().max(size), fill);
        }
        bytes.truncate(size);
    }
    bytes
}

pub(super) fn show(entry: &Entry, bytes: &[u8]) -> String {
    eds::format_value(&Init::Bytes(bytes.to_vec()), entry.dtype)
}

pub(super) fn opts(timeout: Duration, dtype: DataType) -> SdoOptions {
    SdoOptions { max_upload: crate::ops::sdo_options::upload_limit(Some(dtype)), ..sized(timeout, dtype.size()) }
}

pub(super) fn read_one(bus: &mut dyn Bus, node: u8, e: &Entry, timeout: Duration) -> Result<Vec<u8>> {
    bus.sdo_upload(node, e.addr, &opts(timeout, e.dtype)).map(|b| fit(e, b))
}

/// Where the device's vendor-ID and product code are not the ones the file names, in words.
pub(super) fn identity_differences(bus: &mut dyn Bus, node: u8, dcf: &Dcf, timeout: Duration) -> Result<Vec<String>> {
    let (vendor, product) = dcf.identity();
    let parts = crate::ops::node::Node::new(bus, node, timeout).compare_identity(vendor, product)?;
    Ok(parts
        .iter()
        .filter(|p| !p.matches())
        .map(|p| format!("{} {} on node {node}, 0x{:08X} in the file", p.what, p.device_text(), p.file))
        .collect())
}

/// A value the target's dictionary does not allow, refused before anything is written.
pub(super) fn out_of_range(entry: &Entry, value: &[u8], limits: crate::od::OutsideLimits, source: &str) -> Error {
    let crate::od::OutsideLimits { low, high, .. } = limits;
    Error::OutOfRange { object: entry.addr, value: show(entry, value), low, high, dictionary: source.to_string() }
}

/// The dictionary a node is judged by, with the name of its source: the one given (an EDS
/// bound to the node), else the built-in one for the node's profile (0x1000), which decides
/// what 0x6000 and the like mean (DS401/402/406).
pub(super) fn node_dictionary(
    bus: &mut dyn Bus,
    node: u8,
    given: Option<(&Dictionary, &str)>,
    timeout: Duration,
) -> Result<(Dictionary, String)> {
    if let Some((d, source)) = given {
        return Ok((d.clone(), source.to_string()));
    }
    let device_type = builtin::dictionary(None).get(ObjAddr::DEVICE_TYPE).expect("0x1000");
    let profile = le_u32(&read_one(bus, node, device_type, timeout)?) as u16;
    Ok((builtin::dictionary(Some(profile)).clone(), format!("the built-in dictionary (profile {profile})")))
}
