//! The device models of the demo network, after the devices in `seeds/`. Where a seed says
//! something the model follows it; elsewhere it follows CiA 301 and the device profile.

use crate::canopen::lss::SlaveCaps;
use crate::canopen::DataType::*;
use crate::canopen::ObjAddr;
use crate::cia402_drive::{DriveProfile, RemoteBit, VoltageBit};
use crate::od::Access::*;
use crate::od::{builtin, le as u, text, Dictionary, Init};

/// A simulated device type: its dictionary and the protocol features and quirks it has.
pub struct Model {
    /// Stable name used in the state file.
    pub key: String,
    /// Its object dictionary, with the values it starts with.
    pub dict: Dictionary,
    /// Whether its SDO server does block transfers.
    pub block_transfer: bool,
    /// Whether it answers node-guarding requests.
    pub guarding: bool,
    /// Objects that accept any write and keep their value (a firmware quirk some seeds describe).
    pub ignored_writes: Vec<ObjAddr>,
    /// What its LSS slave supports (CiA 305 store and bit timing are optional).
    pub lss: SlaveCaps,
    /// A linear position sensor: position and speed move with time.
    pub moving: bool,
    /// Sends every PDO with 8 data bytes, whatever its mapping (seed 004's frames).
    pub pad_pdos: bool,
    /// An EPOS2: its controller's bit rate is also its own object 0x2001 (EPOS2 coding).
    pub epos2_bit_rate: bool,
    /// What a simulated fault (object 0x5FFE) does to this device.
    pub fault: Option<FaultSpec>,
    /// A CiA 402 drive: controlword 0x6040 drives the state its statusword 0x6041 shows.
    pub drive: Option<DriveProfile>,
}

impl Model {
    /// A device type with this dictionary and nothing else: no block transfer, no node
    /// guarding, full LSS, no fault, no quirk. The models set what they have.
    pub(crate) fn plain(key: impl Into<String>, dict: Dictionary) -> Model {
        Model {
            key: key.into(),
            dict,
            block_transfer: false,
            guarding: false,
            ignored_writes: vec![],
            lss: FULL_LSS,
            moving: false,
            pad_pdos: false,
            epos2_bit_rate: false,
            fault: None,
            drive: None,
        }
    }
}

/// A simulated fault: the EMCY it raises, and whether the device leaves Operational.
#[derive(Clone, Copy, Debug)]
pub struct FaultSpec {
    /// The EMCY error code (CiA 301 table 21).
    pub code: u16,
    /// The error register (0x1001) while the fault stands.
    pub register: u8,
    /// The manufacturer-specific bytes of the EMCY.
    pub vendor: [u8; 5],
    /// Whether the device leaves Operational for Pre-operational.
    pub to_pre_operational: bool,
}

/// The simulator's handle on a device: writing N to 0x5FFE makes the fault strike N ms later.
fn fault_object(d: &mut Dictionary) {
    d.var(0x5FFE, "Simulated fault in ms (0 clears it)", U16, Rw, u(0, U16));
}

/// The simulator's handle on a drive's power supply: 1 switches it off (the drive then
/// does not switch on), 0 back on.
pub(crate) const SUPPLY_OFF_OBJECT: ObjAddr = ObjAddr::new(0x5FFD, 0);

fn supply_object(d: &mut Dictionary) {
    d.var(0x5FFD, "Simulated power supply off (1) or on (0)", U8, Rw, u(0, U8)).range = Some((0, 1));
}

/// The pre-defined error field 0x1003, a slot for each of `fields` (newest first; 0 empty).
fn error_history(d: &mut Dictionary, fields: &[u32]) {
    let field = |s: u8| (s, "Standard error field", U32, Ro, u(fields[s as usize - 1] as u64, U32));
    d.array(0x1003, "Pre-defined error field", (1..=fields.len() as u8).map(field).collect());
    let errors = fields.iter().filter(|f| **f != 0).count() as u8;
    writable_count(d, 0x1003, "Number of errors", errors, None);
}

/// Sub 0 of a record as a count the master writes (the error history's, a dynamic mapping's).
fn writable_count(d: &mut Dictionary, index: u16, name: &str, count: u8, range: Option<(i128, i128)>) {
    let (addr, default) = (ObjAddr::new(index, 0), u(count as u64, U8));
    d.insert(crate::od::Entry { addr, name: name.into(), dtype: U8, access: Rw, default, range });
}

/// The demo sensor's motion: a triangle between 100000 and 300000 steps, 20 steps a ms,
/// forward for 10 s and back for 10 s. Speed is reported as ±2000 (steps per 100 ms).
pub(crate) fn sensor_motion(now_ms: u64) -> (i32, i16) {
    let t = (now_ms % 20_000) as i32;
    if t < 10_000 {
        (100_000 + 20 * t, 2000)
    } else {
        (300_000 - 20 * (t - 10_000), -2000)
    }
}

const FULL_LSS: SlaveCaps = SlaveCaps { store: true, bit_timing: true, fastscan_in_configuration: false };
/// An LSS slave without the optional services (CiA 305 store and bit timing).
pub(crate) const BASIC_LSS: SlaveCaps = SlaveCaps { store: false, bit_timing: false, ..FULL_LSS };

/// The serial of the `i`-th (from 0) demo sensor waiting for a node-id.
pub fn unconfigured_serial(i: u8) -> u32 {
    UNCONFIGURED_SERIALS[0] + i as u32
}

/// The demo network with `unconfigured` sensors waiting for a node-id.
pub fn demo_network_with(unconfigured: u8) -> Vec<(Model, Option<u8>)> {
    let mut devices = vec![
        (drive(), Some(1)),
        (position_sensor(SENSOR_SERIAL), Some(5)),
        (io_module(), Some(10)),
        (stepper(), Some(32)),
    ];
    devices.extend((0..unconfigured).map(|i| (position_sensor(unconfigured_serial(i)), None)));
    devices
}

/// The size of the demo network's large DOMAIN object, big enough to need several block transfers.
pub const DOMAIN_SIZE: usize = 64 * 1024;

/// What every device here has: CiA 301 mandatory and common communication objects.
struct Common {
    device_type: u32,
    name: &'static str,
    hardware: &'static str,
    software: &'static str,
    /// Vendor-ID, product code, revision, serial; `None` for a device without them.
    identity: Option<[u32; 4]>,
    heartbeat_ms: Option<u16>,
    guarding: bool,
    /// Highest 0x1010/0x1011 subindex: 1 (all) or 4 (all, comm, app, manufacturer).
    store_subs: u8,
}

fn common(c: Common) -> Dictionary {
    let mut d = Dictionary::default();
    // Names, types, access and kinds from the CiA 301 table; the values are this device's.
    let mut add = |index, value: &dyn Fn(u8) -> Option<Init>| builtin::add(&mut d, index, |e| value(e.addr.sub));
    add(0x1000, &|_| Some(u(c.device_type as u64, U32)));
    add(0x1001, &|_| Some(u(0, U8)));
    add(0x1005, &|_| Some(u(0x80, U32)));
    add(0x1008, &|_| Some(text(c.name)));
    add(0x1009, &|_| Some(text(c.hardware)));
    add(0x100A, &|_| Some(text(c.software)));
    if c.guarding {
        add(0x100C, &|_| Some(u(0, U16)));
        add(0x100D, &|_| Some(u(0, U8)));
    }
    // Reading a sub gives 1: the device saves (restores) on command (CiA 301 7.5.2.13).
    let store = |sub| (sub <= c.store_subs).then(|| u(1, U32));
    add(0x1010, &store);
    add(0x1011, &store);
    add(0x1014, &|_| Some(Init::NodeIdPlus(0x80)));
    if let Some(ms) = c.heartbeat_ms {
        add(0x1017, &|_| Some(u(ms as u64, U16)));
    }
    add(0x1018, &|sub| c.identity.map(|id| u(id[sub as usize - 1] as u64, U32)));
    add(0x1200, &|sub| Some(Init::NodeIdPlus(if sub == 1 { 0x600 } else { 0x580 })));
    d
}

/// Node 1: after the maxon EPOS2 (seeds 000, 002). Device type 0x00020192 is the value
/// the gateway note reads from node 2; vendor 0xFB is maxon's CiA vendor-ID.
pub fn drive() -> Model {
    let mut d = common(Common {
        device_type: 0x0002_0192,
        name: "EPOS2 24/5",
        hardware: "6220h",
        software: "2126h",
        identity: Some([0x0000_00FB, 0x0000_6220, 0x2126_0000, 0x0001_3F2A]),
        heartbeat_ms: Some(0),
        guarding: true,
        store_subs: 4,
    });
    // EPOS2 firmware specification: 0x2000 Node ID, 0x2001 CAN bit rate (0 = 1 Mbit/s ...).
    d.var(0x2000, "Node ID", U8, Rw, u(1, U8)).range = Some((1, 127));
    d.var(0x2001, "CAN bit rate", U16, Rw, u(0, U16)).range = Some((0, 9));
    // Seed 000's examples: "Software Version" 0x2003:1 reads 0x2010; "Home Offset" 0x2081.
    d.record(
        0x2003,
        "Version",
        vec![(1, "Software version", U16, Ro, u(0x2010, U16)), (2, "Hardware version", U16, Ro, u(0x6220, U16))],
    );
    d.var(0x2081, "Home offset", I32, Rw, u(0, I32));
    d.var(0x6040, "Controlword", U16, Rw, u(0, U16));
    d.var(0x6041, "Statusword", U16, Ro, u(0x0540, U16));
    d.var(0x6060, "Modes of operation", I8, Rw, u(1, I8)).range = Some((-6, 7));
    d.var(0x6061, "Modes of operation display", I8, Ro, u(1, I8));
    d.var(0x6064, "Position actual value", I32, Ro, u(0, I32));
    d.var(0x606C, "Velocity actual value", I32, Ro, u(0, I32));
    d.var(0x607A, "Target position", I32, Rw, u(0, I32));
    d.var(0x6081, "Profile velocity", U32, Rw, u(1000, U32));
    // CiA 302 program download: a DOMAIN large enough to make block transfer matter.
    d.record(0x1F50, "Program data", vec![(1, "Program 1", D, Rw, Init::Bytes(domain_pattern(DOMAIN_SIZE)))]);
    data_type_record(&mut d);
    // TPDO1 with dynamic mapping (the EPOS2 has four): statusword by default.
    event_driven_tpdo1(&mut d, &[0x6041_0010, 0, 0, 0]);
    // The EPOS2's error history keeps five entries.
    error_history(&mut d, &[0; 5]);
    fault_object(&mut d);
    supply_object(&mut d);
    let drive =
        DriveProfile { constant_bits: 0x0500, voltage: VoltageBit::PowerStage, remote: RemoteBit::WhenOperational };
    let model = Model {
        block_transfer: true,
        guarding: true,
        epos2_bit_rate: true,
        // A CiA 402 undervoltage (0x3220), register bits generic and voltage; the drive
        // stays in its NMT state and goes to Fault.
        fault: Some(FaultSpec { code: 0x3220, register: 0x05, vendor: [0; 5], to_pre_operational: false }),
        drive: Some(drive),
        ..Model::plain("drive", d)
    };
    storing_its_eds(model, crate::od::stored::PLAIN, DRIVE_NAMES)
}

/// Not in any seed device: the simulated drive (node 1, reached directly through an EPOS2)
/// and I/O module (node 10, reached through the gateway) carry one entry per CiA 309-3
/// type so that every type can be exercised end to end.
fn data_type_record(d: &mut Dictionary) {
    d.record(
        0x5FF0,
        "Simulator data types",
        vec![
            (1, "boolean", Bool, Rw, u(1, Bool)),
            (2, "unsigned8", U8, Rw, u(0x12, U8)),
            (3, "unsigned16", U16, Rw, u(0x1234, U16)),
            (4, "unsigned32", U32, Rw, u(0x1234_5678, U32)),
            (5, "unsigned64", U64, Rw, u(0x0123_4567_89AB_CDEF, U64)),
            (6, "integer8", I8, Rw, u((-5i8) as u8 as u64, I8)),
            (7, "integer16", I16, Rw, u((-300i16) as u16 as u64, I16)),
            (8, "integer32", I32, Rw, u((-70000i32) as u32 as u64, I32)),
            (9, "integer64", I64, Rw, u((-5_000_000_000i64) as u64, I64)),
            (10, "real32", R32, Rw, u(1.5f32.to_bits() as u64, R32)),
            (11, "real64", R64, Rw, u((-2.25f64).to_bits(), R64)),
            (12, "visible string", Vs, Rw, text("canctl")),
            (13, "octet string", Os, Rw, Init::Bytes(vec![0xDE, 0xAD, 0xBE, 0xEF])),
            (14, "domain", D, Rw, Init::Bytes(vec![1, 2, 3, 4, 5, 6, 7, 8, 9])),
            (15, "write-only command", U16, Wo, u(0, U16)),
        ],
    );
}

/// Serial of the demo sensor at node 5: the example in seed 001 figure 10.
pub const SENSOR_SERIAL: u32 = 0x0950_1234;
/// Serials of the first demo sensors that wait for a node-id over LSS (the default three;
/// more follow on, see `unconfigured_serial`).
pub const UNCONFIGURED_SERIALS: [u32; 3] = [0x0950_1301, 0x0950_1302, 0x0950_1303];

/// After the Temposonics MH CANopen sensor (seed 001, table 5 and §10.3): node 5 of the demo
/// network, and the devices that wait for a node-id.
pub fn position_sensor(serial: u32) -> Model {
    let key = if serial == SENSOR_SERIAL { "sensor".to_string() } else { format!("sensor-{serial:08X}") };
    let mut d = common(Common {
        device_type: 0x000A_0196,
        name: "C01",
        hardware: "1.00",
        software: "1.00",
        // Seed 001 table 5: vendor 0x40, product 0x43787800, revision 0x312E3031 ("1.01").
        identity: Some([0x0000_0040, 0x4378_7800, 0x312E_3031, serial]),
        // The seed's default is 0; the demo sensor beats every 40 ms so that a scan (50 ms
        // quiet window) always sees its state.
        heartbeat_ms: Some(40),
        guarding: false,
        store_subs: 1,
    });
    d.var(0x1002, "Manufacturer status register", U8, Ro, u(1, U8));
    d.var(0x100B, "Node-ID", U32, Ro, Init::NodeIdPlus(0));
    d.var(0x100E, "COB-ID error control", U32, Rw, Init::NodeIdPlus(0x700));
    tpdo1_communication(&mut d, 254, false, Some(1));
    tpdo1_mapping(&mut d, Const, &[0x6020_0120, 0x6030_0110]);
    d.var(0x6000, "Operating parameters", U16, Rw, u(0, U16));
    d.record(
        0x6005,
        "Linear encoder",
        vec![(1, "Measuring step", U32, Ro, u(100_000, U32)), (2, "Speed measuring step", U32, Ro, u(100, U32))],
    );
    d.record(0x6010, "Preset value", vec![(1, "Channel 1", I32, Rw, u(0, I32))]);
    d.record(0x6020, "Position value", vec![(1, "Channel 1", I32, Ro, u(125_000, I32))]);
    d.record(0x6030, "Speed value", vec![(1, "Channel 1", I16, Ro, u(0, I16))]);
    d.var(0x6200, "Cyclic timer", U16, Rw, u(1, U16));
    d.var(0x6500, "Operating status", U16, Ro, u(0, U16));
    d.var(0x6501, "Measuring step", U32, Ro, u(100_000, U32));
    fault_object(&mut d);
    // Seed 001 §8: the magnet lost is a "Device Hardware" error, 0x5000 with register 0x81.
    let fault = FaultSpec { code: 0x5000, register: 0x81, vendor: [0; 5], to_pre_operational: true };
    Model { moving: true, fault: Some(fault), ..Model::plain(key, d) }
}

/// Node 10: after an ICP DAS CAN-2000C module, the CAN-2057C 16-channel DO (seed 004).
pub fn io_module() -> Model {
    let mut d = common(Common {
        // DS401 (0x191) with digital outputs (bit 17) and inputs (bit 16).
        device_type: 0x0003_0191,
        name: "CAN-2057C",
        hardware: "1.00",
        software: "1.00",
        // The seed does not give ICP DAS's vendor-ID; this one is the simulator's.
        identity: Some([0x0000_0444, 0x0000_2057, 0x0001_0000, 0x0000_1F4A]),
        heartbeat_ms: Some(0),
        guarding: true,
        store_subs: 1,
    });
    // EMCY history, newest first (seed 004 §5.3: five records). Two from the seed's table:
    // CAN controller overrun (8110, vendor 06) and EEPROM access error (5000, vendor 02).
    error_history(&mut d, &[0x0006_8110, 0x0002_5000, 0, 0, 0]);
    // Dynamic mapping (seed 004).
    event_driven_tpdo1(&mut d, &[0x6000_0108, 0, 0, 0, 0, 0, 0, 0]);
    d.record(0x6000, "Read input 8-bit", vec![(1, "Inputs 1-8", U8, Ro, u(0, U8))]);
    d.record(
        0x6200,
        "Write output 8-bit",
        vec![(1, "Outputs 1-8", U8, Rw, u(0, U8)), (2, "Outputs 9-16", U8, Rw, u(0, U8))],
    );
    data_type_record(&mut d);
    fault_object(&mut d);
    // Seed 004's EMCY table: "81 10 | 11 | 06 .." CAN controller overrun.
    let fault = FaultSpec { code: 0x8110, register: 0x11, vendor: [0x06, 0, 0, 0, 0], to_pre_operational: false };
    let model = Model { guarding: true, pad_pdos: true, fault: Some(fault), ..Model::plain("io", d) };
    storing_its_eds(model, crate::od::stored::ZIP, IO_NAMES)
}

/// Node 32: after the Stögra SERS stepper (seed 003): DS402 subset, node guarding only, an
/// identity object without vendor, product or serial.
pub fn stepper() -> Model {
    let mut d = common(Common {
        device_type: 0x0004_0192,
        name: "SERS-CAN",
        hardware: "1.0",
        software: "2001-01",
        identity: None,
        heartbeat_ms: None,
        guarding: true,
        store_subs: 1,
    });
    d.var(0x1002, "Manufacturer status register", U32, Ro, u(0, U32));
    // "all values are accepted as comm cycle period (1006), but ... the value read is always 2000"
    d.var(0x1006, "Communication cycle period", U32, Rw, u(2000, U32));
    d.var(0x6040, "Controlword", U16, Rw, u(0, U16));
    d.var(0x6041, "Statusword", U16, Ro, u(0x0250, U16));
    // "the drive supports 1 Profile Position Mode and 6 Homing Mode"
    d.var(0x6060, "Modes of operation", I8, Rw, u(1, I8)).range = Some((1, 6));
    // "position_actual_value (6064) can not be written"
    d.var(0x6064, "Position actual value", I32, Ro, u(0, I32));
    d.var(0x607A, "Target position", I32, Rw, u(0, I32));
    d.var(0x6081, "Profile velocity", U32, Rw, u(500, U32));
    d.var(0x6083, "Profile acceleration", U32, Rw, u(1000, U32));
    // Seed 003 §2.4: "The mapping of the PDO is fixed, and can be read only. ... Transmit
    // PDO: Status word (6041), 16 Bit position_actual_value (6064), 32 Bit
    // ENDSCHALTER_DIGIN (2420), 16 Bit"; sent on SYNC, by RTR (253), or on change (255).
    d.var(0x2420, "ENDSCHALTER_DIGIN", U16, Ro, u(0, U16));
    tpdo1_communication(&mut d, 255, true, None);
    tpdo1_mapping(&mut d, Const, &[0x6041_0010, 0x6064_0020, 0x2420_0010]);
    fault_object(&mut d);
    supply_object(&mut d);
    // Seed 003 §2.8: "0x3200 Voltage inside the device", register "VOLTAGE 0x04 error under
    // voltage" with generic; vendor bytes errno, state class 1 (P11), state class 2 (P12).
    let fault = FaultSpec { code: 0x3200, register: 0x05, vendor: [0, 0x01, 0x00, 0, 0], to_pre_operational: false };
    Model {
        guarding: true,
        ignored_writes: vec![ObjAddr::new(0x1006, 0)],
        // Seed 003: the bit rate comes from DIP switches, and nothing about storing.
        lss: BASIC_LSS,
        fault: Some(fault),
        // Seed 003: 0x0250 after power on, voltage enabled and remote included.
        drive: Some(DriveProfile { constant_bits: 0, voltage: VoltageBit::Supply, remote: RemoteBit::Always }),
        ..Model::plain("stepper", d)
    }
}

/// Reproducible, incompressible-looking content (xorshift32).
pub fn domain_pattern(len: usize) -> Vec<u8> {
    pattern_bytes().take(len).collect()
}

/// The bytes of [`domain_pattern`], without end.
pub(crate) fn pattern_bytes() -> impl Iterator<Item = u8> {
    let mut x: u32 = 0x2545_F491;
    std::iter::repeat_with(move || {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        x as u8
    })
}

/// Vendor and product names of the models' EDS files.
const DRIVE_NAMES: (&str, &str) = ("maxon motor ag (simulated)", "EPOS2 24/5 (simulated)");
const IO_NAMES: (&str, &str) = ("ICP DAS (simulated)", "CAN-2057C (simulated)");

/// The EDS of each device model of the demo network: (file name, text). Generated from
/// the models, committed under `eds/`, and tested to agree with them.
pub fn eds_files() -> Vec<(String, String)> {
    let models = [
        (drive(), DRIVE_NAMES),
        (position_sensor(SENSOR_SERIAL), ("MTS Sensors (simulated)", "Temposonics MH CANopen (simulated)")),
        (io_module(), IO_NAMES),
        (stepper(), ("Stögra (simulated)", "SERS stepper drive (simulated)")),
    ];
    models.into_iter().map(|(m, names)| eds_file(&m, names)).collect()
}

/// A model's EDS: (file name, text, each character standing for one byte).
fn eds_file(m: &Model, (vendor, product): (&str, &str)) -> (String, String) {
    let part =
        |addr| m.dict.get(addr).map(|e| e.default_for(0)).and_then(|v| v.try_into().ok()).map_or(0, u32::from_le_bytes);
    let file_name = format!("canctl-sim-{}.eds", m.key);
    let header = crate::od::eds::Header {
        file_name: file_name.clone(),
        description: format!("{product}: a device model of canctl's simulated network"),
        vendor_name: vendor.into(),
        vendor_number: part(ObjAddr::VENDOR_ID),
        product_name: product.into(),
        product_number: part(ObjAddr::PRODUCT_CODE),
        revision: part(ObjAddr::REVISION_NUMBER),
        node_id: None,
    };
    (file_name, crate::od::eds::write(&m.dict, None, &header))
}

/// The model with its own EDS in 0x1021, as the format 0x1022 says (plain or zipped): the
/// file in eds/, made with 0x1021 empty, since a DOMAIN's content is not part of an EDS.
fn storing_its_eds(mut m: Model, format: u8, names: (&str, &str)) -> Model {
    m.dict.var(0x1022, "Storage format", U8, Ro, u(format as u64, U8));
    m.dict.var(0x1021, "Store EDS", D, Ro, Init::Bytes(Vec::new()));
    let (file_name, text) = eds_file(&m, names);
    let bytes = crate::od::eds::to_latin1(&text);
    let stored = if format == crate::od::stored::ZIP { crate::od::stored::zip(&file_name, &bytes) } else { bytes };
    m.dict.var(0x1021, "Store EDS", D, Ro, Init::Bytes(stored));
    m
}

/// TPDO1's communication parameter: COB-ID, transmission type, and where the device has
/// them an inhibit time (0) and an event timer.
fn tpdo1_communication(d: &mut Dictionary, transmission: u8, inhibit: bool, event_timer: Option<u16>) {
    let mut members = vec![
        (1, "COB-ID", U32, Rw, Init::NodeIdPlus(0x180)),
        (2, "Transmission type", U8, Rw, u(transmission as u64, U8)),
    ];
    members.extend(inhibit.then(|| (3, "Inhibit time", U16, Rw, u(0, U16))));
    members.extend(event_timer.map(|ms| (5, "Event timer", U16, Rw, u(ms as u64, U16))));
    d.record(0x1800, "TPDO1 communication parameter", members);
}

/// TPDO1's mapping parameter, one entry of `access` per value of `mapped`.
fn tpdo1_mapping(d: &mut Dictionary, access: crate::od::Access, mapped: &[u32]) {
    let names: Vec<String> = (1..=mapped.len()).map(|s| format!("Mapped object {s}")).collect();
    let members = (1..).zip(&names).zip(mapped).map(|((s, n), m)| (s, n.as_str(), U32, access, u(*m as u64, U32)));
    d.record(0x1A00, "TPDO1 mapping parameter", members.collect());
}

/// TPDO1, event-driven and off until an event timer is set, with a writable mapping of
/// these entries, the count in sub 0 writable (CiA 301 dynamic mapping) and 1.
fn event_driven_tpdo1(d: &mut Dictionary, mapped: &[u32]) {
    tpdo1_communication(d, 255, true, Some(0));
    tpdo1_mapping(d, Rw, mapped);
    writable_count(d, 0x1A00, "Number of mapped objects", 1, Some((0, mapped.len() as i128)));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The demo network: (model, node-id). `None` is a device waiting for an LSS node-id.
    fn demo_network() -> Vec<(Model, Option<u8>)> {
        demo_network_with(UNCONFIGURED_SERIALS.len() as u8)
    }

    /// CiA 301's objects are one table: a simulated device has each as the table has it
    /// (0x1010 and 0x1011 are ARRAYs, CiA 301 §7.5.2.13/14; 0x1018 a RECORD).
    #[test]
    fn the_devices_have_the_cia_301_objects_as_the_built_in_table_has_them() {
        let table = builtin::dictionary(None);
        for (model, _) in demo_network() {
            for (index, _, kind) in model.dict.objects().filter(|(i, _, _)| (0x1000..0x2000).contains(i)) {
                if let Some((_, want)) = table.object_info(index) {
                    assert_eq!(kind, want, "{}: 0x{index:04X}", model.key);
                }
            }
        }
    }
}
