//! The simulated network behind a socketcand server on TCP: what linux-can/socketcand in
//! front of a CAN interface shows its clients, in raw mode, with the sim devices on the
//! bus. Several clients at once share the bus as programs share a real one: each client's
//! frames reach the devices and every other client (not itself, as a SocketCAN raw socket
//! does not hear its own frames). The server side is a `FrameLink`, so `bridge::run`
//! connects it to the devices as it does a CAN interface.

use crate::bus::FrameLink;
use crate::error::{LinkError, Result};
use crate::frame::Frame;
use crate::socketcand::beacon;
use crate::socketcand::wire::{Decoder, Unit};
use std::io::{Read, Write};
use std::net::{Ipv4Addr, SocketAddr, TcpListener, TcpStream, UdpSocket};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

/// The one interface the server offers: the sim network's bus.
pub const IFACE: &str = "sim";

/// A client that does not take its frames for this long is dropped, as socketcand would
/// lose it: the bus does not wait for one slow reader.
const WRITE_PATIENCE: Duration = Duration::from_secs(2);

/// How long frames for a client wait after its `< ok >` to raw mode, unless it sends
/// something first. python-can reads each handshake answer with one `recv` and takes it
/// whole for the answer: a frame arriving with the `< ok >` would fail its handshake.
/// Frames are held back, not lost.
const HANDSHAKE_GRACE: Duration = Duration::from_millis(50);

/// A client in raw mode.
struct Client {
    number: u64,
    /// The half of its connection frames go to.
    stream: TcpStream,
    /// Frames held back during [`HANDSHAKE_GRACE`]; `None` once they flow.
    held: Option<Vec<u8>>,
    /// Writes of frames to it so far: the frames the devices send at once are one.
    writes: u64,
}

/// The clients in raw mode.
type Clients = Arc<Mutex<Vec<Client>>>;

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
        let open = |error: std::io::Error| LinkError::Open { port: format!("TCP {addr}"), error: error.into() };
        let listener = TcpListener::bind(addr).map_err(open)?;
        let addr = listener.local_addr().map_err(open)?;
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

/// Write `frames` to every client in raw mode but `except`, in one write each; a client
/// that cannot take them is dropped.
fn broadcast(clients: &Clients, frames: &[Frame], except: Option<u64>) {
    let micros = SystemTime::now().duration_since(UNIX_EPOCH).map(|d| d.as_micros() as u64).unwrap_or(0);
    let bytes: Vec<u8> = frames.iter().flat_map(|frame| Unit::Frame { frame: *frame, micros }.encode()).collect();
    if bytes.is_empty() {
        return;
    }
    let mut clients = clients.lock().unwrap_or_else(PoisonError::into_inner);
    clients.retain_mut(|c| match &mut c.held {
        _ if Some(c.number) == except => true,
        Some(held) => {
            held.extend_from_slice(&bytes);
            true
        }
        None => write_or_drop(c, &bytes),
    });
}

/// Write to a client; one that cannot take it is let go.
fn write_or_drop(c: &mut Client, bytes: &[u8]) -> bool {
    c.writes += 1;
    let ok = c.stream.write_all(bytes).is_ok();
    if !ok {
        tracing::debug!(target: "canctl::socketcand", "client {} dropped: it does not take its frames", c.number);
        let _ = c.stream.shutdown(std::net::Shutdown::Both);
    }
    ok
}

/// The end of a client's grace: the frames held back go out, and from now on each at once.
fn release(clients: &Clients, number: u64) {
    let mut clients = clients.lock().unwrap_or_else(PoisonError::into_inner);
    clients.retain_mut(|c| match c.held.take() {
        Some(held) if c.number == number => write_or_drop(c, &held),
        held => {
            c.held = held;
            true
        }
    });
}

/// One client's connection, from `< hi >` to its end.
fn serve_client(number: u64, mut stream: TcpStream, clients: Clients, tx: Sender<Frame>) {
    let peer = stream.peer_addr().map(|a| a.to_string()).unwrap_or_default();
    tracing::debug!(target: "canctl::socketcand", "client {number} from {peer}");
    let _ = stream.set_nodelay(true);
    let _ = stream.set_write_timeout(Some(WRITE_PATIENCE));
    // One half for frames (once in raw mode), one for answers.
    let (Ok(writer), Ok(mut reply)) = (stream.try_clone(), stream.try_clone()) else { return };
    let mut writer = Some(writer);
    // Answers go through the clients' lock once the client is in raw mode, so that they
    // never land inside a frame another thread is writing.
    let answer = |unit: &Unit, stream: &mut TcpStream| {
        let _guard = clients.lock().unwrap_or_else(PoisonError::into_inner);
        stream.write_all(&unit.encode()).is_ok()
    };
    if !answer(&Unit::Hi, &mut reply) {
        return;
    }
    let (mut opened, mut raw, mut held) = (false, false, false);
    let mut decoder = Decoder::new();
    let mut buf = [0u8; 4096];
    'conn: loop {
        let n = match stream.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if held && matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => 0,
            Err(_) => break,
        };
        // The grace ends when the client says anything, or when it is over.
        if std::mem::take(&mut held) {
            release(&clients, number);
            let _ = stream.set_read_timeout(None);
        }
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
                // socket bound before it answers: no frame before the answer, none missed
                // (those of the grace come just after it).
                Ok(Unit::RawMode) if opened && !raw => {
                    (raw, held) = (true, true);
                    let mut clients = clients.lock().unwrap_or_else(PoisonError::into_inner);
                    let ok = reply.write_all(&Unit::Ok.encode()).is_ok();
                    let client =
                        writer.take().map(|stream| Client { number, stream, held: Some(Vec::new()), writes: 0 });
                    clients.extend(client);
                    let _ = stream.set_read_timeout(Some(HANDSHAKE_GRACE));
                    ok
                }
                Ok(Unit::Echo) if opened => answer(&Unit::Echo, &mut reply),
                Ok(Unit::Send(frame)) if raw => {
                    broadcast(&clients, &[frame], Some(number));
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
    clients.lock().unwrap_or_else(PoisonError::into_inner).retain(|c| c.number != number);
    let _ = stream.shutdown(std::net::Shutdown::Both);
    tracing::debug!(target: "canctl::socketcand", "client {number} left");
}

impl FrameLink for SocketcandServer {
    /// A frame from the devices, to every client.
    fn send(&mut self, frame: &Frame) -> Result<()> {
        broadcast(&self.clients, std::slice::from_ref(frame), None);
        Ok(())
    }

    /// Frames from the devices at once (a block upload's segments), in one write a client.
    fn send_all(&mut self, frames: &[Frame]) -> Result<()> {
        broadcast(&self.clients, frames, None);
        Ok(())
    }

    /// A frame from a client, for the devices.
    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        let left = deadline.saturating_duration_since(Instant::now());
        // A timeout, or none: the accepting thread holds a sender for as long as the process runs.
        Ok(self.from_clients.recv_timeout(left).ok())
    }

    fn name(&self) -> String {
        format!("socketcand:{}/{IFACE}", self.addr)
    }
}

/// How often the beacon goes out: socketcand sends one every 3 s, and listeners wait about
/// that long, so a little more often never lets one miss it.
pub const BEACON_EVERY: Duration = Duration::from_millis(2500);

/// The environment variable that moves the beacon's UDP port (both the sender here and the
/// listener of `canctl buses`), so that tests running at once do not hear each other.
/// Not for users: socketcand and its clients use [`beacon::PORT`].
pub const BEACON_PORT_ENV: &str = "CANCTL_BEACON_PORT";

/// The UDP port beacons go to and are listened for on.
pub fn beacon_port() -> u16 {
    std::env::var(BEACON_PORT_ENV).ok().and_then(|p| p.parse().ok()).unwrap_or(beacon::PORT)
}

/// Where the beacon of a server bound to `bound` goes: on loopback to 127.0.0.1 only (a
/// test, a tunnel: nothing goes onto a network), otherwise to the broadcast address, as
/// socketcand sends it.
pub fn beacon_target(bound: SocketAddr, port: u16) -> SocketAddr {
    // The listener of `canctl buses` is IPv4: a server on ::1 is announced there too.
    SocketAddr::from((if bound.ip().is_loopback() { Ipv4Addr::LOCALHOST } else { Ipv4Addr::BROADCAST }, port))
}

/// Announce the server at `bound` offering [`IFACE`] to `target` every [`BEACON_EVERY`],
/// from a thread of its own, for as long as the process runs. A beacon that cannot be sent
/// (no network, broadcasts refused) is skipped: serving goes on without it.
pub fn start_beacon(bound: SocketAddr, target: SocketAddr) -> Result<()> {
    let open = |error: std::io::Error| LinkError::Open { port: format!("UDP beacon to {target}"), error: error.into() };
    let any = if target.is_ipv4() { Ipv4Addr::UNSPECIFIED.into() } else { std::net::Ipv6Addr::UNSPECIFIED.into() };
    let socket = UdpSocket::bind(SocketAddr::new(any, 0)).map_err(open)?;
    socket.set_broadcast(!target.ip().is_loopback()).map_err(open)?;
    // Bound to every address, the URL names the one the beacon leaves from, which is the
    // one its listeners can reach.
    let connected = bound.ip().is_unspecified() && socket.connect(target).is_ok();
    let leaves_from = socket.local_addr().ok().filter(|a| connected && !a.ip().is_unspecified());
    let url = leaves_from.map_or(bound, |a| SocketAddr::new(a.ip(), bound.port()));
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").map(|h| h.trim().to_string());
    let name = host.ok().filter(|h| !h.is_empty()).unwrap_or_else(|| "canctl".into());
    let bytes = beacon::encode(&name, "canctl sim", url, &[IFACE]);
    std::thread::spawn(move || loop {
        if let Err(e) = socket.send_to(&bytes, target) {
            tracing::debug!(target: "canctl::socketcand", "beacon to {target} not sent: {e}");
        }
        std::thread::sleep(BEACON_EVERY);
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use canctl_bus::backend::socketcand::SocketcandLink;

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

    /// python-can takes one read for the `< ok >`: a frame right behind it waits until the
    /// client has had time to read it alone, and then comes.
    #[test]
    fn no_frame_rides_with_the_ok_to_raw_mode() {
        let mut server = SocketcandServer::bind("127.0.0.1:0".parse().unwrap()).unwrap();
        let mut c = TcpStream::connect(server.local_addr()).unwrap();
        c.set_read_timeout(Some(Duration::from_secs(2))).unwrap();
        let mut w = c.try_clone().unwrap();
        let mut read = || {
            let mut buf = [0u8; 256];
            let n = c.read(&mut buf).unwrap();
            String::from_utf8_lossy(&buf[..n]).into_owned()
        };
        assert_eq!(read(), "< hi >");
        w.write_all(b"< open sim >").unwrap();
        assert_eq!(read(), "< ok >");
        w.write_all(b"< rawmode >").unwrap();
        let joined = Instant::now() + Duration::from_secs(2);
        while server.clients.lock().unwrap().is_empty() {
            assert!(Instant::now() < joined, "the client never joined");
            std::thread::sleep(Duration::from_millis(1));
        }
        // The ok is written; a device's frame follows before the client has read.
        let heartbeat = Frame::new(0x705, &[0x7F]);
        server.send(&heartbeat).unwrap();
        std::thread::sleep(Duration::from_millis(10));
        assert_eq!(read(), "< ok >");
        let rest = read();
        assert!(rest.starts_with("< frame 705 ") && rest.ends_with(" 7F >"), "{rest}");
    }

    #[test]
    fn the_beacon_names_the_server_and_stays_on_loopback() {
        let port = 42000;
        let lo: SocketAddr = "127.0.0.1:4000".parse().unwrap();
        assert_eq!(beacon_target(lo, port), "127.0.0.1:42000".parse().unwrap());
        assert_eq!(beacon_target("[::1]:4000".parse().unwrap(), port), "127.0.0.1:42000".parse().unwrap());
        let lan: SocketAddr = "192.168.1.20:4000".parse().unwrap();
        assert_eq!(beacon_target(lan, port), "255.255.255.255:42000".parse().unwrap());
        let listener = UdpSocket::bind("127.0.0.1:0").unwrap();
        listener.set_read_timeout(Some(Duration::from_secs(2))).unwrap();
        start_beacon(lo, listener.local_addr().unwrap()).unwrap();
        let mut buf = [0u8; 1024];
        let n = listener.recv(&mut buf).unwrap();
        let b = beacon::parse(&buf[..n]).unwrap();
        assert_eq!((b.host.as_str(), b.port, b.buses.clone()), ("127.0.0.1", 4000, vec![IFACE.to_string()]));
    }

    /// A block each way through the server, with the devices behind it: canctl's client
    /// writes a block's segments in one write, the server a device's block in one write a
    /// client (one system call and a few TCP segments for up to 127 frames, not one each:
    /// per frame, they were what made a transfer through socketcand slow).
    #[test]
    fn a_block_goes_in_one_write_each_way() {
        use crate::bus::{Bus, Master, SdoOptions};
        use crate::canopen::ObjAddr;
        use crate::{SimConfig, SimLink};
        let mut server = SocketcandServer::bind("127.0.0.1:0".parse().unwrap()).unwrap();
        let clients = server.clients.clone();
        let mut m = Master::new(client(&server), "socketcand".into());
        std::thread::spawn(move || {
            let sim = SimLink::with_config(SimConfig::instant());
            crate::bridge::run(sim, &mut server, None)
        });
        let domain = ObjAddr::new(0x1F50, 1);
        let opts = SdoOptions { block_download: true, block_upload: true, ..SdoOptions::new(Duration::from_secs(2)) };
        // Three blocks of 127 segments of 7 bytes, the last one short.
        let data: Vec<u8> = (0..127 * 7 * 3 - 5).map(|i| (i * 7 % 251) as u8).collect();
        let sent_before = m.link_mut().writes();
        m.sdo_download(1, domain, &data, &opts).unwrap();
        // The initiation, three blocks, the end.
        let sent = m.link_mut().writes() - sent_before;
        assert_eq!(sent, 5, "{sent} writes for a block download of three blocks");
        let served = || clients.lock().unwrap().iter().map(|c| c.writes).sum::<u64>();
        let served_before = served();
        assert_eq!(m.sdo_upload(1, domain, &opts).unwrap(), data);
        // The answer to the initiation, three blocks, the end: five writes when each block
        // is ready at once. The bridge writes what the devices have ready, so on a loaded
        // machine a block may go in a few (one write a frame, 383, is what this keeps away).
        let served = served() - served_before;
        assert!((5..=12).contains(&served), "{served} writes of the server for a block upload of three blocks");
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
