//! One simulated CANopen device: its object dictionary values, SDO server, NMT state
//! machine, heartbeat producer and node-guarding responder.

use super::cia402_drive::{Drive, FAULT_REACTION_MS};
use super::profiles::{Model, SUPPLY_OFF_OBJECT};
use crate::canopen::cia402::{self, State as DriveState};
use crate::canopen::lss::{self, SlaveEvent, UNCONFIGURED};
use crate::canopen::nmt::{self, Command, ErrorControl};
use crate::canopen::sdo::{self, ObjectAccess, SdoServer};
use crate::canopen::ObjAddr;
use crate::frame::Frame;
use crate::od::ParamClass;
use std::collections::BTreeMap;

pub(crate) mod objects;
pub use objects::ObjectStore;

/// The persistent part of a device, as the state file holds it: only what differs from
/// the model's defaults, so a fresh model version still applies its own defaults.
#[derive(serde::Serialize, serde::Deserialize, Default, Clone, Debug, PartialEq)]
#[serde(default)]
pub struct DeviceState {
    pub node_id: Option<u8>,
    pub nmt: Option<nmt::State>,
    pub values: BTreeMap<String, String>,
    pub stored: BTreeMap<String, String>,
    pub bit_rate: Option<BitRates>,
    pub fault: Fault,
    /// Left in LSS configuration state (by a master that went away without switching it
    /// back): it stays there, as hardware does until reset.
    pub lss_configuration: bool,
    /// Resetting: silent until this ms of bus time, when it sends its boot-up.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub booting_until: Option<u64>,
}

/// CiA 305 bit timing table indices: in use, configured and waiting for activation, and
/// stored by "store configuration".
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
pub struct BitRates {
    pub active: u8,
    pub pending: Option<u8>,
    pub stored: u8,
}

pub struct Device {
    pub model: String,
    node_id: Option<u8>,
    nmt: nmt::State,
    od: ObjectStore,
    sdo: SdoServer,
    block_transfer: bool,
    guarding: bool,
    guard_toggle: bool,
    lss: lss::Slave,
    /// Given a node-id by LSS while it had none: boots once it leaves configuration state.
    boot_pending: bool,
    bit_rate: BitRates,
    /// A linear position sensor whose position and speed move with time.
    moving: bool,
    pad_pdos: bool,
    fault_spec: Option<super::profiles::FaultSpec>,
    /// SYNCs counted per TPDO, for transmission types 1..240.
    sync_counts: [u8; 4],
    fault: Fault,
    /// The bus's time in ms (wall-clock ms when the bus runs on real time), set by the
    /// network before each frame and each run of the device's own events: the device never
    /// reads a clock itself, so a virtual clock runs it as well as the real one.
    clock_ms: u64,
    /// Resetting (a bootloader's reset takes its boot time): silent until this ms, when it
    /// sends its boot-up.
    booting_until: Option<u64>,
    /// How long an NMT reset keeps it silent before its boot-up (0: at once).
    reset_ms: u64,
}

/// A simulated device fault (the sensor's magnet lost), armed by writing the time to it.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Fault {
    /// Wall-clock ms at which it strikes.
    pub at: Option<u64>,
    pub active: bool,
    /// A drive's fault reaction ends (fault reaction active → fault) at this wall-clock ms.
    pub reaction_until: Option<u64>,
}

/// The simulator's own object: "simulated fault in N ms" (0 clears an active one).
pub const FAULT_OBJECT: ObjAddr = ObjAddr::new(0x5FFE, 0);

/// One TPDO as its communication and mapping parameters describe it.
struct Tpdo {
    n: usize,
    cob: u16,
    valid: bool,
    rtr: bool,
    transmission: u8,
    event_ms: u16,
    map: Vec<(ObjAddr, u8)>,
}

impl Tpdo {
    /// Valid and event-driven (transmission type 254/255).
    fn on_event(&self) -> bool {
        self.valid && self.transmission >= 254
    }
}

impl Device {
    pub fn new(model: Model, node_id: Option<u8>, bit_rate: u8) -> Device {
        let mut od = ObjectStore {
            dict: model.dict,
            node_id: node_id.unwrap_or(0),
            ignored_writes: model.ignored_writes,
            drive: model.drive.map(Drive::new),
            ..ObjectStore::default()
        };
        // An EPOS2 on a bus was set up for it: 0x2001, which it reads at power-on, saved with
        // the code of the bit rate its controller runs at. Left at its default (1 Mbit/s) on a
        // 500 kbit/s bus, it told a reader a rate the device could not be talking at.
        if let Some(code) = crate::epos2::objects::bit_rate_code(bit_rate).filter(|_| model.epos2_bit_rate) {
            od.stored.insert(crate::epos2::objects::CAN_BIT_RATE, code.to_le_bytes().to_vec());
        }
        od.reload(None);
        od.refresh_statusword();
        od.dirty = false;
        let [vendor, product, revision, serial] = ObjAddr::IDENTITY_PARTS.map(|a| od.u32_value(a).unwrap_or(0));
        let identity = lss::Identity { vendor, product, revision, serial };
        Device {
            lss: lss::Slave::new(identity, model.lss),
            boot_pending: false,
            bit_rate: BitRates { active: bit_rate, pending: None, stored: bit_rate },
            moving: model.moving,
            pad_pdos: model.pad_pdos,
            fault_spec: model.fault,
            sync_counts: [0; 4],
            clock_ms: 0,
            booting_until: None,
            reset_ms: 0,
            fault: Fault::default(),
            model: model.key,
            node_id,
            nmt: nmt::State::PreOperational,
            od,
            sdo: SdoServer::new(model.block_transfer),
            block_transfer: model.block_transfer,
            guarding: model.guarding,
            guard_toggle: false,
        }
    }

    pub fn node_id(&self) -> Option<u8> {
        self.node_id
    }

    pub fn nmt_state(&self) -> nmt::State {
        self.nmt
    }

    pub fn objects(&self) -> &ObjectStore {
        &self.od
    }

    /// Direct access to the dictionary, as the device's own firmware has it.
    pub(crate) fn objects_mut(&mut self) -> &mut ObjectStore {
        &mut self.od
    }

    /// True once since the last call if anything persistent changed.
    pub(crate) fn take_dirty(&mut self) -> bool {
        std::mem::take(&mut self.od.dirty)
    }

    pub fn identity(&self) -> lss::Identity {
        self.lss.identity
    }

    /// The bit rate (CiA 305 table index) the device's controller runs at.
    pub fn bit_rate(&self) -> u8 {
        self.bit_rate.active
    }

    /// A write by the device's own serial interface (the EPOS2 gateway), with what a write
    /// by SDO sets off: a simulated fault armed or repaired. The frames that would follow
    /// on CAN (EMCY, TPDO) are not sent: the serial master cannot see them.
    pub fn write_local(&mut self, addr: ObjAddr, data: &[u8]) -> Result<(), u32> {
        let fault_before = self.od.value(FAULT_OBJECT).map(|v| v.to_vec());
        self.od.write(addr, data)?;
        if self.od.value(FAULT_OBJECT).map(|v| v.to_vec()) != fault_before {
            self.arm_fault();
        }
        Ok(())
    }

    /// Forget any SDO transfer in progress (an injected abort ended it).
    pub(crate) fn reset_sdo(&mut self) {
        self.sdo = SdoServer::new(self.block_transfer);
    }

    /// An NMT reset keeps it silent this long before its boot-up, as a real device's
    /// restart takes (0: at once).
    pub(crate) fn with_reset_time(mut self, ms: u64) -> Device {
        self.reset_ms = ms;
        self
    }

    /// The bus's time now, in ms.
    pub(crate) fn set_clock(&mut self, ms: u64) {
        self.clock_ms = ms;
    }

    /// React to one frame on the bus; returns the frames this device sends in answer.
    pub(crate) fn on_frame(&mut self, f: &Frame) -> Vec<Frame> {
        // Resetting: it hears nothing until its boot-up.
        if self.booting_until.is_some_and(|t| self.clock_ms < t) {
            return vec![];
        }
        if f.id() == lss::MASTER_COB && !f.is_remote() {
            return self.lss_frame(f);
        }
        let Some(id) = self.node_id else { return vec![] };
        if let Some((cmd, target)) = Command::parse(f) {
            return if target == 0 || target == id { self.nmt_command(cmd, id) } else { vec![] };
        }
        if f.id() == sdo::request_cob(id) && !f.is_remote() {
            // CiA 301: no SDO in Stopped.
            if self.nmt == nmt::State::Stopped || f.len() != 8 {
                return vec![];
            }
            if super::bootloader::is_bootloader(&self.od) {
                let (answers, reboot) =
                    super::bootloader::on_request(&mut self.sdo, &mut self.od, f.data(), self.nmt, self.clock_ms);
                if reboot {
                    // The answer (if it gives one first) goes out; the boot-up comes when
                    // the reset is over (`events`).
                    self.nmt = nmt::State::PreOperational;
                    self.sdo = SdoServer::new(self.block_transfer);
                    self.booting_until = Some(self.clock_ms + super::bootloader::boot_ms(&self.od));
                }
                return sdo_frames(id, &answers);
            }
            let fault_before = self.od.value(FAULT_OBJECT).map(|v| v.to_vec());
            let (state_before, status_before) = (self.od.drive_state(), self.od.u16_value(cia402::STATUSWORD));
            let mut out = sdo_frames(id, &self.sdo.handle(f.data(), &mut self.od));
            if self.od.value(FAULT_OBJECT).map(|v| v.to_vec()) != fault_before {
                out.extend(self.arm_fault());
            }
            if state_before == Some(DriveState::Fault) && self.od.drive_state() != state_before {
                // Seed 003 §2.8: an EMCY also when the drive turns to a status of no error.
                out.extend(self.emcy(0x0000, 0, [0; 5]));
            }
            if self.od.u16_value(cia402::STATUSWORD) != status_before {
                out.extend(self.statusword_tpdos());
            }
            return out;
        }
        let operational = self.nmt == nmt::State::Operational;
        if operational
            && !f.is_remote()
            && Some(f.id() as u32) == self.od.u32_value(ObjAddr::new(0x1005, 0)).map(|c| c & 0x7FF)
        {
            return self.on_sync();
        }
        if operational && f.is_remote() {
            if let Some(t) = self.tpdos().into_iter().find(|t| t.valid && t.rtr && t.cob == f.id()) {
                return vec![self.tpdo_frame(&t)];
            }
        }
        // CiA 301: a node that produces heartbeats does not take part in node guarding.
        let guarded = self.guarding && self.heartbeat_ms().is_none();
        if f.is_remote() && f.id() == nmt::error_control_cob(id) && guarded {
            let answer = ErrorControl::State { state: self.nmt, toggle: self.guard_toggle };
            self.guard_toggle = !self.guard_toggle;
            return vec![answer.frame(id)];
        }
        vec![]
    }

    fn lss_frame(&mut self, f: &Frame) -> Vec<Frame> {
        let Some(req) = lss::Request::decode(f.data()) else { return vec![] };
        let before = self.lss.state;
        let (answer, event) = self.lss.handle(req, self.node_id.unwrap_or(UNCONFIGURED));
        self.od.dirty |= self.lss.state != before;
        let mut out: Vec<Frame> = answer.iter().map(|a| Frame::new(lss::SLAVE_COB, &a.encode())).collect();
        self.od.dirty |= matches!(event, Some(SlaveEvent::BitTiming(_) | SlaveEvent::Store));
        match event {
            Some(SlaveEvent::NodeId(id)) => {
                let new = (id != UNCONFIGURED).then_some(id);
                self.boot_pending |= self.node_id.is_none() && new.is_some();
                self.node_id = new;
                self.od.renumber(new.unwrap_or(0));
            }
            Some(SlaveEvent::BitTiming(index)) => self.bit_rate.pending = Some(index),
            // The switch delay is not simulated: the new rate holds from the next frame on.
            Some(SlaveEvent::Activate { .. }) => {
                if let Some(p) = self.bit_rate.pending.take() {
                    self.bit_rate.active = p;
                    self.od.dirty = true;
                }
            }
            Some(SlaveEvent::Store) => self.bit_rate.stored = self.bit_rate.pending.unwrap_or(self.bit_rate.active),
            Some(SlaveEvent::BackToWaiting) => {
                if let (true, Some(id)) = (self.boot_pending, self.node_id) {
                    self.boot_pending = false;
                    self.nmt = nmt::State::PreOperational;
                    out.push(ErrorControl::BootUp.frame(id));
                }
            }
            None => {}
        }
        out
    }

    fn nmt_command(&mut self, cmd: Command, id: u8) -> Vec<Frame> {
        let before = self.nmt;
        self.nmt = self.nmt.after(cmd);
        self.sync_drive();
        match cmd {
            Command::ResetNode | Command::ResetCommunication => {
                self.od.reload(if cmd == Command::ResetNode { None } else { Some(ParamClass::Communication) });
                self.sync_drive();
                self.sdo = SdoServer::new(self.block_transfer);
                self.guard_toggle = false;
                if self.reset_ms > 0 {
                    // Silent while it boots; the boot-up comes with its own events.
                    self.booting_until = Some(self.clock_ms + self.reset_ms);
                    return vec![];
                }
                vec![ErrorControl::BootUp.frame(id)]
            }
            _ => {
                self.od.dirty |= before != self.nmt;
                vec![]
            }
        }
    }

    /// Tell the drive model what the device around it knows (NMT state, fault cause,
    /// supply) and show it in the statusword. After a reset a drive whose fault is still
    /// there comes up in fault.
    fn sync_drive(&mut self) {
        let operational = self.nmt == nmt::State::Operational;
        let (fault, supply_off) = (self.fault.active, self.od.value(SUPPLY_OFF_OBJECT) == Some(&[1]));
        let Some(d) = &mut self.od.drive else { return };
        d.operational = operational;
        d.fault_cause = fault;
        d.supply_off = supply_off;
        if fault && self.fault.reaction_until.is_none() && self.od.drive_state() != Some(DriveState::Fault) {
            self.od.set_drive_state(DriveState::Fault);
        }
        self.od.refresh_statusword();
    }

    /// The event-driven TPDOs (transmission type 254/255) that carry the statusword,
    /// sent when it changes while operational.
    fn statusword_tpdos(&mut self) -> Vec<Frame> {
        let operational = self.nmt == nmt::State::Operational;
        let carries = |t: &Tpdo| t.on_event() && t.map.iter().any(|(a, _)| *a == cia402::STATUSWORD);
        let carrying = self.tpdos().into_iter().filter(|t| operational && carries(t));
        carrying.map(|t| self.tpdo_frame(&t)).collect()
    }

    fn tpdos(&self) -> Vec<Tpdo> {
        (0..4u16)
            .filter_map(|n| {
                let cob = self.od.u32_value(ObjAddr::new(0x1800 + n, 1))?;
                let count = self.od.u8_value(ObjAddr::new(0x1A00 + n, 0)).unwrap_or(0);
                let entries = (1..=count).filter_map(|s| self.od.u32_value(ObjAddr::new(0x1A00 + n, s)));
                let map = entries.map(crate::canopen::pdo::mapping_entry).collect();
                Some(Tpdo {
                    n: n as usize,
                    cob: (cob & 0x7FF) as u16,
                    valid: cob & 0x8000_0000 == 0,
                    rtr: cob & 0x4000_0000 == 0,
                    transmission: self.od.u8_value(ObjAddr::new(0x1800 + n, 2)).unwrap_or(255),
                    event_ms: self.od.u16_value(ObjAddr::new(0x1800 + n, 5)).unwrap_or(0),
                    map,
                })
            })
            .collect()
    }

    fn tpdo_frame(&mut self, t: &Tpdo) -> Frame {
        if self.moving {
            // The sensor's measurements at this moment (zero while its magnet is lost).
            let (position, speed) =
                if self.fault.active { (0, 0) } else { super::profiles::sensor_motion(self.clock_ms) };
            self.od.values.insert(ObjAddr::new(0x6020, 1), position.to_le_bytes().to_vec());
            self.od.values.insert(ObjAddr::new(0x6030, 1), speed.to_le_bytes().to_vec());
        }
        let value = |addr| self.od.value(addr).map(|v| v.to_vec()).unwrap_or_default();
        let fields: Vec<(u8, Vec<u8>)> = t.map.iter().map(|(addr, bits)| (*bits, value(*addr))).collect();
        let mut payload = crate::canopen::pdo::encode(&fields);
        if self.pad_pdos {
            payload.resize(8, 0);
        }
        Frame::new(t.cob, &payload)
    }

    /// Transmission types 0..240: the PDO goes out at every n-th SYNC (0 counts as 1).
    fn on_sync(&mut self) -> Vec<Frame> {
        let mut out = Vec::new();
        for t in self.tpdos().into_iter().filter(|t| t.valid && t.transmission <= 240) {
            self.sync_counts[t.n] += 1;
            if self.sync_counts[t.n] >= t.transmission.max(1) {
                self.sync_counts[t.n] = 0;
                out.push(self.tpdo_frame(&t));
            }
        }
        out
    }

    fn emcy(&self, code: u16, register: u8, vendor: [u8; 5]) -> Option<Frame> {
        let cob = self.od.u32_value(ObjAddr::new(0x1014, 0)).filter(|c| c & 0x8000_0000 == 0)?;
        let e = crate::canopen::emcy::Emergency { code, register, vendor };
        Some(Frame::new((cob & 0x7FF) as u16, e.frame(0).data()))
    }

    /// The fault object was written: arm the fault, or clear an active one.
    fn arm_fault(&mut self) -> Vec<Frame> {
        let ms = self.od.u16_value(FAULT_OBJECT).unwrap_or(0);
        self.od.dirty = true;
        self.fault.at = (ms > 0).then(|| self.clock_ms + ms as u64);
        // Armed, or cleared with none active: nothing to report.
        if ms > 0 || !std::mem::take(&mut self.fault.active) {
            return vec![];
        }
        if self.od.drive.is_some() {
            // A drive's fault stays latched until a fault reset, which reports it.
            self.sync_drive();
            return vec![];
        }
        // Seed 001 §8: repaired errors are reported with "error reset".
        self.od.values.insert(ObjAddr::new(0x1001, 0), vec![0]);
        self.emcy(0x0000, 0, [0; 5]).into_iter().collect()
    }

    /// The fault strikes: the model's EMCY, recorded in the error register and (where the
    /// device keeps one) the 0x1003 history, newest first; some devices then leave
    /// Operational for Pre-operational (CiA 301 error behaviour).
    fn strike(&mut self) -> Vec<Frame> {
        self.fault = Fault { at: None, active: true, reaction_until: None };
        let Some(spec) = self.fault_spec else { return vec![] };
        self.od.values.insert(ObjAddr::new(0x1001, 0), vec![spec.register]);
        let mut out = Vec::new();
        if self.od.drive.is_some() {
            // CiA 402 transition 13: from any state into fault reaction active, then fault.
            self.fault.reaction_until = Some(self.clock_ms + FAULT_REACTION_MS);
            self.sync_drive();
            self.od.set_drive_state(DriveState::FaultReactionActive);
            if let Some(status) = self.od.u32_value(ObjAddr::new(0x1002, 0)) {
                // The SERS's error class (P11) in 0x1002's low word: the EMCY's bytes 4-5.
                let class1 = u16::from_le_bytes([spec.vendor[1], spec.vendor[2]]) as u32;
                self.od.values.insert(ObjAddr::new(0x1002, 0), (status & 0xFFFF_0000 | class1).to_le_bytes().to_vec());
            }
            out.extend(self.statusword_tpdos());
        }
        let e = crate::canopen::emcy::Emergency { code: spec.code, register: spec.register, vendor: spec.vendor };
        let slots = self.od.dict.object_entries(0x1003).filter(|e| e.addr.sub > 0).count() as u8;
        if slots > 0 {
            for sub in (2..=slots).rev() {
                let older = self.od.values[&ObjAddr::new(0x1003, sub - 1)].clone();
                self.od.values.insert(ObjAddr::new(0x1003, sub), older);
            }
            self.od.values.insert(ObjAddr::new(0x1003, 1), e.history_entry().to_le_bytes().to_vec());
            let count = self.od.u8_value(ObjAddr::new(0x1003, 0)).unwrap_or(0);
            self.od.values.insert(ObjAddr::new(0x1003, 0), vec![(count + 1).min(slots)]);
        }
        self.od.dirty = true;
        if spec.to_pre_operational && self.nmt == nmt::State::Operational {
            self.nmt = nmt::State::PreOperational;
        }
        out.splice(0..0, self.emcy(spec.code, spec.register, spec.vendor));
        out
    }

    /// The next time this device sends something by itself, after `now` (wall-clock ms).
    pub(crate) fn next_event(&self, now: u64) -> Option<u64> {
        let id = self.node_id? as u64;
        let timed = self.timed_tpdos().into_iter().map(|t| t.event_ms as u64);
        let beats = self.heartbeat_ms().into_iter().chain(timed).map(|p| super::last_beat(p, id, now) + p);
        beats.chain(self.fault.at).chain(self.fault.reaction_until).chain(self.booting_until).min()
    }

    /// The TPDOs sent by their event timer: event-driven ones with a timer, while operational.
    fn timed_tpdos(&self) -> Vec<Tpdo> {
        let operational = self.nmt == nmt::State::Operational;
        self.tpdos().into_iter().filter(|t| operational && t.on_event() && t.event_ms > 0).collect()
    }

    /// What this device sends by itself in `(after, upto]`, each frame with the ms it was
    /// due: the device keeps its own clock, so a master that polled late still gets every
    /// beat at its time (the latest [`MAX_BACKLOG`] of each kind, as a controller's receive
    /// queue would keep).
    pub fn events(&mut self, after: u64, upto: u64) -> Vec<(u64, Frame)> {
        let Some(id) = self.node_id else { return vec![] };
        let mut out = Vec::new();
        // Resetting: nothing until the boot-up, which ends it.
        let after = match self.booting_until {
            Some(until) if until > upto => return out,
            Some(until) => {
                self.booting_until = None;
                out.push((until.max(after), ErrorControl::BootUp.frame(id)));
                after.max(until)
            }
            None => after,
        };
        // A fault due while no invocation ran the network strikes now.
        if let Some(at) = self.fault.at.filter(|t| *t <= upto) {
            let due = at.clamp(after, upto);
            out.extend(self.strike().into_iter().map(|f| (due, f)));
        }
        if let Some(until) = self.fault.reaction_until.filter(|t| *t <= upto) {
            self.fault.reaction_until = None;
            self.od.set_drive_state(DriveState::Fault);
            let due = until.clamp(after, upto);
            out.extend(self.statusword_tpdos().into_iter().map(|f| (due, f)));
        }
        if let Some(p) = self.heartbeat_ms() {
            let beat = ErrorControl::State { state: self.nmt, toggle: false }.frame(id);
            out.extend(due_times(p, id as u64, after, upto).map(|t| (t, beat)));
        }
        for t in self.timed_tpdos() {
            for due in due_times(t.event_ms as u64, id as u64, after, upto) {
                out.push((due, self.tpdo_frame(&t)));
            }
        }
        out
    }

    pub fn heartbeat_ms(&self) -> Option<u64> {
        self.node_id?;
        self.od.u16_value(ObjAddr::new(0x1017, 0)).filter(|t| *t > 0).map(u64::from)
    }

    pub fn snapshot(&self) -> DeviceState {
        // A reset would bring back the stored value, else the default: save what differs.
        let baseline = |a: &ObjAddr| self.od.stored.get(a).cloned().unwrap_or_else(|| self.od.default_of(*a));
        let entry =
            |(a, v): (&ObjAddr, &Vec<u8>)| (format!("{:04X}:{}", a.index, a.sub), crate::canopen::types::hex(v));
        DeviceState {
            node_id: self.node_id,
            nmt: Some(self.nmt),
            values: self.od.values.iter().filter(|(a, v)| **v != baseline(a)).map(entry).collect(),
            stored: self.od.stored.iter().map(entry).collect(),
            bit_rate: Some(self.bit_rate),
            fault: self.fault,
            lss_configuration: self.lss.state == lss::SlaveState::Configuration,
            booting_until: self.booting_until,
        }
    }

    /// Apply a saved state; entries that no longer fit the model are dropped.
    pub fn restore(&mut self, s: &DeviceState) {
        // The values follow the node-id (the reload below).
        self.node_id = s.node_id;
        self.od.node_id = s.node_id.unwrap_or(0);
        self.nmt = s.nmt.unwrap_or(nmt::State::PreOperational);
        self.bit_rate = s.bit_rate.unwrap_or(self.bit_rate);
        self.fault = s.fault;
        self.booting_until = s.booting_until;
        if s.lss_configuration {
            self.lss.state = lss::SlaveState::Configuration;
        }
        let parse = |m: &BTreeMap<String, String>| -> BTreeMap<ObjAddr, Vec<u8>> {
            m.iter()
                .filter_map(|(k, v)| Some((k.parse::<ObjAddr>().ok()?, crate::canopen::types::parse_hex(v).ok()?)))
                .filter(|(a, _)| self.od.dict.get(*a).is_some())
                .collect()
        };
        self.od.stored = parse(&s.stored);
        let values = parse(&s.values);
        self.od.reload(None);
        self.od.values.extend(values);
        self.sync_drive();
        self.od.dirty = false;
    }
}

/// An SDO server's answers as frames from node `id`.
pub(crate) fn sdo_frames(id: u8, answers: &[[u8; 8]]) -> Vec<Frame> {
    answers.iter().map(|p| Frame::new(sdo::response_cob(id), p)).collect()
}

/// The most frames of one kind a device has waiting after a master stopped polling.
pub(crate) const MAX_BACKLOG: u64 = 64;

/// The times in `(after, upto]` a producer with this period sends (the latest
/// [`MAX_BACKLOG`]), oldest first.
fn due_times(period: u64, node: u64, after: u64, upto: u64) -> impl Iterator<Item = u64> {
    let last = super::last_beat(period, node, upto);
    let count = if last > after { ((last - after - 1) / period + 1).min(MAX_BACKLOG) } else { 0 };
    (0..count).rev().map(move |k| last - k * period)
}

#[cfg(test)]
mod tests;
