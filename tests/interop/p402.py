"""python-canopen's CiA 402 master (canopen.profiles.p402.BaseNode402) driving canctl's
simulated EPOS2 (node 1) through its states on IFACE: python p402.py IFACE EDS.
Prints each state the drive's TPDO showed, one per line (`seen STATE`), and exits
non-zero with a message on the first thing that differs."""

import sys
import time

import canopen
from canopen.profiles.p402 import BaseNode402

iface, eds = sys.argv[1], sys.argv[2]
network = canopen.Network()
network.connect(interface="socketcan", channel=iface)
node = BaseNode402(1, eds)
network.add_node(node)
# The emulated CPU of the test VM answers later than the library's defaults expect.
node.sdo.RESPONSE_TIMEOUT = 5.0
for name in ("TIMEOUT_SWITCH_STATE_FINAL", "TIMEOUT_SWITCH_STATE_SINGLE", "TIMEOUT_RESET_FAULT"):
    setattr(node, name, 5.0)

seen = []


def on_tpdo(pdo_map):
    for var in pdo_map:
        if var.index == 0x6041:
            state = "UNKNOWN"
            for name, (mask, value) in canopen.profiles.p402.State402.SW_MASK.items():
                if var.raw & mask == value:
                    state = name
            if not seen or seen[-1] != state:
                seen.append(state)
                print(f"seen {state} (0x{var.raw:04X})", flush=True)


def check(what, got, want):
    if got != want:
        sys.exit(f"{what}: got {got!r}, want {want!r}")
    print(f"ok  {what}", flush=True)


def wait_for(what, predicate, timeout=10.0):
    end = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > end:
            sys.exit(f"timed out waiting for {what}; states seen: {seen}")
        time.sleep(0.01)
    print(f"ok  {what}", flush=True)


node.nmt.state = "PRE-OPERATIONAL"
# The statusword TPDO (TPDO1, event-driven) also every 20 ms, so that the master's view
# is fresh without a change.
node.sdo[0x1800][5].raw = 20
node.setup_402_state_machine(read_pdos=True)
check("the statusword is in a TPDO", 0x6041 in node.tpdo_values, True)
node.tpdo[1].add_callback(on_tpdo)
node.nmt.state = "OPERATIONAL"
wait_for("a first statusword by TPDO", lambda: node.state == "SWITCH ON DISABLED")

node.state = "OPERATION ENABLED"
check("enabled", node.state, "OPERATION ENABLED")
check("statusword by SDO agrees", node.sdo[0x6041].raw & 0x6F, 0x27)
node.state = "QUICK STOP ACTIVE"
check("quick stop", node.state, "QUICK STOP ACTIVE")
node.state = "OPERATION ENABLED"
check("enabled again from quick stop (transition 16)", node.state, "OPERATION ENABLED")
node.state = "SWITCHED ON"
check("disable operation", node.state, "SWITCHED ON")
node.state = "SWITCH ON DISABLED"
check("disable voltage", node.state, "SWITCH ON DISABLED")

node.state = "OPERATION ENABLED"
node.sdo[0x5FFE].raw = 1  # the simulator's fault: an undervoltage 1 ms later
wait_for("the fault", lambda: node.state == "FAULT")
check("is_faulted", node.is_faulted(), True)
check("error register", node.sdo[0x1001].raw, 0x05)
check("error history", node.sdo[0x1003][1].raw & 0xFFFF, 0x3220)
# The cause is still there: the reset does not take. The device handles the controlword
# write before it answers it, so a read of the statusword after it shows the outcome.
node.controlword = 0x00
node.controlword = 0x80
check("still in fault while the cause remains", node.sdo[0x6041].raw & 0x4F, 0x08)
node.sdo[0x5FFE].raw = 0
node.reset_from_fault()
check("out of fault into operation enabled", node.state, "OPERATION ENABLED")
node.state = "SWITCH ON DISABLED"
check("switched off", node.state, "SWITCH ON DISABLED")
node.nmt.state = "PRE-OPERATIONAL"
print("states seen: " + ", ".join(seen), flush=True)
print("all p402 checks passed", flush=True)
network.disconnect()
