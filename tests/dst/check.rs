//! The invariants: each run's report against the devices as the run left them.

use super::*;

/// The network as the run left it, without its faults and on the instant profile: what
/// the devices hold, read back by a master nothing disturbs.
pub fn clean_copy(sim: &SimLink) -> Master<SimLink> {
    let mut state = sim.network().snapshot();
    if let Some(c) = state.config.as_mut() {
        c.faults.clear();
        c.profile = Profile::Instant;
    }
    let net = canctl::sim::Network::from_state(&state);
    Master::new(SimLink::of(net).on_virtual_time(1_700_000_000_000), "sim".into())
}

/// The devices as the network holds them.
pub struct Devices {
    /// By serial: node-id, LSS configuration state, NMT state.
    pub all: Vec<DeviceView>,
}

pub struct DeviceView {
    pub identity: Identity,
    pub node: Option<u8>,
    pub nmt: nmt::State,
    pub drive: Option<DriveState>,
    pub bit_rate: u8,
    /// Left in LSS configuration state.
    pub configuring: bool,
    /// The objects the procedures read and write.
    pub values: BTreeMap<ObjAddr, Vec<u8>>,
}

pub const WATCHED: [ObjAddr; 4] = [ObjAddr::new(0x1000, 0), ObjAddr::new(0x1008, 0), ObjAddr::new(0x1017, 0), DOMAIN];

impl Devices {
    pub fn of(sim: &SimLink) -> Devices {
        let all = sim
            .network()
            .devices()
            .iter()
            .map(|d| DeviceView {
                identity: d.identity(),
                node: d.node_id(),
                nmt: d.nmt_state(),
                drive: d.objects().drive_state(),
                bit_rate: d.bit_rate(),
                configuring: d.snapshot().lss_configuration,
                values: WATCHED.iter().filter_map(|a| Some((*a, d.objects().value(*a)?.to_vec()))).collect(),
            })
            .collect();
        Devices { all }
    }

    pub fn node(&self, node: u8) -> Option<&DeviceView> {
        self.all.iter().find(|d| d.node == Some(node))
    }

    pub fn value(&self, node: u8, addr: ObjAddr) -> Option<&[u8]> {
        self.node(node)?.values.get(&addr).map(|v| v.as_slice())
    }
}

/// The invariants, for one run.
pub fn check(
    s: &Scenario,
    result: &Result<Report>,
    before: &Devices,
    after: &Devices,
    sim: &SimLink,
    frames: &[Taped],
) -> std::result::Result<(), String> {
    // No node-id held twice, whatever happened.
    let mut held = BTreeMap::new();
    for d in &after.all {
        if let Some(n) = d.node {
            if let Some(other) = held.insert(n, d.identity) {
                return Err(format!("node-id {n} held by {other} and {}", d.identity));
            }
        }
    }
    // Every LSS procedure sends the devices back to waiting, however it ended; a device
    // left at another bit rate (set-baud --force) cannot hear it, and one that missed every
    // switch back is what the error says. A muted device that missed the switch back is
    // beyond any master: only its answer to an inquiry could show where it stays.
    let rate = sim.network().bit_rate();
    let said_so = matches!(
        result,
        Err(Error::LssLeftInConfiguration { .. } | Error::LssStillConfiguring { .. })
            | Ok(Report::Assigned(_, _, _, true))
    );
    if let Some(d) = after.all.iter().find(|d| d.configuring && d.bit_rate == rate && !said_so && !muted(s, d)) {
        return Err(format!("{} left in LSS configuration state", d.identity));
    }
    let Ok(report) = result else { return Ok(()) };
    match report {
        Report::Read(node, addr, data) => {
            let held = after.value(*node, *addr);
            if held != Some(data.as_slice()) {
                return Err(format!(
                    "read {} bytes from node {node} {addr}, the device holds {:?}",
                    data.len(),
                    held.map(|v| v.len())
                ));
            }
        }
        Report::Wrote(node, addr, data) => {
            if after.value(*node, *addr) != Some(data.as_slice()) {
                return Err(format!("wrote node {node} {addr}, the device does not hold it"));
            }
        }
        Report::Scanned(nodes, interrupted, lost, clashes) => {
            // The simulated network never has two devices on one node-id: a clash is said
            // only where a fault makes one device's answers look like two (one answering on
            // another's COB-ID, a duplicated or damaged answer).
            if let Some(n) = clashes.iter().find(|n| !looks_doubled(s, **n)) {
                return Err(format!("scan said node-id {n} is used by two devices, one device holds it"));
            }
            // Frames said lost were lost, damaged or held back past the window: never said
            // of a node that merely answers slowly.
            if let Some(n) = lost.iter().find(|n| !loses_frames(s, **n)) {
                return Err(format!("scan said node {n} lost frames, nothing of it was lost or held back"));
            }
            for (node, serial) in nodes {
                let Some(d) = after.node(*node) else {
                    // Stopped before the nodes found were asked alone (ops::answers_elsewhere),
                    // a scan may still list the id a device answers on in place of its own.
                    if *interrupted && answered_for(s).contains(node) {
                        continue;
                    }
                    return Err(format!("scan reported node {node}, no device has it"));
                };
                if serial.is_some_and(|s| s != d.identity.serial) {
                    return Err(format!(
                        "scan reported node {node} with serial {serial:?}, the device's is {}",
                        d.identity.serial
                    ));
                }
            }
            // Under loss, delay, damaged answers too: a scan that ends (exit 0) lists every
            // node that is there, unless canctl never heard of it: asked in each of the
            // probe's rounds, nothing of it came back (no answer, no heartbeat).
            if !interrupted {
                let got: Vec<u8> = nodes.iter().map(|(n, _)| *n).collect();
                for n in after.all.iter().filter_map(|d| d.node).filter(|n| !got.contains(n)) {
                    let probe = [0x40, 0x00, 0x10, 0x00];
                    let asked = frames
                        .iter()
                        .filter(|f| f.sent && f.id == 0x600 + u16::from(n) && f.data[..4] == probe)
                        .count();
                    let heard = frames.iter().any(|f| {
                        !f.sent
                            && ((f.id == 0x580 + u16::from(n) && f.data.len() == 8)
                                || (f.id == 0x700 + u16::from(n) && f.data.len() == 1))
                    });
                    if heard || asked < SCAN_PROBE_ROUNDS {
                        return Err(format!(
                            "scan found {got:?} and ended ok without node {n}, which is there (asked {asked} time(s), heard: {heard})"
                        ));
                    }
                }
            }
        }
        Report::Found(id) => {
            let waiting = before.all.iter().any(|d| d.node.is_none() && d.identity == *id);
            if !waiting {
                return Err(format!("fastscan found {id}, no device without a node-id has it"));
            }
        }
        Report::Assigned(given, complete, maybe, _) => {
            // A device muted by its fault cannot be told from one that is not there.
            let rate = sim.network().bit_rate();
            let seen = |d: &&DeviceView| d.bit_rate == rate && !muted(s, d);
            if let Some(d) = after.all.iter().filter(seen).find(|d| *complete && d.node.is_none()) {
                return Err(format!("assign ended as complete, {} still has no node-id", d.identity));
            }
            for (id, node) in given {
                let holder = after.all.iter().find(|d| d.identity == *id);
                if holder.and_then(|d| d.node) != Some(*node) {
                    return Err(format!("reported {id} -> node {node}, the device holds {:?}", holder.map(|d| d.node)));
                }
            }
            // Every device numbered is in the report.
            for d in &after.all {
                let was = before.all.iter().find(|b| b.identity == d.identity).and_then(|b| b.node);
                let said = given.iter().chain(maybe).any(|(id, n)| *id == d.identity && d.node == Some(*n));
                if was.is_none() && d.node.is_some() && !said {
                    return Err(format!("{} took node {:?}, the report does not say so", d.identity, d.node));
                }
            }
        }
        Report::Booted(nodes) => {
            for n in nodes {
                if after.node(*n).map(|d| d.nmt) != Some(nmt::State::PreOperational) {
                    return Err(format!("reset confirmed for node {n}, which is not pre-operational"));
                }
            }
        }
        Report::Applied(node, written) => {
            let diff =
                ops::config::diff(&mut clean_copy(sim), *node, sensor_dcf(), TIMEOUT).map_err(|e| e.to_string())?;
            if let Some(d) = diff.differences.iter().find(|d| written.contains(&d.object)) {
                return Err(format!(
                    "applied {} to node {node}: the device holds {}, the DCF {}",
                    d.object, d.device, d.file
                ));
            }
        }
        Report::Project(nodes) => {
            let loaded = machine();
            let o = ops::network::CheckOptions {
                timeout: TIMEOUT,
                window: Duration::from_millis(300),
                jobs: 1,
                state: None,
            };
            let checked =
                ops::network::check(&mut clean_copy(sim), loaded, &o, &mut Silent).map_err(|e| e.to_string())?;
            for (node, ok) in nodes.iter().filter(|(_, ok)| *ok) {
                let c = checked.nodes.iter().find(|c| c.node == *node);
                if !c.is_some_and(|c| c.checks.iter().all(|v| v.ok)) {
                    return Err(format!("node {node} reported brought to its DCF ({ok}), a check says {c:?}"));
                }
            }
        }
        Report::Nodes(nodes) => {
            for (n, ok) in nodes {
                // A node the last scan saw and that is gone now is reported, not healthy.
                let Some(d) = after.node(*n) else {
                    // A device answering on this id's COB-ID that fell silent before it could
                    // be asked alone (ops::answers_elsewhere): the bus showed an answer on the
                    // id and nothing could show whose; said not healthy, never healthy.
                    if !*ok && answered_for_then_silent(s).contains(n) {
                        continue;
                    }
                    if *ok || !last_seen(s).contains(n) {
                        return Err(format!("reported node {n} (healthy: {ok}), no device has it"));
                    }
                    continue;
                };
                if *ok && !serves_sdo(s, d) {
                    return Err(format!("node {n} reported healthy, its device serves no SDO ({:?})", d.nmt));
                }
            }
            // Every node the last scan saw is judged: never left out of a pass.
            if let Some(n) = last_seen(s).iter().find(|n| !nodes.iter().any(|(r, _)| r == *n)) {
                return Err(format!("health left out node {n}, which the last scan saw"));
            }
        }
        Report::Doctor(ok) => {
            let rate = sim.network().bit_rate();
            let silent =
                NODES.iter().find(|n| !after.node(**n).is_some_and(|d| d.bit_rate == rate && serves_sdo(s, d)));
            if let (true, Some(n)) = (ok, silent) {
                return Err(format!("doctor found nothing wrong, node {n} of the last scan serves no SDO"));
            }
            if !ok && s.clean() {
                return Err("doctor found something wrong on a clean network".into());
            }
        }
        Report::DriveState(node, state, done) => {
            let held = after.node(*node).and_then(|d| d.drive);
            if state.is_some() && *state != held {
                return Err(format!("reported drive state {state:?}, the drive is in {held:?}"));
            }
            if *done && held != Some(DriveState::OperationEnabled) {
                return Err(format!("reported enabled, the drive is in {held:?}"));
            }
        }
        Report::Followed(rate, nodes) => {
            for (node, followed) in nodes {
                let held = after.node(*node).map(|d| d.bit_rate);
                if *followed == Some(true) && held != Some(*rate) {
                    return Err(format!("node {node} reported at the new rate, the device is at {held:?}"));
                }
            }
        }
        Report::State(node, state) => {
            // What the node says from the command on, never a beat from before it.
            // (A device that rebooted since may be pre-operational again: only a device left
            // stopped is held to it.)
            let stopped = after.node(*node).is_some_and(|d| d.nmt == nmt::State::Stopped);
            if stopped && *state != nmt::State::Stopped {
                return Err(format!("node {node} reported {state:?} after the stop, the device is stopped"));
            }
        }
        Report::Nothing => {}
    }
    Ok(())
}

/// Whether a fault of the scenario makes this device fall silent for good.
pub fn muted(s: &Scenario, d: &DeviceView) -> bool {
    s.config.faults.iter().any(|f| {
        let spec = f.to_string();
        let (target, kind) = spec.split_once(':').unwrap_or_default();
        let node = target.parse::<u8>().ok();
        kind.starts_with("mute")
            && (target == format!("sensor-{:08x}", d.identity.serial) || node.is_some_and(|n| d.node == Some(n)))
    })
}

/// Whether a fault of the scenario loses, damages or holds back frames to or from this
/// node-id (a device with that node-id, or one that had none yet, or a device that answers
/// on this node-id's COB-ID in place of its own).
pub fn loses_frames(s: &Scenario, node: u8) -> bool {
    let speaks_for = |target: u8| target == node || wrong_cobs(s).contains(&(target, node));
    s.config.faults.iter().any(|f| {
        let spec = f.to_string();
        let (target, kind) = spec.split_once(':').unwrap_or_default();
        let ours = target.parse::<u8>().map_or(target.starts_with("sensor-"), speaks_for);
        ours && ["drop", "miss", "mute", "delay", "corrupt", "short-dlc"].iter().any(|k| kind.starts_with(k))
    })
}

/// Whether a fault of the scenario makes the answers on this node-id look like two devices':
/// another device answering on its COB-ID, or its own answers duplicated or damaged.
pub fn looks_doubled(s: &Scenario, node: u8) -> bool {
    answered_for(s).contains(&node)
        || s.config.faults.iter().any(|f| {
            let spec = f.to_string();
            let (target, kind) = spec.split_once(':').unwrap_or_default();
            let ours = target.parse::<u8>().map_or(target.starts_with("sensor-"), |t| t == node);
            ours && ["duplicate", "corrupt"].iter().any(|k| kind.starts_with(k))
        })
}

/// The nodes the last scan of the bus saw: none on a first look.
pub fn last_seen(s: &Scenario) -> &'static [u8] {
    match s.first_look {
        true => &[],
        false => &NODES,
    }
}

/// The node-ids a device with a wrong-cob fault answers on in place of its own.
pub fn answered_for(s: &Scenario) -> Vec<u8> {
    wrong_cobs(s).into_iter().map(|(_, claimed)| claimed).collect()
}

/// The ids a device answers on in place of its own, where that device also falls silent
/// (muted or off from some frame on, or rebooting): silent, it cannot be asked alone to show
/// the answers were its.
pub fn answered_for_then_silent(s: &Scenario) -> Vec<u8> {
    let silent = |device: u8| {
        s.config.faults.iter().map(|f| f.to_string()).any(|f| {
            f.strip_prefix(&format!("{device}:"))
                .is_some_and(|kind| ["mute", "off", "reboot"].iter().any(|k| kind.starts_with(k)))
        })
    };
    wrong_cobs(s).into_iter().filter(|(device, _)| silent(*device)).map(|(_, claimed)| claimed).collect()
}

/// Each device with a wrong-cob fault: its node-id, and the node-id it answers on.
fn wrong_cobs(s: &Scenario) -> Vec<(u8, u8)> {
    let claimed = |f: &canctl::sim::FaultSpec| {
        let spec = f.to_string();
        let (target, kind) = spec.split_once(':')?;
        let target = target.parse::<u8>().ok()?;
        match kind.strip_prefix("wrong-cob")? {
            "" => Some((target, target + 1)),
            id => u16::from_str_radix(id.strip_prefix("=0x")?, 16).ok().map(|c| (target, (c & 0x7F) as u8)),
        }
    };
    s.config.faults.iter().filter_map(claimed).collect()
}

/// Whether the device answers SDO at all: not stopped, not muted or off from the start.
pub fn serves_sdo(s: &Scenario, d: &DeviceView) -> bool {
    let node = d.node.unwrap_or(0);
    let silent =
        s.config.faults.iter().any(|f| [format!("{node}:off"), format!("{node}:mute")].contains(&f.to_string()));
    d.nmt != nmt::State::Stopped && !silent
}
