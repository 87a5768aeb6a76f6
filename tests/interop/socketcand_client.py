"""Clients we did not write, against `canctl sim --socketcand`: python-can's socketcand
interface, and python-canopen over it. Prints one JSON line of what the sim's devices said.

    socketcand_client.py python-can HOST PORT CHANNEL
    socketcand_client.py canopen HOST PORT CHANNEL
"""

import json
import sys
import time

import can


def python_can(host, port, channel):
    bus = can.Bus(interface="socketcand", host=host, port=port, channel=channel)
    try:
        # SDO upload of 0x1018:1 (vendor-id) from node 5, expedited.
        bus.send(can.Message(arbitration_id=0x605, data=[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0], is_extended_id=False))
        heartbeat, answer = None, None
        deadline = time.monotonic() + 10
        while (answer is None or heartbeat is None) and time.monotonic() < deadline:
            msg = bus.recv(timeout=1)
            if msg is None:
                continue
            if msg.arbitration_id == 0x585 and answer is None:
                answer = msg.data.hex()
            elif msg.arbitration_id == 0x705 and heartbeat is None:
                heartbeat = msg.data.hex()
        print(json.dumps({"answer": answer, "heartbeat": heartbeat}))
    finally:
        bus.shutdown()


def python_canopen(host, port, channel):
    import canopen

    network = canopen.Network()
    network.connect(interface="socketcand", host=host, port=port, channel=channel)
    try:
        node = canopen.RemoteNode(10, canopen.ObjectDictionary())
        network.add_node(node)
        node.sdo.RESPONSE_TIMEOUT = 5
        device_type = int.from_bytes(node.sdo.upload(0x1000, 0), "little")
        name = node.sdo.upload(0x1008, 0).decode("ascii")
        print(json.dumps({"device_type": device_type, "name": name}))
    finally:
        network.disconnect()


if __name__ == "__main__":
    kind, host, port, channel = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
    {"python-can": python_can, "canopen": python_canopen}[kind](host, port, channel)
