//! The LSS sequences made of several requests, pure: a selective switch (four requests,
//! one answer) and what the answers to a configuration service say. The waiting and the
//! sending are the bus's (`bus::lss`).

use super::wire::{Identity, Request, Response};

/// The four selective-switch requests for one device; the answer is 0x44 from it alone.
pub fn switch_selective(id: &Identity) -> [Request; 4] {
    [0, 1, 2, 3].map(|part| Request::SwitchSelective { part, value: id.part(part) })
}

/// What the answers to a confirmed configuration service (set-id, bit timing, store) say.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Configured {
    /// This many devices answered, every one with success.
    Done(usize),
    /// A device refused: the command specifier, error code and manufacturer's code.
    Refused {
        /// The command specifier of the refused request.
        cs: u8,
        /// The error code (CiA 305: 1 out of range, 255 manufacturer-specific).
        error: u8,
        /// The manufacturer's error code, meaningful when `error` is 255.
        specific: u8,
    },
    /// No result among the answers.
    Unanswered,
}

/// What `answers` (to one configuration service) say: a single refusal is a refusal.
pub fn configured(answers: &[Response]) -> Configured {
    let results: Vec<(u8, u8, u8)> = answers
        .iter()
        .filter_map(|a| match a {
            Response::Result { cs, error, specific } => Some((*cs, *error, *specific)),
            _ => None,
        })
        .collect();
    match results.iter().find(|(_, e, _)| *e != 0) {
        _ if results.is_empty() => Configured::Unanswered,
        Some(&(cs, error, specific)) => Configured::Refused { cs, error, specific },
        None => Configured::Done(results.len()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn configuration_answers_are_read_from_their_bytes() {
        let ok = Response::decode(&[0x11, 0, 0, 0, 0, 0, 0, 0]).unwrap();
        let refused = Response::decode(&[0x11, 1, 0, 0, 0, 0, 0, 0]).unwrap();
        let other = Response::decode(&[0x44, 0, 0, 0, 0, 0, 0, 0]).unwrap();
        assert_eq!(configured(&[ok, ok]), Configured::Done(2));
        assert_eq!(configured(&[ok, refused]), Configured::Refused { cs: 0x11, error: 1, specific: 0 });
        assert_eq!(configured(&[other]), Configured::Unanswered);
        assert_eq!(configured(&[]), Configured::Unanswered);
    }

    #[test]
    fn a_selective_switch_is_the_four_parts_in_order() {
        let id = Identity { vendor: 1, product: 2, revision: 3, serial: 4 };
        let r = switch_selective(&id);
        assert_eq!(r[3].encode(), [0x43, 4, 0, 0, 0, 0, 0, 0]);
        assert_eq!(r[0].encode(), [0x40, 1, 0, 0, 0, 0, 0, 0]);
    }
}
