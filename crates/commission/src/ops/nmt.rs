//! Network management: commands to one node or all ([`send`]), resets confirmed by what
//! the nodes show afterwards ([`reset`]), and a node's NMT state as the node shows it
//! ([`state`]).

use super::node::Node;
pub use super::node::StateFrom;
use crate::bus::{Bus, ALL_NODES};
use crate::canopen::nmt::{self, Command, ErrorControl};
use crate::error::{Error, Result, Service};
use serde::Serialize;
use std::collections::BTreeSet;
use std::time::Duration;

/// An NMT command went out. NMT commands are unconfirmed: this says that it was sent, not
/// that it took effect.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Sent {
    /// The command sent.
    #[serde(serialize_with = "command_name")]
    pub command: Command,
    /// A node-id, or [`ALL_NODES`] (serialised as `"all"`).
    #[serde(serialize_with = "target")]
    pub target: u8,
    /// It was sent (NMT has no answer: not that it took effect).
    pub sent: bool,
}

/// A reset went out; whether the nodes were seen coming back.
#[derive(Debug, Serialize)]
pub struct Reset {
    /// The reset sent (node or communication).
    #[serde(serialize_with = "command_name")]
    pub command: Command,
    /// A node-id, or [`ALL_NODES`] (serialised as `"all"`).
    #[serde(serialize_with = "target")]
    pub target: u8,
    /// It was sent.
    pub sent: bool,
    /// The nodes were seen coming back (a boot-up, or answers).
    pub confirmed: bool,
    /// The nodes seen booting (`None` when unconfirmed).
    pub booted: Option<Vec<u8>>,
    /// The state they booted into.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub state: Option<nmt::State>,
    /// How the boot was seen, for the front end to word (in JSON too, as `seen_by`).
    #[serde(skip)]
    pub seen_by: Option<SeenBy>,
    /// Why the reset could not be confirmed, for the front end to word (in JSON too, as
    /// `why`: a front end serialises it in its words).
    #[serde(skip)]
    pub why: Option<Unconfirmed>,
    /// The user stopped the wait for the boot-up (SIGINT, SIGTERM): the reset went out.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub interrupted: bool,
}

/// A node's NMT state, and how it was learned.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct NodeState {
    /// The node-id.
    pub node: u8,
    /// The state it shows.
    pub state: nmt::State,
    /// How it was learned: its heartbeat, node guarding, a boot-up that answered it, or a
    /// remote request through an EPOS2.
    pub source: StateFrom,
}

/// What is known after a reset was sent.
#[derive(Debug, PartialEq)]
#[non_exhaustive]
pub enum Confirmation {
    /// These nodes are back, and how that was seen.
    Confirmed(Vec<u8>, SeenBy),
    /// The reset went out but nothing showed that it took effect; why not.
    Unconfirmed(Unconfirmed),
}

/// How a node was seen coming back from a reset.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeenBy {
    /// Its boot-up message, on a link that shows the bus's traffic.
    BootUpMessage,
    /// Its boot-up, as the answer to a remote request (through an EPOS2).
    BootUpAnswer,
    /// Its state, asked by remote requests: another before, pre-operational after.
    StateChange {
        /// The state it showed before the reset.
        was: nmt::State,
    },
}

/// Why a reset that went out is not confirmed: what was seen instead, for the front end to
/// word (with what the user can do to learn more).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Unconfirmed {
    /// All nodes were reset over a link that passes on no boot-up messages: nothing shows
    /// which came back.
    NoBootUps {
        /// The bus, as it describes itself.
        bus: String,
    },
    /// The node answers, in a state that does not tell a reset from none (not the
    /// Pre-operational of a boot after another state), over a link that passes on no
    /// boot-up messages.
    StateAsBefore {
        /// The node-id.
        node: u8,
        /// The state it answered with before the reset; none when it did not say.
        before: Option<nmt::State>,
        /// The state it answers with after it.
        after: nmt::State,
        /// The bus, as it describes itself.
        bus: String,
    },
    /// The node answers with a state code CiA 301 does not define, over a link that passes
    /// on no boot-up messages.
    UndefinedState {
        /// The node-id.
        node: u8,
        /// The state code it answered with.
        code: u8,
        /// The bus, as it describes itself.
        bus: String,
    },
    /// The user stopped the wait for the boot-up once the reset went out: whether the
    /// target came back is not known.
    Interrupted {
        /// A node-id, or [`ALL_NODES`].
        target: u8,
    },
}

/// How long to wait for a reset to show.
#[derive(Clone, Copy, Debug)]
pub struct ResetOptions {
    /// For the boot-up messages (or, through an EPOS2, for the node to answer again).
    pub wait: Duration,
    /// For each answer; after a reset of all nodes, the quiet time that ends the listening.
    pub timeout: Duration,
}

/// How long to wait for a node's state.
#[derive(Clone, Copy, Debug)]
pub struct StateOptions {
    /// For a heartbeat, before asking by node guarding.
    pub listen: Duration,
    /// For the answer to node guarding.
    pub timeout: Duration,
}

/// `node N`, or `all nodes`.
pub fn target_text(t: u8) -> String {
    if t == ALL_NODES {
        "all nodes".into()
    } else {
        format!("node {t}")
    }
}

fn command_name<S: serde::Serializer>(c: &Command, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(c.name())
}

/// A node-id, or `"all"`.
pub fn target<S: serde::Serializer>(t: &u8, s: S) -> std::result::Result<S::Ok, S::Error> {
    if *t == ALL_NODES {
        s.serialize_str("all")
    } else {
        s.serialize_u8(*t)
    }
}

/// Send an NMT command to `target` (a node-id, or [`ALL_NODES`]).
pub fn send(bus: &mut dyn Bus, command: Command, target: u8) -> Result<Sent> {
    bus.nmt(command, target)?;
    Ok(Sent { command, target, sent: true })
}

/// Send a reset and wait until the target is back; the report says whether it was seen.
/// Stopped by the user once the reset went out (over a
/// [`Stoppable`](crate::bus::stoppable::Stoppable) bus), the report says so, unconfirmed.
pub fn reset(bus: &mut dyn Bus, command: Command, target: u8, o: &ResetOptions) -> Result<Reset> {
    let mut sent = false;
    let (booted, seen_by, why, interrupted) = match reset_and_wait_noting(bus, command, target, o, &mut sent) {
        Err(e) if e.is_interrupted() && sent => (None, None, Some(Unconfirmed::Interrupted { target }), true),
        Err(e) => return Err(e),
        Ok(Confirmation::Confirmed(nodes, how)) => (Some(nodes), Some(how), None, false),
        Ok(Confirmation::Unconfirmed(why)) => (None, None, Some(why), false),
    };
    let (confirmed, state) = (booted.is_some(), booted.as_ref().map(|_| nmt::State::PreOperational));
    Ok(Reset { command, target, sent: true, confirmed, booted, state, seen_by, why, interrupted })
}

/// Send a reset and wait until the target is back. A link that shows the bus's traffic
/// sees boot-up messages; through an EPOS2 only the node's answers to remote requests
/// show anything, and only a boot-up answer or a change of state proves a reset.
pub fn reset_and_wait(bus: &mut dyn Bus, cmd: Command, target: u8, o: &ResetOptions) -> Result<Confirmation> {
    reset_and_wait_noting(bus, cmd, target, o, &mut false)
}

/// [`reset_and_wait`], setting `sent` once the reset went out.
fn reset_and_wait_noting(
    bus: &mut dyn Bus,
    cmd: Command,
    target: u8,
    o: &ResetOptions,
    sent: &mut bool,
) -> Result<Confirmation> {
    if bus.sees_traffic() {
        bus.nmt(cmd, target)?;
        *sent = true;
        let nodes = listen_for_boot_ups(bus, target, o)?;
        return Ok(Confirmation::Confirmed(nodes, SeenBy::BootUpMessage));
    }
    if target == ALL_NODES {
        bus.nmt(cmd, target)?;
        *sent = true;
        return Ok(Confirmation::Unconfirmed(Unconfirmed::NoBootUps { bus: bus.describe() }));
    }
    let before = match Node::new(bus, target, o.timeout).error_control(o.timeout)? {
        Some(Some(ErrorControl::State { state, .. })) => Some(state),
        _ => None,
    };
    bus.nmt(cmd, target)?;
    *sent = true;
    let after = poll_until_answering(bus, target, o)?;
    let pre_operational = nmt::State::PreOperational;
    Ok(match (before, after) {
        (_, ErrorControl::BootUp) => Confirmation::Confirmed(vec![target], SeenBy::BootUpAnswer),
        (Some(was), ErrorControl::State { state, .. }) if state == pre_operational && was != pre_operational => {
            Confirmation::Confirmed(vec![target], SeenBy::StateChange { was })
        }
        (before, ErrorControl::State { state: after, .. }) => {
            Confirmation::Unconfirmed(Unconfirmed::StateAsBefore { node: target, before, after, bus: bus.describe() })
        }
        (_, ErrorControl::Unknown(code)) => {
            Confirmation::Unconfirmed(Unconfirmed::UndefinedState { node: target, code, bus: bus.describe() })
        }
    })
}

/// Boot-up messages after a reset. One node: done at its boot-up. All: boot-ups may come
/// from any node at any time, so listen until a timeout passes with no new one.
fn listen_for_boot_ups(bus: &mut dyn Bus, target: u8, o: &ResetOptions) -> Result<Vec<u8>> {
    let deadline = bus.now() + o.wait;
    let mut booted = BTreeSet::new();
    let mut quiet_until = deadline;
    while let Some(f) = bus.recv_frame(quiet_until.min(deadline))? {
        if let Some((node, ErrorControl::BootUp)) = ErrorControl::parse(&f) {
            if target == ALL_NODES {
                booted.insert(node);
                quiet_until = bus.now() + o.timeout;
            } else if node == target {
                booted.insert(node);
                break;
            }
        }
    }
    if booted.is_empty() {
        return Err(Error::NoAnswer { node: target, what: Service::BootUp, waited: o.wait });
    }
    Ok(booted.into_iter().collect())
}

/// Through a link that shows no traffic, a reset node is back when it answers the
/// error-control remote request again; its answer.
fn poll_until_answering(bus: &mut dyn Bus, node: u8, o: &ResetOptions) -> Result<ErrorControl> {
    let deadline = bus.now() + o.wait;
    loop {
        // Nothing, or what is no error-control message: not back yet.
        if let Some(Some(answer)) = Node::new(bus, node, o.timeout).error_control(o.timeout)? {
            return Ok(answer);
        }
        if bus.now() >= deadline {
            return Err(Error::NoAnswer { node, what: Service::AfterReset, waited: o.wait });
        }
        bus.sleep_until(bus.now() + Duration::from_millis(20))?;
    }
}

/// How long after now a beat may still say what a node was before a command sent just now:
/// until the frames ahead of the command have left (one on the wire when it was sent), the
/// command itself, and a beat the node had queued before it heard the command, which lost
/// arbitration to it. Three frame times, where the link knows them.
fn before_a_command_took_effect(bus: &dyn Bus) -> Duration {
    bus.frame_time().unwrap_or_default() * 3
}

/// A node's NMT state: from its heartbeat (listened for `listen`), else by node guarding.
pub fn state(bus: &mut dyn Bus, node: u8, o: &StateOptions) -> Result<NodeState> {
    if bus.sees_traffic() {
        let start = bus.now() + before_a_command_took_effect(bus);
        let listen_end = start + o.listen;
        while let Some((f, at)) = bus.recv_frame_stamped(listen_end)? {
            // A beat that ended before then may predate a command just sent (a stop): the
            // state is what the node says once the command reached it.
            let beat = ErrorControl::parse(&f).filter(|(n, _)| *n == node && at >= start);
            if let Some((_, ErrorControl::State { state, .. })) = beat {
                return Ok(NodeState { node, state, source: StateFrom::Heartbeat });
            }
        }
    }
    let answer = Node::new(bus, node, o.timeout).guard(o.timeout)?;
    let Some((state, source)) = answer.and_then(|g| Some((g.state()?, StateFrom::guarding(g, bus)))) else {
        let heartbeat = bus.sees_traffic().then_some(o.listen);
        return Err(Error::NoAnswer { node, what: Service::NmtState { heartbeat }, waited: o.timeout });
    };
    Ok(NodeState { node, state, source })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::Frame;
    use crate::ops::node::Guarded;
    use crate::sim::test_bus as bus;

    /// The state says where it came from: a heartbeat heard while listening, else node
    /// guarding; and what an answer to guarding tells, in the one reading every command uses.
    #[test]
    fn a_state_says_whether_a_heartbeat_or_node_guarding_told_it() {
        let mut bus = bus();
        let timeout = Duration::from_millis(200);
        let guarded = state(&mut bus, 5, &StateOptions { listen: Duration::ZERO, timeout }).unwrap();
        assert_eq!((guarded.state, guarded.source), (nmt::State::PreOperational, StateFrom::NodeGuarding));
        let listened = state(&mut bus, 5, &StateOptions { listen: Duration::from_secs(3), timeout }).unwrap();
        assert_eq!(listened.source, StateFrom::Heartbeat, "the sim's node 5 produces a heartbeat");
        assert!(matches!(
            state(&mut bus, 44, &StateOptions { listen: Duration::ZERO, timeout }),
            Err(Error::NoAnswer { node: 44, .. })
        ));
        assert_eq!(StateFrom::guarding(Guarded::BootUp, &bus), StateFrom::BootUp);
        assert_eq!(StateFrom::guarding(Guarded::NotAState, &bus), StateFrom::NotAState);
        assert_eq!(StateFrom::guarding(Guarded::State(nmt::State::Stopped), &bus), StateFrom::NodeGuarding);
    }

    /// A beat already on the wire when a stop is sent, or queued in the node and losing
    /// arbitration to the stop, ends after the stop was sent and says what the node was
    /// before it: the state read next is the stopped one all the same.
    #[test]
    fn a_beat_sent_before_a_stop_took_effect_is_not_the_state_after_it() {
        for quarter_frames in 0..12 {
            let mut bus = bus();
            let beat_of_5 = |f: &Frame| matches!(ErrorControl::parse(f), Some((5, ErrorControl::State { .. })));
            let mut ends = Vec::new();
            let deadline = bus.now() + Duration::from_secs(5);
            while ends.len() < 2 {
                let (f, at) = bus.recv_frame_stamped(deadline).unwrap().expect("node 5 beats");
                if beat_of_5(&f) {
                    ends.push(at);
                }
            }
            // From a quarter of a frame before the next beat ends to three frames before.
            let frame_time = bus.frame_time().expect("a timed bus");
            let next_end = ends[1] + (ends[1] - ends[0]);
            bus.sleep_until(next_end - frame_time * (quarter_frames + 1) / 4).unwrap();
            send(&mut bus, Command::Stop, 5).unwrap();
            let o = StateOptions { listen: Duration::from_millis(300), timeout: Duration::from_millis(200) };
            let read = state(&mut bus, 5, &o).unwrap();
            assert_eq!(read.state, nmt::State::Stopped, "sent {quarter_frames}/4 frames before the beat ended");
        }
    }
}
