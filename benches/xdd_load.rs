//! Time and peak memory to load device descriptions: the XDD of the shared corpus (the
//! CANopenDemo device, 150 kB) beside its EDS, and a generated XDC of 8000 values (1.5 MB)
//! for how it grows. `cargo bench --bench xdd_load` (XDD_LOAD_RUNS=N, default 20;
//! CANCTL_EDS_CORPUS where the corpus is, default ../shared/eds-corpus).
//!
//! Peak memory is the resident high-water mark (VmHWM, Linux) of a child process that
//! loads the file once, less that of one that loads nothing: what loading costs at most.

use canctl::canopen::DataType;
use canctl::od::{self, eds::Header, Access, Dictionary, Init};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

fn peak_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// The child: load `path` (or nothing, for "-") and print the peak.
fn child(path: &str) {
    if path != "-" {
        let eds = od::read_description(Path::new(path)).expect("loads");
        std::hint::black_box(eds.dict.entries().count());
    }
    println!("{}", peak_kib().unwrap_or(0));
}

fn peak_in_child(path: &str) -> Option<u64> {
    let me = std::env::current_exe().ok()?;
    let out = Command::new(me).env("XDD_LOAD_CHILD", path).output().ok()?;
    String::from_utf8(out.stdout).ok()?.trim().parse().ok()
}

/// An XDC of `objects` records of 8 UNSIGNED32 values each, all with actual values.
fn generated(objects: u16, dir: &Path) -> PathBuf {
    let mut dict = Dictionary::default();
    let mut values = std::collections::BTreeMap::new();
    for i in 0..objects {
        let index = 0x2000 + i;
        let members =
            (1..=7u8).map(|s| (s, "Parameter value", DataType::U32, Access::Rw, Init::Bytes(vec![s, 0, 0, 0])));
        dict.record(index, &format!("Manufacturer parameter block {i}"), members.collect());
        for e in dict.object_entries(index) {
            values.insert(e.addr, e.default_for(1));
        }
    }
    let bytes = od::xdd::write_bytes(&dict, Some(&values), &Header { node_id: Some(1), ..Header::default() }).unwrap();
    let path = dir.join("generated.xdc");
    std::fs::write(&path, bytes).unwrap();
    path
}

fn main() {
    if let Ok(path) = std::env::var("XDD_LOAD_CHILD") {
        return child(&path);
    }
    let runs: usize = std::env::var("XDD_LOAD_RUNS").ok().and_then(|v| v.parse().ok()).unwrap_or(20);
    let corpus = std::env::var_os("CANCTL_EDS_CORPUS")
        .map_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/eds-corpus"), PathBuf::from);
    let dir = std::env::temp_dir().join(format!("canctl-xdd-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut files: Vec<PathBuf> = ["CANopenDemo__demoDevice.xdd", "CANopenDemo__demoDevice.eds"]
        .iter()
        .map(|n| corpus.join(n))
        .filter(|p| p.exists())
        .collect();
    if files.is_empty() {
        eprintln!("note: {} not found: only the generated file is measured", corpus.display());
    }
    files.push(generated(1000, &dir));
    let base = peak_in_child("-").unwrap_or(0);
    println!("{:<32} {:>9} {:>8} {:>11} {:>11} {:>14}", "file", "bytes", "objects", "median", "min", "peak RSS");
    for path in &files {
        let mut times: Vec<Duration> = (0..runs)
            .map(|_| {
                let start = Instant::now();
                let eds = od::read_description(path).expect("loads");
                std::hint::black_box(&eds);
                start.elapsed()
            })
            .collect();
        times.sort();
        let objects = od::read_description(path).unwrap().dict.objects().count();
        let peak = peak_in_child(path.to_str().unwrap()).map(|p| p.saturating_sub(base));
        println!(
            "{:<32} {:>9} {:>8} {:>8.2} ms {:>8.2} ms {:>10} KiB",
            path.file_name().unwrap().to_string_lossy(),
            std::fs::metadata(path).unwrap().len(),
            objects,
            times[runs / 2].as_secs_f64() * 1e3,
            times[0].as_secs_f64() * 1e3,
            peak.map_or("?".into(), |p| p.to_string())
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
