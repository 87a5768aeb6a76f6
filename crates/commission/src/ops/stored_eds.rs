//! `config eds`: the EDS a device stores in itself (CiA 301 object 0x1021), unpacked by the
//! storage format it names (0x1022), so that a technician without the vendor's file still
//! gets names, types and ranges.

use crate::bus::{Bus, SdoOptions};
use crate::error::{Error, Result};
use crate::od::stored::{self, STORAGE_FORMAT, STORE_EDS};
use serde::Serialize;
use std::time::Duration;

impl StoredEds {
    /// Write the file to `path` (whole or not at all) and, on the network at `network`,
    /// remember it as the node's description when it lists objects, so that completion
    /// offers them.
    pub fn save(&mut self, node: u8, path: &std::path::Path, network: Option<&str>) -> Result<()> {
        crate::atomic::write_atomic(path, &self.file)?;
        self.saved_to = Some(path.display().to_string());
        if let (Some(_), Some(network)) = (self.objects, network) {
            super::scan_cache::describe(network, node, path);
        }
        Ok(())
    }
}

/// The description a node gave.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct StoredEds {
    /// The node the description was read from.
    pub node: u8,
    /// Its storage format (0x1022): 0 plain, 1 ZIP.
    pub format: u8,
    /// What that format is, in words.
    pub format_name: &'static str,
    /// Whether the node has 0x1022; without it the EDS is taken as plain text.
    pub format_given: bool,
    /// Bytes read from 0x1021.
    pub stored_bytes: usize,
    /// Bytes of the file once unpacked.
    pub bytes: usize,
    /// Objects canctl reads in it; none when it cannot read it (`unreadable` says why):
    /// the file is saved either way, as the device holds it.
    pub objects: Option<usize>,
    /// Why canctl cannot read the file (its parser's message), when it cannot.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unreadable: Option<String>,
    /// Where the command line saved it (the library saves nothing).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub saved_to: Option<String>,
    /// The file itself.
    #[serde(skip)]
    pub file: Vec<u8>,
}

/// Read node `node`'s stored description: at most `limit` bytes from 0x1021 (the SDO
/// client stops an upload, announced or not, beyond it) and as many unpacked.
pub fn read(bus: &mut dyn Bus, node: u8, timeout: Duration, limit: usize) -> Result<StoredEds> {
    // Stored EDSs run to tens of kilobytes: block transfer moves them fastest.
    let opts = SdoOptions { block_upload: true, ..super::sdo_options::capped(timeout, limit) };
    let raw = match bus.sdo_upload(node, STORE_EDS, &opts) {
        Err(e) if super::node::is_missing(&e) => return Err(Error::NoStoredEds { node }),
        other => other?,
    };
    let opts = SdoOptions { size_hint: Some(1), ..SdoOptions::new(timeout) };
    let (format, format_given) = match bus.sdo_upload(node, STORAGE_FORMAT, &opts) {
        Ok(v) if v.len() == 1 => (v[0], true),
        Ok(v) => return Err(Error::StoredEds { node, why: stored::StoredError::FormatSize(v.len()) }),
        // CiA 301 pairs the two objects; a device with 0x1021 alone stores plain text.
        Err(e) if super::node::is_missing(&e) => (stored::PLAIN, false),
        Err(e) => return Err(e),
    };
    let file = stored::unpack(format, &raw, limit).map_err(|why| Error::StoredEds { node, why })?;
    let (objects, unreadable) = match crate::od::parse_description(&file, &format!("node {node}'s 0x1021")) {
        Ok(eds) => (Some(eds.dict.objects().count()), None),
        Err(e) => (None, Some(e.to_string())),
    };
    Ok(StoredEds {
        node,
        format,
        format_name: stored::format_name(format),
        format_given,
        stored_bytes: raw.len(),
        bytes: file.len(),
        objects,
        unreadable,
        saved_to: None,
        file,
    })
}
