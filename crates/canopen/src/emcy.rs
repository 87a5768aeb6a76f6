//! Emergency messages (CiA 301 §7.2.7): 0x080 + node, error code, error register,
//! five manufacturer bytes.

use crate::frame::Frame;

/// The default EMCY COB-ID of `node` (0x080 + node).
pub fn cob(node: u8) -> u16 {
    0x080 + node as u16
}

/// One EMCY message: its error code, error register and manufacturer bytes.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Emergency {
    /// The emergency error code (CiA 301 table 26, or a profile's).
    pub code: u16,
    /// The error register (0x1001) when it was sent.
    pub register: u8,
    /// The five manufacturer-specific bytes.
    pub vendor: [u8; 5],
}

impl Emergency {
    /// Node and message, if `frame` is an EMCY on the default COB-IDs. A zero-length frame
    /// on 0x80+node is the old "EMCY at power on" some drives send (seed 003): no EMCY.
    pub fn parse(frame: &Frame) -> Option<(u8, Emergency)> {
        // A remote frame has no data: no EMCY.
        let node = frame.id().checked_sub(0x080).filter(|n| (1..=127).contains(n))? as u8;
        Some((node, Emergency::decode(frame.data())?))
    }

    /// The message in an EMCY frame's data, whatever COB-ID carried it (0x1014 may move it).
    pub fn decode(d: &[u8]) -> Option<Emergency> {
        let d: &[u8; 8] = d.try_into().ok()?;
        Some(Emergency { code: u16::from_le_bytes([d[0], d[1]]), register: d[2], vendor: d[3..8].try_into().ok()? })
    }

    /// The message as `node` sends it, on its default EMCY COB-ID.
    pub fn frame(&self, node: u8) -> Frame {
        let ([lo, hi], [a, b, c, d, e]) = (self.code.to_le_bytes(), self.vendor);
        Frame::new(cob(node), &[lo, hi, self.register, a, b, c, d, e])
    }

    /// The 0x1003 history entry: error code in the low word, vendor bytes 0..2 high.
    pub fn history_entry(&self) -> u32 {
        self.code as u32 | (u16::from_le_bytes([self.vendor[0], self.vendor[1]]) as u32) << 16
    }
}

/// Where the meaning of an error code comes from.
#[derive(Clone, Copy, PartialEq, Eq, Debug, serde::Serialize)]
pub enum Source {
    /// CiA 301's emergency error codes (its table of classes and the communication codes).
    #[serde(rename = "CiA 301")]
    Cia301,
    /// CiA 402's drive error codes (also IEC 61800-7-201).
    #[serde(rename = "CiA 402")]
    Cia402,
    /// The device's own manual, as the seed documents give it.
    #[serde(rename = "device manual")]
    Device,
}

/// What a code means, and from which table.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Meaning {
    /// The meaning, as the table says it.
    pub text: &'static str,
    /// The table it comes from.
    pub source: Source,
}

/// What is known of the device that logged a code: which tables apply to it.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Origin {
    /// 0x1000: a CiA 402 drive says 402 (0x192) in its low word.
    pub device_type: Option<u32>,
    /// 0x1018:1: the vendor-ID.
    pub vendor: Option<u32>,
    /// 0x1018:2: the product code.
    pub product: Option<u32>,
    /// 0x1008.
    pub name: Option<String>,
}

impl Origin {
    /// Whether the device type names the CiA 402 drive profile.
    pub fn is_drive(&self) -> bool {
        self.device_type.is_some_and(crate::cia402::is_drive)
    }

    /// What the device's own manual (a seed document) says `code` means, where it lists it:
    /// the Temposonics MH sensor's (seed 001, table 2), the ICP DAS CAN-2000C modules' (seed
    /// 004, "EMCY" table, told apart by the first manufacturer-specific byte).
    fn manual_meaning(&self, code: u16, manufacturer: u16) -> Option<&'static str> {
        if self.vendor == Some(0x40) && self.product == Some(0x4378_7800) {
            return find(TEMPOSONICS_MH, code);
        }
        // Seed 004 gives no vendor-ID for ICP DAS, only the modules' names ("CAN-2057C",
        // "CAN-208...": CAN-2, three digits, C).
        let name = self.name.as_deref().unwrap_or("").as_bytes();
        let can2000c = name.len() == 9
            && name.starts_with(b"CAN-2")
            && name[5..8].iter().all(u8::is_ascii_digit)
            && name[8] == b'C';
        let first = manufacturer.to_le_bytes()[0];
        let row = ICP_DAS_CAN2000C.iter().find(|(c, b, _)| can2000c && *c == code && *b == first);
        row.map(|(_, _, m)| *m)
    }
}

/// CiA 301 emergency error codes; `0xNN00` rows also name the class of `0xNNxx`.
const CIA301: &[(u16, &str)] = &[
    (0x0000, "Error reset or no error"),
    (0x1000, "Generic error"),
    (0x2000, "Current"),
    (0x2100, "Current, device input side"),
    (0x2200, "Current inside the device"),
    (0x2300, "Current, device output side"),
    (0x3000, "Voltage"),
    (0x3100, "Mains voltage"),
    (0x3200, "Voltage inside the device"),
    (0x3300, "Output voltage"),
    (0x4000, "Temperature"),
    (0x4100, "Ambient temperature"),
    (0x4200, "Device temperature"),
    (0x5000, "Device hardware"),
    (0x6000, "Device software"),
    (0x6100, "Internal software"),
    (0x6200, "User software"),
    (0x6300, "Data set"),
    (0x7000, "Additional modules"),
    (0x8000, "Monitoring"),
    (0x8100, "Communication"),
    (0x8110, "CAN overrun (objects lost)"),
    (0x8120, "CAN in error passive mode"),
    (0x8130, "Life guard error or heartbeat error"),
    (0x8140, "Recovered from bus off"),
    (0x8150, "CAN-ID collision"),
    (0x8200, "Protocol error"),
    (0x8210, "PDO not processed due to length error"),
    (0x8220, "PDO length exceeded"),
    (0x8230, "DAM MPDO not processed, destination object not available"),
    (0x8240, "Unexpected SYNC data length"),
    (0x8250, "RPDO timeout"),
    (0x9000, "External error"),
    (0xF000, "Additional functions"),
    (0xFF00, "Device specific"),
];

/// CiA 402 drive error codes (the profile's table; IEC 61800-7-201 has the same).
const CIA402: &[(u16, &str)] = &[
    (0x2110, "Short circuit/earth leakage (input)"),
    (0x2120, "Earth leakage (input)"),
    (0x2121, "Earth leakage phase L1"),
    (0x2122, "Earth leakage phase L2"),
    (0x2123, "Earth leakage phase L3"),
    (0x2130, "Short circuit (input)"),
    (0x2131, "Short circuit phases L1-L2"),
    (0x2132, "Short circuit phases L2-L3"),
    (0x2133, "Short circuit phases L3-L1"),
    (0x2211, "Internal current no. 1"),
    (0x2212, "Internal current no. 2"),
    (0x2213, "Over-current in ramp function"),
    (0x2214, "Over-current in the sequence"),
    (0x2220, "Continuous over current (device internal)"),
    (0x2221, "Continuous over current no. 1"),
    (0x2222, "Continuous over current no. 2"),
    (0x2230, "Short circuit/earth leakage (device internal)"),
    (0x2240, "Earth leakage (device internal)"),
    (0x2250, "Short circuit (device internal)"),
    (0x2310, "Continuous over current"),
    (0x2311, "Continuous over current no. 1"),
    (0x2312, "Continuous over current no. 2"),
    (0x2320, "Short circuit/earth leakage (motor-side)"),
    (0x2330, "Earth leakage (motor-side)"),
    (0x2331, "Earth leakage phase U"),
    (0x2332, "Earth leakage phase V"),
    (0x2333, "Earth leakage phase W"),
    (0x2340, "Short circuit (motor-side)"),
    (0x2341, "Short circuit phases U-V"),
    (0x2342, "Short circuit phases V-W"),
    (0x2343, "Short circuit phases W-U"),
    (0x3110, "Mains over-voltage"),
    (0x3111, "Mains over-voltage phase L1"),
    (0x3112, "Mains over-voltage phase L2"),
    (0x3113, "Mains over-voltage phase L3"),
    (0x3120, "Mains under-voltage"),
    (0x3121, "Mains under-voltage phase L1"),
    (0x3122, "Mains under-voltage phase L2"),
    (0x3123, "Mains under-voltage phase L3"),
    (0x3130, "Phase failure"),
    (0x3131, "Phase failure L1"),
    (0x3132, "Phase failure L2"),
    (0x3133, "Phase failure L3"),
    (0x3134, "Phase sequence"),
    (0x3140, "Mains frequency"),
    (0x3141, "Mains frequency too high"),
    (0x3142, "Mains frequency too low"),
    (0x3210, "DC link over-voltage"),
    (0x3211, "DC link over-voltage no. 1"),
    (0x3212, "DC link over-voltage no. 2"),
    (0x3220, "DC link under-voltage"),
    (0x3221, "DC link under-voltage no. 1"),
    (0x3222, "DC link under-voltage no. 2"),
    (0x3230, "Load error"),
    (0x3310, "Output over-voltage"),
    (0x3311, "Output over-voltage phase U"),
    (0x3312, "Output over-voltage phase V"),
    (0x3313, "Output over-voltage phase W"),
    (0x3320, "Armature circuit"),
    (0x3321, "Armature circuit interrupted"),
    (0x3330, "Field circuit"),
    (0x3331, "Field circuit interrupted"),
    (0x4110, "Excess ambient temperature"),
    (0x4120, "Too low ambient temperature"),
    (0x4130, "Temperature supply air"),
    (0x4140, "Temperature air outlet"),
    (0x4210, "Excess temperature device"),
    (0x4220, "Too low temperature device"),
    (0x4300, "Temperature drive"),
    (0x4310, "Excess temperature drive"),
    (0x4320, "Too low temperature drive"),
    (0x4400, "Temperature supply"),
    (0x4410, "Excess temperature supply"),
    (0x4420, "Too low temperature supply"),
    (0x5100, "Supply"),
    (0x5110, "Supply low voltage"),
    (0x5111, "U1 = supply ±15 V"),
    (0x5112, "U2 = supply +24 V"),
    (0x5113, "U3 = supply +5 V"),
    (0x5120, "Supply intermediate circuit"),
    (0x5200, "Control"),
    (0x5210, "Measurement circuit"),
    (0x5220, "Computing circuit"),
    (0x5300, "Operating unit"),
    (0x5400, "Power section"),
    (0x5410, "Output stages"),
    (0x5420, "Chopper"),
    (0x5430, "Input stages"),
    (0x5440, "Contacts"),
    (0x5450, "Fuses"),
    (0x5451, "Fuse S1 = L1"),
    (0x5452, "Fuse S2 = L2"),
    (0x5453, "Fuse S3 = L3"),
    (0x5500, "Data storage"),
    (0x5510, "Working memory (RAM)"),
    (0x5520, "Program memory (EPROM)"),
    (0x5530, "Non-volatile data memory (EEPROM)"),
    (0x6010, "Software reset (watchdog)"),
    (0x6301, "Data record no. 1"),
    (0x6302, "Data record no. 2"),
    (0x6303, "Data record no. 3"),
    (0x6304, "Data record no. 4"),
    (0x6305, "Data record no. 5"),
    (0x6306, "Data record no. 6"),
    (0x6307, "Data record no. 7"),
    (0x6308, "Data record no. 8"),
    (0x6309, "Data record no. 9"),
    (0x630A, "Data record no. 10"),
    (0x630B, "Data record no. 11"),
    (0x630C, "Data record no. 12"),
    (0x630D, "Data record no. 13"),
    (0x630E, "Data record no. 14"),
    (0x630F, "Data record no. 15"),
    (0x6310, "Loss of parameters"),
    (0x6320, "Parameter error"),
    (0x7100, "Power"),
    (0x7110, "Brake chopper"),
    (0x7111, "Failure brake chopper"),
    (0x7112, "Over current brake chopper"),
    (0x7113, "Protective circuit brake chopper"),
    (0x7120, "Motor"),
    (0x7121, "Motor blocked"),
    (0x7122, "Motor error or commutation malfunction"),
    (0x7123, "Motor tilted"),
    (0x7200, "Measurement circuit"),
    (0x7300, "Sensor"),
    (0x7301, "Tacho fault"),
    (0x7302, "Tacho wrong polarity"),
    (0x7303, "Resolver 1 fault"),
    (0x7304, "Resolver 2 fault"),
    (0x7305, "Incremental sensor 1 fault"),
    (0x7306, "Incremental sensor 2 fault"),
    (0x7307, "Incremental sensor 3 fault"),
    (0x7310, "Speed"),
    (0x7320, "Position"),
    (0x7400, "Computation circuit"),
    (0x7500, "Communication"),
    (0x7510, "Serial interface no. 1"),
    (0x7520, "Serial interface no. 2"),
    (0x7600, "Data storage (external)"),
    (0x8300, "Torque control"),
    (0x8311, "Excess torque"),
    (0x8312, "Difficult start up"),
    (0x8313, "Standstill torque"),
    (0x8321, "Insufficient torque"),
    (0x8331, "Torque fault"),
    (0x8400, "Velocity speed controller"),
    (0x8500, "Position controller"),
    (0x8600, "Positioning controller"),
    (0x8611, "Following error"),
    (0x8612, "Reference limit"),
    (0x8700, "Sync controller"),
    (0x8800, "Winding controller"),
    (0x8900, "Process data monitoring"),
    (0x8A00, "Control"),
    (0xF001, "Deceleration"),
    (0xF002, "Sub-synchronous run"),
    (0xF003, "Stroke operation"),
    (0xF004, "Control"),
];

/// Seed 001 table 2: the MH sensor's codes.
const TEMPOSONICS_MH: &[(u16, &str)] = &[
    (0x5000, "Device hardware: no stop pulses in a measuring cycle (magnet missing?)"),
    (0x6300, "Data set: checksum of the non-volatile memory does not match"),
];

/// Seed 004's EMCY table: error code and the first manufacturer-specific byte, which
/// the module also keeps in 0x1003 (bits 16..23).
const ICP_DAS_CAN2000C: &[(u16, u8, &str)] = &[
    (0x0000, 0x00, "Error reset or no error"),
    (0x1000, 0x01, "CAN controller error"),
    (0x5000, 0x02, "EEPROM access error"),
    (0x8110, 0x04, "Soft Rx buffer overrun"),
    (0x8110, 0x05, "Soft Tx buffer overrun"),
    (0x8110, 0x06, "CAN controller overrun"),
    (0x8130, 0x07, "Life guarding fails"),
    (0x8140, 0x08, "Recovered from bus off"),
    (0x8210, 0x09, "PDO data length error"),
    (0xFF00, 0x0A, "Request to reset node or communication"),
];

fn find(table: &[(u16, &'static str)], code: u16) -> Option<&'static str> {
    table.iter().find(|(c, _)| *c == code).map(|(_, m)| *m)
}

/// What `code` means from a device of `origin`; `manufacturer` is the manufacturer-specific
/// part the device sent with it (the upper 16 bits of a 0x1003 entry, EMCY bytes 3 and 4).
/// The device's own manual first, then CiA 402 for drives, then CiA 301.
pub fn meaning(code: u16, manufacturer: u16, origin: &Origin) -> Meaning {
    if let Some(text) = origin.manual_meaning(code, manufacturer) {
        return Meaning { text, source: Source::Device };
    }
    if origin.is_drive() {
        // An exact code, else its group (0x2311 is one of the 0x2310 over-currents).
        if let Some(text) = find(CIA402, code).or_else(|| find(CIA402, code & 0xFFF0)) {
            return Meaning { text, source: Source::Cia402 };
        }
    }
    Meaning { text: code_meaning(code), source: Source::Cia301 }
}

/// The CiA 301 meaning of a code: the exact code where CiA 301 names it, else its class
/// (`0x2310` is "Current, device output side", `0x42AB` "Device temperature").
pub fn code_meaning(code: u16) -> &'static str {
    let class = |mask: u16| find(CIA301, code & mask).filter(|_| code & mask != 0);
    find(CIA301, code)
        .or_else(|| class(0xFFF0))
        .or_else(|| class(0xFF00))
        .or_else(|| class(0xF000))
        .unwrap_or("Unknown error code class")
}

/// One entry of the pre-defined error field 0x1003 (CiA 301): the error code in the low
/// word, manufacturer-specific information in the high word.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct HistoryEntry {
    /// The entry as the device holds it: the error code in the low 16 bits, the
    /// manufacturer's additional information in the high 16.
    pub raw: u32,
}

impl HistoryEntry {
    /// The emergency error code (the low 16 bits).
    pub fn code(&self) -> u16 {
        self.raw as u16
    }

    /// The manufacturer's additional information (the high 16 bits).
    pub fn manufacturer(&self) -> u16 {
        (self.raw >> 16) as u16
    }
}

/// Names of the error register (0x1001) bits that are set.
pub fn register_bits(register: u8) -> Vec<&'static str> {
    const BITS: [&str; 8] =
        ["generic", "current", "voltage", "temperature", "communication", "device profile", "reserved", "manufacturer"];
    (0..8).filter(|b| register & (1 << b) != 0).map(|b| BITS[b]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_004_emcy_table() {
        // The seed's table row "81 10 | 11 | 06 00 00 00 00  CAN Controller Overrun" lists
        // the code high byte first; on the wire it is little-endian.
        let f: Frame = "08A#1081110600000000".parse().unwrap();
        let (node, e) = Emergency::parse(&f).unwrap();
        assert_eq!(node, 10);
        assert_eq!(e.code, 0x8110);
        assert_eq!(code_meaning(e.code), "CAN overrun (objects lost)");
        assert_eq!(register_bits(e.register), vec!["generic", "communication"]);
        assert_eq!(e.frame(10), f);
        assert_eq!(code_meaning(0x2310), "Current, device output side");
        assert!(Emergency::parse(&"085#".parse().unwrap()).is_none());
    }

    fn can2057c() -> Origin {
        Origin { name: Some("CAN-2057C".into()), ..Origin::default() }
    }

    #[test]
    fn seed_004_history_entry_read_by_sdo() {
        // Seed 004, EMCY example step 4: the upload of 0x1003:1 answers 43 03 10 01 10 82 09 00.
        let answer = [0x43, 0x03, 0x10, 0x01, 0x10, 0x82, 0x09, 0x00];
        let e = HistoryEntry { raw: u32::from_le_bytes(answer[4..].try_into().unwrap()) };
        assert_eq!((e.code(), e.manufacturer()), (0x8210, 0x0009));
        assert_eq!(
            meaning(e.code(), e.manufacturer(), &can2057c()),
            Meaning { text: "PDO data length error", source: Source::Device }
        );
        // Without knowing the device: CiA 301's name for the code.
        assert_eq!(
            meaning(e.code(), e.manufacturer(), &Origin::default()).text,
            "PDO not processed due to length error"
        );
    }

    #[test]
    fn seed_004_emcy_codes_by_their_manufacturer_byte() {
        // "30 81 11 07 00 00 00 00 ... indicates a life guard error".
        let (_, e) = Emergency::parse(&"081#3081110700000000".parse().unwrap()).unwrap();
        assert_eq!(e.history_entry(), 0x0007_8130);
        let h = HistoryEntry { raw: e.history_entry() };
        assert_eq!(meaning(h.code(), h.manufacturer(), &can2057c()).text, "Life guarding fails");
        // 8110 is three different overruns, told apart by the first manufacturer byte.
        assert_eq!(meaning(0x8110, 0x0004, &can2057c()).text, "Soft Rx buffer overrun");
        assert_eq!(meaning(0x8110, 0x0006, &can2057c()).text, "CAN controller overrun");
        // A byte the manual does not list: CiA 301.
        assert_eq!(
            meaning(0x8110, 0x0033, &can2057c()),
            Meaning { text: "CAN overrun (objects lost)", source: Source::Cia301 }
        );
        // Only the CAN-2000C family's names pick its table.
        for other in ["CAN-2057", "CAN-20570", "XCAN-2057C", "CAN-2O57C"] {
            let o = Origin { name: Some(other.into()), ..Origin::default() };
            assert_eq!(meaning(0x8110, 0x0004, &o).source, Source::Cia301, "{other}");
        }
    }

    #[test]
    fn seed_001_sensor_codes_by_identity() {
        let mh = Origin { vendor: Some(0x40), product: Some(0x4378_7800), ..Origin::default() };
        assert_eq!(meaning(0x5000, 0, &mh).source, Source::Device);
        assert!(meaning(0x5000, 0, &mh).text.contains("no stop pulses"));
        assert!(meaning(0x6300, 0, &mh).text.starts_with("Data set"));
        let other_product = Origin { product: Some(1), ..mh.clone() };
        assert_eq!(meaning(0x5000, 0, &other_product), Meaning { text: "Device hardware", source: Source::Cia301 });
    }

    #[test]
    fn drives_get_cia_402_names_others_cia_301_classes() {
        let drive = Origin { device_type: Some(0x0002_0192), ..Origin::default() };
        assert!(drive.is_drive());
        assert_eq!(meaning(0x2310, 0, &drive), Meaning { text: "Continuous over current", source: Source::Cia402 });
        assert_eq!(meaning(0x8611, 0, &drive).text, "Following error");
        assert_eq!(meaning(0x3211, 0, &drive).text, "DC link over-voltage no. 1");
        // Not in the table itself: its group.
        assert_eq!(meaning(0x7129, 0, &drive).text, "Motor");
        // Communication codes are CiA 301's on a drive too.
        assert_eq!(
            meaning(0x8130, 0, &drive),
            Meaning { text: "Life guard error or heartbeat error", source: Source::Cia301 }
        );
        let io = Origin { device_type: Some(0x0003_0191), ..Origin::default() };
        assert!(!io.is_drive());
        assert_eq!(meaning(0x8611, 0, &io).text, "Monitoring");
        assert_eq!(code_meaning(0x42AB), "Device temperature");
        assert_eq!(code_meaning(0x1234), "Generic error");
        assert_eq!(code_meaning(0xFF12), "Device specific");
        assert_eq!(code_meaning(0x0005), "Unknown error code class");
        assert_eq!(code_meaning(0xA000), "Unknown error code class");
    }
}
