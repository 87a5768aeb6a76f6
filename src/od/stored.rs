//! The EDS a device keeps in itself (CiA 301 object 0x1021, DOMAIN) in the storage
//! format object 0x1022 names: 0 the file's text as it is, 1 compressed, as a ZIP archive
//! (CiA 306), 0x80..0xFF the manufacturer's own. Pure: bytes in, the file's bytes out.
//!
//! The ZIP reader takes what a device's firmware would hold: one archive, its members
//! stored or deflated (the methods every ZIP tool writes), found through the central
//! directory so that sizes in a data descriptor are read too. Each member is checked
//! against its CRC-32, and inflating stops at a limit, so that a broken or hostile
//! archive cannot fill memory.

/// Object 0x1021: the stored EDS.
pub const STORE_EDS: crate::canopen::ObjAddr = crate::canopen::ObjAddr::new(0x1021, 0);
/// Object 0x1022: its storage format.
pub const STORAGE_FORMAT: crate::canopen::ObjAddr = crate::canopen::ObjAddr::new(0x1022, 0);

/// 0x1022 values.
pub const PLAIN: u8 = 0;
pub const ZIP: u8 = 1;

/// Why the stored bytes give no file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum StoredError {
    #[error("storage format {0} (0x1022) is {kind}: canctl reads 0 (plain) and 1 (ZIP)", kind = format_name(*.0))]
    UnknownFormat(u8),
    #[error("its storage format (0x1022) holds {0} bytes, not the 1 of an UNSIGNED8")]
    FormatSize(usize),
    #[error("the ZIP archive is broken: {0}")]
    BrokenZip(String),
    #[error("the ZIP archive holds {0}, which canctl does not unpack (it reads stored and deflated members)")]
    Method(String),
    #[error("the ZIP member {name} unpacks to more than {limit} bytes")]
    TooLarge { name: String, limit: usize },
}

/// What a 0x1022 value means (CiA 301).
pub fn format_name(format: u8) -> &'static str {
    match format {
        PLAIN => "plain text",
        ZIP => "ZIP",
        0x80..=0xFF => "manufacturer-specific",
        _ => "reserved",
    }
}

/// The EDS (or XDD) in `stored`, of storage format `format`; at most `limit` bytes.
pub fn unpack(format: u8, stored: &[u8], limit: usize) -> Result<Vec<u8>, StoredError> {
    match format {
        PLAIN => Ok(stored.to_vec()),
        ZIP => unzip(stored, limit).map(|(_, data)| data),
        other => Err(StoredError::UnknownFormat(other)),
    }
}

fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    b.get(at..at + 2).map(|s| u16::from_le_bytes([s[0], s[1]]))
}

fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    b.get(at..at + 4).map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
}

const LOCAL: u32 = 0x0403_4B50;
const CENTRAL: u32 = 0x0201_4B50;
const END: u32 = 0x0605_4B50;
const CRC32: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC);

/// One member of a ZIP archive: a device description (`.eds`, `.xdd`, `.dcf`, `.xdc`) if
/// there is one, else the first. Its name and content.
pub fn unzip(zip: &[u8], limit: usize) -> Result<(String, Vec<u8>), StoredError> {
    let broken = |why: &str| StoredError::BrokenZip(why.to_string());
    // The end record is the last 22 bytes, before a comment of up to 64 KiB.
    let end = (0..=zip.len().saturating_sub(22))
        .rev()
        .take(22 + 0xFFFF)
        .find(|at| u32_at(zip, *at) == Some(END))
        .ok_or_else(|| broken("no end of central directory record"))?;
    let count = u16_at(zip, end + 10).ok_or_else(|| broken("short end record"))? as usize;
    let mut at = u32_at(zip, end + 16).ok_or_else(|| broken("short end record"))? as usize;
    let mut members = Vec::new();
    for _ in 0..count {
        if u32_at(zip, at) != Some(CENTRAL) {
            return Err(broken("a central directory entry is missing"));
        }
        let field = |off: usize| u16_at(zip, at + off).map(usize::from).ok_or_else(|| broken("short central entry"));
        let (method, name_len, extra_len, comment_len) = (field(10)?, field(28)?, field(30)?, field(32)?);
        let crc = u32_at(zip, at + 16).ok_or_else(|| broken("short central entry"))?;
        let packed = u32_at(zip, at + 20).ok_or_else(|| broken("short central entry"))? as usize;
        let size = u32_at(zip, at + 24).ok_or_else(|| broken("short central entry"))? as usize;
        let local = u32_at(zip, at + 42).ok_or_else(|| broken("short central entry"))? as usize;
        let name = zip.get(at + 46..at + 46 + name_len).ok_or_else(|| broken("short central entry"))?;
        members.push((String::from_utf8_lossy(name).into_owned(), method, crc, packed, size, local));
        at += 46 + name_len + extra_len + comment_len;
    }
    let description = |n: &str| {
        let n = n.to_ascii_lowercase();
        [".eds", ".xdd", ".dcf", ".xdc"].iter().any(|x| n.ends_with(x))
    };
    let (name, method, crc, packed, size, local) = members
        .iter()
        .find(|m| description(&m.0))
        .or(members.first())
        .cloned()
        .ok_or_else(|| broken("the archive is empty"))?;
    if size > limit {
        return Err(StoredError::TooLarge { name, limit });
    }
    if u32_at(zip, local) != Some(LOCAL) {
        return Err(broken("the member's local header is missing"));
    }
    let data_at = local
        + 30
        + u16_at(zip, local + 26).map(usize::from).unwrap_or(0)
        + u16_at(zip, local + 28).map(usize::from).unwrap_or(0);
    let data = zip.get(data_at..data_at + packed).ok_or_else(|| broken("the member's data is cut short"))?;
    let content = match method {
        0 => data.to_vec(),
        8 => miniz_oxide::inflate::decompress_to_vec_with_limit(data, limit).map_err(|e| match e.status {
            miniz_oxide::inflate::TINFLStatus::HasMoreOutput => StoredError::TooLarge { name: name.clone(), limit },
            _ => broken(&format!("{name} does not inflate ({:?})", e.status)),
        })?,
        other => return Err(StoredError::Method(format!("compression method {other}"))),
    };
    if content.len() != size || CRC32.checksum(&content) != crc {
        return Err(broken(&format!("{name} does not match its size and CRC-32")));
    }
    Ok((name, content))
}

/// A ZIP archive of one deflated member, as a device's tools would store it.
pub fn zip(name: &str, content: &[u8]) -> Vec<u8> {
    let packed = miniz_oxide::deflate::compress_to_vec(content, 6);
    let crc = CRC32.checksum(content);
    // Version 2.0, no flags, deflate, no time stamp: the fields both headers share.
    let common = |out: &mut Vec<u8>| {
        out.extend_from_slice(&20u16.to_le_bytes());
        out.extend_from_slice(&0u16.to_le_bytes());
        out.extend_from_slice(&8u16.to_le_bytes());
        out.extend_from_slice(&[0; 4]);
        out.extend_from_slice(&crc.to_le_bytes());
        out.extend_from_slice(&(packed.len() as u32).to_le_bytes());
        out.extend_from_slice(&(content.len() as u32).to_le_bytes());
        out.extend_from_slice(&(name.len() as u16).to_le_bytes());
        out.extend_from_slice(&0u16.to_le_bytes());
    };
    let mut out = Vec::with_capacity(packed.len() + 2 * name.len() + 100);
    out.extend_from_slice(&LOCAL.to_le_bytes());
    common(&mut out);
    out.extend_from_slice(name.as_bytes());
    out.extend_from_slice(&packed);
    let central = out.len();
    out.extend_from_slice(&CENTRAL.to_le_bytes());
    out.extend_from_slice(&20u16.to_le_bytes());
    common(&mut out);
    // Comment length, disk, internal and external attributes, local header offset.
    out.extend_from_slice(&[0; 2 + 2 + 2 + 4]);
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(name.as_bytes());
    let central_len = out.len() - central;
    out.extend_from_slice(&END.to_le_bytes());
    out.extend_from_slice(&[0; 4]);
    out.extend_from_slice(&1u16.to_le_bytes());
    out.extend_from_slice(&1u16.to_le_bytes());
    out.extend_from_slice(&(central_len as u32).to_le_bytes());
    out.extend_from_slice(&(central as u32).to_le_bytes());
    out.extend_from_slice(&0u16.to_le_bytes());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Python's zipfile (an implementation of its own) writing `hello\n` as `a.eds`, stored.
    const PYTHON_STORED: &[u8] = b"PK\x03\x04\x14\x00\x00\x00\x00\x00\x00\x00!\x00 0:6\x06\x00\x00\x00\x06\x00\x00\x00\x05\x00\x00\x00a.edshello\nPK\x01\x02\x14\x03\x14\x00\x00\x00\x00\x00\x00\x00!\x00 0:6\x06\x00\x00\x00\x06\x00\x00\x00\x05\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x80\x01\x00\x00\x00\x00a.edsPK\x05\x06\x00\x00\x00\x00\x01\x00\x01\x003\x00\x00\x00)\x00\x00\x00\x00\x00";
    /// The same, deflated: `[FileInfo]\nFileName=x.eds\n` three times as `x.eds`.
    const PYTHON_DEFLATED: &[u8] = b"PK\x03\x04\x14\x00\x00\x00\x08\x00\x00\x00!\x002\x12\x00\x80\x1d\x00\x00\x00N\x00\x00\x00\x05\x00\x00\x00x.eds\x8bv\xcb\xccI\xf5\xccK\xcb\x8f\xe5\x02\xb1\xfc\x12sSm+\xf4RS\x8a\xb9\xa2\xc9\x90\x01\x00PK\x01\x02\x14\x03\x14\x00\x00\x00\x08\x00\x00\x00!\x002\x12\x00\x80\x1d\x00\x00\x00N\x00\x00\x00\x05\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x80\x01\x00\x00\x00\x00x.edsPK\x05\x06\x00\x00\x00\x00\x01\x00\x01\x003\x00\x00\x00@\x00\x00\x00\x00\x00";

    #[test]
    fn a_stored_member_is_read_and_checked_against_its_crc() {
        assert_eq!(unzip(PYTHON_STORED, 1000).unwrap(), ("a.eds".to_string(), b"hello\n".to_vec()));
        let (name, text) = unzip(PYTHON_DEFLATED, 1000).unwrap();
        assert_eq!((name.as_str(), text), ("x.eds", b"[FileInfo]\nFileName=x.eds\n".repeat(3)));
        let mut bad = PYTHON_STORED.to_vec();
        bad[35] = b'j';
        assert!(matches!(unzip(&bad, 1000), Err(StoredError::BrokenZip(why)) if why.contains("CRC-32")));
    }

    #[test]
    fn what_zip_packs_unzip_gives_back() {
        let text = "[FileInfo]\nFileName=x.eds\n".repeat(200);
        let z = zip("x.eds", text.as_bytes());
        assert!(z.len() < text.len() / 4, "deflated: {} of {} bytes", z.len(), text.len());
        assert_eq!(unpack(ZIP, &z, 1 << 20).unwrap(), text.as_bytes());
        assert_eq!(unpack(PLAIN, text.as_bytes(), 1 << 20).unwrap(), text.as_bytes());
    }

    #[test]
    fn an_archive_that_unpacks_beyond_the_limit_is_stopped() {
        let z = zip("big.eds", &vec![b'x'; 100_000]);
        assert_eq!(unzip(&z, 10_000), Err(StoredError::TooLarge { name: "big.eds".into(), limit: 10_000 }));
    }

    #[test]
    fn cut_and_foreign_bytes_are_broken_archives_not_panics() {
        let z = zip("x.eds", b"some text");
        for len in 0..z.len() {
            assert!(unzip(&z[..len], 1000).is_err(), "cut at {len}");
        }
        assert!(matches!(unpack(ZIP, b"[FileInfo]\n", 1000), Err(StoredError::BrokenZip(_))));
        assert_eq!(unpack(0x80, b"x", 10), Err(StoredError::UnknownFormat(0x80)));
        assert!(StoredError::UnknownFormat(0x80).to_string().contains("manufacturer-specific"));
    }
}
