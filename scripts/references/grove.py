#!/usr/bin/env python3
"""Writes the grove: one low cone (a tree, 32 triangles, with normals) placed by 24 nodes, each
turned, scaled and moved, under a root node that is itself moved, on a ground quad; the glTF
that `gltfpack -mi` (scripts/references/gltfpack.sh) turns into one node whose mesh
EXT_mesh_gpu_instancing repeats. crates/gltf-import/tests/import.rs renders both and holds them
to the same image. Python's standard library only; deterministic."""

import base64
import json
import math
import struct
import sys

SIDES = 16


def cone():
    """Positions, normals and indices of a cone of radius 0.5 and height 1.5 standing on y = 0:
    its side as SIDES triangles with smooth normals, its base as SIDES triangles facing down."""
    positions, normals, indices = [], [], []
    slope = 0.5 / 1.5
    for k in range(SIDES):
        a0, a1 = 2 * math.pi * k / SIDES, 2 * math.pi * (k + 1) / SIDES
        am = (a0 + a1) / 2
        base = len(positions)
        for a, y in ((a0, 0.0), (a1, 0.0), (am, 1.5)):
            r = 0.5 if y == 0.0 else 0.0
            positions.append((r * math.cos(a), y, r * math.sin(a)))
            n = (math.cos(a), slope, math.sin(a))
            length = math.sqrt(sum(c * c for c in n))
            normals.append(tuple(c / length for c in n))
        indices += [base, base + 2, base + 1]
        base = len(positions)
        for a in (a0, a1):
            positions.append((0.5 * math.cos(a), 0.0, 0.5 * math.sin(a)))
            normals.append((0.0, -1.0, 0.0))
        positions.append((0.0, 0.0, 0.0))
        normals.append((0.0, -1.0, 0.0))
        indices += [base, base + 1, base + 2]
    return positions, normals, indices


def main(out):
    positions, normals, indices = cone()
    ground = [(-4.0, 0.0, -4.0), (4.0, 0.0, -4.0), (4.0, 0.0, 4.0), (-4.0, 0.0, 4.0)]
    bin_ = bytearray()
    views, accessors = [], []

    def add(data, count, kind, component, bounds=None):
        views.append({"buffer": 0, "byteOffset": len(bin_), "byteLength": len(data)})
        bin_.extend(data)
        while len(bin_) % 4:
            bin_.append(0)
        accessor = {"bufferView": len(views) - 1, "count": count, "type": kind, "componentType": component}
        if bounds:
            accessor["min"], accessor["max"] = bounds
        accessors.append(accessor)
        return len(accessors) - 1

    def bounds(points):
        return [min(p[i] for p in points) for i in range(3)], [max(p[i] for p in points) for i in range(3)]

    floats = lambda values: struct.pack(f"<{len(values)}f", *values)
    cone_p = add(floats([c for p in positions for c in p]), len(positions), "VEC3", 5126, bounds(positions))
    cone_n = add(floats([c for n in normals for c in n]), len(normals), "VEC3", 5126)
    cone_i = add(struct.pack(f"<{len(indices)}H", *indices), len(indices), "SCALAR", 5123)
    ground_p = add(floats([c for p in ground for c in p]), 4, "VEC3", 5126, bounds(ground))
    ground_n = add(floats([0.0, 1.0, 0.0] * 4), 4, "VEC3", 5126)
    ground_i = add(struct.pack("<6H", 0, 2, 1, 0, 3, 2), 6, "SCALAR", 5123)

    trees = []
    for k in range(24):
        row, column = divmod(k, 6)
        angle = 0.7 * k
        turn = (0.0, math.sin(angle / 2), 0.0, math.cos(angle / 2))
        size = 0.6 + 0.05 * ((k * 7) % 9)
        trees.append({
            "mesh": 0,
            "translation": [-3.0 + 1.2 * column + 0.2 * (row % 2), 0.0, -2.0 + 1.3 * row],
            "rotation": list(turn),
            "scale": [size, size * (1.0 + 0.1 * (k % 3)), size],
        })
    document = {
        "asset": {"version": "2.0", "generator": "scripts/references/grove.py"},
        "buffers": [{"byteLength": len(bin_), "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(bin_)).decode()}],
        "bufferViews": views,
        "accessors": accessors,
        "materials": [
            {"name": "leaves", "pbrMetallicRoughness": {"baseColorFactor": [0.15, 0.5, 0.2, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8}},
            {"name": "ground", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.45, 0.35, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}},
        ],
        "meshes": [
            {"name": "tree", "primitives": [{"attributes": {"POSITION": cone_p, "NORMAL": cone_n}, "indices": cone_i, "material": 0}]},
            {"name": "ground", "primitives": [{"attributes": {"POSITION": ground_p, "NORMAL": ground_n}, "indices": ground_i, "material": 1}]},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "aspectRatio": 1.5, "znear": 0.1}}],
        # The camera at (0, 6, 9), looking down at the origin: turned about x by atan(6 / 9).
        "nodes": [
            {"name": "grove", "translation": [0.3, 0.0, -0.2], "children": list(range(3, 27))},
            {"mesh": 1},
            {"camera": 0, "translation": [0.0, 6.0, 9.0], "rotation": [-math.sin(math.atan2(6, 9) / 2), 0.0, 0.0, math.cos(math.atan2(6, 9) / 2)]},
        ]
        + trees,
        "scenes": [{"nodes": [0, 1, 2]}],
        "scene": 0,
    }
    with open(out, "w") as f:
        json.dump(document, f)


if __name__ == "__main__":
    main(sys.argv[1])
