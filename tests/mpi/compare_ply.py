#!/usr/bin/env python3
"""Says how two binary_little_endian PLY files differ, for the MPI tests' failure messages (the
distributed filter writes one process's bytes; docs/method.md, "Distributed runs (MPI)"): every
byte but the vertex normals must be equal, and each normal within TOLERANCE degrees. Usage:
compare_ply.py EXPECTED ACTUAL [TOLERANCE_DEG]. Prints the largest angle; exits 1 on any
difference."""
import math
import struct
import sys

TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h", "ushort": "H",
         "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I", "float": "f", "float32": "f",
         "double": "d", "float64": "d"}


def layout(data):
    end = data.index(b"end_header\n") + len(b"end_header\n")
    elements = []
    for line in data[:end].decode("ascii").splitlines():
        t = line.split()
        if t and t[0] == "element":
            elements.append([t[1], int(t[2]), []])
        elif t and t[0] == "property":
            if t[1] == "list":
                sys.exit("compare_ply.py: list properties are not supported")
            elements[-1][2].append((t[2], TYPES[t[1]]))
    return end, elements


def main():
    expected, actual = (open(p, "rb").read() for p in sys.argv[1:3])
    tolerance = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-3
    end, elements = layout(expected)
    if actual[:end] != expected[:end]:
        sys.exit("headers differ")
    if len(actual) != len(expected):
        sys.exit(f"sizes differ: {len(expected)} and {len(actual)} bytes")
    offset, worst, identical = end, 0.0, True
    for name, count, props in elements:
        fmt = "<" + "".join(t for _, t in props)
        size = struct.calcsize(fmt)
        names = [n for n, _ in props]
        normal = []
        for fields in (("nx", "ny", "nz"), ("normal_x", "normal_y", "normal_z")):  # PLY's, PCL's
            if name == "vertex" and fields[0] in names:
                normal = [names.index(n) for n in fields]
        for r in range(count):
            a = struct.unpack_from(fmt, expected, offset + r * size)
            b = struct.unpack_from(fmt, actual, offset + r * size)
            for i in range(len(props)):
                if i not in normal and struct.pack("<" + props[i][1], a[i]) != struct.pack("<" + props[i][1], b[i]):
                    sys.exit(f"{name} {r} property {names[i]} differs: {a[i]!r} and {b[i]!r}")
            if normal:
                u = [a[i] for i in normal]
                v = [b[i] for i in normal]
                identical = identical and u == v
                cross = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
                angle = math.degrees(math.atan2(math.sqrt(sum(c * c for c in cross)), sum(x * y for x, y in zip(u, v))))
                worst = max(worst, angle)
        offset += count * size
    print(f"compare_ply.py: other bytes identical; normals {'bit-identical' if identical else 'differ'}, "
          f"largest angle {worst:.3g} deg (tolerance {tolerance:g})")
    if worst > tolerance:
        sys.exit(1)


main()
