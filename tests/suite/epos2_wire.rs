//! Every EPOS2 command's request and answer bytes, pinned to the layouts of seed 000
//! chapter 3 (parameters, word counts) and to the byte-exact examples of seeds 000 and 002,
//! not to an encode-then-decode with canctl's own code.
//!
//! The frames are built here by a reference framer written from the seeds' text (header
//! word, CRC over the words and a zero word, DLE stuffing), which is itself first checked
//! against all four example exchanges of the seeds. The parameter bytes of each command
//! are written out by hand from the seed's parameter table.

use canctl::canopen::ObjAddr;
use canctl::epos2::command::{self, Command};
use canctl::epos2::frame::{self, Frame};
use canctl::sim::epos2_device::Epos2Device;
use canctl::sim::SimLink;
use std::time::Duration;

/// Seed 000 §5.1.5: CRC-CCITT (polynomial 0x1021, start 0) over the 16-bit words of the
/// frame, each most significant bit first, followed by a zero word.
fn ref_crc(words: &[u16]) -> u16 {
    let mut crc = 0u16;
    for &word in words.iter().chain(&[0u16]) {
        for bit in (0..16).rev() {
            let carry = crc & 0x8000 != 0;
            crc = (crc << 1) | ((word >> bit) & 1);
            if carry {
                crc ^= 0x1021;
            }
        }
    }
    crc
}

/// Data bytes as the seed's words: low byte first.
fn words(data: &[u8]) -> Vec<u16> {
    assert!(data.len().is_multiple_of(2), "whole words");
    data.chunks(2).map(|w| u16::from_le_bytes([w[0], w[1]])).collect()
}

/// Seed 000 §5.1.3: OpCode, Len-1 (words), data, CRC low byte first; the header word for
/// the CRC is OpCode<<8 | Len-1.
fn ref_rs232(opcode: u8, data: &[u8]) -> Vec<u8> {
    let n = (data.len() / 2) as u8;
    let mut all = vec![(opcode as u16) << 8 | (n - 1) as u16];
    all.extend(words(data));
    let mut out = vec![opcode, n - 1];
    out.extend_from_slice(data);
    out.extend_from_slice(&ref_crc(&all).to_le_bytes());
    out
}

/// Seed 000 §4.1.3/§4.1.5: DLE STX, then OpCode, Len (words), data, CRC, with every DLE
/// (0x90) after the start doubled; the header word for the CRC is Len<<8 | OpCode.
fn ref_usb(opcode: u8, data: &[u8]) -> Vec<u8> {
    let n = (data.len() / 2) as u8;
    let mut all = vec![(n as u16) << 8 | opcode as u16];
    all.extend(words(data));
    let mut body = vec![opcode, n];
    body.extend_from_slice(data);
    body.extend_from_slice(&ref_crc(&all).to_le_bytes());
    let mut out = vec![0x90, 0x02];
    for b in body {
        out.push(b);
        if b == 0x90 {
            out.push(0x90);
        }
    }
    out
}

fn hex(s: &str) -> Vec<u8> {
    s.split_whitespace().map(|b| u8::from_str_radix(b, 16).unwrap()).collect()
}

#[test]
fn the_reference_framer_reproduces_every_example_of_the_seeds() {
    // Seed 000 table 4-4 / 4-5: ReadObject "Home Offset" over USB and its answer (the
    // answer's word 0x8090 is stuffed).
    assert_eq!(ref_usb(0x10, &hex("81 20 00 01")), hex("90 02 10 02 81 20 00 01 0F 87"));
    assert_eq!(ref_usb(0x00, &hex("00 00 00 00 00 00 90 80")), hex("90 02 00 04 00 00 00 00 00 00 90 90 80 14 35"));
    // Seed 000 table 5-7 / 5-8: ReadObject "Software Version" over RS232 and its answer.
    assert_eq!(ref_rs232(0x10, &hex("03 20 01 02")), hex("10 01 03 20 01 02 88 A8"));
    assert_eq!(ref_rs232(0x00, &hex("00 00 00 00 10 20 10 62")), hex("00 03 00 00 00 00 10 20 10 62 10 26"));
    // Seed 002: ReadObject DeviceType of node 2 through the gateway, USB and RS232.
    assert_eq!(ref_usb(0x10, &hex("00 10 00 02")), hex("90 02 10 02 00 10 00 02 DF F2"));
    assert_eq!(ref_usb(0x00, &hex("00 00 00 00 92 01 02 00")), hex("90 02 00 04 00 00 00 00 92 01 02 00 9A ED"));
    assert_eq!(ref_rs232(0x10, &hex("00 10 00 02")), hex("10 01 00 10 00 02 10 CD"));
    assert_eq!(ref_rs232(0x00, &hex("00 00 00 00 92 01 02 00")), hex("00 03 00 00 00 00 92 01 02 00 EB 6D"));
}

#[test]
fn canctl_frames_the_seed_examples_byte_for_byte() {
    let f = |op: u8, d: &str| Frame { opcode: op, data: hex(d) };
    assert_eq!(frame::usb_encode(&f(0x10, "81 20 00 01")), hex("90 02 10 02 81 20 00 01 0F 87"));
    assert_eq!(
        frame::usb_encode(&f(0x00, "00 00 00 00 00 00 90 80")),
        hex("90 02 00 04 00 00 00 00 00 00 90 90 80 14 35")
    );
    assert_eq!(frame::rs232_encode(&f(0x10, "03 20 01 02")), hex("10 01 03 20 01 02 88 A8"));
    assert_eq!(frame::rs232_encode(&f(0x00, "00 00 00 00 10 20 10 62")), hex("00 03 00 00 00 00 10 20 10 62 10 26"));
    // And reads them.
    assert_eq!(
        frame::usb_decode(&hex("90 02 00 04 00 00 00 00 00 00 90 90 80 14 35")),
        Ok(f(0x00, "00 00 00 00 00 00 90 80"))
    );
    assert_eq!(
        frame::rs232_decode(&hex("00 03 00 00 00 00 92 01 02 00 EB 6D")),
        Ok(f(0x00, "00 00 00 00 92 01 02 00"))
    );
    // Seed 000 §4.1.5: the stuffing examples.
    assert_eq!(frame::stuff(&hex("21 90 45")), hex("21 90 90 45"));
    assert_eq!(frame::stuff(&hex("21 90 02 45")), hex("21 90 90 02 45"));
    assert_eq!(frame::stuff(&hex("21 90 90 45")), hex("21 90 90 90 90 45"));
}

/// Every command of seed 000 chapter 3 with its parameter bytes as the seed lays them out.
fn requests() -> Vec<(Command, u8, &'static str)> {
    let a = ObjAddr::new;
    vec![
        // ReadObject: WORD Index, BYTE SubIndex, BYTE NodeId (2 words).
        (Command::ReadObject { node: 2, addr: a(0x2003, 1) }, 0x10, "03 20 01 02"),
        // WriteObject: WORD Index, BYTE SubIndex, BYTE NodeId, BYTE Data[4] (4 words).
        (
            Command::WriteObject { node: 1, addr: a(0x607A, 0), data: [0x78, 0x56, 0x34, 0x12] },
            0x11,
            "7A 60 00 01 78 56 34 12",
        ),
        // InitiateSegmentedRead: as ReadObject (2 words).
        (Command::InitiateSegmentedRead { node: 10, addr: a(0x1008, 0) }, 0x12, "08 10 00 0A"),
        // InitiateSegmentedWrite: object, then DWORD ObjectLength (4 words).
        (
            Command::InitiateSegmentedWrite { node: 1, addr: a(0x1F50, 1), length: 0x0001_0000 },
            0x13,
            "50 1F 01 01 00 00 01 00",
        ),
        // SegmentRead: BYTE ControlByte (bit 6 toggle), BYTE Dummy (1 word).
        (Command::SegmentRead { toggle: false }, 0x14, "00 00"),
        (Command::SegmentRead { toggle: true }, 0x14, "40 00"),
        // SegmentWrite: ControlByte (bits 0-5 length, bit 6 toggle), Data[0..63]: an odd
        // byte count is filled up to a whole word.
        (Command::SegmentWrite { toggle: true, data: hex("01 02 03 04 05") }, 0x15, "45 01 02 03 04 05"),
        (Command::SegmentWrite { toggle: false, data: hex("AA BB") }, 0x15, "02 AA BB 00"),
        // SendNMTService: WORD NodeId, WORD CmdSpecifier (129 = reset node) (2 words).
        (Command::SendNmtService { node: 5, specifier: 129 }, 0x0E, "05 00 81 00"),
        (Command::SendNmtService { node: 0, specifier: 1 }, 0x0E, "00 00 01 00"),
        // SendCANFrame: WORD Identifier, WORD Length (DLC), BYTE Data[8] (6 words).
        (Command::SendCanFrame { id: 0x080, len: 0, data: [0; 8] }, 0x20, "80 00 00 00 00 00 00 00 00 00 00 00"),
        (
            Command::SendCanFrame { id: 0x205, len: 2, data: [0x0F, 0, 0, 0, 0, 0, 0, 0] },
            0x20,
            "05 02 02 00 0F 00 00 00 00 00 00 00",
        ),
        // RequestCANFrame: WORD Identifier, WORD Length (2 words).
        (Command::RequestCanFrame { id: 0x185, len: 8 }, 0x21, "85 01 08 00"),
        // SendLSSFrame: BYTE Data[8] (4 words); here seed 001's first selective switch.
        (Command::SendLssFrame { data: [0x40, 0x40, 0, 0, 0, 0, 0, 0] }, 0x30, "40 40 00 00 00 00 00 00"),
        // ReadLSSFrame: WORD Timeout in ms (1 word).
        (Command::ReadLssFrame { timeout_ms: 100 }, 0x31, "64 00"),
    ]
}

#[test]
fn every_request_has_the_seeds_layout_in_both_framings() {
    for (cmd, opcode, params) in requests() {
        let params = hex(params);
        let f = cmd.to_frame();
        assert_eq!((f.opcode, &f.data), (opcode, &params), "{}", cmd.name());
        assert_eq!(frame::rs232_encode(&f), ref_rs232(opcode, &params), "{} over RS232", cmd.name());
        assert_eq!(frame::usb_encode(&f), ref_usb(opcode, &params), "{} over USB", cmd.name());
        // The device side reads the seed's bytes as that command.
        let from_rs232 = frame::rs232_decode(&ref_rs232(opcode, &params)).unwrap();
        assert_eq!(Command::from_frame(&from_rs232), Some(cmd.clone()), "{} read from RS232", cmd.name());
        let from_usb = frame::usb_decode(&ref_usb(opcode, &params)).unwrap();
        assert_eq!(Command::from_frame(&from_usb), Some(cmd.clone()), "{} read from USB", cmd.name());
    }
}

#[test]
fn the_longest_segment_is_63_bytes_in_32_words() {
    // Seed 000: SegmentWrite Len 1..32 (Len-1 0..31), Data[0..63].
    let data: Vec<u8> = (1..=63).collect();
    let f = Command::SegmentWrite { toggle: false, data: data.clone() }.to_frame();
    let mut params = vec![63u8];
    params.extend(&data);
    assert_eq!(f.data, params);
    let wire = frame::rs232_encode(&f);
    assert_eq!(wire[1], 31, "Len-1");
    assert_eq!(wire, ref_rs232(0x15, &params));
    assert_eq!(frame::usb_encode(&f)[3], 32, "Len");
}

/// The RS232 answer frames the commands get from the simulated EPOS2 must have the
/// seed's layout: the device side is what stands in for real hardware in every other test.
struct Device(Epos2Device);

impl Device {
    fn new() -> Device {
        Device(Epos2Device::new(SimLink::ephemeral(), Duration::from_secs(2)))
    }

    /// The answer to `cmd` as RS232 bytes (read back with the reference layout).
    fn ask(&mut self, cmd: Command) -> Vec<u8> {
        let request = frame::rs232_decode(&frame::rs232_encode(&cmd.to_frame())).unwrap();
        frame::rs232_encode(&self.0.execute(&request).unwrap())
    }
}

#[test]
fn the_simulated_epos2_answers_in_the_seeds_layout() {
    let mut dev = Device::new();
    let a = ObjAddr::new;
    // ReadObject DeviceType: seed 002's answer, byte for byte (the sim drive is an EPOS2
    // with the same device type), and the same frame over USB.
    let answer = dev.ask(Command::ReadObject { node: 0, addr: a(0x1000, 0) });
    assert_eq!(answer, hex("00 03 00 00 00 00 92 01 02 00 EB 6D"));
    let usb = frame::usb_encode(&frame::rs232_decode(&answer).unwrap());
    assert_eq!(usb, hex("90 02 00 04 00 00 00 00 92 01 02 00 9A ED"));

    // WriteObject: DWORD ErrorCode only (2 words).
    let answer = dev.ask(Command::WriteObject { node: 0, addr: a(0x5FF0, 4), data: [1, 2, 3, 4] });
    assert_eq!(answer, ref_rs232(0x00, &hex("00 00 00 00")));
    // A refusal carries the CiA 301 abort code (seed 000 §8.1) in the same place.
    let answer = dev.ask(Command::WriteObject { node: 0, addr: a(0x1000, 0), data: [1, 0, 0, 0] });
    assert_eq!(answer, ref_rs232(0x00, &hex("02 00 01 06")), "0x06010002 read only");

    // InitiateSegmentedRead: DWORD ErrorCode (2 words); then SegmentRead: ErrorCode,
    // ControlByte (length, toggle, more), Data.
    let answer = dev.ask(Command::InitiateSegmentedRead { node: 0, addr: a(0x1008, 0) });
    assert_eq!(answer, ref_rs232(0x00, &hex("00 00 00 00")));
    let answer = dev.ask(Command::SegmentRead { toggle: false });
    let name = b"EPOS2 24/5";
    let mut want = hex("00 00 00 00");
    want.push(name.len() as u8); // 10 bytes, toggle 0, no more segments
    want.extend_from_slice(name);
    want.push(0); // filled to a whole word
    assert_eq!(answer, ref_rs232(0x00, &want));

    // InitiateSegmentedWrite: DWORD ErrorCode; SegmentWrite: ErrorCode, ControlByte
    // (length, toggle), Dummy (3 words).
    let answer = dev.ask(Command::InitiateSegmentedWrite { node: 0, addr: a(0x5FF0, 12), length: 5 });
    assert_eq!(answer, ref_rs232(0x00, &hex("00 00 00 00")));
    let answer = dev.ask(Command::SegmentWrite { toggle: false, data: b"hello".to_vec() });
    assert_eq!(answer, ref_rs232(0x00, &hex("00 00 00 00 05 00")));
    // Five bytes do not fit ReadObject: 0x06070012 "length too high"; read by segments.
    let answer = dev.ask(Command::ReadObject { node: 0, addr: a(0x5FF0, 12) });
    assert_eq!(answer, ref_rs232(0x00, &hex("12 00 07 06 00 00 00 00")));
    dev.ask(Command::InitiateSegmentedRead { node: 0, addr: a(0x5FF0, 12) });
    let answer = dev.ask(Command::SegmentRead { toggle: false });
    assert_eq!(answer, ref_rs232(0x00, &hex("00 00 00 00 05 68 65 6C 6C 6F")), "'hello' in one segment");

    // SendLSSFrame (USB: ErrorCode) and ReadLSSFrame (ErrorCode, Data[8]): seed 001's
    // selective switch of the sensor and its 0x44 answer.
    for data in
        ["40 40 00 00 00 00 00 00", "41 00 78 78 43 00 00 00", "42 31 30 2E 31 00 00 00", "43 34 12 50 09 00 00 00"]
    {
        let answer = dev.ask(Command::SendLssFrame { data: hex(data).try_into().unwrap() });
        assert_eq!(answer, ref_rs232(0x00, &hex("00 00 00 00")));
    }
    let answer = dev.ask(Command::ReadLssFrame { timeout_ms: 2000 });
    assert_eq!(answer, ref_rs232(0x00, &hex("00 00 00 00 44 00 00 00 00 00 00 00")));

    // SendNMTService and SendCANFrame: ErrorCode (over USB; RS232 sends no answer).
    assert!(!Command::SendNmtService { node: 5, specifier: 1 }.answered_on_rs232());
    assert!(!Command::SendCanFrame { id: 0x80, len: 0, data: [0; 8] }.answered_on_rs232());
    assert!(!Command::SendLssFrame { data: [0; 8] }.answered_on_rs232());
    let answer = dev.ask(Command::SendNmtService { node: 5, specifier: 1 });
    assert_eq!(answer, ref_rs232(0x00, &hex("00 00 00 00")));
    let answer = dev.ask(Command::SendCanFrame { id: 0x080, len: 0, data: [0; 8] });
    assert_eq!(answer, ref_rs232(0x00, &hex("00 00 00 00")));

    // RequestCANFrame: ErrorCode, Data[8] (6 words): the sensor's TPDO1 (position i32,
    // speed i16; seed 001), whatever its values at this moment.
    let answer = dev.ask(Command::RequestCanFrame { id: 0x185, len: 6 });
    assert_eq!(answer.len(), 2 + 12 + 2, "6 words: {answer:02X?}");
    assert_eq!(&answer[..6], hex("00 05 00 00 00 00"), "opcode, Len-1 5, error code 0");
    assert_eq!(&answer[12..14], [0, 0], "a 6-byte PDO in Data[8]");
    let body = frame::rs232_decode(&answer).unwrap().data;
    assert_eq!(answer, ref_rs232(0x00, &body), "the CRC");

    // An unknown opcode: maxon's "RS232 command is illegal" 0x0F00FFBF (seed 000 §8.2).
    let request = Frame { opcode: 0x7F, data: hex("00 00") };
    let answer = frame::rs232_encode(&dev.0.execute(&request).unwrap());
    assert_eq!(&answer[..6], hex("00 01 BF FF 00 0F"));
}

#[test]
fn canctl_reads_the_seeds_answers() {
    // The client's side of the same layouts: error code first, then the data.
    let f = frame::rs232_decode(&hex("00 03 00 00 00 00 92 01 02 00 EB 6D")).unwrap();
    assert_eq!(command::parse_answer(&f), Some((0, &hex("92 01 02 00")[..])));
    let f = frame::usb_decode(&hex("90 02 00 04 00 00 00 00 00 00 90 90 80 14 35")).unwrap();
    assert_eq!(command::parse_answer(&f), Some((0, &hex("00 00 90 80")[..])));
    let refused = frame::rs232_decode(&ref_rs232(0x00, &hex("02 00 01 06"))).unwrap();
    assert_eq!(command::parse_answer(&refused), Some((0x0601_0002, &[][..])));
    // A wrong CRC is caught.
    assert!(frame::rs232_decode(&hex("00 03 00 00 00 00 92 01 02 00 EB 6E")).is_err());
    assert!(frame::usb_decode(&hex("90 02 00 04 00 00 00 00 92 01 02 00 9A EE")).is_err());
}
