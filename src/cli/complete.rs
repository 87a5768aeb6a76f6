//! Shell completion at run time (clap_complete's dynamic engine): bus URIs that exist here,
//! node-ids from the last scan of the bus, objects from the node's dictionary, and the
//! fixed sets. It reads files only — never the bus — and must answer in milliseconds.

use clap::CommandFactory;
use clap_complete::engine::CompletionCandidate;

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

pub(crate) fn buses() -> Vec<CompletionCandidate> {
    crate::output::completion::buses(crate::ops::completion::buses())
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

/// The bus the command line gives (its last `--bus`), and its `--eds` files.
fn bus_and_eds(words: &[String]) -> (Option<String>, Vec<super::objects::EdsArg>) {
    let eds = flag_values(words, "--eds").iter().filter_map(|e| super::objects::parse_eds_arg(e).ok()).collect();
    (flag_values(words, "--bus").pop(), eds)
}

/// Node-ids of the last scan of the bus, with what they are.
pub(crate) fn nodes() -> Vec<CompletionCandidate> {
    crate::output::completion::nodes(crate::ops::completion::line_nodes(bus_and_eds(&words()).0))
}

pub(crate) fn nodes_or_all() -> Vec<CompletionCandidate> {
    let mut out = nodes();
    out.push(CompletionCandidate::new("all").help(Some("every node (a broadcast)".into())));
    out
}

/// Objects of the node named before the object on the command line (`sdo read NODE OBJ`)
/// that it is known to have ([`crate::ops::completion::objects`]), with the descriptions
/// given on the line or in canctl.toml.
pub(crate) fn objects() -> Vec<CompletionCandidate> {
    let w = words();
    let node = w
        .iter()
        .position(|a| a == "read" || a == "write")
        .and_then(|i| positionals(&w[i + 1..]).first().and_then(|n| super::parse_sdo_node(n).ok()))
        .unwrap_or(0);
    let (bus, eds) = bus_and_eds(&w);
    let (objects, refused) = crate::ops::completion::line_objects(bus, eds, node);
    // A refused EDS is said (the shell shows stderr), not silently replaced.
    if let Some(e) = refused {
        eprintln!("\ncanctl: {e}; completing from the built-in dictionary");
    }
    crate::output::completion::objects(objects)
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

pub(crate) fn types() -> Vec<CompletionCandidate> {
    crate::output::completion::types()
}

pub(crate) fn bit_rates() -> Vec<CompletionCandidate> {
    crate::output::completion::bit_rates()
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
