//! Time and peak memory to load the largest EDS/DCF of the corpus (`../shared/eds-corpus`,
//! or `CANCTL_EDS_CORPUS`), or the files given as arguments.
//!
//! `cargo bench --bench eds_load [-- FILE...]` (EDS_LOAD_RUNS=N, default 20). A plain harness:
//! each run reads and parses the file as `--eds` does; peak memory is the process's high-water
//! mark (Linux `VmHWM`) after the first load, over its resident size before it.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// `VmHWM` or `VmRSS` of this process, in KiB (Linux); 0 elsewhere.
fn status_kib(key: &str) -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix(key)?.trim_start_matches(':').split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

fn largest() -> Option<PathBuf> {
    let dir = std::env::var_os("CANCTL_EDS_CORPUS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/eds-corpus"));
    std::fs::read_dir(&dir)
        .ok()?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("eds") || e.eq_ignore_ascii_case("dcf")))
        .max_by_key(|p| std::fs::metadata(p).map(|m| m.len()).unwrap_or(0))
}

fn main() {
    // cargo bench passes --bench; the rest are files.
    let mut files: Vec<PathBuf> =
        std::env::args().skip(1).filter(|a| !a.starts_with("--")).map(PathBuf::from).collect();
    if files.is_empty() {
        match largest() {
            Some(f) => files.push(f),
            None => {
                eprintln!("eds_load: no corpus (../shared/eds-corpus or CANCTL_EDS_CORPUS); give files as arguments");
                return;
            }
        }
    }
    let runs: u32 = std::env::var("EDS_LOAD_RUNS").ok().and_then(|v| v.parse().ok()).unwrap_or(20);
    for file in files {
        let before = status_kib("VmRSS");
        let first = canctl::od::eds::read_file(&file).unwrap_or_else(|e| panic!("{e}"));
        let peak = status_kib("VmHWM").saturating_sub(before);
        let entries = first.dict.entries().count();
        drop(first);
        let mut times: Vec<Duration> = (0..runs)
            .map(|_| {
                let t = Instant::now();
                let eds = canctl::od::eds::read_file(&file).unwrap();
                std::hint::black_box(&eds);
                t.elapsed()
            })
            .collect();
        times.sort();
        let size = std::fs::metadata(&file).map(|m| m.len()).unwrap_or(0);
        println!(
            "{}: {} bytes, {entries} entries; load median {:.2} ms, min {:.2} ms over {runs} runs; peak memory +{peak} KiB",
            file.display(),
            size,
            times[times.len() / 2].as_secs_f64() * 1e3,
            times[0].as_secs_f64() * 1e3,
        );
    }
}
