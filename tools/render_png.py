#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Renders a binary PLY mesh (lasmesh's, or a `lasmesh compare --heatmap`) to a PNG picture:
an orthographic view from above and the side (yaw, pitch in degrees), z-buffered, flat shaded
with the vertex colours. Pure Python, no dependencies: for the pictures in docs/.

Usage: tools/render_png.py MESH.ply OUT.png [--width 1200] [--yaw -35] [--pitch 55]
                           [--crop x0,y0,x1,y1]  (a window of the mesh's x/y, in its units)
"""
import argparse
import math
import struct
import zlib


def read_ply(path):
    with open(path, "rb") as f:
        header = []
        while not header or header[-1] != "end_header":
            header.append(f.readline().decode().strip())
        props, counts, current = {}, {}, None
        for line in header:
            words = line.split()
            if words[0] == "element":
                current = words[1]
                counts[current] = int(words[2])
                props[current] = []
            elif words[0] == "property" and words[1] != "list":
                props[current].append((words[2], words[1]))
        sizes = {"float": "f", "uchar": "B", "double": "d", "int": "i", "uint": "I"}
        vfmt = "<" + "".join(sizes[t] for _, t in props["vertex"])
        names = [n for n, _ in props["vertex"]]
        vsize = struct.calcsize(vfmt)
        data = f.read(vsize * counts["vertex"])
        verts = [struct.unpack_from(vfmt, data, i * vsize) for i in range(counts["vertex"])]
        ix, iy, iz = names.index("x"), names.index("y"), names.index("z")
        has_color = "red" in names
        positions = [(v[ix], v[iy], v[iz]) for v in verts]
        colors = [(v[names.index("red")], v[names.index("green")], v[names.index("blue")]) for v in verts] if has_color \
            else [(200, 200, 200)] * len(verts)
        faces = []
        for _ in range(counts["face"]):
            n = f.read(1)[0]
            faces.append(struct.unpack("<%di" % n, f.read(4 * n)))
    return positions, colors, faces


def write_png(path, width, height, pixels):
    raw = b"".join(b"\x00" + bytes(pixels[y * width * 3:(y + 1) * width * 3]) for y in range(height))
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("mesh")
    parser.add_argument("png")
    parser.add_argument("--width", type=int, default=1200)
    parser.add_argument("--yaw", type=float, default=-35)
    parser.add_argument("--pitch", type=float, default=55)
    parser.add_argument("--crop")
    a = parser.parse_args()
    positions, colors, faces = read_ply(a.mesh)
    if a.crop:
        x0, y0, x1, y1 = map(float, a.crop.split(","))
        faces = [f for f in faces if all(x0 <= positions[i][0] <= x1 and y0 <= positions[i][1] <= y1 for i in f)]
    yaw, pitch = math.radians(a.yaw), math.radians(a.pitch)
    cy, sy, cp, sp = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch)

    def view(p):  # rotate about z by yaw, then tilt by pitch; screen x right, y up, depth towards viewer
        # The viewer looks along (0, cos pitch, -sin pitch) in the rotated frame: forward and down,
        # so a higher point is nearer (at pitch 90, straight down, depth is z).
        x, y, z = p
        x1, y1 = cy * x - sy * y, sy * x + cy * y
        return x1, cp * z + sp * y1, sp * z - cp * y1

    used = sorted({i for f in faces for i in f})
    projected = {i: view(positions[i]) for i in used}
    xs = [projected[i][0] for i in used]
    ys = [projected[i][1] for i in used]
    scale = (a.width - 20) / max(1e-9, max(xs) - min(xs))
    width = a.width
    height = int((max(ys) - min(ys)) * scale) + 20
    screen = {i: ((projected[i][0] - min(xs)) * scale + 10, (max(ys) - projected[i][1]) * scale + 10, projected[i][2])
              for i in used}
    depth = [-1e30] * (width * height)
    pixels = bytearray([255, 255, 255] * (width * height))
    light = (0.3, 0.5, 0.81)
    for f in faces:
        for k in range(1, len(f) - 1):
            tri = (f[0], f[k], f[k + 1])
            p = [positions[i] for i in tri]
            u = [p[1][j] - p[0][j] for j in range(3)]
            v = [p[2][j] - p[0][j] for j in range(3)]
            n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
            length = math.sqrt(sum(c * c for c in n)) or 1
            shade = 0.35 + 0.65 * abs(sum(n[j] * light[j] for j in range(3)) / length)  # two-sided
            col = [sum(colors[i][c] for i in tri) / 3 * shade for c in range(3)]
            s = [screen[i] for i in tri]
            x_lo, x_hi = max(0, int(min(q[0] for q in s))), min(width - 1, int(max(q[0] for q in s)) + 1)
            y_lo, y_hi = max(0, int(min(q[1] for q in s))), min(height - 1, int(max(q[1] for q in s)) + 1)
            area = (s[1][0] - s[0][0]) * (s[2][1] - s[0][1]) - (s[2][0] - s[0][0]) * (s[1][1] - s[0][1])
            if abs(area) < 1e-12:
                continue
            for py in range(y_lo, y_hi + 1):
                for px in range(x_lo, x_hi + 1):
                    cx, cyy = px + 0.5, py + 0.5
                    w0 = ((s[1][0] - cx) * (s[2][1] - cyy) - (s[2][0] - cx) * (s[1][1] - cyy)) / area
                    w1 = ((s[2][0] - cx) * (s[0][1] - cyy) - (s[0][0] - cx) * (s[2][1] - cyy)) / area
                    w2 = 1 - w0 - w1
                    if w0 < 0 or w1 < 0 or w2 < 0:
                        continue
                    z = w0 * s[0][2] + w1 * s[1][2] + w2 * s[2][2]
                    at = py * width + px
                    if z > depth[at]:
                        depth[at] = z
                        pixels[3 * at:3 * at + 3] = bytes(int(min(255, c)) for c in col)
    write_png(a.png, width, height, pixels)


if __name__ == "__main__":
    main()
