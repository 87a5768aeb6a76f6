"""A CiA 302-3 bootloader built with the `canopen` package, following the rules of Zephyr's
subsys/canbus/canopen/canopen_program.c (from its facts, not its code): program data only
in NMT pre-operational, only while stopped and after a clear (else abort 0x08000022); clear
only while stopped; 0x1F56 the CRC-32 of the program; 0x1F57 the flash status (0 ok, error
codes in bits 1..7); a new program runs unconfirmed (0x1F51 reads 0x80) until 0x80 is
written. Start answers, then the device reboots into the program (a boot-up follows).

python program_device.py IFACE NODE. Prints READY once it listens, then a JSON line per
program control command and one per download (size, CRC-32); runs until killed.
"""

import json
import sys
import threading
import time
import zlib

import canopen
from canopen.objectdictionary import ODArray, ODVariable, ObjectDictionary
from canopen.objectdictionary import datatypes as dt
from canopen.sdo.exceptions import SdoAbortedError

iface, node_id = sys.argv[1], int(sys.argv[2])
WRONG_STATE = 0x08000022
STOP, START, RESET, CLEAR, CONFIRM = 0, 1, 2, 3, 0x80


def var(index, sub, name, dtype, access, default=0):
    v = ODVariable(name, index, sub)
    v.data_type, v.access_type, v.default = dtype, access, default
    return v


def array(index, name, dtype, access):
    a = ODArray(name, index)
    a.add_member(var(index, 0, "Highest sub-index supported", dt.UNSIGNED8, "ro", 1))
    a.add_member(var(index, 1, "Program number 1", dtype, access, b"" if dtype == dt.DOMAIN else 0))
    return a


od = ObjectDictionary()
od.add_object(var(0x1000, 0, "Device type", dt.UNSIGNED32, "ro"))
od.add_object(var(0x1017, 0, "Producer heartbeat time", dt.UNSIGNED16, "rw", 100))
od.add_object(array(0x1F50, "Program data", dt.DOMAIN, "wo"))
od.add_object(array(0x1F51, "Program control", dt.UNSIGNED8, "rw"))
od.add_object(array(0x1F56, "Program software identification", dt.UNSIGNED32, "ro"))
od.add_object(array(0x1F57, "Flash status identification", dt.UNSIGNED32, "ro"))

state = {
    "status": START,  # the factory program runs
    "crc": zlib.crc32(b"factory program"),
    "erased": False,
    "confirmed": True,
    "flash": 0,
}

network = canopen.Network()
node = canopen.LocalNode(node_id, od)
network.add_node(node)


def report(**kv):
    print(json.dumps(kv), flush=True)


def reboot():
    # Out of the SDO answer's way, as a reset after the answer would be.
    time.sleep(0.1)
    node.nmt.state = "INITIALISING"
    network.send_message(0x700 + node_id, b"\x00")
    node.nmt.state = "PRE-OPERATIONAL"


def on_write(index, subindex, od, data):
    if index == 0x1F50:
        if node.nmt.state != "PRE-OPERATIONAL" or state["status"] != STOP or not state["erased"]:
            raise SdoAbortedError(WRONG_STATE)
        state["erased"] = False
        state["crc"] = zlib.crc32(bytes(data))
        state["flash"] = 0
        report(download=len(data), crc32=state["crc"])
    elif index == 0x1F51:
        cmd = data[0]
        report(control=cmd, nmt=node.nmt.state)
        if cmd == STOP:
            if state["status"] not in (START, STOP):
                raise SdoAbortedError(WRONG_STATE)
            state["status"] = STOP
        elif cmd == START:
            if state["status"] != STOP or state["crc"] == 0:
                raise SdoAbortedError(WRONG_STATE)
            state["status"] = START
            state["confirmed"] = False
            threading.Thread(target=reboot, daemon=True).start()
        elif cmd == RESET:
            state["flash"] = 0
        elif cmd == CLEAR:
            if state["status"] != STOP or node.nmt.state != "PRE-OPERATIONAL":
                raise SdoAbortedError(WRONG_STATE)
            state["erased"], state["crc"], state["flash"] = True, 0, 0
        elif cmd == CONFIRM:
            if state["status"] != START:
                raise SdoAbortedError(WRONG_STATE)
            state["confirmed"] = True
        else:
            raise SdoAbortedError(0x06090030)


def on_read(index, subindex, od):
    if subindex != 1:
        return None
    if index == 0x1F51:
        # An unconfirmed program takes precedence over the other states.
        return CONFIRM if state["status"] == START and not state["confirmed"] else state["status"]
    if index == 0x1F56:
        return state["crc"]
    if index == 0x1F57:
        return state["flash"]
    return None


node.add_write_callback(on_write)
node.add_read_callback(on_read)
network.connect(interface="socketcan", channel=iface)
node.nmt.state = "PRE-OPERATIONAL"
node.nmt.start_heartbeat(100)
print("READY", flush=True)
while True:
    time.sleep(1)
