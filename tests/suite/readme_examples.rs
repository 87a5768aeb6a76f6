//! Every README block that shows output is the program's real output: each `$ canctl ...`
//! line is run on a fresh sim network (one per block, commands in order), and what it
//! prints (stdout and stderr, as a terminal shows them) must be the lines below it.
//!
//! Only what honestly varies is let through: a clock time `hh:mm:ss.mmm`, and `…` in the
//! README, which stands for one number (a duration, a pid, a count of ms) or one path (a
//! pty, a state file), never for a column, a name or a meaning ([`varies`]).

use crate::common;
use common::{canctl_bin, finish};
use std::process::Command;

struct Example {
    /// Line number of the block's first line in README.md, for messages.
    line: usize,
    /// Each command with the lines it is shown printing.
    commands: Vec<(String, Vec<String>)>,
}

fn examples(readme: &str) -> Vec<Example> {
    let mut out = Vec::new();
    let mut block: Option<Example> = None;
    for (i, line) in readme.lines().enumerate() {
        if line.starts_with("```") {
            match block.take() {
                Some(b) if !b.commands.is_empty() => out.push(b),
                Some(_) => {}
                None => block = Some(Example { line: i + 2, commands: Vec::new() }),
            }
            continue;
        }
        let Some(b) = block.as_mut() else { continue };
        if let Some(cmd) = line.strip_prefix("$ ") {
            b.commands.push((cmd.to_string(), Vec::new()));
        } else if let Some((_, shown)) = b.commands.last_mut() {
            shown.push(line.to_string());
        }
    }
    out
}

/// Clock times read the same whenever they were printed.
fn normalize(line: &str) -> String {
    let b = line.as_bytes();
    let mut out = String::with_capacity(line.len());
    let mut i = 0;
    let digits = |r: std::ops::Range<usize>| r.clone().all(|k| b.get(k).is_some_and(u8::is_ascii_digit));
    while i < b.len() {
        let is_time = digits(i..i + 2)
            && b.get(i + 2) == Some(&b':')
            && digits(i + 3..i + 5)
            && b.get(i + 5) == Some(&b':')
            && digits(i + 6..i + 8)
            && b.get(i + 8) == Some(&b'.')
            && digits(i + 9..i + 12);
        if is_time {
            out.push_str("hh:mm:ss.mmm");
            i += 12;
        } else {
            let c = line[i..].chars().next().unwrap();
            out.push(c);
            i += c.len_utf8();
        }
    }
    out
}

/// What `…` may stand for: one word that honestly varies from run to run, never a column
/// or a meaning. A number (a duration's, a pid, a count of ms: digits with at most one
/// `.`), or a path (no blank, at least one `/`). Nothing else: no blank, no empty text.
fn varies(text: &str) -> bool {
    let number = !text.is_empty()
        && text.chars().all(|c| c.is_ascii_digit() || c == '.')
        && text.chars().filter(|c| *c == '.').count() <= 1
        && text.chars().any(|c| c.is_ascii_digit());
    let path = text.contains('/') && !text.chars().any(char::is_whitespace);
    number || path
}

/// Whether `actual` is what `shown` shows, each `…` standing for what [`varies`] allows.
fn matches(shown: &str, actual: &str) -> bool {
    let (shown, actual) = (normalize(shown.trim_end()), normalize(actual.trim_end()));
    let parts: Vec<&str> = shown.split('…').collect();
    let Some(rest) = actual.strip_prefix(parts[0]) else { return false };
    fill(&parts[1..], rest)
}

/// `rest` is a stand-in followed by `parts[0]`, then again for each further part.
fn fill(parts: &[&str], rest: &str) -> bool {
    let Some((part, more)) = parts.split_first() else { return rest.is_empty() };
    // Each place the next literal text could start, the stand-in being one blank-free word.
    let word = rest.find(char::is_whitespace).unwrap_or(rest.len());
    (1..=word)
        .filter(|end| rest.is_char_boundary(*end))
        .any(|end| varies(&rest[..end]) && rest[end..].strip_prefix(part).is_some_and(|after| fill(more, after)))
}

#[test]
fn the_readme_shows_what_canctl_prints() {
    let readme = include_str!("../../README.md");
    let found = examples(readme);
    assert!(found.len() >= 3, "README blocks with `$ canctl` lines: {}", found.len());
    let path = format!("{}:{}", canctl_bin().parent().unwrap().display(), std::env::var("PATH").unwrap_or_default());
    let mut wrong = Vec::new();
    for ex in &found {
        let dir = tempfile::tempdir().unwrap();
        for (cmd, shown) in &ex.commands {
            if MACHINE_DEPENDENT.contains(&cmd.as_str()) {
                continue;
            }
            let mut c = Command::new("bash");
            c.arg("-c").arg(format!("{cmd} 2>&1")).env("PATH", &path).current_dir(dir.path());
            c.env_remove("CANCTL_BUS").env("COLUMNS", "100");
            for var in ["XDG_CONFIG_HOME", "XDG_CACHE_HOME", "XDG_STATE_HOME"] {
                c.env(var, dir.path());
            }
            let run = finish(c.output().unwrap());
            let actual: Vec<&str> = run.stdout.lines().collect();
            let same = actual.len() == shown.len() && shown.iter().zip(&actual).all(|(s, a)| matches(s, a));
            if !same {
                wrong.push(format!(
                    "README.md:{}: `$ {cmd}` (exit {})\n  shown:\n    {}\n  printed:\n    {}",
                    ex.line,
                    run.code,
                    shown.join("\n    "),
                    actual.join("\n    ")
                ));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n\n"));
}

/// Commands whose output depends on the machine (its CAN interfaces, serial ports, host
/// name): their blocks are checked for their shape by a test of their own.
const MACHINE_DEPENDENT: [&str; 1] = ["canctl buses"];

/// The lines a README block shows for `cmd`.
fn shown_for(cmd: &str) -> Vec<String> {
    let found = examples(include_str!("../../README.md"));
    let mut blocks = found.into_iter().flat_map(|ex| ex.commands).filter(|(c, _)| c == cmd);
    let (_, shown) = blocks.next().unwrap_or_else(|| panic!("README shows no `$ {cmd}` block"));
    shown
}

/// `canctl buses` output cut into its parts: the header's and each row's cells (cut at runs
/// of two blanks or more), and the notes (lines that are no table row).
fn buses_parts(lines: &[String]) -> (Vec<String>, Vec<Vec<String>>, Vec<String>) {
    let cells = |l: &str| l.split("  ").map(str::trim).filter(|c| !c.is_empty()).map(String::from).collect();
    let header = lines.first().map(|l| cells(l)).unwrap_or_default();
    let rows = lines.iter().skip(1).filter(|l| l.starts_with(' ')).map(|l| cells(l)).collect();
    let notes = lines.iter().skip(1).filter(|l| !l.starts_with(' ')).cloned().collect();
    (header, rows, notes)
}

/// README's `canctl buses` block has the shape of what canctl prints, checked against a real
/// run with `canctl sim --socketcand` beaconing to a UDP port of the test's own
/// (CANCTL_BEACON_PORT): the same header; one socketcand row naming the sim's bus and a
/// host; every other row of a kind canctl prints; every note one canctl prints.
#[test]
fn the_readme_buses_block_has_the_shape_canctl_prints() {
    use std::io::{BufRead, BufReader};
    let port = std::net::UdpSocket::bind("0.0.0.0:0").unwrap().local_addr().unwrap().port().to_string();
    let sim = common::Sim::new();
    let mut server = sim.command(&["sim", "--socketcand", "127.0.0.1:0"]);
    server.env("CANCTL_BEACON_PORT", &port).stdout(std::process::Stdio::piped()).stderr(std::process::Stdio::null());
    let mut server = server.spawn().unwrap();
    let mut bus = String::new();
    BufReader::new(server.stdout.take().unwrap()).read_line(&mut bus).unwrap();
    let mut c = Command::new("bash");
    c.arg("-c").arg("canctl buses 2>&1").env("COLUMNS", "100").env_remove("CANCTL_BUS");
    c.env(
        "PATH",
        format!("{}:{}", canctl_bin().parent().unwrap().display(), std::env::var("PATH").unwrap_or_default()),
    );
    c.env("XDG_CONFIG_HOME", sim.path("")).env("XDG_CACHE_HOME", sim.path("")).env("CANCTL_BEACON_PORT", &port);
    let run = finish(c.output().unwrap());
    let _ = (server.kill(), server.wait());
    let actual: Vec<String> = run.stdout.lines().map(String::from).collect();

    let kinds = ["CAN interface", "slcan adapter", "EPOS2 (USB)", "socketcand"];
    let notes = ["other serial ports: ", "no socketcand beacon heard"];
    let sim_host = |row: &[String]| {
        row.get(2)
            .and_then(|w| w.strip_prefix("socketcand on "))
            .and_then(|w| w.strip_suffix(" (canctl sim)"))
            .is_some_and(|host| !host.is_empty() && !host.contains(' '))
    };
    for (what, lines, sim_bus) in
        [("README", shown_for("canctl buses"), "socketcand:127.0.0.1/sim"), ("canctl", actual, bus.trim())]
    {
        let (header, rows, said) = buses_parts(&lines);
        assert_eq!(header, ["--bus", "kind", "what"], "{what}: {lines:#?}");
        for row in &rows {
            assert!(row.len() == 3 && kinds.contains(&row[1].as_str()), "{what}: a row canctl does not print: {row:?}");
        }
        let servers: Vec<&Vec<String>> = rows.iter().filter(|r| r[1] == "socketcand").collect();
        assert!(
            servers.len() == 1 && servers[0][0] == sim_bus && sim_host(servers[0]),
            "{what}: not one row for the sim's server {sim_bus}: {lines:#?}"
        );
        for note in said {
            assert!(notes.iter().any(|n| note.starts_with(n)), "{what}: a line canctl does not print: {note:?}");
        }
    }
}

#[test]
fn wildcards_and_times() {
    assert!(matches("12:00:01.123  5  TPDO1", "08:46:15.322  5  TPDO1"));
    assert!(matches("done in … ms", "done in 42 ms"));
    assert!(matches("/dev/pts/…", "/dev/pts/7"));
    assert!(!matches("done in … ms", "done in 42 s"));
    assert!(!matches("251", "252"));
    assert!(!matches("a…b…c", "a-c-b"));
    assert!(!matches("sim network reset (…): profile", "sim network reset (/tmp/x y/../sim.json): profile"));
    assert!(matches("sim network reset (…): profile", "sim network reset (/tmp/.tmpAb/sim.json): profile"));
    assert!(matches("pid …, … ms", "pid 4711, 12.5 ms"));
    // Never a column, a name or a meaning.
    assert!(!matches(" #  code    meaning…entry", " #  code    meaning                     entry"));
    assert!(!matches(" 1  0x3220  …0x00003220", " 1  0x3220  DC link under-voltage  0x00003220"));
    assert!(!matches("code … found", "code 0x3220 found"), "a code is not a number that varies");
    assert!(!matches("… ms", " ms"), "never empty");
}

/// README's install recipe for the man pages works for a user who installed canctl as it
/// says (`cargo install`: the binary in ~/.cargo/bin, on PATH) and set no MANPATH: man-db
/// derives its search path from PATH (DIR/bin gives DIR/share/man), so the pages must go
/// where that finds them.
#[cfg(unix)]
#[test]
fn the_man_page_recipe_finds_the_pages() {
    if Command::new("man").arg("--version").output().is_err() {
        return common::skipped("no man command");
    }
    let readme = include_str!("../../README.md");
    let install = readme.split("\n## Install\n").nth(1).unwrap().split("\n## ").next().unwrap();
    let recipe = install.lines().find(|l| l.starts_with("canctl man --out")).expect("README installs the man pages");
    let recipe = recipe.split(" #").next().unwrap().trim();
    let home = tempfile::tempdir().unwrap();
    let bin = home.path().join(".cargo/bin");
    std::fs::create_dir_all(&bin).unwrap();
    std::os::unix::fs::symlink(canctl_bin(), bin.join("canctl")).unwrap();
    let path = format!("{}:/usr/bin:/bin", bin.display());
    let run = |cmd: &str| {
        let mut c = Command::new("bash");
        c.arg("-c").arg(cmd).env("HOME", home.path()).env("PATH", &path).env_remove("MANPATH");
        finish(c.output().unwrap())
    };
    assert_eq!(run(recipe).code, 0, "{recipe}");
    let found = run("man -w canctl-sdo-read");
    assert_eq!(found.code, 0, "`{recipe}`, then man finds no canctl-sdo-read: {}", found.stderr);
    assert!(found.stdout.starts_with(home.path().to_str().unwrap()), "{}", found.stdout);
}
