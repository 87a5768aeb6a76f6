//! Shell completion at run time (clap_complete's dynamic engine): bus URIs that exist here,
//! node-ids from the last scan of the bus, objects from the node's dictionary, and the
//! fixed sets. It reads files only — never the bus — and must answer in milliseconds.

use clap_complete::engine::CompletionCandidate;

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
fn bus_and_eds(words: &[String]) -> (Option<String>, Vec<crate::settings::EdsFile>) {
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
        .and_then(|i| {
            crate::output::completion::positionals(&w[i + 1..])
                .first()
                .and_then(|n| crate::settings::parse::parse_sdo_node(n).ok())
        })
        .unwrap_or(0);
    let (bus, eds) = bus_and_eds(&w);
    let (objects, refused) = crate::ops::completion::line_objects(bus, eds, node);
    // A refused EDS is said (the shell shows stderr), not silently replaced.
    if let Some(e) = refused {
        crate::output::stderr::say(&format!("\ncanctl: {e}; completing from the built-in dictionary"));
    }
    crate::output::completion::objects(objects)
}

pub(crate) fn types() -> Vec<CompletionCandidate> {
    crate::output::completion::types()
}

pub(crate) fn bit_rates() -> Vec<CompletionCandidate> {
    crate::output::completion::bit_rates()
}
