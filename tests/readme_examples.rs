//! Every README block that shows output is the program's real output: each `$ canctl ...`
//! line is run on a fresh sim network (one per block, commands in order), and what it
//! prints (stdout and stderr, as a terminal shows them) must be the lines below it.
//!
//! Only what honestly varies is let through: a clock time `hh:mm:ss.mmm`, and `…` in the
//! README, which stands for any text within that line (a duration, a pty path).

mod common;
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

/// Whether `actual` is what `shown` shows, `…` standing for any text.
fn matches(shown: &str, actual: &str) -> bool {
    let (shown, actual) = (normalize(shown.trim_end()), normalize(actual.trim_end()));
    let mut parts = shown.split('…');
    let first = parts.next().unwrap_or("");
    let Some(mut rest) = actual.strip_prefix(first) else { return false };
    let parts: Vec<&str> = parts.collect();
    for (k, part) in parts.iter().enumerate() {
        if k + 1 == parts.len() {
            return rest.ends_with(part);
        }
        match rest.find(part) {
            Some(at) => rest = &rest[at + part.len()..],
            None => return false,
        }
    }
    rest.is_empty()
}

#[test]
fn the_readme_shows_what_canctl_prints() {
    let readme = include_str!("../README.md");
    let found = examples(readme);
    assert!(found.len() >= 3, "README blocks with `$ canctl` lines: {}", found.len());
    let path = format!("{}:{}", canctl_bin().parent().unwrap().display(), std::env::var("PATH").unwrap_or_default());
    let mut wrong = Vec::new();
    for ex in &found {
        let dir = tempfile::tempdir().unwrap();
        for (cmd, shown) in &ex.commands {
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

#[test]
fn wildcards_and_times() {
    assert!(matches("12:00:01.123  5  TPDO1", "08:46:15.322  5  TPDO1"));
    assert!(matches("done in … ms", "done in 42 ms"));
    assert!(matches("/dev/pts/…", "/dev/pts/7"));
    assert!(!matches("done in … ms", "done in 42 s"));
    assert!(!matches("251", "252"));
    assert!(!matches("a…b…c", "a-c-b"));
}
