//! One procedure on several buses at once: ten benches checked by one command. Each bus
//! gets its own thread and its own opened [`Bus`], so a slow or dead bus delays none of
//! the others; a bus that cannot be opened is that bus's failure, not the end of the run.

use crate::bus::Bus;
use crate::cancel::Cancel;
use crate::connect::{BusAddr, OpenOptions};
use crate::error::{Error, ErrorClass};
use crate::ops::unmet::Shortfall;

/// What a procedure did on one bus of several.
#[derive(Debug)]
pub struct OnBus<T> {
    /// The bus, as its URI (`sim:/tmp/a.json`, `socketcan:can0`): what tells the buses apart
    /// (two simulated networks both describe themselves as `sim`).
    pub bus: String,
    /// The procedure's result there, or why the bus could not be opened or closed.
    pub result: Result<T, Error>,
}

/// Run `f` on each of `buses` (it is told which) in parallel, each bus opened (with `opts`) in its own thread
/// and closed when `f` returns; the results come back in the order of `buses`. A request to
/// stop (`cancel`) ends each procedure at its next call to its bus, and each reports what
/// it did. A bus whose closing fails (a simulated network whose state could not be saved)
/// reports that failure instead of its result.
pub fn each<T: Send>(
    buses: &[BusAddr],
    opts: &OpenOptions,
    cancel: &Cancel,
    f: impl Fn(&BusAddr, &mut dyn Bus) -> Result<T, Error> + Sync,
) -> Vec<OnBus<T>> {
    let f = &f;
    std::thread::scope(|scope| {
        let running: Vec<_> = buses
            .iter()
            .map(|addr| scope.spawn(move || OnBus { bus: addr.to_string(), result: on_one(addr, opts, cancel, f) }))
            .collect();
        running.into_iter().map(|t| t.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))).collect()
    })
}

fn on_one<T>(
    addr: &BusAddr,
    opts: &OpenOptions,
    cancel: &Cancel,
    f: &(impl Fn(&BusAddr, &mut dyn Bus) -> Result<T, Error> + Sync),
) -> Result<T, Error> {
    let mut result = None;
    let run = |bus: &mut dyn Bus| {
        result = Some(crate::ops::stop::stoppable(bus, cancel, |bus| f(addr, bus)));
        Ok(())
    };
    crate::ops::stop::on_bus(addr, opts, cancel, run, |_, e: Error| e)?;
    result.expect("on_bus runs the procedure once it has opened the bus")
}

/// The class of the run's exit: the worst of the buses' (the later in the exit-code
/// table, [`ErrorClass::ALL`]: an interruption over an output failure over a verification
/// failure over a link failure, and so on), the first of equals; `None` when every bus
/// ended well.
pub fn worst<'a>(shortfalls: impl IntoIterator<Item = &'a Shortfall>) -> Option<&'a Shortfall> {
    let rank = |e: &Shortfall| ErrorClass::ALL.iter().position(|c| *c == e.class());
    shortfalls.into_iter().fold(None, |worst, e| match worst {
        Some(w) if rank(w) >= rank(e) => Some(w),
        _ => Some(e),
    })
}

/// How one bus's run ended: the procedure's report, when it got as far as one, and how the
/// bus fell short: the procedure's error, or the report's verdict (a node unhealthy).
#[derive(Debug)]
pub struct Ended<R> {
    /// The bus, as its URI.
    pub bus: String,
    /// The procedure's report.
    pub report: Option<R>,
    /// How this bus fell short.
    pub error: Option<Shortfall>,
}

/// Each bus's run, its report judged by `outcome` (the verdict a single bus would end with).
pub fn judged<R, V: Into<Shortfall>>(runs: Vec<OnBus<R>>, outcome: impl Fn(&R) -> Result<(), V>) -> Vec<Ended<R>> {
    let judge = |run: OnBus<R>| match run.result {
        Ok(report) => Ended { bus: run.bus, error: outcome(&report).err().map(Into::into), report: Some(report) },
        Err(e) => Ended { bus: run.bus, report: None, error: Some(e.into()) },
    };
    runs.into_iter().map(judge).collect()
}

/// How the whole run ends: well when every bus did, else with the [`worst`] failure, naming
/// its bus and how many failed ([`Shortfall::OnBuses`]); a request to stop as itself.
pub fn exit<R>(ended: Vec<Ended<R>>) -> Result<(), Shortfall> {
    let total = ended.len();
    let mut errors: Vec<(String, Shortfall)> = ended.into_iter().filter_map(|e| Some((e.bus, e.error?))).collect();
    let failed = errors.len();
    let worst = worst(errors.iter().map(|(_, e)| e)).and_then(|w| errors.iter().position(|(_, e)| std::ptr::eq(e, w)));
    match worst.map(|i| errors.swap_remove(i)) {
        None => Ok(()),
        Some((_, Shortfall::Failed(Error::Interrupted))) => Err(Error::Interrupted.into()),
        Some((bus, worst)) => Err(Shortfall::OnBuses { bus, worst: Box::new(worst), failed, total }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ops::unmet::{NotHealthy, Unmet};
    use std::time::Duration;

    #[test]
    fn the_worst_error_is_the_latest_in_the_exit_code_table() {
        let link = Shortfall::Failed(link());
        let unhealthy = Shortfall::Unmet(Unmet::Unhealthy {
            bus: "sim".into(),
            total: 1,
            nodes: vec![NotHealthy { node: 5, failed: vec!["error register"] }],
        });
        let interrupted = Shortfall::Failed(Error::Interrupted);
        assert_eq!(worst([&link, &unhealthy]).map(Shortfall::exit_code), Some(6));
        assert_eq!(worst([&interrupted, &unhealthy]).map(Shortfall::exit_code), Some(130));
        assert_eq!(worst([&link]).map(Shortfall::exit_code), Some(5));
        assert!(worst(std::iter::empty()).is_none());
        let other = Shortfall::Unmet(Unmet::Unhealthy { bus: "sim".into(), total: 2, nodes: Vec::new() });
        assert!(std::ptr::eq(worst([&unhealthy, &other]).unwrap(), &unhealthy), "the first of equals");
    }

    #[test]
    fn every_bus_answers_in_the_given_order_and_an_unopenable_one_fails_alone() {
        let dir = tempfile::tempdir().unwrap();
        let buses = vec![
            BusAddr::Sim { state: Some(dir.path().join("a.json")) },
            BusAddr::Socketcand { host: "127.0.0.1".into(), port: closed_port(), iface: "vcan0".into() },
            BusAddr::Sim { state: Some(dir.path().join("c.json")) },
        ];
        let opts = OpenOptions::new(Duration::from_millis(200));
        let runs = each(&buses, &opts, &Cancel::default(), |_, bus| Ok(bus.describe().to_string()));
        let shown: Vec<(&str, bool)> = runs.iter().map(|r| (r.bus.as_str(), r.result.is_ok())).collect();
        let uri = |b: &BusAddr| b.to_string();
        assert_eq!(shown, vec![(&*uri(&buses[0]), true), (&*uri(&buses[1]), false), (&*uri(&buses[2]), true)]);
        assert_eq!(runs[1].result.as_ref().unwrap_err().exit_code(), 5, "{:?}", runs[1].result);
    }

    fn link() -> Error {
        Error::Link(crate::error::LinkError::Open {
            port: "can9".into(),
            error: std::io::Error::from(std::io::ErrorKind::NotFound).into(),
        })
    }

    #[test]
    fn the_run_ends_with_its_worst_failure_naming_its_bus_and_how_many_failed() {
        let unhealthy =
            || Unmet::Unhealthy { bus: "b".into(), total: 1, nodes: vec![NotHealthy { node: 5, failed: vec!["nmt"] }] };
        let runs = vec![
            OnBus { bus: "a".into(), result: Ok(1) },
            OnBus { bus: "b".into(), result: Ok(2) },
            OnBus { bus: "c".into(), result: Err(link()) },
        ];
        let ended = judged(runs, |r: &i32| if *r == 2 { Err(unhealthy()) } else { Ok(()) });
        let reports: Vec<Option<i32>> = ended.iter().map(|e| e.report).collect();
        assert_eq!(reports, [Some(1), Some(2), None], "a report kept beside its failure");
        match exit(ended) {
            Err(Shortfall::OnBuses { bus, worst, failed: 2, total: 3 }) => {
                assert_eq!((bus.as_str(), worst.exit_code()), ("b", 6));
            }
            other => panic!("{other:?}"),
        }
        let stopped = vec![Ended { bus: "a".into(), report: None::<i32>, error: Some(Error::Interrupted.into()) }];
        assert!(matches!(exit(stopped), Err(Shortfall::Failed(Error::Interrupted))));
        assert!(exit(vec![Ended { bus: "a".into(), report: Some(1), error: None }]).is_ok());
    }

    /// A local TCP port nothing listens on (bound, then let go).
    fn closed_port() -> u16 {
        std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
    }
}
