//! The command line's words for the library's [`Hint`]s: the one place remedies name
//! canctl's flags and commands.

use crate::hint::Hint;

/// The remedy as canctl says it, to follow the error's message.
pub fn hint_text(hint: Hint) -> &'static str {
    match hint {
        Hint::FreeNodeIdOrForce => "; choose a free id (canctl scan lists those in use), or --force gives it anyway",
        Hint::GiveEds => "; get the EDS from its vendor and give it with --eds",
    }
}

/// An error from a command as canctl prints it: its message (with its causes), then the
/// remedy of the library's error in it, in canctl's terms.
pub fn error_text(err: &anyhow::Error) -> String {
    let hint = err.chain().find_map(|c| c.downcast_ref::<crate::Error>()).and_then(Hint::of);
    format!("{err:#}{}", hint.map_or("", hint_text))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What the user reads is what canctl printed before the remedy was typed.
    #[test]
    fn the_remedy_follows_the_message_naming_the_flag() {
        let e = anyhow::Error::from(crate::Error::NoStoredEds { node: 5 });
        assert_eq!(
            error_text(&e),
            "node 5: the device does not store its EDS (0x1021); get the EDS from its vendor and give it with --eds"
        );
        let e = anyhow::Error::from(crate::Error::NodeIdInUse { node: 7, identity: None, by: "its heartbeat" });
        assert!(error_text(&e).ends_with(
            "Nothing was sent; choose a free id (canctl scan lists those in use), or --force gives it anyway"
        ));
        let e = anyhow::Error::from(crate::Error::Interrupted);
        assert_eq!(error_text(&e), format!("{e:#}"));
    }
}
