"""The `canopen` package as the client of canctl's simulated devices on IFACE:
python client.py IFACE. Exits non-zero with a message on the first thing that differs."""

import struct
import sys
import time

import canopen
from canopen.objectdictionary import ObjectDictionary

iface = sys.argv[1]
network = canopen.Network()
network.connect(interface="socketcan", channel=iface)


# Every wait is for the event itself, under a bound that only a missing answer reaches:
# python-canopen's own SDO timeout (0.3 s) is shorter than an emulated CPU under load takes.
PATIENCE = 10.0


def remote(node_id):
    node = canopen.RemoteNode(node_id, ObjectDictionary())
    node.sdo.RESPONSE_TIMEOUT = PATIENCE
    network.add_node(node)
    return node


def check(what, got, want):
    if got != want:
        sys.exit(f"{what}: got {got!r}, want {want!r}")
    print(f"ok  {what}")


# Scanner: SDO uploads of 0x1000 to every node-id, then a wait until all four answered.
network.scanner.search()
deadline = time.monotonic() + PATIENCE
while len(network.scanner.nodes) < 4 and time.monotonic() < deadline:
    time.sleep(0.01)
check("scanner finds the demo nodes", sorted(network.scanner.nodes), [1, 5, 10, 32])

drive, sensor, io = remote(1), remote(5), remote(10)
check("expedited upload of the device type", drive.sdo.upload(0x1000, 0), struct.pack("<I", 0x00020192))
check("segmented upload of a name", io.sdo.upload(0x1008, 0), b"CAN-2057C")
for sub, fmt, value in [(2, "<B", 0xA5), (3, "<H", 0xBEEF), (4, "<I", 0xDEADBEEF), (5, "<Q", 2**63 + 5),
                        (7, "<h", -1234), (8, "<i", -123456), (9, "<q", -(2**40)), (10, "<f", 1.25), (11, "<d", -2.5)]:
    raw = struct.pack(fmt, value)
    io.sdo.download(0x5FF0, sub, raw)
    check(f"download/upload of 0x5FF0:{sub} ({fmt})", io.sdo.upload(0x5FF0, sub), raw)
text = b"a string long enough for segmented transfer"
io.sdo.download(0x5FF0, 12, text)
check("segmented download of a string", io.sdo.upload(0x5FF0, 12), text)

try:
    drive.sdo.download(0x1000, 0, struct.pack("<I", 1))
    sys.exit("writing a read-only object did not abort")
except canopen.SdoAbortedError as e:
    check("abort code for a read-only object", e.code, 0x06010002)

# Block transfer, where canopen's client offers it, on node 1's domain 0x5FF0:14 (4 KiB:
# the pure-Python client needs seconds per 64 KiB; canctl's own tests move that).
blob = bytes((i * 13 + (i >> 8)) & 0xFF for i in range(4096))
with drive.sdo.open(0x5FF0, 14, "wb", size=len(blob), block_transfer=True) as f:
    f.write(blob)
check("block download, read back by segmented upload", drive.sdo.upload(0x5FF0, 14), blob)
with drive.sdo.open(0x5FF0, 14, "rb", block_transfer=True) as f:
    check("block upload", f.read(), blob)


def heartbeat_shows(node, want):
    """Beats sent before the command may still be on their way. Through slcand and a pty on
    an emulated CPU the path lags by more than five of the sensor's 40 ms beats (a run saw
    'OPERATIONAL' after a pre-operational command): wait for the state itself, bounded by
    PATIENCE as every other wait here, not for a count of beats."""
    deadline = time.monotonic() + PATIENCE
    while time.monotonic() < deadline:
        node.nmt.wait_for_heartbeat(timeout=PATIENCE)
        if node.nmt.state == want:
            break
    check(f"heartbeat shows {want}", node.nmt.state, want)


# NMT and the heartbeat consumer: the sensor beats every 40 ms.
for state in ["STOPPED", "OPERATIONAL", "PRE-OPERATIONAL"]:
    sensor.nmt.state = state
    heartbeat_shows(sensor, state)
network.disconnect()
print("all interop checks passed")
