//! Outputs that cannot be lost or turned against the terminal: `--out` replaces its file
//! atomically (the old file survives a full disk), output I/O errors exit 7, and strings
//! from devices reach a terminal with their control characters escaped while JSON and CSV
//! keep them exact.

use crate::common;

use std::process::Command;

/// `sh -c` running canctl with a file-size limit of 512 bytes and SIGXFSZ ignored: a write
/// past the limit fails with EFBIG, as a write on a full disk fails with ENOSPC, after part
/// of the data went in.
#[cfg(unix)]
fn with_small_disk(sim: &common::Sim, args: &[&str]) -> common::Run {
    let c = sim.command(args);
    let mut line = String::from("ulimit -f 1; trap '' XFSZ; exec");
    line.push_str(&format!(" '{}'", c.get_program().to_string_lossy()));
    for a in c.get_args() {
        line.push_str(&format!(" '{}'", a.to_string_lossy()));
    }
    let mut sh = Command::new("sh");
    sh.arg("-c").arg(line).current_dir(sim.path(""));
    for (k, v) in c.get_envs() {
        match v {
            Some(v) => sh.env(k, v),
            None => sh.env_remove(k),
        };
    }
    common::finish(sh.output().unwrap())
}

fn leftovers(sim: &common::Sim) -> Vec<String> {
    std::fs::read_dir(sim.path(""))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("canctl-tmp"))
        .collect()
}

#[test]
fn out_replaces_the_file_whole() {
    let sim = common::Sim::new();
    let out = sim.path("program.bin");
    std::fs::write(&out, b"old").unwrap();
    let run = sim.run(&["sdo", "read", "1", "1F50:1", "--type", "d", "--out", out.to_str().unwrap()]).ok();
    assert!(run.stdout.contains("written to"), "{}", run.stdout);
    assert_eq!(std::fs::read(&out).unwrap().len(), 65536);
    assert!(leftovers(&sim).is_empty(), "{:?}", leftovers(&sim));
}

#[cfg(unix)]
#[test]
fn a_full_disk_keeps_the_old_file_and_exits_7() {
    let sim = common::Sim::new();
    let out = sim.path("program.bin");
    std::fs::write(&out, b"the previous file").unwrap();
    let run = with_small_disk(&sim, &["sdo", "read", "1", "1F50:1", "--type", "d", "--out", "program.bin"]);
    assert_eq!(run.code, 7, "{}", run.stderr);
    assert!(run.stderr.contains("cannot write program.bin") && run.stderr.contains("unchanged"), "{}", run.stderr);
    assert_eq!(std::fs::read(&out).unwrap(), b"the previous file");
    assert!(leftovers(&sim).is_empty(), "temporary file left: {:?}", leftovers(&sim));

    // The DCF of config dump likewise.
    let dcf = sim.path("node10.dcf");
    std::fs::write(&dcf, b"[FileInfo]\n").unwrap();
    let run = with_small_disk(&sim, &["config", "dump", "10", "--out", "node10.dcf"]);
    assert_eq!(run.code, 7, "{}", run.stderr);
    assert_eq!(std::fs::read(&dcf).unwrap(), b"[FileInfo]\n");
    assert!(leftovers(&sim).is_empty(), "temporary file left: {:?}", leftovers(&sim));
}

/// A temporary file left by a canctl killed outright while it wrote (SIGKILL, a power cut),
/// and one of the name older versions used, are in nobody's way: the next write succeeds,
/// and removes the one whose writer is gone. A writer still running keeps its file.
#[cfg(unix)]
#[test]
fn a_temporary_file_left_by_a_killed_writer_does_not_block_the_next_write() {
    let sim = common::Sim::new();
    let out = sim.path("sensor.dcf");
    std::fs::write(&out, b"old").unwrap();
    // A canctl killed with SIGKILL: its pid is free again.
    let mut killed = sim.command(&["config", "dump", "5", "--out", out.to_str().unwrap()]);
    killed.stdout(std::process::Stdio::null()).stderr(std::process::Stdio::null());
    let mut child = killed.spawn().unwrap();
    let dead = child.id();
    child.kill().unwrap();
    child.wait().unwrap();
    // What it would have left had it died between writing and renaming.
    let stale = sim.path(&format!(".sensor.dcf.{dead}.canctl-tmp"));
    std::fs::write(&stale, b"[FileInfo]\nFileName=sens").unwrap();
    let legacy = sim.path(".sensor.dcf.canctl-tmp");
    std::fs::write(&legacy, b"half").unwrap();
    let live = sim.path(&format!(".sensor.dcf.{}.canctl-tmp", std::process::id()));
    std::fs::write(&live, b"busy").unwrap();
    let run = sim.run(&["config", "dump", "5", "--out", out.to_str().unwrap()]).ok();
    assert!(run.stderr.contains("written to"), "{}", run.stderr);
    assert!(std::fs::read_to_string(&out).unwrap().starts_with("[FileInfo]"));
    assert!(!stale.exists(), "the dead writer's temporary file is still there");
    assert!(live.exists(), "a running writer's temporary file was removed");
    // Only the running writer's file, and the old name's, are left.
    let mut left = leftovers(&sim);
    left.sort();
    let mut want = [".sensor.dcf.canctl-tmp".to_string(), format!(".sensor.dcf.{}.canctl-tmp", std::process::id())];
    want.sort();
    assert_eq!(left, want);
}

#[test]
fn a_directory_as_the_target_is_refused() {
    let sim = common::Sim::new();
    let run = sim.run(&["sdo", "read", "1", "1F50:1", "--type", "d", "--out", sim.path("").to_str().unwrap()]);
    assert_eq!(run.code, 7, "{}", run.stderr);
    assert!(run.stderr.contains("it is a directory"), "{}", run.stderr);
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_standard_output_exits_7() {
    let sim = common::Sim::new();
    let full = || std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
    let run = common::finish(sim.command(&["sdo", "read", "10", "1008"]).stdout(full()).output().unwrap());
    assert_eq!(run.code, 7, "{}", run.stderr);
    assert!(run.stderr.contains("cannot write to standard output: No space left on device"), "{}", run.stderr);
    // --out to a device writes to it directly (no file renamed over /dev/full).
    let run = sim.run(&["sdo", "read", "1", "1F50:1", "--type", "d", "--out", "/dev/full"]);
    assert_eq!(run.code, 7, "{}", run.stderr);
    assert!(std::fs::metadata("/dev/full").unwrap().file_type().is_char_device_like());
}

#[cfg(target_os = "linux")]
trait CharDevice {
    fn is_char_device_like(&self) -> bool;
}

#[cfg(target_os = "linux")]
impl CharDevice for std::fs::FileType {
    fn is_char_device_like(&self) -> bool {
        use std::os::unix::fs::FileTypeExt;
        self.is_char_device()
    }
}

/// What a hostile or broken device might hold in its name: a window-title escape, a bell,
/// a line break, a cursor movement, a C1 control and a right-to-left override.
const HOSTILE: &str = "\u{1b}]0;pwned\u{7}\nX\u{1b}[2A\u{9b}31m\u{202e}evil";

/// The sim keeps device values in its state file: a name no SDO write could set (0x1008 is
/// const) is put there, as a device that holds it would answer it.
fn device_named(sim: &common::Sim, name: &str) {
    sim.run(&["sdo", "write", "10", "5FF0:2", "7", "--type", "u8"]).ok();
    let path = sim.path("sim.json");
    let mut state: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    let hex: String = name.bytes().map(|b| format!("{b:02x}")).collect();
    state["devices"]["io"]["values"]["1008:0"] = serde_json::Value::String(hex);
    std::fs::write(&path, serde_json::to_vec(&state).unwrap()).unwrap();
}

fn controls(text: &str) -> Vec<char> {
    text.chars().filter(|c| (c.is_control() && *c != '\n') || *c == '\u{202e}').collect()
}

#[test]
fn device_strings_reach_the_terminal_escaped_and_json_exact() {
    let sim = common::Sim::new();
    device_named(&sim, HOSTILE);
    let escaped = r"\x1b]0;pwned\x07\nX\x1b[2A\u{9b}31m\u{202e}evil";

    let read = sim.run(&["sdo", "read", "10", "1008"]).ok();
    assert_eq!(read.stdout, format!("{escaped}\n"));
    let scan = sim.run(&["scan"]).ok();
    assert!(controls(&scan.stdout).is_empty(), "{:?}", scan.stdout);
    assert!(scan.stdout.contains(escaped), "{}", scan.stdout);

    // Machine formats: the exact string, in their own escaping.
    let json = sim.run(&["sdo", "read", "10", "1008", "--format", "json"]).ok().json();
    assert_eq!(json["value"], HOSTILE);
    let scan = sim.run(&["scan", "--format", "json"]).ok().json();
    let io = scan["nodes"].as_array().unwrap().iter().find(|n| n["node"] == 10).unwrap();
    assert_eq!(io["name"], HOSTILE, "{io}");
    let csv = sim.run(&["sdo", "read", "10", "1008", "--format", "csv"]).ok();
    assert!(csv.stdout.contains(&format!("\"{HOSTILE}\"")), "{:?}", csv.stdout);

    // A DCF read from it: the file holds what the device said (CiA 306 escaping, or the
    // value left out with a note); the note itself is escaped.
    let dump = sim.run(&["config", "dump", "10"]);
    assert!(controls(&dump.stderr).is_empty(), "{:?}", dump.stderr);
}

/// A DCF's strings (a name, a bad value quoted in the error) reach the terminal escaped.
#[test]
fn file_strings_reach_the_terminal_escaped() {
    let sim = common::Sim::new();
    let dcf = |value: &str| {
        format!(
            "[FileInfo]\nFileName=x.dcf\n[1017]\nParameterName=Heart\u{1b}]0;pwned\u{7}beat\nObjectType=0x7\n\
             DataType=0x0006\nAccessType=rw\nDefaultValue=0\nParameterValue={value}\n"
        )
    };
    let path = sim.path("evil.dcf");
    std::fs::write(&path, dcf("zz\u{1b}[2J")).unwrap();
    let run = sim.run(&["config", "diff", "5", path.to_str().unwrap()]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(controls(&run.stderr).is_empty() && run.stderr.contains(r"'zz\x1b[2J'"), "{:?}", run.stderr);

    std::fs::write(&path, dcf("1234")).unwrap();
    let run = sim.run(&["config", "diff", "5", path.to_str().unwrap()]).ok();
    assert!(run.stdout.contains(r"Heart\x1b]0;pwned\x07beat"), "{:?}", run.stdout);
    assert!(controls(&run.stdout).is_empty(), "{:?}", run.stdout);
    let json = sim.run(&["config", "diff", "5", path.to_str().unwrap(), "--format", "json"]).ok().json();
    assert_eq!(json["differences"][0]["name"], "Heart\u{1b}]0;pwned\u{7}beat");
}

/// How canctl ended when what it writes goes into a pipe whose reader reads `lines` lines
/// and goes away (`canctl ... 2>&1 | head -1`): stderr always into the pipe, stdout too when
/// `stdout_too` (else to /dev/null: `2>&1 >/dev/null | head -1`).
#[cfg(unix)]
fn code_with_reader_gone(mut c: Command, stdout_too: bool, lines: usize) -> i32 {
    use std::io::BufRead;
    let (reader, writer) = std::io::pipe().unwrap();
    match stdout_too {
        true => c.stdout(writer.try_clone().unwrap()),
        false => c.stdout(std::process::Stdio::null()),
    };
    let mut child = c.stderr(writer).spawn().unwrap();
    // The command holds copies of the pipe's writing end: without them, the child's are the
    // last, and its writes fail once the reader is gone.
    drop(c);
    let mut reader = std::io::BufReader::new(reader);
    for _ in 0..lines {
        reader.read_line(&mut String::new()).unwrap();
    }
    drop(reader);
    let start = std::time::Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status.code().unwrap_or(-1);
        }
        if start.elapsed() > std::time::Duration::from_secs(60) {
            let _ = child.kill();
            panic!("still running a minute after its reader went away");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// Exit 101 is Rust's panic: `eprintln!` panics when stderr's reader is gone. A closed
/// pipe ends canctl quietly with exit 0 (README: also when the reader went away), whichever
/// stream found it closed.
#[cfg(unix)]
#[test]
fn a_reader_gone_ends_the_command_quietly_not_with_a_panic() {
    let sim = common::Sim::new();
    // Node 7 is silent: doctor waits out each question it asks it.
    let doctor = &["--timeout", "100ms", "doctor", "7"][..];
    // `2>&1 | head -1`: a stream ends at its next record; a report may have gone whole
    // into the pipe before its reader left, and then ends with its own verdict (doctor's 6).
    let stream = sim.command(&["stream-pdo", "5", "--start", "--interval", "5ms"]);
    assert_eq!(code_with_reader_gone(stream, true, 1), 0, "stream-pdo 5 --start 2>&1 | head -1");
    for (args, verdict) in [(doctor, 6), (&["health"][..], 0)] {
        let code = code_with_reader_gone(sim.command(args), true, 1);
        assert!(code == 0 || code == verdict, "{args:?} 2>&1 | head -1: exit {code}");
    }
    // Only stderr into the pipe, its reader gone at once: the notes and the final message
    // find it closed, every time.
    for args in [doctor, &["health"][..], &["stream-pdo", "5", "--start", "--count", "3"][..]] {
        assert_eq!(code_with_reader_gone(sim.command(args), false, 0), 0, "{args:?} 2>&1 >/dev/null | head -0");
    }
}
