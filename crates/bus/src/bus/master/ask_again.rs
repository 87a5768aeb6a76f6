//! Reads asked again early within their window ([`SdoOptions::ask_again_after`]), and the
//! answers a batch that does so counts: more requests than answers is a lost frame, more
//! answers than requests a second device.

use super::active::Active;
use crate::bus::observer::Asked;
use crate::bus::reply::upload_answer;
use crate::canopen::ObjAddr;
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

/// Whether a job may be asked again early ([`SdoOptions::ask_again_after`]).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum AskAgain {
    Yes,
    No,
}

/// The reads of a batch that counts its answers, by node and object, once answered: the
/// answers to their other requests (a slow node's), and a second device's, are counted until
/// the last request's window closes.
pub(super) type Echoes = BTreeMap<(u8, ObjAddr), Asked>;

/// Whether answers to `asked` are still to come at `now`: fewer than requests, in the window.
pub(super) fn awaited(asked: &Asked, now: Instant) -> bool {
    asked.counted_until > now && asked.lost_frames()
}

/// A read `a` of `node` ended on `answer`, its first frame heard: where that answers the
/// read (a value, or a refusal), its answers are counted from now. Not counted: a read that
/// went on by segments or blocks (it took the answers to its other requests for repeats on
/// the way), nor one ended by a frame that answers something else (a segment of the
/// transfer before, late): either count would show a loss or a second device where there
/// was none.
pub(super) fn echo(echoes: &mut Echoes, node: u8, a: &Active, answer: &[u8], timeout: Duration) {
    let Some(first) = upload_answer(answer, a.client.addr()).filter(|_| a.client.is_upload()) else { return };
    let asked = Asked { requests: a.requests, answers: vec![first.carried()], counted_until: a.last_left + timeout };
    echoes.insert((node, a.client.addr()), asked);
}

/// Whether `request` starts a plain upload (command specifier 2, CiA 301).
pub(super) fn is_initiate_upload(request: &[u8; 8]) -> bool {
    request[0] == 0x40
}
