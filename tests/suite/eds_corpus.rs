//! Real device description files (`../shared/eds-corpus/`, vendors' and generators' EDS
//! and DCF files, each with its source in SOURCES.txt; never copied into this repository):
//! every one loads, canctl finds the objects python-canopen finds where python-canopen
//! loads the file, and each DCF's values survive dump and reload.
//!
//! Without the corpus the tests say they are skipped, unless `CANCTL_REQUIRE_CORPUS` is set.
//! `CANCTL_EDS_CORPUS` points elsewhere (a git worktree has no `../shared`). Without
//! python-canopen the comparison is skipped, unless `CANCTL_REQUIRE_PEERS` is set (CI).
//! `cargo test --test suite eds_corpus:: -- --nocapture` prints the corpus table.

use crate::common;

use canctl::canopen::ObjAddr;
use canctl::od::eds::{self, Eds, Header};
use canctl::od::{lint::Severity, Entry, ObjectKind};
use serde_json::Value as J;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The corpus's EDS and DCF files, or `None` (said) when it is absent.
fn corpus() -> Option<Vec<PathBuf>> {
    let dir = common::eds_corpus()?;
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("eds") || e.eq_ignore_ascii_case("dcf")))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "an empty corpus at {}", dir.display());
    Some(files)
}

fn name(p: &Path) -> String {
    p.file_name().unwrap().to_string_lossy().into_owned()
}

/// python-canopen's objects for each file (index, sub, data type, name), or its refusal;
/// `None` (said) without python-canopen.
/// python-canopen's view of one file: its objects (index, sub, data type, name) or why it refuses it.
type Theirs = Result<Vec<(u16, u8, u16, String)>, String>;

fn python_canopen(files: &[PathBuf]) -> Option<BTreeMap<String, Theirs>> {
    let out = common::python_peer("eds_objects.py", files, "No module named 'canopen'")?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "eds_objects.py failed: {stderr}");
    let answer: J = serde_json::from_slice(&out.stdout).unwrap();
    let mut by_file = BTreeMap::new();
    for path in files {
        let theirs = &answer[path.to_str().unwrap()];
        let result = match theirs.get("objects") {
            Some(list) => Ok(list
                .as_array()
                .unwrap()
                .iter()
                .map(|o| {
                    let n = |i: usize| o[i].as_u64().unwrap_or(0);
                    (n(0) as u16, n(1) as u8, n(2) as u16, o[3].as_str().unwrap_or("").to_string())
                })
                .collect()),
            None => Err(theirs["refused"].as_str().unwrap_or("?").to_string()),
        };
        by_file.insert(name(path), result);
    }
    Some(by_file)
}

fn load(path: &Path) -> Eds {
    eds::read_file(path).unwrap_or_else(|e| panic!("refused: {e}"))
}

/// Objects of a CompactSubObj array: python-canopen names their sub 0 "Number of entries"
/// and sub 1 after the object, canctl after CiA 306 (NrOfObjects, name + sub-index).
fn compact_arrays(path: &Path) -> BTreeSet<u16> {
    let text = String::from_utf8_lossy(&std::fs::read(path).unwrap()).to_ascii_lowercase();
    let mut out = BTreeSet::new();
    let mut section = None;
    for line in text.lines() {
        let line = line.trim();
        if let Some(s) = line.strip_prefix('[').and_then(|s| s.strip_suffix(']')) {
            section = u16::from_str_radix(s, 16).ok().filter(|_| s.len() == 4);
        } else if line.starts_with("compactsubobj") && !line.ends_with("=0") {
            out.extend(section);
        }
    }
    out
}

#[test]
fn every_file_loads_with_python_canopens_objects() {
    let Some(files) = corpus() else { return };
    let python = python_canopen(&files);
    println!(
        "{:<58} {:<28} {:<9} {:>4} {:>4} {:>7} {:>7}",
        "file", "vendor", "verdict", "err", "warn", "canctl", "python"
    );
    let (mut refused_by_python, mut mismatches) = (0, Vec::new());
    for path in &files {
        let eds = load(path);
        let errors = eds.warnings.iter().filter(|w| w.severity == Severity::Error).count();
        let warnings = eds.warnings.len() - errors;
        let verdict = match (errors, warnings) {
            (0, 0) => "ok",
            (0, _) => "warnings",
            _ => "errors",
        };
        let ours: BTreeMap<(u16, u8), &Entry> = eds.dict.entries().map(|e| ((e.addr.index, e.addr.sub), e)).collect();
        let theirs = python.as_ref().map(|p| p[&name(path)].clone());
        let count = match &theirs {
            Some(Ok(list)) => list.iter().filter(|o| o.0 >= 0x1000).count().to_string(),
            Some(Err(_)) => {
                refused_by_python += 1;
                "refused".into()
            }
            None => "-".into(),
        };
        let vendor = eds.info.get("vendorname").cloned().unwrap_or_default();
        println!(
            "{:<58} {:<28} {:<9} {:>4} {:>4} {:>7} {:>7}",
            name(path),
            vendor.chars().take(28).collect::<String>(),
            verdict,
            errors,
            warnings,
            ours.len(),
            count
        );
        for w in &eds.warnings {
            println!("    {w}");
        }
        let Some(Ok(theirs)) = theirs else { continue };
        let compact = compact_arrays(path);
        for (index, sub, code, their_name) in theirs.iter().filter(|o| o.0 >= 0x1000) {
            let at = ObjAddr::new(*index, *sub);
            let Some(e) = ours.get(&(*index, *sub)) else {
                mismatches.push(format!("{}: {at} ({their_name}) python-canopen has it, canctl not", name(path)));
                continue;
            };
            if e.dtype.code() != *code {
                mismatches.push(format!(
                    "{}: {at} type {} in canctl, 0x{code:04X} in python-canopen",
                    name(path),
                    e.dtype
                ));
            }
            let our_name = match eds.dict.object_info(*index) {
                Some((object, ObjectKind::Var)) => object.to_string(),
                _ => e.name.clone(),
            };
            if our_name != *their_name && !compact.contains(index) {
                mismatches.push(format!(
                    "{}: {at} named '{our_name}' by canctl, '{their_name}' by python-canopen",
                    name(path)
                ));
            }
        }
    }
    println!("python-canopen refuses {refused_by_python} of {} files; canctl refuses none", files.len());
    assert!(mismatches.is_empty(), "{} differences:\n{}", mismatches.len(), mismatches.join("\n"));
}

#[test]
fn every_dcf_value_survives_dump_and_reload() {
    let Some(files) = corpus() else { return };
    let mut checked = 0;
    for path in files.iter().filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("dcf"))) {
        let eds = load(path);
        let node = eds.node_id.unwrap_or(1);
        let resolved = |e: &Eds, addr: &ObjAddr, init: &canctl::od::Init| {
            let entry = e.dict.get(*addr).expect("a value has its entry");
            Entry { default: init.clone(), ..entry.clone() }.default_for(node)
        };
        let values: BTreeMap<ObjAddr, Vec<u8>> = eds
            .values
            .iter()
            .filter(|(a, _)| eds.dict.get(**a).is_some())
            .map(|(a, v)| (*a, resolved(&eds, a, v)))
            .collect();
        let header = Header { file_name: name(path), node_id: Some(node), ..Header::default() };
        let file =
            eds::write_bytes(&eds.dict, Some(&values), &header).unwrap_or_else(|e| panic!("{}: {e}", name(path)));
        let back = eds::parse(&file, "reloaded.dcf").unwrap();
        assert!(back.warnings.is_empty(), "{}: {:?}", name(path), back.warnings);
        for (addr, want) in &values {
            let got = back.values.get(addr).map(|v| resolved(&back, addr, v));
            assert_eq!(got.as_ref(), Some(want), "{}: {addr}", name(path));
            checked += 1;
        }
    }
    println!("{checked} DCF values dumped and read back");
}
