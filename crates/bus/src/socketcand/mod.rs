//! socketcand (linux-can/socketcand): a daemon that offers a machine's CAN interfaces over
//! TCP. canctl speaks its raw mode: the protocol's `< ... >` units ([`wire`]) and the
//! failures of a link over it ([`SocketcandError`]). The link that speaks it is
//! `backend::socketcand`; `canctl sim --socketcand` serves the simulated network with it.

pub mod beacon;
pub mod wire;

use std::time::Duration;

/// The port socketcand listens on unless told otherwise.
pub const DEFAULT_PORT: u16 = 29536;

/// What went wrong with a socketcand server; `server` is the bus as the user named it.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum SocketcandError {
    /// The TCP connection could not be made.
    #[error(
        "{server}: cannot connect: {error}. Is socketcand running there (socketcand -i IFACE -l ETH) and its port \
         open? Through an SSH tunnel: is the tunnel up (ssh -N -L 29536:localhost:29536 HOST)?"
    )]
    Connect {
        /// The bus address.
        server: String,
        /// Why the connection failed.
        error: std::sync::Arc<std::io::Error>,
    },
    /// The server said nothing in time while canctl waited for `waiting_for`.
    #[error("{server}: no {waiting_for} within {} ms: is that port a socketcand server, is it overloaded, is the network to it up?", waited.as_millis())]
    NoAnswer {
        /// The bus address.
        server: String,
        /// The answer waited for (`< hi >`, `< ok >`).
        waiting_for: &'static str,
        /// How long canctl waited.
        waited: Duration,
    },
    /// The server refused a step of the handshake with `< error ... >`.
    #[error(
        "{server}: the server refused to {what}: {answer}. The interfaces it offers are the ones its -i option names"
    )]
    Refused {
        /// The bus address.
        server: String,
        /// The step refused ("open can0", "switch to raw mode").
        what: String,
        /// The server's words.
        answer: String,
    },
    /// The server answered a step of the handshake with something else than `< ok >`.
    #[error("{server}: to {what}, the server answered {answer:?}, not < ok >: is that a socketcand server?")]
    Unexpected {
        /// The bus address.
        server: String,
        /// The step ("greet", "open can0", "switch to raw mode").
        what: String,
        /// What came instead.
        answer: String,
    },
    /// The server took no bytes for this long: it, or the network to it, is stuck.
    #[error("{server}: the server has taken nothing canctl sent for {} ms: is it overloaded, or the network to it down?", waited.as_millis())]
    Stalled {
        /// The bus address.
        server: String,
        /// How long a write waited.
        waited: Duration,
    },
    /// The connection broke or was closed by the server.
    #[error("{server}: the connection to the server was lost{}: check the server (is socketcand still running?) and the network, then run the command again",
        error.as_ref().map(|e| format!(" ({e})")).unwrap_or_default())]
    Lost {
        /// The bus address.
        server: String,
        /// The socket's error; none when the server closed the connection.
        error: Option<std::sync::Arc<std::io::Error>>,
    },
}
