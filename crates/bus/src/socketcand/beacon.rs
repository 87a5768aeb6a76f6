//! The discovery beacon of socketcand, pure: a UDP datagram to port 42000 that socketcand
//! sends every 3 s (linux-can/socketcand `beacon.c`), one XML element:
//!
//! ```text
//! <CANBeacon name="HOSTNAME" type="SocketCAN" description="...">
//! <URL>can://192.168.1.20:29536</URL><Bus name="can0"/><Bus name="vcan0"/></CANBeacon>
//! ```
//!
//! Only this shape is read (python-can's `detect_beacon` reads the same: the `URL` and
//! each `Bus`); anything else is refused with what was wrong, never guessed.

use std::fmt::Write as _;
use std::net::SocketAddr;

/// The UDP port socketcand beacons go to.
pub const PORT: u16 = 42000;

/// The `type` socketcand puts in its beacons.
pub const TYPE: &str = "SocketCAN";

/// A beacon as a server sent it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Beacon {
    /// The `name` attribute: socketcand's host name.
    pub name: String,
    /// The `type` attribute (`SocketCAN`).
    pub kind: String,
    /// The `description` attribute.
    pub description: String,
    /// The host of the `URL`, as written (an IPv4 address for socketcand).
    pub host: String,
    /// The TCP port of the `URL`.
    pub port: u16,
    /// The CAN interfaces offered, in the beacon's order.
    pub buses: Vec<String>,
}

/// Why a datagram is not a beacon.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BeaconError {
    /// Not UTF-8 text.
    #[error("not text")]
    NotText,
    /// No `<CANBeacon ...>` element.
    #[error("not a CANBeacon")]
    NotBeacon,
    /// The element does not end with `</CANBeacon>`: cut short.
    #[error("cut short (no </CANBeacon>)")]
    Truncated,
    /// No `<URL>`, or one that is not `can://HOST:PORT`.
    #[error("no can://HOST:PORT URL: {0:?}")]
    Url(String),
    /// No `<Bus name=".."/>`: nothing to open.
    #[error("no bus offered")]
    NoBus,
    /// Something between the elements that is not one of them.
    #[error("unexpected {0:?}")]
    Unexpected(String),
}

/// Read a beacon from a datagram's bytes.
pub fn parse(bytes: &[u8]) -> Result<Beacon, BeaconError> {
    let text = std::str::from_utf8(bytes).map_err(|_| BeaconError::NotText)?;
    let text = text.trim_matches(|c: char| c.is_whitespace() || c == '\0');
    let rest = text.strip_prefix("<CANBeacon").ok_or(BeaconError::NotBeacon)?;
    if !rest.starts_with(|c: char| c.is_whitespace() || c == '>') {
        return Err(BeaconError::NotBeacon);
    }
    let (attrs, body) = rest.split_once('>').ok_or(BeaconError::Truncated)?;
    let body = body.strip_suffix("</CANBeacon>").ok_or(BeaconError::Truncated)?;
    let attr = |name| attribute(attrs, name).unwrap_or_default();
    let (name, kind, description) = (attr("name"), attr("type"), attr("description"));
    let (mut url, mut buses) = (None, Vec::new());
    let mut body = body.trim_start();
    while !body.is_empty() {
        if let Some(r) = body.strip_prefix("<URL>") {
            let (u, r) = r.split_once("</URL>").ok_or(BeaconError::Truncated)?;
            url = Some(unescape(u.trim()));
            body = r;
        } else if let Some(r) = body.strip_prefix("<Bus") {
            let (a, r) = r.split_once("/>").ok_or(BeaconError::Truncated)?;
            let bus = attribute(a, "name").filter(|b| !b.is_empty());
            buses.push(bus.ok_or_else(|| BeaconError::Unexpected(format!("<Bus{a}/>")))?);
            body = r;
        } else {
            return Err(BeaconError::Unexpected(body.chars().take(40).collect()));
        }
        body = body.trim_start();
    }
    let url = url.ok_or_else(|| BeaconError::Url(String::new()))?;
    let (host, port) = parse_url(&url).ok_or(BeaconError::Url(url))?;
    if buses.is_empty() {
        return Err(BeaconError::NoBus);
    }
    Ok(Beacon { name, kind, description, host, port, buses })
}

/// `can://HOST:PORT` (`[V6]:PORT` too).
fn parse_url(url: &str) -> Option<(String, u16)> {
    let rest = url.strip_prefix("can://")?.trim_end_matches('/');
    let (host, port) = rest.rsplit_once(':')?;
    let host = host.strip_prefix('[').and_then(|h| h.strip_suffix(']')).unwrap_or(host);
    let port = port.parse().ok().filter(|p| *p != 0)?;
    (!host.is_empty() && !host.contains(['/', ' '])).then(|| (host.to_string(), port))
}

/// The value of `name="..."` in an element's attributes.
fn attribute(attrs: &str, name: &str) -> Option<String> {
    let mut rest = attrs;
    loop {
        let at = rest.find(name)?;
        let before_ok = rest[..at].ends_with(char::is_whitespace);
        rest = &rest[at + name.len()..];
        let Some(v) = rest.trim_start().strip_prefix('=') else { continue };
        let v = v.trim_start();
        let quote = v.chars().next().filter(|q| *q == '"' || *q == '\'')?;
        let (value, _) = v[1..].split_once(quote)?;
        if before_ok {
            return Some(unescape(value));
        }
    }
}

/// XML's five entities; socketcand writes none, other senders may.
fn unescape(s: &str) -> String {
    s.replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", "\"").replace("&apos;", "'").replace("&amp;", "&")
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// The beacon a server at `addr` offering `buses` sends, as socketcand writes it.
pub fn encode(name: &str, description: &str, addr: SocketAddr, buses: &[&str]) -> Vec<u8> {
    let host = match addr {
        SocketAddr::V4(a) => a.ip().to_string(),
        SocketAddr::V6(a) => format!("[{}]", a.ip()),
    };
    let mut out = format!(
        "<CANBeacon name=\"{}\" type=\"{TYPE}\" description=\"{}\">\n<URL>can://{host}:{}</URL>",
        escape(name),
        escape(description),
        addr.port()
    );
    for bus in buses {
        let _ = write!(out, "<Bus name=\"{}\"/>", escape(bus));
    }
    out.push_str("</CANBeacon>");
    out.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// As socketcand 0.6 sends it from a Raspberry Pi offering two interfaces.
    const REAL: &[u8] = b"<CANBeacon name=\"raspberrypi\" type=\"SocketCAN\" description=\"socketcand\">\n\
        <URL>can://192.168.1.20:29536</URL><Bus name=\"can0\"/><Bus name=\"vcan0\"/></CANBeacon>";

    #[test]
    fn a_socketcand_beacon_with_two_buses() {
        let b = parse(REAL).unwrap();
        assert_eq!(b.name, "raspberrypi");
        assert_eq!(b.kind, "SocketCAN");
        assert_eq!(b.description, "socketcand");
        assert_eq!((b.host.as_str(), b.port), ("192.168.1.20", 29536));
        assert_eq!(b.buses, ["can0", "vcan0"]);
    }

    #[test]
    fn what_encode_writes_parses_back() {
        let addr: SocketAddr = "127.0.0.1:4711".parse().unwrap();
        let bytes = encode("bench \"1\"", "canctl sim", addr, &["sim"]);
        let b = parse(&bytes).unwrap();
        assert_eq!((b.name.as_str(), b.description.as_str()), ("bench \"1\"", "canctl sim"));
        assert_eq!((b.host.as_str(), b.port, b.buses.clone()), ("127.0.0.1", 4711, vec!["sim".to_string()]));
        let v6 = parse(&encode("h", "d", "[::1]:29536".parse().unwrap(), &["can0"])).unwrap();
        assert_eq!(v6.host, "::1");
    }

    #[test]
    fn other_spacing_and_a_trailing_nul_are_read() {
        let b = parse(b"<CANBeacon  type='SocketCAN' name='x'>\r\n <URL> can://10.0.0.2:4000 </URL>\n <Bus name='can1' />\n</CANBeacon>\0\n")
            .unwrap();
        assert_eq!((b.name.as_str(), b.host.as_str(), b.port), ("x", "10.0.0.2", 4000));
        assert_eq!(b.buses, ["can1"]);
        assert_eq!(b.description, "");
    }

    #[test]
    fn every_cut_of_a_beacon_is_refused() {
        for n in 0..REAL.len() {
            assert!(parse(&REAL[..n]).is_err(), "accepted {:?}", String::from_utf8_lossy(&REAL[..n]));
        }
        assert_eq!(parse(&REAL[..REAL.len() - 3]), Err(BeaconError::Truncated));
    }

    #[test]
    fn garbage_is_refused_with_why() {
        assert_eq!(parse(&[0xff, 0xfe, 0x00]), Err(BeaconError::NotText));
        assert_eq!(parse(b"hello"), Err(BeaconError::NotBeacon));
        assert_eq!(parse(b"<CANBeaconX name=\"a\"></CANBeaconX>"), Err(BeaconError::NotBeacon));
        let no_bus = b"<CANBeacon name=\"a\"><URL>can://1.2.3.4:5</URL></CANBeacon>";
        assert_eq!(parse(no_bus), Err(BeaconError::NoBus));
        let no_url = b"<CANBeacon name=\"a\"><Bus name=\"can0\"/></CANBeacon>";
        assert_eq!(parse(no_url), Err(BeaconError::Url(String::new())));
        for bad in ["http://1.2.3.4:5", "can://1.2.3.4", "can://1.2.3.4:0", "can://:29536", "can://1.2.3.4:x"] {
            let b = format!("<CANBeacon><URL>{bad}</URL><Bus name=\"can0\"/></CANBeacon>");
            assert!(matches!(parse(b.as_bytes()), Err(BeaconError::Url(_))), "{bad}");
        }
        let stray = b"<CANBeacon><URL>can://1.2.3.4:5</URL><Bus name=\"can0\"/><script/></CANBeacon>";
        assert!(matches!(parse(stray), Err(BeaconError::Unexpected(_))));
        let nameless = b"<CANBeacon><URL>can://1.2.3.4:5</URL><Bus/></CANBeacon>";
        assert!(matches!(parse(nameless), Err(BeaconError::Unexpected(_))));
    }

    #[test]
    fn an_attribute_is_not_found_inside_another_name() {
        let b =
            parse(b"<CANBeacon hostname=\"no\" name=\"yes\"><URL>can://1.2.3.4:5</URL><Bus name=\"c\"/></CANBeacon>")
                .unwrap();
        assert_eq!(b.name, "yes");
    }
}
