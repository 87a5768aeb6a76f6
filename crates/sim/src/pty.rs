//! Pseudo-terminals for the simulator's serial device sides (EPOS2, slcan adapter).

use crate::error::{Error, LinkError, PtyOp, Result};
use std::os::fd::OwnedFd;

/// A pseudo-terminal operation that failed, as a link failure.
pub fn failed(op: PtyOp, e: impl std::fmt::Display) -> Error {
    LinkError::Pty { op, detail: e.to_string() }.into()
}

/// A raw pty: its master, its slave and the slave's path. Whoever serves on it keeps the
/// slave open, so that the pty lives on between the programs that open it.
pub(crate) fn open_raw() -> Result<(OwnedFd, OwnedFd, String)> {
    use nix::sys::termios::{cfmakeraw, tcgetattr, tcsetattr, SetArg};
    let pty = nix::pty::openpty(None, None).map_err(|e| failed(PtyOp::Create, e))?;
    let mut t = tcgetattr(&pty.slave).map_err(|e| failed(PtyOp::Termios, e))?;
    cfmakeraw(&mut t);
    tcsetattr(&pty.slave, SetArg::TCSANOW, &t).map_err(|e| failed(PtyOp::Termios, e))?;
    let path = nix::unistd::ttyname(&pty.slave).map_err(|e| failed(PtyOp::Name, e))?;
    // openpty(3) leaves both ends inheritable: a program started meanwhile (a test runs
    // many) would keep this pty alive after its server is gone.
    for fd in [&pty.master, &pty.slave] {
        use nix::fcntl::{fcntl, FcntlArg, FdFlag};
        fcntl(std::os::fd::AsRawFd::as_raw_fd(fd), FcntlArg::F_SETFD(FdFlag::FD_CLOEXEC))
            .map_err(|e| failed(PtyOp::Create, e))?;
    }
    Ok((pty.master, pty.slave, path.display().to_string()))
}
