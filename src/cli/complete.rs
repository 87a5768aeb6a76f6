//! Shell completion at run time (clap_complete's dynamic engine): bus URIs that exist here,
//! node-ids from the last scan of the bus, objects from the node's dictionary, and the
//! fixed sets. It reads files only — never the bus — and must answer in milliseconds.

use super::objects::{parse_eds_arg, Dictionaries, EdsArg};
use crate::canopen::types::ALL_TYPES;
use crate::canopen::ObjAddr;
use crate::connect::BusAddr;
use crate::epos2::Framing;
use crate::od::names;
use crate::ops::scan_cache as cache;
use clap::CommandFactory;
use clap_complete::engine::CompletionCandidate;
use std::collections::HashMap;

/// Answer the shell's completion request (`COMPLETE=bash|zsh|fish|...`) and exit; without
/// one, return.
///
/// clap_complete's engine (4.6.11, `engine::complete`) looks each word up as a subcommand
/// before it asks whether the word is the value of the option before it, so in
/// `canctl --bus sim sdo read <Tab>` the bus `sim` is taken for the `sim` subcommand and its
/// options are offered. No upstream report was found when this was written (2026-11). Until
/// the engine is fixed, each option is joined with its value (`--bus=sim`) before the engine
/// sees the line, and the index of the word being completed moves with it.
pub fn complete_from_env() {
    if std::env::var_os("COMPLETE").is_none_or(|v| v.is_empty()) {
        return;
    }
    let mut args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    if let Some(dash) = args.iter().position(|a| a == "--") {
        // bash and zsh say which word is being completed; the other shells complete the last.
        let index_var = "_CLAP_COMPLETE_INDEX";
        let mut words = args.split_off(dash + 1);
        let mut index = std::env::var(index_var).ok().and_then(|i| i.parse().ok()).unwrap_or(words.len() - 1);
        join_option_values(&mut words, &mut index);
        if std::env::var_os(index_var).is_some() {
            std::env::set_var(index_var, index.to_string());
        }
        args.extend(words);
    }
    let current_dir = std::env::current_dir().ok();
    match clap_complete::CompleteEnv::with_factory(super::Cli::command).try_complete(args, current_dir.as_deref()) {
        Ok(true) => std::process::exit(0),
        Ok(false) => {}
        Err(e) => e.exit(),
    }
}

/// Join `--option VALUE` into `--option=VALUE` for every option that takes a value, in the
/// words before the one at `index` (which the user is still typing), and move `index` back
/// by the words joined.
fn join_option_values(words: &mut Vec<std::ffi::OsString>, index: &mut usize) {
    let cli = super::Cli::command();
    let mut i = 0;
    while i + 1 < (*index).min(words.len()) {
        let joinable = words[i]
            .to_str()
            .is_some_and(|w| w.starts_with("--") && w.len() > 2 && !w.contains('=') && takes_value(&cli, w));
        if joinable {
            let value = words.remove(i + 1);
            words[i].push("=");
            words[i].push(value);
            *index -= 1;
        }
        i += 1;
    }
}

/// The words of the partial command line, as the shell passed them after `--`.
fn words() -> Vec<String> {
    let args: Vec<String> = std::env::args().collect();
    args.iter().position(|a| a == "--").map(|i| args[i + 1..].to_vec()).unwrap_or_default()
}

/// Every value given to `--name` (as `--name V` or `--name=V`).
fn flag_values(words: &[String], name: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (i, w) in words.iter().enumerate() {
        if let Some(v) = w.strip_prefix(&format!("{name}=")) {
            out.push(v.to_string());
        } else if w == name {
            out.extend(words.get(i + 1).cloned());
        }
    }
    out
}

fn settings() -> crate::settings::FileSettings {
    crate::settings::load().unwrap_or_default()
}

/// The bus the command line would use.
fn bus(words: &[String]) -> Option<String> {
    flag_values(words, "--bus")
        .pop()
        .or_else(|| std::env::var("CANCTL_BUS").ok().filter(|b| !b.is_empty()))
        .or_else(|| settings().bus.map(|(b, _)| b))
}

pub fn buses() -> Vec<CompletionCandidate> {
    let mut out = vec![CompletionCandidate::new("sim").help(Some("the simulated demo network".into()))];
    let candidate =
        |addr: BusAddr, help: &'static str| CompletionCandidate::new(addr.to_string()).help(Some(help.into()));
    for iface in crate::connect::can_interfaces() {
        out.push(candidate(BusAddr::SocketCan { iface }, "CAN interface"));
    }
    for port in crate::connect::serial_ports() {
        out.push(
            CompletionCandidate::new(format!("slcan:{port}")).help(Some("slcan CAN adapter (CANable, CANUSB)".into())),
        );
        let baud = crate::connect::RS232_DEFAULT_BAUD;
        out.push(candidate(
            BusAddr::Epos2 { framing: Framing::Rs232, port: port.clone(), baud },
            "maxon EPOS2 on RS232",
        ));
        let baud = crate::connect::USB_DEFAULT_BAUD;
        out.push(candidate(BusAddr::Epos2 { framing: Framing::Usb, port, baud }, "maxon EPOS2 on USB"));
    }
    out
}

/// Node-ids of the last scan of the bus, with what they are.
pub fn nodes() -> Vec<CompletionCandidate> {
    let Some(bus) = bus(&words()) else { return vec![] };
    cache::load(&bus)
        .into_iter()
        .map(|n| {
            let what = match (n.name, n.vendor_id) {
                (Some(name), Some(v)) => format!("{name} (vendor 0x{v:08X})"),
                (Some(name), None) => name,
                (None, Some(v)) => format!("vendor 0x{v:08X}"),
                (None, None) => "seen on the last scan".into(),
            };
            CompletionCandidate::new(n.node.to_string()).help(Some(what.into()))
        })
        .collect()
}

pub fn nodes_or_all() -> Vec<CompletionCandidate> {
    let mut out = nodes();
    out.push(CompletionCandidate::new("all").help(Some("every node (a broadcast)".into())));
    out
}

/// Objects of the node named before the object on the command line (`sdo read NODE OBJ`):
/// only those the node is known to have.
///
/// - The node's description, if one is known, lists them: an EDS/DCF/XDD given for it on
///   the line or in canctl.toml, else the one its last scan was given or the one it stores
///   in itself once `config eds --out` saved it (both kept in the scan cache). Only its
///   objects are offered.
/// - Without one: the objects CiA 301 makes mandatory (0x1000 device type, 0x1001 error
///   register, 0x1018:0 and :1 identity; and 0x1017 producer heartbeat time, mandatory for
///   every device without node guarding), the device-profile objects (0x6000-0x9FFF) of the
///   built-in dictionary for the device type the scan read, and every object the node
///   answered (the scan's reads, `sdo read`, `sdo write`). The built-in dictionary's other
///   communication objects (PDOs, SDO channels, ...) are guesses a node may not have, and
///   are not offered.
/// - Never an object whose index the node refused (SDO abort 0x06020000), as remembered.
/// - By name only where the command finds the object by that name (in the dictionary it
///   uses: an EDS given now, else the built-in one); otherwise by address, named in the help.
pub fn objects() -> Vec<CompletionCandidate> {
    let w = words();
    let node = w
        .iter()
        .position(|a| a == "read" || a == "write")
        .and_then(|i| positionals(&w[i + 1..]).first().and_then(|n| super::parse_sdo_node(n).ok()))
        .unwrap_or(0);
    let mut eds: Vec<EdsArg> = flag_values(&w, "--eds").iter().filter_map(|e| parse_eds_arg(e).ok()).collect();
    for (n, (path, _)) in settings().eds {
        if !eds.iter().any(|e| e.node == Some(n)) {
            eds.push(EdsArg { node: Some(n), path });
        }
    }
    // A refused EDS is said (the shell shows stderr), not silently replaced.
    let dicts = Dictionaries::load(&eds).unwrap_or_else(|e| {
        eprintln!("\ncanctl: {e}; completing from the built-in dictionary");
        Dictionaries::default()
    });
    let seen = bus(&w).and_then(|b| cache::load_all(&b).into_iter().find(|n| n.node == node));
    // A description remembered from the scan that has since gone is no longer known.
    let remembered = match &seen {
        Some(n) if dicts.eds_for(node).is_none() => {
            n.dictionary.as_deref().and_then(|p| crate::od::read_description(p).ok())
        }
        _ => None,
    };
    let described = dicts.eds_for(node).or(remembered.as_ref());
    // Without a description, the built-in dictionary of the node's profile names them.
    let profile = seen.as_ref().and_then(|n| n.device_type).map(|t| (t & 0xFFFF) as u16);
    let dict = described.map_or_else(|| crate::od::builtin::dictionary(profile), |e| &e.dict);
    let answered = |a: ObjAddr| seen.as_ref().is_some_and(|n| n.answered.contains(&(a.index, a.sub)));
    let refused = |a: ObjAddr| seen.as_ref().is_some_and(|n| n.refused.contains(&a.index));
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
    // Offered by name only where the command finds it by that name: it looks in the
    // dictionary it uses for the node (an EDS given now, else the built-in one), which may
    // not be the one that names the objects here. Indexed once: a large EDS has thousands.
    let command_dict = dicts.for_node(node);
    let mut command_names: HashMap<String, Vec<ObjAddr>> = HashMap::new();
    for e in command_dict.entries() {
        if let Some(name) = command_dict.display_name(e.addr) {
            command_names.entry(names::normalize(&name)).or_default().push(e.addr);
        }
    }
    let mut out = Vec::new();
    let mut by_name = Vec::new();
    for (e, name) in &named {
        let kind = format!("{} {}", e.dtype, e.access.name());
        out.push(CompletionCandidate::new(e.addr.to_string()).help(Some(format!("{name} ({kind})").into())));
        let found = |word: &str| match command_names.get(&names::normalize(word)).map(Vec::as_slice) {
            Some([one]) => *one == e.addr,
            // Names alike, or not among the full names: as the command decides (rare).
            _ => names::find(command_dict, word).is_ok_and(|a| a == e.addr),
        };
        if !name.is_empty() && uses[&names::normalize(name)] == 1 && found(&names::identifier(name)) {
            by_name.push(
                CompletionCandidate::new(names::identifier(name)).help(Some(format!("{} ({kind})", e.addr).into())),
            );
        }
    }
    // What the node answered that the dictionary does not describe is offered by address.
    for (index, sub) in seen.iter().flat_map(|n| &n.answered) {
        let addr = ObjAddr::new(*index, *sub);
        if dict.get(addr).is_none() && !refused(addr) {
            out.push(CompletionCandidate::new(addr.to_string()).help(Some("answered before".into())));
        }
    }
    out.extend(by_name);
    out
}

/// The objects CiA 301 requires of every device (0x1017 of every one without node
/// guarding, which is optional and rare).
fn mandatory(a: ObjAddr) -> bool {
    matches!((a.index, a.sub), (0x1000 | 0x1001 | 0x1017, 0) | (0x1018, 0 | 1))
}

/// The positional words among `words`: flags and the values they take left out.
fn positionals(words: &[String]) -> Vec<&String> {
    let cli = super::Cli::command();
    let mut out = Vec::new();
    let mut iter = words.iter();
    while let Some(w) = iter.next() {
        if w.starts_with('-') && w.len() > 1 {
            if !w.contains('=') && takes_value(&cli, w) {
                iter.next();
            }
        } else {
            out.push(w);
        }
    }
    out
}

/// Whether the flag `--name` or `-n` takes a value anywhere in the command tree.
fn takes_value(cmd: &clap::Command, flag: &str) -> bool {
    let matches = |a: &clap::Arg| match flag.strip_prefix("--") {
        Some(long) => a.get_long() == Some(long),
        None => flag.chars().nth(1).is_some_and(|c| a.get_short() == Some(c)),
    };
    cmd.get_arguments().any(|a| matches(a) && a.get_action().takes_values())
        || cmd.get_subcommands().any(|s| takes_value(s, flag))
}

pub fn types() -> Vec<CompletionCandidate> {
    ALL_TYPES
        .iter()
        .map(|t| CompletionCandidate::new(t.name()).help(Some(format!("CiA 301 type 0x{:04X}", t.code()).into())))
        .collect()
}

/// The CiA 305 bit timing table, reserved entries left out.
pub fn bit_rates() -> Vec<CompletionCandidate> {
    use crate::canopen::lss::{bit_rate_name, AUTO_BIT_RATE, BIT_TIMINGS};
    BIT_TIMINGS
        .iter()
        .filter(|(i, kbit)| kbit.is_some() || *i == AUTO_BIT_RATE)
        .map(|(i, _)| CompletionCandidate::new(bit_rate_name(*i)).help(Some(format!("CiA 305 table index {i}").into())))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::join_option_values;
    use std::ffi::OsString;

    fn joined(words: &[&str], index: usize) -> (Vec<String>, usize) {
        let mut w: Vec<OsString> = words.iter().map(OsString::from).collect();
        let mut i = index;
        join_option_values(&mut w, &mut i);
        (w.into_iter().map(|w| w.into_string().unwrap()).collect(), i)
    }

    #[test]
    fn options_with_values_are_joined_before_the_word_being_completed() {
        let (w, i) = joined(&["canctl", "--bus", "sim", "-v", "sdo", "read", ""], 6);
        assert_eq!(w, ["canctl", "--bus=sim", "-v", "sdo", "read", ""]);
        assert_eq!(w[i], "");
        let (w, i) = joined(&["canctl", "--timeout", "2s", "--eds", "5=a.eds", "nmt", "start", "5"], 7);
        assert_eq!(w, ["canctl", "--timeout=2s", "--eds=5=a.eds", "nmt", "start", "5"]);
        assert_eq!(w[i], "5");
    }

    #[test]
    fn the_value_being_typed_and_flags_are_left_alone() {
        // `--bus s<Tab>`: the value itself is being completed.
        assert_eq!(joined(&["canctl", "--bus", "s"], 2), (vec!["canctl".into(), "--bus".into(), "s".into()], 2));
        // `--quiet` takes no value; `--bus=sim` is already joined.
        let words = ["canctl", "--quiet", "scan", "--bus=sim", "nmt"];
        assert_eq!(joined(&words, 4).0, words);
    }
}
