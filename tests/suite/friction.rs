//! What a new user meets in the first hour (issue 25, "Friction"): messages that say what
//! is wrong once and name the path, output paths checked before the work, tables that fit
//! the terminal, progress while slow work runs, suggestions from the node's own dictionary.

use crate::common;

use common::Sim;

fn reset(sim: &Sim, profile: &str) {
    sim.run(&["sim", "reset", "--profile", profile]).ok();
}

/// An EDS or DCF that cannot be read is said once: "cannot read FILE: why", not
/// "cannot use EDS cannot read FILE" nor "cannot use cannot read FILE".
#[test]
fn an_unreadable_dictionary_is_said_once() {
    let sim = Sim::new();
    reset(&sim, "instant");
    for args in [
        &["--eds", "/nonexistent.eds", "scan"][..],
        &["--eds", "5=/nonexistent.eds", "scan"],
        &["config", "diff", "5", "/nonexistent.dcf"],
        &["config", "apply", "5", "/nonexistent.dcf"],
    ] {
        let run = sim.run(args);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        let name = if args.contains(&"scan") { "/nonexistent.eds" } else { "/nonexistent.dcf" };
        assert!(run.stderr.starts_with(&format!("canctl: cannot read {name}: ")), "{args:?}: {}", run.stderr);
        assert!(!run.stderr.contains("cannot use"), "{args:?}: {}", run.stderr);
    }
}

/// `man --out` into a folder that cannot be made names the path it could not make.
#[test]
fn man_out_names_the_path_it_cannot_write() {
    let run = common::bare(&["man", "--out", "/proc/x"]);
    assert_eq!(run.code, 7, "{}", run.stderr);
    assert!(run.stderr.contains("/proc/x"), "{}", run.stderr);
}

/// `--out` is checked before the work, as `--log-frames` is: a path in a folder that does
/// not exist fails before a single frame is sent, and says which folder is missing.
#[test]
fn out_paths_are_checked_before_the_work() {
    let sim = Sim::new();
    reset(&sim, "instant");
    let log = sim.path("frames.log");
    let log = log.to_str().unwrap();
    let missing = sim.path("no-such-folder/x.dcf");
    let missing = missing.to_str().unwrap();
    for args in [
        &["--log-frames", log, "config", "dump", "1", "--out", missing][..],
        &["--log-frames", log, "sdo", "read", "1", "1008", "--out", missing],
    ] {
        let run = sim.run(args);
        assert_eq!(run.code, 7, "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains("there is no folder") && run.stderr.contains("no-such-folder"), "{}", run.stderr);
        let frames = std::fs::read_to_string(log).unwrap();
        assert!(frames.is_empty(), "{args:?} talked to the bus before checking --out:\n{frames}");
    }
    // network dump into a folder that cannot be made (under a file) fails before the scan;
    // into one that does not exist yet, it is made.
    let file = sim.path("a-file");
    std::fs::write(&file, "x").unwrap();
    let under_a_file = file.join("machine");
    let run = sim.run(&["--log-frames", log, "network", "dump", under_a_file.to_str().unwrap()]);
    assert_eq!(run.code, 7, "{}", run.stderr);
    assert!(std::fs::read_to_string(log).unwrap().is_empty(), "network dump talked to the bus first");
    let fresh = sim.path("new/machine");
    sim.run(&["network", "dump", fresh.to_str().unwrap()]).ok();
    assert!(fresh.join("nodelist.cpj").exists());
    // A folder given where a file is meant is refused at once too.
    let run = sim.run(&["--log-frames", log, "config", "dump", "1", "--out", sim.path("").to_str().unwrap()]);
    assert_eq!(run.code, 7, "{}", run.stderr);
    assert!(run.stderr.contains("it is a directory"), "{}", run.stderr);
    assert!(std::fs::read_to_string(log).unwrap().is_empty());
    // And a good path still gets its file.
    let good = sim.path("node1.dcf");
    sim.run(&["config", "dump", "1", "--out", good.to_str().unwrap()]).ok();
    assert!(std::fs::read_to_string(&good).unwrap().contains("[DeviceInfo]"));
}

/// What `--bus` echoes is cut to a readable length; a name one letter from `sim` gets
/// "did you mean"; a path that is no serial port is said to be none, not "Not a typewriter".
#[test]
fn bus_mistakes_are_explained() {
    let long = "a".repeat(100_000);
    let run = common::bare(&["--bus", &long, "scan"]);
    assert_eq!(run.code, 2, "{}", &run.stderr[..run.stderr.len().min(300)]);
    assert!(run.stderr.len() < 1000, "{} bytes of message", run.stderr.len());
    assert!(run.stderr.contains("(100000 characters)"), "{}", run.stderr);

    let run = common::bare(&["--bus", "sims", "scan"]);
    assert_eq!(run.code, 5, "{}", run.stderr);
    assert!(run.stderr.contains("did you mean --bus sim?"), "{}", run.stderr);

    let run = common::bare(&["--bus", "epos2-rs232:/dev/null", "scan"]);
    assert_eq!(run.code, 5, "{}", run.stderr);
    assert!(run.stderr.starts_with("canctl: /dev/null is not a serial port"), "{}", run.stderr);
    assert!(!run.stderr.contains("typewriter"), "{}", run.stderr);
}

/// A fault for a device the sim network does not have is refused, naming the ones it has,
/// rather than accepted and never fired.
#[test]
fn a_fault_for_no_device_is_refused() {
    let sim = Sim::new();
    let run = sim.run(&["sim", "reset", "--fault", "99:drop"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("node 99") && run.stderr.contains("1, 5, 10, 32"), "{}", run.stderr);
    let run = sim.run(&["sim", "reset", "--unconfigured", "0", "--fault", "sensor-09501301:drop"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    sim.run(&["sim", "reset", "--fault", "sensor-09501301:drop", "--fault", "5:drop"]).ok();
}

/// `args` run with stdout and stderr on a pseudo-terminal `cols` columns wide (no
/// `COLUMNS`): its exit code and what stays on the screen, line by line.
fn on_a_terminal(sim: &Sim, cols: u16, args: &[&str]) -> (i32, Vec<String>) {
    let (code, shown) = on_a_terminal_raw(sim, cols, args);
    (code, screen(&shown, cols as usize))
}

/// `args` run on a pseudo-terminal `cols` columns wide: its exit code and every byte it
/// sent there (progress bars as they were drawn).
fn on_a_terminal_raw(sim: &Sim, cols: u16, args: &[&str]) -> (i32, String) {
    use std::io::Read;
    let size = nix::pty::Winsize { ws_row: 40, ws_col: cols, ws_xpixel: 0, ws_ypixel: 0 };
    let pty = nix::pty::openpty(Some(&size), None).unwrap();
    let mut c = sim.command(args);
    c.env_remove("COLUMNS");
    c.stdout(std::process::Stdio::from(pty.slave.try_clone().unwrap()));
    c.stderr(std::process::Stdio::from(pty.slave));
    let mut child = c.spawn().unwrap();
    // Only canctl may hold the terminal's other side, for EIO at its end.
    drop(c);
    let mut master = std::fs::File::from(pty.master);
    let reader = std::thread::spawn(move || {
        let mut shown = Vec::new();
        let _ = master.read_to_end(&mut shown);
        String::from_utf8_lossy(&shown).into_owned()
    });
    let code = child.wait().unwrap().code().unwrap_or(-1);
    (code, reader.join().unwrap())
}

/// What stays on a terminal `width` columns wide after `output`: lines wrap at the width,
/// and the cursor moves and erasures progress bars use (CR, ESC[nA, ESC[nB, ESC[K, ESC[2K,
/// ESC[J) are obeyed; other escapes are ignored.
fn screen(output: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<Vec<char>> = vec![Vec::new()];
    let (mut row, mut col) = (0usize, 0usize);
    let mut chars = output.chars().peekable();
    while let Some(c) = chars.next() {
        if lines.len() <= row {
            lines.resize(row + 1, Vec::new());
        }
        match c {
            '\x1b' if chars.peek() == Some(&'[') => {
                chars.next();
                let mut arg = String::new();
                while let Some(&p) = chars.peek().filter(|p| p.is_ascii_digit() || **p == '?') {
                    arg.push(p);
                    chars.next();
                }
                let n: usize = arg.trim_start_matches('?').parse().unwrap_or(0);
                match chars.next() {
                    Some('A') => row = row.saturating_sub(n.max(1)),
                    Some('B') => row += n.max(1),
                    Some('K') if n == 2 => lines[row].clear(),
                    Some('K') => lines[row].truncate(col),
                    Some('J') => {
                        lines[row].truncate(col);
                        lines.truncate(row + 1);
                    }
                    _ => {}
                }
            }
            '\r' => col = 0,
            '\n' => row += 1,
            c if c.is_control() => {}
            c => {
                if col >= width {
                    (row, col) = (row + 1, 0);
                    if lines.len() <= row {
                        lines.resize(row + 1, Vec::new());
                    }
                }
                let line = &mut lines[row];
                if line.len() < col {
                    line.resize(col, ' ');
                }
                if col < line.len() {
                    line[col] = c;
                } else {
                    line.push(c);
                }
                col += 1;
            }
        }
    }
    lines.into_iter().map(|l| l.into_iter().collect::<String>().trim_end().to_string()).collect()
}

/// Progress lines are cleared once the work is done: at 80 columns a bar drawn before it
/// joined the per-node display stayed on the screen (`probing [ ] 0/127`).
#[test]
fn no_progress_line_stays_on_the_screen() {
    let sim = Sim::new();
    reset(&sim, "instant");
    let project = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/sim-machine");
    let (code, lines) = on_a_terminal(&sim, 80, &["network", "apply", project, "--assign"]);
    assert_eq!(code, 3, "{lines:#?}");
    assert!(lines.iter().any(|l| l.contains("object(s) written on")), "{lines:#?}");
    for l in &lines {
        assert!(!l.contains("probing") && !l.contains("applying") && !l.contains("read(s)"), "left: {l:?}\n{lines:#?}");
    }
}

/// The first screen of the main job fits a terminal of 80 columns: scan and health drop
/// the columns least needed and say so; `--wide` and a pipe keep every column.
#[test]
fn tables_fit_an_80_column_terminal() {
    let sim = Sim::new();
    reset(&sim, "instant");
    for command in ["scan", "health"] {
        let (code, lines) = on_a_terminal(&sim, 80, &[command]);
        assert_eq!(code, 0, "{lines:#?}");
        // The table's lines (sentences wrap between words, as text does).
        for l in lines.iter().filter(|l| l.starts_with([' ', '│', '┌', '╞', '└'])) {
            assert!(l.chars().count() <= 80, "{command}: {} columns: {l:?}", l.chars().count());
        }
        assert!(lines.iter().any(|l| l.contains("node") && l.contains("name")), "{command}: {lines:#?}");
        // The note is prose: broken between words to fit, "column)" on a line of its own.
        assert!(lines.iter().any(|l| l.contains("(--wide shows every")), "{command}: {lines:#?}");
    }
    let (_, lines) = on_a_terminal(&sim, 80, &["scan"]);
    let header = lines.iter().find(|l| l.contains("node") && l.contains("state")).expect("a header with the state");
    assert!(!header.contains("serial"), "{header}");
    assert!(lines.iter().any(|l| l.contains("C01") && l.contains("pre-operational")), "{lines:#?}");

    let (_, wide) = on_a_terminal(&sim, 80, &["--wide", "scan"]);
    assert!(wide.iter().any(|l| l.contains("serial") && l.contains("revision")), "{wide:#?}");
    assert!(!wide.iter().any(|l| l.contains("--wide shows")), "{wide:#?}");
    let piped = sim.run(&["scan"]).ok();
    assert!(piped.stdout.lines().next().unwrap().contains("serial"), "{}", piped.stdout);
    assert!(!piped.stderr.contains("--wide"), "{}", piped.stderr);
}

/// The lines a terminal was sent, each as it was finally drawn: escape sequences left
/// out, only what follows the last carriage return (a progress line redrawn in place).
fn drawn_lines(shown: &str) -> Vec<String> {
    let mut plain = String::new();
    let mut chars = shown.chars().peekable();
    while let Some(c) = chars.next() {
        if c == '\x1b' && chars.peek() == Some(&'[') {
            chars.next();
            while chars.next().is_some_and(|p| p.is_ascii_digit() || p == ';' || p == '?') {}
            continue;
        }
        plain.push(c);
    }
    plain.lines().map(|l| l.rsplit('\r').next().unwrap_or("").to_string()).collect()
}

/// Prose fits an 80-column terminal too: the sim reset summary, doctor's findings and
/// fixes, the final message are broken between words, never folded by the terminal in the
/// middle of one (lines of 112 and 224 columns before). While doctor works, a line moves
/// (2 to 4 s blank before), and it is gone when the report comes.
#[test]
fn prose_fits_an_80_column_terminal_and_doctor_is_never_blank() {
    let sim = Sim::new();
    // Node 13 is absent: each of its waits is a short timeout, not the tests' generous one.
    let doctor_13 = ["--timeout", "200ms", "doctor", "13"];
    let read_13 = ["--timeout", "200ms", "sdo", "read", "13", "1000"];
    for args in [&["sim", "reset", "--profile", "instant", "--fault", "5:drop"][..], &doctor_13, &read_13] {
        let (_, shown) = on_a_terminal_raw(&sim, 80, args);
        for line in drawn_lines(&shown) {
            assert!(line.chars().count() <= 80, "{args:?}: {} columns: {line:?}\n{shown}", line.chars().count());
        }
        assert!(screen(&shown, 80).iter().any(|l| !l.trim().is_empty()), "{args:?}: nothing shown");
    }
    let (code, shown) = on_a_terminal_raw(&sim, 80, &doctor_13);
    assert_eq!(code, 6, "{shown}");
    assert!(shown.contains("doctor: looking at node 13"), "{shown:?}");
    let left = screen(&shown, 80);
    assert!(!left.iter().any(|l| l.contains("looking at node 13")), "{left:#?}");
    // A pipe keeps every line whole, for grep.
    let piped = sim.run(&doctor_13);
    assert!(piped.stdout.lines().any(|l| l.chars().count() > 80), "{}", piped.stdout);
}

/// `firmware download` on a terminal tells each step as it is done (the erase and the boot
/// showed nothing before, the steps came only at the end), its byte bar fits 80 columns
/// (83 before), and nothing of the progress is left when the report comes.
#[test]
fn a_firmware_download_shows_its_steps_as_they_happen() {
    let sim = Sim::new();
    // In real time: the erase takes its 2.5 s, as on a device.
    sim.run(&["sim", "reset", "--bootloader", "9"]).ok();
    let image = sim.path("app.bin");
    std::fs::write(&image, (0..20_000u32).map(|i| i as u8).collect::<Vec<u8>>()).unwrap();
    let (code, shown) = on_a_terminal_raw(&sim, 80, &["firmware", "download", "9", image.to_str().unwrap()]);
    assert_eq!(code, 0, "{shown}");
    // Steps a few ms apart come faster than a terminal is redrawn (20 times a second):
    // the long waits, the erase and the transfer, are what must show.
    let before_report = &shown[..shown.find("node 9, program 1:").expect("the report")];
    for step in ["node 9: erasing (", "0x1F50:1 ["] {
        assert!(before_report.contains(step), "{step:?} not shown while it happened: {shown:?}");
    }
    for line in drawn_lines(&shown) {
        assert!(line.chars().count() <= 80, "{} columns: {line:?}", line.chars().count());
    }
    let left = screen(&shown, 80);
    assert!(!left.iter().any(|l| l.starts_with("node 9: ") || l.contains("0x1F50:1 [")), "{left:#?}");
    assert!(left.iter().any(|l| l.contains("it runs the image")), "{left:#?}");
}

/// Candidates fish would be given for `words`.
fn complete(sim: &Sim, words: &[&str]) -> Vec<String> {
    let mut c = std::process::Command::new(common::canctl_bin());
    c.env("XDG_CONFIG_HOME", sim.path("")).env("XDG_CACHE_HOME", sim.path("")).env_remove("CANCTL_BUS");
    c.env("COMPLETE", "fish").arg("--").arg("canctl").args(words);
    let run = common::finish(c.output().unwrap()).ok();
    run.stdout.lines().map(|l| l.split('\t').next().unwrap_or("").to_string()).collect()
}

/// `--format junit` is offered (help, completion) by the commands that write it, and only
/// by them; the others still refuse it with the reason.
#[test]
fn junit_is_offered_only_where_it_works() {
    let sim = Sim::new();
    for command in [&["health"][..], &["network", "check"]] {
        let help = sim.run(&[command, &["--help"]].concat()).ok();
        assert!(help.stdout.contains("junit"), "{command:?}: {}", help.stdout);
        let offered = complete(&sim, &[command, &["--format", ""]].concat());
        assert!(offered.contains(&"junit".to_string()), "{command:?}: {offered:?}");
    }
    for command in [&["scan"][..], &["sdo", "read"], &["network", "apply"], &["config", "diff"]] {
        let help = sim.run(&[command, &["--help"]].concat()).ok();
        assert!(!help.stdout.contains("junit"), "{command:?}: {}", help.stdout);
        let offered = complete(&sim, &[command, &["--format", ""]].concat());
        assert_eq!(offered, ["human", "json", "csv"], "{command:?}");
    }
    reset(&sim, "instant");
    let run = sim.run(&["scan", "--format", "junit"]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("--format junit is for commands that check things"), "{}", run.stderr);
    for args in [&["health", "--format", "junit"][..], &["--format", "junit", "health"]] {
        let run = sim.run(args).ok();
        assert!(run.stdout.starts_with("<?xml"), "{args:?}: {}", run.stdout);
    }
}

/// `config diff` of a DCF made for another device warns as `config apply` refuses; an
/// apply with nothing to do says so instead of drawing an empty table.
#[test]
fn config_diff_warns_of_another_device_and_apply_says_nothing_to_change() {
    let sim = Sim::new();
    reset(&sim, "instant");
    let sensor = sim.path("sensor.dcf");
    let sensor = sensor.to_str().unwrap();
    sim.run(&["config", "dump", "5", "--out", sensor]).ok();

    let diff = sim.run(&["config", "diff", "10", sensor]).ok();
    assert!(
        diff.stderr.contains("is for another device (vendor-ID 0x00000444 on node 10, 0x00000040 in the file"),
        "{}",
        diff.stderr
    );
    let json = sim.run(&["config", "diff", "10", sensor, "--format", "json"]).ok().json();
    assert_eq!(json["other_device"].as_array().map(Vec::len), Some(2), "{json}");
    let same = sim.run(&["config", "diff", "5", sensor]).ok();
    assert!(!same.stderr.contains("another device"), "{}", same.stderr);

    let apply = sim.run(&["config", "apply", "5", sensor]).ok();
    assert_eq!(apply.stdout.trim(), format!("nothing to change: node 5 already matches {sensor}"));
    let csv = sim.run(&["config", "apply", "5", sensor, "--format", "csv"]).ok();
    assert_eq!(csv.stdout, "object,name,old,new,result\n");
}

/// `lss set-id --node 0` on an EPOS2 reached directly writes its object 0x2000 and says
/// what makes it count: a store and a power cycle.
#[test]
fn epos2_set_id_says_a_store_and_a_power_cycle_are_needed() {
    let sim = Sim::new();
    reset(&sim, "instant");
    let epos2 = common::DeviceSide::start(&sim, "--epos2-rs232", &[]);
    let run = epos2.run(&["lss", "set-id", "3", "--node", "0"]).ok();
    assert!(run.stdout.contains("lss store --node 0") && run.stdout.contains("power cycle"), "{}", run.stdout);
}

/// Suggestions come from what the node has: `stream-pdo --tpdo 2` on a node without TPDO2
/// says so (not "did you mean 0x1801:2"); an object the node lacks is answered with
/// objects it has; a word of a name finds it; completion offers the node's profile only.
#[test]
fn suggestions_come_from_what_the_node_has() {
    let sim = Sim::new();
    reset(&sim, "instant");
    let run = sim.run(&["stream-pdo", "5", "--tpdo", "2", "--count", "1"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("node 5 has no TPDO2"), "{}", run.stderr);
    assert!(!run.stderr.contains("0x1801:"), "{}", run.stderr);

    // Node 5 has no 0x1801 at all: none of its sub-indexes is offered, and whatever is
    // offered, node 5 has.
    let run = sim.run(&["sdo", "read", "5", "1801:1"]);
    assert_eq!(run.code, 4, "{}", run.stderr);
    let offered = run.stderr.split("did you mean ").nth(1).unwrap_or_default();
    assert!(!offered.contains("0x1801:"), "{}", run.stderr);
    let run = sim.run(&["sdo", "read", "5", "1081:0"]);
    let offered = run.stderr.split("did you mean ").nth(1).unwrap_or_default();
    for addr in offered.split(", ").filter_map(|o| o.split(' ').next()) {
        sim.run(&["sdo", "read", "5", addr]).ok();
    }
    assert!(offered.contains("0x1018:0"), "{}", run.stderr);

    let run = sim.run(&["sdo", "read", "5", "heartbeat"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("did you mean 'Producer heartbeat time' (0x1017:0)"), "{}", run.stderr);

    // After a scan, node 5 (a DS406 sensor) is not offered a drive's objects, node 1 is.
    sim.run(&["scan"]).ok();
    let bus = sim.bus();
    let sensor = complete(&sim, &["--bus", &bus, "sdo", "read", "5", "0x60"]);
    assert!(sensor.contains(&"0x6004:0".to_string()) && !sensor.contains(&"0x6041:0".to_string()), "{sensor:?}");
    let drive = complete(&sim, &["--bus", &bus, "sdo", "read", "1", "0x60"]);
    assert!(drive.contains(&"0x6041:0".to_string()) && !drive.contains(&"0x6004:0".to_string()), "{drive:?}");
}

/// Slow LSS work shows its progress on a terminal (fastscan was blank for 13 s on slow
/// devices, assign for 12 s), request by request; not with -q, not in a pipe.
#[test]
fn lss_work_shows_progress_on_a_terminal_only() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--profile", "instant", "--unconfigured", "1"]).ok();
    let (code, shown) = on_a_terminal_raw(&sim, 80, &["lss", "fastscan"]);
    assert_eq!(code, 0, "{shown}");
    assert!(shown.contains("fastscan [") && shown.contains("/133"), "{shown:?}");
    let (code, shown) = on_a_terminal_raw(&sim, 80, &["-q", "lss", "fastscan"]);
    assert_eq!(code, 0, "{shown}");
    assert!(!shown.contains("fastscan ["), "{shown:?}");
    let piped = sim.run(&["lss", "fastscan"]).ok();
    assert!(!piped.stderr.contains("fastscan ["), "{}", piped.stderr);

    let (code, shown) = on_a_terminal_raw(&sim, 80, &["lss", "assign", "--start", "20"]);
    assert_eq!(code, 0, "{shown}");
    assert!(shown.contains("fastscan for device 1 ["), "{shown:?}");
    let left = screen(&shown, 80);
    assert!(!left.iter().any(|l| l.contains("fastscan for")), "{left:#?}");
    assert!(left.iter().any(|l| l.contains("-> node 20")), "{left:#?}");
}

/// A large SDO upload counts its bytes on a terminal (64 KiB took 2 s with nothing shown),
/// and the count is gone when the result is printed; not with -q.
#[test]
fn a_large_upload_shows_its_bytes_on_a_terminal() {
    let sim = Sim::new();
    reset(&sim, "instant");
    let out = sim.path("program.bin");
    let args = ["sdo", "read", "1", "1F50:1", "--type", "d", "--out", out.to_str().unwrap()];
    let (code, shown) = on_a_terminal_raw(&sim, 80, &args);
    assert_eq!(code, 0, "{shown}");
    assert!(shown.contains("node 1: reading 0x1F50:1: "), "{shown:?}");
    let left = screen(&shown, 80);
    assert!(!left.iter().any(|l| l.contains("reading 0x1F50")), "{left:#?}");
    assert_eq!(std::fs::metadata(&out).unwrap().len(), 65536);
    let (_, quiet) = on_a_terminal_raw(&sim, 80, &[&["-q"][..], &args].concat());
    assert!(!quiet.contains("reading 0x1F50"), "{quiet:?}");
}

/// `config apply` says where it stands on a terminal as it reads and writes (3.5 s blank
/// before), and the line is gone when the report is printed.
#[test]
fn config_apply_shows_its_transfers_on_a_terminal() {
    let sim = Sim::new();
    reset(&sim, "instant");
    let dcf = sim.path("sensor.dcf");
    sim.run(&["config", "dump", "5", "--out", dcf.to_str().unwrap()]).ok();
    let (code, shown) = on_a_terminal_raw(&sim, 80, &["config", "apply", "5", dcf.to_str().unwrap()]);
    assert_eq!(code, 0, "{shown}");
    assert!(shown.contains("node 5: applying ") && shown.contains(" read(s), 0 write(s)"), "{shown:?}");
    let left = screen(&shown, 80);
    assert!(!left.iter().any(|l| l.contains("applying")), "{left:#?}");
    assert!(left.iter().any(|l| l.starts_with("nothing to change")), "{left:#?}");
    let (_, quiet) = on_a_terminal_raw(&sim, 80, &["-q", "config", "apply", "5", dcf.to_str().unwrap()]);
    assert!(!quiet.contains("applying"), "{quiet:?}");
}

/// An slcan adapter at another bit rate than the bus hears nothing: the scan asks the
/// adapter's status flags (frames nobody acknowledged) and says so, exit 5, instead of
/// "0 node(s)" and exit 0. At the right rate the same adapter finds the nodes.
#[cfg(unix)]
#[test]
fn an_slcan_adapter_at_the_wrong_bit_rate_is_not_an_empty_bus() {
    let sim = Sim::new();
    reset(&sim, "instant");
    let adapter = common::DeviceSide::start(&sim, "--slcan", &[]);
    let wrong = format!("slcan:{}@250k", adapter.pty);
    let mut c = std::process::Command::new(common::canctl_bin());
    c.env("XDG_CONFIG_HOME", sim.path("")).env("XDG_CACHE_HOME", sim.path("")).env_remove("CANCTL_BUS");
    c.args(["--bus", &wrong, "scan"]).stdin(std::process::Stdio::null());
    let run = common::finish(c.output().unwrap());
    assert_eq!(run.code, 5, "{}\n{}", run.stdout, run.stderr);
    assert!(run.stderr.contains("the adapter reports") && run.stderr.contains("bit rate"), "{}", run.stderr);
    let right = adapter.run(&["scan"]).ok();
    assert!(right.stderr.contains("4 node(s)"), "{}", right.stderr);
}

/// A file that is not there is said once, with the system's reason once: the message
/// came three times over ("cannot read nofile.bin: ... (os error 2): cannot read
/// nofile.bin: ... (os error 2): ... (os error 2)").
#[test]
fn a_missing_input_file_is_said_once() {
    let sim = Sim::new();
    for args in [
        &["sdo", "write", "1", "1F50:1", "@nofile.bin", "--type", "d"][..],
        &["firmware", "download", "1", "nofile.bin"],
    ] {
        let run = sim.run(args);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        assert_eq!(
            run.stderr.trim(),
            "canctl: cannot read nofile.bin: No such file or directory (os error 2)",
            "{args:?}"
        );
    }
}

/// `--out` into a folder that exists but takes no new files (/proc): not "there is no
/// folder /proc".
#[cfg(target_os = "linux")]
#[test]
fn out_where_no_file_can_be_made_says_why() {
    let sim = Sim::new();
    let run = sim.run(&["sdo", "read", "10", "1008", "--out", "/proc/version"]);
    assert_eq!(run.code, 7, "{}", run.stderr);
    assert!(!run.stderr.contains("there is no folder"), "{}", run.stderr);
    assert!(run.stderr.contains("cannot write /proc/version: the folder /proc takes no new files"), "{}", run.stderr);
}
