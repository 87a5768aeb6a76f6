"""A CiA 302-3 program-download master on python-canopen, following the sequence of
Zephyr's west runner (scripts/west_commands/runners/canopen_program.py) from its facts:
flash status polled until 0, software identification read, NMT pre-operational, stop (0),
clear (3), flash status polled, program data into 0x1F50:1, flash status polled, software
identification read, start (1), boot-up waited for, identification read again, NMT
pre-operational, confirm (0x80). Written for canctl's tests, not copied.

usage: program_master.py CHANNEL INTERFACE NODE IMAGE
Prints one line per step and, last, a JSON line with what the device reported.
"""

import json
import sys
import time
import zlib

import canopen

DATA, CONTROL, SWID, STATUS = 0x1F50, 0x1F51, 0x1F56, 0x1F57
STOP, START, CLEAR, CONFIRM = 0x00, 0x01, 0x03, 0x80


def dictionary():
    od = canopen.objectdictionary.ObjectDictionary()
    for index, name, dtype in (
        (DATA, "Program data", canopen.objectdictionary.DOMAIN),
        (CONTROL, "Program control", canopen.objectdictionary.UNSIGNED8),
        (SWID, "Program software identification", canopen.objectdictionary.UNSIGNED32),
        (STATUS, "Flash status identification", canopen.objectdictionary.UNSIGNED32),
    ):
        array = canopen.objectdictionary.ODArray(name, index)
        member = canopen.objectdictionary.ODVariable(name + " 1", index, 1)
        member.data_type = dtype
        array.add_member(member)
        od.add_object(array)
    return od


def flash_ok(node, timeout):
    """Poll 0x1F57:1 until it reads 0, as the runner does (bounded)."""
    end = time.time() + timeout
    status = None
    while True:
        try:
            status = node.sdo[STATUS][1].raw
            if status == 0:
                return status
        except canopen.SdoCommunicationError:
            pass
        if time.time() > end:
            return status
        time.sleep(0.1)


def main():
    channel, interface, node_id, image_path = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
    image = open(image_path, "rb").read()
    network = canopen.Network()
    node = network.add_node(node_id, dictionary())
    node.sdo.RESPONSE_TIMEOUT = 1.0
    network.connect(interface=interface, channel=channel, bitrate=500000)
    try:
        print("flash status", flash_ok(node, 10.0), flush=True)
        before = node.sdo[SWID][1].raw
        print("swid 0x%08x" % before, flush=True)
        node.nmt.state = "PRE-OPERATIONAL"
        node.sdo[CONTROL][1].raw = STOP
        print("stopped", flush=True)
        node.sdo[CONTROL][1].raw = CLEAR
        print("cleared, erase: flash status", flash_ok(node, 30.0), flush=True)
        with node.sdo[DATA][1].open("wb", size=len(image), buffering=1024, block_transfer=False) as f:
            f.write(image)
        status = flash_ok(node, 10.0)
        print("downloaded %d bytes, flash status %s" % (len(image), status), flush=True)
        written = node.sdo[SWID][1].raw
        print("swid 0x%08x (crc32 of the image 0x%08x)" % (written, zlib.crc32(image)), flush=True)
        try:
            node.sdo[CONTROL][1].raw = START
            start = "answered"
        except canopen.SdoCommunicationError as e:
            start = "not answered (%s)" % e
        print("start", start, flush=True)
        node.nmt.wait_for_bootup(10.0) if start == "answered" else None
        after = node.sdo[SWID][1].raw
        control = node.sdo[CONTROL][1].raw
        print("swid 0x%08x, program control 0x%02x" % (after, control), flush=True)
        node.nmt.state = "PRE-OPERATIONAL"
        node.sdo[CONTROL][1].raw = CONFIRM
        confirmed = node.sdo[CONTROL][1].raw
        print("confirmed: program control 0x%02x" % confirmed, flush=True)
        print(json.dumps({"before": before, "written": written, "after": after, "crc32": zlib.crc32(image),
                          "start": start, "control": confirmed}))
    finally:
        network.disconnect()


if __name__ == "__main__":
    main()
