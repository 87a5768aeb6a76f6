"""python-canopen's object dictionary codecs as an independent encoder for canctl's tests.

Reads a JSON list of cases on stdin: {"code": CiA 301 data type index, "value": text or
null, "bytes": hex or null}. For each case prints one JSON line: the bytes python-canopen
encodes the value to (ODVariable.encode_raw), and the value it decodes the bytes to
(ODVariable.decode_raw); either is {"error": ...} where python-canopen refuses.
"""
import json
import sys

import canopen
from canopen.objectdictionary import ODVariable
from canopen.objectdictionary import datatypes as dt

from tagged import tagged


def python_value(code, text):
    """The value as a Python program would write it, from the same text."""
    if code == dt.BOOLEAN:
        return {"true": True, "false": False, "1": True, "0": False}[text.lower()]
    if code in dt.INTEGER_TYPES:
        return int(text, 0)
    if code in dt.FLOAT_TYPES:
        return float(text)
    if code in (dt.OCTET_STRING, dt.DOMAIN):
        return bytes.fromhex(text)
    return text


def main():
    out = []
    for case in json.load(sys.stdin):
        var = ODVariable("v", 0x2000, 0)
        var.data_type = case["code"]
        result = {}
        if case.get("value") is not None:
            try:
                result["encoded"] = var.encode_raw(python_value(case["code"], case["value"])).hex().upper()
            except Exception as e:  # a refusal is a result too
                result["encoded"] = {"error": f"{type(e).__name__}: {e}"}
        if case.get("bytes") is not None:
            try:
                result["decoded"] = tagged(var.decode_raw(bytes.fromhex(case["bytes"])))
            except Exception as e:
                result["decoded"] = {"error": f"{type(e).__name__}: {e}"}
        out.append(result)
    json.dump({"canopen": canopen.__version__, "results": out}, sys.stdout)


main()
