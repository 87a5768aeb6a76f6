use super::*;

fn io(kind: std::io::ErrorKind, raw: Option<i32>) -> std::io::Error {
    match raw {
        Some(code) => std::io::Error::from_raw_os_error(code),
        None => std::io::Error::from(kind),
    }
}

#[test]
fn each_link_failure_names_the_host_or_the_controller() {
    let cause = |e: LinkError| link_finding(&e).cause;
    assert_eq!(cause(LinkError::Down { iface: "can0".into() }), Cause::Host { problem: HostProblem::InterfaceDown });
    assert_eq!(
        cause(LinkError::Open { port: "can0".into(), error: io(std::io::ErrorKind::PermissionDenied, None).into() }),
        Cause::Host { problem: HostProblem::NoPermission }
    );
    assert_eq!(
        cause(LinkError::Io {
            port: "can0".into(),
            op: "send",
            error: io(std::io::ErrorKind::Other, Some(ENOBUFS)).into()
        }),
        Cause::Host { problem: HostProblem::TransmitQueueFull }
    );
    assert_eq!(
        cause(LinkError::TxQueueFull { iface: "can0".into(), waited: Duration::from_secs(1) }),
        Cause::Host { problem: HostProblem::TransmitQueueFull }
    );
    assert_eq!(
        cause(LinkError::BusOff { iface: "can0".into(), detail: "bus off".into() }),
        Cause::Controller { state: ControllerState::BusOff }
    );
    let f = link_finding(&LinkError::AdapterBusError { port: "slcan:x".into(), flags: vec!["bus error"] });
    assert_eq!(f.cause, Cause::Controller { state: ControllerState::BusErrors });
    assert_eq!(f.remedy, Remedy::CheckBus);
    // The link's own words are the evidence.
    assert!(matches!(&f.evidence[..], [Evidence::LinkReported { message }] if message.contains("bus error")));
}

#[test]
fn the_listen_counts_frames_and_the_states_heartbeats_say() {
    let mut h = Heard::default();
    for f in
        [Frame::new(0x705, &[0x7F]), Frame::new(0x705, &[0x04]), Frame::new(0x185, &[1, 2]), Frame::remote(0x705, 1)]
    {
        h.take(&f);
    }
    assert_eq!(h.frames, BTreeMap::from([(0x185, 1), (0x705, 2)]));
    assert_eq!(h.beats[&5], (2, vec![nmt::State::PreOperational, nmt::State::Stopped], nmt::State::Stopped));
    assert_eq!(h.heartbeats(5), Some(Evidence::Heartbeats { node: 5, count: 2, state: nmt::State::Stopped }));
    assert_eq!(h.heartbeats(6), None);
}

#[test]
fn findings_rank_the_host_before_the_node() {
    let mut causes = [
        Cause::NodeSilent { node: 5 },
        Cause::Stopped { node: 5 },
        Cause::BusSilent,
        Cause::Host { problem: HostProblem::InterfaceDown },
    ];
    causes.sort_by_key(Cause::rank);
    assert_eq!(causes[0], Cause::Host { problem: HostProblem::InterfaceDown });
    assert_eq!(causes[3], Cause::NodeSilent { node: 5 });
}

#[test]
fn a_finding_serialises_its_cause_evidence_and_remedy() {
    let f = Finding {
        cause: Cause::Stopped { node: 5 },
        evidence: vec![Evidence::Heartbeats { node: 5, count: 3, state: nmt::State::Stopped }],
        remedy: Remedy::PreOperational { node: 5 },
    };
    let json = serde_json::to_value(&f).unwrap();
    assert_eq!(json["cause"], "stopped");
    assert_eq!(json["node"], 5);
    assert_eq!(json["evidence"][0]["kind"], "heartbeats");
    assert_eq!(json["evidence"][0]["state"], "stopped");
    assert_eq!(json["remedy"]["remedy"], "pre_operational");
}
