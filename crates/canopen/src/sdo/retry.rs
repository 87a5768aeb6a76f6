//! What to do when an SDO transfer gets no answer in time: a lost frame (a request or an
//! answer: USB adapters and gateways drop frames under load) is retried, not waited out,
//! unless repeating the transfer could do something twice.
//!
//! Reads and writes of plain values are idempotent: the transfer is aborted (so that the
//! server forgets it) and started again from its first request. A write that is an
//! *action* — the device does something when it receives it — is never repeated once the
//! request that completes it has gone out: the server may have received it and its answer
//! been lost. Its outcome is then read back where a read-back can tell, else reported as
//! unknown.
//!
//! A node that never answered anything in this session is retried all the same: each
//! command is a session of its own, so the first request of a one-shot read has no earlier
//! answer to go by, and a frame lost on the way (2 % on a loaded adapter) would end it
//! with exit 3. An unreachable node costs every retry (`DEFAULT_RETRIES` + 1 timeouts),
//! and its message says so ("no answer to 3 requests, 1.5 s in all"); a scan, which asks
//! nodes that mostly are not there, asks without retries.

use super::SdoClient;
use crate::ObjAddr;

/// Retries after the first attempt, per transfer, unless the caller says otherwise.
pub const DEFAULT_RETRIES: u8 = 2;

/// The objects whose write is an action, with what it does: the one list (CiA 301, CiA
/// 302). Manufacturer-specific actions are for a dictionary to mark (not yet read from
/// EDS files). Not in the list, and why:
/// - 0x1F50 program data (CiA 302-3): a download restarted from its first byte replaces the
///   partial one; the bootloader acts on 0x1F51, not on the data.
/// - 0x1029 error behaviour, 0x1F80 NMT start-up: settings, written again to the same value.
/// - 0x6040 controlword (CiA 402): state transitions are commands on levels, and the fault
///   reset acts on a rising edge; the same word written twice is one command.
const ACTIONS: &[(u16, &str)] = &[
    (0x1010, "store parameters (CiA 301)"),
    (0x1011, "restore default parameters (CiA 301)"),
    (0x1F25, "configuration request (CiA 302-2)"),
    (0x1F51, "program control (CiA 302-3)"),
    (0x1F82, "request NMT (CiA 302-2)"),
];

/// What writing `addr` does when it is an action, `None` for a plain value.
pub fn action(addr: ObjAddr) -> Option<&'static str> {
    ACTIONS.iter().find(|(index, _)| *index == addr.index).map(|(_, what)| *what)
}

/// What to do with a transfer that ran out of time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OnTimeout {
    /// Abort it and start it again.
    Again,
    /// Report that the device did not answer (nothing it may have done is left unsaid).
    GiveUp,
    /// An action whose completing request went out without an answer: it may have been
    /// done. Read back (`read_back`) or report the outcome as unknown; never repeat it.
    Unknown,
}

/// The decision for `client`, which ran out of time with `retries_left` retries left.
pub fn on_timeout(client: &SdoClient, retries_left: u8) -> OnTimeout {
    let may_have_acted = !client.is_upload() && action(client.addr()).is_some() && client.completing_request_sent();
    match (may_have_acted, retries_left) {
        (true, _) => OnTimeout::Unknown,
        (false, 0) => OnTimeout::GiveUp,
        (false, _) => OnTimeout::Again,
    }
}

/// After an action's answer was lost: the object to read that tells whether `written`
/// took effect, and the value that says it did. Program control reads back its state
/// (CiA 302-3: stop 0 reads 0 "stopped", start 1 reads 1 "started", clear 3 reads 3 "no
/// program"); a reset (2) ends started like a program never stopped, and a store or
/// restore leaves nothing to read.
pub fn read_back(addr: ObjAddr, written: &[u8]) -> Option<(ObjAddr, Vec<u8>)> {
    match (addr.index, written) {
        (0x1F51, [v @ (0 | 1 | 3)]) => Some((addr, vec![*v])),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAVE: ObjAddr = ObjAddr::new(0x1010, 1);
    const HEARTBEAT: ObjAddr = ObjAddr::new(0x1017, 0);

    #[test]
    fn reads_and_plain_writes_are_retried_until_the_retries_are_spent() {
        let mut read = SdoClient::upload(HEARTBEAT, false);
        read.start();
        assert_eq!(on_timeout(&read, 2), OnTimeout::Again);
        assert_eq!(on_timeout(&read, 0), OnTimeout::GiveUp);
        let mut write = SdoClient::download(HEARTBEAT, vec![0xE8, 0x03], true);
        write.start();
        assert_eq!(on_timeout(&write, 1), OnTimeout::Again);
        // Program data restarts from its first byte.
        let mut program = SdoClient::download(ObjAddr::new(0x1F50, 1), vec![0; 100], true);
        program.start();
        assert_eq!(on_timeout(&program, 1), OnTimeout::Again);
    }

    #[test]
    fn an_action_sent_whole_is_never_repeated() {
        let mut store = SdoClient::download(SAVE, b"save".to_vec(), true);
        store.start();
        assert_eq!(on_timeout(&store, 2), OnTimeout::Unknown);
        assert_eq!(on_timeout(&store, 0), OnTimeout::Unknown);
    }

    #[test]
    fn an_action_not_yet_sent_whole_may_start_again() {
        // Segmented: the device acts on the last segment; the initiation alone does nothing.
        let mut request = SdoClient::download(ObjAddr::new(0x1F82, 5), vec![5; 12], false);
        request.start();
        assert_eq!(on_timeout(&request, 1), OnTimeout::Again);
        // Initiation answered: the first segment (7 of 12 bytes) goes out, not yet the last.
        let step = request.on_response(&[0x60, 0x82, 0x1F, 5, 0, 0, 0, 0]).unwrap();
        assert_eq!(step.send.len(), 1);
        assert_eq!(on_timeout(&request, 1), OnTimeout::Again);
        // Acknowledged: the last segment goes out, and from now on it may have been done.
        request.on_response(&[0x20, 0, 0, 0, 0, 0, 0, 0]).unwrap();
        assert_eq!(on_timeout(&request, 1), OnTimeout::Unknown);
    }

    #[test]
    fn program_control_reads_back_what_a_read_can_tell() {
        let control = ObjAddr::new(0x1F51, 1);
        assert_eq!(read_back(control, &[1]), Some((control, vec![1])));
        assert_eq!(read_back(control, &[0]), Some((control, vec![0])));
        assert_eq!(read_back(control, &[2]), None);
        assert_eq!(read_back(SAVE, b"save"), None);
        assert_eq!(action(HEARTBEAT), None);
        assert!(action(SAVE).unwrap().contains("store"));
    }
}
