//! A CiA 302-3 bootloader on the simulated bus, behaving as real ones do: the erase takes
//! seconds of bus time (the busy bit of 0x1F57 shows it), program data is refused outside
//! pre-operational or before a clear (abort 0x08000022), 0x1F56 is the CRC-32 of the
//! program that will run, and "start" resets the device. As Zephyr's and CANopenNode's do,
//! it answers "start" first and then resets (a master that writes 0x1F51 = 1 and then waits
//! for the boot-up sees it); some reset before they can answer ([`START_STYLE`]). A reset
//! takes [`BOOT_TIME`] ms of bus time before the boot-up (an image swap takes seconds),
//! silent all the while. Faults
//! armed through [`FAULT_OBJECT`]: power lost mid-download, a flash write error, a device
//! that reboots into its bootloader when told to stop.
//!
//! Its state lives in the dictionary and in "flash" (the device's stored values), so a
//! reset, and the state file between invocations, keep it as hardware would.

use super::device::objects::ObjectStore;
use super::profiles::{Model, BASIC_LSS};
use crate::canopen::program::{self, code, FlashStatus, FLASH_STATUS, PROGRAM_CONTROL, PROGRAM_DATA, SOFTWARE_ID};
use crate::canopen::sdo::{ObjectAccess, SdoServer};
use crate::canopen::DataType::*;
use crate::canopen::{abort, nmt, ObjAddr};
use crate::od::Access::*;
use crate::od::{le as u, text, Dictionary, Init};

/// The model key (state file, `Network::device_mut`).
pub const KEY: &str = "bootloader";
/// How long a clear (erase) keeps the flash busy, in ms of bus time.
pub const ERASE_MS: u64 = 2500;
/// How long writing the last of the data keeps it busy once the transfer is done.
pub(crate) const WRITE_MS: u64 = 200;
/// The program the device leaves the factory with.
pub const FACTORY_IMAGE: &[u8] = b"canctl simulated bootloader: factory program";

/// The simulator's handle: which fault the bootloader has (see [`Fault`]).
pub const FAULT_OBJECT: ObjAddr = ObjAddr::new(0x5F51, 0);
/// The simulator's handle: how long a reset takes until the boot-up, in ms.
pub const BOOT_TIME: ObjAddr = ObjAddr::new(0x5F52, 0);
/// The boot time a bootloader starts with: a real one takes 100 ms to seconds.
pub const DEFAULT_BOOT_MS: u64 = 500;
/// The simulator's handle: 1, "start" is answered before the reset (the default); 0, the
/// device resets before it can answer.
pub const START_STYLE: ObjAddr = ObjAddr::new(0x5F53, 0);

/// A bootloader fault, the value of [`FAULT_OBJECT`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Fault {
    /// No fault: downloads and starts go as a real device's do.
    None = 0,
    /// Power is lost halfway through the next download (once): the device comes back in
    /// its bootloader with no valid program.
    PowerLoss = 1,
    /// Every write of program data ends in a flash write error (flash status code 5).
    FlashWrite = 2,
    /// Told to stop, it reboots into its bootloader instead of answering.
    RebootOnStop = 3,
}

const BUSY_UNTIL: ObjAddr = ObjAddr::new(0x5F50, 1);
/// 1: cleared, program data may come; 2: a program written, not yet started.
const CLEARED: ObjAddr = ObjAddr::new(0x5F50, 2);
/// Frames of program data until the power goes (armed by [`Fault::PowerLoss`]).
const POWER_LEFT: ObjAddr = ObjAddr::new(0x5F50, 3);

const CONTROL: ObjAddr = ObjAddr::new(PROGRAM_CONTROL, 1);
const ID: ObjAddr = ObjAddr::new(SOFTWARE_ID, 1);
const STATUS: ObjAddr = ObjAddr::new(FLASH_STATUS, 1);
const DATA: ObjAddr = ObjAddr::new(PROGRAM_DATA, 1);

/// A device with one program and a CiA 302-3 bootloader (heartbeat 100 ms);
/// `block_transfer: false` makes one that refuses SDO block transfer.
pub fn model(block_transfer: bool) -> Model {
    let mut d = Dictionary::default();
    d.var(0x1000, "Device type", U32, Ro, u(0, U32));
    d.var(0x1001, "Error register", U8, Ro, u(0, U8));
    d.var(0x1008, "Manufacturer device name", Vs, Const, text("SimBoot"));
    d.var(0x100A, "Manufacturer software version", Vs, Const, text("boot 1.0"));
    d.var(0x1017, "Producer heartbeat time", U16, Rw, u(100, U16));
    let identity = [0x0000_0ABC_u64, 0x0000_0302, 0x0001_0000, 0x0000_0001];
    let names = ["Vendor-ID", "Product code", "Revision number", "Serial number"];
    d.record(
        0x1018,
        "Identity object",
        identity.iter().zip(names).enumerate().map(|(i, (v, n))| (i as u8 + 1, n, U32, Ro, u(*v, U32))).collect(),
    );
    d.record(0x1F50, "Program data", vec![(1, "Program number 1", D, Wo, Init::Bytes(vec![]))]);
    d.array(0x1F51, "Program control", vec![(1, "Program number 1", U8, Rw, u(1, U8))]);
    let factory = program::image_id(FACTORY_IMAGE) as u64;
    d.array(0x1F56, "Program software identification", vec![(1, "Program number 1", U32, Ro, u(factory, U32))]);
    d.array(0x1F57, "Flash status identification", vec![(1, "Program number 1", U32, Ro, u(0, U32))]);
    d.record(
        0x5F50,
        "Simulated bootloader state",
        vec![
            (1, "Flash busy until (ms)", U64, Ro, u(0, U64)),
            (2, "Cleared (1), written and not yet started (2)", U8, Ro, u(0, U8)),
            (3, "Program data frames until power loss", U32, Ro, u(0, U32)),
        ],
    );
    d.var(0x5F51, "Simulated bootloader fault", U8, Rw, u(0, U8)).range = Some((0, 3));
    d.var(0x5F52, "Simulated boot time (ms)", U16, Rw, u(DEFAULT_BOOT_MS, U16));
    d.var(0x5F53, "Simulated start answered before the reset", U8, Rw, u(1, U8)).range = Some((0, 1));
    let key = if block_transfer { KEY.into() } else { format!("{KEY}-segmented") };
    Model { block_transfer, lss: BASIC_LSS, ..Model::plain(key, d) }
}

/// Whether a device's dictionary makes it a bootloader.
pub(crate) fn is_bootloader(od: &ObjectStore) -> bool {
    od.value(CONTROL).is_some() && od.value(BUSY_UNTIL).is_some()
}

/// How long a reset of this bootloader takes until its boot-up, in ms.
pub(crate) fn boot_ms(od: &ObjectStore) -> u64 {
    od.u16_value(BOOT_TIME).map_or(DEFAULT_BOOT_MS, u64::from)
}

/// One SDO request to a bootloader: the answers, and whether the device resets after them
/// (it then is silent until its boot-up). A device that resets before it can answer (the
/// power lost, a reset-first "start", a reboot into the bootloader) sends no answer.
pub(crate) fn on_request(
    sdo: &mut SdoServer,
    od: &mut ObjectStore,
    raw: &[u8],
    nmt: nmt::State,
    now_ms: u64,
) -> (Vec<[u8; 8]>, bool) {
    if starts_program_download(raw) && fault(od) == Fault::PowerLoss && may_program(od, nmt, now_ms).is_ok() {
        // Half the announced size, in frames of 7 bytes (block segments) at the least.
        let size = raw.get(4..8).map_or(0, |b| u32::from_le_bytes(b.try_into().expect("4 bytes")));
        od.keep(POWER_LEFT, (size / 14).max(1).to_le_bytes().to_vec());
    } else if let Some(left) = od.u32_value(POWER_LEFT).filter(|n| *n > 0) {
        if left == 1 {
            power_lost(od);
            return (vec![], true);
        }
        od.keep(POWER_LEFT, (left - 1).to_le_bytes().to_vec());
    }
    let mut flash = Flash { od, nmt, now_ms, reboot: false, answered_first: false };
    let answers = sdo.handle(raw, &mut flash);
    // Reset before it could answer: no answer.
    let answered = !flash.reboot || flash.answered_first;
    (if answered { answers } else { vec![] }, flash.reboot)
}

/// An SDO download initiate (segmented/expedited or block) to the program data.
fn starts_program_download(raw: &[u8]) -> bool {
    let (Some(cmd), Some(index), Some(sub)) = (raw.first(), raw.get(1..3), raw.get(3)) else { return false };
    let index = u16::from_le_bytes([index[0], index[1]]);
    let initiate = cmd >> 5 == 1 || (cmd >> 5 == 6 && cmd & 1 == 0);
    initiate && index == PROGRAM_DATA && *sub == 1
}

fn busy_until(od: &ObjectStore) -> u64 {
    od.value(BUSY_UNTIL).and_then(|v| v.try_into().ok()).map_or(0, u64::from_le_bytes)
}

fn fault(od: &ObjectStore) -> Fault {
    match od.u8_value(FAULT_OBJECT) {
        Some(1) => Fault::PowerLoss,
        Some(2) => Fault::FlashWrite,
        Some(3) => Fault::RebootOnStop,
        _ => Fault::None,
    }
}

fn set_status(od: &mut ObjectStore, code: u8) {
    od.keep(STATUS, FlashStatus::encode(code, false).to_le_bytes().to_vec());
}

/// Program data is taken only in pre-operational, after a clear, once the erase is over.
fn may_program(od: &ObjectStore, nmt: nmt::State, now_ms: u64) -> Result<(), u32> {
    let cleared = od.value(CLEARED) == Some(&[1]);
    if nmt != nmt::State::PreOperational || !cleared || now_ms < busy_until(od) {
        return Err(abort::WRONG_STATE);
    }
    Ok(())
}

/// The power went mid-download: half a program in flash, which the bootloader finds
/// invalid when it comes back.
fn power_lost(od: &mut ObjectStore) {
    od.keep(POWER_LEFT, 0u32.to_le_bytes().to_vec());
    od.keep(FAULT_OBJECT, vec![0]);
    od.keep(CLEARED, vec![0]);
    od.keep(CONTROL, vec![program::Control::Stop.code()]);
    od.keep(ID, 0u32.to_le_bytes().to_vec());
    set_status(od, code::NO_VALID_PROGRAM);
}

/// The dictionary as the bootloader's SDO server sees it: its own objects act, the rest
/// are plain values.
struct Flash<'a> {
    od: &'a mut ObjectStore,
    nmt: nmt::State,
    now_ms: u64,
    reboot: bool,
    /// The request that makes it reset is answered first.
    answered_first: bool,
}

impl Flash<'_> {
    fn on_control(&mut self, command: u8) -> Result<(), u32> {
        use program::Control;
        let od = &mut *self.od;
        let running =
            matches!(Control::from_code(od.u8_value(CONTROL).unwrap_or(0)), Control::Start | Control::Confirm);
        match Control::from_code(command) {
            Control::Stop => {
                od.keep(CONTROL, vec![0]);
                // A device whose bootloader is a separate image gets there by a reset.
                self.reboot = running && fault(od) == Fault::RebootOnStop;
            }
            Control::Start => {
                let valid = od.u32_value(ID).unwrap_or(0) != 0
                    && FlashStatus::decode(od.u32_value(STATUS).unwrap_or(0)).code == 0;
                if !valid || self.now_ms < busy_until(od) {
                    return Err(abort::WRONG_STATE);
                }
                if !running {
                    // A new program runs on trial until confirmed (Zephyr's MCUboot rule);
                    // the bootloader jumps to it by a reset, after its answer or before.
                    let fresh = od.value(CLEARED) == Some(&[2]);
                    od.keep(CLEARED, vec![0]);
                    od.keep(CONTROL, vec![if fresh { Control::Confirm.code() } else { 1 }]);
                    self.reboot = true;
                    self.answered_first = od.value(START_STYLE) != Some(&[0]);
                }
            }
            Control::Reset => set_status(od, code::OK),
            Control::Clear => {
                if running || self.nmt != nmt::State::PreOperational || self.now_ms < busy_until(od) {
                    return Err(abort::WRONG_STATE);
                }
                od.keep(CONTROL, vec![Control::Clear.code()]);
                od.keep(ID, 0u32.to_le_bytes().to_vec());
                set_status(od, code::OK);
                od.keep(CLEARED, vec![1]);
                od.keep(BUSY_UNTIL, (self.now_ms + ERASE_MS).to_le_bytes().to_vec());
            }
            Control::Confirm => {
                if !running {
                    return Err(abort::WRONG_STATE);
                }
                od.keep(CONTROL, vec![1]);
            }
            Control::Other(_) => return Err(abort::INVALID_VALUE),
        }
        Ok(())
    }

    fn on_program(&mut self, data: &[u8]) -> Result<(), u32> {
        may_program(self.od, self.nmt, self.now_ms)?;
        let od = &mut *self.od;
        let failed = fault(od) == Fault::FlashWrite;
        od.keep(POWER_LEFT, 0u32.to_le_bytes().to_vec());
        od.keep(CLEARED, vec![if failed { 0 } else { 2 }]);
        od.keep(CONTROL, vec![program::Control::Stop.code()]);
        od.keep(BUSY_UNTIL, (self.now_ms + WRITE_MS).to_le_bytes().to_vec());
        od.keep(ID, if failed { 0 } else { program::image_id(data) }.to_le_bytes().to_vec());
        set_status(od, if failed { code::FLASH_WRITE_ERROR } else { code::OK });
        Ok(())
    }
}

impl ObjectAccess for Flash<'_> {
    fn read(&mut self, addr: ObjAddr) -> Result<Vec<u8>, u32> {
        let value = self.od.read(addr)?;
        if addr == STATUS && self.now_ms < busy_until(self.od) {
            let raw = self.od.u32_value(STATUS).unwrap_or(0) | program::BUSY;
            return Ok(raw.to_le_bytes().to_vec());
        }
        Ok(value)
    }

    fn check_write(&self, addr: ObjAddr, size: Option<usize>) -> Result<(), u32> {
        if addr == DATA {
            return may_program(self.od, self.nmt, self.now_ms);
        }
        self.od.check_write(addr, size)
    }

    fn fixed_size(&self, addr: ObjAddr) -> Option<usize> {
        self.od.fixed_size(addr)
    }

    fn write(&mut self, addr: ObjAddr, data: &[u8]) -> Result<(), u32> {
        match addr {
            DATA => self.on_program(data),
            CONTROL => {
                self.od.check_write(addr, Some(data.len()))?;
                self.on_control(data[0])
            }
            _ => self.od.write(addr, data),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn program_download_initiates_are_told_apart_from_other_requests() {
        // Segmented initiate with size (0x21), block initiate with CRC and size (0xC6).
        assert!(starts_program_download(&[0x21, 0x50, 0x1F, 1, 0x00, 0x40, 0, 0]));
        assert!(starts_program_download(&[0xC6, 0x50, 0x1F, 1, 0x00, 0x00, 0x04, 0]));
        // Block download end (0xC1 and friends: bit 0 set), another object, another
        // program, an upload.
        assert!(!starts_program_download(&[0xC1, 0x50, 0x1F, 1, 0, 0, 0, 0]));
        assert!(!starts_program_download(&[0x21, 0x51, 0x1F, 1, 1, 0, 0, 0]));
        assert!(!starts_program_download(&[0x21, 0x50, 0x1F, 2, 0, 0, 0, 0]));
        assert!(!starts_program_download(&[0x40, 0x50, 0x1F, 1, 0, 0, 0, 0]));
    }
}
