"""A CANopen device built with the `canopen` package, for canctl to scan, read, write and
command: python local_node.py IFACE NODE. Prints READY once it listens, then one JSON line
per SDO write with the value python-canopen decodes from the written bytes (its own codec,
by the object's data type); runs until killed. 0x2001 holds values python-canopen encoded."""

import json
import math
import sys
import time

import canopen
from canopen.objectdictionary import ODRecord, ODVariable, ObjectDictionary
from canopen.objectdictionary import datatypes as dt

from tagged import tagged

iface, node_id = sys.argv[1], int(sys.argv[2])


def var(index, sub, name, dtype, default, access="rw"):
    v = ODVariable(name, index, sub)
    v.data_type, v.access_type, v.default = dtype, access, default
    return v


def record(index, name, members):
    r = ODRecord(name, index)
    r.add_member(var(index, 0, "Highest sub-index supported", dt.UNSIGNED8, len(members), "ro"))
    for sub, (mname, dtype, default, access) in enumerate(members, 1):
        r.add_member(var(index, sub, mname, dtype, default, access))
    return r


od = ObjectDictionary()
od.add_object(var(0x1000, 0, "Device type", dt.UNSIGNED32, 0x00000191, "ro"))
od.add_object(var(0x1008, 0, "Manufacturer device name", dt.VISIBLE_STRING, "python-canopen LocalNode", "const"))
od.add_object(var(0x1017, 0, "Producer heartbeat time", dt.UNSIGNED16, 50))
od.add_object(record(0x1018, "Identity object", [
    ("Vendor-ID", dt.UNSIGNED32, 0x00000123, "ro"),
    ("Product code", dt.UNSIGNED32, 0x00004567, "ro"),
    ("Revision number", dt.UNSIGNED32, 0x00010002, "ro"),
    ("Serial number", dt.UNSIGNED32, 0x0000BEEF, "ro"),
]))
od.add_object(record(0x2000, "Data types", [
    ("boolean", dt.BOOLEAN, False, "rw"),
    ("unsigned8", dt.UNSIGNED8, 0, "rw"),
    ("unsigned16", dt.UNSIGNED16, 0, "rw"),
    ("unsigned32", dt.UNSIGNED32, 0, "rw"),
    ("unsigned64", dt.UNSIGNED64, 0, "rw"),
    ("integer8", dt.INTEGER8, 0, "rw"),
    ("integer16", dt.INTEGER16, 0, "rw"),
    ("integer32", dt.INTEGER32, 0, "rw"),
    ("integer64", dt.INTEGER64, 0, "rw"),
    ("real32", dt.REAL32, 0.0, "rw"),
    ("real64", dt.REAL64, 0.0, "rw"),
    ("visible string", dt.VISIBLE_STRING, "", "rw"),
    ("octet string", dt.OCTET_STRING, b"", "rw"),
    ("domain", dt.DOMAIN, b"", "rw"),
]))

# The same types, with values python-canopen encodes itself, for canctl to read.
od.add_object(record(0x2001, "Values set by python-canopen", [
    ("boolean", dt.BOOLEAN, True, "ro"),
    ("unsigned8", dt.UNSIGNED8, 255, "ro"),
    ("unsigned16", dt.UNSIGNED16, 0xBEEF, "ro"),
    ("unsigned32", dt.UNSIGNED32, 0xFFFFFFFF, "ro"),
    ("unsigned64", dt.UNSIGNED64, 2**64 - 1, "ro"),
    ("integer8", dt.INTEGER8, -128, "ro"),
    ("integer16", dt.INTEGER16, -12345, "ro"),
    ("integer32", dt.INTEGER32, -(2**31), "ro"),
    ("integer64", dt.INTEGER64, -(2**63), "ro"),
    ("real32", dt.REAL32, -1.25, "ro"),
    ("real64", dt.REAL64, math.pi, "ro"),
    ("visible string", dt.VISIBLE_STRING, "set by python-canopen", "ro"),
    ("octet string", dt.OCTET_STRING, bytes([0x00, 0x7F, 0x80, 0xFF]), "ro"),
    ("domain", dt.DOMAIN, bytes(range(20)), "ro"),
]))


def on_write(index, subindex, od, data):
    print(json.dumps({"index": index, "sub": subindex, "value": tagged(od.decode_raw(data))}), flush=True)


network = canopen.Network()
network.connect(interface="socketcan", channel=iface)
node = canopen.LocalNode(node_id, od)
network.add_node(node)
node.add_write_callback(on_write)
# Initialising -> pre-operational starts the heartbeat from 0x1017.
node.nmt.state = "PRE-OPERATIONAL"
print("READY", flush=True)
while True:
    time.sleep(1)
