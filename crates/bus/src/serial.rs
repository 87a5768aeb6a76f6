//! The serial port as the serial backends (EPOS2, slcan) need it: a trait of three methods,
//! so that tests and the simulator can stand in for a port.

use std::io;
use std::time::Instant;

/// What a transport needs from a serial port.
pub trait SerialIo {
    /// Write every byte, and flush.
    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()>;
    /// Read what is available, waiting until `deadline` for at least one byte; 0 means the
    /// deadline passed. A vanished port is an error, never a 0.
    fn read_some(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize>;
    /// Drop what the port received and nobody read yet (resynchronising after garbage).
    fn discard_input(&mut self) -> io::Result<()>;
}

/// Any serial port of the OS: `/dev/tty*` on Unix, `COM*` on Windows.
impl<P: serialport::SerialPort> SerialIo for P {
    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        io::Write::write_all(self, bytes)?;
        io::Write::flush(self)
    }

    fn read_some(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            serialport::SerialPort::set_timeout(self, left)?;
            return match io::Read::read(self, buf) {
                Ok(0) => Err(io::Error::new(io::ErrorKind::UnexpectedEof, "the port closed")),
                Ok(n) => Ok(n),
                Err(e) if e.kind() == io::ErrorKind::TimedOut || e.kind() == io::ErrorKind::WouldBlock => Ok(0),
                // A signal (Ctrl-C, SIGTERM) cut the wait short: the line is fine. The
                // procedure looks at the interruption at its next safe point.
                Err(e) if e.kind() == io::ErrorKind::Interrupted && Instant::now() < deadline => continue,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => Ok(0),
                Err(e) => Err(e),
            };
        }
    }

    fn discard_input(&mut self) -> io::Result<()> {
        serialport::SerialPort::clear(self, serialport::ClearBuffer::Input).map_err(io::Error::from)
    }
}
