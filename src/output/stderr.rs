//! Everything canctl writes on stderr goes through here: diagnostics, notes and the message
//! a command ends with. `eprintln!` panics (exit 101) when stderr cannot be written, as when
//! its reader went away (`canctl health 2>&1 | head -1`); these say what became of the
//! text instead, and the caller decides.

use std::io::Write;

/// `text` on `out`, a line break added when it has none, flushed (stdout's results too).
pub(crate) fn write_line(out: &mut impl Write, text: &str) -> std::io::Result<()> {
    out.write_all(text.as_bytes())?;
    if !text.ends_with('\n') {
        out.write_all(b"\n")?;
    }
    out.flush()
}

/// `text` on stderr, a line break added when it has none.
pub fn write(text: &str) -> std::io::Result<()> {
    write_line(&mut std::io::stderr().lock(), text)
}

/// A diagnostic on stderr, dropped when it cannot be written: a note nobody can read is no
/// reason to leave a procedure half done. The command goes on to its end, and its result
/// (stdout, the exit code) is what it was.
pub fn say(text: &str) {
    let _ = write(text);
}

/// The exit code once the message a command ended with (`code`) is said: 0 when its reader
/// went away, as when stdout's did (a closed pipe ends canctl quietly); else `code`, the
/// message written or not.
pub fn last_words(text: &str, code: i32) -> i32 {
    match write(text) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => 0,
        _ => code,
    }
}
