# SPDX-License-Identifier: Apache-2.0
# What a lasmesh page should show of a binary little-endian PLY written by the same run, as JSON
# for html_page.js: the triangle count, every vertex in the file's coordinates (the header's
# origin comment added), the vertices to click (the highest, where the camera sees them), and the
# mean sRGB colour seen from above: the topmost surface's colour (interpolated between its
# triangle's vertices) at the centres of a plan lattice of 1000 cells along the longer side.
# Usage: python3 ply_facts.py MESH.ply > EXPECTED.json
import json
import math
import struct
import sys

types = {"float": "f", "float32": "f", "double": "d", "uchar": "B", "uint8": "B", "char": "b", "int8": "b",
         "ushort": "H", "uint16": "H", "short": "h", "int16": "h", "uint": "I", "uint32": "I", "int": "i", "int32": "i"}
data = open(sys.argv[1], "rb").read()
end = data.index(b"end_header\n") + len(b"end_header\n")
origin, elements = [0.0, 0.0, 0.0], []
for line in data[:end].decode("ascii").splitlines():
    words = line.split()
    if words[:2] == ["comment", "origin"]:
        origin = [float(w) for w in words[2:5]]
    elif words[:1] == ["element"]:
        elements.append((words[1], int(words[2]), []))
    elif words[:1] == ["property"]:
        elements[-1][2].append(words[1:])
at = end
vertices, colours, faces = [], [], []
for name, count, properties in elements:
    if name == "vertex":
        names = [p[-1] for p in properties]
        layout = "<" + "".join(types[p[0]] for p in properties)
        size = struct.calcsize(layout)
        for i in range(count):
            row = dict(zip(names, struct.unpack_from(layout, data, at + i * size)))
            vertices.append([origin[0] + row["x"], origin[1] + row["y"], origin[2] + row["z"]])
            colours.append([row.get("red", 180), row.get("green", 180), row.get("blue", 180)])
        at += count * size
    elif name == "face":
        count_type, index_type = types[properties[0][1]], types[properties[0][2]]
        for i in range(count):
            n = struct.unpack_from("<" + count_type, data, at)[0]
            at += struct.calcsize(count_type)
            faces.append(struct.unpack_from("<" + index_type * n, data, at))
            at += n * struct.calcsize(index_type)
xs, ys = [v[0] for v in vertices], [v[1] for v in vertices]
x0, y0 = min(xs), min(ys)
step = max(max(xs) - x0, max(ys) - y0, 1e-9) / 1000
top = {}  # lattice cell -> (height, colour) of the topmost triangle over its centre
for a, b, c in faces:
    pa, pb, pc = vertices[a], vertices[b], vertices[c]
    twice = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0])  # twice the area in plan, signed
    if abs(twice) < 1e-12:
        continue  # seen edge-on from above
    first = [math.ceil((min(p[k] for p in (pa, pb, pc)) - o) / step - 0.5) for k, o in ((0, x0), (1, y0))]
    last = [math.floor((max(p[k] for p in (pa, pb, pc)) - o) / step - 0.5) for k, o in ((0, x0), (1, y0))]
    for i in range(first[0], last[0] + 1):
        x = x0 + (i + 0.5) * step
        for j in range(first[1], last[1] + 1):
            y = y0 + (j + 0.5) * step
            wb = ((x - pa[0]) * (pc[1] - pa[1]) - (y - pa[1]) * (pc[0] - pa[0])) / twice
            wc = ((pb[0] - pa[0]) * (y - pa[1]) - (pb[1] - pa[1]) * (x - pa[0])) / twice
            wa = 1 - wb - wc
            if min(wa, wb, wc) < 0:
                continue
            z = wa * pa[2] + wb * pb[2] + wc * pc[2]
            if (i, j) not in top or top[(i, j)][0] < z:
                top[(i, j)] = (z, [wa * colours[a][k] + wb * colours[b][k] + wc * colours[c][k] for k in range(3)])
seen = max(len(top), 1)
highest = sorted(range(len(vertices)), key=lambda v: -vertices[v][2])[:200]
json.dump({"triangles": len(faces), "vertices": vertices, "candidates": highest,
           "plan_colour": [sum(t[1][k] for t in top.values()) / seen for k in range(3)]}, sys.stdout)
