#!/usr/bin/env python3
"""Exits 0 when two double x y z nx ny nz PLY files (as `pnf demo` and `pnf filter` write them)
hold the same rows, bit for bit, in any order: the test that a result does not depend on the
input's row order. Usage: same_rows.py A B"""
import sys


def rows(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    count = int([l for l in header.splitlines() if l.startswith("element vertex")][0].split()[2])
    return sorted(data[end + 48 * i:end + 48 * (i + 1)] for i in range(count))


a, b = rows(sys.argv[1]), rows(sys.argv[2])
if a != b:
    differ = sum(1 for x, y in zip(a, b) if x != y) + abs(len(a) - len(b))
    sys.exit(f"{sys.argv[1]} and {sys.argv[2]}: {differ} of {max(len(a), len(b))} sorted rows differ")
