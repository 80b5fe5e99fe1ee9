#!/usr/bin/env python3
"""Renders the reference image of the classic Cornell box with Mitsuba 3.

The room comes from raystage's own glTF (`cargo run -p raystage-demo --example
write_cornell_box -- room.gltf`, or `-- --spheres spheres.gltf` for the room with a million
triangles of spheres), so that both renderers read the very same arrays: every
primitive becomes a Mitsuba mesh with a two-sided diffuse BSDF of its base colour, the emissive
one an area light of its emissive colour × strength (one-sided, as glTF's triangle fronts face),
and the glTF camera a perspective sensor with its vertical field of view. Mitsuba's path
tracer (`max_depth` 64, Russian roulette from depth 5, unbiased) renders it through a box filter
of one pixel, and the image is written as a little-endian PFM of linear RGB.

    pip install mitsuba numpy
    python3 scripts/references/cornell_box.py room.gltf out.pfm --size 64 --spp 32768

Mitsuba's scalar variant needs nothing else; `--variant llvm_ad_rgb` needs LLVM (see the
path-tracing benchmark in docs/performance.md).
"""

import argparse
import base64
import json
import math
import os
import sys
import tempfile
import time

import numpy as np


def read_gltf(path):
    """The document and its one buffer (inline `data:` URI or a file beside it)."""
    with open(path) as f:
        doc = json.load(f)
    uri = doc["buffers"][0]["uri"]
    if uri.startswith("data:"):
        data = base64.b64decode(uri.split(",", 1)[1])
    else:
        with open(os.path.join(os.path.dirname(path), uri), "rb") as f:
            data = f.read()
    return doc, data


def accessor(doc, data, index):
    """An accessor's values: float VEC3 positions or uint32 scalars, as numpy arrays."""
    a = doc["accessors"][index]
    view = doc["bufferViews"][a["bufferView"]]
    offset = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    if a["componentType"] == 5126:
        return np.frombuffer(data, dtype="<f4", count=a["count"] * 3, offset=offset).reshape(-1, 3)
    if a["componentType"] == 5125:
        return np.frombuffer(data, dtype="<u4", count=a["count"], offset=offset)
    sys.exit(f"accessor {index}: component type {a['componentType']} is not read here")


def write_ply(path, positions, indices):
    """A binary PLY of one triangle mesh, as Mitsuba reads it."""
    faces = indices.reshape(-1, 3)
    with open(path, "wb") as f:
        f.write(
            (
                "ply\nformat binary_little_endian 1.0\n"
                f"element vertex {len(positions)}\nproperty float x\nproperty float y\nproperty float z\n"
                f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
            ).encode()
        )
        f.write(positions.astype("<f4").tobytes())
        # Each face as PLY lists it, a count byte then three indices: one packed array for a
        # million faces rather than a million writes.
        records = np.empty(len(faces), dtype=[("count", "u1"), ("indices", "<i4", (3,))])
        records["count"] = 3
        records["indices"] = faces
        f.write(records.tobytes())


def rotate(q, v):
    """Vector `v` turned by the unit quaternion `q` (x, y, z, w)."""
    x, y, z, w = q
    u = np.array([x, y, z])
    v = np.asarray(v, dtype=float)
    return 2.0 * np.dot(u, v) * u + (w * w - np.dot(u, u)) * v + 2.0 * w * np.cross(u, v)


def scene_dict(mi, doc, data, folder, size, spp):
    scene = {"type": "scene", "integrator": {"type": "path", "max_depth": 64}}
    for k, prim in enumerate(doc["meshes"][0]["primitives"]):
        positions = accessor(doc, data, prim["attributes"]["POSITION"])
        indices = accessor(doc, data, prim["indices"])
        ply = os.path.join(folder, f"mesh{k}.ply")
        write_ply(ply, positions, indices)
        material = doc["materials"][prim["material"]]
        pbr = material["pbrMetallicRoughness"]
        specular = material.get("extensions", {}).get("KHR_materials_specular", {}).get("specularFactor", 1.0)
        if pbr.get("metallicFactor", 1.0) != 0.0 or specular != 0.0:
            sys.exit(f"material {material.get('name')}: only Lambertian materials (metallic 0, KHR_materials_specular factor 0) are translated")
        base = pbr["baseColorFactor"][:3]
        shape = {
            "type": "ply",
            "filename": ply,
            "face_normals": True,
            "bsdf": {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": base}}},
        }
        emissive = material.get("emissiveFactor", [0.0, 0.0, 0.0])
        strength = material.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
        if max(emissive) > 0.0:
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": [c * strength for c in emissive]}}
        scene[f"shape{k}"] = shape
    scene["sensor"] = sensor(mi, doc, size, size, spp)
    return scene


def sensor(mi, doc, width, height, spp):
    """The file's first camera node as a Mitsuba perspective sensor of `width` × `height` pixels
    (vertical field of view, box filter of one pixel, `spp` independent samples per pixel)."""
    node = next(n for n in doc["nodes"] if "camera" in n)
    camera = doc["cameras"][node["camera"]]["perspective"]
    q = node.get("rotation", [0.0, 0.0, 0.0, 1.0])
    eye = np.array(node.get("translation", [0.0, 0.0, 0.0]))
    forward, up = rotate(q, [0.0, 0.0, -1.0]), rotate(q, [0.0, 1.0, 0.0])
    return {
        "type": "perspective",
        "fov_axis": "y",
        "fov": math.degrees(camera["yfov"]),
        "to_world": mi.ScalarTransform4f().look_at(origin=eye.tolist(), target=(eye + forward).tolist(), up=up.tolist()),
        "sampler": {"type": "independent", "sample_count": spp},
        "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"}, "pixel_format": "rgb"},
    }


def write_pfm(path, image):
    """Linear RGB as a little-endian PFM (rows bottom to top, as the format has them)."""
    height, width, _ = image.shape
    with open(path, "wb") as f:
        f.write(f"PF\n{width} {height}\n-1.0\n".encode())
        f.write(np.ascontiguousarray(image[::-1], dtype="<f4").tobytes())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("gltf")
    parser.add_argument("out")
    parser.add_argument("--size", type=int, default=64)
    parser.add_argument("--spp", type=int, default=16384)
    parser.add_argument("--variant", default="scalar_rgb")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--threads", type=int, default=0, help="render threads (0: every core)")
    parser.add_argument("--time", action="store_true", help="print the render's seconds (scene loading left out) as JSON")
    args = parser.parse_args()
    try:
        import mitsuba as mi
    except ImportError:
        sys.exit("Mitsuba 3 is not installed: pip install mitsuba numpy")
    import drjit as dr

    mi.set_variant(args.variant)
    if args.threads > 0:
        dr.set_thread_count(args.threads)
    doc, data = read_gltf(args.gltf)
    with tempfile.TemporaryDirectory() as folder:
        scene = mi.load_dict(scene_dict(mi, doc, data, folder, args.size, args.spp))
        start = time.perf_counter()
        image = np.array(mi.render(scene, seed=args.seed))
        seconds = time.perf_counter() - start
    write_pfm(args.out, image[:, :, :3])
    if args.time:
        print(json.dumps({"seconds": seconds}))


if __name__ == "__main__":
    main()
