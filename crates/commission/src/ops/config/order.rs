//! The order a DCF's values are written in: plain objects first, then each PDO changed the
//! CiA 301 way.

use crate::canopen::ObjAddr;
use crate::ops::values::le_u32;
use std::collections::{BTreeMap, BTreeSet};

/// One write of the plan.
pub(crate) struct Step {
    pub addr: ObjAddr,
    pub value: Vec<u8>,
    /// An intermediate write of the PDO sequence, not a value of the file.
    pub interim: &'static str,
    /// The PDO (communication and mapping index) whose change this write is part of: the
    /// device holds a usable PDO only before the first and after the last of them.
    pub pdo: Option<(u16, u16)>,
}

impl Step {
    fn new(addr: ObjAddr, value: Vec<u8>, interim: &'static str) -> Step {
        Step { addr, value, interim, pdo: None }
    }
}

/// The communication and mapping parameter indexes of the PDO an index belongs to.
pub(super) fn pdo_indices(index: u16) -> Option<(u16, u16)> {
    match index {
        0x1400..=0x15FF | 0x1800..=0x19FF => Some((index, index + 0x200)),
        0x1600..=0x17FF | 0x1A00..=0x1BFF => Some((index - 0x200, index)),
        _ => None,
    }
}

/// Writes in a safe order: plain objects first; then per PDO whose COB-ID or mapping
/// changes: COB-ID invalid, mapping count 0, entries, count, other parameters, COB-ID.
pub(crate) fn plan(changes: &BTreeMap<ObjAddr, Vec<u8>>, current: &dyn Fn(ObjAddr) -> Option<Vec<u8>>) -> Vec<Step> {
    let mut steps: Vec<Step> = Vec::new();
    let mut pdos: BTreeSet<(u16, u16)> = BTreeSet::new();
    for (addr, value) in changes {
        match pdo_indices(addr.index) {
            Some((comm, map)) if addr.index == map || addr.sub == 1 => {
                pdos.insert((comm, map));
            }
            _ => steps.push(Step::new(*addr, value.clone(), "")),
        }
    }
    // Plain objects of a PDO comm record (transmission type, timers) already went above.
    for (comm, map) in pdos {
        let first = steps.len();
        let cob = ObjAddr::new(comm, 1);
        let cob_now = current(cob).map(|v| le_u32(&v));
        if let Some(c) = cob_now.filter(|c| c & 0x8000_0000 == 0) {
            steps.push(Step::new(cob, (c | 0x8000_0000).to_le_bytes().to_vec(), "PDO made invalid"));
        }
        let map_changes: Vec<(&ObjAddr, &Vec<u8>)> = changes.iter().filter(|(a, _)| a.index == map).collect();
        if !map_changes.is_empty() {
            let count = ObjAddr::new(map, 0);
            steps.push(Step::new(count, vec![0], "mapping count 0"));
            for (a, v) in map_changes.iter().filter(|(a, _)| a.sub > 0) {
                steps.push(Step::new(**a, (*v).clone(), ""));
            }
            let final_count = changes.get(&count).cloned().or_else(|| current(count)).unwrap_or(vec![0]);
            let interim = if changes.contains_key(&count) { "" } else { "mapping count back" };
            steps.push(Step::new(count, final_count, interim));
        }
        let final_cob = changes.get(&cob).cloned().or_else(|| cob_now.map(|c| c.to_le_bytes().to_vec()));
        if let Some(v) = final_cob {
            steps.push(Step::new(cob, v, if changes.contains_key(&cob) { "" } else { "PDO valid again" }));
        }
        for step in &mut steps[first..] {
            step.pdo = Some((comm, map));
        }
    }
    steps
}
