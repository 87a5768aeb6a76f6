//! Through an EPOS2 gateway: canctl sees none of the bus's traffic, but the EPOS2 (node 0,
//! itself) says how its side of the bus is: its error register 0x1001 (bit 4, a
//! communication error: CAN overrun, error passive, bus-off) and the CAN bit rate it runs
//! at, 0x2001 (EPOS2 firmware specification). Two reads of its own dictionary.

use super::report::{Cause, Diagnosis, Evidence, Finding, Remedy};
use crate::bus::Bus;
use crate::canopen::ObjAddr;
use crate::error::{Error, Result};
use std::time::Duration;

use crate::epos2::objects::CAN_BIT_RATE;
/// The error register's communication bit (CiA 301).
const COMMUNICATION: u8 = 0x10;

/// Read the gateway's error register and bit rate: a communication error is a finding (its
/// CAN side sees errors), else what it said is fine; both go with a silent node or bus.
pub(super) fn look(bus: &mut dyn Bus, timeout: Duration, d: &mut Diagnosis) -> Result<()> {
    let opts = crate::ops::sdo_options::capped(timeout, crate::ops::sdo_options::NUMBER_LIMIT);
    let mut read = |addr| match bus.sdo_upload(0, addr, &opts) {
        Ok(v) => Ok(Some(v)),
        Err(e) if matches!(e.root(), Error::Link(_)) => Err(e),
        Err(_) => Ok(None),
    };
    let error_register = read(ObjAddr::ERROR_REGISTER)?.and_then(|b| b.first().copied());
    let bit_rate_code = read(CAN_BIT_RATE)?.filter(|b| b.len() >= 2).map(|b| u16::from_le_bytes([b[0], b[1]]));
    judge(error_register, bit_rate_code, d);
    Ok(())
}

/// What the gateway said, into the diagnosis.
fn judge(error_register: Option<u8>, bit_rate_code: Option<u16>, d: &mut Diagnosis) {
    let seen = Evidence::Epos2Gateway { error_register, bit_rate_code };
    let silent: Vec<&mut Finding> =
        d.findings.iter_mut().filter(|f| matches!(f.cause, Cause::BusSilent | Cause::NodeSilent { .. })).collect();
    let explains = !silent.is_empty();
    silent.into_iter().for_each(|f| f.evidence.push(seen.clone()));
    match error_register {
        Some(register) if register & COMMUNICATION != 0 => {
            let cause = Cause::Epos2CanErrors { register };
            d.findings.push(Finding { cause, evidence: vec![seen], remedy: Remedy::CheckBus })
        }
        // Fine, unless it is already the evidence of a silence.
        _ if !explains => d.fine.push(seen),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn diagnosis(findings: Vec<Finding>) -> Diagnosis {
        Diagnosis { bus: "epos2-usb:x".into(), node: Some(6), listened_ms: 0, findings, fine: vec![], ok: false }
    }

    #[test]
    fn a_communication_error_is_a_finding_and_the_rest_evidence() {
        let silent =
            Finding { cause: Cause::NodeSilent { node: 6 }, evidence: vec![], remedy: Remedy::CheckNode { node: 6 } };
        // Error passive: the communication bit (and generic) set.
        let mut d = diagnosis(vec![silent.clone()]);
        judge(Some(0x11), Some(2), &mut d);
        let seen = Evidence::Epos2Gateway { error_register: Some(0x11), bit_rate_code: Some(2) };
        assert_eq!(d.findings[0].evidence, vec![seen.clone()]);
        assert_eq!(d.findings[1].cause, Cause::Epos2CanErrors { register: 0x11 });
        assert!(d.fine.is_empty());
        // A voltage error is not the bus's: evidence only, fine when nothing is silent.
        let mut d = diagnosis(vec![]);
        judge(Some(0x05), Some(0), &mut d);
        assert!(d.findings.is_empty());
        assert_eq!(d.fine, vec![Evidence::Epos2Gateway { error_register: Some(0x05), bit_rate_code: Some(0) }]);
        let mut d = diagnosis(vec![silent]);
        judge(None, None, &mut d);
        assert_eq!((d.findings.len(), d.fine.len()), (1, 0));
    }
}
