//! One object read ([`read()`]) or written ([`write()`]), any size, any type: expedited,
//! segmented or block transfer as the size and the device allow. The node's dictionary
//! gives the type when none is asked for, the object's name, and the limits a value must
//! keep to.

use super::progress::Progress;
use super::values::{as_text, check_range};
use crate::bus::{Bus, SdoOptions};
use crate::canopen::types::{hex, obvious_unsigned, Value};
use crate::canopen::{DataType, ObjAddr};
use crate::error::{Error, Result};
use crate::od::Dictionary;
use serde::Serialize;
use std::path::Path;
use std::time::Duration;

/// How to read.
#[derive(Clone, Copy, Debug)]
pub struct ReadOptions {
    /// How long to wait for each answer.
    pub timeout: Duration,
    /// The type to decode; `None`: the dictionary's, else the raw bytes.
    pub dtype: Option<DataType>,
    /// Whether block transfer may be used (for strings and domains, where the device offers it).
    pub block: bool,
    /// The largest value to accept: an upload that grows past it is aborted. `None`: as
    /// the type wants (`upload_limit`): 64 KiB, a domain 1 MiB.
    pub max_size: Option<usize>,
}

/// How to write.
#[derive(Clone, Copy, Debug)]
pub struct WriteOptions {
    /// How long to wait for each answer.
    pub timeout: Duration,
    /// The type to encode the value as; `None`: the dictionary's.
    pub dtype: Option<DataType>,
    /// Whether block transfer may be used (for 64 bytes and more, where the device offers it).
    pub block: bool,
    /// Read the object back and compare.
    pub verify: bool,
}

/// An object's value.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Read {
    /// The node-id read from.
    pub node: u8,
    /// The object read.
    #[serde(serialize_with = "as_text")]
    pub object: ObjAddr,
    /// Its name in the dictionary.
    pub name: Option<String>,
    /// The data type it was decoded as; none: raw bytes.
    #[serde(rename = "type", serialize_with = "type_name")]
    pub dtype: Option<DataType>,
    /// Its size, in bytes.
    pub size: usize,
    /// The bytes the node sent.
    #[serde(rename = "raw", serialize_with = "hex_text")]
    pub bytes: Vec<u8>,
    /// Decoded by its type; without one, the plain unsigned reading of 1, 2, 4 or 8 bytes.
    #[serde(serialize_with = "value_json")]
    pub value: Option<Value>,
}

/// An object's value, saved to a file.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Saved {
    /// The node-id read from.
    pub node: u8,
    /// The object read.
    #[serde(serialize_with = "as_text")]
    pub object: ObjAddr,
    /// Its size, in bytes.
    pub size: usize,
    /// The file it was saved to.
    pub file: String,
}

/// A value written (and read back, when verified).
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Written {
    /// The node-id written to.
    pub node: u8,
    /// The object written.
    #[serde(serialize_with = "as_text")]
    pub object: ObjAddr,
    /// The data type the value was encoded as.
    #[serde(rename = "type", serialize_with = "type_name")]
    pub dtype: DataType,
    /// The value's size, in bytes.
    pub size: usize,
    /// The value written, decoded by its type; none when the bytes do not decode as it.
    #[serde(serialize_with = "value_json")]
    pub value: Option<Value>,
    /// It was read back and found equal.
    pub verified: bool,
    /// The read-back of `verify` was interrupted (SIGINT, SIGTERM): written, not verified.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub interrupted: bool,
    /// The bytes written.
    #[serde(skip)]
    pub bytes: Vec<u8>,
}

fn type_name<S: serde::Serializer, T: Copy + Into<Option<DataType>>>(
    t: &T,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    (*t).into().map(DataType::name).serialize(s)
}

fn hex_text<S: serde::Serializer>(bytes: &[u8], s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(&hex(bytes))
}

fn value_json<S: serde::Serializer>(v: &Option<Value>, s: S) -> std::result::Result<S::Ok, S::Error> {
    v.as_ref().map(Value::to_json).serialize(s)
}

fn sdo_options(timeout: Duration, dtype: Option<DataType>, block: bool) -> SdoOptions {
    // Block upload only for a value that may be large.
    let large = matches!(dtype, Some(DataType::Vs | DataType::Os | DataType::D | DataType::Unicode));
    SdoOptions {
        block_upload: block && large,
        block_download: block,
        size_hint: dtype.and_then(DataType::size),
        max_upload: super::sdo_options::upload_limit(dtype),
        ..SdoOptions::new(timeout)
    }
}

/// Read `object` from `node`, decoded by the type asked for, else the dictionary's.
pub fn read(bus: &mut dyn Bus, dict: &Dictionary, node: u8, object: ObjAddr, o: &ReadOptions) -> Result<Read> {
    read_watched(bus, dict, node, object, o, &mut super::progress::Silent)
}

/// [`read`], `progress` told the bytes received so far as a segmented or block upload
/// moves on (64 KiB take seconds), through [`Progress::transfer`].
pub fn read_watched(
    bus: &mut dyn Bus,
    dict: &Dictionary,
    node: u8,
    object: ObjAddr,
    o: &ReadOptions,
    progress: &mut dyn Progress,
) -> Result<Read> {
    let entry = dict.get(object);
    let dtype = o.dtype.or(entry.map(|e| e.dtype));
    let name = entry.and_then(|_| dict.display_name(object));
    let mut opts = sdo_options(o.timeout, dtype, o.block);
    opts.max_upload = o.max_size.unwrap_or(opts.max_upload);
    opts.on_progress = progress.transfer(&format!("node {node}: reading {object}"), None);
    let read = bus.sdo_upload(node, object, &opts);
    progress.finish();
    let bytes = super::unheard::sdo(bus, read)?;
    let not_of_type = |dtype| Error::NotOfType { node, obj: object, bytes: bytes.clone(), dtype };
    let value = match dtype {
        Some(t) => Some(t.decode(&bytes).ok_or_else(|| not_of_type(t))?),
        None => obvious_unsigned(&bytes).map(Value::Uint),
    };
    Ok(Read { node, object, name, dtype, size: bytes.len(), bytes, value })
}

impl Read {
    /// Write the raw bytes to a file.
    pub fn save(&self, path: &Path) -> Result<Saved> {
        crate::atomic::write_atomic(path, &self.bytes)?;
        Ok(Saved { node: self.node, object: self.object, size: self.size, file: path.display().to_string() })
    }
}

/// Write `value` to `object` of `node`: text parsed by the type asked for, else the
/// dictionary's, and checked against the dictionary's limits; `@FILE` for the raw bytes of
/// a file (`@-`: standard input).
pub fn write(
    bus: &mut dyn Bus,
    dict: &Dictionary,
    node: u8,
    object: ObjAddr,
    value: &str,
    o: &WriteOptions,
) -> Result<Written> {
    let Some(dtype) = o.dtype.or(dict.get(object).map(|e| e.dtype)) else {
        return Err(Error::TypeNeeded { value: value.to_string(), object });
    };
    let bytes = value_bytes(dtype, value)?;
    if let Some(entry) = dict.get(object).filter(|e| e.dtype == dtype) {
        check_range(entry, &bytes)?;
    }
    let mut opts = sdo_options(o.timeout, Some(dtype), o.block);
    // The read-back of --verify takes back as much as was written.
    opts.max_upload = opts.max_upload.max(bytes.len());
    let written = bus.sdo_download(node, object, &bytes, &opts);
    super::unheard::sdo(bus, written)?;
    let mut interrupted = false;
    if o.verify {
        match bus.sdo_upload(node, object, &opts) {
            Ok(back) if back != bytes => {
                let (wrote, read) = (shown(dtype, &bytes), shown(dtype, &back));
                return Err(Error::ReadBack { node, obj: object, wrote, read });
            }
            Ok(_) => {}
            Err(e) if e.is_interrupted() => interrupted = true,
            Err(e) => return Err(e),
        }
    }
    let (value, size, verified) = (dtype.decode(&bytes), bytes.len(), o.verify && !interrupted);
    Ok(Written { node, object, dtype, size, value, verified, interrupted, bytes })
}

/// A value as text by its type, else as hex bytes.
pub fn shown(dtype: DataType, bytes: &[u8]) -> String {
    dtype.decode(bytes).map_or_else(|| hex(bytes), |v: Value| v.to_string())
}

/// The bytes VALUE stands for: `@FILE` (`@-` for stdin) or text parsed by type.
fn value_bytes(dtype: DataType, value: &str) -> Result<Vec<u8>> {
    if let Some(path) = value.strip_prefix('@') {
        let data = crate::input::read_value_file(path, crate::input::VALUE, crate::input::VALUE_IDLE_LIMIT)?;
        if let Some(size) = dtype.size().filter(|size| *size != data.len()) {
            return Err(Error::Usage(format!("{path} holds {} bytes; a {dtype} is {size}", data.len())));
        }
        return Ok(data);
    }
    dtype.parse(value).map_err(|e| Error::Usage(e.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::Master;
    use crate::sim::{SimConfig, SimLink};
    use std::sync::{Arc, Mutex};

    /// The bytes a transfer told its watcher, and the phases begun and ended.
    #[derive(Default)]
    struct Watcher {
        moved: Arc<Mutex<Vec<usize>>>,
        phases: Vec<String>,
        finished: usize,
    }

    impl Progress for Watcher {
        fn transfer(&mut self, what: &str, _len: Option<u64>) -> Option<crate::bus::TransferHook> {
            self.phases.push(what.to_string());
            let moved = self.moved.clone();
            Some(Arc::new(move |n| moved.lock().unwrap().push(n)))
        }
        fn finish(&mut self) {
            self.finished += 1;
        }
    }

    /// A segmented read tells the procedure's observer its bytes as they come, the one
    /// way every procedure reports progress.
    #[test]
    fn a_segmented_read_tells_its_progress_the_bytes_as_they_come() {
        let mut bus = Master::new(SimLink::with_config(SimConfig::instant()), "sim".into());
        let o = ReadOptions { timeout: Duration::from_secs(2), dtype: None, block: false, max_size: None };
        let mut watcher = Watcher::default();
        // The device name (0x1008), longer than 4 bytes: a segmented upload.
        let read =
            read_watched(&mut bus, &Dictionary::default(), 1, ObjAddr::new(0x1008, 0), &o, &mut watcher).unwrap();
        assert!(read.size > 7, "{read:?}");
        let moved = watcher.moved.lock().unwrap().clone();
        // Told as it moves on (the last segment ends the transfer, and the display with it).
        assert!(moved.iter().any(|n| (1..=read.size).contains(n)), "{moved:?}");
        assert!(moved.windows(2).all(|w| w[0] <= w[1]) && moved.iter().all(|n| *n <= read.size), "{moved:?}");
        assert_eq!(watcher.phases, ["node 1: reading 0x1008:0"]);
        assert_eq!(watcher.finished, 1);
    }
}
