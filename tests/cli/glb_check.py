#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Checks a .glb as lasmesh writes it, independently of lasmesh's own reader: the GLB container
(header, 4-byte aligned JSON and BIN chunks), the glTF 2.0 members a Draco-compressed mesh needs
(KHR_draco_mesh_compression used and required, accessors without bufferView, POSITION bounds,
normalized 16-bit COLOR_0, the Z-up to Y-up node), or a plain file's aligned buffer views; the
origin in extras, names, double-sided material. For a Draco file, writes the primitive's Draco
bytes to DRACO_OUT. Prints the mesh origin (the node translation turned back to Z-up), the POSITION count and the
index count.
POSITION's min and max must be the bounds of the positions: exactly, read from the BIN chunk, for
a plain file; for a Draco file, within 1e-5 of the extent of the vertices of DECODED_OBJ (the
Draco bytes through draco_decoder) when it is given.
Usage: glb_check.py FILE.glb DRACO_OUT [DECODED_OBJ]"""
import json
import math
import struct
import sys

path, draco_out = sys.argv[1], sys.argv[2]
decoded_obj = sys.argv[3] if len(sys.argv) > 3 else None
data = open(path, "rb").read()
magic, version, length = struct.unpack_from("<4sII", data, 0)
assert magic == b"glTF" and version == 2, (magic, version)
assert length == len(data), (length, len(data))
json_length, json_type = struct.unpack_from("<II", data, 12)
assert json_type == 0x4E4F534A and json_length % 4 == 0, (hex(json_type), json_length)
gltf = json.loads(data[20 : 20 + json_length])  # fails on padding other than spaces (NUL, say)
bin_at = 20 + json_length
bin_length, bin_type = struct.unpack_from("<II", data, bin_at)
assert bin_type == 0x004E4942 and bin_length % 4 == 0 and bin_at + 8 + bin_length == len(data)
binary = data[bin_at + 8 :]

assert gltf["asset"]["version"] == "2.0"
ext = "KHR_draco_mesh_compression"
draco_file = ext in gltf.get("extensionsUsed", [])
if draco_file:
    assert ext in gltf["extensionsUsed"] and ext in gltf["extensionsRequired"]
scene = gltf["scenes"][gltf.get("scene", 0)]
assert scene["nodes"] == [0]
node = gltf["nodes"][0]
h = math.sqrt(0.5)
assert all(abs(a - b) < 1e-12 for a, b in zip(node["rotation"], [-h, 0, 0, h])), node["rotation"]
# The origin: in the extras (LAS axes) and, with --glb-origin node, as the translation (glTF axes).
extras = node.get("extras", {})
if "origin" in extras:
    o = extras["origin"]
    assert scene["extras"]["origin"] == o
    assert extras["origin_gltf"] == [o[0], o[2], -o[1]]
    t = node.get("translation", extras["origin_gltf"])
    assert t == extras["origin_gltf"], (t, extras["origin_gltf"])
else:
    t = node["translation"]
assert len(t) == 3
# Named after the input, double-sided.
assert node.get("name") and gltf["meshes"][node["mesh"]].get("name") == node["name"], node

mesh = gltf["meshes"][node["mesh"]]
assert len(mesh["primitives"]) == 1
primitive = mesh["primitives"][0]
assert primitive.get("mode", 4) == 4
assert gltf["materials"][primitive["material"]].get("doubleSided") is True
material = gltf["materials"][primitive["material"]]["pbrMetallicRoughness"]
assert material["metallicFactor"] == 0 and material["roughnessFactor"] == 1
accessors = gltf["accessors"]
if draco_file:
    draco = primitive["extensions"][ext]
    assert set(draco["attributes"]) == set(primitive["attributes"]), "extension and primitive attributes differ"
position = accessors[primitive["attributes"]["POSITION"]]
assert position["componentType"] == 5126 and position["type"] == "VEC3"
assert len(position["min"]) == 3 and len(position["max"]) == 3
assert all(lo <= hi for lo, hi in zip(position["min"], position["max"]))
if "COLOR_0" in primitive["attributes"]:
    color = accessors[primitive["attributes"]["COLOR_0"]]
    assert color["componentType"] == 5123 and color.get("normalized") is True and color["type"] == "VEC3"
    assert color["count"] == position["count"]
if "NORMAL" in primitive["attributes"]:
    normal = accessors[primitive["attributes"]["NORMAL"]]
    assert normal["componentType"] == 5126 and normal["type"] == "VEC3" and normal["count"] == position["count"]
indices = accessors[primitive["indices"]]
assert indices["componentType"] in (5121, 5123, 5125) and indices["type"] == "SCALAR" and indices["count"] % 3 == 0
# 16-bit indices whenever they fit (assimp reads only those from a Draco primitive).
assert (indices["componentType"] == 5123) == (position["count"] <= 65535), (indices["componentType"], position["count"])
if not draco_file:  # plain: every accessor in its own 4-byte aligned view of the BIN chunk
    for a in accessors:
        v = gltf["bufferViews"][a["bufferView"]]
        assert v.get("byteOffset", 0) % 4 == 0 and v["byteOffset"] + v["byteLength"] <= bin_length
    v = gltf["bufferViews"][position["bufferView"]]
    stride = v.get("byteStride", 12)
    at = v.get("byteOffset", 0) + position.get("byteOffset", 0)
    xyz = [struct.unpack_from("<3f", binary, at + stride * i) for i in range(position["count"])]
    lo = [min(p[k] for p in xyz) for k in range(3)]
    hi = [max(p[k] for p in xyz) for k in range(3)]
    # As float32: the JSON numbers must read back as the exact float bounds.
    f32 = lambda x: struct.unpack("<f", struct.pack("<f", x))[0]
    assert [f32(x) for x in position["min"]] == lo and [f32(x) for x in position["max"]] == hi, (position["min"], lo, position["max"], hi)
    print(f"{t[0]!r},{-t[2]!r},{t[1]!r} {position['count']} {indices['count']}")
    sys.exit(0)
for a in accessors:
    assert "bufferView" not in a, "a Draco accessor with a bufferView"

view = gltf["bufferViews"][draco["bufferView"]]
assert view["buffer"] == 0 and len(gltf["buffers"]) == 1 and "uri" not in gltf["buffers"][0]
assert gltf["buffers"][0]["byteLength"] <= bin_length <= gltf["buffers"][0]["byteLength"] + 3
start = view.get("byteOffset", 0)
assert start + view["byteLength"] <= gltf["buffers"][0]["byteLength"]
open(draco_out, "wb").write(binary[start : start + view["byteLength"]])
if decoded_obj:
    xyz = [[float(x) for x in line.split()[1:4]] for line in open(decoded_obj) if line.startswith("v ")]
    lo = [min(p[k] for p in xyz) for k in range(3)]
    hi = [max(p[k] for p in xyz) for k in range(3)]
    extent = max(h - l for l, h in zip(lo, hi))
    assert all(abs(a - b) <= 1e-5 * extent for a, b in zip(position["min"] + position["max"], lo + hi)), (position["min"], lo, position["max"], hi)
# glTF (x, y, z) = LAS (x, z, -y): the origin is (tx, -tz, ty).
print(f"{t[0]!r},{-t[2]!r},{t[1]!r} {position['count']} {indices['count']}")
