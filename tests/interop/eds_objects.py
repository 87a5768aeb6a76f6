"""The objects python-canopen finds in an EDS/DCF, for tests/suite/eds_corpus.rs.

Usage: eds_objects.py FILE...  Prints one JSON document: for each file either
{"objects": [[index, subindex, data_type, name], ...]} or {"refused": "why"}.
Sub-index 0 of a VAR is its object; ARRAY/RECORD members are listed with their own
subindex. DOMAIN and types python-canopen does not know keep their code.
"""
import json
import sys

import canopen
from canopen.objectdictionary import ODArray, ODRecord, ODVariable


def objects(path):
    od = canopen.import_od(path)
    out = []
    for index in sorted(od.indices):
        obj = od[index]
        if isinstance(obj, ODVariable):
            out.append([index, 0, obj.data_type, obj.name])
        elif isinstance(obj, (ODArray, ODRecord)):
            for sub in sorted(obj.subindices):
                v = obj.subindices[sub]
                out.append([index, sub, v.data_type, v.name])
    return out


def main():
    result = {}
    for path in sys.argv[1:]:
        try:
            result[path] = {"objects": objects(path)}
        except Exception as e:  # any refusal, as the technician would see it
            result[path] = {"refused": f"{type(e).__name__}: {e}"}
    json.dump(result, sys.stdout)


if __name__ == "__main__":
    main()
