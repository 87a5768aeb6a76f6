//! Through an EPOS2 gateway: canctl sees none of the bus's traffic, but the EPOS2 (node 0,
//! itself) says how its side of the bus is: its error register 0x1001 (bit 4, a
//! communication error: CAN overrun, error passive, bus-off) and the CAN bit rate it runs
//! at, 0x2001 (EPOS2 firmware specification). Two reads of its own dictionary.

use super::{Cause, Diagnosis, Evidence, Finding, Remedy};
use crate::bus::{Bus, SdoOptions};
use crate::canopen::ObjAddr;
use crate::error::{Error, Result};
use std::time::Duration;

const ERROR_REGISTER: ObjAddr = ObjAddr::new(0x1001, 0);
/// EPOS2 firmware specification: "CAN Bitrate", its own code table.
const CAN_BIT_RATE: ObjAddr = ObjAddr::new(0x2001, 0);
/// The error register's communication bit (CiA 301).
const COMMUNICATION: u8 = 0x10;

/// Read the gateway's error register and bit rate: a communication error is a finding (its
/// CAN side sees errors), else what it said is fine; both go with a silent node or bus.
pub(super) fn look(bus: &mut dyn Bus, timeout: Duration, d: &mut Diagnosis) -> Result<()> {
    let opts = SdoOptions::new(timeout);
    let mut read = |addr| match bus.sdo_upload(0, addr, &opts) {
        Ok(v) => Ok(Some(v)),
        Err(e) if matches!(e.root(), Error::Link(_)) => Err(e),
        Err(_) => Ok(None),
    };
    let error_register = read(ERROR_REGISTER)?.and_then(|b| b.first().copied());
    let bit_rate_code = read(CAN_BIT_RATE)?.filter(|b| b.len() >= 2).map(|b| u16::from_le_bytes([b[0], b[1]]));
    let seen = Evidence::Epos2Gateway { error_register, bit_rate_code };
    let silent: Vec<&mut Finding> =
        d.findings.iter_mut().filter(|f| matches!(f.cause, Cause::BusSilent | Cause::NodeSilent { .. })).collect();
    let explains = !silent.is_empty();
    silent.into_iter().for_each(|f| f.evidence.push(seen.clone()));
    match error_register {
        Some(register) if register & COMMUNICATION != 0 => d.findings.push(Finding {
            cause: Cause::Epos2CanErrors { register },
            evidence: vec![seen],
            remedy: Remedy::CheckBus,
        }),
        // Fine, unless it is already the evidence of a silence.
        _ if !explains => d.fine.push(seen),
        _ => {}
    }
    Ok(())
}

/// The CiA 305 bit-rate index of an EPOS2 0x2001 code; `None` for 9 (it detects the bus's
/// rate) and codes it does not have.
pub(crate) fn bit_rate_index(code: u16) -> Option<u8> {
    (0..=8).find(|i| crate::ops::lss::epos2_bit_rate_code(*i) == Some(code))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_epos2_codes_are_its_own_table() {
        assert_eq!(bit_rate_index(0), Some(0)); // 1 Mbit/s
        assert_eq!(bit_rate_index(2), Some(2)); // 500 kbit/s
        assert_eq!(bit_rate_index(5), Some(6)); // 50 kbit/s, CiA 305's index 6
        assert_eq!(bit_rate_index(6), Some(7)); // 20 kbit/s
        assert_eq!(bit_rate_index(9), None); // automatic detection
    }
}
