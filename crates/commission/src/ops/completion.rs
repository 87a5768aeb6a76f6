//! What shell completion offers, from files only (never the bus; it must answer in
//! milliseconds): the buses that exist here, the nodes of the last scan of a bus, and the
//! objects a node is known to have. The command line turns these into the shell's
//! candidates and words their help.

use crate::canopen::{DataType, ObjAddr};
use crate::connect::BusAddr;
use crate::epos2::Framing;
use crate::od::{names, Access};
use crate::ops::dictionaries::Dictionaries;
use crate::ops::scan_cache::{self, SeenNode};
use crate::settings::EdsFile;
use crate::settings::{Given, Settings};
use std::collections::HashMap;

/// A bus address that exists on this machine, and what kind it is.
#[derive(Debug, Clone, PartialEq)]
pub enum BusCandidate {
    /// The simulated demo network (`sim`).
    Sim,
    /// An address built from a CAN interface or serial port found here.
    Found(BusAddr),
    /// `slcan:PORT`, an slcan adapter on a serial port found here.
    Slcan(String),
    /// `socketcand:`, the start of a socketcand server's address (`HOST[:PORT]/IFACE` follows).
    Socketcand,
    /// A socketcand server's bus whose beacon the last `canctl buses` heard, and what the
    /// server called itself.
    Heard(BusAddr, String),
}

/// The buses that could be given to `--bus` here: the simulator, every CAN interface, and
/// for every serial port an slcan adapter and an EPOS2 on RS232 and on USB, and the start of
/// a socketcand server's address, after the socketcand buses the last `canctl buses` heard
/// (remembered: completion never waits for a beacon).
pub fn buses() -> Vec<BusCandidate> {
    let mut out = vec![BusCandidate::Sim];
    for iface in crate::connect::can_interfaces() {
        out.push(BusCandidate::Found(BusAddr::SocketCan { iface }));
    }
    for port in crate::connect::serial_ports() {
        out.push(BusCandidate::Slcan(port.clone()));
        for framing in [Framing::Rs232, Framing::Usb] {
            let (port, baud) = (port.clone(), crate::connect::default_baud(framing));
            out.push(BusCandidate::Found(BusAddr::Epos2 { framing, port, baud }));
        }
    }
    for heard in crate::ops::buses::last_heard() {
        out.extend(heard.bus.parse().ok().map(|addr| BusCandidate::Heard(addr, heard.what)));
    }
    out.push(BusCandidate::Socketcand);
    out
}

/// The bus and the descriptions a partial command line gives (`bus`, `eds`), resolved as
/// the command resolves them (else CANCTL_BUS, else the settings file's).
fn line_settings(bus: Option<String>, eds: Vec<EdsFile>) -> Settings {
    let bus = bus.or_else(|| std::env::var("CANCTL_BUS").ok());
    Settings::resolve(Given { bus, eds, ..Given::default() }, crate::settings::load().unwrap_or_default())
}

/// The nodes the last scan saw on the bus a partial command line names (`bus`).
pub fn line_nodes(bus: Option<String>) -> Vec<SeenNode> {
    line_settings(bus, Vec::new()).bus.map(|bus| scan_cache::load(&bus.value)).unwrap_or_default()
}

/// [`objects`] of `node` on the bus and with the descriptions a partial command line names
/// (or canctl.toml); a description that cannot be read is returned beside the built-in
/// dictionary's objects, to be said rather than silently replaced.
pub fn line_objects(bus: Option<String>, eds: Vec<EdsFile>, node: u8) -> (Vec<ObjectCandidate>, Option<crate::Error>) {
    let settings = line_settings(bus, eds);
    let eds: Vec<_> = settings.eds.into_iter().map(|e| e.value).collect();
    let (dicts, refused) = match Dictionaries::load(&eds) {
        Ok(dicts) => (dicts, None),
        Err(e) => (Dictionaries::default(), Some(e)),
    };
    let seen = settings.bus.and_then(|b| scan_cache::load_all(&b.value).into_iter().find(|n| n.node == node));
    (objects(node, &dicts, seen.as_ref()), refused)
}

/// An object a node is known to have.
#[derive(Debug, Clone, PartialEq)]
pub enum ObjectCandidate {
    /// Described by the dictionary that names the node's objects; `identifier` is the name
    /// the command finds it by, where it finds it by one.
    Described {
        /// Its index and sub-index.
        addr: ObjAddr,
        /// Its name in the dictionary.
        name: String,
        /// Its data type.
        dtype: DataType,
        /// Its access.
        access: Access,
        /// The name the command finds it by.
        identifier: Option<String>,
    },
    /// Answered before, but not in the dictionary.
    Answered(ObjAddr),
}

/// Objects of `node` that it is known to have, with `seen` what the scan cache remembers of
/// it and `dicts` the descriptions given now (`--eds`, canctl.toml).
///
/// - The node's description, if one is known, lists them: one given now, else the one its
///   last scan was given or the one it stores in itself (both kept in the scan cache). Only
///   its objects are offered.
/// - Without one: the objects CiA 301 makes mandatory (0x1000 device type, 0x1001 error
///   register, 0x1018:0 and :1 identity; and 0x1017 producer heartbeat time, mandatory for
///   every device without node guarding), the device-profile objects (0x6000-0x9FFF) of the
///   built-in dictionary for the device type the scan read, and every object the node
///   answered (the scan's reads, `sdo read`, `sdo write`). The built-in dictionary's other
///   communication objects (PDOs, SDO channels, ...) are guesses a node may not have, and
///   are not offered.
/// - Never an object whose index the node refused (SDO abort 0x06020000), as remembered.
/// - An identifier only where the command finds the object by that name (in the dictionary
///   it uses: a description given now, else the built-in one).
pub fn objects(node: u8, dicts: &Dictionaries, seen: Option<&SeenNode>) -> Vec<ObjectCandidate> {
    // A description remembered from the scan that has since gone is no longer known.
    let remembered = match seen {
        Some(n) if dicts.eds_for(node).is_none() => {
            n.dictionary.as_deref().and_then(|p| crate::od::read_description(p).ok())
        }
        _ => None,
    };
    let described = dicts.eds_for(node).or(remembered.as_ref());
    // Without a description, the built-in dictionary of the node's profile names them.
    let profile = seen.and_then(|n| n.device_type).map(|t| (t & 0xFFFF) as u16);
    let dict = described.map_or_else(|| crate::od::builtin::dictionary(profile), |e| &e.dict);
    let answered = |a: ObjAddr| seen.is_some_and(|n| n.answered.contains(&(a.index, a.sub)));
    let refused = |a: ObjAddr| seen.is_some_and(|n| n.refused.contains(&a.index));
    let known = |a: ObjAddr| described.is_some() || answered(a) || mandatory(a) || (0x6000..=0x9FFF).contains(&a.index);
    let named: Vec<(&crate::od::Entry, String)> = dict
        .entries()
        .filter(|e| known(e.addr) && !refused(e.addr))
        .map(|e| (e, dict.display_name(e.addr).unwrap_or_default()))
        .collect();
    // A name is offered only where it stands for one object (array subs share theirs).
    let mut uses: HashMap<String, usize> = HashMap::new();
    for (_, name) in &named {
        *uses.entry(names::normalize(name)).or_default() += 1;
    }
    // The command looks in the dictionary it uses for the node (an EDS given now, else the
    // built-in one), which may not be the one that names the objects here. Indexed once: a
    // large EDS has thousands.
    let command_dict = dicts.for_node(node);
    let mut command_names: HashMap<String, Vec<ObjAddr>> = HashMap::new();
    for e in command_dict.entries() {
        if let Some(name) = command_dict.display_name(e.addr) {
            command_names.entry(names::normalize(&name)).or_default().push(e.addr);
        }
    }
    let mut out = Vec::new();
    for (e, name) in named {
        let found = |word: &str| match command_names.get(&names::normalize(word)).map(Vec::as_slice) {
            Some([one]) => *one == e.addr,
            // Names alike, or not among the full names: as the command decides (rare).
            _ => names::find(command_dict, word).is_ok_and(|a| a == e.addr),
        };
        let identifier = (!name.is_empty() && uses[&names::normalize(&name)] == 1)
            .then(|| names::identifier(&name))
            .filter(|id| found(id));
        out.push(ObjectCandidate::Described { addr: e.addr, name, dtype: e.dtype, access: e.access, identifier });
    }
    // What the node answered that the dictionary does not describe is offered by address.
    for (index, sub) in seen.iter().flat_map(|n| &n.answered) {
        let addr = ObjAddr::new(*index, *sub);
        if dict.get(addr).is_none() && !refused(addr) {
            out.push(ObjectCandidate::Answered(addr));
        }
    }
    out
}

/// The objects CiA 301 requires of every device (0x1017 of every one without node
/// guarding, which is optional and rare).
fn mandatory(a: ObjAddr) -> bool {
    matches!(
        a,
        ObjAddr::DEVICE_TYPE
            | ObjAddr::ERROR_REGISTER
            | ObjAddr::HEARTBEAT_TIME
            | ObjAddr::IDENTITY
            | ObjAddr::VENDOR_ID
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn addrs(c: &[ObjectCandidate]) -> Vec<ObjAddr> {
        c.iter()
            .map(|c| match c {
                ObjectCandidate::Described { addr, .. } | ObjectCandidate::Answered(addr) => *addr,
            })
            .collect()
    }

    #[test]
    fn without_a_description_the_mandatory_objects_and_what_the_node_answered() {
        let seen = SeenNode {
            node: 5,
            answered: [(0x1008, 0), (0x2345, 7)].into_iter().collect(),
            refused: [0x1017].into_iter().collect(),
            name: None,
            vendor_id: None,
            device_type: None,
            scanned: true,
            dictionary: None,
        };
        let got = objects(5, &Dictionaries::default(), Some(&seen));
        let a = addrs(&got);
        assert!(a.contains(&ObjAddr::new(0x1000, 0)) && a.contains(&ObjAddr::new(0x1018, 1)), "{a:?}");
        assert!(a.contains(&ObjAddr::new(0x1008, 0)), "answered: {a:?}");
        assert!(got.contains(&ObjectCandidate::Answered(ObjAddr::new(0x2345, 7))), "{got:?}");
        // Refused, and a communication object it was never seen to have.
        assert!(!a.contains(&ObjAddr::new(0x1017, 0)) && !a.iter().any(|a| a.index == 0x1400), "{a:?}");
        let device_type = got.iter().find_map(|c| match c {
            ObjectCandidate::Described { addr, identifier, .. } if addr.index == 0x1000 => Some(identifier.clone()),
            _ => None,
        });
        assert!(matches!(device_type, Some(Some(_))), "0x1000 is found by its name: {device_type:?}");
    }
}
