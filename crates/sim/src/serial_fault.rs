//! Faults the simulator's serial device sides (EPOS2, slcan adapter) inject for tests:
//! `KIND@N` on the N-th command frame, `KIND@*` on every one.

use std::str::FromStr;
use std::time::Duration;

/// What goes wrong with a command frame of a simulated EPOS2's serial link.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaultKind {
    /// RS232: answer 'F' to the frame. USB: answer with error 0x05040004 (CRC error).
    Nack,
    /// Corrupt the answer's CRC.
    Crc,
    /// Send junk bytes before the answer.
    Garbage,
    /// Leave the last byte of the answer out.
    Drop,
    /// Do not answer at all.
    Mute,
    /// Before the answer, one left over in the line from an earlier client (the answer to
    /// its ReadObject of 0x1000:0, a client killed before it read it).
    Stale,
    /// Answer late, as a gateway does that waits on a slow node (`LATE`).
    Late,
    /// Instead of the answer, bytes without pause and without a frame (`BABBLE_TIME`).
    Babble,
    /// Answer SegmentRead with a segment of no data that says more follow.
    EmptySegments,
    /// Answer SegmentRead with a full segment that says more follow, whatever the object.
    EndlessSegments,
    /// A forwarded SDO request is first answered on the CAN bus for another object and by
    /// another node; the gateway must wait for the answer to its own request.
    WrongObject,
}

/// How late a `late` answer comes: longer than canctl's default timeout.
pub const LATE: Duration = Duration::from_millis(800);
/// How long a `babble` fault talks.
pub const BABBLE_TIME: Duration = Duration::from_secs(30);

/// A fault on the n-th command frame (counting from 1), or on every one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fault {
    /// What goes wrong.
    pub kind: FaultKind,
    /// The frame it hits (counting from 1); `None`: every frame.
    pub nth: Option<u64>,
}

impl FromStr for Fault {
    type Err = String;

    /// `crc@3` (the third frame), `nack@*` (every frame), `mute` (the first frame).
    fn from_str(s: &str) -> std::result::Result<Fault, String> {
        let (kind, at) = s.split_once('@').unwrap_or((s, "1"));
        let kind = match kind {
            "nack" => FaultKind::Nack,
            "crc" => FaultKind::Crc,
            "garbage" => FaultKind::Garbage,
            "drop" => FaultKind::Drop,
            "mute" => FaultKind::Mute,
            "stale" => FaultKind::Stale,
            "late" => FaultKind::Late,
            "babble" => FaultKind::Babble,
            "empty-segments" => FaultKind::EmptySegments,
            "endless-segments" => FaultKind::EndlessSegments,
            "wrong-object" => FaultKind::WrongObject,
            k => {
                return Err(format!(
                    "'{k}' is not a fault: use nack, crc, garbage, drop, mute, stale, late, babble, \
                     empty-segments, endless-segments or wrong-object"
                ))
            }
        };
        let bad = || format!("'{at}' is not a frame number (1, 2, ... or *)");
        let nth = if at == "*" { None } else { Some(at.parse::<u64>().ok().filter(|n| *n > 0).ok_or_else(bad)?) };
        Ok(Fault { kind, nth })
    }
}
