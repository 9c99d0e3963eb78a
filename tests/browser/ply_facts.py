# SPDX-License-Identifier: Apache-2.0
# What a lasmesh page should show of a binary little-endian PLY written by the same run, as JSON
# for html_page.js: the triangle count, every vertex in the file's coordinates (the header's
# origin comment added), the vertices to click (the highest, where the camera sees them), and the
# mean sRGB colour seen from above: up-facing triangles' mean vertex colour, weighted by their
# area in plan.
# Usage: python3 ply_facts.py MESH.ply > EXPECTED.json
import json
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
weights, total = [0.0, 0.0, 0.0], 0.0
for a, b, c in faces:
    pa, pb, pc = vertices[a], vertices[b], vertices[c]
    up = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0])  # twice the area in plan, signed
    area = abs(up) / 2
    for k in range(3):
        weights[k] += area * (colours[a][k] + colours[b][k] + colours[c][k]) / 3
    total += area
highest = sorted(range(len(vertices)), key=lambda v: -vertices[v][2])[:200]
json.dump({"triangles": len(faces), "vertices": vertices, "candidates": highest,
           "plan_colour": [w / total for w in weights]}, sys.stdout)
