#!/usr/bin/env python3
"""Renders reference images of glTF files with Blender's Cycles, as their authors see them.

Each file is read by Blender's own glTF importer (`bpy.ops.import_scene.gltf`, the Principled
BSDF it builds: multiple-scattering GGX, the base under an energy-preserving specular layer),
into an empty scene, and rendered through the file's camera by Cycles on the CPU: a fixed seed,
a fixed number of samples per pixel (no adaptive sampling), no denoiser, no clamping, no glossy
blur, caustics on, light paths up to 64 bounces of every kind, a box filter of one pixel, the
view transform "Standard". Camera rays that miss everything see black (a transparent film,
whose colour is premultiplied), as in raystage's references; the world lights the scene with a
uniform colour when the scene's `extras.environment` (raystage's material scenes) or
`--environment R,G,B` asks for one, else it is black. The image is rendered to a 32-bit OpenEXR,
read back linear and written as `NAME.pfm`, little-endian linear RGB, rows bottom to top; its
size is the scene's `extras.image_size`, else `--size`.

`--time SECONDS` renders the file's animation at that time, as the importer made it: the
importer keys glTF time t at frame t × fps (the scene's, 24) and stashes each animation on NLA
tracks named after it; asked (through its import hook) to leave them all stashed, so that every
node keeps its file's transform until then, it has the chosen one's actions made active by its
own `restore_animation_on_object` (`--animation NAME|INDEX`, default the first), and the scene
frame is set to time × fps, the fraction as a subframe. Node animation, skins (an armature
deforming the mesh) and morph targets (shape keys) are Blender's. The image is then
`NAME_TIMEs.pfm` (`box_animated_1.875s.pfm`).

Blender runs as a Python module (no Blender install), in a Python 3.11 environment outside the
repository:

    python3.11 -m venv ~/venv-bpy && ~/venv-bpy/bin/pip install bpy==5.0.1
    cargo run -p raystage-demo --example write_cycles_scenes -- scenes/
    cd scenes && for spp in 8192:cornell_box 4096:furnace_spheres 4096:material_spheres \\
        4096:normal_mapped_quad 4096:alpha_cutout 4096:vertex_colours 8192:transmission_spheres; do
      nice -n 10 ~/venv-bpy/bin/python ../scripts/references/cycles_gltf.py ${spp#*:}.gltf \\
        --out ../tests/references/ --prefix cycles_ --spp ${spp%:*} --linear-textures --front-emission
    done
    nice -n 10 ~/venv-bpy/bin/python ../scripts/references/cycles_gltf.py emitter_backs.gltf \\
        --out ../tests/references/ --prefix cycles_ --spp 16384
    for asset in box_animated:0.625:1.875 rigged_simple:0.5:1 animated_morph_cube:1:3; do
      for time in $(echo ${asset#*:} | tr : ' '); do
        nice -n 10 ~/venv-bpy/bin/python ../scripts/references/cycles_gltf.py ${asset%%:*}.glb \\
          --out ../tests/references/ --prefix cycles_ --spp 1024 --time $time --backface-culling
      done
    done

(the Cornell box, lit by a small light, at 8,192 samples per pixel: about 3 minutes on two
shared cores; the transmitting spheres at 8,192, 85 seconds; the others at 4,096, under 80
seconds each; the double-sided emitter at 16,384, 35 seconds; the animated assets, 160×120 at
1,024, 4 to 13 seconds each).

Three differences of convention between Cycles and raystage (and Mitsuba) are taken out by
options, which the checked-in references use: `--front-emission` (Cycles' emitters shine from
both sides, single-sided ones too; raystage's double-sided emitters do, its single-sided ones
shine from the front only, as Mitsuba's area lights: the scene of a double-sided emitter,
`emitter_backs`, is rendered without it), `--linear-textures` (Cycles filters 8-bit sRGB texels before decoding them) and
`--backface-culling` (Cycles shows the backs of glTF's single-sided materials).

Nothing here models a BSDF: the reference is what the importer and Cycles make of the file.
`--dump` prints the node tree the importer built for each material, to see what was imported.
Version 5.0.1 of `bpy` made the checked-in references (tests/references/cycles_*.pfm).
"""

import argparse
import json
import os
import struct
import sys
import tempfile
import time

import numpy as np


def read_document(path):
    """The glTF JSON of a .gltf or a .glb file."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"glTF":
        length, kind = struct.unpack_from("<II", data, 12)
        if kind != 0x4E4F534A:
            sys.exit(f"{path}: the first chunk of a .glb must be JSON")
        return json.loads(data[20 : 20 + length])
    return json.loads(data)


def write_pfm(path, image):
    """Linear RGB (rows bottom to top, as Blender's images and the format have them) as a
    little-endian PFM."""
    height, width, _ = image.shape
    with open(path, "wb") as f:
        f.write(f"PF\n{width} {height}\n-1.0\n".encode())
        f.write(np.ascontiguousarray(image, dtype="<f4").tobytes())


def reset(bpy):
    """An empty scene: no objects, no world, Blender's factory settings."""
    bpy.ops.wm.read_factory_settings(use_empty=True)


def camera_of(bpy, doc):
    """The imported camera, its vertical field of view set from the file's (the importer
    converts it to a lens and sensor; this keeps it exact whatever the aspect ratio)."""
    cameras = [o for o in bpy.context.scene.objects if o.type == "CAMERA"]
    if len(cameras) != 1:
        sys.exit(f"the file must hold one camera, it holds {len(cameras)}")
    camera = cameras[0]
    perspective = doc["cameras"][0].get("perspective")
    if perspective is None:
        sys.exit("the file's camera must be perspective")
    camera.data.sensor_fit = "VERTICAL"
    camera.data.angle_y = perspective["yfov"]
    camera.data.shift_x = camera.data.shift_y = 0.0
    return camera


def world(bpy, colour):
    """A world of uniform radiance `colour` (black: no light from it)."""
    w = bpy.data.worlds.new("environment")
    w.use_nodes = True
    background = next(n for n in w.node_tree.nodes if n.type == "BACKGROUND")
    background.inputs["Color"].default_value = (*colour, 1.0)
    background.inputs["Strength"].default_value = 1.0
    return w


def configure(bpy, scene, width, height, spp, seed, threads, depth):
    """Cycles as the references need it: unbiased, fixed, one-pixel box filter, linear."""
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = spp
    cycles.use_adaptive_sampling = False
    cycles.seed = seed
    cycles.use_animated_seed = False
    cycles.use_denoising = False
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0
    for bounces in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces", "transparent_max_bounces"):
        setattr(cycles, bounces, depth)
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.blur_glossy = 0.0
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    cycles.light_sampling_threshold = 0.0
    scene.render.film_transparent = True
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    scene.render.use_border = False
    scene.render.threads_mode = "FIXED" if threads > 0 else "AUTO"
    if threads > 0:
        scene.render.threads = threads
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"
    settings.color_mode = "RGBA"


def dump_materials(bpy):
    """What the importer made of each material: its nodes and their links."""
    for material in bpy.data.materials:
        if not material.use_nodes:
            continue
        print(f"  material {material.name!r}:")
        for node in material.node_tree.nodes:
            values = []
            for socket in node.inputs:
                if socket.is_linked or not hasattr(socket, "default_value"):
                    continue
                value = socket.default_value
                value = tuple(round(v, 4) for v in value) if hasattr(value, "__len__") else round(value, 4) if isinstance(value, float) else value
                if socket.name in ("Base Color", "Metallic", "Roughness", "IOR", "Specular IOR Level", "Emission Color", "Emission Strength", "Alpha", "Coat Weight", "Transmission Weight", "Sheen Weight"):
                    values.append(f"{socket.name}={value}")
            print(f"    {node.bl_idname} {node.name!r} {' '.join(values)}")
        for link in material.node_tree.links:
            print(f"    {link.from_node.name}.{link.from_socket.name} -> {link.to_node.name}.{link.to_socket.name}")


def linear_textures(bpy):
    """Every 8-bit sRGB image replaced by its linear float decoding, so that Cycles filters
    linear values, as glTF asks (and raystage and Mitsuba do): Cycles keeps an 8-bit sRGB image
    in 8 bits and filters the encoded values before decoding them, which darkens a bilinear
    blend between unlike texels."""
    for image in list(bpy.data.images):
        if image.is_float or image.colorspace_settings.name != "sRGB":
            continue
        width, height = image.size
        encoded = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(encoded)
        rgb = encoded.reshape(-1, 4)[:, :3]
        encoded.reshape(-1, 4)[:, :3] = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
        decoded = bpy.data.images.new(f"{image.name} (linear)", width, height, alpha=True, float_buffer=True)
        decoded.colorspace_settings.name = "Linear Rec.709"
        decoded.pixels.foreach_set(encoded)
        decoded.pack()
        image.user_remap(decoded)


def front_emission(bpy):
    """Emission from the fronts of surfaces only, as raystage's single-sided emitters shine (and
    Mitsuba's area lights): Cycles' emission leaves both sides of every surface. The importer's
    Principled BSDF keeps its emission; its strength is multiplied by 1 − Backfacing."""
    for material in bpy.data.materials:
        tree = material.node_tree
        for node in list(tree.nodes) if tree else []:
            if node.type != "BSDF_PRINCIPLED" or node.inputs["Emission Strength"].is_linked:
                continue
            strength = node.inputs["Emission Strength"].default_value
            if strength == 0.0:
                continue
            geometry = tree.nodes.new("ShaderNodeNewGeometry")
            front = tree.nodes.new("ShaderNodeMath")
            front.operation = "MULTIPLY_ADD"
            front.inputs[1].default_value = -strength
            front.inputs[2].default_value = strength
            tree.links.new(geometry.outputs["Backfacing"], front.inputs[0])
            tree.links.new(front.outputs["Value"], node.inputs["Emission Strength"])


class KeepAnimationsStashed:
    """An import hook (the importer's user-extension interface, which it finds as
    `glTF2ImportUserExtension` on an enabled add-on's module): the importer makes no animation
    active, where it would make the first one's actions active and Blender would move every node
    it animates to its value at the current frame, which nodes that another animation chosen
    later does not animate would keep. Nothing else of the import changes."""

    def gather_import_animations(self, animations, options, gltf):
        options.restore_first_anim = False


def pose(bpy, doc, scene, time, animation):
    """`scene` at `time` seconds of the animation `animation` names (its name or index; None:
    the first), imported with `KeepAnimationsStashed`. Returns the frame it is set to."""
    from io_scene_gltf2.blender.imp.animation_utils import restore_animation_on_object
    from io_scene_gltf2.blender.imp.blender_gltf import BlenderGlTF
    # The NLA track names the importer gave the animations, in the file's order (its own
    # naming, as blender_gltf.py does it).
    tracks = []
    for k, animation_k in enumerate(doc.get("animations", [])):
        tracks.append(BlenderGlTF.find_unused_name(set(tracks), animation_k.get("name") or f"Anim_{k}"))
    if not tracks:
        sys.exit("--time: the file has no animations")
    animation = tracks[0] if animation is None else animation
    if animation not in tracks:
        if not animation.isdigit() or int(animation) >= len(tracks):
            sys.exit(f"--animation {animation}: the file has {', '.join(tracks)} (or an index)")
        animation = tracks[int(animation)]
    for obj in scene.objects:
        restore_animation_on_object(obj, animation)
        if obj.type == "MESH" and obj.data.shape_keys is not None:
            restore_animation_on_object(obj.data.shape_keys, animation)
    # The importer's own conversion of glTF seconds to frames (animation_node.py).
    frame = time * scene.render.fps * scene.render.fps_base
    whole = int(np.floor(frame))
    scene.frame_set(whole, subframe=frame - whole)
    return frame


def backface_culling(bpy):
    """Single-sided materials (glTF's default) invisible from behind to every ray, as glTF asks
    and raystage's are: the importer only marks them `use_backface_culling`, which Cycles
    ignores (a setting of the viewport), so that a ray meets the back of a face and, where a
    surface lies on another facing the other way (the walls of BoxAnimated's boxes), the
    back of either. Their surface shader is mixed with a transparent BSDF by Backfacing."""
    for material in bpy.data.materials:
        tree = material.node_tree
        if not material.use_backface_culling or tree is None:
            continue
        output = next(n for n in tree.nodes if n.type == "OUTPUT_MATERIAL" and n.is_active_output)
        surface = output.inputs["Surface"]
        if not surface.is_linked:
            continue
        shader = surface.links[0].from_socket
        geometry = tree.nodes.new("ShaderNodeNewGeometry")
        transparent = tree.nodes.new("ShaderNodeBsdfTransparent")
        mix = tree.nodes.new("ShaderNodeMixShader")
        tree.links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
        tree.links.new(shader, mix.inputs[1])
        tree.links.new(transparent.outputs["BSDF"], mix.inputs[2])
        tree.links.new(mix.outputs["Shader"], surface)


def render(bpy, path, args):
    """`path` rendered by Cycles: its linear RGB, rows bottom to top."""
    doc = read_document(path)
    reset(bpy)
    if args.time is not None:
        import io_scene_gltf2
        io_scene_gltf2.glTF2ImportUserExtension = KeepAnimationsStashed
    result = bpy.ops.import_scene.gltf(filepath=os.path.abspath(path))
    if result != {"FINISHED"}:
        sys.exit(f"{path}: Blender's importer says {result}")
    scene = bpy.context.scene
    extras = doc.get("scenes", [{}])[doc.get("scene", 0)].get("extras", {})
    width, height = extras.get("image_size", [args.size, args.size])
    environment = args.environment or extras.get("environment", [0.0, 0.0, 0.0])
    frame = None if args.time is None else pose(bpy, doc, scene, args.time, args.animation)
    scene.camera = camera_of(bpy, doc)
    scene.world = world(bpy, environment)
    configure(bpy, scene, width, height, args.spp, args.seed, args.threads, args.depth)
    if args.linear_textures:
        linear_textures(bpy)
    if args.front_emission:
        front_emission(bpy)
    if args.backface_culling:
        backface_culling(bpy)
    if args.dump:
        dump_materials(bpy)
    with tempfile.TemporaryDirectory() as folder:
        exr = os.path.join(folder, "render.exr")
        scene.render.filepath = exr
        start = time.perf_counter()
        bpy.ops.render.render(write_still=True)
        seconds = time.perf_counter() - start
        image = bpy.data.images.load(exr)
        image.colorspace_settings.is_data = True
        if (image.size[0], image.size[1]) != (width, height):
            sys.exit(f"{path}: rendered {tuple(image.size)}, not {width}×{height}")
        pixels = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
    return pixels.reshape(height, width, 4)[:, :, :3], environment, frame, seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("gltf", nargs="+", help=".gltf or .glb files")
    parser.add_argument("--out", default=".", help="folder for the .pfm images")
    parser.add_argument("--prefix", default="", help="put before each file's name (NAME.gltf → PREFIXNAME.pfm)")
    parser.add_argument("--size", type=int, default=64, help="image side where the scene's extras name no size")
    parser.add_argument("--spp", type=int, default=1024)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--depth", type=int, default=64, help="the longest light path, bounces of each kind")
    parser.add_argument("--threads", type=int, default=0, help="render threads (0: every core)")
    parser.add_argument("--environment", type=lambda s: [float(c) for c in s.split(",")], help="uniform world radiance R,G,B (default: the scene's extras.environment, else black)")
    parser.add_argument("--linear-textures", action="store_true", help="filter colour textures as linear floats (see linear_textures)")
    parser.add_argument("--front-emission", action="store_true", help="emitters shine from their fronts only (see front_emission)")
    parser.add_argument("--time", type=float, help="render the animation at this many seconds (see pose)")
    parser.add_argument("--animation", help="with --time: the animation, by name or index (default: the first)")
    parser.add_argument("--backface-culling", action="store_true", help="single-sided materials invisible from behind (see backface_culling)")
    parser.add_argument("--dump", action="store_true", help="print the imported materials' node trees")
    args = parser.parse_args()
    if args.animation is not None and args.time is None:
        sys.exit("--animation needs --time")
    if args.environment is not None and len(args.environment) != 3:
        sys.exit("--environment takes R,G,B")
    try:
        import bpy
    except ImportError:
        sys.exit("Blender's Python module is not installed: in a Python 3.11 environment, pip install bpy==5.0.1")
    for path in args.gltf:
        name = os.path.splitext(os.path.basename(path))[0]
        if args.time is not None:
            name += f"_{args.time:g}s"
        rgb, environment, frame, seconds = render(bpy, path, args)
        write_pfm(os.path.join(args.out, f"{args.prefix}{name}.pfm"), rgb)
        means = " ".join(f"{m:.4f}" for m in rgb.reshape(-1, 3).mean(axis=0))
        at = "" if frame is None else f", frame {frame:g}"
        print(f"{name}: {rgb.shape[1]}×{rgb.shape[0]}{at}, {args.spp} spp, environment {environment}, means {means}, {seconds:.0f} s (Blender {bpy.app.version_string})", flush=True)


if __name__ == "__main__":
    main()
