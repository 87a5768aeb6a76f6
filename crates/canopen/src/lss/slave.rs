//! The slave side of LSS (CiA 305), for the simulated devices: the state a device is in,
//! what it answers and what its firmware must do after a request.

use super::wire::{Identity, Inquiry, Request, Response, BIT_TIMINGS, FASTSCAN_RESET, UNCONFIGURED};

/// LSS state of a slave.
#[derive(Clone, Copy, PartialEq, Eq, Debug, serde::Serialize, serde::Deserialize)]
pub enum SlaveState {
    /// LSS waiting state: only switch and identify services are answered.
    Waiting,
    /// LSS configuration state: node-id and bit timing may be configured.
    Configuration,
}

/// What the device behind a slave must do after a request.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum SlaveEvent {
    /// The node-id was configured (pending until the slave leaves configuration).
    NodeId(u8),
    /// The bit timing was configured: a CiA 305 table index.
    BitTiming(u8),
    /// Activate bit timing was asked: switch after `delay_ms`, and once more after it.
    Activate {
        /// The switch delay, in milliseconds.
        delay_ms: u16,
    },
    /// Store configuration was asked.
    Store,
    /// Left configuration state (a device given a node-id boots with it then).
    BackToWaiting,
}

/// What a slave device supports and holds, as its firmware decides.
#[derive(Clone, Copy, Debug)]
pub struct SlaveCaps {
    /// Whether it can store its configuration.
    pub store: bool,
    /// Whether it can configure its bit timing.
    pub bit_timing: bool,
    /// durand 0.5's way: a node-id given applies only on the switch back to waiting, and
    /// until then the device takes part in fastscan in configuration state too (CiA 305
    /// has only devices in waiting state take part; CANopenNode keeps to it).
    pub fastscan_in_configuration: bool,
}

/// The slave side (CiA 305), for the simulated devices.
#[derive(Clone, Debug)]
pub struct Slave {
    /// Its LSS address (0x1018).
    pub identity: Identity,
    /// Its LSS state.
    pub state: SlaveState,
    caps: SlaveCaps,
    /// Selective switch: how many identity parts have matched in sequence.
    selective: u8,
    /// Identify remote slave: which of the six range checks have passed.
    identify: u8,
    fastscan_pos: u8,
    /// It had no node-id when it entered configuration state (durand's fastscan asks that).
    entered_unnumbered: bool,
}

impl Slave {
    /// A slave in waiting state.
    pub fn new(identity: Identity, caps: SlaveCaps) -> Slave {
        Slave {
            identity,
            state: SlaveState::Waiting,
            caps,
            selective: 0,
            identify: 0,
            fastscan_pos: 0,
            entered_unnumbered: false,
        }
    }

    /// One request; `node_id` is the device's current one (`UNCONFIGURED` for none).
    pub fn handle(&mut self, req: Request, node_id: u8) -> (Option<Response>, Option<SlaveEvent>) {
        let was = self.state;
        let done = self.respond(req, node_id);
        if was == SlaveState::Waiting && self.state == SlaveState::Configuration {
            self.entered_unnumbered = node_id == UNCONFIGURED;
        }
        done
    }

    fn respond(&mut self, req: Request, node_id: u8) -> (Option<Response>, Option<SlaveEvent>) {
        let configuring = self.state == SlaveState::Configuration;
        match req {
            Request::SwitchGlobal { configuration } => {
                self.selective = 0;
                let was = self.state;
                self.state = if configuration { SlaveState::Configuration } else { SlaveState::Waiting };
                let event = (was == SlaveState::Configuration && !configuration).then_some(SlaveEvent::BackToWaiting);
                (None, event)
            }
            Request::SwitchSelective { part, value } => {
                if part == self.selective && value == self.identity.part(part) {
                    self.selective += 1;
                    if self.selective == 4 {
                        self.selective = 0;
                        self.state = SlaveState::Configuration;
                        return (Some(Response::SwitchSelectiveAck), None);
                    }
                } else {
                    self.selective = if part == 0 && value == self.identity.vendor { 1 } else { 0 };
                }
                (None, None)
            }
            Request::ConfigureNodeId(id) if configuring => {
                result(0x11, (1..=127).contains(&id) || id == UNCONFIGURED, SlaveEvent::NodeId(id))
            }
            Request::ConfigureBitTiming { table, index } if configuring => {
                let ok = self.caps.bit_timing
                    && table == 0
                    && BIT_TIMINGS.get(index as usize).is_some_and(|(_, k)| k.is_some());
                result(0x13, ok, SlaveEvent::BitTiming(index))
            }
            Request::ActivateBitTiming { delay_ms } if configuring => (None, Some(SlaveEvent::Activate { delay_ms })),
            Request::StoreConfiguration if configuring => result(0x17, self.caps.store, SlaveEvent::Store),
            Request::Inquire(q) if configuring => {
                let value = match q {
                    Inquiry::NodeId => node_id as u32,
                    part => self.identity.part(part.cs() - Inquiry::Vendor.cs()),
                };
                (Some(Response::InquiredValue { inquiry: q, value }), None)
            }
            Request::IdentifyRemote { field, value } => {
                let ok = match field {
                    0x46 => value == self.identity.vendor,
                    0x47 => value == self.identity.product,
                    0x48 => self.identity.revision >= value,
                    0x49 => self.identity.revision <= value,
                    0x4A => self.identity.serial >= value,
                    _ => self.identity.serial <= value,
                };
                let step = field - 0x46;
                self.identify = if ok && self.identify == step { step + 1 } else { 0 };
                if self.identify == 6 {
                    self.identify = 0;
                    return (Some(Response::IdentifySlave), None);
                }
                (None, None)
            }
            Request::IdentifyNonConfigured => (
                (node_id == UNCONFIGURED && self.state == SlaveState::Waiting)
                    .then_some(Response::IdentifyNonConfiguredSlave),
                None,
            ),
            Request::Fastscan { id, bit_checked, sub, next } => self.fastscan(id, bit_checked, sub, next, node_id),
            // Configuration services outside configuration state are ignored (CiA 305).
            _ => (None, None),
        }
    }

    fn fastscan(&mut self, id: u32, bit: u8, sub: u8, next: u8, node_id: u8) -> (Option<Response>, Option<SlaveEvent>) {
        // Only non-configured devices in waiting state take part.
        let takes_part = match self.state {
            SlaveState::Waiting => node_id == UNCONFIGURED,
            SlaveState::Configuration => self.caps.fastscan_in_configuration && self.entered_unnumbered,
        };
        if !takes_part {
            return (None, None);
        }
        if bit == FASTSCAN_RESET {
            self.fastscan_pos = 0;
            return (Some(Response::IdentifySlave), None);
        }
        if bit > 31 || sub > 3 || sub != self.fastscan_pos {
            return (None, None);
        }
        // The bits from 31 down to the one checked must match.
        if (id ^ self.identity.part(sub)) & (u32::MAX << bit) != 0 {
            return (None, None);
        }
        self.fastscan_pos = next;
        // A complete match of the last part, pointing back to the first: this is the
        // device found, and it goes into configuration state.
        if bit == 0 && next < sub {
            self.state = SlaveState::Configuration;
        }
        (Some(Response::IdentifySlave), None)
    }
}

/// The answer to configuration command `cs`: done, with what the device is to do, or refused
/// (error 1, "not supported").
fn result(cs: u8, ok: bool, event: SlaveEvent) -> (Option<Response>, Option<SlaveEvent>) {
    (Some(Response::Result { cs, error: u8::from(!ok), specific: 0 }), ok.then_some(event))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lss::{error_meaning, switch_selective};

    fn sensor() -> Identity {
        // Seed 001 table 5, with the serial of figure 10's example.
        Identity { vendor: 0x40, product: 0x4378_7800, revision: 0x312E_3031, serial: 0x0950_1234 }
    }

    #[test]
    fn seed_001_figure_10_selective_switch() {
        let frames: Vec<[u8; 8]> = switch_selective(&sensor()).iter().map(Request::encode).collect();
        assert_eq!(
            frames,
            [
                [0x40, 0x40, 0x00, 0x00, 0x00, 0, 0, 0],
                [0x41, 0x00, 0x78, 0x78, 0x43, 0, 0, 0],
                [0x42, 0x31, 0x30, 0x2E, 0x31, 0, 0, 0],
                [0x43, 0x34, 0x12, 0x50, 0x09, 0, 0, 0],
            ]
        );
        let mut slave =
            Slave::new(sensor(), SlaveCaps { store: true, bit_timing: true, fastscan_in_configuration: false });
        let mut answers = vec![];
        for f in &frames {
            answers.push(slave.handle(Request::decode(f).unwrap(), 5).0);
        }
        assert_eq!(answers, [None, None, None, Some(Response::SwitchSelectiveAck)]);
        assert_eq!(Response::SwitchSelectiveAck.encode()[0], 0x44);
        assert_eq!(slave.state, SlaveState::Configuration);
    }

    #[test]
    fn seed_001_figures_11_to_15() {
        assert_eq!(Request::SwitchGlobal { configuration: true }.encode(), [0x04, 0x01, 0, 0, 0, 0, 0, 0]);
        assert_eq!(Request::ConfigureNodeId(5).encode(), [0x11, 5, 0, 0, 0, 0, 0, 0]);
        assert_eq!(Request::ConfigureBitTiming { table: 0, index: 2 }.encode(), [0x13, 0, 2, 0, 0, 0, 0, 0]);
        assert_eq!(Request::ActivateBitTiming { delay_ms: 100 }.encode(), [0x15, 100, 0, 0, 0, 0, 0, 0]);
        assert_eq!(Request::StoreConfiguration.encode(), [0x17, 0, 0, 0, 0, 0, 0, 0]);
        assert_eq!(
            Response::decode(&[0x17, 2, 0, 0, 0, 0, 0, 0]),
            Some(Response::Result { cs: 0x17, error: 2, specific: 0 })
        );
        assert_eq!(error_meaning(0x17, 2), "storage media access error");
        assert_eq!(error_meaning(0x11, 1), "node-id out of range");
        assert_eq!(error_meaning(0x13, 1), "bit timing not supported");
    }
}
