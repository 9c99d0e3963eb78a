#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""An independent minimal PLY reader for the tests: parses the header and body of a binary or
ASCII PLY as lasmesh writes it and checks it against expectations given as arguments.
Usage: ply_check.py FILE.ply CLOUD_MIN_X,Y,Z CLOUD_MAX_X,Y,Z CELL [R,G,B]"""
import os
import struct
import sys

path, lo, hi, cell = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
color = [int(c) for c in sys.argv[5].split(",")] if len(sys.argv) > 5 else None
data = open(path, "rb").read()
end = data.index(b"end_header\n") + len(b"end_header\n")
header = data[:end].decode("ascii").splitlines()
assert header[0] == "ply", header[0]
fmt = header[1].split()[1]
origin = [float(v) for v in next(l for l in header if l.startswith("comment origin")).split()[2:]]
vertices = int(next(l for l in header if l.startswith("element vertex")).split()[2])
faces = int(next(l for l in header if l.startswith("element face")).split()[2])
has_color = "property uchar red" in header
has_normals = "property float nx" in header  # nx, ny, nz (float) between x, y, z and the colour
color_at = 24 if has_normals else 12
normals = []
body = data[end:]
points, tris, colors = [], [], []
if fmt == "binary_little_endian":
    stride = color_at + (3 if has_color else 0)
    for v in range(vertices):
        points.append(struct.unpack_from("<3f", body, v * stride))
        if has_normals:
            normals.append(struct.unpack_from("<3f", body, v * stride + 12))
        if has_color:
            colors.append(tuple(body[v * stride + color_at : v * stride + color_at + 3]))
    at = vertices * stride
    for f in range(faces):
        n, a, b, c = struct.unpack_from("<B3i", body, at)
        assert n == 3
        tris.append((a, b, c))
        at += 13
    assert at == len(body), "trailing bytes"
else:
    lines = body.decode("ascii").splitlines()
    for line in lines[:vertices]:
        parts = line.split()
        points.append(tuple(float(p) for p in parts[:3]))
        if has_normals:
            normals.append(tuple(float(p) for p in parts[3:6]))
        if has_color:
            first = 6 if has_normals else 3
            colors.append(tuple(int(p) for p in parts[first : first + 3]))
    for line in lines[vertices:]:
        parts = [int(p) for p in line.split()]
        assert parts[0] == 3
        tris.append(tuple(parts[1:]))
    assert len(tris) == faces
assert vertices > 0 and faces > 0
assert all(0 <= i < vertices for t in tris for i in t), "index out of range"
# Every edge used exactly twice, in opposite directions: a closed, oriented surface.
directed = {}
for a, b, c in tris:
    for e in ((a, b), (b, c), (c, a)):
        directed[e] = directed.get(e, 0) + 1
assert all(n == 1 for n in directed.values()), "an edge used twice in one direction"
# OPEN=1: an open sheet (lasmesh's default surface) may have boundary edges.
if os.environ.get("OPEN") != "1":
    assert all((b, a) in directed for (a, b) in directed), "boundary edge"
# The mesh's bounding box lies within one cell of the cloud's.
lo = [float(v) for v in lo.split(",")]
hi = [float(v) for v in hi.split(",")]
for axis in range(3):
    mn = min(p[axis] for p in points) + origin[axis]
    mx = max(p[axis] for p in points) + origin[axis]
    assert abs(mn - lo[axis]) <= cell and abs(mx - hi[axis]) <= cell, (axis, mn, mx, lo[axis], hi[axis], cell)
# Normals: unit length, and pointing where the faces around each vertex face.
if has_normals:
    assert len(normals) == vertices
    assert all(abs(sum(c * c for c in n) - 1) < 1e-4 for n in normals), "a normal is not unit length"
    facing = [[0.0, 0.0, 0.0] for _ in range(vertices)]
    for t in tris:
        a, b, c = (points[i] for i in t)
        u = [b[k] - a[k] for k in range(3)]
        v = [c[k] - a[k] for k in range(3)]
        n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        for i in t:
            for k in range(3):
                facing[i][k] += n[k]
    agree = sum(1 for n, f in zip(normals, facing) if sum(n[k] * f[k] for k in range(3)) > 0)
    assert agree >= 0.999 * vertices, f"only {agree} of {vertices} normals agree with the winding"
if color is not None:
    assert has_color and set(colors) == {tuple(color)}, set(colors)
print(f"{path}: {vertices} vertices, {faces} triangles, closed and oriented" + (", normals" if has_normals else ""))
