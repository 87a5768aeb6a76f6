"""Benchmarks on vcan0 (run inside the kernel-test VM by scripts/bench-vcan.sh):

- scan of node-ids 1..127 with the sim devices on vcan0: canctl, and the `canopen`
  package's scanner.search() followed by the same 50 ms wait, side by side;
- 64 KiB SDO upload from node 1, block and segmented: MB/s, and the client's CPU time per
  CAN frame it handled (user+system CPU of the canctl process / frames sent and received).
"""

import os
import resource
import statistics
import subprocess
import sys
import time

import canopen

CANCTL = os.environ.get("CANCTL_BIN", "target/release/canctl")
RUNS = 20


def child_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(args):
    """Wall time and CPU time of one canctl run."""
    cpu0, t0 = child_cpu(), time.perf_counter()
    subprocess.run([CANCTL, "--bus", "vcan0", *args], check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0, child_cpu() - cpu0


def median(xs):
    return statistics.median(xs)


devices = subprocess.Popen([CANCTL, "--bus", "sim:/tmp/bench-sim.json", "sim", "--socketcan", "vcan0"],
                           stderr=subprocess.PIPE)
devices.stderr.readline()  # bound and serving
try:
    scans = [run(["scan", "-q"])[0] for _ in range(RUNS)]
    network = canopen.Network()
    network.connect(interface="socketcan", channel="vcan0")
    searches = []
    for _ in range(RUNS):
        network.scanner.reset()
        t0 = time.perf_counter()
        network.scanner.search()
        time.sleep(0.05)
        found = sorted(network.scanner.nodes)
        searches.append(time.perf_counter() - t0)
    network.disconnect()
    print(f"scan 1..127, median of {RUNS}:")
    print(f"  canctl scan (process start to exit, 50 ms window, identities read): {median(scans) * 1000:7.1f} ms")
    print(f"  canopen scanner.search() + 50 ms sleep (found {found}, no identities): {median(searches) * 1000:7.1f} ms")

    # Frames the client handles for 64 KiB: block = 9363 segments in + 74 acks out + 2
    # initiate + start + 2 end; segmented = one request and one answer per 7 bytes + 2.
    size = 65536
    segments = -(-size // 7)
    frames = {"block": segments + -(-segments // 127) + 5, "segmented": 2 * segments + 2}
    for name, extra in [("block", []), ("segmented", ["--no-block"])]:
        walls, cpus = [], []
        for _ in range(5):
            w, c = run(["sdo", "read", "1", "1F50:1", "--type", "d", "--out", "/tmp/bench.bin", *extra])
            walls.append(w)
            cpus.append(c)
        w, c = median(walls), median(cpus)
        print(f"64 KiB upload, {name:9}: {w * 1000:7.1f} ms = {size / w / 1e6:5.2f} MB/s; "
              f"client CPU {c * 1000:6.1f} ms for {frames[name]} frames = {c / frames[name] * 1e6:5.2f} us/frame")
finally:
    devices.kill()
