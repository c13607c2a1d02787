#!/usr/bin/env python3
"""Writes a double x y z nx ny nz PLY (as `pnf demo` writes it) with its vertices in a random
row order, for the tests that a result does not depend on the input's row order.
Usage: shuffle_ply.py IN OUT SEED"""
import random
import sys

data = open(sys.argv[1], "rb").read()
end = data.index(b"end_header\n") + len(b"end_header\n")
count = int([l for l in data[:end].decode().splitlines() if l.startswith("element vertex")][0].split()[2])
rows = [data[end + 48 * i:end + 48 * (i + 1)] for i in range(count)]
random.Random(int(sys.argv[3])).shuffle(rows)
open(sys.argv[2], "wb").write(data[:end] + b"".join(rows) + data[end + 48 * count:])
