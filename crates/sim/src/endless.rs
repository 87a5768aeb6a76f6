//! SDO servers that never finish, as misbehaving real devices do: an upload whose segments
//! never end (no size announced, the last-segment bit never set), a block upload whose
//! sub-blocks never end, and a block download whose every sub-block is acknowledged as
//! "nothing received" (sequence 0). A device with one of these faults answers the requests
//! of that kind from here instead of from its object dictionary; everything else it answers
//! as before.

use crate::canopen::sdo::wire::{BlockSegment, Initiate, Request, Response, Segment};
use crate::canopen::sdo::{pad, MAX_BLOCK_SIZE, SEGMENT_DATA};

/// Which transfers never finish.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Endless {
    /// An upload is answered as segmented of unstated size; its segments never end.
    Segments,
    /// A block upload announces no size; its sub-blocks never end.
    Block,
    /// A block download: every sub-block is acknowledged with sequence 0, so the client
    /// sends it again, for ever if it lets itself.
    AckZero,
}

/// The transfer an endless server is in.
#[derive(Debug, Default)]
pub(crate) struct EndlessServer {
    state: State,
}

#[derive(Debug, Default, Clone, Copy, PartialEq)]
enum State {
    #[default]
    Idle,
    /// A segmented upload under way (the toggle is the client's, echoed).
    Segments,
    /// A block upload: sub-blocks of this many segments, sent after start and each ack.
    Block { blksize: u8 },
    /// A block download: the sub-block size given to the client.
    Download { blksize: u8 },
}

/// The bytes every endless upload is made of: a name that goes on and on.
const FILLER: &[u8; SEGMENT_DATA] = b"ENDLESS";

impl EndlessServer {
    /// Whether `request` (a payload sent to the device's SDO server) starts a transfer that
    /// a fault of `kind` never finishes.
    pub(crate) fn starts(kind: Endless, request: &[u8]) -> bool {
        matches!(
            (kind, Request::parse(&pad(request))),
            (Endless::Segments, Some(Request::InitiateUpload { .. }))
                | (Endless::Block, Some(Request::BlockUpload { .. }))
                | (Endless::AckZero, Some(Request::BlockDownload { .. }))
        )
    }

    /// Whether a never-ending transfer is under way.
    pub(crate) fn busy(&self) -> bool {
        self.state != State::Idle
    }

    /// The answers to `request` when it starts a transfer of `kind` or goes on with the one
    /// under way; `None` (and no transfer under way any more) when it is for the device's
    /// own server.
    pub(crate) fn answer(&mut self, kind: Endless, request: &[u8]) -> Option<Vec<[u8; 8]>> {
        let p = pad(request);
        // Inside a block download sub-block every frame is a segment, whatever its first byte.
        if let State::Download { blksize } = self.state {
            let segment = BlockSegment::parse(&p);
            if matches!(Request::parse(&p), Some(Request::Abort { .. })) {
                self.state = State::Idle;
                return Some(Vec::new());
            }
            let ack = segment.seqno == blksize || segment.last;
            return Some(if ack { vec![Response::BlockDownloadAck { ackseq: 0, blksize }.emit()] } else { Vec::new() });
        }
        let answers = match (Request::parse(&p), self.state) {
            (Some(Request::Abort { .. }), State::Segments | State::Block { .. }) => {
                self.state = State::Idle;
                Vec::new()
            }
            (Some(Request::UploadSegment { toggle }), State::Segments) => {
                vec![Response::UploadSegment(Segment::new(toggle, FILLER, false)).emit()]
            }
            (Some(Request::BlockUploadStart), State::Block { blksize }) => sub_block(blksize),
            (Some(Request::BlockUploadAck { blksize, .. }), State::Block { .. }) => {
                let blksize = blksize.clamp(1, MAX_BLOCK_SIZE);
                self.state = State::Block { blksize };
                sub_block(blksize)
            }
            (Some(Request::InitiateUpload { addr }), _) if kind == Endless::Segments => {
                self.state = State::Segments;
                vec![Response::InitiateUpload { addr, init: Initiate::Unsized }.emit()]
            }
            (Some(Request::BlockUpload { addr, blksize, .. }), _) if kind == Endless::Block => {
                self.state = State::Block { blksize: blksize.clamp(1, MAX_BLOCK_SIZE) };
                vec![Response::BlockUpload { addr, crc: false, size: None }.emit()]
            }
            (Some(Request::BlockDownload { addr, .. }), _) if kind == Endless::AckZero => {
                let blksize = MAX_BLOCK_SIZE;
                self.state = State::Download { blksize };
                vec![Response::BlockDownload { addr, crc: false, blksize }.emit()]
            }
            _ => {
                self.state = State::Idle;
                return None;
            }
        };
        Some(answers)
    }
}

/// One sub-block of an endless block upload: never the last.
fn sub_block(blksize: u8) -> Vec<[u8; 8]> {
    (1..=blksize).map(|seqno| BlockSegment::new(seqno, FILLER, false).emit()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canopen::sdo::client::SdoClient;
    use crate::canopen::ObjAddr;

    const NAME: ObjAddr = ObjAddr::new(0x1008, 0);

    /// Runs `client` against an endless server of `kind`: the client's end, and how many
    /// requests it sent before it.
    fn run(kind: Endless, mut client: SdoClient) -> (String, usize) {
        let mut server = EndlessServer::default();
        let first = client.start();
        assert!(EndlessServer::starts(kind, &first));
        let mut pending = vec![first];
        for sent in 1..100_000 {
            let request = pending.remove(0);
            let answers = server.answer(kind, &request).unwrap_or_else(|| panic!("not answered: {request:02X?}"));
            for answer in answers {
                match client.on_response(&answer) {
                    Ok(step) if step.done.is_some() => return ("done".into(), sent),
                    Ok(step) => pending.extend(step.send),
                    Err(e) => return (format!("{e:?}"), sent),
                }
            }
            if pending.is_empty() {
                return ("the client stopped asking".into(), sent);
            }
        }
        panic!("the client never stopped");
    }

    #[test]
    fn a_segmented_upload_without_end_stops_at_the_clients_limit() {
        let (end, sent) = run(Endless::Segments, SdoClient::upload(NAME, false).with_max_upload(255));
        assert_eq!(end, "OverLimit { limit: 255, received: 259 }");
        // The initiation, then a segment per seven bytes up to the limit and one past it.
        assert_eq!(sent, 1 + 255 / SEGMENT_DATA + 1);
    }

    #[test]
    fn a_block_upload_without_end_stops_at_the_clients_limit() {
        let (end, _) = run(Endless::Block, SdoClient::upload(NAME, true).with_max_upload(4096));
        assert!(end.starts_with("OverLimit { limit: 4096,"), "{end}");
    }

    #[test]
    fn a_block_download_acknowledged_with_sequence_0_gives_up() {
        let (end, sent) = run(Endless::AckZero, SdoClient::download(NAME, vec![7; 3000], true));
        assert!(!end.contains("done"), "{end}");
        assert!(sent < 2_000, "{sent} requests");
    }
}
