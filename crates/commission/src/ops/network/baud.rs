//! `network set-baud`: the whole bus switched to a new bit rate over LSS.

use crate::bus::lss::LssMaster;
use crate::bus::{Bus, LssWait};
use crate::cancel::Cancel;
use crate::canopen::lss::Request;
use crate::error::{Error, ProjectProblem, Result};
use crate::od::cpj;
use crate::ops::lss::LssTally;
use crate::ops::progress::Progress;
use serde::Serialize;
use std::path::PathBuf;
use std::time::Duration;

use super::project::{probe, read_dcf, Loaded};
use crate::ops::unmet::{Shortfall, Unmet};

/// How to switch a network's bit rate.
#[derive(Clone, Debug)]
pub struct SetBaudOptions {
    /// How long to collect the devices' LSS answers.
    pub timeout: Duration,
    /// How long the probes before and after the switch wait for answers.
    pub window: Duration,
    /// The new bit rate: its index in the CiA 305 table.
    pub index: u8,
    /// CiA 305 switch delay: the devices wait this long, switch, and wait as long again
    /// before they transmit.
    pub delay_ms: u16,
    /// Make the devices keep the new rate across power cycles ("store configuration").
    pub store: bool,
    /// Activate even when some device refused the new rate (it is left behind).
    pub force: bool,
    /// Set when the user asks to stop: checked before each LSS step; nothing is switched
    /// once it is set before the activation.
    pub interrupted: Cancel,
}

/// One node expected to follow the switch.
#[derive(Debug, Serialize)]
pub struct NodeFollowed {
    /// The node-id.
    pub node: u8,
    /// Its name in the project (`NodeXName`, else its DCF's product name); empty without a
    /// project.
    pub name: String,
    /// Whether it answered the probe before the switch.
    pub before: bool,
    /// Whether it answers at the new rate; `None` where the link could not look (it stays
    /// at the old rate), or the switch was not activated.
    pub after: Option<bool>,
}

/// Why a network-wide bit-rate switch stopped before "activate bit timing" (every device is
/// then back in LSS waiting state at the old rate).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NotActivated {
    /// No device took the new rate.
    NoneTook,
    /// `count` devices refused the new rate, and the switch was not forced (a forced one
    /// leaves them behind at the old rate).
    Refused {
        /// How many refused.
        count: usize,
    },
    /// The user asked to stop before the activation.
    Interrupted,
}

/// What a network-wide bit-rate switch did.
#[derive(Debug, Default, Serialize)]
pub struct BaudSwitched {
    /// The bus, as it describes itself.
    pub bus: String,
    /// The new rate (`250k`).
    pub rate: String,
    /// Where the expected nodes come from: the project file, or the probe before the switch.
    pub expected_from: String,
    /// "configure bit timing", sent to every device in configuration state.
    pub configured: LssTally,
    /// "store configuration", when asked.
    pub stored: Option<LssTally>,
    /// Whether "activate bit timing" was sent.
    pub activated: bool,
    /// Why it was not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_activated: Option<NotActivated>,
    /// How long the devices wait before switching, in ms (the LSS switch delay).
    pub delay_ms: u16,
    /// Whether the link switched with the devices (the simulated bus does; a CAN interface
    /// or an EPOS2 must be switched by its owner).
    pub bus_followed: bool,
    /// Each node expected to follow, by node-id.
    pub nodes: Vec<NodeFollowed>,
    /// Nodes answering at the new rate that were not expected.
    pub unexpected: Vec<u8>,
    /// Devices without a node-id that answered LSS before and after the switch.
    pub unconfigured_before: usize,
    /// After the switch; none where the link could not look.
    pub unconfigured_after: Option<usize>,
    /// Whether every expected node is confirmed at the new rate.
    pub ok: bool,
    /// Why it is not (its exit code is the command's).
    #[serde(skip)]
    pub failure: Option<Shortfall>,
}

impl BaudSwitched {
    /// The command's outcome: Ok when every expected node is confirmed at the new rate, else why not.
    pub fn outcome(self) -> Result<(), Shortfall> {
        self.failure.map_or(Ok(()), Err)
    }
}

/// Switch every device on the bus to a new bit rate (CiA 305, LSS global): all into
/// configuration state, "configure bit timing", "store configuration" when asked, then
/// "activate bit timing" with the switch delay; the devices go quiet, switch after the
/// delay and wait as long again, during which nothing is sent. Where the link switched with
/// them, the devices are sent back to waiting state and the bus is probed again: every
/// expected node (the project's, else those found before) that does not answer at the new
/// rate is reported. A device refusing the rate stops the switch before anything is
/// activated, unless `force`.
pub fn set_baud(
    bus: &mut dyn Bus,
    project: Option<&Loaded>,
    o: &SetBaudOptions,
    progress: &mut dyn Progress,
) -> Result<BaudSwitched> {
    let stop = || o.interrupted.is_cancelled();
    if stop() {
        return Err(Error::Interrupted);
    }
    let rate = crate::canopen::lss::bit_rate_name(o.index);
    let before = probe(bus, o.window, progress)?;
    let unconfigured_before = crate::bus::lss::count_unconfigured(bus, o.window)?;
    let (expected, expected_from): (Vec<(u8, String)>, String) = match project {
        Some(p) => (p.nodes.iter().map(|l| (l.node, l.name.clone())).collect(), p.file.display().to_string()),
        None => (before.keys().map(|n| (*n, String::new())).collect(), "the probe before the switch".into()),
    };
    let followed = |(node, name): &(u8, String)| NodeFollowed {
        node: *node,
        name: name.clone(),
        before: before.contains_key(node),
        after: None,
    };
    let nodes = expected.iter().map(followed).collect();
    let mut report = BaudSwitched {
        bus: bus.describe(),
        rate: rate.clone(),
        expected_from,
        delay_ms: o.delay_ms,
        nodes,
        unconfigured_before,
        ..BaudSwitched::default()
    };
    let not_switched = |report: &mut BaudSwitched, e: Error, why: NotActivated| {
        report.not_activated = Some(why);
        report.failure = Some(e.into());
    };

    let mut m = LssMaster::new(bus, o.timeout);
    m.enter(None)?;
    let configure = Request::ConfigureBitTiming { table: 0, index: o.index };
    let answers = m.ask(configure, LssWait::All).or_else(|e| m.leave().and(Err(e)))?;
    report.configured = LssTally::of(&answers, "configure bit timing");
    let refused = report.configured.first_refusal.take();
    if report.configured.confirmed == 0 {
        m.leave()?;
        let silence =
            || Error::NoLssAnswer { request: "configure bit timing".into(), identity: None, waited: o.timeout };
        not_switched(&mut report, refused.unwrap_or_else(silence), NotActivated::NoneTook);
        return Ok(report);
    }
    if let Some(e) = refused.filter(|_| !o.force) {
        m.leave()?;
        let why = NotActivated::Refused { count: report.configured.refused.len() };
        not_switched(&mut report, e, why);
        return Ok(report);
    }
    if stop() {
        m.leave()?;
        not_switched(&mut report, Error::Interrupted, NotActivated::Interrupted);
        return Ok(report);
    }
    if o.store {
        let answers = m.ask(Request::StoreConfiguration, LssWait::All).or_else(|e| m.leave().and(Err(e)))?;
        report.stored = Some(LssTally::of(&answers, "store configuration"));
        // Those that stored it boot at the new rate from now on: the running bus must
        // follow them, so an interruption here no longer stops the switch.
    }
    m.send(Request::ActivateBitTiming { delay_ms: o.delay_ms })?;
    report.activated = true;
    // CiA 305: each device switches after the delay and is silent until the delay has
    // passed a second time; the master sends nothing in between either.
    let link = m.bus();
    link.sleep_until(link.now() + Duration::from_millis(2 * u64::from(o.delay_ms)))?;
    report.bus_followed = m.bus().follows_bit_rate_switch();
    if !report.bus_followed {
        // Only a link at the new rate reaches the devices again; they stay in
        // configuration state until an LSS command does.
        return Ok(report);
    }
    m.leave()?;
    let after = probe(bus, o.window, progress)?;
    report.unconfigured_after = Some(crate::bus::lss::count_unconfigured(bus, o.window)?);
    for n in &mut report.nodes {
        n.after = Some(after.contains_key(&n.node));
    }
    let behind: Vec<u8> = report.nodes.iter().filter(|n| n.after == Some(false)).map(|n| n.node).collect();
    report.unexpected = after.keys().filter(|n| !expected.iter().any(|(e, _)| e == *n)).copied().collect();
    report.ok = behind.is_empty();
    if !behind.is_empty() {
        report.failure = Some(Unmet::NotFollowed { rate, nodes: behind }.into());
    } else if stop() {
        report.failure = Some(Error::Interrupted.into());
    }
    Ok(report)
}

/// The project's DCFs with `[DeviceComissioning] Baudrate` set to `kbit`: each file's new
/// bytes, all made before any is written (the caller writes each atomically).
pub(crate) fn with_bit_rate(loaded: &Loaded, kbit: u32, nodes: &[u8]) -> Result<Vec<(PathBuf, Vec<u8>)>> {
    let mut out = Vec::new();
    for listed in loaded.nodes.iter().filter(|l| nodes.contains(&l.node)) {
        let Some(path) = loaded.project.dcf_path(&loaded.file, listed.node) else { continue };
        // Read here and rewritten in place by the caller.
        let (name, bytes) = read_dcf(&loaded.file, &path, None)?;
        let mut c = cpj::read_commissioning(&bytes, &name)
            .map_err(|e| Error::ProjectUnusable(Box::new(ProjectProblem::Commissioning(e))))?;
        c.baudrate_kbit = Some(kbit);
        let new = cpj::with_commissioning(&bytes, &c).map_err(|e| Error::NotWritable(e.into()))?;
        out.push((path, new));
    }
    Ok(out)
}

/// Set `[DeviceComissioning] Baudrate` to `kbit` in the DCFs of `nodes`: every file made
/// before any is written, so that a DCF that cannot be read changes none. The files
/// written, in order.
pub(crate) fn update_bit_rate(loaded: &Loaded, kbit: u32, nodes: &[u8]) -> Result<Vec<PathBuf>> {
    let files = with_bit_rate(loaded, kbit, nodes)?.into_iter();
    files.map(|(path, bytes)| crate::atomic::write_atomic(&path, &bytes).map(|_| path)).collect()
}

/// What `network set-baud --update-project` did to the project's DCFs.
#[derive(Debug, Default)]
pub struct DcfsFollowed {
    /// The DCFs now at the new rate, in order: those of the nodes heard at it.
    pub updated: Vec<PathBuf>,
    /// The nodes listed in the project that were not heard at the new rate: their DCFs say
    /// the rate they have.
    pub left: Vec<u8>,
}

/// After `network set-baud` to the bit rate `index` (`switched`): when the devices were
/// switched, the DCFs of the nodes heard at the new rate follow (`update_bit_rate`), and
/// only those: a DCF never says a rate its device does not have. Otherwise none is touched.
pub fn follow_switch(loaded: &Loaded, switched: &BaudSwitched, index: u8) -> Result<DcfsFollowed> {
    let kbit = crate::canopen::lss::BIT_TIMINGS.get(index as usize).and_then(|(_, kbit)| *kbit);
    let Some(kbit) = kbit.filter(|_| switched.activated) else { return Ok(DcfsFollowed::default()) };
    let heard: Vec<u8> = switched.nodes.iter().filter(|n| n.after == Some(true)).map(|n| n.node).collect();
    let left = loaded.nodes.iter().map(|l| l.node).filter(|n| !heard.contains(n)).collect();
    Ok(DcfsFollowed { updated: update_bit_rate(loaded, kbit, &heard)?, left })
}
