//! A log of every frame canctl sent and received, in the can-utils candump log format
//! (`candump -L`, read back by `canplayer` and `log2asc`), for support cases:
//!
//! ```text
//! (1700000000.123456) vcan0 605#4000100000000000
//! (1700000000.124001) vcan0 585#4300100092010200
//! ```
//!
//! Each line is written as it happens (no buffering in the process), so a log survives a
//! command that is killed. A write that fails ends the logging; the failure is reported by
//! [`FrameLog::finish`], the command itself goes on (a support log must not break the
//! commissioning it records).

use crate::error::{Error, Result};
use crate::frame::Frame;
use std::fs::File;
use std::io::Write;
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::{SystemTime, UNIX_EPOCH};

/// A shared handle on one log: clones write to the same file, in order.
#[derive(Clone)]
pub struct FrameLog {
    inner: Arc<Mutex<Inner>>,
}

struct Inner {
    out: Box<dyn Write + Send>,
    /// Where the log goes, for messages.
    name: String,
    /// The first write that failed; nothing more is written after it.
    failed: Option<std::io::Error>,
}

impl std::fmt::Debug for FrameLog {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let name = self.inner.lock().map(|i| i.name.clone()).unwrap_or_default();
        f.debug_struct("FrameLog").field("to", &name).finish()
    }
}

impl FrameLog {
    /// Create (or truncate) the log file at `path`.
    pub fn create(path: &Path) -> Result<FrameLog> {
        let file = File::create(path).map_err(|e| Error::Output {
            path: path.display().to_string(),
            why: format!("{e}; no frame log can be kept"),
        })?;
        Ok(FrameLog::to_writer(file, path.display().to_string()))
    }

    /// A log into any writer (`name` says where it goes, for messages).
    pub(crate) fn to_writer(out: impl Write + Send + 'static, name: String) -> FrameLog {
        FrameLog { inner: Arc::new(Mutex::new(Inner { out: Box::new(out), name, failed: None })) }
    }

    /// Log one frame seen on `iface` now.
    pub fn record(&self, iface: &str, frame: &Frame) {
        self.record_at(SystemTime::now(), iface, frame)
    }

    fn record_at(&self, time: SystemTime, iface: &str, frame: &Frame) {
        let mut inner = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        if inner.failed.is_some() {
            return;
        }
        let line = candump_log_line(time, iface, frame) + "\n";
        if let Err(e) = inner.out.write_all(line.as_bytes()) {
            tracing::warn!(target: "canctl::frame_log", "frame log {}: {e}; logging stopped", inner.name);
            inner.failed = Some(e);
        }
    }

    /// Flush the log; the first write that failed, if any, as an error.
    pub fn finish(&self) -> Result<()> {
        let mut inner = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        if inner.failed.is_none() {
            inner.failed = inner.out.flush().err();
        }
        let why = |e| format!("{e}; the frame log is incomplete");
        inner.failed.as_ref().map_or(Ok(()), |e| Err(Error::Output { path: inner.name.clone(), why: why(e) }))
    }
}

/// One line of a candump log: `(SECONDS.MICROS) IFACE ID#DATA`, the frame in can-utils'
/// compact notation (`123#R` for a remote request, `123#R4` with a length). Whitespace in
/// an interface name would split the line's fields: it becomes `_`.
pub(crate) fn candump_log_line(time: SystemTime, iface: &str, frame: &Frame) -> String {
    let since = time.duration_since(UNIX_EPOCH).unwrap_or_default();
    let iface: String = iface.chars().map(|c| if c.is_whitespace() { '_' } else { c }).collect();
    format!("({:010}.{:06}) {iface} {frame}", since.as_secs(), since.subsec_micros())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn at(secs: u64, micros: u64) -> SystemTime {
        UNIX_EPOCH + Duration::from_secs(secs) + Duration::from_micros(micros)
    }

    /// The lines `candump -L` writes for the same frames (can-utils lib.c notation).
    #[test]
    fn lines_are_can_utils_candump_log_lines() {
        let sdo = Frame::new(0x605, &[0x40, 0x00, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00]);
        assert_eq!(
            candump_log_line(at(1_700_000_000, 123_456), "vcan0", &sdo),
            "(1700000000.123456) vcan0 605#4000100000000000"
        );
        let nmt = Frame::new(0x000, &[0x81, 0x05]);
        assert_eq!(candump_log_line(at(1_700_000_000, 7), "can0", &nmt), "(1700000000.000007) can0 000#8105");
        assert_eq!(candump_log_line(at(1, 0), "can0", &Frame::remote(0x705, 0)), "(0000000001.000000) can0 705#R");
        assert_eq!(candump_log_line(at(1, 0), "can0", &Frame::remote(0x185, 8)), "(0000000001.000000) can0 185#R8");
        assert_eq!(candump_log_line(at(1, 0), "sim", &Frame::new(0x080, &[])), "(0000000001.000000) sim 080#");
        assert_eq!(candump_log_line(at(1, 0), "COM 5", &nmt), "(0000000001.000000) COM_5 000#8105");
    }

    /// Every line reads back as the frame it logged.
    #[test]
    fn lines_parse_back_to_their_frames() {
        for text in ["605#4000100000000000", "705#R", "185#R8", "080#", "7E4#4F00000000000000"] {
            let frame: Frame = text.parse().unwrap();
            let line = candump_log_line(SystemTime::now(), "vcan0", &frame);
            let logged = line.rsplit(' ').next().unwrap();
            assert_eq!(logged.parse::<Frame>().unwrap(), frame, "{line}");
        }
    }

    #[derive(Clone, Default)]
    struct Shared(Arc<Mutex<Vec<u8>>>);
    impl Write for Shared {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.0.lock().unwrap().extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn clones_write_one_line_per_frame_in_order() {
        let out = Shared::default();
        let log = FrameLog::to_writer(out.clone(), "memory".into());
        let other = log.clone();
        log.record_at(at(10, 1), "sim", &Frame::new(0x601, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]));
        other.record_at(at(10, 2), "sim", &Frame::new(0x581, &[0x43, 0x18, 0x10, 0x01, 0xFB, 0, 0, 0]));
        log.finish().unwrap();
        let text = String::from_utf8(out.0.lock().unwrap().clone()).unwrap();
        assert_eq!(
            text,
            "(0000000010.000001) sim 601#4018100100000000\n(0000000010.000002) sim 581#43181001FB000000\n"
        );
    }

    /// A full disk: the command goes on, the log stops at the failure, and `finish` says so.
    #[test]
    fn a_failed_write_stops_the_log_and_is_reported_at_the_end() {
        struct Full(usize);
        impl Write for Full {
            fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
                if self.0 == 0 {
                    return Err(std::io::Error::new(std::io::ErrorKind::StorageFull, "no space left on device"));
                }
                self.0 -= 1;
                Ok(buf.len())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let log = FrameLog::to_writer(Full(1), "full.log".into());
        let f = Frame::new(0x000, &[0x01, 0x00]);
        log.record("sim", &f);
        log.record("sim", &f);
        log.record("sim", &f);
        let err = log.finish().unwrap_err();
        assert_eq!(err.exit_code(), 7);
        assert!(err.to_string().contains("full.log") && err.to_string().contains("no space left"), "{err}");
    }
}
