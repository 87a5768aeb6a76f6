//! The library's `tracing` events on stderr, in canctl's voice: the frame and byte traces
//! exactly as candump prints frames (no time, no level), warnings as `canctl: warning: ...`.
//! `-q` shows errors only, the default warnings, `-v` the frame trace, `-vv` everything.

use crate::bus::trace::{BYTES, FRAMES};
use std::fmt;
use tracing::field::{Field, Visit};
use tracing::{Event, Level, Subscriber};
use tracing_subscriber::filter::LevelFilter;
use tracing_subscriber::fmt::format::Writer;
use tracing_subscriber::fmt::{FmtContext, FormatEvent, FormatFields, MakeWriter};
use tracing_subscriber::registry::LookupSpan;

/// The most detailed events shown for these flags.
pub fn level(verbose: u8, quiet: bool) -> LevelFilter {
    match (quiet, verbose) {
        (true, _) => LevelFilter::ERROR,
        (false, 0) => LevelFilter::WARN,
        (false, 1) => LevelFilter::DEBUG,
        (false, _) => LevelFilter::TRACE,
    }
}

/// Render events on stderr from now on (once per process; a second call does nothing).
pub fn install(verbose: u8, quiet: bool) {
    let _ = subscriber(level(verbose, quiet), std::io::stderr).try_init();
}

fn subscriber<W>(
    level: LevelFilter,
    writer: W,
) -> tracing_subscriber::fmt::SubscriberBuilder<
    tracing_subscriber::fmt::format::DefaultFields,
    CanctlFormat,
    LevelFilter,
    W,
>
where
    W: for<'w> MakeWriter<'w> + Send + Sync + 'static,
{
    // A stderr nobody reads any more loses the diagnostics; reporting that on stderr would
    // panic and end a command that was going well.
    tracing_subscriber::fmt()
        .with_max_level(level)
        .log_internal_errors(false)
        .event_format(CanctlFormat)
        .with_writer(writer)
}

/// One line per event: traces as they are, everything else prefixed with `canctl:`.
pub(crate) struct CanctlFormat;

impl<S, N> FormatEvent<S, N> for CanctlFormat
where
    S: Subscriber + for<'a> LookupSpan<'a>,
    N: for<'a> FormatFields<'a> + 'static,
{
    fn format_event(&self, _ctx: &FmtContext<'_, S, N>, mut w: Writer<'_>, event: &Event<'_>) -> fmt::Result {
        let meta = event.metadata();
        let mut fields = Fields::default();
        event.record(&mut fields);
        if meta.target() == FRAMES || meta.target() == BYTES {
            return writeln!(w, "{}", fields.message);
        }
        // Messages carry what devices and files say: nothing in them may drive the terminal.
        let message = super::text::terminal_safe_lines(&fields.message);
        match *meta.level() {
            Level::ERROR => write!(w, "canctl: error: {message}")?,
            Level::WARN => write!(w, "canctl: warning: {message}")?,
            Level::INFO => write!(w, "canctl: {message}")?,
            // Detail for whoever reads -vv: where it came from, and the event's own fields.
            _ => {
                let target = meta.target().strip_prefix("canctl::").unwrap_or(meta.target());
                write!(w, "canctl: {target}: {message}")?;
                for (name, value) in &fields.rest {
                    write!(w, " {name}={value}")?;
                }
            }
        }
        writeln!(w)
    }
}

#[derive(Default)]
struct Fields {
    message: String,
    rest: Vec<(&'static str, String)>,
}

impl Visit for Fields {
    fn record_str(&mut self, field: &Field, value: &str) {
        if field.name() == "message" {
            self.message = value.to_string();
        } else {
            self.rest.push((field.name(), value.to_string()));
        }
    }

    fn record_debug(&mut self, field: &Field, value: &dyn fmt::Debug) {
        if field.name() == "message" {
            self.message = format!("{value:?}");
        } else {
            self.rest.push((field.name(), format!("{value:?}")));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::trace::{self, Dir};
    use crate::frame::Frame;
    use std::sync::{Arc, Mutex};

    #[derive(Clone, Default)]
    struct Captured(Arc<Mutex<Vec<u8>>>);

    impl std::io::Write for Captured {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.0.lock().unwrap().extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    /// What stderr shows for the same events at each setting of -v/-q.
    fn rendered(verbose: u8, quiet: bool) -> String {
        let out = Captured::default();
        let writer = out.clone();
        let sub = subscriber(level(verbose, quiet), move || writer.clone()).finish();
        tracing::subscriber::with_default(sub, || {
            trace::frame("vcan0", Dir::Tx, &Frame::new(0x605, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]));
            trace::frame("can0", Dir::Rx, &Frame::remote(0x705, 1));
            trace::bytes("epos2-rs232:/dev/ttyS0", "<", &[0x10, 0x01, 0x02]);
            tracing::warn!(target: "canctl::socketcan", iface = "can0", "can0: error passive");
            tracing::trace!(target: "canctl::sdo", node = 5, "node 5: SDO transfer of 0x1000:0 starts");
            tracing::error!(target: "canctl::x", "broken");
        });
        let text = String::from_utf8(out.0.lock().unwrap().clone()).unwrap();
        text
    }

    #[test]
    fn the_default_shows_warnings_and_errors() {
        assert_eq!(rendered(0, false), "canctl: warning: can0: error passive\ncanctl: error: broken\n");
    }

    #[test]
    fn quiet_shows_errors_only() {
        assert_eq!(rendered(0, true), "canctl: error: broken\n");
        assert_eq!(rendered(2, true), "canctl: error: broken\n");
    }

    /// The trace lines are candump's, byte for byte: what tests and the README rely on.
    #[test]
    fn one_v_adds_the_frame_trace_as_candump_prints_it() {
        assert_eq!(
            rendered(1, false),
            "  vcan0  605   [8]  40 00 10 00 00 00 00 00\n  can0  705   [1]  remote request\n  \
             epos2-rs232:/dev/ttyS0 < 10 01 02\ncanctl: warning: can0: error passive\ncanctl: error: broken\n"
        );
    }

    #[test]
    fn two_v_add_what_procedures_do_with_their_fields() {
        let text = rendered(2, false);
        assert!(text.contains("canctl: sdo: node 5: SDO transfer of 0x1000:0 starts node=5\n"), "{text}");
        assert!(text.starts_with("  vcan0  605   [8]  40 00 10 00 00 00 00 00\n"), "{text}");
    }
}
