//! LSS master procedures over any `Bus` (CiA 305): the sequences of requests that the
//! `lss` commands are made of, with the waiting each step needs.

use super::{Bus, LssWait};
use crate::canopen::lss::{self, Fastscan, FastscanError, Identity, Request, Response};
use crate::error::{Error, Result};
use std::collections::BTreeSet;
use std::time::Duration;

/// A device `assign` gave a node-id.
pub struct Assigned {
    pub identity: Identity,
    pub node: u8,
    /// Whether "store configuration" succeeded; the reason when not (or not asked).
    pub stored: std::result::Result<(), String>,
}

/// Why `assign` stopped before every device had a node-id.
pub enum AssignFailure {
    Fastscan(FastscanError),
    Refused(Error),
}

pub struct AssignOutcome {
    pub assigned: Vec<Assigned>,
    pub steps: u32,
    pub failure: Option<AssignFailure>,
}

/// LSS through a bus: each confirmed step waits for the first answer, at most the timeout.
pub struct LssMaster<'a> {
    bus: &'a mut dyn Bus,
    timeout: Duration,
}

impl<'a> LssMaster<'a> {
    pub fn new(bus: &'a mut dyn Bus, timeout: Duration) -> LssMaster<'a> {
        LssMaster { bus, timeout }
    }

    pub fn bus(&mut self) -> &mut dyn Bus {
        self.bus
    }

    pub fn send(&mut self, req: Request) -> Result<()> {
        self.bus.lss_exchange(&req.encode(), Duration::ZERO, LssWait::Nothing).map(|_| ())
    }

    pub fn ask(&mut self, req: Request, collect: LssWait) -> Result<Vec<Response>> {
        let answers = self.bus.lss_exchange(&req.encode(), self.timeout, collect)?;
        Ok(answers.iter().filter_map(|a| Response::decode(a)).collect())
    }

    /// Put one device (by identity) or every device (`None`) into configuration state.
    pub fn enter(&mut self, identity: Option<&Identity>) -> Result<()> {
        match identity {
            Some(id) => {
                let [a, b, c, d] = lss::switch_selective(id);
                for r in [a, b, c] {
                    self.send(r)?;
                }
                if !self.ask(d, LssWait::First)?.contains(&Response::SwitchSelectiveAck) {
                    return Err(Error::Timeout(format!(
                        "no LSS device with identity {id} answered the selective switch within {} ms",
                        self.timeout.as_millis()
                    )));
                }
                Ok(())
            }
            None => self.send(Request::SwitchGlobal { configuration: true }),
        }
    }

    pub fn leave(&mut self) -> Result<()> {
        self.send(Request::SwitchGlobal { configuration: false })
    }

    /// A confirmed configuration service; every answer must report success.
    pub fn configure(&mut self, req: Request, what: &str, global: bool) -> Result<usize> {
        let answers = self.ask(req, if global { LssWait::All } else { LssWait::First })?;
        let results: Vec<(u8, u8, u8)> = answers
            .iter()
            .filter_map(|a| match a {
                Response::Result { cs, error, specific } => Some((*cs, *error, *specific)),
                _ => None,
            })
            .collect();
        if results.is_empty() {
            return Err(Error::Timeout(format!(
                "no LSS device answered {what} within {} ms",
                self.timeout.as_millis()
            )));
        }
        if let Some((cs, error, specific)) = results.iter().find(|(_, e, _)| *e != 0) {
            let extra = if *error == 255 { format!(" (specific code {specific})") } else { String::new() };
            return Err(Error::Refused(format!(
                "LSS {what}: error {error}: {}{extra}",
                lss::error_meaning(*cs, *error)
            )));
        }
        Ok(results.len())
    }

    pub fn fastscan(&mut self, step: Duration) -> Result<Result<(Identity, u32), FastscanError>> {
        let mut scan = Fastscan::new();
        while let Some(req) = scan.request() {
            let answered = !self.bus.lss_exchange(&req.encode(), step, LssWait::Settle(step / 5))?.is_empty();
            if let Err(e) = scan.answered(answered) {
                return Ok(Err(e));
            }
        }
        Ok(Ok((scan.found().expect("search over"), scan.steps())))
    }
}

/// How many devices without a node-id answer "identify non-configured remote slave".
pub fn count_unconfigured(bus: &mut dyn Bus, wait: Duration) -> Result<usize> {
    let answers = bus.lss_exchange(&Request::IdentifyNonConfigured.encode(), wait, LssWait::All)?;
    Ok(count_non_configured(&answers))
}

/// Answers "I have no node-id" among these.
pub fn count_non_configured(answers: &[[u8; 8]]) -> usize {
    answers.iter().filter(|a| Response::decode(*a) == Some(Response::IdentifyNonConfiguredSlave)).count()
}

impl LssMaster<'_> {
    /// Give every device without a node-id the next node-id from `start` on that is not in
    /// `used`: fastscan finds one (leaving it in configuration state), it gets its node-id
    /// and, with `store`, keeps it; back in waiting state it boots and leaves the search.
    pub fn assign(
        &mut self,
        start: u8,
        mut used: BTreeSet<u8>,
        step: Duration,
        store: bool,
        each: &mut dyn FnMut(&Assigned),
    ) -> Result<AssignOutcome> {
        let mut out = AssignOutcome { assigned: Vec::new(), steps: 0, failure: None };
        loop {
            let (identity, n) = match self.fastscan(step)? {
                Ok(found) => found,
                Err(FastscanError::NoDevice) => break,
                Err(e) => {
                    out.failure = Some(AssignFailure::Fastscan(e));
                    break;
                }
            };
            out.steps += n;
            let Some(node) = (start..=127).find(|n| !used.contains(n)) else {
                self.leave()?;
                let e = Error::Refused(format!("no free node-id left from {start} to 127 for {identity}"));
                out.failure = Some(AssignFailure::Refused(e));
                break;
            };
            if let Err(e) = self.configure(Request::ConfigureNodeId(node), "set-id", false) {
                self.leave()?;
                out.failure = Some(AssignFailure::Refused(e));
                break;
            }
            let stored = if store {
                self.configure(Request::StoreConfiguration, "store", false).map(|_| ()).map_err(|e| e.to_string())
            } else {
                Err("not asked".to_string())
            };
            self.leave()?;
            used.insert(node);
            let done = Assigned { identity, node, stored };
            each(&done);
            out.assigned.push(done);
        }
        Ok(out)
    }
}
