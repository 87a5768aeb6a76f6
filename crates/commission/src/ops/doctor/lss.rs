//! Devices waiting in LSS configuration without a node-id (CiA 305): silent to SDO and
//! heartbeat, found only by LSS's "identify non-configured remote slave", a broadcast that
//! doctor sends only when asked.

use super::report::{Cause, Diagnosis, Evidence, Finding, Remedy};
use crate::bus::Bus;
use crate::error::Result;
use std::time::Duration;

/// Ask once for devices without a node-id, waiting `wait`: any is a finding (it explains a
/// silent node or bus better than they do); none is evidence for the silent ones.
pub(super) fn ask(bus: &mut dyn Bus, wait: Duration, d: &mut Diagnosis) -> Result<()> {
    let (count, waited_ms) = super::report::timed(bus, |bus| crate::bus::lss::count_unconfigured(bus, wait))?;
    let answers = Evidence::LssAnswers { count, waited_ms };
    if count == 0 {
        let silent: Vec<&mut Finding> = d.findings.iter_mut().filter(|f| silent(&f.cause)).collect();
        match silent.is_empty() {
            true => d.fine.push(answers),
            false => silent.into_iter().for_each(|f| f.evidence.push(answers.clone())),
        }
        return Ok(());
    }
    // A bus with a device on it is not silent: what showed it silent is evidence here.
    let mut evidence = vec![answers];
    if let Some(i) = d.findings.iter().position(|f| f.cause == Cause::BusSilent) {
        evidence.extend(d.findings.remove(i).evidence);
    }
    // First among equals: it explains a silent node too.
    let finding = Finding { cause: Cause::LssUnconfigured { count }, evidence, remedy: Remedy::LssAssign };
    d.findings.insert(0, finding);
    Ok(())
}

/// Not asked: where nothing answers, the remedy says that a device without a node-id would
/// be found by asking.
pub(super) fn point_at_it(d: &mut Diagnosis) {
    for f in d.findings.iter_mut() {
        f.remedy = match (&f.cause, &f.remedy) {
            (Cause::BusSilent, Remedy::CheckBus) => Remedy::CheckBusOrLss,
            (Cause::NodeSilent { node }, Remedy::CheckNode { .. }) => Remedy::CheckNodeOrLss { node: *node },
            _ => continue,
        };
    }
}

/// The causes a device without a node-id would explain.
fn silent(cause: &Cause) -> bool {
    matches!(cause, Cause::BusSilent | Cause::NodeSilent { .. })
}
