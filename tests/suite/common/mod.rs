//! Running the built `canctl` binary, each test on its own simulated network.

#![allow(dead_code)]

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

pub struct Sim {
    dir: tempfile::TempDir,
}

pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    pub fn ok(self) -> Run {
        assert_eq!(self.code, 0, "expected success\nstdout: {}\nstderr: {}", self.stdout, self.stderr);
        self
    }
    pub fn json(&self) -> serde_json::Value {
        serde_json::from_str(&self.stdout).unwrap_or_else(|e| panic!("not JSON ({e}): {}", self.stdout))
    }
}

impl Default for Sim {
    fn default() -> Sim {
        Sim::new()
    }
}

impl Sim {
    pub fn new() -> Sim {
        let dir = tempfile::tempdir().unwrap();
        generous_timeout(dir.path());
        Sim { dir }
    }

    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    pub fn bus(&self) -> String {
        format!("sim:{}", self.path("sim.json").display())
    }

    pub fn command(&self, args: &[&str]) -> Command {
        let mut c = Command::new(canctl_bin());
        // No settings file of the developer's may change what the tests see.
        c.env("XDG_CONFIG_HOME", self.dir.path()).env("XDG_CACHE_HOME", self.dir.path()).env_remove("CANCTL_BUS");
        c.arg("--bus").arg(self.bus()).args(args);
        c.stdin(Stdio::null());
        c
    }

    pub fn run(&self, args: &[&str]) -> Run {
        finish(self.command(args).output().unwrap())
    }
}

/// A settings file (in the XDG config home the tests give canctl) with an answer timeout
/// that only a missing answer exceeds: on a loaded machine, or in the emulated kernel-test
/// VM, devices answer later than canctl's 500 ms default allows. Tests about timeouts pass
/// their own `--timeout`, which wins over the file.
pub fn generous_timeout(config_home: &std::path::Path) {
    let dir = config_home.join("canctl");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("config.toml"), "timeout = \"5s\"\n").unwrap();
}

pub fn finish(out: Output) -> Run {
    let run = Run {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    };
    assert!(!run.stderr.contains("panicked"), "canctl panicked: {}", run.stderr);
    run
}

/// canctl without any bus.
pub fn bare(args: &[&str]) -> Run {
    let mut c = Command::new(canctl_bin());
    c.env("XDG_CONFIG_HOME", std::env::temp_dir().join("canctl-tests-no-config"))
        .env_remove("CANCTL_BUS")
        .args(args)
        .stdin(Stdio::null());
    finish(c.output().unwrap())
}

/// `canctl sim --epos2-rs232|--epos2-usb` on a sim network, killed when dropped.
pub struct DeviceSide {
    child: std::process::Child,
    pub pty: String,
    pub uri: String,
    config_home: PathBuf,
    _stdout: std::io::BufReader<std::process::ChildStdout>,
}

impl DeviceSide {
    pub fn start(sim: &Sim, framing: &str, extra: &[&str]) -> DeviceSide {
        use std::io::BufRead;
        let mut args = vec!["sim", framing];
        args.extend_from_slice(extra);
        let mut child = sim.command(&args).stdout(Stdio::piped()).stderr(Stdio::null()).spawn().unwrap();
        let mut stdout = std::io::BufReader::new(child.stdout.take().unwrap());
        let mut pty = String::new();
        stdout.read_line(&mut pty).unwrap();
        let pty = pty.trim().to_string();
        assert!(pty.starts_with("/dev/"), "no pty path printed: '{pty}'");
        let scheme = framing.trim_start_matches("--");
        DeviceSide { child, uri: format!("{scheme}:{pty}"), pty, config_home: sim.path(""), _stdout: stdout }
    }

    /// canctl on this device side's serial link.
    pub fn run(&self, args: &[&str]) -> Run {
        finish(self.command(args).output().unwrap())
    }

    pub fn command(&self, args: &[&str]) -> Command {
        let mut c = Command::new(canctl_bin());
        c.env("XDG_CONFIG_HOME", &self.config_home).env("XDG_CACHE_HOME", &self.config_home);
        c.env_remove("CANCTL_BUS").arg("--bus").arg(&self.uri).args(args).stdin(Stdio::null());
        c
    }

    pub fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for DeviceSide {
    fn drop(&mut self) {
        self.kill();
    }
}
pub mod scenarios;

/// The vcan interface of the kernel tests: vcan0, or `CANCTL_TEST_VCAN` (scripts/kernel-tests.sh
/// runs several tests at once, each worker on an interface of its own).
pub fn vcan() -> &'static str {
    static IFACE: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    IFACE.get_or_init(|| std::env::var("CANCTL_TEST_VCAN").unwrap_or_else(|_| "vcan0".into()))
}

/// Whether this kernel has the interface. Without it the test is skipped, and says so,
/// unless `CANCTL_REQUIRE_KERNEL` is set (CI and the kernel-test VM set it): then a missing
/// interface is a failure, not a pass.
pub fn has_interface(iface: &str) -> bool {
    if std::path::Path::new("/sys/class/net").join(iface).exists() {
        return true;
    }
    if std::env::var_os("CANCTL_REQUIRE_KERNEL").is_some() {
        panic!("no {iface} here, but CANCTL_REQUIRE_KERNEL is set: the kernel tests must run");
    }
    skipped(&format!("no {iface}; scripts/kernel-tests.sh runs the kernel tests in a VM"));
    false
}

/// Says that the running test is skipped and why, on the real standard error: the harness
/// captures `eprintln!` and shows it only for failures, so a skip would pass unseen.
pub fn skipped(why: &str) {
    use std::io::Write;
    let thread = std::thread::current();
    let test = thread.name().unwrap_or("a test");
    let _ = writeln!(std::io::stderr().lock(), "SKIPPED {test}: {why}");
}

/// A peer script of tests/interop/ run to its end: its output (a failure included), or
/// `None`, said as skipped, when there is no python3 or a failure's stderr shows `missing`
/// (a package not installed) — unless CI requires the peers (`CANCTL_REQUIRE_PEERS`).
pub fn python_peer<S: AsRef<std::ffi::OsStr>>(
    script: &str,
    args: impl IntoIterator<Item = S>,
    missing: &str,
) -> Option<Output> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/interop").join(script);
    let required = std::env::var_os("CANCTL_REQUIRE_PEERS").is_some();
    let out = match Command::new("python3").arg(&path).args(args).output() {
        Ok(out) => out,
        Err(e) if !required => {
            skipped(&format!("no python3 ({e}); CI sets CANCTL_REQUIRE_PEERS=1"));
            return None;
        }
        Err(e) => panic!("python3: {e}"),
    };
    if !out.status.success() && !required && String::from_utf8_lossy(&out.stderr).contains(missing) {
        skipped(&format!("python3 lacks a package {script} needs (pip install -r tests/interop/requirements.txt)"));
        return None;
    }
    Some(out)
}

/// `canctl sim --socketcan IFACE` on this sim's state, started and bound.
pub fn sim_on_interface(sim: &Sim, iface: &str) -> std::process::Child {
    use std::io::BufRead;
    let mut devices =
        sim.command(&["sim", "--socketcan", iface]).stdout(Stdio::null()).stderr(Stdio::piped()).spawn().unwrap();
    // The device side says where it is once its socket is bound.
    let mut line = String::new();
    std::io::BufReader::new(devices.stderr.take().unwrap()).read_line(&mut line).unwrap();
    assert!(line.contains(iface), "device side did not start: {line}");
    devices
}

/// The canctl binary under test: `CANCTL_BIN` when set (the kernel-test VM runs a copy
/// from its own memory, as reading it over 9p costs a second per start), else cargo's.
pub fn canctl_bin() -> PathBuf {
    std::env::var_os("CANCTL_BIN").map(PathBuf::from).unwrap_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_canctl")))
}

/// `c` (a canctl command: [`Sim::command`], [`DeviceSide::command`]) run by the test build
/// of canctl instead, which interrupts itself at `plan` (`3:TERM`, `r5:INT`, `s20:INT`,
/// `o1:TERM`; tests/seams/canctl.rs says them): the real `main` and its signal handler, the
/// point of interruption exact without timing. The canctl under test has no such seam.
pub fn interrupted(c: Command, plan: &str) -> Command {
    let mut seams = Command::new(env!("CARGO_BIN_EXE_canctl-seams"));
    seams.args(c.get_args()).env("CANCTL_TEST_SIGNAL_AFTER_WRITES", plan).stdin(Stdio::null());
    for (k, v) in c.get_envs() {
        match v {
            Some(v) => seams.env(k, v),
            None => seams.env_remove(k),
        };
    }
    if let Some(dir) = c.get_current_dir() {
        seams.current_dir(dir);
    }
    seams
}

/// No settings file or scan cache of the developer's may change what a test sees, and no
/// test writes into theirs.
pub fn isolate(c: &mut Command) {
    let dir = std::env::temp_dir().join(format!("canctl-tests-{}", std::process::id()));
    generous_timeout(&dir);
    c.env("XDG_CONFIG_HOME", &dir).env("XDG_CACHE_HOME", &dir);
}

/// Run `c`, and fail the test (killing it) if it is still running after `limit`: for
/// commands whose bug would be to hang.
pub fn run_within(mut c: Command, limit: std::time::Duration) -> Run {
    let mut child = c.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("{c:?} still running after {} s", limit.as_secs());
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    finish(child.wait_with_output().unwrap())
}

/// Start `c`, wait until it has written `lines` lines on stdout (it is under way), send it
/// `signal`, and return how it ended with everything it wrote.
#[cfg(unix)]
pub fn signal_after_lines(mut c: Command, lines: usize, signal: nix::sys::signal::Signal) -> Run {
    use std::io::{BufRead, Read};
    let mut child = c.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let mut stdout = std::io::BufReader::new(child.stdout.take().unwrap());
    let mut seen = String::new();
    for _ in 0..lines {
        assert!(stdout.read_line(&mut seen).unwrap() > 0, "{c:?} ended before {lines} line(s):\n{seen}");
    }
    nix::sys::signal::kill(nix::unistd::Pid::from_raw(child.id() as i32), signal).unwrap();
    stdout.read_to_string(&mut seen).unwrap();
    let mut out = child.wait_with_output().unwrap();
    out.stdout = seen.into_bytes();
    finish(out)
}

/// Where the shared corpus of real EDS/DCF/XDD files is: `../shared/eds-corpus` beside the
/// repository, or `CANCTL_EDS_CORPUS` (a checkout elsewhere, a git worktree). `None` (the
/// test says it is skipped) when it is not there, unless `CANCTL_REQUIRE_CORPUS` is set.
#[allow(dead_code)]
pub fn eds_corpus() -> Option<std::path::PathBuf> {
    let dir = std::env::var_os("CANCTL_EDS_CORPUS")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/eds-corpus"));
    if dir.is_dir() {
        return Some(dir);
    }
    assert!(std::env::var_os("CANCTL_REQUIRE_CORPUS").is_none(), "no EDS corpus at {}", dir.display());
    skipped(&format!("no EDS corpus at {} (CANCTL_EDS_CORPUS names another place)", dir.display()));
    None
}
