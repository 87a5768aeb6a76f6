//! `--eds [NODE=]FILE`: which dictionary describes a node (see [`crate::ops::dictionaries`]).

pub(crate) use crate::ops::dictionaries::Dictionaries;
use crate::settings::EdsFile;

pub(crate) fn parse_eds_arg(s: &str) -> Result<EdsFile, String> {
    s.parse()
}

/// Read every `--eds` file, its warnings said on stderr.
pub(crate) fn load(args: &[crate::settings::Sourced<EdsFile>]) -> crate::Result<Dictionaries> {
    let dicts = Dictionaries::load_in_force(args)?;
    crate::output::say_deviations(dicts.warnings());
    Ok(dicts)
}
