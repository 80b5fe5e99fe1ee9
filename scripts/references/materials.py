#!/usr/bin/env python3
"""Renders the reference images of glTF 2.0's metallic-roughness material with Mitsuba 3.

The scenes come from raystage's own glTF files (`cargo run -p raystage-demo --example
write_material_scenes -- --mitsuba scenes/`), so that both renderers read the very same arrays and
texels: every primitive becomes a Mitsuba mesh (with its normals and texture coordinates), its
material a BSDF, emissive ones a one-sided area light, the scene's `extras.environment` a
constant environment, and the glTF camera a perspective sensor with its vertical field of view.
Mitsuba's path tracer (`volpath`, which lets shadow rays through alpha cut-outs) renders each
through a box filter of one pixel, camera rays that miss everything black (`hide_emitters`),
and writes `NAME.pfm`, little-endian linear RGB:

    pip install mitsuba numpy
    python3 scripts/references/materials.py scenes/ tests/references/ --spp 4096

The material is the specification's Appendix B, written out here as a Mitsuba BSDF (`GltfBsdf`):
a Lambertian base weighted by 1 − F(v·h) under a GGX specular lobe (height-correlated Smith
visibility, Schlick's Fresnel from F0 = 0.04), mixed by metallic with the GGX lobe of a
Schlick conductor of the base colour, alpha = roughness². None of Mitsuba's own plugins is that
model, and the nearest differ by more than the errors the tests must catch (directional albedo
against Appendix B's, base colour (0.8, 0.3, 0.1), measured with `bsdf.eval` by quadrature):

- `principled` (metallic, roughness, specular 0.5 → F0 0.04): its metal is Appendix B's up to
  Smith's separable masking (1.00 seen head-on; 0.95 at 45° and 0.82 at 75° for roughness 1,
  within 3 % below roughness 0.6), but its base is Disney's diffuse with retro-reflection and
  no 1 − F weight: 2–8 % brighter head-on (roughness 0.1 to 1) and up to 24 % at 75°.
- `roughplastic` (GGX, alpha = roughness², index 1.5): its coupled coating darkens the base
  with roughness, to 0.35 of Appendix B's at roughness 1.
- `roughconductor`: no Schlick conductor (`material = none` has no Fresnel; an index fitted to
  F0 tints the grazing reflection, up to +10 % in blue at 45°).

`--bsdf principled` renders with Mitsuba's `principled` instead, to measure those differences
on the images: on the spheres its dielectrics read 2–11 % brighter than this BSDF's (roughness
0.1 to 1), its roughest metal 7 % darker, more than the tests allow.

Two kinds of material are Mitsuba's own plugins, exactly: a dielectric without a specular layer
(`KHR_materials_specular` factor 0, metallic 0) is Appendix B's Lambertian base alone,
`diffuse`; a fully transmitting dielectric volume (`KHR_materials_transmission` factor 1,
`KHR_materials_volume` thickness above 0, metallic 0) is `roughdielectric` (GGX, visible-normal
sampling, alpha = roughness², at least raystage's smallest alpha 0.001; `int_ior` from
`KHR_materials_ior`), the base colour its `specular_transmittance` (the tint at each
crossing), its attenuation colour c at distance d an absorbing `homogeneous` interior medium of
extinction -ln(c) / d and albedo 0. The two differ where Mitsuba's masking is separable
G1(wo) G1(wi) and raystage's height-correlated, a few percent at the roughest spheres' rims,
and in the η² compression of radiance inside a volume, which every path that leaves it undoes.

Mitsuba's own wrappers carry the rest of glTF's material: `normalmap` for the normal texture
(its frame is (∂p/∂u, n × ∂p/∂u, n) in tangent space, glTF's frame for an unmirrored texture
layout, which the scenes use: +x along increasing u, +y up the image; with its flip of normals
facing away from the viewer and its bump-terminator shadowing off), `mask` for alpha MASK
(opacity = alpha ≥ cutoff, sampled nearest as the scene's sampler says), `twosided` for
double-sided materials, and `bitmap` textures (sRGB for colour, raw for normals; bilinear or
nearest and repeating, as the glTF sampler says). Anything else a material holds is an error,
not a silent difference.

Mitsuba's scalar variant runs the Python BSDF on one thread, about 20 µs a sample: at 4096
samples per pixel each scene takes 4 to 8 minutes of a core (the transmitting spheres, all
Mitsuba's own plugins, under one).
"""

import argparse
import base64
import glob
import os
import struct
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cornell_box import read_gltf, sensor, write_pfm  # noqa: E402

# glTF accessor component types and element widths, as numpy reads them.
COMPONENTS = {5126: "<f4", 5125: "<u4"}
WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def accessor(doc, data, index):
    """An accessor's values (float or uint32 elements) as a numpy array, one row an element."""
    a = doc["accessors"][index]
    if a["componentType"] not in COMPONENTS:
        sys.exit(f"accessor {index}: component type {a['componentType']} is not read here")
    view = doc["bufferViews"][a["bufferView"]]
    offset = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    width = WIDTHS[a["type"]]
    return np.frombuffer(data, dtype=COMPONENTS[a["componentType"]], count=a["count"] * width, offset=offset).reshape(-1, width)


def write_ply(path, positions, normals, uvs, indices):
    """A binary PLY of one triangle mesh with normals and texture coordinates, as Mitsuba reads
    it (texture coordinates as glTF has them: v down the image, as Mitsuba's bitmaps too)."""
    faces = indices.reshape(-1, 3)
    properties = "".join(f"property float {p}\n" for p in ("x", "y", "z", "nx", "ny", "nz", "u", "v"))
    with open(path, "wb") as f:
        f.write(
            (
                "ply\nformat binary_little_endian 1.0\n"
                f"element vertex {len(positions)}\n{properties}"
                f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
            ).encode()
        )
        f.write(np.hstack([positions, normals, uvs]).astype("<f4").tobytes())
        for face in faces:
            f.write(struct.pack("<B3i", 3, *map(int, face)))


def define_gltf_bsdf(mi, dr):
    """Registers `gltf`, the specification's Appendix B BRDF, as a Mitsuba BSDF."""

    def schlick(f0, cos):
        return f0 + (1.0 - f0) * (1.0 - dr.clip(cos, 0.0, 1.0)) ** 5

    class GltfBsdf(mi.BSDF):
        """glTF 2.0's metallic-roughness BRDF, one-sided (nothing below the surface)."""

        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            # A texture, or (Mitsuba hands `rgb` values over as they are) a colour.
            base = props["base_color"]
            self.base = base if hasattr(base, "eval") else None
            self.base_color = mi.Color3f(base) if self.base is None else None
            self.metallic = props["metallic"]
            self.alpha = props["roughness"] ** 2
            # The specular lobe is sampled half the time on dielectrics (its highlights are
            # narrow where the base is wide), always on metals, which have no base.
            self.specular_share = self.metallic + 0.5 * (1.0 - self.metallic)
            reflection = mi.BSDFFlags.FrontSide
            self.m_components = [mi.BSDFFlags.DiffuseReflection | reflection, mi.BSDFFlags.GlossyReflection | reflection]
            self.m_flags = self.m_components[0] | self.m_components[1]

        def ggx(self, h):
            a2 = self.alpha * self.alpha
            t = h.z * h.z * (a2 - 1.0) + 1.0
            return a2 / (dr.pi * t * t)

        def visibility(self, wo, wi):
            a2 = self.alpha * self.alpha
            lo = wi.z * dr.sqrt(wo.z * wo.z * (1.0 - a2) + a2)
            li = wo.z * dr.sqrt(wi.z * wi.z * (1.0 - a2) + a2)
            return 0.5 / (lo + li)

        def value(self, si, wo, wi):
            """BRDF × cos θi, Appendix B's `fresnel_mix` and `conductor_fresnel` spelled out."""
            if wo.z <= 0.0 or wi.z <= 0.0:
                return mi.Color3f(0.0)
            base = self.base_color if self.base is None else self.base.eval(si)
            h = dr.normalize(wo + wi)
            v_dot_h = dr.dot(wo, h)
            specular = self.ggx(h) * self.visibility(wo, wi)
            f_dielectric = schlick(0.04, v_dot_h)
            dielectric = (1.0 - f_dielectric) * base / dr.pi + f_dielectric * specular
            metal = schlick(base, v_dot_h) * specular
            return (dielectric * (1.0 - self.metallic) + metal * self.metallic) * wi.z

        def density(self, wo, wi):
            if wo.z <= 0.0 or wi.z <= 0.0:
                return 0.0
            h = dr.normalize(wo + wi)
            specular = self.ggx(h) * h.z / (4.0 * dr.dot(wo, h))
            return self.specular_share * specular + (1.0 - self.specular_share) * wi.z / dr.pi

        def sample(self, ctx, si, sample1, sample2, active=True):
            wo = si.wi
            bs = mi.BSDFSample3f()
            if wo.z <= 0.0:
                return bs, mi.Color3f(0.0)
            if sample1 < self.specular_share:
                # A microfacet normal with density D(h) cos θh, wo reflected about it.
                a2 = self.alpha * self.alpha
                cos2 = (1.0 - sample2.x) / (1.0 + (a2 - 1.0) * sample2.x)
                sin = dr.sqrt(dr.maximum(0.0, 1.0 - cos2))
                phi = 2.0 * dr.pi * sample2.y
                h = mi.Vector3f(sin * dr.cos(phi), sin * dr.sin(phi), dr.sqrt(cos2))
                wi = 2.0 * dr.dot(wo, h) * h - wo
                bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
                bs.sampled_component = 1
            else:
                wi = mi.warp.square_to_cosine_hemisphere(sample2)
                bs.sampled_type = mi.UInt32(+mi.BSDFFlags.DiffuseReflection)
                bs.sampled_component = 0
            pdf = self.density(wo, wi)
            if pdf <= 0.0:
                return bs, mi.Color3f(0.0)
            bs.wo, bs.pdf, bs.eta = wi, pdf, 1.0
            return bs, self.value(si, wo, wi) / pdf

        def eval(self, ctx, si, wo, active=True):
            return self.value(si, si.wi, wo)

        def pdf(self, ctx, si, wo, active=True):
            return self.density(si.wi, wo)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.value(si, si.wi, wo), self.density(si.wi, wo)

        def to_string(self):
            return f"GltfBsdf[metallic={self.metallic}, alpha={self.alpha}]"

    mi.register_bsdf("gltf", lambda props: GltfBsdf(props))


def texture(doc, data, folder, index, raw, alpha_cutoff=None):
    """A glTF texture as a Mitsuba `bitmap`: its image (a PNG, inline or in the buffer) written
    to `folder`, filtered and wrapped as its sampler says. With `alpha_cutoff`, the texture is
    the image's alpha thresholded there (what MASK shows)."""
    import mitsuba as mi

    tex = doc["textures"][index]
    image = doc["images"][tex["source"]]
    if "uri" in image:
        uri = image["uri"]
        if not uri.startswith("data:image/png;base64,"):
            sys.exit(f"image {tex['source']}: only inline PNG images are read here")
        png = base64.b64decode(uri.split(",", 1)[1])
    else:
        view = doc["bufferViews"][image["bufferView"]]
        png = data[view.get("byteOffset", 0) : view.get("byteOffset", 0) + view["byteLength"]]
    path = os.path.join(folder, f"texture{index}.png")
    with open(path, "wb") as f:
        f.write(png)
    sampler = doc["samplers"][tex["sampler"]] if "sampler" in tex else {}
    if sampler.get("wrapS", 10497) != 10497 or sampler.get("wrapT", 10497) != 10497:
        sys.exit(f"texture {index}: only repeating samplers are translated")
    filter_type = "nearest" if sampler.get("magFilter") == 9728 else "bilinear"
    if alpha_cutoff is None:
        return {"type": "bitmap", "filename": path, "raw": raw, "filter_type": filter_type, "wrap_mode": "repeat"}
    rgba = np.array(mi.Bitmap(path))
    if rgba.shape[2] != 4:
        sys.exit(f"texture {index}: MASK needs an alpha channel")
    opaque = (rgba[:, :, 3:4] / 255.0 >= alpha_cutoff).astype(np.float32)
    return {"type": "bitmap", "bitmap": mi.Bitmap(opaque), "raw": True, "filter_type": filter_type, "wrap_mode": "repeat"}


TRANSMISSION = {"KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior"}


def transmitting(material):
    """Whether a material transmits (KHR_materials_transmission)."""
    return "KHR_materials_transmission" in material.get("extensions", {})


def transmitting_bsdf(material):
    """A fully transmitting dielectric volume as Mitsuba's `roughdielectric`, and its interior
    medium (None where it absorbs nothing)."""
    name, pbr, extensions = material.get("name"), material.get("pbrMetallicRoughness", {}), material["extensions"]
    if set(material) - {"name", "pbrMetallicRoughness", "extensions"} or set(extensions) - TRANSMISSION or set(pbr) - {"baseColorFactor", "metallicFactor", "roughnessFactor"}:
        sys.exit(f"material {name}: a transmitting material is translated with factors and the transmission, volume and ior extensions only")
    volume = extensions.get("KHR_materials_volume", {})
    if pbr.get("metallicFactor", 1.0) != 0.0 or extensions["KHR_materials_transmission"].get("transmissionFactor", 0.0) != 1.0 or volume.get("thicknessFactor", 0.0) <= 0.0:
        sys.exit(f"material {name}: only fully transmitting dielectric volumes (metallic 0, transmission 1, thickness > 0) are translated")
    base = pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])[:3]
    bsdf = {
        "type": "roughdielectric",
        "distribution": "ggx",
        "sample_visible": True,
        "alpha": max(pbr.get("roughnessFactor", 1.0) ** 2, 1e-3),
        "int_ior": extensions.get("KHR_materials_ior", {}).get("ior", 1.5),
        "ext_ior": 1.0,
        "specular_transmittance": {"type": "rgb", "value": base},
    }
    medium = None
    if "attenuationDistance" in volume:
        colour = np.maximum(np.array(volume.get("attenuationColor", [1.0, 1.0, 1.0])), 1e-6)
        sigma = -np.log(colour) / volume["attenuationDistance"]
        # Mitsuba reads an `rgb` extinction as a colour in [0, 1]: the largest channel is the scale.
        scale = float(sigma.max())
        medium = {"type": "homogeneous", "sigma_t": {"type": "rgb", "value": (sigma / scale).tolist()}, "scale": scale, "albedo": {"type": "rgb", "value": [0.0, 0.0, 0.0]}}
    return bsdf, medium


def material_bsdf(doc, data, folder, material, bsdf):
    """A glTF material as a Mitsuba BSDF: `bsdf` (`gltf` or `principled`) with glTF's normal
    map, double-sidedness and alpha mask wrapped around it; `diffuse` for one without a
    specular layer."""
    pbr = material.get("pbrMetallicRoughness", {})
    factor = pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])
    known = {"name", "pbrMetallicRoughness", "normalTexture", "alphaMode", "alphaCutoff", "doubleSided", "extensions"}
    extensions = material.get("extensions", {})
    matte = extensions == {"KHR_materials_specular": {"specularFactor": 0.0}} and pbr.get("metallicFactor", 1.0) == 0.0
    if set(material) - known or "metallicRoughnessTexture" in pbr or (extensions and not matte):
        sys.exit(f"material {material.get('name')}: {sorted(set(material) - known) or 'metallicRoughnessTexture or an extension'} is not translated")
    if "baseColorTexture" in pbr:
        if factor != [1.0, 1.0, 1.0, 1.0] or pbr["baseColorTexture"].get("texCoord", 0) != 0:
            sys.exit(f"material {material.get('name')}: a base colour texture is translated with factor 1 and TEXCOORD_0 only")
        base = texture(doc, data, folder, pbr["baseColorTexture"]["index"], raw=False)
    else:
        base = {"type": "rgb", "value": factor[:3]}
    metallic, roughness = pbr.get("metallicFactor", 1.0), pbr.get("roughnessFactor", 1.0)
    if matte:
        result = {"type": "diffuse", "reflectance": base}
    elif bsdf == "principled":
        result = {"type": "principled", "base_color": base, "metallic": metallic, "roughness": roughness, "specular": 0.5}
    else:
        result = {"type": "gltf", "base_color": base, "metallic": metallic, "roughness": roughness}
    if "normalTexture" in material:
        normal = material["normalTexture"]
        if normal.get("scale", 1.0) != 1.0 or normal.get("texCoord", 0) != 0:
            sys.exit(f"material {material.get('name')}: a normal texture is translated with scale 1 and TEXCOORD_0 only")
        # Only the frame change glTF describes: neither Mitsuba's flip of normals that face away
        # from the viewer nor its bump-terminator shadowing (both on by default since 3.7.1).
        result = {
            "type": "normalmap",
            "normalmap": texture(doc, data, folder, normal["index"], raw=True),
            "flip_invalid_normals": False,
            "use_shadowing_function": False,
            "bsdf": result,
        }
    if material.get("doubleSided", False):
        result = {"type": "twosided", "bsdf": result}
    mode = material.get("alphaMode", "OPAQUE")
    if mode == "MASK":
        if "baseColorTexture" not in pbr:
            sys.exit(f"material {material.get('name')}: MASK is translated from a base colour texture's alpha only")
        opacity = texture(doc, data, folder, pbr["baseColorTexture"]["index"], raw=True, alpha_cutoff=material.get("alphaCutoff", 0.5))
        result = {"type": "mask", "opacity": opacity, "bsdf": result}
    elif mode != "OPAQUE":
        sys.exit(f"material {material.get('name')}: alpha mode {mode} is not translated")
    return result


def emitter_shape(material):
    """What an emissive material is: a one-sided area light of its emissive colour × strength,
    on a black Lambertian surface (the light must reflect nothing: base colour 0,
    `KHR_materials_specular` factor 0)."""
    extensions = material.get("extensions", {})
    strength = extensions.get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
    base = material["pbrMetallicRoughness"]["baseColorFactor"][:3]
    if max(base) > 0.0 or extensions.get("KHR_materials_specular", {}).get("specularFactor", 1.0) != 0.0:
        sys.exit(f"material {material.get('name')}: only emitters that reflect nothing are translated")
    radiance = [c * strength for c in material["emissiveFactor"]]
    return {"bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.0, 0.0, 0.0]}}, "emitter": {"type": "area", "radiance": {"type": "rgb", "value": radiance}}}


def scene_dict(mi, doc, data, folder, spp, bsdf):
    extras = doc["scenes"][0]["extras"]
    width, height = extras["image_size"]
    scene = {
        "type": "scene",
        # `volpath`, not `path`: its shadow rays pass through cut-outs (null BSDF components).
        "integrator": {"type": "volpath", "max_depth": 64, "hide_emitters": True},
        "environment": {"type": "constant", "radiance": {"type": "rgb", "value": extras["environment"]}},
    }
    for node_index, node in enumerate(doc["nodes"]):
        if "mesh" not in node:
            continue
        if any(k in node for k in ("matrix", "translation", "rotation", "scale", "children")):
            sys.exit(f"node {node_index}: only untransformed mesh nodes are translated")
        for k, prim in enumerate(doc["meshes"][node["mesh"]]["primitives"]):
            attributes = prim["attributes"]
            ply = os.path.join(folder, f"mesh{node_index}_{k}.ply")
            write_ply(
                ply,
                accessor(doc, data, attributes["POSITION"]),
                accessor(doc, data, attributes["NORMAL"]),
                accessor(doc, data, attributes["TEXCOORD_0"]),
                accessor(doc, data, prim["indices"]),
            )
            material = doc["materials"][prim["material"]]
            shape = {"type": "ply", "filename": ply}
            if max(material.get("emissiveFactor", [0.0, 0.0, 0.0])) > 0.0:
                shape.update(emitter_shape(material))
            elif transmitting(material):
                shape["bsdf"], medium = transmitting_bsdf(material)
                if medium is not None:
                    shape["interior"] = medium
            else:
                shape["bsdf"] = material_bsdf(doc, data, folder, material, bsdf)
            scene[f"shape{node_index}_{k}"] = shape
    scene["sensor"] = sensor(mi, doc, width, height, spp)
    return scene


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", help="folder of the scenes' .gltf files")
    parser.add_argument("out", help="folder for the .pfm images")
    parser.add_argument("--spp", type=int, default=4096)
    parser.add_argument("--bsdf", choices=["gltf", "principled"], default="gltf", help="the material: glTF's Appendix B, or Mitsuba's principled")
    parser.add_argument("--only", help="render this scene only (its name)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    try:
        import mitsuba as mi
    except ImportError:
        sys.exit("Mitsuba 3 is not installed: pip install mitsuba numpy")
    import drjit as dr

    # The Python BSDF is evaluated per sample: the scalar variant needs no compiler.
    mi.set_variant("scalar_rgb")
    define_gltf_bsdf(mi, dr)
    paths = sorted(glob.glob(os.path.join(args.scenes, "*.gltf")))
    if not paths:
        sys.exit(f"no .gltf files in {args.scenes}")
    for path in paths:
        name = os.path.splitext(os.path.basename(path))[0]
        if args.only and name != args.only:
            continue
        doc, data = read_gltf(path)
        with tempfile.TemporaryDirectory() as folder:
            scene = mi.load_dict(scene_dict(mi, doc, data, folder, args.spp, args.bsdf))
            image = np.array(mi.render(scene, seed=args.seed))
        write_pfm(os.path.join(args.out, f"{name}.pfm"), image[:, :, :3])
        print(f"{name}: {image.shape[1]}×{image.shape[0]}, {args.spp} spp", flush=True)


if __name__ == "__main__":
    main()
