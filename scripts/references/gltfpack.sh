#!/usr/bin/env bash
# Re-encodes the animated Khronos samples with gltfpack, the meshoptimizer project's glTF
# optimiser, as web pipelines deliver glTF: positions, normals, texture coordinates and morph
# displacements quantised to bytes and shorts (KHR_mesh_quantization, which the files then
# require), dequantised by their nodes' transforms (NAME.glb); and the same compressed as well
# (`-cc`: EXT_meshopt_compression with its octahedral, quaternion and exponential filters,
# NAME.cc.glb). The outputs are checked in beside the originals
# (crates/demo/assets/animated/gltfpack/); tests/cycles_reference.rs holds them to the Cycles
# references of the originals, so an independent encoder checks raystage's decoding.
#
# It also writes the grove (scripts/references/grove.py: one tree placed by 24 nodes) and has
# gltfpack gather its trees into one node whose mesh EXT_mesh_gpu_instancing repeats (`-mi`);
# crates/gltf-import/tests/import.rs holds the two to the same image.
#
# Needs Node.js and npm; gltfpack is fetched from the npm registry at the pinned version.
# `-af 0` keeps the animations' keyframes as they are (gltfpack resamples them at 30 Hz by
# default, which would change the pose at the compared times).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
assets="$root/crates/demo/assets/animated"
mkdir -p "$assets/gltfpack"
for name in BoxAnimated RiggedSimple AnimatedMorphCube; do
    npx --yes gltfpack@1.3.0 -i "$assets/$name.glb" -o "$assets/gltfpack/$name.glb" -af 0
    npx --yes gltfpack@1.3.0 -i "$assets/$name.glb" -o "$assets/gltfpack/$name.cc.glb" -af 0 -cc
done
python3 "$root/scripts/references/grove.py" "$root/crates/demo/assets/instanced/grove.gltf"
npx --yes gltfpack@1.3.0 -i "$root/crates/demo/assets/instanced/grove.gltf" -o "$root/crates/demo/assets/instanced/grove.instanced.glb" -mi
