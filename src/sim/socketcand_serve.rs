//! The simulated network behind a socketcand server on TCP: what linux-can/socketcand in
//! front of a CAN interface shows its clients, in raw mode, with the sim devices on the
//! bus. Several clients at once share the bus as programs share a real one: each client's
//! frames reach the devices and every other client (not itself, as a SocketCAN raw socket
//! does not hear its own frames). The server side is a `FrameLink`, so `bridge::run`
//! connects it to the devices as it does a CAN interface.

use crate::bus::FrameLink;
use crate::error::{LinkError, Result};
use crate::frame::Frame;
use crate::socketcand::wire::{Decoder, Unit};
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

/// The one interface the server offers: the sim network's bus.
pub const IFACE: &str = "sim";

/// A client that does not take its frames for this long is dropped, as socketcand would
/// lose it: the bus does not wait for one slow reader.
const WRITE_PATIENCE: Duration = Duration::from_secs(2);

/// The clients in raw mode, by number, each with the half of its connection frames go to.
type Clients = Arc<Mutex<Vec<(u64, TcpStream)>>>;

/// The server side: frames from the clients for the devices, frames from the devices to
/// every client.
pub struct SocketcandServer {
    addr: SocketAddr,
    clients: Clients,
    from_clients: Receiver<Frame>,
}

impl SocketcandServer {
    /// Listen on `addr` (port 0: any free one) and take clients from now on.
    pub fn bind(addr: SocketAddr) -> Result<SocketcandServer> {
        let listener =
            TcpListener::bind(addr).map_err(|error| LinkError::Open { port: format!("TCP {addr}"), error })?;
        let addr = listener.local_addr().map_err(|error| LinkError::Open { port: format!("TCP {addr}"), error })?;
        let clients: Clients = Arc::default();
        let (tx, from_clients) = mpsc::channel();
        let shared = clients.clone();
        std::thread::spawn(move || {
            for (stream, number) in listener.incoming().flatten().zip(1u64..) {
                let (clients, tx) = (shared.clone(), tx.clone());
                std::thread::spawn(move || serve_client(number, stream, clients, tx));
            }
        });
        Ok(SocketcandServer { addr, clients, from_clients })
    }

    /// Where the server listens.
    pub fn local_addr(&self) -> SocketAddr {
        self.addr
    }
}

fn micros_now() -> u64 {
    SystemTime::now().duration_since(UNIX_EPOCH).map(|d| d.as_micros() as u64).unwrap_or(0)
}

/// Write `frame` to every client in raw mode but `except`; a client that cannot take it
/// is dropped.
fn broadcast(clients: &Clients, frame: &Frame, except: Option<u64>) {
    let bytes = Unit::Frame { frame: *frame, micros: micros_now() }.encode();
    let mut clients = clients.lock().unwrap_or_else(PoisonError::into_inner);
    clients.retain_mut(|(number, stream)| {
        Some(*number) == except || {
            let ok = stream.write_all(&bytes).is_ok();
            if !ok {
                tracing::debug!(target: "canctl::socketcand", "client {number} dropped: it does not take its frames");
                let _ = stream.shutdown(std::net::Shutdown::Both);
            }
            ok
        }
    });
}

/// One client's connection, from `< hi >` to its end.
fn serve_client(number: u64, mut stream: TcpStream, clients: Clients, tx: Sender<Frame>) {
    let peer = stream.peer_addr().map(|a| a.to_string()).unwrap_or_default();
    tracing::debug!(target: "canctl::socketcand", "client {number} from {peer}");
    let _ = stream.set_nodelay(true);
    let _ = stream.set_write_timeout(Some(WRITE_PATIENCE));
    let Ok(writer) = stream.try_clone() else { return };
    let mut writer = Some(writer);
    // Answers go through the clients' lock once the client is in raw mode, so that they
    // never land inside a frame another thread is writing.
    let answer = |unit: &Unit, stream: &mut TcpStream| {
        let _guard = clients.lock().unwrap_or_else(PoisonError::into_inner);
        stream.write_all(&unit.encode()).is_ok()
    };
    let mut reply = match stream.try_clone() {
        Ok(s) => s,
        Err(_) => return,
    };
    if !answer(&Unit::Hi, &mut reply) {
        return;
    }
    let (mut opened, mut raw) = (false, false);
    let mut decoder = Decoder::new();
    let mut buf = [0u8; 4096];
    'conn: loop {
        let n = match stream.read(&mut buf) {
            Ok(0) | Err(_) => break,
            Ok(n) => n,
        };
        for unit in decoder.push(&buf[..n]) {
            let ok = match unit {
                Ok(Unit::Open(iface)) if !opened && iface == IFACE => {
                    opened = true;
                    answer(&Unit::Ok, &mut reply)
                }
                // As socketcand: a bus it does not offer ends the connection.
                Ok(Unit::Open(_)) if !opened => {
                    answer(&Unit::Refused("could not open bus".into()), &mut reply);
                    break 'conn;
                }
                // The client hears the bus from its `< ok >` on, as from socketcand's raw
                // socket bound before it answers: no frame before the answer, none missed.
                Ok(Unit::RawMode) if opened && !raw => {
                    raw = true;
                    let mut clients = clients.lock().unwrap_or_else(PoisonError::into_inner);
                    let ok = reply.write_all(&Unit::Ok.encode()).is_ok();
                    clients.extend(writer.take().map(|w| (number, w)));
                    ok
                }
                Ok(Unit::Echo) if opened => answer(&Unit::Echo, &mut reply),
                Ok(Unit::Send(frame)) if raw => {
                    broadcast(&clients, &frame, Some(number));
                    tx.send(frame).is_ok()
                }
                // 29-bit frames: no sim device listens to them.
                Ok(Unit::Extended { .. }) if raw => true,
                Ok(other) => {
                    tracing::debug!(target: "canctl::socketcand", "client {number}: {other:?} out of place");
                    answer(&Unit::Refused("unknown command".into()), &mut reply)
                }
                // socketcand logs a malformed unit and answers nothing.
                Err(bad) => {
                    tracing::debug!(target: "canctl::socketcand", "client {number}: malformed {:?}", bad.0);
                    true
                }
            };
            if !ok {
                break 'conn;
            }
        }
    }
    clients.lock().unwrap_or_else(PoisonError::into_inner).retain(|(n, _)| *n != number);
    let _ = stream.shutdown(std::net::Shutdown::Both);
    tracing::debug!(target: "canctl::socketcand", "client {number} left");
}

impl FrameLink for SocketcandServer {
    /// A frame from the devices, to every client.
    fn send(&mut self, frame: &Frame) -> Result<()> {
        broadcast(&self.clients, frame, None);
        Ok(())
    }

    /// A frame from a client, for the devices.
    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        let left = deadline.saturating_duration_since(Instant::now());
        match self.from_clients.recv_timeout(left) {
            Ok(f) => Ok(Some(f)),
            Err(RecvTimeoutError::Timeout) => Ok(None),
            // The accepting thread holds a sender for as long as the process runs.
            Err(RecvTimeoutError::Disconnected) => Ok(None),
        }
    }

    fn name(&self) -> String {
        format!("socketcand:{}/{IFACE}", self.addr)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backend::socketcand::SocketcandLink;

    fn client(server: &SocketcandServer) -> SocketcandLink {
        let addr = server.local_addr();
        let name = format!("socketcand:{addr}/{IFACE}");
        SocketcandLink::open(&addr.ip().to_string(), addr.port(), IFACE, name, Duration::from_secs(2)).unwrap()
    }

    #[test]
    fn every_client_sees_the_others_and_the_devices_frames() {
        let mut server = SocketcandServer::bind("127.0.0.1:0".parse().unwrap()).unwrap();
        let (mut a, mut b) = (client(&server), client(&server));
        let soon = || Instant::now() + Duration::from_secs(2);
        let request = Frame::new(0x605, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]);
        a.send(&request).unwrap();
        assert_eq!(server.recv(soon()).unwrap(), Some(request));
        assert_eq!(b.recv(soon()).unwrap(), Some(request));
        let answer = Frame::new(0x585, &[0x43, 0x00, 0x10, 0x00, 0x91, 0x01, 0x0F, 0x00]);
        server.send(&answer).unwrap();
        assert_eq!(a.recv(soon()).unwrap(), Some(answer));
        assert_eq!(b.recv(soon()).unwrap(), Some(answer));
        // A client does not hear its own frame back.
        assert_eq!(a.recv(Instant::now() + Duration::from_millis(50)).unwrap(), None);
        // The server answers the echo a silence is checked with.
        a.check().unwrap();
    }

    #[test]
    fn an_interface_it_does_not_offer_is_refused() {
        let server = SocketcandServer::bind("127.0.0.1:0".parse().unwrap()).unwrap();
        let addr = server.local_addr();
        let e =
            SocketcandLink::open("127.0.0.1", addr.port(), "can0", "x".into(), Duration::from_secs(2)).err().unwrap();
        assert!(e.to_string().contains("refused to open can0: could not open bus"), "{e}");
    }
}
