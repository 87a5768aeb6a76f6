//! `--eds [NODE=]FILE`: which dictionary describes a node (see [`crate::ops::dictionaries`]).

pub use crate::ops::dictionaries::{Dictionaries, EdsFile as EdsArg};

pub fn parse_eds_arg(s: &str) -> Result<EdsArg, String> {
    s.parse()
}

/// Read every `--eds` file, its warnings said on stderr.
pub fn load(args: &[EdsArg]) -> crate::Result<Dictionaries> {
    let dicts = Dictionaries::load(args)?;
    say_deviations(dicts.warnings());
    Ok(dicts)
}

/// How many of a file's deviations are said one by one on every command that reads it.
const SAID_EACH: usize = 3;

/// A file's deviations from CiA 306 on stderr: a few one by one (what is left out first),
/// then how many more and where to see them all, so that a vendor's file with dozens of
/// harmless deviations does not bury the command's own output.
pub fn say_deviations<'a>(warnings: impl Iterator<Item = &'a crate::od::lint::Warning>) {
    use crate::od::lint::Severity;
    let mut by_file: Vec<(&str, Vec<&crate::od::lint::Warning>)> = Vec::new();
    for w in warnings {
        match by_file.iter_mut().find(|(p, _)| *p == w.path) {
            Some((_, list)) => list.push(w),
            None => by_file.push((&w.path, vec![w])),
        }
    }
    for (path, mut list) in by_file {
        list.sort_by_key(|w| (w.severity != Severity::Error, w.line));
        for w in list.iter().take(SAID_EACH) {
            tracing::warn!("{w}");
        }
        if list.len() > SAID_EACH {
            tracing::warn!(
                "{path}: {} more deviation(s) from CiA 306; canctl config check {path} lists them all",
                list.len() - SAID_EACH
            );
        }
    }
}
