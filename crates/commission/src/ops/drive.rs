//! CiA 402 drives: their state, flags, mode and errors ([`status`]), watching the state
//! change (`Watch`), and walking the state machine to a goal with the controlword,
//! confirming each transition in the statusword ([`walk`]). Power state only: nothing here
//! writes a target or starts a motion.

use super::node::{optional, Node};
use super::sdo_options::sized;
use crate::bus::Bus;
use crate::cancel::Cancel;
use crate::canopen::cia402::{self, Command, Goal, State, Step};
use crate::canopen::{emcy, pdo, ObjAddr};
use crate::error::{DriveStop, Error, Result};
use serde::Serialize;
use std::time::{Duration, Instant};

/// How often the statusword is read while a transition is awaited (by SDO).
const POLL: Duration = Duration::from_millis(10);
/// More steps than any path has: a drive that keeps changing state ends the walk.
const MAX_STEPS: usize = 8;

/// How long to wait.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// For each SDO answer.
    pub timeout: Duration,
    /// For each transition to show in the statusword.
    pub wait: Duration,
}

/// One statusword bit.
#[derive(Debug, Serialize, Clone, PartialEq)]
#[non_exhaustive]
pub struct Flag {
    /// Its bit number in the statusword (0 to 15).
    pub bit: u8,
    /// What CiA 402 calls it.
    pub name: &'static str,
    /// Whether the bit is set.
    pub set: bool,
}

/// The mode of operation the drive shows.
#[derive(Debug, Serialize, Clone, PartialEq)]
#[non_exhaustive]
pub struct Mode {
    /// The mode's code (CiA 402, 0x6060/0x6061).
    pub value: i8,
    /// Its name; none for a code CiA 402 does not define (manufacturer modes are negative).
    pub name: Option<&'static str>,
    /// The object it was read from: 0x6061 (display), or 0x6060 on a drive without it.
    #[serde(serialize_with = "super::values::as_text")]
    pub from: ObjAddr,
}

pub use super::node::LoggedError;

/// A drive's state as its objects show it.
#[derive(Debug, Serialize, Clone, PartialEq)]
#[non_exhaustive]
pub struct Status {
    /// The drive's node-id.
    pub node: u8,
    /// Its device type (0x1000).
    pub device_type: u32,
    /// The statusword (0x6041) as read.
    pub statusword: u16,
    /// None when the statusword matches no CiA 402 state.
    pub state: Option<State>,
    /// Every bit of the statusword, by name.
    pub flags: Vec<Flag>,
    /// None when the drive has neither 0x6061 nor 0x6060.
    pub mode: Option<Mode>,
    /// The error register (0x1001).
    pub error_register: u8,
    /// The bits set in the error register, by name.
    pub error_register_bits: Vec<&'static str>,
    /// Newest first; None when the drive has no 0x1003.
    #[serde(serialize_with = "drive_errors")]
    pub errors: Option<Vec<LoggedError>>,
}

impl Status {
    /// The CiA 402 state in words, from the statusword.
    pub fn state_name(&self) -> String {
        state_text(self.state, self.statusword)
    }
}

/// The state's name, or what the statusword says when it codes none.
pub fn state_text(state: Option<State>, statusword: u16) -> String {
    state.map_or_else(|| format!("no CiA 402 state (statusword 0x{statusword:04X})"), |s| s.name().to_string())
}

/// An unsigned object of the drive.
fn read<T: TryFrom<u32>>(bus: &mut dyn Bus, node: u8, addr: ObjAddr, timeout: Duration) -> Result<T> {
    Node::new(bus, node, timeout).read(addr)
}

/// The node's device type, if it is a CiA 402 drive; [`Error::NotADrive`] otherwise.
pub(crate) fn check_drive(bus: &mut dyn Bus, node: u8, timeout: Duration) -> Result<u32> {
    let device_type: u32 = read(bus, node, ObjAddr::DEVICE_TYPE, timeout)?;
    if !cia402::is_drive(device_type) {
        return Err(Error::NotADrive { node, device_type });
    }
    Ok(device_type)
}

/// The statusword and the state it codes.
pub fn statusword(bus: &mut dyn Bus, node: u8, timeout: Duration) -> Result<(u16, Option<State>)> {
    let word = read::<u16>(bus, node, cia402::STATUSWORD, timeout)?;
    Ok((word, State::from_statusword(word)))
}

fn mode(bus: &mut dyn Bus, node: u8, timeout: Duration) -> Result<Option<Mode>> {
    for from in [cia402::MODES_OF_OPERATION_DISPLAY, cia402::MODES_OF_OPERATION] {
        if let Some(v) = optional(read::<u8>(bus, node, from, timeout))? {
            let value = v as i8;
            return Ok(Some(Mode { value, name: cia402::mode_name(value), from }));
        }
    }
    Ok(None)
}

/// `drive status` shows each entry as its raw value, its code (a number) and meaning.
fn drive_errors<S: serde::Serializer>(v: &Option<Vec<LoggedError>>, s: S) -> std::result::Result<S::Ok, S::Error> {
    #[derive(Serialize)]
    struct Entry {
        raw: u32,
        code: u16,
        meaning: &'static str,
    }
    let entries: Option<Vec<Entry>> =
        v.as_ref().map(|v| v.iter().map(|e| Entry { raw: e.raw, code: e.code, meaning: e.meaning }).collect());
    entries.serialize(s)
}

/// Everything `drive status` shows.
pub fn status(bus: &mut dyn Bus, node: u8, timeout: Duration) -> Result<Status> {
    let device_type = check_drive(bus, node, timeout)?;
    let (word, state) = statusword(bus, node, timeout)?;
    let mode = mode(bus, node, timeout)?;
    let register = read::<u8>(bus, node, ObjAddr::ERROR_REGISTER, timeout)?;
    // The error history, newest first (sub 1 is the newest, CiA 301 §7.5.2.5), each code
    // named as `errors` names it: the device type picks the table (CiA 402 before CiA 301's
    // classes), since no device manual lists a drive.
    let origin = emcy::Origin { device_type: Some(device_type), vendor: None, product: None, name: None };
    let errors = Node::new(bus, node, timeout).error_history(&origin)?.map(|field| field.entries);
    Ok(Status {
        node,
        device_type,
        statusword: word,
        state,
        flags: flags(word),
        mode,
        error_register: register,
        error_register_bits: emcy::register_bits(register),
        errors,
    })
}

pub(crate) fn flags(statusword: u16) -> Vec<Flag> {
    cia402::flags(statusword).map(|(bit, name, set)| Flag { bit, name, set }).collect()
}

/// One command of a walk and what the drive showed after it.
#[derive(Debug, Serialize, Clone, PartialEq)]
#[non_exhaustive]
pub struct Transition {
    /// The controlword command sent.
    pub command: Command,
    /// The controlword written (0x6040).
    pub controlword: u16,
    /// The state the drive was in before it.
    pub from: State,
    /// The state the command leads to.
    pub expected: State,
    /// What the statusword showed last (None: no CiA 402 state).
    pub reached: Option<State>,
    /// The last statusword read.
    pub statusword: u16,
    /// The expected state was reached.
    pub confirmed: bool,
}

/// Where a walk ended and why.
#[derive(Debug, Serialize, Clone, PartialEq)]
#[non_exhaustive]
pub struct Walk {
    /// The drive's node-id.
    pub node: u8,
    /// The state asked for.
    pub goal: Goal,
    /// The state it was in first; none when the statusword showed no CiA 402 state.
    pub start: Option<State>,
    /// Each command sent, in order.
    pub transitions: Vec<Transition>,
    /// The state it ended in; none when the statusword shows no CiA 402 state.
    pub state: Option<State>,
    /// The last statusword read.
    pub statusword: u16,
    /// The goal's state was reached and confirmed.
    pub done: bool,
    /// Why it stopped before the goal.
    pub stopped: Option<DriveStop>,
    /// Interrupted by the user between steps.
    pub interrupted: bool,
}

impl Walk {
    /// The walk as the command's outcome: Ok when done, else the typed reason (exit 3/4).
    pub fn outcome(&self) -> Result<()> {
        match self.stopped {
            _ if self.interrupted => Err(Error::Interrupted),
            None => Ok(()),
            Some(why) => {
                let state = state_text(self.state, self.statusword);
                Err(Error::DriveStopped { node: self.node, goal: self.goal.name(), state, why })
            }
        }
    }
}

/// Read the statusword until the state it codes is `settled` or the wait is over.
fn await_settled(
    bus: &mut dyn Bus,
    node: u8,
    o: &Options,
    settled: impl Fn(Option<State>) -> bool,
) -> Result<(u16, Option<State>)> {
    let end = bus.now() + o.wait;
    loop {
        let (word, state) = statusword(bus, node, o.timeout)?;
        if settled(state) || bus.now() >= end {
            return Ok((word, state));
        }
        bus.sleep_until(end.min(bus.now() + POLL))?;
    }
}

/// Why a transition to `expected` did not show.
fn refusal(expected: State, statusword: u16, state: Option<State>) -> DriveStop {
    match state {
        Some(State::Fault | State::FaultReactionActive) => DriveStop::FaultPresent,
        None => DriveStop::NoState,
        _ if matches!(expected, State::SwitchedOn | State::OperationEnabled)
            && statusword & cia402::sw::VOLTAGE_ENABLED == 0 =>
        {
            DriveStop::VoltageMissing
        }
        _ => DriveStop::TransitionRefused,
    }
}

/// Walk node `node` towards `goal`, one confirmed transition at a time. The report says
/// where it ended; a drive that stops answering mid-way ends it with [`DriveStop::NoAnswer`]
/// (a node that does not answer at all is an error, as are non-drives).
pub fn walk(bus: &mut dyn Bus, node: u8, goal: Goal, o: &Options, interrupt: &Cancel) -> Result<Walk> {
    check_drive(bus, node, o.timeout)?;
    let (word, state) = statusword(bus, node, o.timeout)?;
    let mut w = Walk {
        node,
        goal,
        start: state,
        transitions: Vec::new(),
        state,
        statusword: word,
        done: false,
        stopped: None,
        interrupted: false,
    };
    match walk_steps(bus, &mut w, o, interrupt) {
        Ok(stopped) => w.stopped = stopped,
        Err(e) if e.is_timeout() => {
            w.stopped = Some(DriveStop::NoAnswer);
            // The answer lost may be a controlword's that the drive acted on: the state
            // from before it is no longer known. Read back once, never write again.
            match statusword(bus, node, o.timeout) {
                Ok((word, state)) => (w.statusword, w.state) = (word, state),
                Err(e) if e.is_timeout() => w.state = None,
                Err(e) => return Err(e),
            }
        }
        Err(e) => return Err(e),
    }
    Ok(w)
}

/// The steps of a walk, each recorded in `w`; why it stopped before the goal, if it did.
fn walk_steps(bus: &mut dyn Bus, w: &mut Walk, o: &Options, interrupt: &Cancel) -> Result<Option<DriveStop>> {
    let node = w.node;
    for _ in 0..MAX_STEPS {
        if interrupt.is_cancelled() {
            w.interrupted = true;
            return Ok(None);
        }
        let Some(state) = w.state else { return Ok(Some(DriveStop::NoState)) };
        match cia402::next_step(state, w.goal) {
            Step::Done => {
                w.done = true;
                return Ok(None);
            }
            Step::Blocked(cia402::Blocker::FaultPresent) => return Ok(Some(DriveStop::FaultPresent)),
            Step::Wait => {
                // A state the drive leaves by itself: wait until it does.
                let (word, next) = await_settled(bus, node, o, |s| s != Some(state))?;
                (w.statusword, w.state) = (word, next);
                if next == Some(state) {
                    return Ok(Some(refusal(state, word, next)));
                }
            }
            Step::Send(command, expected) => {
                if command == Command::FaultReset {
                    // The reset acts on bit 7's rising edge: clear it first if it is set.
                    let current = optional(read::<u16>(bus, node, cia402::CONTROLWORD, o.timeout))?.unwrap_or(0);
                    if current & cia402::cw::FAULT_RESET != 0 {
                        write_controlword(bus, node, current & !cia402::cw::FAULT_RESET, o.timeout)?;
                    }
                }
                let controlword = command.controlword();
                write_controlword(bus, node, controlword, o.timeout)?;
                // Until it shows `expected` (or a fault: the walk ends there); out of a fault,
                // fault is where the drive starts: it waits.
                let recovering = state == State::Fault;
                let settled = |s: Option<State>| s.is_some_and(|s| s == expected || (s == State::Fault && !recovering));
                let (word, reached) = await_settled(bus, node, o, settled)?;
                let confirmed = reached == Some(expected);
                w.transitions.push(Transition {
                    command,
                    controlword,
                    from: state,
                    expected,
                    reached,
                    statusword: word,
                    confirmed,
                });
                (w.statusword, w.state) = (word, reached);
                if !confirmed {
                    let remains = command == Command::FaultReset && reached == Some(State::Fault);
                    return Ok(Some(if remains { DriveStop::FaultRemains } else { refusal(expected, word, reached) }));
                }
            }
        }
    }
    Ok(Some(DriveStop::TransitionRefused))
}

fn write_controlword(bus: &mut dyn Bus, node: u8, word: u16, timeout: Duration) -> Result<()> {
    bus.sdo_download(node, cia402::CONTROLWORD, &word.to_le_bytes(), &sized(timeout, Some(2)))
}

/// One change seen by `Watch`.
#[derive(Debug, Serialize, Clone, PartialEq)]
#[non_exhaustive]
pub struct Change {
    /// The drive's node-id.
    pub node: u8,
    /// Unix time in ms.
    pub time_ms: u64,
    /// The statusword (0x6041) as it changed.
    pub statusword: u16,
    /// The state it codes; none when it codes no CiA 402 state.
    pub state: Option<State>,
    /// `tpdo` or `sdo`.
    pub source: &'static str,
}

/// Where a watch gets the statusword.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// From this TPDO (COB-ID, and the statusword's bit offset and the PDO's length).
    Tpdo {
        /// The TPDO's COB-ID.
        cob_id: u16,
        /// The statusword's bit offset in the PDO.
        offset: usize,
        /// The PDO's mapping.
        layout: pdo::Layout,
    },
    /// By SDO, at this interval.
    Sdo(Duration),
}

/// Whether the node says it is operational (its heartbeat, else node guarding).
fn operational(bus: &mut dyn Bus, node: u8, timeout: Duration) -> bool {
    let o = super::nmt::StateOptions { listen: Duration::from_millis(300), timeout };
    super::nmt::state(bus, node, &o).is_ok_and(|s| s.state == crate::canopen::nmt::State::Operational)
}

/// The statusword as it changes, until the caller stops asking.
pub struct Watch {
    node: u8,
    source: Source,
    last: Option<u16>,
    timeout: Duration,
}

impl Watch {
    /// Watch by the TPDO that carries the statusword when the bus sees the node's traffic
    /// and the node is operational (only then does it send its TPDOs); by SDO polling every
    /// `interval` otherwise, or when its NMT state cannot be learned.
    pub fn new(bus: &mut dyn Bus, node: u8, interval: Duration, timeout: Duration) -> Result<Watch> {
        let mut source = Source::Sdo(interval);
        if bus.sees_traffic() && operational(bus, node, timeout) {
            if let Some((offset, layout)) = statusword_tpdo(bus, node, timeout)? {
                source = Source::Tpdo { cob_id: layout.cob_id, offset, layout };
            }
        }
        Ok(Watch { node, source, last: None, timeout })
    }

    /// Where the statusword comes from.
    pub fn source(&self) -> &Source {
        &self.source
    }

    /// The next change of the statusword; None once `cancel` is set. It waits in short
    /// rounds, so that an interruption is seen within one.
    pub fn next_until(&mut self, bus: &mut dyn Bus, cancel: &Cancel) -> Result<Option<Change>> {
        while !cancel.is_cancelled() {
            let until = bus.now() + Duration::from_millis(100);
            if let Some(change) = self.next(bus, until)? {
                return Ok(Some(change));
            }
        }
        Ok(None)
    }

    /// The next change of the statusword; None when `until` passed first (the caller checks
    /// for an interruption and asks again).
    pub fn next(&mut self, bus: &mut dyn Bus, until: Instant) -> Result<Option<Change>> {
        loop {
            let word = match &self.source {
                Source::Sdo(_) => read::<u16>(bus, self.node, cia402::STATUSWORD, self.timeout)?,
                Source::Tpdo { cob_id, offset, layout } => {
                    let Some(f) = bus.recv_frame(until)? else { return Ok(None) };
                    if f.id() != *cob_id || f.is_remote() || f.len() * 8 < offset + 16 || layout.bits() > f.len() * 8 {
                        continue;
                    }
                    bits16(f.data(), *offset)
                }
            };
            if Some(word) == self.last {
                // Polled: again after the interval, unless `until` comes first.
                if let Source::Sdo(interval) = self.source {
                    bus.sleep_until(until.min(bus.now() + interval))?;
                    if bus.now() >= until {
                        return Ok(None);
                    }
                }
                continue;
            }
            self.last = Some(word);
            let source = if matches!(self.source, Source::Tpdo { .. }) { "tpdo" } else { "sdo" };
            return Ok(Some(Change {
                node: self.node,
                time_ms: crate::sim::wall_ms(),
                statusword: word,
                state: State::from_statusword(word),
                source,
            }));
        }
    }
}

/// The first valid TPDO (1..4) whose mapping carries the statusword, read from the node, with
/// the statusword's bit offset in it.
fn statusword_tpdo(bus: &mut dyn Bus, node: u8, timeout: Duration) -> Result<Option<(usize, pdo::Layout)>> {
    let dict = crate::od::Dictionary::default();
    let layouts =
        match super::pdo::read_layouts(bus, node, &dict, &[1, 2, 3, 4], true, timeout, &mut super::progress::Silent) {
            Ok(l) => l,
            Err(Error::NoValidTpdo { .. }) => return Ok(None),
            Err(e) => return Err(e),
        };
    Ok(layouts.into_iter().find_map(|(_, l)| Some((statusword_offset(&l)?, l))))
}

/// The bit offset of a 16-bit statusword in a PDO layout.
fn statusword_offset(layout: &pdo::Layout) -> Option<usize> {
    let mut offset = 0;
    for f in &layout.fields {
        if f.addr == cia402::STATUSWORD && f.bits == 16 {
            return Some(offset);
        }
        offset += f.bits as usize;
    }
    None
}

/// 16 bits at a bit offset, little-endian (CiA 301 PDO packing).
fn bits16(data: &[u8], offset: usize) -> u16 {
    (0..16).fold(0u16, |acc, i| {
        let bit = offset + i;
        let set = data.get(bit / 8).is_some_and(|b| b >> (bit % 8) & 1 == 1);
        acc | (set as u16) << i
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_statusword_is_found_at_its_bit_offset_in_a_pdo() {
        // Seed 003's TPDO: statusword, position (32), limit switches and inputs (16).
        assert_eq!(bits16(&[0x37, 0x06, 1, 2, 3, 4, 5, 6], 0), 0x0637);
        assert_eq!(bits16(&[1, 2, 3, 4, 0x37, 0x06], 32), 0x0637);
        assert_eq!(bits16(&[0x7F, 0x63, 0xF0], 4), 0x0637);
    }

    #[test]
    fn a_refused_switch_on_without_voltage_is_voltage_missing() {
        assert_eq!(refusal(State::SwitchedOn, 0x0221, Some(State::ReadyToSwitchOn)), DriveStop::VoltageMissing);
        assert_eq!(refusal(State::SwitchedOn, 0x0231, Some(State::ReadyToSwitchOn)), DriveStop::TransitionRefused);
        assert_eq!(
            refusal(State::ReadyToSwitchOn, 0x0240, Some(State::SwitchOnDisabled)),
            DriveStop::TransitionRefused
        );
        assert_eq!(refusal(State::SwitchOnDisabled, 0x0208, Some(State::Fault)), DriveStop::FaultPresent);
        assert_eq!(refusal(State::SwitchOnDisabled, 0x0001, None), DriveStop::NoState);
    }

    /// The drive takes a controlword but its answer is lost (a gateway under load drops
    /// it): the walk ends with no answer, and the state it reports is the drive's, read
    /// back, not the one from before the write. (Found by tests/dst/, seed 0x5eed053d.)
    #[test]
    fn a_lost_answer_to_a_controlword_leaves_no_stale_state_in_the_report() {
        use crate::sim::{SimConfig, SimLink};
        // Answers of the drive: 0x1000, statusword, controlword (shutdown), statusword,
        // controlword (switch on) — the fifth is lost, and so are the answers to the two
        // retries of that write (a single loss is retried: see the next test).
        let mut config = SimConfig::instant().virtual_time(true);
        for n in 5..=7 {
            config = config.fault(format!("1:drop@{n}").parse().unwrap());
        }
        let mut bus = crate::bus::Master::new(SimLink::with_config(config).on_virtual_time(0), "sim".into());
        let o = Options { timeout: Duration::from_millis(100), wait: Duration::from_millis(500) };
        let w = walk(&mut bus, 1, Goal::Enable, &o, &Cancel::new()).unwrap();
        assert_eq!(w.stopped, Some(DriveStop::NoAnswer), "{w:?}");
        let drive = bus.link_mut().network().devices().iter().find(|d| d.node_id() == Some(1)).unwrap();
        assert_eq!(w.state, drive.objects().drive_state(), "{w:?}");
        assert_eq!(w.state, Some(State::SwitchedOn), "the write took effect");
    }

    /// One lost answer to a controlword (a plain value: the same word twice is one command)
    /// is retried, not waited out: the walk goes on to the goal.
    #[test]
    fn one_lost_answer_to_a_controlword_is_retried() {
        use crate::sim::{SimConfig, SimLink};
        let config = SimConfig::instant().fault("1:drop@5".parse().unwrap()).virtual_time(true);
        let mut bus = crate::bus::Master::new(SimLink::with_config(config).on_virtual_time(0), "sim".into());
        let o = Options { timeout: Duration::from_millis(100), wait: Duration::from_millis(500) };
        let w = walk(&mut bus, 1, Goal::Enable, &o, &Cancel::new()).unwrap();
        assert_eq!(w.stopped, None, "{w:?}");
        assert_eq!(w.state, Some(State::OperationEnabled), "{w:?}");
    }

    /// The watch decides by the node's NMT state: a pre-operational drive sends no TPDO, so
    /// it is read by SDO; once started, its statusword comes from the TPDO that maps it.
    #[test]
    fn a_watch_takes_the_tpdo_only_of_an_operational_node() {
        use crate::canopen::nmt::Command as Nmt;
        use crate::sim::{SimConfig, SimLink};
        let config = SimConfig::instant().virtual_time(true);
        let mut bus = crate::bus::Master::new(SimLink::with_config(config).on_virtual_time(0), "sim".into());
        let (interval, timeout) = (Duration::from_millis(200), Duration::from_millis(100));
        let watch = Watch::new(&mut bus, 1, interval, timeout).unwrap();
        assert!(matches!(watch.source(), Source::Sdo(i) if *i == interval), "{:?}", watch.source());
        bus.nmt(Nmt::Start, 1).unwrap();
        let watch = Watch::new(&mut bus, 1, interval, timeout).unwrap();
        assert!(matches!(watch.source(), Source::Tpdo { .. }), "{:?}", watch.source());
    }
}
