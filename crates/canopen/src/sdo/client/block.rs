//! Block transfer (CiA 301 7.2.4.3.9 ff.) of the SDO client: sub-blocks, their
//! acknowledgements and the CRC, both ways.

use super::super::shared::{block_crc, block_segment_count, block_segments, block_unused_in_last};
use super::super::wire::{BlockSegment, Request, Response};
use super::*;

impl SdoClient {
    pub(super) fn block_upload_initiated(&mut self, p: &[u8; 8], response: Response) -> Result<Step, SdoError> {
        match response {
            // The server used the protocol switch threshold: plain upload from here.
            Response::InitiateUpload { addr, .. } => {
                self.require(4, "an upload answer")?;
                if let Some(step) = self.other_object(addr) {
                    return Ok(step);
                }
                self.state = State::UploadInit;
                self.upload_initiated(p, response)
            }
            Response::BlockUpload { addr, crc, size } => {
                self.require(4, "a block upload answer")?;
                if let Some(step) = self.other_object(addr) {
                    return Ok(step);
                }
                self.crc = crc;
                if let Some(size) = size {
                    self.require(8, "a block upload answer with its size")?;
                    self.announce(size)?;
                }
                self.blksize = UPLOAD_BLOCK_SIZE;
                self.state = State::BlockUploadData { expected: 1 };
                Ok(Step::send(vec![Request::BlockUploadStart.emit()]))
            }
            _ => self.not_for_this_transfer(p),
        }
    }

    pub(super) fn block_upload_segment(&mut self, seg: BlockSegment, expected: u8) -> Result<Step, SdoError> {
        let BlockSegment { seqno: seq, last, data } = seg;
        // Only the final segment may come short: how much of it is data, the end frame says.
        if !last {
            self.require(8, &format!("block segment {seq}"))?;
        }
        let in_order = seq == expected;
        let mut expected = expected;
        if in_order {
            let len = self.last.map_or(8, |(_, len)| len);
            self.buf.extend_from_slice(&data[..len - 1]);
            if last {
                self.tail_missing = 8 - len;
            } else {
                self.check_received(self.buf.len())?;
            }
            expected += 1;
        }
        if seq != self.blksize && !last {
            self.state = State::BlockUploadData { expected };
            if in_order {
                return Ok(Step::wait());
            }
            return Ok(self.ignore(format!("block segment {seq} where segment {expected} was due")));
        }
        // End of a sub-block. Lost or repeated segments were not stored; the acknowledgement
        // tells the server the last one received in order, and it repeats from there.
        let received = expected - 1;
        self.count_fruitless(received > 0, |n| {
            format!(
                "the device sent {n} sub-blocks in a row without segment 1 in sequence \
                 (the last one ended with segment {seq})"
            )
        })?;
        let ack = Request::BlockUploadAck { ackseq: received, blksize: self.blksize }.emit();
        self.state = if last && in_order { State::BlockUploadEnd } else { State::BlockUploadData { expected: 1 } };
        Ok(if received == 0 { Step::retry(vec![ack]) } else { Step::send(vec![ack]) })
    }

    /// Count a sub-block that moved no data: past `MAX_BLOCK_RETRANSMISSIONS` in a row the
    /// transfer ends, for the reason `why` gives for that count.
    fn count_fruitless(&mut self, moved: bool, why: impl FnOnce(u32) -> String) -> Result<(), SdoError> {
        if moved {
            self.fruitless = 0;
            return Ok(());
        }
        self.fruitless += 1;
        if self.fruitless > MAX_BLOCK_RETRANSMISSIONS {
            let reason = why(self.fruitless);
            return Err(self.fail(abort::INVALID_SEQUENCE, reason));
        }
        Ok(())
    }

    pub(super) fn block_upload_end(&mut self, p: &[u8; 8], response: Response) -> Result<Step, SdoError> {
        let Response::BlockUploadEnd { unused: n, crc: got } = response else { return Err(self.unexpected(p)) };
        self.require(if self.crc { 3 } else { 1 }, "the block upload end")?;
        self.state = State::Finished;
        let n = n as usize;
        if n < self.tail_missing {
            return Err(self.fail(
                abort::GENERAL_ERROR,
                format!(
                    "the last block segment came {} byte(s) short of the data the end frame counts",
                    self.tail_missing - n
                ),
            ));
        }
        let unused = n - self.tail_missing;
        if unused > self.buf.len() {
            return Err(self.fail(abort::GENERAL_ERROR, "block end claims more unused bytes than were sent"));
        }
        self.buf.truncate(self.buf.len() - unused);
        self.check_received(self.buf.len())?;
        if self.crc {
            let want = block_crc(&self.buf);
            if got != want {
                return Err(self
                    .fail(abort::CRC_ERROR, format!("block CRC 0x{got:04X} does not match the data (0x{want:04X})")));
            }
        }
        self.finish_upload(vec![Request::BlockUploadEnd.emit()])
    }

    /// Send the next sub-block, starting at the first unconfirmed segment.
    pub(super) fn send_block(&mut self) -> Vec<[u8; 8]> {
        let first = self.pos / SEGMENT_DATA;
        let count = (block_segment_count(self.buf.len()) - first).min(self.blksize as usize);
        self.state = State::BlockDownloadData { in_block: count };
        block_segments(&self.buf, first, count)
    }

    pub(super) fn check_block_size(&mut self, blksize: u8) -> Result<(), SdoError> {
        self.blksize = blksize;
        if !(1..=MAX_BLOCK_SIZE).contains(&blksize) {
            return Err(self.fail(abort::INVALID_BLOCK_SIZE, format!("the server asked for block size {blksize}")));
        }
        Ok(())
    }

    pub(super) fn block_download_initiated(&mut self, p: &[u8; 8], response: Response) -> Result<Step, SdoError> {
        let Response::BlockDownload { addr, crc, blksize } = response else { return self.not_for_this_transfer(p) };
        self.require(5, "a block download answer with its block size")?;
        if let Some(step) = self.other_object(addr) {
            return Ok(step);
        }
        self.crc = crc;
        self.check_block_size(blksize)?;
        Ok(Step::send(self.send_block()))
    }

    pub(super) fn block_download_acked(
        &mut self,
        p: &[u8; 8],
        response: Response,
        in_block: usize,
    ) -> Result<Step, SdoError> {
        let Response::BlockDownloadAck { ackseq, blksize } = response else { return Err(self.unexpected(p)) };
        self.require(3, "a block acknowledgement")?;
        let acked = ackseq as usize;
        if acked > in_block {
            return Err(self
                .fail(abort::INVALID_SEQUENCE, format!("acknowledged segment {acked} of a {in_block}-segment block")));
        }
        self.count_fruitless(acked > 0, |n| {
            format!("the device acknowledged none of the segments of {n} sub-blocks in a row (ackseq 0)")
        })?;
        self.pos = ((self.pos / SEGMENT_DATA + acked) * SEGMENT_DATA).min(self.buf.len());
        self.check_block_size(blksize)?;
        if self.pos < self.buf.len() {
            let block = self.send_block();
            return Ok(if acked == 0 { Step::retry(block) } else { Step::send(block) });
        }
        let unused = block_unused_in_last(self.buf.len());
        let crc = if self.crc { block_crc(&self.buf) } else { 0 };
        self.state = State::BlockDownloadEnd;
        Ok(Step::send(vec![Request::BlockDownloadEnd { unused, crc }.emit()]))
    }

    pub(super) fn block_download_end(&mut self, p: &[u8; 8], response: Response) -> Result<Step, SdoError> {
        let Response::BlockDownloadEnd = response else { return Err(self.unexpected(p)) };
        self.state = State::Finished;
        Ok(Step::done(vec![], vec![]))
    }
}
