"""CANopen devices built with `durand` (a device stack written independently of canctl and
of python-canopen), for tests/suite/interop_durand.rs.

    python3 durand_node.py IFACE [--node ID]... [--unconfigured N] [--seconds S]

--node ID        a configured device with node-id ID: identity, heartbeat, one object of
                 every CiA 301 type (0x2000:1..14), a writable domain (0x2100) and
                 read-only domains of the block/segment boundary sizes (0x2200:1..).
--unconfigured N N LSS devices without a node-id (node-id 255), distinct identities.
--seconds S      exit after S seconds at the latest (default 7200; end of input ends it too).

Standard output, one line per event, for the test to wait on:
    READY                                   every device is up (again after `reset`)
    DOWNLOAD <node> <index:04X> <sub> <v>   an SDO download arrived; v as durand decoded it:
                                            integers in decimal, reals with repr, bytes in hex
    BOOT <serial:08X> <node>                a device booted with this node-id
    STORED <serial:08X> <node>              LSS "store configuration" for this device
Standard input, one command a line: `reset` takes every LSS device back to no node-id
(as after a power cycle without a stored id) and prints READY. End of input ends the
program."""

import argparse
import asyncio
import sys

import can
from durand import CANBusNetwork, DatatypeEnum as DT, Node, Record, Variable
from durand.scheduler import AsyncScheduler, set_scheduler
from durand.services.nmt import StateEnum

VENDOR = 0x00000D0A
PRODUCT = 0x00D0_5000
REVISION = 0x0005_0000
DEVICE_TYPE = 0x000F0191
HEARTBEAT_MS = 200

# Serials of the devices without a node-id: they differ in their highest and lowest bits,
# so that fastscan has to tell them apart at both ends of the word.
UNCONFIGURED_SERIALS = [0x00000001, 0x80000000, 0x7FFFFFFE, 0x12345678, 0xFFFFFFFF, 0x00010000, 0xC0FFEE00, 0x5A5A5A5A]

# 0x2000:1..14, one of each type, with a start value read by the test (kept in step with
# TYPED in tests/suite/interop_durand.rs).
TYPED = [
    (DT.BOOLEAN, True),
    (DT.UNSIGNED8, 0xA5),
    (DT.UNSIGNED16, 0xBEEF),
    (DT.UNSIGNED32, 0xDEADBEEF),
    (DT.UNSIGNED64, 0x0123456789ABCDEF),
    (DT.INTEGER8, -128),
    (DT.INTEGER16, -32768),
    (DT.INTEGER32, -2147483648),
    (DT.INTEGER64, -9223372036854775808),
    (DT.REAL32, -1.5),
    (DT.REAL64, 2.718281828459045),
    (DT.VISIBLE_STRING, b"durand"),
    (DT.OCTET_STRING, bytes([0x00, 0xFF, 0x10, 0x80])),
    (DT.DOMAIN, bytes(range(10))),
]

# 0x2200:1.. read-only domains around the segment and block boundaries: 127 x 7 = 889
# bytes is one full block.
BOUNDARY_SIZES = [0, 1, 7, 8, 888, 889, 890, 65536]


def pattern(size):
    """The content of a boundary domain: also computed by the test."""
    return bytes((i * 7 + size) & 0xFF for i in range(size))


def shown(value):
    if isinstance(value, (bytes, bytearray)):
        return bytes(value).hex().upper() or "-"
    if isinstance(value, bool):
        return str(int(value))
    if isinstance(value, float):
        return repr(value)
    return str(value)


def say(line):
    print(line, flush=True)


class Device:
    def __init__(self, iface, loop, node_id, serial, revision):
        self.bus = can.Bus(interface="socketcan", channel=iface)
        self.network = CANBusNetwork(self.bus, loop=loop)
        self.serial = serial
        self.node = Node(self.network, node_id)
        od = self.node.object_dictionary
        od.write(0x1000, 0, DEVICE_TYPE)
        od.write(0x1008, 0, b"durand %d" % node_id if node_id != 0xFF else b"durand LSS")
        for sub, value in enumerate([VENDOR, PRODUCT, revision, serial], 1):
            od.write(0x1018, sub, value)
        self.node.nmt.state_callbacks.add(self.on_state)
        self.node.lss.set_store_configuration_callback(
            lambda _baud, node: say(f"STORED {self.serial:08X} {node}")
        )

    def on_state(self, state):
        if state == StateEnum.PRE_OPERATIONAL and self.node.node_id != 0xFF:
            say(f"BOOT {self.serial:08X} {self.node.node_id}")

    def add_objects(self):
        od = self.node.object_dictionary
        typed = Record(name="Data types")
        for sub, (dtype, value) in enumerate(TYPED, 1):
            typed[sub] = Variable(dtype, "rw", value, name=f"type {sub}")
        od[0x2000] = typed
        od[0x2100] = Variable(DT.DOMAIN, "rw", b"", name="Writable domain")
        sizes = Record(name="Boundary domains")
        for sub, size in enumerate(BOUNDARY_SIZES, 1):
            sizes[sub] = Variable(DT.DOMAIN, "ro", pattern(size), name=f"{size} bytes")
        od[0x2200] = sizes
        for index, sub in [(0x2000, s) for s in range(1, len(TYPED) + 1)] + [(0x2100, 0)]:
            od.download_callbacks[(index, sub)].add(
                lambda v, index=index, sub=sub: say(f"DOWNLOAD {self.node.node_id} {index:04X} {sub} {shown(v)}")
            )
        od.write(0x1017, 0, HEARTBEAT_MS)

    def forget_node_id(self):
        """Back to no node-id, LSS waiting, as a device without a stored id powers up."""
        self.node.nmt.pending_node_id = 0xFF
        self.node.nmt.reset()


def main():
    p = argparse.ArgumentParser()
    p.add_argument("iface")
    p.add_argument("--node", type=int, action="append", default=[])
    p.add_argument("--unconfigured", type=int, default=0)
    p.add_argument("--seconds", type=float, default=7200)
    a = p.parse_args()
    if a.unconfigured > len(UNCONFIGURED_SERIALS):
        p.error(f"at most {len(UNCONFIGURED_SERIALS)} unconfigured devices")

    loop = asyncio.new_event_loop()
    asyncio.set_event_loop(loop)
    set_scheduler(AsyncScheduler(loop))

    configured = []
    for node_id in a.node:
        d = Device(a.iface, loop, node_id, 0xC0000000 | node_id, REVISION)
        d.add_objects()
        configured.append(d)
    # Every other one has another revision, so that fastscan's revision part differs too.
    lss = [Device(a.iface, loop, 0xFF, s, REVISION + (i % 2)) for i, s in enumerate(UNCONFIGURED_SERIALS[: a.unconfigured])]

    def on_stdin():
        line = sys.stdin.readline()
        if not line:
            loop.stop()
        elif line.strip() == "reset":
            for d in lss:
                d.forget_node_id()
            say("READY")

    loop.add_reader(sys.stdin.fileno(), on_stdin)
    loop.call_later(a.seconds, loop.stop)
    say("READY")
    try:
        loop.run_forever()
    finally:
        for d in configured + lss:
            d.network.stop()
            d.bus.shutdown()


if __name__ == "__main__":
    main()
