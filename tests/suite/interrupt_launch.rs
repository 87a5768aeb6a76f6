//! SIGTERM reaches canctl the same way however it was launched. Supervisors (a service
//! manager, a CI runner cancelling a job, a Python or Go supervisor) start canctl through a
//! parent of their own and stop it with SIGTERM, at any moment: also while the bus is being
//! opened, before the command has taken its first step. The request to stop is caught from
//! the start of the program, so the command still reports and exits 130.
//!
//! The parent here is the one of the field report: a non-interactive bash script runs the
//! command as a background job (so SIGINT arrives ignored), through a Python wrapper that
//! puts SIGINT back to its default and execs canctl. The point of the signal is exact,
//! without timing: [`common::interrupted`] with `o1:TERM` runs the test build of canctl
//! (tests/seams/canctl.rs), which sends it to itself right after the bus was opened.

#![cfg(unix)]

use crate::common;

use std::process::Command;

const PYTHON_PARENT: &str = "import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); \
                             os.execvp(sys.argv[1], sys.argv[1:])";

/// `c`, run as a background job of a non-interactive bash script through the Python parent.
fn through_a_supervisor(c: &Command) -> Command {
    let mut script = Command::new("bash");
    // `wait` gives the job's status as a shell sees it: 128+N when signal N ended it.
    script.arg("-c").arg("python3 -c \"$0\" \"$@\" & wait $!").arg(PYTHON_PARENT).arg(c.get_program());
    script.args(c.get_args());
    for (k, v) in c.get_envs() {
        match v {
            Some(v) => script.env(k, v),
            None => script.env_remove(k),
        };
    }
    script.stdin(std::process::Stdio::null());
    script
}

#[test]
fn sigterm_while_the_bus_opens_is_reported_however_canctl_was_launched() {
    let sim = common::Sim::new();
    let dcf = sim.path("node10.dcf");
    sim.run(&["config", "dump", "10", "--out", dcf.to_str().unwrap()]).ok();
    let text = std::fs::read_to_string(&dcf).unwrap();
    // Node 10's heartbeat: the one value the apply would write.
    let at = text.find("[1017]").unwrap();
    let value = at + text[at..].find("ParameterValue=").unwrap();
    let end = value + text[value..].find('\n').unwrap();
    let changed = format!("{}ParameterValue=250{}", &text[..value], &text[end..]);
    std::fs::write(&dcf, changed).unwrap();
    let before = sim.run(&["sdo", "read", "10", "0x1017:0", "--type", "u16"]).ok().stdout;

    let direct = common::interrupted(sim.command(&["config", "apply", "10", dcf.to_str().unwrap()]), "o1:TERM");
    for (how, mut c) in [("supervised", through_a_supervisor(&direct)), ("direct", direct)] {
        let run = common::finish(c.output().unwrap());
        assert_eq!(run.code, 130, "{how}: {}", run.stderr);
        assert!(run.stderr.contains("node 10 is as it was"), "{how}: {}", run.stderr);
        assert!(run.stderr.ends_with("canctl: interrupted\n"), "{how}: {}", run.stderr);
        let after = sim.run(&["sdo", "read", "10", "0x1017:0", "--type", "u16"]).ok().stdout;
        assert_eq!(after, before, "{how}: a write went out after the stop");
    }
}

/// The served simulator has no step to stop at: SIGTERM (or Ctrl-C) ends it with the exit
/// code of an interruption, also while it waits on its pseudo-terminal (the signal, now
/// caught, cuts that wait short without it being a failure of the pty).
#[test]
fn a_served_sim_ends_on_sigterm_with_exit_130() {
    use nix::sys::signal::{kill, Signal};
    use nix::unistd::Pid;
    use std::io::BufRead;
    for framing in ["--slcan", "--epos2-usb"] {
        let sim = common::Sim::new();
        let mut child = sim.command(&["sim", framing]).stdout(std::process::Stdio::piped()).spawn().unwrap();
        // Serving once it has printed its pty.
        let mut line = String::new();
        std::io::BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
        assert!(line.starts_with("/dev/"), "{line}");
        kill(Pid::from_raw(child.id() as i32), Signal::SIGTERM).unwrap();
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(130), "{framing}: {stderr}");
        assert!(!stderr.contains("pty poll"), "{framing}: {stderr}");
    }
}
