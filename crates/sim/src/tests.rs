use super::*;
use crate::canopen::nmt;
use timing::MS;

const READ_DEVICE_TYPE: [u8; 8] = [0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0];

#[test]
fn a_slow_device_answers_5_to_80_ms_after_it_heard_the_request_and_in_order() {
    let mut net = Network::demo_with(SimConfig::default().profile(Profile::Slow));
    let mut last = 0;
    for i in 0..50u64 {
        let heard = i * MS;
        let out = net.deliver(&Frame::new(0x605, &READ_DEVICE_TYPE), heard);
        assert_eq!(out.len(), 1);
        let (ready, _, f) = out[0];
        assert_eq!(f.id(), 0x585);
        assert!(ready >= heard + 5 * MS && ready <= heard + 80 * MS, "{ready} after {heard}");
        assert!(ready >= last, "answers keep their order");
        last = ready;
    }
}

#[test]
fn the_same_seed_gives_the_same_answer_times() {
    let times = |seed| {
        let mut net = Network::demo_with(SimConfig::default().seed(seed));
        (0..20).map(|i| net.deliver(&Frame::new(0x601, &READ_DEVICE_TYPE), i * MS)[0].0).collect::<Vec<_>>()
    };
    assert_eq!(times(3), times(3));
    assert_ne!(times(3), times(4));
}

#[test]
fn faults_apply_to_the_device_they_name() {
    let config = SimConfig::instant().fault("5:drop".parse().unwrap()).fault("10:duplicate".parse().unwrap());
    let mut net = Network::demo_with(config);
    assert!(net.deliver(&Frame::new(0x605, &READ_DEVICE_TYPE), 0).is_empty());
    assert_eq!(net.deliver(&Frame::new(0x60A, &READ_DEVICE_TYPE), 0).len(), 2);
    assert_eq!(net.deliver(&Frame::new(0x601, &READ_DEVICE_TYPE), 0).len(), 1);
}

#[test]
fn a_device_missing_a_frame_does_not_act_on_it_and_hears_the_next() {
    let mut net = Network::demo_with(SimConfig::instant().fault("5:miss@2".parse().unwrap()));
    let stop = nmt::Command::Stop.frame(5);
    assert_eq!(net.deliver(&Frame::new(0x605, &READ_DEVICE_TYPE), 0).len(), 1);
    assert!(net.deliver(&stop, 0).is_empty());
    let sensor = net.devices().iter().find(|d| d.node_id() == Some(5)).unwrap();
    assert_eq!(sensor.nmt_state(), nmt::State::PreOperational, "the stop was missed");
    assert_eq!(net.deliver(&Frame::new(0x605, &READ_DEVICE_TYPE), 0).len(), 1);
}

#[test]
fn the_unconfigured_count_builds_that_many_lss_devices() {
    let net = Network::demo_with(SimConfig::instant().unconfigured(8));
    assert_eq!(net.devices().iter().filter(|d| d.node_id().is_none()).count(), 8);
    let serials: std::collections::BTreeSet<u32> = net.devices().iter().map(|d| d.identity().serial).collect();
    assert_eq!(serials.len(), net.devices().len(), "distinct serials");
}

#[test]
fn a_command_the_master_queued_reaches_the_devices_before_the_link_closes() {
    let mut link = SimLink::with_config(SimConfig::default().profile(Profile::Slow));
    link.send(&nmt::Command::Stop.frame(5)).unwrap();
    link.close().unwrap();
    let sensor = link.network().devices().iter().find(|d| d.node_id() == Some(5)).unwrap();
    assert_eq!(sensor.nmt_state(), nmt::State::Stopped);
}

#[test]
fn the_configured_bit_rate_times_the_frames() {
    let link = SimLink::with_config(SimConfig::default().bit_rate(0));
    assert_eq!(link.network().bit_rate(), 0);
    assert!(link.network().devices().iter().all(|d| d.bit_rate() == 0));
    assert_eq!(SimLink::bps_of(link.network()), Some(1_000_000));
    assert_eq!(SimLink::bps_of(&Network::demo_with(SimConfig::instant().bit_rate(4))), None);
}

#[test]
fn answers_arrive_through_the_link_whatever_the_profile() {
    for profile in [Profile::Instant, Profile::Typical, Profile::Slow] {
        let mut link = SimLink::with_config(SimConfig::default().profile(profile).bit_rate(4));
        link.send(&Frame::new(0x601, &READ_DEVICE_TYPE)).unwrap();
        let deadline = Instant::now() + Duration::from_secs(5);
        let answer = std::iter::from_fn(|| link.recv(deadline).unwrap()).find(|f| f.id() == 0x581);
        assert_eq!(answer.map(|f| f.data()[0]), Some(0x43), "{profile}");
        assert!(link.bus_stats().frames >= 2, "request and answer went over the bus");
    }
}

#[test]
fn the_devices_own_frames_come_with_the_times_they_were_due() {
    let mut net = Network::demo_with(SimConfig::instant());
    let sensor = net.devices().iter().position(|d| d.node_id() == Some(5)).unwrap();
    let beats: Vec<u64> = net
        .events(1_000_000, 1_000_300)
        .into_iter()
        .filter(|(_, i, f)| *i == sensor && f.id() == 0x705)
        .map(|(due, _, _)| due)
        .collect();
    assert!(beats.len() >= 7, "{beats:?}");
    assert!(beats.windows(2).all(|w| w[1] - w[0] == 40), "{beats:?}");
    assert!(beats.iter().all(|t| (1_000_001..=1_000_300).contains(t)), "{beats:?}");
}

#[test]
fn a_master_that_polls_late_gets_the_beats_stamped_when_they_were_on_the_bus() {
    let mut link = SimLink::with_config(SimConfig::default());
    // The master is held up (a loaded host): nobody polls the link for 300 ms.
    std::thread::sleep(Duration::from_millis(300));
    let mut beats = Vec::new();
    while let Some((f, at)) = link.recv_stamped(Instant::now()).unwrap() {
        if f.id() == 0x705 {
            beats.push(at);
        }
    }
    assert!(beats.len() >= 6, "{beats:?}");
    for w in beats.windows(2) {
        let gap = w[1] - w[0];
        // 40 ms apart, give or take the frames of other nodes ahead on the bus.
        assert!(gap > Duration::from_millis(39) && gap < Duration::from_millis(41), "{gap:?} in {beats:?}");
    }
}

/// Every frame a virtual-time link hands over in `span` of bus time after sending
/// `request`, with its bus time from the link's zero.
fn virtual_run(config: SimConfig, request: Frame, span: Duration) -> Vec<(Frame, Duration)> {
    let mut link = SimLink::with_config(config).on_virtual_time(1_000_000);
    let zero = link.now();
    link.send(&request).unwrap();
    let end = zero + span;
    std::iter::from_fn(|| link.recv_stamped(end).unwrap()).map(|(f, at)| (f, at - zero)).collect()
}

#[test]
fn on_virtual_time_a_ten_minute_watch_sees_every_beat_at_its_bus_time() {
    let frames =
        virtual_run(SimConfig::default().profile(Profile::Slow), Frame::new(0x601, &READ_DEVICE_TYPE), TEN_MINUTES);
    let beats: Vec<Duration> = frames.iter().filter(|(f, _)| f.id() == 0x705).map(|(_, at)| *at).collect();
    // The sensor beats every 40 ms: 15,000 beats in ten minutes of bus time.
    assert!((14_999..=15_001).contains(&beats.len()), "{}", beats.len());
    for w in beats.windows(2) {
        let gap = w[1] - w[0];
        assert!(gap > Duration::from_millis(39) && gap < Duration::from_millis(41), "{gap:?}");
    }
    // The slow drive answered 5-80 ms after the request.
    let (_, answered) = frames.iter().find(|(f, _)| f.id() == 0x581).expect("the drive answers");
    assert!(*answered >= Duration::from_millis(5) && *answered <= Duration::from_millis(81), "{answered:?}");
}

#[test]
fn on_virtual_time_the_same_seed_gives_the_same_frames_at_the_same_times() {
    let run = |seed| {
        let config = SimConfig::default().profile(Profile::Slow).seed(seed).fault("5:duplicate".parse().unwrap());
        virtual_run(config, Frame::new(0x601, &READ_DEVICE_TYPE), Duration::from_secs(2))
    };
    assert_eq!(run(9), run(9));
    assert_ne!(run(9), run(10));
}

#[test]
fn a_virtual_sleep_lets_the_devices_run_and_keeps_their_frames() {
    let mut link = SimLink::with_config(SimConfig::instant()).on_virtual_time(0);
    let zero = link.now();
    link.sleep_until(zero + Duration::from_millis(200)).unwrap();
    assert_eq!(link.now(), zero + Duration::from_millis(200));
    // Heartbeats that fell due while the master slept wait for it, stamped when due.
    let (f, at) = link.recv_stamped(link.now()).unwrap().expect("a frame kept");
    assert!(at <= zero + Duration::from_millis(200), "{f:?} at {:?}", at - zero);
}

/// `sdo write 1 5FFE 1` in one invocation, `errors 1` in the next (README's errors
/// example): the fault fell due between the two, so it has struck before the next
/// invocation's first request is answered, however fast that answer comes.
#[test]
fn a_fault_that_fell_due_between_two_invocations_has_struck_before_the_first_answer() {
    let mut first = SimLink::with_config(SimConfig::instant()).on_virtual_time(1_000_000);
    first.send(&Frame::new(0x601, &[0x2B, 0xFE, 0x5F, 0, 1, 0, 0, 0])).unwrap();
    let end = first.now() + Duration::from_millis(1);
    assert!(std::iter::from_fn(|| first.recv(end).unwrap())
        .any(|f| f == Frame::new(0x581, &[0x60, 0xFE, 0x5F, 0, 0, 0, 0, 0])));
    let state = first.network().snapshot();
    // The next invocation opens in the same ms (by a wall clock that stepped back, or
    // one that reads the same): the fault was due 1 ms after the write.
    let mut next = SimLink::of(Network::from_state(&state)).on_virtual_time(1_000_000);
    next.send(&Frame::new(0x601, &[0x40, 0x03, 0x10, 0, 0, 0, 0, 0])).unwrap();
    let end = next.now() + Duration::from_millis(1);
    let answer = std::iter::from_fn(|| next.recv(end).unwrap()).find(|f| f.id() == 0x581);
    assert_eq!(answer.map(|f| f.data()[4]), Some(1), "errors logged in 0x1003:0");
}

const TEN_MINUTES: Duration = Duration::from_secs(600);

#[test]
fn a_rebooting_device_loses_what_it_did_not_store_and_says_so_with_its_boot_up() {
    let config = SimConfig::instant().fault("5:reboot@1".parse().unwrap());
    let mut link = SimLink::with_config(config).on_virtual_time(0);
    // Heartbeat time 500 ms: the device reboots instead of answering.
    link.send(&Frame::new(0x605, &[0x2B, 0x17, 0x10, 0, 0xF4, 0x01, 0, 0])).unwrap();
    let end = link.now() + Duration::from_millis(10);
    let frames: Vec<Frame> = std::iter::from_fn(|| link.recv(end).unwrap()).collect();
    assert!(!frames.iter().any(|f| f.id() == 0x585), "no answer: {frames:?}");
    assert!(frames.contains(&Frame::new(0x705, &[0])), "boot-up: {frames:?}");
    let sensor = link.network().devices().iter().find(|d| d.node_id() == Some(5)).unwrap();
    assert_eq!(sensor.heartbeat_ms(), Some(40), "the write was lost with the reboot");
}

#[test]
fn a_bus_off_controller_sends_nothing_and_reports_itself() {
    use crate::bus::controller::{CanState, Controller};
    let config = SimConfig::instant().fault("bus:off".parse().unwrap());
    let mut link = SimLink::with_config(config.clone()).on_virtual_time(1_000);
    let far = link.now() + Duration::from_secs(1);
    let bus_off = |r: Result<()>| matches!(r, Err(crate::error::Error::Link(crate::error::LinkError::BusOff { .. })));
    assert!(bus_off(link.send(&Frame::new(0x605, &READ_DEVICE_TYPE))));
    assert!(bus_off(link.recv(far).map(|_| ())));
    assert_eq!(link.bus_stats().frames, 0, "nothing reached the bus");
    let report = link.report().unwrap();
    assert!(matches!(report.controller, Some(Controller::Can { state: Some(CanState::BusOff), .. })));
    assert_eq!(report.error_frames.bus_off, 1);
    // Behind an adapter the devices still answer: the bus-off is the adapter's to show.
    let mut devices = SimLink::with_config(config).on_virtual_time(1_000).devices_only();
    devices.send(&Frame::new(0x605, &READ_DEVICE_TYPE)).unwrap();
    let far = devices.now() + Duration::from_secs(1);
    assert_eq!(devices.recv(far).unwrap().map(|f| f.id()), Some(0x585));
    assert_eq!(devices.report(), None);
}

/// A real device restarts its firmware after an NMT reset: silent for a while, then its
/// boot-up. The simulated one rebooted at once, so a master that read the first answer after
/// the reset as its effect (through an EPOS2, whose remote request catches the boot-up only
/// when it is waiting for it) passed or failed by how fast the host ran.
#[test]
fn a_reset_device_is_silent_while_it_restarts_then_sends_its_boot_up() {
    let config = SimConfig::default().profile(Profile::Typical);
    let mut link = SimLink::with_config(config).on_virtual_time(0);
    let began = link.now();
    link.send(&nmt::Command::ResetNode.frame(10)).unwrap();
    // Asked while it restarts: no answer to guarding or SDO.
    link.send(&Frame::remote(0x70A, 1)).unwrap();
    link.send(&Frame::new(0x60A, &READ_DEVICE_TYPE)).unwrap();
    let end = began + Duration::from_millis(300);
    let frames: Vec<(Frame, Instant)> = std::iter::from_fn(|| link.recv_stamped(end).unwrap()).collect();
    let from_10: Vec<&(Frame, Instant)> = frames.iter().filter(|(f, _)| f.id() & 0x7F == 10).collect();
    assert_eq!(from_10.len(), 1, "only the boot-up: {frames:?}");
    let (boot_up, at) = from_10[0];
    assert_eq!(*boot_up, Frame::new(0x70A, &[0]));
    let restart = *at - began;
    assert!(restart >= Duration::from_millis(100) && restart < Duration::from_millis(110), "{restart:?}");
    // The instant profile (unit tests of protocol logic) reboots at once.
    let mut link = SimLink::with_config(SimConfig::instant()).on_virtual_time(0);
    link.send(&nmt::Command::ResetNode.frame(10)).unwrap();
    assert_eq!(link.recv(link.now()).unwrap(), Some(Frame::new(0x70A, &[0])));
}

/// A stop, then a master held up (a loaded host): the sensor's beats that fell due after
/// it heard the stop say stopped, though the master polled only once they were all due.
#[test]
fn a_device_hears_a_command_before_the_beats_that_fall_due_after_it_even_when_polled_late() {
    let mut link = SimLink::with_config(SimConfig::instant()).on_virtual_time(1_000_000);
    let zero = link.now();
    link.send(&nmt::Command::Stop.frame(5)).unwrap();
    // At 1 Mbit/s the stop has left the bus 0.1 ms after it was sent.
    let heard = zero + Duration::from_micros(100);
    link.sleep_until(zero + Duration::from_millis(200)).unwrap();
    let beats: Vec<(Frame, Instant)> =
        std::iter::from_fn(|| link.recv_stamped(link.now()).unwrap()).filter(|(f, _)| f.id() == 0x705).collect();
    assert!(beats.len() >= 4, "{beats:?}");
    for (f, at) in beats.iter().filter(|(_, at)| *at > heard + Duration::from_millis(1)) {
        assert_eq!(f.data()[0], 0x04, "a beat at {:?} after the stop: {f:?}", *at - zero);
    }
}
