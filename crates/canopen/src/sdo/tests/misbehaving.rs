//! Misbehaving devices, byte by byte (issue 12): late, repeated, malformed and stale answers.

use super::*;

const MUX: [u8; 3] = [0x00, 0x20, 0x01];

/// An answer with A's multiplexer.
/// A frame as a device writes it: command byte, then the bytes after it.
fn segment(cmd: u8, data: &[u8]) -> [u8; 8] {
    let mut f = [0u8; 8];
    f[0] = cmd;
    f[1..1 + data.len()].copy_from_slice(data);
    f
}

fn answer(cmd: u8, data: &[u8]) -> Vec<u8> {
    let mut f = vec![cmd, MUX[0], MUX[1], MUX[2]];
    f.extend_from_slice(data);
    f
}

fn client_abort(r: Result<Step, SdoError>) -> (u32, String) {
    match r {
        Err(SdoError::ClientAbort { code, reason }) => (code, reason),
        other => panic!("expected a client abort, got {other:?}"),
    }
}

#[test]
fn short_expedited_answer_is_a_protocol_error_not_zeroes() {
    // Expedited, size indicated, 4 bytes (0x43) in a DLC-5 frame: three data bytes missing.
    let mut c = SdoClient::upload(A, false);
    c.start();
    let (code, reason) = client_abort(c.on_response(&answer(0x43, &[0x11])));
    assert_eq!(code, abort::GENERAL_ERROR);
    assert!(reason.contains("5-byte frame") && reason.contains("needs 8"), "{reason}");
    // Expedited, 2 bytes indicated (0x4B), only one present.
    let mut c = SdoClient::upload(A, false);
    c.start();
    client_abort(c.on_response(&answer(0x4B, &[0x11])));
    // Exactly the bytes the specifier makes meaningful is legal (seed 004: 0x4F in DLC 5).
    let mut c = SdoClient::upload(A, false);
    c.start();
    assert_eq!(c.on_response(&answer(0x4B, &[0x11, 0x22])).unwrap().done, Some(vec![0x11, 0x22]));
}

#[test]
fn short_segment_is_a_protocol_error() {
    let mut c = SdoClient::upload(A, false);
    c.start();
    c.on_response(&answer(0x41, &[20, 0, 0, 0])).unwrap();
    // t=0, n=0 (seven bytes), c=0 in a DLC-3 frame.
    let (code, reason) = client_abort(c.on_response(&[0x00, 0xAA, 0xBB]));
    assert_eq!(code, abort::GENERAL_ERROR);
    assert!(reason.contains("segment of 7 byte(s)") && reason.contains("3-byte frame"), "{reason}");
    // A last segment of two bytes (n=5) in a DLC-3 frame is complete.
    let mut c = SdoClient::upload(A, false);
    c.start();
    c.on_response(&answer(0x41, &[2, 0, 0, 0])).unwrap();
    assert_eq!(c.on_response(&[0x0B, 0xAA, 0xBB]).unwrap().done, Some(vec![0xAA, 0xBB]));
}

#[test]
fn short_answers_in_every_other_state_are_protocol_errors() {
    // A segmented upload answer with the size bit but no size.
    let mut c = SdoClient::upload(A, false);
    c.start();
    client_abort(c.on_response(&answer(0x41, &[9])));
    // An upload answer without its multiplexer.
    let mut c = SdoClient::upload(A, false);
    c.start();
    client_abort(c.on_response(&[0x40, 0x00]));
    // An abort without its code.
    let mut c = SdoClient::upload(A, false);
    c.start();
    client_abort(c.on_response(&answer(0x80, &[0x11, 0x00])));
    // A block download answer without its block size.
    let mut c = SdoClient::download(A, pattern(100), true);
    c.start();
    client_abort(c.on_response(&answer(0xA4, &[])));
    // A block acknowledgement without ackseq and blksize.
    let mut c = SdoClient::download(A, pattern(100), true);
    c.start();
    c.on_response(&answer(0xA4, &[127])).unwrap();
    client_abort(c.on_response(&[0xA2, 15]));
    // A block upload segment that is not the last, in a short frame.
    let mut c = SdoClient::upload(A, true);
    c.start();
    c.on_response(&answer(0xC2, &[20, 0, 0, 0])).unwrap();
    client_abort(c.on_response(&[0x01, 1, 2, 3]));
    // An empty frame.
    let mut c = SdoClient::upload(A, false);
    c.start();
    client_abort(c.on_response(&[]));
}

#[test]
fn block_upload_short_final_segment_counts_against_the_end_frame() {
    let data = pattern(10);
    let open = |c: &mut SdoClient| {
        c.start();
        c.on_response(&answer(0xC2, &[10, 0, 0, 0])).unwrap();
        c.on_response(&segment(0x01, &data[..7])).unwrap();
    };
    // Final segment with its three bytes in a DLC-4 frame; end frame n=4: complete.
    let mut c = SdoClient::upload(A, true);
    open(&mut c);
    let s = c.on_response(&[0x82, data[7], data[8], data[9]]).unwrap();
    assert_eq!(s.send, vec![segment(0xA2, &[2, 127])]);
    assert_eq!(c.on_response(&[0xC1 | 4 << 2]).unwrap().done, Some(data.clone()));
    // The same frame, but the end frame says five bytes of it are data (n=2).
    let mut c = SdoClient::upload(A, true);
    open(&mut c);
    c.on_response(&[0x82, data[7], data[8], data[9]]).unwrap();
    client_abort(c.on_response(&[0xC1 | 2 << 2]));
}

#[test]
fn expedited_without_size_takes_the_requested_type_or_four_bytes() {
    // e=1, s=0 (0x42): CiA 301 allows it; the data is as long as the type asked for.
    let mut c = SdoClient::upload(A, false).with_size_hint(Some(2));
    c.start();
    assert_eq!(c.on_response(&answer(0x42, &[0x34, 0x12, 0xEE, 0xEE])).unwrap().done, Some(vec![0x34, 0x12]));
    // ... which may come in a frame just long enough for it.
    let mut c = SdoClient::upload(A, false).with_size_hint(Some(1));
    c.start();
    assert_eq!(c.on_response(&answer(0x42, &[0x07])).unwrap().done, Some(vec![0x07]));
    // Type unknown: all four bytes.
    let mut c = SdoClient::upload(A, false);
    c.start();
    assert_eq!(c.on_response(&answer(0x42, &[1, 2, 3, 4])).unwrap().done, Some(vec![1, 2, 3, 4]));
    // Type unknown and a short frame: the four bytes are not all there.
    let mut c = SdoClient::upload(A, false);
    c.start();
    client_abort(c.on_response(&answer(0x42, &[1, 2])));
    // A type larger than four bytes cannot be expedited: the four bytes, for the caller to refuse.
    let mut c = SdoClient::upload(A, false).with_size_hint(Some(8));
    c.start();
    assert_eq!(c.on_response(&answer(0x42, &[1, 2, 3, 4])).unwrap().done, Some(vec![1, 2, 3, 4]));
}

#[test]
fn late_answer_for_another_object_is_set_aside() {
    // The answer to an earlier request (0x2000:2) that timed out arrives first.
    let mut c = SdoClient::upload(A, false);
    c.start();
    let s = c.on_response(&[0x43, 0x00, 0x20, 0x02, 1, 2, 3, 4]).unwrap();
    assert_eq!(s, Step { send: vec![], done: None, progress: false });
    assert_eq!(c.ignored(), Some((1, "an answer for object 0x2000:2, not 0x2000:1")));
    let s = c.on_response(&answer(0x4F, &[9])).unwrap();
    assert!(s.progress);
    assert_eq!(s.done, Some(vec![9]));
    // The same for a download and a block download.
    let mut c = SdoClient::download(A, vec![1], false);
    c.start();
    assert!(!c.on_response(&[0x60, 0x00, 0x20, 0x02, 0, 0, 0, 0]).unwrap().progress);
    assert_eq!(c.on_response(&answer(0x60, &[0, 0, 0, 0])).unwrap().done, Some(vec![]));
    let mut c = SdoClient::download(A, pattern(100), true);
    c.start();
    assert!(!c.on_response(&[0xA4, 0x00, 0x20, 0x02, 127, 0, 0, 0]).unwrap().progress);
    assert_eq!(c.on_response(&answer(0xA4, &[127, 0, 0, 0])).unwrap().send.len(), 15);
}

#[test]
fn duplicated_answers_are_set_aside() {
    let data = pattern(100);
    let mut od = Od::default().with(A, &data, true);
    // Every server answer delivered twice (CAN double reception), in each protocol.
    for block in [false, true] {
        let mut server = SdoServer::new(block);
        let mut c = SdoClient::upload(A, block);
        let mut to_server = vec![c.start()];
        let mut got = None;
        for _ in 0..100 {
            let answers: Vec<[u8; 8]> = to_server.drain(..).flat_map(|r| server.handle(&r, &mut od)).collect();
            for a in answers {
                let first = c.on_response(&a).unwrap();
                let second = c.on_response(&a).unwrap();
                assert!(!second.progress && second.send.is_empty() && second.done.is_none(), "block={block}");
                to_server.extend(first.send);
                if first.done.is_some() {
                    got = first.done;
                }
            }
            if got.is_some() {
                break;
            }
        }
        assert_eq!(got, Some(data.clone()), "block={block}");
    }
    // A segmented download with every acknowledgement twice.
    let mut od = Od::default().with(A, &[], true);
    let mut server = SdoServer::new(false);
    let mut c = SdoClient::download(A, data.clone(), false);
    let mut to_server = vec![c.start()];
    'outer: for _ in 0..100 {
        let answers: Vec<[u8; 8]> = to_server.drain(..).flat_map(|r| server.handle(&r, &mut od)).collect();
        for a in answers {
            let first = c.on_response(&a).unwrap();
            assert!(!c.on_response(&a).unwrap().progress);
            to_server.extend(first.send);
            if first.done.is_some() {
                break 'outer;
            }
        }
    }
    assert_eq!(od.0[&A].0, data);
}

#[test]
fn block_download_acked_zero_forever_ends_after_bounded_retransmissions() {
    let mut c = SdoClient::download(A, pattern(500), true);
    c.start();
    let first = c.on_response(&answer(0xA4, &[127])).unwrap();
    assert_eq!(first.send.len(), 72);
    let mut retransmissions = 0;
    let (code, reason) = loop {
        match c.on_response(&[0xA2, 0, 127, 0, 0, 0, 0, 0]) {
            Ok(step) => {
                assert!(!step.progress, "an ack of nothing is no progress");
                assert_eq!(step.send, first.send, "the same sub-block again");
                retransmissions += 1;
                assert!(retransmissions <= MAX_BLOCK_RETRANSMISSIONS, "retransmits without end");
            }
            Err(e) => break client_abort(Err(e)),
        }
    };
    assert_eq!(retransmissions, MAX_BLOCK_RETRANSMISSIONS);
    assert_eq!(code, abort::INVALID_SEQUENCE);
    assert!(reason.contains("acknowledged none") && reason.contains("ackseq 0"), "{reason}");
}

#[test]
fn block_download_partial_acks_are_progress() {
    // A lossy bus: each sub-block acknowledged only in part. Never counted against the bound.
    let data = pattern(2000);
    let mut c = SdoClient::download(A, data.clone(), true);
    c.start();
    let mut step = c.on_response(&answer(0xA4, &[127])).unwrap();
    let mut rounds = 0;
    while step.done.is_none() {
        rounds += 1;
        assert!(rounds < 1000);
        let last = *step.send.last().unwrap();
        step = if last[0] & 0xE3 == 0xC1 {
            c.on_response(&[0xA1, 0, 0, 0, 0, 0, 0, 0]).unwrap()
        } else {
            let n = step.send.len() as u8;
            let acked = if n > 1 { n / 2 } else { n };
            c.on_response(&[0xA2, acked, 127, 0, 0, 0, 0, 0]).unwrap()
        };
        assert!(step.progress);
    }
    assert!(rounds > MAX_BLOCK_RETRANSMISSIONS as usize + 1);
}

#[test]
fn block_upload_never_in_sequence_ends_after_bounded_retransmissions() {
    let mut c = SdoClient::upload(A, true);
    c.start();
    assert_eq!(c.on_response(&answer(0xC2, &[0, 4, 0, 0])).unwrap().send, vec![segment(0xA3, &[])]);
    // The device numbers every sub-block from 2: segment 1 never arrives.
    let mut acks = 0;
    let (code, reason) = 'device: loop {
        for seq in 2..=127u8 {
            match c.on_response(&segment(seq, &pattern(7))) {
                Ok(step) if seq < 127 => assert!(!step.progress && step.send.is_empty()),
                Ok(step) => {
                    assert_eq!(step.send, vec![segment(0xA2, &[0, 127])]);
                    assert!(!step.progress);
                    acks += 1;
                    assert!(acks <= MAX_BLOCK_RETRANSMISSIONS, "acknowledges without end");
                }
                Err(e) => break 'device client_abort(Err(e)),
            }
        }
    };
    assert_eq!(acks, MAX_BLOCK_RETRANSMISSIONS);
    assert_eq!(code, abort::INVALID_SEQUENCE);
    assert!(reason.contains("without segment 1"), "{reason}");
}

#[test]
fn endless_segmented_upload_stops_at_the_limit() {
    let mut c = SdoClient::upload(A, false).with_max_upload(100);
    c.start();
    c.on_response(&answer(0x40, &[])).unwrap(); // segmented, size not indicated
    let mut toggle = 0;
    let err = loop {
        match c.on_response(&segment(toggle, &pattern(7))) {
            Ok(step) => {
                assert!(step.done.is_none());
                toggle ^= 0x10;
            }
            Err(e) => break e,
        }
    };
    // Typed: the master aborts it with OUT_OF_MEMORY, the front end words it.
    assert_eq!(err, SdoError::OverLimit { limit: 100, received: 105 });
}

#[test]
fn upload_sending_more_than_announced_stops_there() {
    let mut c = SdoClient::upload(A, false);
    c.start();
    c.on_response(&answer(0x41, &[10, 0, 0, 0])).unwrap();
    c.on_response(&segment(0x00, &pattern(7))).unwrap();
    let (code, reason) = client_abort(c.on_response(&segment(0x10, &pattern(7))));
    assert_eq!(code, abort::GENERAL_ERROR);
    assert!(reason.contains("announced 10 bytes and sent more (14"), "{reason}");
    // By block transfer: a sub-block that goes on past the announced size.
    let mut c = SdoClient::upload(A, true);
    c.start();
    c.on_response(&answer(0xC2, &[10, 0, 0, 0])).unwrap();
    c.on_response(&segment(1, &pattern(7))).unwrap();
    client_abort(c.on_response(&segment(2, &pattern(7))));
}

#[test]
fn endless_block_upload_stops_at_the_limit() {
    let mut c = SdoClient::upload(A, true).with_max_upload(1000);
    c.start();
    c.on_response(&answer(0xC0, &[])).unwrap(); // no size
    let mut segments = 0;
    let err = 'device: loop {
        for seq in 1..=127u8 {
            segments += 1;
            if let Err(e) = c.on_response(&segment(seq, &pattern(7))) {
                break 'device e;
            }
        }
    };
    assert!(matches!(err, SdoError::OverLimit { limit: 1000, .. }), "{err:?}");
    assert_eq!(segments, 1000 / 7 + 1);
}

#[test]
fn endless_empty_segments_are_no_progress() {
    // n=7: a segment without data, not the last; the toggle alternates as it should.
    let mut c = SdoClient::upload(A, false);
    c.start();
    c.on_response(&answer(0x40, &[])).unwrap();
    assert!(!c.on_response(&[0x0E]).unwrap().progress);
    assert!(!c.on_response(&[0x1E]).unwrap().progress);
    assert!(c.on_response(&segment(0x00, &pattern(7))).unwrap().progress);
}

#[test]
fn answers_after_the_end_are_set_aside() {
    let mut c = SdoClient::upload(A, false);
    c.start();
    c.on_response(&answer(0x4F, &[1])).unwrap();
    assert!(!c.on_response(&answer(0x4F, &[2])).unwrap().progress);
}

#[test]
fn time_budget_follows_the_size() {
    let t = std::time::Duration::from_millis(500);
    // Expedited download: set-up only, plus one segment's worth.
    assert_eq!(SdoClient::download(A, vec![1, 2], false).time_budget(t), t * 4 + t / 2);
    // 700 bytes: 100 segments.
    assert_eq!(SdoClient::download(A, pattern(700), true).time_budget(t), t * 4 + t * 50);
    // An upload of unknown size is bounded by its limit until the device announces one.
    let mut c = SdoClient::upload(A, false).with_max_upload(70);
    assert_eq!(c.time_budget(t), t * 4 + t * 5);
    c.start();
    c.on_response(&answer(0x41, &[14, 0, 0, 0])).unwrap();
    assert_eq!(c.time_budget(t), t * 4 + t);
}

#[test]
fn second_copy_of_the_previous_transfers_answer_is_set_aside() {
    // A write's answer (0x60) arrived twice; the second copy reaches the read-back.
    let written = answer(0x60, &[0, 0, 0, 0]);
    let mut c = SdoClient::upload(A, false);
    c.set_previous_answer(&written);
    c.start();
    let s = c.on_response(&written).unwrap();
    assert!(!s.progress && s.send.is_empty() && s.done.is_none());
    assert!(c.ignored().unwrap().1.contains("previous transfer's last answer"));
    assert_eq!(c.on_response(&answer(0x4F, &[7])).unwrap().done, Some(vec![7]));
    // The last segment of an earlier upload, before a download's answer.
    let mut c = SdoClient::download(A, vec![1, 2], false);
    c.set_previous_answer(&[0x0B, 1, 2]);
    c.start();
    assert!(!c.on_response(&[0x0B, 1, 2]).unwrap().progress);
    assert_eq!(c.on_response(&answer(0x60, &[0, 0, 0, 0])).unwrap().done, Some(vec![]));
    // Any other answer of the wrong kind is an error (a corrupted command byte).
    let mut c = SdoClient::upload(A, false);
    c.set_previous_answer(&written);
    c.start();
    let (code, _) = client_abort(c.on_response(&answer(0xBC, &[1, 2, 3, 4])));
    assert_eq!(code, abort::UNKNOWN_COMMAND);
    // An identical answer that is right for this transfer is taken (polling one object).
    let mut c = SdoClient::upload(A, false);
    c.set_previous_answer(&answer(0x4F, &[7]));
    c.start();
    assert_eq!(c.on_response(&answer(0x4F, &[7])).unwrap().done, Some(vec![7]));
}

/// A device whose object holds 4 GiB + 10 bytes, more than the 32-bit size of CiA 301 can
/// carry. Its low 32 bits say 10: announcing that would be a lie the client cannot see
/// through, so the size goes unannounced and the client's limit ends the transfer.
/// (The zeroes are never touched: the allocation costs address space, not memory.)
#[cfg(all(target_os = "linux", target_pointer_width = "64"))]
#[test]
fn an_object_over_4_gib_is_announced_without_a_size_never_as_its_low_32_bits() {
    struct Huge;
    impl ObjectAccess for Huge {
        fn read(&mut self, _: ObjAddr) -> Result<Vec<u8>, u32> {
            Ok(vec![0; (1 << 32) + 10])
        }
        fn write(&mut self, _: ObjAddr, _: &[u8]) -> Result<(), u32> {
            Err(abort::READ_ONLY)
        }
        fn check_write(&self, _: ObjAddr, _: Option<usize>) -> Result<(), u32> {
            Err(abort::READ_ONLY)
        }
    }
    for block in [false, true] {
        let mut server = SdoServer::new(true);
        let mut c = SdoClient::upload(A, block).with_max_upload(1000);
        let mut to_client = server.handle(&c.start(), &mut Huge);
        // Not 41 00 20 01 0A 00 00 00 (or C6 ... 0A 00 00 00).
        let unsized_answer = if block { 0xC4 } else { 0x40 };
        assert_eq!(to_client, vec![[unsized_answer, 0x00, 0x20, 0x01, 0, 0, 0, 0]], "block: {block}");
        let err = 'transfer: loop {
            let mut to_server = Vec::new();
            for f in to_client.drain(..) {
                match c.on_response(&f) {
                    Ok(step) => to_server.extend(step.send),
                    Err(e) => break 'transfer e,
                }
            }
            assert!(!to_server.is_empty(), "block: {block}: stalled");
            for f in to_server {
                to_client.extend(server.handle(&f, &mut Huge));
            }
        };
        assert!(matches!(err, SdoError::OverLimit { limit: 1000, .. }), "block: {block}: {err:?}");
    }
}

/// A restarted transfer (`SdoClient::restart`, after a timeout): the caller aborted the
/// first attempt and starts again. What the first attempt still gets must not be taken for
/// the new attempt's answers.
mod restart {
    use super::*;

    const NAME: ObjAddr = ObjAddr::new(0x1008, 0);

    fn od() -> Od {
        Od::default().with(NAME, b"CAN-2000C I/O module", false).with(A, &[0, 0], true)
    }

    /// The transfer run to its end from `first`, each answer delivered once: what it
    /// finished with (the data read; empty for a download), if it finished.
    fn finish(client: &mut SdoClient, server: &mut SdoServer, od: &mut Od, first: [u8; 8]) -> Option<Vec<u8>> {
        let mut to_server = vec![first];
        let mut got = None;
        while let Some(req) = to_server.pop() {
            for resp in server.handle(&req, od) {
                let step = client.on_response(&resp).unwrap();
                to_server.extend(step.send);
                got = got.or(step.done);
            }
        }
        got
    }

    #[test]
    fn a_lost_request_is_sent_again_and_the_read_finishes() {
        let (mut server, mut od) = (SdoServer::new(false), od());
        let mut client = SdoClient::upload(NAME, false);
        let first = client.start();
        // Lost on the way: the server never sees it. Timeout, abort, again.
        assert!(server.handle(&abort_frame(NAME, abort::TIMED_OUT), &mut od).is_empty());
        let again = client.restart();
        assert_eq!(again, first);
        let got = finish(&mut client, &mut server, &mut od, again);
        assert_eq!(got.unwrap(), b"CAN-2000C I/O module");
    }

    #[test]
    fn a_late_segment_of_the_abandoned_attempt_is_set_aside_by_its_command_and_toggle() {
        let (mut server, mut od) = (SdoServer::new(false), od());
        let mut client = SdoClient::upload(NAME, false);
        let init = server.handle(&client.start(), &mut od);
        let seg_request = client.on_response(&init[0]).unwrap().send;
        // The answer with the first segment (toggle 0) comes late, after the timeout.
        let late = server.handle(&seg_request[0], &mut od);
        assert_eq!(late[0][0] & 0xE0, 0x00);
        assert!(server.handle(&abort_frame(NAME, abort::TIMED_OUT), &mut od).is_empty());
        let again = client.restart();
        // The late segment arrives while the new attempt waits for its initiation answer.
        let step = client.on_response(&late[0]).unwrap();
        assert!(step.send.is_empty() && step.done.is_none() && !step.progress);
        assert!(client.ignored().unwrap().1.contains("abandoned"));
        // Then the new attempt runs to the end; its own first segment, the same bytes as the
        // late one, is not mistaken for a repeat of it.
        let got = finish(&mut client, &mut server, &mut od, again);
        assert_eq!(got.unwrap(), b"CAN-2000C I/O module");
    }

    #[test]
    fn a_late_answer_to_the_abandoned_initiation_and_its_duplicate_move_the_read_once() {
        let (mut server, mut od) = (SdoServer::new(false), od());
        let mut client = SdoClient::upload(NAME, false);
        let first = client.start();
        let late = server.handle(&first, &mut od);
        // Timeout; the abort and the new request reach the server after it answered.
        assert!(server.handle(&abort_frame(NAME, abort::TIMED_OUT), &mut od).is_empty());
        let again = client.restart();
        let answer = server.handle(&again, &mut od);
        assert_eq!(answer, late, "the same answer to the same request");
        // The late answer is this object's initiation answer: the read goes on from it ...
        let step = client.on_response(&late[0]).unwrap();
        assert!(step.progress);
        let mut to_server = step.send;
        // ... and the new attempt's own answer, the same bytes again, is a repeat.
        let step = client.on_response(&answer[0]).unwrap();
        assert!(!step.progress && step.send.is_empty());
        let mut got = None;
        while let Some(req) = to_server.pop() {
            for resp in server.handle(&req, &mut od) {
                let step = client.on_response(&resp).unwrap();
                to_server.extend(step.send);
                got = got.or(step.done);
            }
        }
        assert_eq!(got.unwrap(), b"CAN-2000C I/O module");
    }

    #[test]
    fn a_lost_answer_to_a_plain_write_writes_the_same_value_again() {
        let (mut server, mut od) = (SdoServer::new(false), od());
        let mut client = SdoClient::download(A, vec![0xE8, 0x03], true);
        let first = client.start();
        // Done by the server; its answer is lost.
        assert_eq!(server.handle(&first, &mut od).len(), 1);
        assert!(server.handle(&abort_frame(A, abort::TIMED_OUT), &mut od).is_empty());
        let again = client.restart();
        assert_eq!(again, first);
        let answer = server.handle(&again, &mut od);
        assert_eq!(client.on_response(&answer[0]).unwrap().done, Some(vec![]));
        assert_eq!(od.read(A).unwrap(), vec![0xE8, 0x03]);
    }

    #[test]
    fn a_segmented_write_restarts_from_its_first_segment_past_a_late_acknowledgement() {
        let (mut server, mut od) = (SdoServer::new(false), od());
        let data: Vec<u8> = (1..=20).collect();
        let od_addr = A;
        let mut client = SdoClient::download(od_addr, data.clone(), false);
        let init = server.handle(&client.start(), &mut od);
        let seg0 = client.on_response(&init[0]).unwrap().send;
        // The acknowledgement of segment 0 (toggle 0) comes late.
        let late = server.handle(&seg0[0], &mut od);
        assert_eq!(late[0][0], 0x20);
        assert!(server.handle(&abort_frame(od_addr, abort::TIMED_OUT), &mut od).is_empty());
        let again = client.restart();
        assert!(!client.on_response(&late[0]).unwrap().progress);
        assert!(finish(&mut client, &mut server, &mut od, again).is_some());
        assert_eq!(od.read(od_addr).unwrap(), data);
    }

    #[test]
    fn the_servers_timeout_of_the_abandoned_attempt_is_not_the_new_attempts_refusal() {
        let mut client = SdoClient::upload(NAME, false);
        client.start();
        client.restart();
        let step = client.on_response(&abort_frame(NAME, abort::TIMED_OUT)).unwrap();
        assert!(!step.progress);
        // A refusal of the new attempt is one.
        assert_eq!(
            client.on_response(&abort_frame(NAME, abort::NO_OBJECT)),
            Err(SdoError::ServerAbort(abort::NO_OBJECT))
        );
    }

    #[test]
    fn a_block_read_restarts_as_a_block_read_unless_the_server_refused_block() {
        let mut client = SdoClient::upload(NAME, true);
        let first = client.start();
        assert_eq!(client.restart(), first);
        // A server without block transfer: the retry asks for a plain upload.
        client.on_response(&abort_frame(NAME, abort::UNKNOWN_COMMAND)).unwrap();
        assert!(client.fell_back());
        assert_eq!(client.restart()[0], 0x40);
    }
}

/// A device rebooted in the middle of a block upload of 0x1F50:1 and aborted the rest
/// (0x05040001) late, into the read of 0x1000:0 that followed: an abort carries the object
/// it ends (CiA 301), and one for another object is not this transfer's answer.
#[test]
fn an_abort_for_another_object_is_not_this_transfers_answer() {
    let stale = [0x80, 0x50, 0x1F, 0x01, 0x01, 0x00, 0x04, 0x05];
    let mut c = SdoClient::upload(ObjAddr::new(0x1000, 0), false);
    c.start();
    assert!(!c.on_response(&stale).unwrap().progress);
    assert_eq!(c.ignored(), Some((1, "an answer for object 0x1F50:1, not 0x1000:0")));
    let s = c.on_response(&[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]).unwrap();
    assert_eq!(s.done, Some(vec![0x92, 0x01, 0x02, 0x00]));
    // Inside a sub-block of a block upload of our own, likewise.
    let mut c = SdoClient::upload(A, true);
    c.start();
    assert_eq!(c.on_response(&[0xC6, 0x00, 0x20, 0x01, 10, 0, 0, 0]).unwrap().send.len(), 1);
    assert!(!c.on_response(&stale).unwrap().progress);
    // Our own abort, and one that names no object (some servers leave it empty), end it.
    let mut c = SdoClient::upload(A, false);
    c.start();
    assert!(matches!(
        c.on_response(&[0x80, 0x00, 0x20, 0x01, 0x00, 0x00, 0x02, 0x06]),
        Err(SdoError::ServerAbort(0x0602_0000))
    ));
    let mut c = SdoClient::upload(A, false);
    c.start();
    assert!(matches!(c.on_response(&[0x80, 0, 0, 0, 0x00, 0x00, 0x02, 0x06]), Err(SdoError::ServerAbort(0x0602_0000))));
}
