//! Reading input files with bounds: every file canctl reads (EDS, DCF, project and value
//! files) goes through here, so none can make it read forever or fill the memory.
//!
//! Dictionary and configuration files must be regular files: a FIFO or a device would block
//! or never end. A value file (`@FILE`, `@-`) may be a pipe or a device — `@<(zcat fw.gz)` is
//! a pipe — so it is read up to a size limit, and a source that sends nothing for a while is
//! given up on.

use std::io::Read;
use std::path::Path;
use std::time::Duration;

/// The largest EDS or DCF canctl reads. Real ones are well under a megabyte.
pub const MAX_EDS_BYTES: u64 = 16 << 20;

/// The largest value a file or standard input may give (`@FILE`): firmware images fit.
pub const MAX_VALUE_BYTES: u64 = 64 << 20;

/// How long a pipe or device may stay silent before a value read from it is given up.
pub const VALUE_IDLE_LIMIT: Duration = Duration::from_secs(10);

/// Why an input file (EDS, DCF, value file) was not read: the limits keep a wrong path or an
/// endless pipe from eating memory or hanging.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum InputError {
    /// The file could not be opened or read.
    #[error("cannot read {path}: {error}")]
    Io {
        /// The file, as given.
        path: String,
        /// What the system said: in the text, not a cause of its own (which would say it
        /// again where causes are listed).
        error: std::sync::Arc<std::io::Error>,
    },
    /// The file is larger than its kind may be.
    #[error("{path}: larger than {}, the limit for {what}", size_text(*.limit))]
    TooLarge {
        /// The file, as given.
        path: String,
        /// The limit it passed, in bytes.
        limit: u64,
        /// What the file was to be, for the message.
        what: &'static str,
    },
    /// The path is a directory, socket or the like, not a file.
    #[error("{path}: {kind}, not a regular file ({what} must be a file)")]
    NotRegular {
        /// The file, as given.
        path: String,
        /// What it is instead: a directory, a socket.
        kind: &'static str,
        /// What the file was to be, for the message.
        what: &'static str,
    },
    /// A pipe or device sent nothing for too long.
    #[error("{path} sent nothing for {} s: given up (a pipe or device needs a writer)", .idle.as_secs_f64())]
    Idle {
        /// The pipe or device, as given.
        path: String,
        /// How long it stayed silent.
        idle: Duration,
    },
}

/// `16 MiB` for whole mebibytes, else bytes.
fn size_text(bytes: u64) -> String {
    if bytes >= 1 << 20 && bytes.is_multiple_of(1 << 20) {
        format!("{} MiB", bytes >> 20)
    } else {
        format!("{bytes} bytes")
    }
}

/// What a bounded read is for: its size limit and the name used in messages.
#[derive(Clone, Copy, Debug)]
pub struct Limit {
    /// The most bytes read before giving up.
    pub bytes: u64,
    /// What the input is, for messages ("an EDS or DCF file").
    pub what: &'static str,
}

/// The limit for EDS and DCF files.
pub const EDS: Limit = Limit { bytes: MAX_EDS_BYTES, what: "an EDS or DCF file" };
/// The limit for a value file (`sdo write --file`).
pub const VALUE: Limit = Limit { bytes: MAX_VALUE_BYTES, what: "a value file" };

/// A regular file, whole, if it is no larger than `limit`. FIFOs, devices and directories
/// are refused without reading (and without blocking on opening them).
pub fn read_regular_file(path: &Path, limit: Limit) -> Result<Vec<u8>, InputError> {
    let shown = path.display().to_string();
    let file = open_nonblocking(path).map_err(|error| InputError::Io { path: shown.clone(), error: error.into() })?;
    let meta = file.metadata().map_err(|error| InputError::Io { path: shown.clone(), error: error.into() })?;
    if !meta.is_file() {
        return Err(InputError::NotRegular { path: shown, kind: kind_of(&meta), what: limit.what });
    }
    if meta.len() > limit.bytes {
        return Err(InputError::TooLarge { path: shown, limit: limit.bytes, what: limit.what });
    }
    read_limited(file, &shown, limit)
}

/// A value file: a regular file, or a pipe or device read until its end within `limit`
/// bytes and `idle` silence. `-` is standard input, likewise bounded.
pub fn read_value_file(path: &str, limit: Limit, idle: Duration) -> Result<Vec<u8>, InputError> {
    if path == "-" {
        return read_stream(std::io::stdin(), "standard input", limit, idle);
    }
    let file =
        open_nonblocking(Path::new(path)).map_err(|error| InputError::Io { path: path.into(), error: error.into() })?;
    let meta = file.metadata().map_err(|error| InputError::Io { path: path.into(), error: error.into() })?;
    if meta.is_dir() {
        return Err(InputError::NotRegular { path: path.into(), kind: "a directory", what: limit.what });
    }
    if meta.is_file() {
        if meta.len() > limit.bytes {
            return Err(InputError::TooLarge { path: path.into(), limit: limit.bytes, what: limit.what });
        }
        return read_limited(file, path, limit);
    }
    read_stream(file, path, limit, idle)
}

/// Reads at most `limit` bytes; one more means the source is too large.
fn read_limited(source: impl Read, path: &str, limit: Limit) -> Result<Vec<u8>, InputError> {
    let mut data = Vec::new();
    source
        .take(limit.bytes + 1)
        .read_to_end(&mut data)
        .map_err(|error| InputError::Io { path: path.into(), error: error.into() })?;
    if data.len() as u64 > limit.bytes {
        return Err(InputError::TooLarge { path: path.into(), limit: limit.bytes, what: limit.what });
    }
    Ok(data)
}

/// A pipe or device: each read waits at most `idle` for data (Unix: poll), and the total
/// is bounded by `limit`.
#[cfg(unix)]
fn read_stream(
    mut source: impl Read + std::os::fd::AsFd,
    path: &str,
    limit: Limit,
    idle: Duration,
) -> Result<Vec<u8>, InputError> {
    use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
    let io_err = |error: std::io::Error| InputError::Io { path: path.into(), error: error.into() };
    let mut data = Vec::new();
    let mut chunk = vec![0u8; 64 << 10];
    let timeout = PollTimeout::try_from(idle).unwrap_or(PollTimeout::MAX);
    loop {
        let ready = {
            let mut fds = [PollFd::new(source.as_fd(), PollFlags::POLLIN)];
            match poll(&mut fds, timeout) {
                Ok(n) => n,
                Err(nix::errno::Errno::EINTR) => continue,
                Err(e) => return Err(io_err(e.into())),
            }
        };
        if ready == 0 {
            return Err(InputError::Idle { path: path.into(), idle });
        }
        let n = match source.read(&mut chunk) {
            Ok(n) => n,
            // Opened without blocking and nobody wrote yet: wait again, within `idle`.
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock || e.kind() == std::io::ErrorKind::Interrupted => {
                continue
            }
            Err(e) => return Err(io_err(e)),
        };
        if n == 0 {
            return Ok(data);
        }
        if data.len() as u64 + n as u64 > limit.bytes {
            return Err(InputError::TooLarge { path: path.into(), limit: limit.bytes, what: limit.what });
        }
        data.extend_from_slice(&chunk[..n]);
    }
}

#[cfg(not(unix))]
fn read_stream(source: impl Read, path: &str, limit: Limit, _idle: Duration) -> Result<Vec<u8>, InputError> {
    read_limited(source, path, limit)
}

/// Opening a FIFO for reading blocks until a writer comes; without blocking it does not.
#[cfg(unix)]
fn open_nonblocking(path: &Path) -> std::io::Result<std::fs::File> {
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new().read(true).custom_flags(nix::fcntl::OFlag::O_NONBLOCK.bits()).open(path)
}

#[cfg(not(unix))]
fn open_nonblocking(path: &Path) -> std::io::Result<std::fs::File> {
    std::fs::File::open(path)
}

fn kind_of(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        let kinds = [t.is_fifo(), t.is_char_device(), t.is_block_device(), t.is_socket()];
        if let Some(i) = kinds.iter().position(|is| *is) {
            return ["a FIFO", "a character device", "a block device", "a socket"][i];
        }
    }
    if meta.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

#[cfg(test)]
mod tests;
