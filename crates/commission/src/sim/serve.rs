//! The simulated network as a service: start its saved state afresh, or put its devices
//! behind a real CAN interface, a simulated slcan adapter or a simulated EPOS2 on a
//! pseudo-terminal, or a socketcand server on TCP, and answer there until the process is
//! stopped.

use super::serial_fault::{Fault, FaultKind};
use super::state::{default_path, StateFile};
use super::SimConfig;
use crate::bus::FrameLog;
use crate::canopen::lss::bit_rate_name;
use crate::connect::BusAddr;
use crate::epos2::Framing;
use crate::error::{Error, Result};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The state file of the sim bus `bus` names (`sim` or `sim:PATH`), or the default one
/// when none is named; `None` when `bus` names another kind of bus.
pub fn state_path(bus: Option<&str>) -> Result<Option<PathBuf>> {
    Ok(match bus.filter(|b| !b.is_empty()).map(str::parse::<BusAddr>).transpose()? {
        None | Some(BusAddr::Sim { state: None }) => Some(default_path()),
        Some(BusAddr::Sim { state: Some(p) }) => Some(p),
        Some(_) => None,
    })
}

/// A network started afresh.
#[derive(Debug, Serialize)]
pub struct Reset {
    /// Always true.
    pub reset: bool,
    /// The state file written.
    pub state_file: String,
    /// The device profile of the network.
    pub profile: String,
    /// The random seed the network was made with.
    pub seed: u64,
    /// Devices without a node-id.
    pub unconfigured: u8,
    /// The network's bit rate.
    pub bit_rate: String,
    /// The faults injected.
    pub faults: Vec<String>,
    /// Commands run on virtual time (`--virtual-time`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub virtual_time: bool,
    /// The node-id of the device with a CiA 302-3 bootloader (`--bootloader`), if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bootloader: Option<u8>,
}

/// Forget the saved state at `path`: from now on the devices start as `config` builds them.
pub fn reset(path: &Path, config: &SimConfig) -> Result<Reset> {
    let mut devices: Vec<(String, Option<u8>)> = super::profiles::demo_network_with(config.unconfigured)
        .into_iter()
        .map(|(model, node)| (model.key, node))
        .collect();
    if let Some(node) = config.bootloader {
        // Two devices on one node-id is a fault of its own, not what --bootloader asks for.
        if let Some((model, _)) = devices.iter().find(|(_, n)| *n == Some(node)) {
            let taken = devices.iter().filter_map(|(_, n)| n.map(|n| n.to_string())).collect::<Vec<_>>().join(", ");
            return Err(Error::Usage(format!(
                "a bootloader on node {node}: node {node} is the demo network's {model}; give it a free node-id (taken: {taken})"
            )));
        }
        devices.push((super::bootloader::KEY.to_string(), Some(node)));
    }
    if let Some(why) = super::unmatched(&config.faults, &devices) {
        return Err(Error::Usage(why));
    }
    StateFile::lock(path)?.start_fresh(config)?;
    Ok(Reset {
        reset: true,
        state_file: path.display().to_string(),
        profile: config.profile.to_string(),
        seed: config.seed,
        unconfigured: config.unconfigured,
        bit_rate: bit_rate_name(config.bit_rate),
        faults: config.faults.iter().map(|f| f.to_string()).collect(),
        virtual_time: config.virtual_time,
        bootloader: config.bootloader,
    })
}

/// Where to put the devices.
#[derive(Clone, Debug)]
pub enum Serve {
    /// On a CAN interface (vcan0, can0).
    SocketCan {
        /// The interface's name.
        iface: String,
    },
    /// Behind a simulated slcan (Lawicel) adapter on a pseudo-terminal; the faults are
    /// the adapter's.
    Slcan {
        /// The adapter's faults.
        faults: Vec<Fault>,
    },
    /// As the network's EPOS2 (node 1) on a pseudo-terminal, with the devices on the CAN
    /// bus behind it; `can_timeout` is how long it waits for their SDO answers.
    Epos2 {
        /// RS232 or USB framing.
        framing: Framing,
        /// Pace bytes as a line at this baud rate would; `None`: as fast as the pty goes.
        baud: Option<u32>,
        /// The serial faults to inject.
        faults: Vec<Fault>,
        /// How long the gateway waits for a device's SDO answer.
        can_timeout: Duration,
    },
    /// Behind a socketcand server (raw mode) listening on this address; several clients
    /// share the bus.
    Socketcand {
        /// The address to listen on (port 0: any free one).
        addr: std::net::SocketAddr,
    },
}

/// Where the devices are now served.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Serving {
    /// On a CAN interface: nodes 1, 5, 10 and 32 answer there.
    SocketCan {
        /// The interface's name.
        iface: String,
    },
    /// As the network's EPOS2 (node 1) on a pseudo-terminal.
    Epos2 {
        /// RS232 or USB framing.
        framing: Framing,
        /// The pseudo-terminal's path.
        pty: String,
    },
    /// Behind a simulated slcan adapter on a pseudo-terminal.
    Slcan {
        /// The pseudo-terminal's path.
        pty: String,
        /// The bus's bit rate (a CiA 305 bit timing index).
        bit_rate: u8,
    },
    /// Behind a socketcand server: its clients share the bus.
    Socketcand {
        /// The address the server listens on.
        bound: std::net::SocketAddr,
        /// The `--bus` value that reaches it from this machine.
        bus: String,
        /// The CAN interface it offers.
        iface: String,
    },
}

impl Serving {
    /// The pseudo-terminal to open, if the devices sit behind one.
    pub fn pty(&self) -> Option<&str> {
        match self {
            Serving::SocketCan { .. } | Serving::Socketcand { .. } => None,
            Serving::Epos2 { pty, .. } | Serving::Slcan { pty, .. } => Some(pty),
        }
    }

    /// The `--bus` value that reaches the devices where they are served.
    pub fn uri(&self) -> String {
        match self {
            Serving::SocketCan { iface } => BusAddr::SocketCan { iface: iface.clone() }.to_string(),
            Serving::Epos2 { framing, pty } => format!("{}:{pty}", framing.scheme()),
            Serving::Slcan { pty, bit_rate } => format!("slcan:{pty}@{}", bit_rate_name(*bit_rate)),
            Serving::Socketcand { bus, .. } => bus.clone(),
        }
    }

    /// The bus address that reaches the devices, if it is no pseudo-terminal (a server).
    pub fn bus(&self) -> Option<&str> {
        match self {
            Serving::Socketcand { bus, .. } => Some(bus),
            _ => None,
        }
    }
}

/// Why [`serve`] did not serve: asked for what cannot be served here, or failed.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// A CAN interface was asked for where there is no SocketCAN (it is Linux's).
    #[error("SocketCAN is Linux's: the devices are served on a CAN interface on Linux only")]
    NoSocketCan,
    /// A serial device was asked for where there are no pseudo-terminals.
    #[error("the simulated serial devices sit on a pseudo-terminal, which this OS lacks")]
    NoPty,
    /// A fault the slcan adapter does not take (the devices' own faults are the
    /// network's, set when it is reset).
    #[error("the slcan adapter takes the faults nack, crc, garbage, drop and mute, not {0:?}")]
    AdapterFault(FaultKind),
    /// Serving failed.
    #[error(transparent)]
    Failed(#[from] Error),
    /// The network has the fault bus:off, which only the sim bus itself and the simulated
    /// slcan adapter model: behind a CAN interface, socketcand or an EPOS2 the controller is
    /// another's, and serving the devices as if all were well would hide the fault.
    #[error("the fault bus:off is modelled on the sim bus itself and behind the simulated slcan adapter only")]
    BusOffElsewhere,
}

/// Serve the network saved at `path` until the link fails or the process is stopped.
/// `ready` hears where once the devices answer; `log` records every frame the devices
/// exchange (the `-v` trace goes through `tracing` regardless).
#[cfg_attr(not(unix), allow(unused_variables))]
pub fn serve(
    path: &Path,
    how: &Serve,
    log: Option<FrameLog>,
    ready: impl FnOnce(&Serving) -> Result<()>,
) -> std::result::Result<(), ServeError> {
    if !matches!(how, Serve::Slcan { .. }) && bus_off_saved(path)? {
        return Err(ServeError::BusOffElsewhere);
    }
    // A command that finds the network taken is told where this process serves it.
    let ready = |serving: &Serving| {
        super::state::announce_serving(path, &serving.uri());
        ready(serving)
    };
    match how {
        #[cfg(target_os = "linux")]
        Serve::SocketCan { iface } => Ok(socketcan(path, iface, log, ready)?),
        #[cfg(not(target_os = "linux"))]
        Serve::SocketCan { .. } => Err(ServeError::NoSocketCan),
        Serve::Socketcand { addr } => Ok(socketcand(path, *addr, log, ready)?),
        #[cfg(unix)]
        Serve::Slcan { faults } => slcan(path, faults, log, ready),
        #[cfg(unix)]
        Serve::Epos2 { framing, baud, faults, can_timeout } => {
            Ok(epos2(path, *framing, *baud, faults, *can_timeout, log, ready)?)
        }
        #[cfg(not(unix))]
        Serve::Slcan { .. } | Serve::Epos2 { .. } => Err(ServeError::NoPty),
    }
}

/// Whether the network saved at `path` has the fault bus:off.
fn bus_off_saved(path: &Path) -> Result<bool> {
    let saved = StateFile::lock(path)?.load()?;
    Ok(saved.and_then(|s| s.config).is_some_and(|c| super::bus_off(&c.faults)))
}

#[cfg(target_os = "linux")]
fn socketcan(
    path: &Path,
    iface: &str,
    log: Option<FrameLog>,
    ready: impl FnOnce(&Serving) -> Result<()>,
) -> Result<()> {
    let mut can = crate::backend::socketcan::SocketCanLink::open(iface)?;
    // The interface is a bus with its own timing: the devices only answer late.
    let sim = super::SimLink::open(StateFile::lock(path)?)?.without_bus_timing();
    ready(&Serving::SocketCan { iface: iface.to_string() })?;
    super::bridge::run(sim, &mut can, log)
}

/// The simulated EPOS2 on a pseudo-terminal.
#[cfg(unix)]
fn epos2(
    path: &Path,
    framing: Framing,
    baud: Option<u32>,
    faults: &[Fault],
    can_timeout: Duration,
    log: Option<FrameLog>,
    ready: impl FnOnce(&Serving) -> Result<()>,
) -> Result<()> {
    use super::epos2_serve::{self, ServeOptions};
    let link = super::SimLink::open(StateFile::lock(path)?)?;
    let device = super::epos2_device::Epos2Device::new(link, can_timeout).with_frame_log(log);
    let opts = ServeOptions { framing, baud, faults: faults.to_vec() };
    epos2_serve::serve(device, &opts, |pty| ready(&Serving::Epos2 { framing, pty: pty.to_string() }))
}

/// The devices behind a simulated slcan adapter: the adapter is a frame link, bridged to
/// the sim network as a CAN interface is.
#[cfg(unix)]
fn slcan(
    path: &Path,
    faults: &[Fault],
    log: Option<FrameLog>,
    ready: impl FnOnce(&Serving) -> Result<()>,
) -> std::result::Result<(), ServeError> {
    let adapter_faults = [FaultKind::Nack, FaultKind::Crc, FaultKind::Garbage, FaultKind::Drop, FaultKind::Mute];
    if let Some(f) = faults.iter().find(|f| !adapter_faults.contains(&f.kind)) {
        return Err(ServeError::AdapterFault(f.kind));
    }
    let sim = super::SimLink::open(StateFile::lock(path)?)?;
    let rate = sim.network().bit_rate();
    let kbit = crate::canopen::lss::BIT_TIMINGS.get(rate as usize).and_then(|(_, k)| *k).unwrap_or(500);
    let mut adapter = super::slcan_serve::SlcanAdapter::create(kbit, faults.to_vec())?;
    if super::bus_off(&sim.network().config().faults) {
        adapter = adapter.bus_off();
    }
    ready(&Serving::Slcan { pty: adapter.path().to_string(), bit_rate: rate })?;
    Ok(super::bridge::run(sim, &mut adapter, log)?)
}

/// The devices behind a socketcand server: the server is a frame link, bridged to the sim
/// network as a CAN interface is; its clients share the bus.
fn socketcand(
    path: &Path,
    addr: std::net::SocketAddr,
    log: Option<FrameLog>,
    ready: impl FnOnce(&Serving) -> Result<()>,
) -> Result<()> {
    use super::socketcand_serve::{SocketcandServer, IFACE};
    let sim = super::SimLink::open(StateFile::lock(path)?)?;
    let mut server = SocketcandServer::bind(addr).map_err(|e| e.advised(crate::error::Advice::PortTaken))?;
    let bound = server.local_addr();
    // Listening on every address: this machine's loopback reaches it too.
    let host = match bound.ip() {
        ip if ip.is_unspecified() && ip.is_ipv4() => "127.0.0.1".to_string(),
        ip if ip.is_unspecified() => "::1".to_string(),
        ip => ip.to_string(),
    };
    let bus = BusAddr::Socketcand { host, port: bound.port(), iface: IFACE.into() }.to_string();
    ready(&Serving::Socketcand { bound, bus, iface: IFACE.into() })?;
    super::bridge::run(sim, &mut server, log)
}
