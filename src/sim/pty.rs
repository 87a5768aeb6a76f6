//! Pseudo-terminals for the simulator's serial device sides (EPOS2, slcan adapter).

use crate::error::{Error, Result};
use std::os::fd::OwnedFd;

/// A raw pty: its master, its slave and the slave's path. Whoever serves on it keeps the
/// slave open, so that the pty lives on between the programs that open it.
pub fn open_raw() -> Result<(OwnedFd, OwnedFd, String)> {
    use nix::sys::termios::{cfmakeraw, tcgetattr, tcsetattr, SetArg};
    let pty = nix::pty::openpty(None, None)
        .map_err(|e| Error::link_other(format!("cannot create a pseudo-terminal: {e}")))?;
    let mut t = tcgetattr(&pty.slave).map_err(|e| Error::link_other(format!("pty termios: {e}")))?;
    cfmakeraw(&mut t);
    tcsetattr(&pty.slave, SetArg::TCSANOW, &t).map_err(|e| Error::link_other(format!("pty termios: {e}")))?;
    let path = nix::unistd::ttyname(&pty.slave).map_err(|e| Error::link_other(format!("pty name: {e}")))?;
    Ok((pty.master, pty.slave, path.display().to_string()))
}
