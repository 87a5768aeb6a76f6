use super::*;
use std::io::Write;

const SMALL: Limit = Limit { bytes: 16, what: "a test file" };

#[test]
fn a_regular_file_within_the_limit_is_read_whole() {
    let mut f = tempfile::NamedTempFile::new().unwrap();
    f.write_all(b"0123456789ABCDEF").unwrap();
    assert_eq!(read_regular_file(f.path(), SMALL).unwrap(), b"0123456789ABCDEF");
    assert_eq!(read_value_file(f.path().to_str().unwrap(), SMALL, Duration::from_secs(5)).unwrap().len(), 16);
}

#[test]
fn a_file_over_the_limit_is_refused_naming_the_limit() {
    let mut f = tempfile::NamedTempFile::new().unwrap();
    f.write_all(&[b'x'; 17]).unwrap();
    let path = f.path().display().to_string();
    let want = format!("{path}: larger than 16 bytes, the limit for a test file");
    assert_eq!(read_regular_file(f.path(), SMALL).unwrap_err().to_string(), want);
    assert_eq!(read_value_file(&path, SMALL, Duration::from_secs(5)).unwrap_err().to_string(), want);
}

#[cfg(unix)]
fn fifo(dir: &tempfile::TempDir) -> std::path::PathBuf {
    let path = dir.path().join("fifo");
    let ok = std::process::Command::new("mkfifo").arg(&path).status().unwrap().success();
    assert!(ok, "mkfifo");
    path
}

#[cfg(unix)]
#[test]
fn a_fifo_or_a_device_is_not_a_dictionary_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = fifo(&dir);
    // Nobody writes to the FIFO: a blocking open would wait forever.
    let e = read_regular_file(&path, EDS).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!("{}: a FIFO, not a regular file (an EDS or DCF file must be a file)", path.display())
    );
    let e = read_regular_file(Path::new("/dev/zero"), EDS).unwrap_err();
    assert!(e.to_string().contains(": a character device, not a regular file"), "{e}");
    let e = read_regular_file(dir.path(), EDS).unwrap_err();
    assert!(e.to_string().contains(": a directory, not a regular file"), "{e}");
}

#[cfg(unix)]
#[test]
fn an_endless_device_as_a_value_stops_at_the_limit() {
    let e = read_value_file("/dev/zero", SMALL, Duration::from_secs(60)).unwrap_err();
    assert_eq!(e.to_string(), "/dev/zero: larger than 16 bytes, the limit for a test file");
}

#[cfg(unix)]
#[test]
fn a_fifo_without_a_writer_is_given_up_after_the_idle_limit() {
    let dir = tempfile::tempdir().unwrap();
    let path = fifo(&dir);
    let e = read_value_file(path.to_str().unwrap(), SMALL, Duration::from_millis(50)).unwrap_err();
    assert!(matches!(e, InputError::Idle { .. }), "{e}");
    assert!(e.to_string().contains("sent nothing for 0.05 s"), "{e}");
}

#[cfg(unix)]
#[test]
fn a_fifo_with_a_writer_is_read_to_its_end() {
    let dir = tempfile::tempdir().unwrap();
    let path = fifo(&dir);
    let writer_path = path.clone();
    let writer = std::thread::spawn(move || {
        let mut w = std::fs::OpenOptions::new().write(true).open(writer_path).unwrap();
        w.write_all(b"firmware").unwrap();
    });
    let got = read_value_file(path.to_str().unwrap(), SMALL, Duration::from_secs(30)).unwrap();
    writer.join().unwrap();
    assert_eq!(got, b"firmware");
}
