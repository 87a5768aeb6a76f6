//! The socketcand bus end to end on loopback: canctl's client (`--bus socketcand:...`)
//! against `canctl sim --socketcand`, and clients we did not write against the same server:
//! python-can's socketcand interface and python-canopen over it (versions pinned in
//! tests/interop/requirements.txt). Without python3 and those packages the python tests
//! say they are skipped, unless `CANCTL_REQUIRE_PEERS` is set (CI sets it).

use crate::common;

use common::scenarios::{self, Under};
use common::{Run, Sim};
use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

/// `canctl sim --socketcand` on a sim network of its own, on a free port; killed when dropped.
struct Server {
    sim: Sim,
    child: Child,
    /// The `--bus` value it printed.
    bus: String,
    _stdout: BufReader<ChildStdout>,
}

impl Server {
    fn start(reset: &[&str]) -> Server {
        let sim = Sim::new();
        let mut args = vec!["sim", "reset"];
        args.extend_from_slice(reset);
        sim.run(&args).ok();
        let mut child =
            sim.command(&["sim", "--socketcand", "0"]).stdout(Stdio::piped()).stderr(Stdio::null()).spawn().unwrap();
        let mut stdout = BufReader::new(child.stdout.take().unwrap());
        let mut bus = String::new();
        stdout.read_line(&mut bus).unwrap();
        let bus = bus.trim().to_string();
        assert!(bus.starts_with("socketcand:127.0.0.1:") && bus.ends_with("/sim"), "no --bus value printed: '{bus}'");
        Server { sim, child, bus, _stdout: stdout }
    }

    /// The host, port and interface of the printed bus value.
    fn parts(&self) -> (String, String, String) {
        let rest = self.bus.strip_prefix("socketcand:").unwrap();
        let (server, iface) = rest.rsplit_once('/').unwrap();
        let (host, port) = server.rsplit_once(':').unwrap();
        (host.into(), port.into(), iface.into())
    }

    fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.kill();
    }
}

impl Under for Server {
    fn run(&self, args: &[&str]) -> Run {
        common::finish(self.command(args).output().unwrap())
    }
    fn iface(&self) -> &str {
        &self.bus
    }
    fn path(&self, name: &str) -> PathBuf {
        self.sim.path(name)
    }
    fn command(&self, args: &[&str]) -> Command {
        let mut c = Command::new(common::canctl_bin());
        c.env("XDG_CONFIG_HOME", self.sim.path("")).env("XDG_CACHE_HOME", self.sim.path("")).env_remove("CANCTL_BUS");
        c.arg("--bus").arg(&self.bus).args(args).stdin(Stdio::null());
        c
    }
}

#[test]
fn scan_sdo_and_nmt_through_the_server() {
    let server = Server::start(&["--bit-rate", "1M"]);
    let scan = server.run(&["scan", "--format", "json"]).ok().json();
    let nodes = scan["nodes"].as_array().unwrap();
    let ids: Vec<u64> = nodes.iter().map(|n| n["node"].as_u64().unwrap()).collect();
    assert_eq!(ids, [1, 5, 10, 32], "{scan}");
    assert_eq!((nodes[1]["name"].as_str(), nodes[1]["vendor_id"].as_u64()), (Some("C01"), Some(0x40)));
    // The sensor's heartbeat shows its state; the others would need node guarding, which
    // raw mode cannot carry: unknown, and said why, not guessed.
    assert_eq!(
        (nodes[1]["state"].as_str(), nodes[1]["state_from"].as_str()),
        (Some("pre-operational"), Some("heartbeat"))
    );
    assert_eq!(nodes[2]["state"], serde_json::Value::Null, "{scan}");
    assert!(nodes[2]["state_from"].as_str().unwrap().contains("no RTR frames"), "{scan}");

    scenarios::a_long_name_comes_back_whole_by_segmented_transfer(&server);
    let out = server.path("domain.bin");
    let read = server.run(&["-v", "sdo", "read", "1", "1F50:1", "--type", "d", "--out", out.to_str().unwrap()]).ok();
    assert_eq!(std::fs::read(&out).unwrap().len(), 65536);
    let trace = format!("{}  601   [8]  A4 50 1F 01", server.bus);
    assert!(read.stderr.lines().any(|l| l.trim_start().starts_with(&trace)), "no block upload:\n{}", read.stderr);

    server.run(&["nmt", "start", "5"]).ok();
    assert!(server.run(&["nmt", "state", "5"]).ok().stdout.contains("operational (from heartbeat)"));
    // Node 10 sends no heartbeat: asking it by node guarding is refused by name.
    let guarded = server.run(&["nmt", "state", "10"]);
    assert_eq!(guarded.code, 2, "{}", guarded.stderr);
    assert!(guarded.stderr.contains("socketcand's raw mode carries no remote (RTR) frames"), "{}", guarded.stderr);
}

/// Where the link cannot guard, health judges the NMT state by heartbeat or says it is not
/// checkable here, never a failure of the node; doctor of a stopped node gives a finding,
/// not a usage error (issue 39: health said "UNHEALTHY: nmt" on a healthy bus, exit 6, and
/// `doctor 10` exited 2).
#[test]
fn health_and_doctor_through_the_server_do_not_fail_a_node_for_the_links_lack_of_rtr() {
    let server = Server::start(&["--bit-rate", "1M"]);
    let health = server.run(&["health", "--format", "json"]);
    assert_eq!(health.code, 0, "{}\n{}", health.stdout, health.stderr);
    let report = health.json();
    let io = report["nodes"].as_array().unwrap().iter().find(|n| n["node"] == 10).expect("node 10 judged").clone();
    let nmt = io["checks"].as_array().unwrap().iter().find(|c| c["check"] == "nmt").expect("an nmt check").clone();
    assert_eq!(nmt["ok"], true, "{nmt}");
    assert!(nmt["detail"].as_str().unwrap().starts_with("not checkable here"), "{nmt}");

    server.run(&["nmt", "stop", "10"]).ok();
    let doctor = server.run(&["doctor", "10"]);
    assert_eq!(doctor.code, 6, "{}\n{}", doctor.stdout, doctor.stderr);
    assert!(doctor.stdout.contains("node guarding of node 10 cannot be asked"), "{}", doctor.stdout);
    assert!(doctor.stdout.contains("1. node 10 answers nothing while the bus is not: stopped"), "{}", doctor.stdout);
    assert!(doctor.stdout.contains("canctl nmt preop 10"), "{}", doctor.stdout);
}

#[test]
fn monitor_through_the_server_sees_another_programs_frames() {
    let server = Server::start(&[]);
    let mut monitor = server
        .command(&["monitor", "--format", "json", "--duration", "20s"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(monitor.stdout.take().unwrap()).lines();
    // The sensor's heartbeat: the monitor is on the bus.
    let first = lines.next().unwrap().unwrap();
    assert!(first.contains("\"heartbeat\""), "{first}");
    server.run(&["sdo", "read", "10", "1000"]).ok();
    let request = lines.map_while(Result::ok).find(|l| l.contains("\"cob\":\"0x60A\""));
    let _ = monitor.kill();
    let _ = monitor.wait();
    let request = request.expect("the monitor saw the other program's SDO request");
    assert!(request.contains("upload 0x1000:0"), "{request}");
}

#[test]
fn a_server_killed_mid_transfer_ends_with_exit_5() {
    let mut server = Server::start(&[]);
    let out = server.path("partial.bin");
    let mut child = server
        .command(&["-v", "sdo", "read", "1", "1F50:1", "--type", "d", "--out", out.to_str().unwrap()])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The server goes away once the device has answered: the block transfer is under way.
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let answered = format!("{}  581 ", server.bus);
    let mut seen = String::new();
    loop {
        let mut line = String::new();
        assert!(stderr.read_line(&mut line).unwrap() > 0, "canctl ended before the device answered: {seen}");
        seen += &line;
        if line.trim_start().starts_with(&answered) {
            break;
        }
    }
    server.kill();
    let start = Instant::now();
    std::io::Read::read_to_string(&mut stderr, &mut seen).unwrap();
    let mut r = common::finish(child.wait_with_output().unwrap());
    r.stderr = seen;
    assert_eq!(r.code, 5, "{}", r.stderr);
    assert!(r.stderr.contains("the connection to the server was lost"), "{}", r.stderr);
    assert!(start.elapsed() < Duration::from_secs(5), "hung for {:?}", start.elapsed());
    assert!(!out.exists(), "a partial upload must not be written");
}

#[test]
fn a_stuck_server_is_a_bounded_link_failure() {
    use nix::sys::signal::{kill, Signal};
    let server = Server::start(&[]);
    let pid = nix::unistd::Pid::from_raw(server.child.id() as i32);
    // Stopped, the server's kernel still accepts the connection, and nothing answers.
    kill(pid, Signal::SIGSTOP).unwrap();
    let stuck = server.run(&["--timeout", "300ms", "scan"]);
    kill(pid, Signal::SIGCONT).unwrap();
    assert_eq!(stuck.code, 5, "{}", stuck.stderr);
    assert!(stuck.stderr.contains("no < hi > within 300 ms"), "{}", stuck.stderr);
}

#[test]
fn no_server_and_a_wrong_interface_are_link_failures_saying_what_to_do() {
    let server = Server::start(&[]);
    let (host, port, _) = server.parts();
    let wrong = Command::new(common::canctl_bin())
        .env_remove("CANCTL_BUS")
        .args(["--bus", &format!("socketcand:{host}:{port}/can0"), "scan"])
        .output()
        .unwrap();
    let wrong = common::finish(wrong);
    assert_eq!(wrong.code, 5, "{}", wrong.stderr);
    assert!(wrong.stderr.contains("refused to open can0: could not open bus"), "{}", wrong.stderr);

    let free = std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
    let none = common::bare(&["--bus", &format!("socketcand:127.0.0.1:{free}/can0"), "scan"]);
    assert_eq!(none.code, 5, "{}", none.stderr);
    assert!(none.stderr.contains("cannot connect") && none.stderr.contains("SSH tunnel"), "{}", none.stderr);
}

#[test]
fn a_port_in_use_says_to_take_another() {
    let sim = Sim::new();
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    let r = sim.run(&["sim", "--socketcand", &port]);
    assert_eq!(r.code, 5, "{}", r.stderr);
    assert!(r.stderr.contains(&format!("cannot open TCP 127.0.0.1:{port}")), "{}", r.stderr);
    assert!(r.stderr.contains("serve on another port, or on port 0 for any free one"), "{}", r.stderr);
}

#[test]
fn completion_offers_socketcand_addresses() {
    let sim = Sim::new();
    let mut c = Command::new(common::canctl_bin());
    c.env("XDG_CONFIG_HOME", sim.path("")).env("XDG_CACHE_HOME", sim.path("")).env_remove("CANCTL_BUS");
    c.env("COMPLETE", "fish").args(["--", "canctl", "--bus", "sock"]);
    let out = common::finish(c.output().unwrap()).ok();
    assert!(
        out.stdout.lines().any(|l| l.starts_with("socketcand:\t") && l.contains("HOST[:PORT]/IFACE")),
        "{}",
        out.stdout
    );
}

/// python3 with python-can and canopen, or why not (a skip, or a failure under
/// `CANCTL_REQUIRE_PEERS`).
fn python_peer(server: &Server, kind: &str) -> Option<serde_json::Value> {
    let (host, port, iface) = server.parts();
    let out = common::python_peer("socketcand_client.py", [kind, &host, &port, &iface], "ModuleNotFoundError")?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{kind} client failed:\n{stderr}");
    Some(
        serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout))),
    )
}

#[test]
fn python_cans_socketcand_client_talks_to_the_sim() {
    let server = Server::start(&[]);
    let Some(got) = python_peer(&server, "python-can") else { return };
    // The expedited answer with the sensor's vendor-id 0x40, and its heartbeat.
    assert_eq!(got["answer"], "4318100140000000", "{got}");
    assert_eq!(got["heartbeat"], "7f", "{got}");
}

#[test]
fn python_canopen_reads_objects_over_socketcand() {
    let server = Server::start(&[]);
    let Some(got) = python_peer(&server, "canopen") else { return };
    // Expedited (0x1000) and segmented (0x1008) uploads by python-canopen's SDO client.
    assert_eq!(got["device_type"], 0x0003_0191, "{got}");
    assert_eq!(got["name"], "CAN-2057C", "{got}");
}
