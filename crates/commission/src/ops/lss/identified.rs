//! An LSS identity as a report shows it: its `V:P:R:S` text and its four numbers.

use crate::canopen::lss::Identity;
use serde::ser::SerializeMap;
use serde::Serialize;

/// An identity in a report: its `V:P:R:S` text (`identity`) and its four numbers (`lss`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Identified(pub Identity);

impl Serialize for Identified {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        let id = &self.0;
        let mut m = s.serialize_map(Some(2))?;
        m.serialize_entry("identity", &id.to_string())?;
        let lss =
            LssNumbers { vendor_id: id.vendor, product_code: id.product, revision: id.revision, serial: id.serial };
        m.serialize_entry("lss", &lss)?;
        m.end()
    }
}

/// The four entries of the identity object (0x1018:1..4), named.
#[derive(Serialize)]
struct LssNumbers {
    vendor_id: u32,
    product_code: u32,
    revision: u32,
    serial: u32,
}
