//! A node's error history: the pre-defined error field 0x1003 (CiA 301), newest first,
//! each entry with what it means; and clearing it (writing 0 to 0x1003:0).

use super::node::{self, Node, HISTORY_COUNT};
use super::sdo_options::sized;
use super::values::le_u32;
use crate::bus::{Bus, SdoOptions};
use crate::canopen::emcy::{self, Origin};
use crate::canopen::{DataType, ObjAddr};
use crate::error::{Error, Result};
use serde::Serialize;
use std::time::Duration;

/// A device name longer than this is not read for the meanings (it only picks a table).
const MAX_NAME: usize = 64;

/// What `canctl errors` found on a node.
#[derive(Debug, Default, Serialize)]
pub struct ErrorHistory {
    /// The node-id.
    pub node: u8,
    /// 0x1008, when the node has one.
    pub name: Option<String>,
    /// Whether the node keeps an error history at all (has object 0x1003).
    pub kept: bool,
    /// 0x1003:0: how many errors the node says it logged.
    pub count: Option<u8>,
    /// The entries, newest (0x1003:1) first.
    pub entries: Vec<LoggedError>,
    /// Entries the node counts but would not show: (subindex, why).
    pub unreadable: Vec<Unreadable>,
    /// 0x1001, when it could be read.
    pub error_register: Option<u8>,
    /// Names of the error register's bits that are set.
    pub error_register_bits: Vec<&'static str>,
    /// Whether the history was cleared, confirmed by reading 0x1003:0 back as 0.
    pub cleared: bool,
    /// The clear was asked for but interrupted: `Some(true)` when the 0 was written (not
    /// confirmed), `Some(false)` when nothing was written.
    pub clear_interrupted: Option<bool>,
}

pub use super::node::{LoggedError, Unreadable};

/// Read the node's error history (and, with `clear`, then clear it and confirm).
pub fn errors(bus: &mut dyn Bus, node: u8, clear: bool, timeout: Duration) -> Result<ErrorHistory> {
    let first = [
        HISTORY_COUNT,
        ObjAddr::ERROR_REGISTER,
        ObjAddr::DEVICE_TYPE,
        ObjAddr::VENDOR_ID,
        ObjAddr::PRODUCT_CODE,
        ObjAddr::DEVICE_NAME,
    ];
    let requests: Vec<(u8, ObjAddr)> = first.iter().map(|a| (node, *a)).collect();
    let opts = SdoOptions { max_upload: MAX_NAME, ..SdoOptions::new(timeout) };
    let mut answers = bus.sdo_upload_many(&requests, &opts, &mut |_| {})?.into_iter();
    let count = answers.next().expect("one answer per request");
    let mut next = || answers.next().expect("one answer per request").ok();
    let u32_of = |b: Vec<u8>| (b.len() >= 4).then(|| le_u32(&b));
    let register = next().and_then(|b| b.first().copied());
    let origin = Origin {
        device_type: next().and_then(u32_of),
        vendor: next().and_then(u32_of),
        product: next().and_then(u32_of),
        name: next().and_then(|b| DataType::Vs.decode(&b)).map(|v| v.to_string()),
    };
    let mut report = ErrorHistory {
        node,
        name: origin.name.clone(),
        kept: true,
        error_register: register,
        error_register_bits: register.map(emcy::register_bits).unwrap_or_default(),
        ..ErrorHistory::default()
    };
    match count {
        Ok(bytes) => report.count = bytes.first().copied(),
        Err(e) if node::is_missing(&e) && clear => return Err(Error::NoErrorHistory { node }),
        Err(e) if node::is_missing(&e) => return Ok(ErrorHistory { kept: false, ..report }),
        Err(e) => return Err(e),
    }
    let field = Node::new(bus, node, timeout).error_entries(report.count.unwrap_or(0), &origin)?;
    (report.entries, report.unreadable) = (field.entries, field.unreadable);
    if clear {
        // CiA 301: writing 0 to sub 0 deletes the history; any other value is refused.
        // Interrupted, the report still says what was read and how far the clear got.
        let mut written = false;
        let one = sized(timeout, Some(1));
        let back = bus.sdo_download(node, HISTORY_COUNT, &[0], &one).and_then(|()| {
            written = true;
            bus.sdo_upload(node, HISTORY_COUNT, &one)
        });
        let back = match back {
            Err(e) if e.is_interrupted() => {
                report.clear_interrupted = Some(written);
                return Ok(report);
            }
            back => back?,
        };
        let read = back.first().copied();
        if read != Some(0) {
            let read = read.map_or("nothing".into(), |v| v.to_string());
            return Err(Error::ReadBack { node, obj: HISTORY_COUNT, wrote: "0".into(), read });
        }
        report.cleared = true;
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::Master;
    use crate::canopen::emcy::Source;
    use crate::sim::{SimConfig, SimLink};

    fn sim() -> Master<SimLink> {
        Master::new(SimLink::with_config(SimConfig::instant()), "sim".into())
    }

    const T: Duration = Duration::from_secs(2);

    #[test]
    fn the_io_modules_history_is_read_newest_first_with_the_manuals_meanings() {
        let mut bus = sim();
        let h = errors(&mut bus, 10, false, T).unwrap();
        assert!(h.kept);
        assert_eq!(h.count, Some(2));
        let got: Vec<(u8, u16, u16, &str)> =
            h.entries.iter().map(|e| (e.sub, e.code, e.manufacturer, e.meaning)).collect();
        assert_eq!(got, [(1, 0x8110, 0x0006, "CAN controller overrun"), (2, 0x5000, 0x0002, "EEPROM access error")]);
        assert!(h.entries.iter().all(|e| e.source == Source::Device));
        assert_eq!(h.error_register, Some(0));
        let json = serde_json::to_value(&h).unwrap();
        assert_eq!(json["entries"][0]["raw"], 0x0006_8110);
        assert_eq!(json["entries"][0]["code"], "0x8110");
        assert_eq!(json["entries"][0]["source"], "device manual");
    }

    #[test]
    fn clearing_writes_zero_and_confirms_it() {
        let mut bus = sim();
        let h = errors(&mut bus, 10, true, T).unwrap();
        assert!(h.cleared);
        assert_eq!(h.entries.len(), 2, "what was cleared is reported");
        let after = errors(&mut bus, 10, false, T).unwrap();
        assert_eq!((after.count, after.entries.len()), (Some(0), 0));
    }

    #[test]
    fn a_node_without_a_history_says_so() {
        let mut bus = sim();
        let h = errors(&mut bus, 32, false, T).unwrap();
        assert!(!h.kept);
        assert_eq!(h.count, None);
        assert!(matches!(errors(&mut bus, 32, true, T), Err(Error::NoErrorHistory { node: 32 })));
    }

    #[test]
    fn a_device_that_refuses_to_clear_is_reported_with_its_abort() {
        // The module's 11th answer is the one to the write: six reads (its 9-byte name in
        // three frames), then the two entries.
        let refusing = SimConfig::instant().fault("10:abort=0x08000020@11".parse().unwrap());
        let mut bus = Master::new(SimLink::with_config(refusing), "sim".into());
        let e = errors(&mut bus, 10, true, T).unwrap_err();
        assert!(matches!(e, Error::SdoAbort { node: 10, obj: HISTORY_COUNT, code: 0x0800_0020 }), "{e}");
        assert_eq!(e.exit_code(), 4);
    }

    #[test]
    fn a_node_that_does_not_answer_is_a_timeout() {
        let mut bus = sim();
        assert!(errors(&mut bus, 77, false, Duration::from_millis(50)).unwrap_err().is_timeout());
    }
}
