//! Why a PDO stream may be silent: the node not operational, a synchronous TPDO without
//! SYNC, an event-driven one that SYNC does not drive, one sent only on request.

use crate::bus::{Bus, SdoOptions};
use crate::canopen::nmt::State;
use crate::canopen::pdo::Layout;
use crate::canopen::ObjAddr;
use crate::error::Result;
pub use crate::ops::event::Silence;
use crate::ops::event::Warning;
use crate::ops::nmt::NodeState;
use std::time::Duration;

/// How long the stream of these TPDOs of `node` may be silent before it is worth saying,
/// and why it may be. `state` is the node's NMT state (and how it was learned) when it was
/// asked (not when the stream puts the node in Operational itself); `sync` the SYNC period
/// sent, if any. Also the warnings worth giving before the stream starts: SYNC asked for
/// TPDOs that SYNC does not drive.
pub fn hint(
    bus: &mut dyn Bus,
    node: u8,
    layouts: &[(u16, Layout)],
    state: Option<Result<NodeState>>,
    sync: Option<Duration>,
    timeout: Duration,
) -> ((Duration, Vec<Silence>), Vec<Warning>) {
    let mut why = Vec::new();
    let mut warnings = Vec::new();
    let mut after = Duration::from_secs(1);
    match state {
        None | Some(Ok(NodeState { state: State::Operational, .. })) => {}
        Some(Ok(NodeState { state, source, .. })) => why.push(Silence::NotOperational { node, state, source }),
        Some(Err(_)) => why.push(Silence::StateUnknown { node }),
    }
    let read = |bus: &mut dyn Bus, addr: ObjAddr| bus.sdo_upload(node, addr, &SdoOptions::new(timeout)).ok();
    for (n, _) in layouts {
        let (pdo, comm) = (*n, 0x1800 + n - 1);
        let Some(kind) = read(bus, ObjAddr::new(comm, 2)).and_then(|b| b.first().copied()) else { continue };
        let timer = read(bus, ObjAddr::new(comm, 5)).and_then(|b| Some(u16::from_le_bytes([*b.first()?, *b.get(1)?])));
        match (kind, sync) {
            (0..=240, None) => why.push(Silence::WaitsForSync { pdo, kind }),
            (0..=240, Some(period)) => after = after.max(period * 3 * u32::from(kind.max(1))),
            (252 | 253, _) => why.push(Silence::OnRequest { pdo, kind }),
            (254 | 255, sync) => {
                if sync.is_some() {
                    why.push(Silence::SyncDoesNotDrive { pdo, kind });
                    warnings.push(Warning::SyncDoesNotDrive { node, pdo, transmission: kind });
                }
                match timer {
                    Some(0) | None => why.push(Silence::NoEventTimer { pdo }),
                    Some(ms) => after = after.max(Duration::from_millis(3 * u64::from(ms))),
                }
            }
            _ => {}
        }
    }
    if why.is_empty() {
        why.push(Silence::NothingFound);
    }
    ((after.min(Duration::from_secs(30)), why), warnings)
}
