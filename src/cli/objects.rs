//! `--eds [NODE=]FILE`: which dictionary describes a node (see [`crate::ops::dictionaries`]).

pub use crate::ops::dictionaries::{Dictionaries, EdsFile as EdsArg};
use std::path::PathBuf;

pub fn parse_eds_arg(s: &str) -> Result<EdsArg, String> {
    match s.split_once('=') {
        Some((node, path)) if !node.is_empty() && node.chars().all(|c| c.is_ascii_digit()) => {
            let node = super::parse_node(node)?;
            Ok(EdsArg { node: Some(node), path: PathBuf::from(path) })
        }
        _ => Ok(EdsArg { node: None, path: PathBuf::from(s) }),
    }
}

/// Read every `--eds` file, its warnings said on stderr.
pub fn load(args: &[EdsArg]) -> crate::Result<Dictionaries> {
    let dicts = Dictionaries::load(args)?;
    dicts.warnings().for_each(|w| eprintln!("canctl: warning: {w}"));
    Ok(dicts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eds_arguments() {
        let a = parse_eds_arg("5=sensors/mh.eds").unwrap();
        assert_eq!((a.node, a.path), (Some(5), PathBuf::from("sensors/mh.eds")));
        assert_eq!(parse_eds_arg("mh.eds").unwrap().node, None);
        assert_eq!(parse_eds_arg("C:=odd").unwrap().node, None);
        assert!(parse_eds_arg("200=x.eds").is_err());
    }
}
