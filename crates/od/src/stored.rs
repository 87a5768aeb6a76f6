//! The EDS a device keeps in itself (CiA 301 object 0x1021, DOMAIN) in the storage
//! format object 0x1022 names: 0 the file's text as it is, 1 compressed, as a ZIP archive
//! (CiA 306), 0x80..0xFF the manufacturer's own. Pure: bytes in, the file's bytes out.
//!
//! The ZIP archive is read by the `zip` crate: one archive, its members stored or deflated
//! (the methods every ZIP tool writes), found through the central directory. Each member is
//! checked against its CRC-32, and inflating stops at a limit, so that a broken or hostile
//! archive cannot fill memory.

/// Object 0x1021: the stored EDS.
pub const STORE_EDS: canctl_canopen::ObjAddr = canctl_canopen::ObjAddr::new(0x1021, 0);
/// Object 0x1022: its storage format.
pub const STORAGE_FORMAT: canctl_canopen::ObjAddr = canctl_canopen::ObjAddr::new(0x1022, 0);

/// 0x1022 values.
pub const PLAIN: u8 = 0;
/// 0x1022 value: a ZIP archive holding the file.
pub const ZIP: u8 = 1;

/// Why the stored bytes give no file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum StoredError {
    /// 0x1022 holds a format other than plain or ZIP.
    #[error("storage format {0} (0x1022) is {kind}: canctl reads 0 (plain) and 1 (ZIP)", kind = format_name(*.0))]
    UnknownFormat(u8),
    /// 0x1022 is not one byte long.
    #[error("its storage format (0x1022) holds {0} bytes, not the 1 of an UNSIGNED8")]
    FormatSize(usize),
    /// The ZIP archive cannot be read (what the unpacker said).
    #[error("the ZIP archive is broken: {0}")]
    BrokenZip(String),
    /// The archive uses what canctl does not unpack (the compression method, or the feature).
    #[error("the ZIP archive holds {0}, which canctl does not unpack (it reads stored and deflated members)")]
    Method(String),
    /// The ZIP member would unpack to more than the limit: refused before it fills memory.
    #[error("the ZIP member {name} unpacks to more than {limit} bytes")]
    TooLarge {
        /// The member's name.
        name: String,
        /// The limit it passed, in bytes.
        limit: usize,
    },
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

/// One member of a ZIP archive: a device description (`.eds`, `.xdd`, `.dcf`, `.xdc`) if
/// there is one, else the first. Its name and content.
pub(crate) fn unzip(zip: &[u8], limit: usize) -> Result<(String, Vec<u8>), StoredError> {
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(zip)).map_err(broken)?;
    let description = |n: &str| {
        let n = n.to_ascii_lowercase();
        [".eds", ".xdd", ".dcf", ".xdc"].iter().any(|x| n.ends_with(x))
    };
    let names: Vec<String> =
        archive.file_names().map(|n| n.map(|n| n.into_owned())).collect::<Result<_, _>>().map_err(broken)?;
    let index = names
        .iter()
        .position(|n| description(n))
        .or((!names.is_empty()).then_some(0))
        .ok_or_else(|| StoredError::BrokenZip("the archive is empty".into()))?;
    let name = names[index].clone();
    let mut member = archive.by_index(index).map_err(|e| match e {
        zip::result::ZipError::CompressionMethodNotSupported(m) => {
            StoredError::Method(format!("compression method {m}"))
        }
        zip::result::ZipError::UnsupportedArchive(what) => StoredError::Method(what.to_string()),
        e => broken(e),
    })?;
    let size = member.size();
    if size > limit as u64 {
        return Err(StoredError::TooLarge { name, limit });
    }
    // The declared size is the archive's word only: inflating reads at most one byte past
    // the limit, so that a member that unpacks to more is stopped there (a zip bomb).
    let mut content = Vec::with_capacity(size as usize);
    let read = std::io::Read::read_to_end(&mut std::io::Read::take(&mut member, limit as u64 + 1), &mut content);
    if content.len() > limit {
        return Err(StoredError::TooLarge { name, limit });
    }
    // The CRC-32 is checked as the member's end is read: a mismatch is a read error.
    if read.is_err() || content.len() as u64 != size {
        return Err(StoredError::BrokenZip(format!("{name} does not match its size and CRC-32")));
    }
    Ok((name, content))
}

fn broken(e: zip::result::ZipError) -> StoredError {
    StoredError::BrokenZip(e.to_string())
}

/// A ZIP archive of one deflated member, as a device's tools would store it.
pub fn zip(name: &str, content: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let options = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    let mut w = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    // Writing to memory cannot fail.
    w.start_file(name, options).expect("a zip member in memory");
    w.write_all(content).expect("a zip member in memory");
    w.finish().expect("a zip archive in memory").into_inner()
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
        // A bomb: its headers claim 1000 bytes, its data inflate to 100 000.
        let mut bomb = z.clone();
        let central = bomb.windows(4).position(|w| w == b"PK\x01\x02").unwrap();
        for at in [22, central + 24] {
            bomb[at..at + 4].copy_from_slice(&1000u32.to_le_bytes());
        }
        assert!(unzip(&bomb, 10_000).is_err(), "{:?}", unzip(&bomb, 10_000).map(|(n, c)| (n, c.len())));
        assert!(matches!(unzip(&bomb, 10_000), Err(StoredError::BrokenZip(why)) if why.contains("CRC-32")));
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
