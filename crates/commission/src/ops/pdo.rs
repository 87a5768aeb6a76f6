//! Transmit PDOs: their layouts read from a node (or a DCF), a mapping changed for a
//! session and put back at its end, and the stream of decoded records.

use super::progress::Progress;
use super::sdo_options::sized;
use super::values::le_u32;
use crate::bus::Bus;
use crate::cancel::Cancel;
use crate::canopen::nmt::{self, Command};
use crate::canopen::pdo::{self, Field, Layout};
use crate::canopen::types::Value;
use crate::canopen::{abort, DataType, ObjAddr};
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::od::eds::Eds;
use crate::od::{Dictionary, Entry};
use crate::ops::event::{Notice, Warning};
use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::time::{Duration, Instant};

/// Object values by address.
type Values = BTreeMap<ObjAddr, Vec<u8>>;

/// The communication and mapping parameter indexes of TPDO `n` (1-based).
fn tpdo_indices(n: u16) -> (u16, u16) {
    (0x1800 + n - 1, 0x1A00 + n - 1)
}

fn read_u32(bus: &mut dyn Bus, node: u8, addr: ObjAddr, timeout: Duration) -> Result<u32> {
    Ok(le_u32(&bus.sdo_upload(node, addr, &sized(timeout, Some(4)))?))
}

fn read_u8(bus: &mut dyn Bus, node: u8, addr: ObjAddr, timeout: Duration) -> Result<u8> {
    Ok(bus.sdo_upload(node, addr, &sized(timeout, Some(1)))?.first().copied().unwrap_or(0))
}

/// Writes in the safe PDO order of `config apply`, each written value recorded in `state`
/// as soon as the device took it, so that what a failure leaves behind is known.
fn write_plan(bus: &mut dyn Bus, node: u8, changes: &Values, state: &mut Values, timeout: Duration) -> Result<()> {
    let current = state.clone();
    for step in super::config::plan(changes, &|a| current.get(&a).cloned()) {
        bus.sdo_download(node, step.addr, &step.value, &sized(timeout, Some(step.value.len())))?;
        state.insert(step.addr, step.value);
    }
    Ok(())
}

/// The TPDO's parameters that a remapping touches, as they are now.
fn snapshot(bus: &mut dyn Bus, node: u8, n: u16, timeout: Duration) -> Result<Values> {
    let (comm, map) = tpdo_indices(n);
    let mut s = BTreeMap::new();
    s.insert(ObjAddr::new(comm, 1), read_u32(bus, node, ObjAddr::new(comm, 1), timeout)?.to_le_bytes().to_vec());
    s.insert(ObjAddr::new(comm, 2), vec![read_u8(bus, node, ObjAddr::new(comm, 2), timeout)?]);
    if let Ok(v) = bus.sdo_upload(node, ObjAddr::new(comm, 5), &sized(timeout, Some(2))) {
        s.insert(ObjAddr::new(comm, 5), v);
    }
    let count = read_u8(bus, node, ObjAddr::new(map, 0), timeout)?;
    s.insert(ObjAddr::new(map, 0), vec![count]);
    for sub in 1..=count {
        s.insert(ObjAddr::new(map, sub), read_u32(bus, node, ObjAddr::new(map, sub), timeout)?.to_le_bytes().to_vec());
    }
    Ok(s)
}

/// What a streaming session changed on a node, to put back when it ends — whatever ends
/// it: call [`Session::restore`] on every path.
#[derive(Default)]
pub struct Session {
    /// The TPDO, its parameters before the session, and as the device took them since.
    mapping: Option<(u16, Values, Values)>,
    /// The NMT state the node was in before the session started it.
    state: Option<nmt::State>,
}

/// A new mapping for one TPDO.
#[derive(Clone, Debug)]
pub(crate) struct Remap {
    /// The TPDO, 1-based.
    pub tpdo: u16,
    /// The objects to map, with their sizes in bits.
    pub objects: Vec<(ObjAddr, u8)>,
    /// Event timer in ms.
    pub event: Option<u16>,
    /// Transmission type (default 255: by event).
    pub transmission: Option<u8>,
}

impl Session {
    /// Map `r.objects` into the TPDO for the session, in the safe order.
    pub(crate) fn remap(&mut self, bus: &mut dyn Bus, node: u8, r: &Remap, timeout: Duration) -> Result<()> {
        let (comm, map) = tpdo_indices(r.tpdo);
        let original = snapshot(bus, node, r.tpdo, timeout)?;
        let mut wanted = BTreeMap::new();
        for (i, (addr, bits)) in r.objects.iter().enumerate() {
            wanted.insert(ObjAddr::new(map, i as u8 + 1), pdo::mapping_raw(*addr, *bits).to_le_bytes().to_vec());
        }
        wanted.insert(ObjAddr::new(map, 0), vec![r.objects.len() as u8]);
        wanted.insert(ObjAddr::new(comm, 2), vec![r.transmission.unwrap_or(255)]);
        if let Some(ms) = r.event {
            wanted.insert(ObjAddr::new(comm, 5), ms.to_le_bytes().to_vec());
        }
        let changes: Values = wanted.into_iter().filter(|(k, v)| original.get(k) != Some(v)).collect();
        let (_, _, now) = self.mapping.insert((r.tpdo, original.clone(), original));
        write_plan(bus, node, &changes, now, timeout)
    }

    /// Put the node in Operational; `state` is the one it is in now (to go back to).
    pub fn start(&mut self, bus: &mut dyn Bus, node: u8, state: nmt::State) -> Result<()> {
        if state != nmt::State::Operational {
            self.state = Some(state);
            bus.nmt(Command::Start, node)?;
        }
        Ok(())
    }

    /// Put back what the session changed, whatever ended it (a refused write part-way
    /// included): the parameters the device took, then the NMT state.
    pub fn restore(self, bus: &mut dyn Bus, node: u8, timeout: Duration) -> Result<Restored> {
        let mut restored = Restored::default();
        let mut mapping = Ok(());
        if let Some((tpdo, original, mut now)) = self.mapping {
            // Entries the session added beyond the original count go back to 0 too.
            let mut back = original;
            for (a, _) in now.iter().filter(|(a, _)| a.sub > 0 && (0x1A00..=0x1BFF).contains(&a.index)) {
                back.entry(*a).or_insert(vec![0; 4]);
            }
            back.retain(|a, v| now.get(a) != Some(v));
            if !back.is_empty() {
                let not_put_back = |e| Error::TpdoNotPutBack { node, tpdo, error: Box::new(e) };
                mapping = write_plan(bus, node, &back, &mut now, timeout).map_err(not_put_back);
                restored.tpdo = mapping.is_ok().then_some(tpdo);
            }
        }
        // The state goes back even when the mapping could not.
        match self.state {
            Some(nmt::State::Stopped) => bus.nmt(Command::Stop, node)?,
            Some(nmt::State::PreOperational) => bus.nmt(Command::PreOperational, node)?,
            _ => {}
        }
        mapping?;
        restored.state = self.state;
        Ok(restored)
    }
}

/// What [`Session::restore`] put back.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct Restored {
    /// The TPDO whose parameters were written back, if the session had changed any.
    pub tpdo: Option<u16>,
    /// The NMT state the node was sent back to, if the session had started it.
    pub state: Option<nmt::State>,
}

/// A PDO entry is 1 to 8 whole bytes (8 to 64 bits).
const MAX_ENTRY_BYTES: usize = 8;

/// The size in bits of an object to map into a PDO: its dictionary type's when that has a
/// fixed size, else learnt by reading the object once (at most 8 bytes are read). An
/// object that cannot be read, or is empty or longer than 8 bytes, is refused.
pub(crate) fn mapped_bits(
    bus: &mut dyn Bus,
    node: u8,
    addr: ObjAddr,
    entry: Option<&Entry>,
    timeout: Duration,
) -> Result<u8> {
    if let Some(size) = entry.and_then(|e| e.dtype.size()) {
        return Ok((size * 8) as u8);
    }
    let opts = super::sdo_options::capped(timeout, MAX_ENTRY_BYTES);
    let refused = |why: String| Error::Usage(format!("cannot map {addr} into a PDO: {why}"));
    match bus.sdo_upload(node, addr, &opts) {
        Ok(v) if (1..=MAX_ENTRY_BYTES).contains(&v.len()) => Ok((v.len() * 8) as u8),
        Ok(v) => Err(refused(format!("it reads {} bytes, and a PDO entry is 1 to 8 bytes (8 to 64 bits)", v.len()))),
        // The client stopped the upload at the limit.
        Err(Error::Link(crate::error::LinkError::SdoProtocol { aborted: Some(abort::OUT_OF_MEMORY), .. })) => {
            Err(refused("it is longer than 8 bytes, and a PDO entry is 1 to 8 bytes (8 to 64 bits)".into()))
        }
        // Its remedy (a dictionary gives the type) is the front end's to word (`output::remedies`).
        Err(e) => Err(Error::MapSizeUnread { obj: addr, error: Box::new(e) }),
    }
}

/// The field a raw mapping entry maps, named by `dict`; its type the dictionary's when its
/// size matches the mapping, else unsigned of the mapped width.
fn field(dict: &Dictionary, raw: u32) -> Field {
    let (addr, bits) = pdo::mapping_entry(raw);
    let fits = |t: &DataType| t.size().is_some_and(|s| s * 8 == bits as usize) || *t == DataType::Bool && bits == 1;
    let dtype = dict.get(addr).map(|e| e.dtype).filter(fits).unwrap_or_else(|| pdo::default_type(bits));
    Field { addr, bits, dtype, name: dict.display_name(addr).unwrap_or_else(|| addr.to_string()) }
}

/// The layouts of a node's TPDOs `tpdos` (1-based), read from the node; names and types
/// from `dict`. With `skip_missing`, TPDOs the node does not have are passed over; invalid
/// ones always are, with a note.
pub fn read_layouts(
    bus: &mut dyn Bus,
    node: u8,
    dict: &Dictionary,
    tpdos: &[u16],
    skip_missing: bool,
    timeout: Duration,
    progress: &mut dyn Progress,
) -> Result<Vec<(u16, Layout)>> {
    let mut out = Vec::new();
    for &n in tpdos {
        let (comm, map) = tpdo_indices(n);
        let cob = match read_u32(bus, node, ObjAddr::new(comm, 1), timeout) {
            Ok(c) => c,
            Err(e) if skip_missing && super::node::is_missing(&e) => continue,
            // Said as what it means, not as an abort on an object the user never named.
            Err(e) if super::node::lacks_index(&e) => return Err(Error::NoSuchTpdo { node, pdo: n, comm }),
            Err(e) => return Err(e),
        };
        if cob & 0x8000_0000 != 0 {
            progress.event(Notice::PdoInvalid { node, pdo: n, comm, cob }.into());
            continue;
        }
        let count = read_u8(bus, node, ObjAddr::new(map, 0), timeout)?;
        let mut names = BTreeSet::new();
        let mut fields = Vec::new();
        for sub in 1..=count {
            let mut field = field(dict, read_u32(bus, node, ObjAddr::new(map, sub), timeout)?);
            if !names.insert(field.name.clone()) {
                field.name = format!("{} ({})", field.name, field.addr);
            }
            fields.push(field);
        }
        out.push((n, Layout { cob_id: (cob & 0x7FF) as u16, fields }));
    }
    if out.is_empty() {
        return Err(Error::NoValidTpdo { node });
    }
    Ok(out)
}

/// The layouts of the valid PDOs (TPDO and RPDO 1..4) a DCF describes for `node`, by COB-ID.
pub(crate) fn dcf_layouts(eds: &Eds, node: u8) -> BTreeMap<u16, Layout> {
    let mut out = BTreeMap::new();
    let value = |addr: ObjAddr| -> Option<Vec<u8>> {
        let e = eds.dict.get(addr)?;
        let init = eds.values.get(&addr).cloned().unwrap_or_else(|| e.default.clone());
        Some(Entry { default: init, ..e.clone() }.default_for(node))
    };
    let u32_at = |addr| value(addr).filter(|v| v.len() >= 4).map(|v| le_u32(&v));
    for (comm, map) in (0..4u16).flat_map(|n| [(0x1400 + n, 0x1600 + n), (0x1800 + n, 0x1A00 + n)]) {
        let Some(cob) = u32_at(ObjAddr::new(comm, 1)).filter(|c| c & 0x8000_0000 == 0) else { continue };
        let count = value(ObjAddr::new(map, 0)).and_then(|v| v.first().copied()).unwrap_or(0);
        let fields =
            (1..=count).filter_map(|s| u32_at(ObjAddr::new(map, s))).map(|raw| field(&eds.dict, raw)).collect();
        out.insert((cob & 0x7FF) as u16, Layout { cob_id: (cob & 0x7FF) as u16, fields });
    }
    out
}

/// When a stream ends, and how it gets its frames.
#[derive(Clone, Debug)]
pub struct StreamOptions {
    /// Stop after this many records.
    pub count: Option<u64>,
    /// Stop after this long.
    pub duration: Option<Duration>,
    /// Send SYNC at this period.
    pub sync: Option<Duration>,
    /// On a link that sees no traffic (an EPOS2): how often to poll each PDO.
    pub interval: Duration,
    /// How long to wait for each polled PDO.
    pub timeout: Duration,
    /// If no PDO has come after this long, say so, with why it may be silent.
    pub silence: Option<(Duration, Vec<crate::ops::silence::Silence>)>,
}

/// One decoded PDO.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Record {
    /// Wall-clock time of reception, ms since the Unix epoch.
    pub time_ms: u64,
    /// Which of the stream's layouts it is (an index into them).
    pub layout: usize,
    /// The mapped values, in the layout's order, decoded by their data types.
    pub values: Vec<Value>,
}

/// The records of a node's TPDOs as they come: pull them with [`Stream::next`]. Through a
/// link that sees no traffic the PDOs are polled with remote frames.
pub struct Stream<'a> {
    /// When the stream began; the silence note is measured from here.
    started: Instant,
    node: u8,
    layouts: &'a [(u16, Layout)],
    opts: StreamOptions,
    polling: bool,
    end: Option<Instant>,
    next_sync: Option<Instant>,
    next_poll: Instant,
    pending: VecDeque<Record>,
    records: u64,
    warned: BTreeSet<u16>,
    interrupted: &'a Cancel,
}

const SYNC_COB: u16 = 0x080;

/// Now as Unix time in ms: the time column of streamed records (a label for people and
/// files, never used to measure a wait).
pub(crate) use crate::sim::wall_ms;

impl<'a> Stream<'a> {
    /// A stream that ends at `opts`' count or duration, or once `interrupted` is set.
    pub fn new(
        bus: &dyn Bus,
        node: u8,
        layouts: &'a [(u16, Layout)],
        opts: StreamOptions,
        interrupted: &'a Cancel,
    ) -> Stream<'a> {
        let now = bus.now();
        Stream {
            node,
            layouts,
            polling: !bus.sees_traffic(),
            end: opts.duration.map(|d| now + d),
            next_sync: opts.sync.map(|_| now),
            next_poll: now,
            opts,
            pending: VecDeque::new(),
            records: 0,
            warned: BTreeSet::new(),
            interrupted,
            started: now,
        }
    }

    /// Whether the PDOs are polled (the link shows no traffic by itself).
    pub fn polling(&self) -> bool {
        self.polling
    }

    /// Records given so far.
    pub fn records(&self) -> u64 {
        self.records
    }

    fn done(&self) -> bool {
        self.opts.count.is_some_and(|c| self.records >= c)
    }

    /// The next record, or `None` when the stream is over. A PDO whose length does not
    /// match its mapping is not decoded; that is noted once per TPDO.
    pub fn next(&mut self, bus: &mut dyn Bus, progress: &mut dyn Progress) -> Result<Option<Record>> {
        loop {
            if self.done() {
                return Ok(None);
            }
            if let Some(r) = self.pending.pop_front() {
                self.records += 1;
                return Ok(Some(r));
            }
            if self.interrupted.is_cancelled() || self.end.is_some_and(|e| bus.now() >= e) {
                return Ok(None);
            }
            self.cycle(bus, progress)?;
        }
    }

    /// One round: SYNC when due, then the frames of one wait or one poll.
    fn cycle(&mut self, bus: &mut dyn Bus, progress: &mut dyn Progress) -> Result<()> {
        if let (Some(period), Some(due)) = (self.opts.sync, self.next_sync) {
            if bus.now() >= due {
                bus.send_frame(&Frame::new(SYNC_COB, &[]))?;
                self.next_sync = Some(due + period);
            }
        }
        let quiet = self.records == 0 && self.pending.is_empty();
        let since = bus.now().saturating_duration_since(self.started);
        if let Some((after, why)) = self.opts.silence.take_if(|(after, _)| quiet && since >= *after) {
            progress.event(Notice::Silent { node: self.node, after, why }.into());
        }
        let wake = [self.end, self.next_sync, self.polling.then_some(self.next_poll)]
            .into_iter()
            .flatten()
            .fold(bus.now() + Duration::from_millis(100), Instant::min);
        let frames: Vec<Frame> = if self.polling {
            bus.sleep_until(self.next_poll)?;
            self.next_poll += self.opts.interval;
            let mut got = Vec::new();
            for (_, l) in self.layouts {
                match bus.request_frame(l.cob_id, l.len() as u8, self.opts.timeout) {
                    Ok(f) => got.push(f),
                    Err(e) if e.is_timeout() => {}
                    Err(e) => return Err(e),
                }
            }
            got
        } else {
            bus.recv_frame(wake)?.into_iter().filter(|f| !f.is_remote()).collect()
        };
        for f in frames {
            let Some(i) = self.layouts.iter().position(|(_, l)| l.cob_id == f.id()) else { continue };
            let (n, l) = &self.layouts[i];
            match l.decode(f.data()) {
                Ok(values) => self.pending.push_back(Record { time_ms: wall_ms(), layout: i, values }),
                Err(m) => {
                    if self.warned.insert(*n) {
                        let (node, pdo, cob_id) = (self.node, *n, u32::from(l.cob_id));
                        progress.event(Warning::PdoLength { node, pdo, cob_id, got: m.got, want: m.want }.into());
                    }
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::Master;
    use crate::sim::{SimConfig, SimLink};

    const T: Duration = Duration::from_secs(2);

    fn drive() -> Master<SimLink> {
        Master::new(SimLink::with_config(SimConfig::instant()), "sim".into())
    }

    #[test]
    fn an_object_without_a_dictionary_entry_is_sized_by_reading_it_once() {
        let mut bus = drive();
        // Home offset (i32) and the simulator's unsigned8: no entry given for either.
        assert_eq!(mapped_bits(&mut bus, 1, ObjAddr::new(0x2081, 0), None, T).unwrap(), 32);
        assert_eq!(mapped_bits(&mut bus, 1, ObjAddr::new(0x5FF0, 2), None, T).unwrap(), 8);
        assert_eq!(mapped_bits(&mut bus, 1, ObjAddr::new(0x5FF0, 5), None, T).unwrap(), 64);
        // A dictionary's fixed size is used as it is, without asking the node.
        let entry = crate::od::builtin::dictionary(None).get(ObjAddr::new(0x1017, 0)).cloned();
        assert_eq!(mapped_bits(&mut bus, 99, ObjAddr::new(0x1017, 0), entry.as_ref(), T).unwrap(), 16);
    }

    #[test]
    fn objects_that_do_not_fit_a_pdo_entry_or_cannot_be_read_are_refused() {
        let mut bus = drive();
        // A 9-byte domain and a 10-byte name: longer than a PDO entry, stopped at 8 bytes.
        for addr in [ObjAddr::new(0x5FF0, 14), ObjAddr::new(0x1008, 0)] {
            let e = mapped_bits(&mut bus, 1, addr, None, T).unwrap_err();
            assert!(matches!(e, Error::Usage(_)), "{e}");
            assert!(e.to_string().contains("longer than 8 bytes"), "{e}");
        }
        // Write-only, and not there: the device's abort, said as such.
        let e = mapped_bits(&mut bus, 1, ObjAddr::new(0x5FF0, 15), None, T).unwrap_err();
        assert!(matches!(e.root(), Error::SdoAbort { code: abort::WRITE_ONLY, .. }), "{e}");
        let e = mapped_bits(&mut bus, 1, ObjAddr::new(0x5123, 0), None, T).unwrap_err();
        assert!(matches!(e.root(), Error::SdoAbort { code: abort::NO_OBJECT, .. }), "{e}");
    }
}
