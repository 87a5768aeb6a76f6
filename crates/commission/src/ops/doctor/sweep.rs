//! A listen-only sweep over the CiA 301 bit rates, for a bus whose traffic the link cannot
//! decode: the rate at which it decodes cleanly is the bus's. Only where the link can change
//! its own rate (an slcan adapter); a CAN interface belongs to its owner, who gets the `ip
//! link` commands instead. Each trial listens only: nothing is sent, nothing acknowledged.

use super::report::{Cause, ControllerState, Diagnosis, Evidence, Finding, Remedy};
use crate::bus::controller::RateHeard;
use crate::bus::Bus;
use crate::error::Result;
use std::time::Duration;

/// The CiA 301 bit rates in kbit/s, fastest first.
pub const RATES: [u32; 8] = [1000, 800, 500, 250, 125, 50, 20, 10];

/// Listen at each of [`RATES`] for `window` (eight windows in all, plus the adapter's
/// commands), and add what it shows to `d`: the rate the bus's traffic decodes at when it
/// is not `own_kbit` (the link's), the trials themselves either way. A link that cannot
/// change its rate gets evidence saying so (the `ip link` way to do it by hand).
pub fn sweep(bus: &mut dyn Bus, d: &mut Diagnosis, own_kbit: Option<u32>, window: Duration) -> Result<()> {
    let mut trials = Vec::new();
    for kbit in RATES {
        match bus.listen_at(kbit, window)? {
            Some(heard) => trials.push(heard),
            None => {
                d.fine.push(Evidence::NoSweep { bus: d.bus.clone() });
                return Ok(());
            }
        }
    }
    judge(d, trials, own_kbit);
    Ok(())
}

/// Without a sweep, on an adapter at `kbit` that reports bus errors: the fix names its rate
/// and the sweep, which finds the bus's (a wrong rate is the likeliest cause of them).
pub fn offer(d: &mut Diagnosis, kbit: u32) {
    let bus_errors = Cause::Controller { state: ControllerState::BusErrors };
    for f in d.findings.iter_mut().filter(|f| f.cause == bus_errors && f.remedy == Remedy::CheckBus) {
        f.remedy = Remedy::CheckBusOrSweep { kbit };
    }
}

/// The finding the trials show, if any.
fn judge(d: &mut Diagnosis, trials: Vec<RateHeard>, own_kbit: Option<u32>) {
    let clean: Vec<u32> = trials.iter().filter(|t| t.clean()).map(|t| t.kbit).collect();
    let evidence = Evidence::Sweep { trials };
    match clean[..] {
        // One rate hears the traffic cleanly and it is not the link's: that is the bus's.
        [kbit] if own_kbit != Some(kbit) => {
            // Ahead of the controller's bus errors, which it explains (a stable sort
            // keeps it there among the causes of its rank).
            let (cause, remedy) = (Cause::OtherBitRate { kbit }, Remedy::UseBitRate { kbit });
            d.findings.insert(0, Finding { cause, evidence: vec![evidence], remedy });
            d.findings.sort_by_key(|f| f.cause.rank());
            d.ok = false;
        }
        // The link's own rate, no traffic at any (nothing to tell a rate by), or several
        // (a bus quiet enough to decode by chance): no rate to name.
        _ => d.fine.push(evidence),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn heard(clean_at: &[u32], errors_elsewhere: bool) -> Vec<RateHeard> {
        RATES
            .iter()
            .map(|&kbit| match clean_at.contains(&kbit) {
                true => RateHeard { kbit, frames: 12, errors: false },
                false => RateHeard { kbit, frames: 0, errors: errors_elsewhere },
            })
            .collect()
    }

    fn diagnosis() -> Diagnosis {
        Diagnosis {
            bus: "slcan:/dev/pts/3@250k".into(),
            node: None,
            listened_ms: 0,
            findings: vec![],
            fine: vec![],
            ok: true,
        }
    }

    #[test]
    fn the_one_clean_rate_other_than_the_links_is_named() {
        let mut d = diagnosis();
        judge(&mut d, heard(&[500], true), Some(250));
        assert!(!d.ok);
        assert_eq!(d.findings[0].cause, Cause::OtherBitRate { kbit: 500 });
        assert_eq!(d.findings[0].remedy, Remedy::UseBitRate { kbit: 500 });
    }

    #[test]
    fn the_links_own_rate_or_no_traffic_names_nothing() {
        for (clean, own) in [(&[250][..], Some(250)), (&[][..], Some(250)), (&[250, 500][..], Some(125))] {
            let mut d = diagnosis();
            judge(&mut d, heard(clean, false), own);
            assert!(d.findings.is_empty() && d.ok, "{clean:?}");
            assert!(matches!(d.fine[..], [Evidence::Sweep { .. }]));
        }
    }
}
