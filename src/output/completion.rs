//! Completion candidates as the shell shows them: the value, and its help in words; and the
//! answer to the shell's request itself (clap_complete's dynamic engine, driven from the
//! command line's clap definition, as `docs` renders the scripts and man pages from it).

use crate::canopen::types::ALL_TYPES;
use crate::ops::completion::{BusCandidate, ObjectCandidate};
use crate::ops::scan_cache::SeenNode;
use clap_complete::engine::CompletionCandidate;

fn candidate(value: impl Into<std::ffi::OsString>, help: impl Into<String>) -> CompletionCandidate {
    CompletionCandidate::new(value).help(Some(help.into().into()))
}

pub(crate) fn buses(buses: Vec<BusCandidate>) -> Vec<CompletionCandidate> {
    use crate::connect::BusAddr;
    use crate::epos2::Framing;
    buses
        .into_iter()
        .map(|b| match b {
            BusCandidate::Sim => candidate("sim", "the simulated demo network"),
            BusCandidate::Slcan(port) => candidate(format!("slcan:{port}"), "slcan CAN adapter (CANable, CANUSB)"),
            BusCandidate::Socketcand => {
                candidate("socketcand:", "socketcand:HOST[:PORT]/IFACE, a CAN interface over TCP")
            }
            BusCandidate::Heard(addr, what) => candidate(addr.to_string(), what),
            BusCandidate::Found(addr) => {
                let help = match &addr {
                    BusAddr::SocketCan { .. } => "CAN interface",
                    BusAddr::Epos2 { framing: Framing::Rs232, .. } => "maxon EPOS2 on RS232",
                    BusAddr::Epos2 { framing: Framing::Usb, .. } => "maxon EPOS2 on USB",
                    _ => "",
                };
                candidate(addr.to_string(), help)
            }
        })
        .collect()
}

/// Node-ids of the last scan of the bus, with what they are.
pub(crate) fn nodes(seen: Vec<SeenNode>) -> Vec<CompletionCandidate> {
    seen.into_iter()
        .map(|n| {
            let what = match (n.name, n.vendor_id) {
                (Some(name), Some(v)) => format!("{name} (vendor 0x{v:08X})"),
                (Some(name), None) => name,
                (None, Some(v)) => format!("vendor 0x{v:08X}"),
                (None, None) => "seen on the last scan".into(),
            };
            candidate(n.node.to_string(), what)
        })
        .collect()
}

/// Every object by address, then those the command finds by name by that name.
pub(crate) fn objects(objects: Vec<ObjectCandidate>) -> Vec<CompletionCandidate> {
    let mut out = Vec::new();
    let mut by_name = Vec::new();
    for o in objects {
        match o {
            ObjectCandidate::Described { addr, name, dtype, access, identifier } => {
                let kind = format!("{dtype} {}", access.name());
                out.push(candidate(addr.to_string(), format!("{name} ({kind})")));
                if let Some(id) = identifier {
                    by_name.push(candidate(id, format!("{addr} ({kind})")));
                }
            }
            ObjectCandidate::Answered(addr) => out.push(candidate(addr.to_string(), "answered before")),
        }
    }
    out.extend(by_name);
    out
}

pub(crate) fn types() -> Vec<CompletionCandidate> {
    ALL_TYPES.iter().map(|t| candidate(t.name(), format!("CiA 301 type 0x{:04X}", t.code()))).collect()
}

/// The CiA 305 bit timing table, reserved entries left out.
pub(crate) fn bit_rates() -> Vec<CompletionCandidate> {
    use crate::canopen::lss::{bit_rate_name, AUTO_BIT_RATE, BIT_TIMINGS};
    BIT_TIMINGS
        .iter()
        .filter(|(i, kbit)| kbit.is_some() || *i == AUTO_BIT_RATE)
        .map(|(i, _)| candidate(bit_rate_name(*i), format!("CiA 305 table index {i}")))
        .collect()
}

/// Answer the shell's completion request (`COMPLETE=bash|zsh|fish|...`) for the command line
/// `command` makes, and exit; without one, return.
///
/// clap_complete's engine (4.6.11, `engine::complete`) looks each word up as a subcommand
/// before it asks whether the word is the value of the option before it, so in
/// `canctl --bus sim sdo read <Tab>` the bus `sim` is taken for the `sim` subcommand and its
/// options are offered. No upstream report was found when this was written (2026-11). Until
/// the engine is fixed, each option is joined with its value (`--bus=sim`) before the engine
/// sees the line, and the index of the word being completed moves with it.
pub(crate) fn complete_from_env(command: fn() -> clap::Command) {
    if std::env::var_os("COMPLETE").is_none_or(|v| v.is_empty()) {
        return;
    }
    let _ = COMMAND.set(command);
    let mut args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    if let Some(dash) = args.iter().position(|a| a == "--") {
        // bash and zsh say which word is being completed; the other shells complete the last.
        let index_var = "_CLAP_COMPLETE_INDEX";
        let mut words = args.split_off(dash + 1);
        let mut index = std::env::var(index_var).ok().and_then(|i| i.parse().ok()).unwrap_or(words.len() - 1);
        join_option_values(&command(), &mut words, &mut index);
        if std::env::var_os(index_var).is_some() {
            std::env::set_var(index_var, index.to_string());
        }
        args.extend(words);
    }
    let current_dir = std::env::current_dir().ok();
    match clap_complete::CompleteEnv::with_factory(command).try_complete(args, current_dir.as_deref()) {
        Ok(true) => std::process::exit(0),
        Ok(false) => {}
        Err(e) => e.exit(),
    }
}

/// Join `--option VALUE` into `--option=VALUE` for every option that takes a value, in the
/// words before the one at `index` (which the user is still typing), and move `index` back
/// by the words joined.
fn join_option_values(cli: &clap::Command, words: &mut Vec<std::ffi::OsString>, index: &mut usize) {
    let mut i = 0;
    while i + 1 < (*index).min(words.len()) {
        let joinable = words[i]
            .to_str()
            .is_some_and(|w| w.starts_with("--") && w.len() > 2 && !w.contains('=') && takes_value(cli, w));
        if joinable {
            let value = words.remove(i + 1);
            words[i].push("=");
            words[i].push(value);
            *index -= 1;
        }
        i += 1;
    }
}

/// The command line's clap definition, as [`complete_from_env`] was given it: the completers
/// that read the words typed (`cli` hands them no definition) look its flags up there.
static COMMAND: std::sync::OnceLock<fn() -> clap::Command> = std::sync::OnceLock::new();

/// The positional words among `words` of the command line being completed: flags and the
/// values they take left out.
pub(crate) fn positionals(words: &[String]) -> Vec<&String> {
    let cli = COMMAND.get().map_or_else(clap::Command::default, |command| command());
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

#[cfg(test)]
mod tests {
    use super::join_option_values;
    use clap::CommandFactory;
    use std::ffi::OsString;

    fn joined(words: &[&str], index: usize) -> (Vec<String>, usize) {
        let mut w: Vec<OsString> = words.iter().map(OsString::from).collect();
        let mut i = index;
        join_option_values(&crate::cli::Cli::command(), &mut w, &mut i);
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
