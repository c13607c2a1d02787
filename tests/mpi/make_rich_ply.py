#!/usr/bin/env python3
"""Rewrites a double x y z nx ny nz PLY as a richer one for the distributed I/O tests: float
positions and normals between other properties, a comment, and an element before and after the
vertices. Usage: make_rich_ply.py IN OUT"""
import struct
import sys

data = open(sys.argv[1], "rb").read()
end = data.index(b"end_header\n") + len(b"end_header\n")
count = int([l for l in data[:end].decode().splitlines() if l.startswith("element vertex")][0].split()[2])
rows = [struct.unpack_from("<6d", data, end + 48 * i) for i in range(count)]
header = (f"ply\nformat binary_little_endian 1.0\ncomment made by make_rich_ply.py\nelement camera 2\n"
          f"property float fx\nproperty int id\nelement vertex {count}\nproperty uchar red\nproperty float x\n"
          f"property float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
          f"property ushort quality\nelement marker 3\nproperty double value\nend_header\n")
body = bytearray(header.encode())
body += struct.pack("<fi", 1.5, 7) + struct.pack("<fi", -2.25, 9)
for i, r in enumerate(rows):
    body += struct.pack("<B6fH", i % 251, *r, (7 * i) % 65521)
body += struct.pack("<3d", 1.0, 2.0, 3.0)
open(sys.argv[2], "wb").write(body)
