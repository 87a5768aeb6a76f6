//! The [`Bus`] services of [`Master`], and the frame waits under them.

use super::*;

impl<L: FrameLink> Bus for Master<L> {
    fn describe(&self) -> String {
        self.describe.clone()
    }

    fn sdo_batch(&mut self, jobs: &[SdoJob], progress: &mut dyn FnMut(usize)) -> Result<Vec<Result<Vec<u8>>>> {
        let mut clients = Vec::with_capacity(jobs.len());
        let mut timeout = Duration::ZERO;
        let mut retries = 0;
        // Asked again early only where the link says when a request has left the bus.
        let ask_again =
            jobs.iter().filter_map(|j| j.opts().ask_again_after).max().filter(|_| self.link.frame_time().is_some());
        let watch = Watch::of(jobs.iter().map(SdoJob::opts));
        for job in jobs {
            let (node, client, opts) = match job {
                SdoJob::Upload { node, addr, opts } => (*node, self.upload_client(*node, *addr, opts), opts),
                SdoJob::Download { node, addr, data, opts } => {
                    if u32::try_from(data.len()).is_err() {
                        return Err(Error::TooLargeForSdo { len: data.len() });
                    }
                    let block = self.block_allowed(*node, opts.block_download);
                    (*node, SdoClient::download(*addr, data.clone(), block), opts)
                }
            };
            check_node(node)?;
            // One wait for the batch: the longest any job asks for.
            timeout = timeout.max(opts.timeout);
            retries = retries.max(opts.retries);
            let again = if opts.ask_again_after.is_some() { AskAgain::Yes } else { AskAgain::No };
            clients.push((node, client, again));
        }
        self.run(clients, timeout, retries, ask_again, progress, &watch)
    }

    fn nmt(&mut self, cmd: Command, node: u8) -> Result<()> {
        if node != ALL_NODES {
            check_node(node)?;
        }
        self.send(&cmd.frame(node))
    }

    fn send_frame(&mut self, frame: &Frame) -> Result<()> {
        self.send(frame)
    }

    fn now(&self) -> Instant {
        self.link.now()
    }

    fn sleep_until(&mut self, t: Instant) -> Result<()> {
        self.link.sleep_until(t)
    }

    fn follows_bit_rate_switch(&self) -> bool {
        self.link.follows_bit_rate_switch()
    }

    fn sees_traffic(&self) -> bool {
        true
    }
    fn frame_time(&self) -> Option<Duration> {
        self.link.frame_time()
    }
    fn block_transfer_to(&self, node: u8) -> bool {
        self.block_allowed(node, true)
    }
    fn check_link(&mut self) -> Result<()> {
        self.link.check()
    }
    fn link_report(&mut self) -> Option<crate::bus::controller::LinkReport> {
        self.link.report()
    }
    fn listen_at(&mut self, kbit: u32, window: Duration) -> Result<Option<crate::bus::controller::RateHeard>> {
        self.link.listen_at(kbit, window)
    }

    fn recv_frame_stamped(&mut self, deadline: Instant) -> Result<Option<(Frame, Instant)>> {
        // A link hands over frames already queued even past the deadline; on a bus that
        // never falls quiet a listener looping until `None` would never stop.
        if self.link.now() >= deadline {
            return Ok(None);
        }
        self.link.set_filters(&EVERYTHING)?;
        self.recv_stamped(deadline)
    }

    fn request_frame(&mut self, id: u16, len: u8, timeout: Duration) -> Result<Frame> {
        // LSS answers pass too: a scan's inquiries are answered while it guards its nodes.
        self.link.set_filters(&[(id, 0x7FF), (lss::SLAVE_COB, 0x7FF)])?;
        self.send(&Frame::remote(id, len))?;
        let deadline = self.link.now() + timeout;
        self.guarding = Some(id);
        let answer = self.wait_for(id, deadline);
        self.guarding = None;
        answer?.ok_or(Error::NoRemoteAnswer { cob: id, waited: timeout })
    }

    fn lss(&mut self, exchange: &LssExchange) -> Result<Vec<LssAnswer>> {
        self.link.set_filters(&[(lss::SLAVE_COB, 0x7FF)])?;
        let answers = self.exchange_lss(exchange);
        self.in_lss_exchange = false;
        answers
    }

    fn observed(&mut self) -> &mut Observed {
        &mut self.observed
    }

    fn close(&mut self) -> Result<()> {
        self.link.close()
    }
}

impl<L: FrameLink> Master<L> {
    /// The first data frame with this id before the deadline.
    fn wait_for(&mut self, id: u16, deadline: Instant) -> Result<Option<Frame>> {
        while let Some(f) = self.recv(deadline)? {
            if f.id() == id && !f.is_remote() {
                return Ok(Some(f));
            }
        }
        Ok(None)
    }

    fn exchange_lss(&mut self, exchange: &LssExchange) -> Result<Vec<LssAnswer>> {
        let LssExchange { request, expect, wait, collect } = *exchange;
        // A slow slave's answer to the previous request must not count for this one (the
        // observer keeps it as a stray). Bounded: a babbling device never lets up.
        let drain_until = self.link.now() + DRAIN_LIMIT;
        while self.link.now() < drain_until && self.recv(self.link.now())?.is_some() {}
        self.send(&Frame::new(lss::MASTER_COB, &request))?;
        let mut answers = Vec::new();
        if collect == LssWait::Nothing {
            return Ok(answers);
        }
        self.in_lss_exchange = true;
        let sent = self.link.now();
        // Only a well-formed answer with the expected command specifier counts, and none
        // moves the deadline later: a flood on 0x7E4 cannot keep this waiting.
        let mut deadline = sent + wait;
        while let Some(f) = self.recv(deadline)? {
            if f.id() != lss::SLAVE_COB || f.is_remote() || !lss::is_answer(f.data(), expect) {
                continue;
            }
            let data: [u8; 8] = f.data().try_into().expect("8 bytes");
            answers.push(LssAnswer { data, after: self.link.now().saturating_duration_since(sent) });
            match collect {
                LssWait::First => break,
                LssWait::Settle(more) if answers.len() == 1 => deadline = deadline.min(self.link.now() + more),
                _ => {}
            }
        }
        Ok(answers)
    }
}
