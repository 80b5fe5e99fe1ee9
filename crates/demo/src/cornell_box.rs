//! The classic Cornell box as a glTF 2.0 file: the room measured at the Cornell Program of
//! Computer Graphics (its published coordinates, in millimetres, here in metres), with the
//! colours pbrt-v4's and Bitterli's versions of it use. Its only light is an emissive quad just
//! under the ceiling, one-sided, facing down.
//!
//! This is the scene raystage is compared with other renderers on: the same file is read by
//! raystage's importer and, by `scripts/references/cornell_box.py`, turned into a Mitsuba 3
//! scene, so both render the very same arrays.

use base64::Engine;
use glam::Vec3;
use serde_json::json;

/// Diffuse reflectance of the floor, ceiling, back wall and both blocks.
pub const WHITE: [f32; 3] = [0.73, 0.73, 0.73];
/// Diffuse reflectance of the left wall (as the camera sees it).
pub const RED: [f32; 3] = [0.63, 0.065, 0.05];
/// Diffuse reflectance of the right wall.
pub const GREEN: [f32; 3] = [0.14, 0.45, 0.091];
/// Radiance of the light.
pub const LIGHT: [f32; 3] = [17.0, 12.0, 4.0];

/// The side of the rough dielectric room's image, as `tests/cycles_reference.rs` compares it.
pub const CYCLES_SIZE: u32 = 64;

/// Height of the light under the ceiling's 548.8 mm: clear of the ceiling, so that the two
/// never overlap.
const LIGHT_HEIGHT: f32 = 548.0;

/// The camera: where it is (mm), and its vertical field of view (a 35 mm lens over a 25 mm
/// film, as measured).
pub const EYE_MM: [f32; 3] = [278.0, 273.0, -800.0];
/// The vertical field of view in degrees.
pub const FOV_Y_DEGREES: f32 = 39.307_7;

/// A surface of the room: triangles (positions in mm, three indices each) and what they are
/// made of.
struct Surface {
    name: &'static str,
    reflectance: [f32; 3],
    emission: [f32; 3],
    positions: Vec<[f32; 3]>,
    indices: Vec<u32>,
}

impl Surface {
    /// A surface of quads, corners in order around each, cut along their first diagonal.
    fn quads(name: &'static str, reflectance: [f32; 3], emission: [f32; 3], quads: &[[[f32; 3]; 4]]) -> Surface {
        let positions = quads.iter().flatten().copied().collect();
        let indices = (0..quads.len() as u32).flat_map(|q| [0, 1, 2, 0, 2, 3].map(|i| 4 * q + i)).collect();
        Surface { name, reflectance, emission, positions, indices }
    }
}

/// What stands on the room's floor.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Contents {
    /// The two blocks of the measured room.
    Blocks,
    /// [`SPHERES_PER_SIDE`]² white spheres in rows on the floor, instead of the blocks.
    Spheres,
}

/// Spheres along each side of the floor in [`spheres_gltf`]'s room.
pub const SPHERES_PER_SIDE: u32 = 6;
/// Segments around each of those spheres (and half as many from pole to pole): 27,888
/// triangles a sphere, 1,003,968 in all.
pub const SPHERE_SEGMENTS: u32 = 168;

/// Every surface, with the published coordinates; what `contents` says in it.
fn surfaces(contents: Contents) -> Vec<Surface> {
    let y = LIGHT_HEIGHT;
    let mut white = vec![
        // Floor, ceiling, back wall.
        [[552.8, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 559.2], [549.6, 0.0, 559.2]],
        [[556.0, 548.8, 0.0], [556.0, 548.8, 559.2], [0.0, 548.8, 559.2], [0.0, 548.8, 0.0]],
        [[549.6, 0.0, 559.2], [0.0, 0.0, 559.2], [0.0, 548.8, 559.2], [556.0, 548.8, 559.2]],
    ];
    if contents == Contents::Blocks {
        white.extend([
            // The short block.
            [[130.0, 165.0, 65.0], [82.0, 165.0, 225.0], [240.0, 165.0, 272.0], [290.0, 165.0, 114.0]],
            [[290.0, 0.0, 114.0], [290.0, 165.0, 114.0], [240.0, 165.0, 272.0], [240.0, 0.0, 272.0]],
            [[130.0, 0.0, 65.0], [130.0, 165.0, 65.0], [290.0, 165.0, 114.0], [290.0, 0.0, 114.0]],
            [[82.0, 0.0, 225.0], [82.0, 165.0, 225.0], [130.0, 165.0, 65.0], [130.0, 0.0, 65.0]],
            [[240.0, 0.0, 272.0], [240.0, 165.0, 272.0], [82.0, 165.0, 225.0], [82.0, 0.0, 225.0]],
            // The tall block.
            [[423.0, 330.0, 247.0], [265.0, 330.0, 296.0], [314.0, 330.0, 456.0], [472.0, 330.0, 406.0]],
            [[423.0, 0.0, 247.0], [423.0, 330.0, 247.0], [472.0, 330.0, 406.0], [472.0, 0.0, 406.0]],
            [[472.0, 0.0, 406.0], [472.0, 330.0, 406.0], [314.0, 330.0, 456.0], [314.0, 0.0, 456.0]],
            [[314.0, 0.0, 456.0], [314.0, 330.0, 456.0], [265.0, 330.0, 296.0], [265.0, 0.0, 296.0]],
            [[265.0, 0.0, 296.0], [265.0, 330.0, 296.0], [423.0, 330.0, 247.0], [423.0, 0.0, 247.0]],
        ]);
    }
    let mut surfaces = vec![
        Surface::quads("white", WHITE, [0.0; 3], &white),
        Surface::quads("red", RED, [0.0; 3], &[[[552.8, 0.0, 0.0], [549.6, 0.0, 559.2], [556.0, 548.8, 559.2], [556.0, 548.8, 0.0]]]),
        Surface::quads("green", GREEN, [0.0; 3], &[[[0.0, 0.0, 559.2], [0.0, 0.0, 0.0], [0.0, 548.8, 0.0], [0.0, 548.8, 559.2]]]),
        // Wound so that its front (counter-clockwise) faces down, into the room.
        Surface::quads("light", [0.0; 3], LIGHT, &[[[343.0, y, 227.0], [343.0, y, 332.0], [213.0, y, 332.0], [213.0, y, 227.0]]]),
    ];
    if contents == Contents::Spheres {
        surfaces.push(spheres());
    }
    surfaces
}

/// [`SPHERES_PER_SIDE`]² spheres in rows on the floor, each resting on it and a
/// latitude-longitude mesh of [`SPHERE_SEGMENTS`] segments: a million triangles, a scene too
/// large for the caches, which most paths that reach the floor's half of the room trace into.
fn spheres() -> Surface {
    let (around, down) = (SPHERE_SEGMENTS, SPHERE_SEGMENTS / 2);
    let cell = 549.6 / SPHERES_PER_SIDE as f32;
    let radius = 0.45 * cell;
    let (mut positions, mut indices) = (Vec::new(), Vec::new());
    let n = SPHERES_PER_SIDE;
    for (row, column) in (0..n * n).map(|k| (k / n, k % n)) {
        let centre = Vec3::new((column as f32 + 0.5) * cell, radius, (row as f32 + 0.5) * cell);
        let first = positions.len() as u32;
        for i in 0..=down {
            let (sin_theta, cos_theta) = (std::f32::consts::PI * i as f32 / down as f32).sin_cos();
            for j in 0..around {
                let (sin_phi, cos_phi) = (std::f32::consts::TAU * j as f32 / around as f32).sin_cos();
                positions.push((centre + radius * Vec3::new(sin_theta * cos_phi, cos_theta, sin_theta * sin_phi)).to_array());
            }
        }
        let at = |i: u32, j: u32| first + i * around + j % around;
        for i in 0..down {
            for j in 0..around {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                // The rows at the poles are fans: the triangle with two corners on the pole
                // has no area.
                if i + 1 != down {
                    indices.extend([a, c, b]);
                }
                if i != 0 {
                    indices.extend([a, d, c]);
                }
            }
        }
    }
    Surface { name: "spheres", reflectance: WHITE, emission: [0.0; 3], positions, indices }
}

/// The room as a glTF 2.0 JSON document with its buffer inline (a `data:` URI): one mesh with a
/// primitive per material, a node that holds it, and the camera, a node looking down +z. The
/// materials are Lambertian (`KHR_materials_specular` factor 0); the light's emits `LIGHT` as a
/// unit colour times `KHR_materials_emissive_strength`.
pub fn gltf() -> String {
    document(Walls::Lambertian, Contents::Blocks)
}

/// The room with [`SPHERES_PER_SIDE`]² Lambertian spheres on its floor instead of the blocks,
/// a million triangles in all: the path-tracing benchmark's large scene, read by raystage and
/// Mitsuba alike.
pub fn spheres_gltf() -> String {
    document(Walls::Lambertian, Contents::Spheres)
}

/// The same room with rough dielectric walls: glTF's metallic-roughness material as a user
/// writes it (metallic 0, roughness 1, the default specular layer of index 1.5 over the base),
/// the light still reflecting nothing. This is the room where Blender's Cycles
/// (`scripts/references/cycles_gltf.py`) is the reference; the extras name the image size it
/// is compared at.
pub fn rough_dielectric_gltf() -> String {
    document(Walls::RoughDielectric, Contents::Blocks)
}

/// What the walls and blocks are made of.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Walls {
    /// A dielectric without its specular layer (`KHR_materials_specular` factor 0).
    Lambertian,
    /// The default dielectric, metallic 0 and roughness 1.
    RoughDielectric,
}

/// The room's glTF document, its walls as `walls` says and `contents` in it.
fn document(walls: Walls, contents: Contents) -> String {
    let mut bin: Vec<u8> = Vec::new();
    let mut buffer_views = Vec::new();
    let mut accessors = Vec::new();
    let mut materials = Vec::new();
    let mut primitives = Vec::new();
    for surface in surfaces(contents) {
        let positions: Vec<[f32; 3]> = surface.positions.iter().map(|p| p.map(|c| c / 1000.0)).collect();
        let indices = surface.indices;
        let (lo, hi) = positions.iter().fold(([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]), |(lo, hi), p| {
            (std::array::from_fn(|i| lo[i].min(p[i])), std::array::from_fn(|i| hi[i].max(p[i])))
        });
        let position_view = buffer_views.len();
        buffer_views.push(json!({ "buffer": 0, "byteOffset": bin.len(), "byteLength": positions.len() * 12 }));
        bin.extend(positions.iter().flatten().flat_map(|c| c.to_le_bytes()));
        let index_view = buffer_views.len();
        buffer_views.push(json!({ "buffer": 0, "byteOffset": bin.len(), "byteLength": indices.len() * 4 }));
        bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
        let position_accessor = accessors.len();
        accessors.push(json!({ "bufferView": position_view, "componentType": 5126, "count": positions.len(), "type": "VEC3", "min": lo, "max": hi }));
        accessors.push(json!({ "bufferView": index_view, "componentType": 5125, "count": indices.len(), "type": "SCALAR" }));
        let [r, g, b] = surface.reflectance;
        let strength = surface.emission.into_iter().fold(0.0f32, f32::max);
        // Lambertian walls, as the measured room has them: a dielectric without its specular
        // layer. The light reflects nothing in either room, and shines down only, as the
        // measured light does: single-sided (a double-sided emitter glows from its back too).
        let mut material = json!({
            "name": surface.name,
            "pbrMetallicRoughness": { "baseColorFactor": [r, g, b, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0 },
            "doubleSided": strength == 0.0,
            "extensions": { "KHR_materials_specular": { "specularFactor": 0.0 } },
        });
        if walls == Walls::RoughDielectric && strength == 0.0 {
            material.as_object_mut().expect("a JSON object").remove("extensions");
        }
        if strength > 0.0 {
            material["emissiveFactor"] = json!(surface.emission.map(|c| c / strength));
            material["extensions"]["KHR_materials_emissive_strength"] = json!({ "emissiveStrength": strength });
        }
        primitives.push(json!({ "attributes": { "POSITION": position_accessor }, "indices": position_accessor + 1, "material": materials.len() }));
        materials.push(material);
    }
    let uri = format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&bin));
    let eye = EYE_MM.map(|c| c / 1000.0);
    let mut document = json!({
        "asset": { "version": "2.0", "generator": "raystage-demo cornell_box" },
        "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_materials_specular"],
        "scene": 0,
        "scenes": [{ "nodes": [0, 1] }],
        // The camera node turned half a turn about y: glTF cameras look down their −z.
        "nodes": [
            { "name": "room", "mesh": 0 },
            { "name": "camera", "camera": 0, "translation": eye, "rotation": [0.0, 1.0, 0.0, 0.0] },
        ],
        "cameras": [{ "type": "perspective", "perspective": { "yfov": FOV_Y_DEGREES.to_radians(), "aspectRatio": 1.0, "znear": 0.01 } }],
        "meshes": [{ "name": "room", "primitives": primitives }],
        "materials": materials,
        "accessors": accessors,
        "bufferViews": buffer_views,
        "buffers": [{ "byteLength": bin.len(), "uri": uri }],
    });
    if walls == Walls::RoughDielectric {
        document["scenes"][0]["extras"] = json!({ "image_size": [CYCLES_SIZE, CYCLES_SIZE] });
    }
    serde_json::to_string_pretty(&document).expect("JSON values serialise")
}

/// How far an image of the room is from a reference image of it (both linear RGB, row by row,
/// of the same size, a multiple of 4 on each side): the measures `tests/cornell_box.rs` and the
/// path-tracing benchmark judge renders by.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison {
    /// Per channel, the image's mean over the pixels that are not the light, over the
    /// reference's.
    pub channel_ratio: Vec3,
    /// The image's mean luminance over the light's own pixels, over the reference's.
    pub light_ratio: f32,
    /// The root-mean-square difference of the 4×4-pixel block means (blocks that touch the
    /// light left out), over the reference's mean: a noise measure that keeps where light
    /// falls while averaging each block's noise down.
    pub block_rmse: f32,
}

impl Comparison {
    /// `image` against `reference`, both `width` pixels wide.
    pub fn of(image: &[Vec3], reference: &[Vec3], width: usize) -> Comparison {
        assert_eq!(image.len(), reference.len(), "images of one size");
        let height = reference.len() / width;
        let lum = |c: Vec3| c.dot(Vec3::new(0.2126, 0.7152, 0.0722));
        let peak = lum(Vec3::from(LIGHT));
        // The light: pixels wholly inside it (its edge pixels mix it with the ceiling).
        let light: Vec<bool> = reference.iter().map(|&c| lum(c) > 0.95 * peak).collect();
        let mean = |img: &[Vec3], on: bool| {
            let (sum, n) = img.iter().zip(&light).filter(|(_, l)| **l == on).fold((Vec3::ZERO, 0), |(s, n), (c, _)| (s + *c, n + 1));
            sum / n.max(1) as f32
        };
        // Blocks that touch the light at all: anything brighter than a wall.
        let near_light: Vec<bool> = reference.iter().map(|&c| lum(c) > 1.0).collect();
        let (mut squares, mut sum, mut count) = (0.0f64, 0.0f64, 0);
        for by in 0..height / 4 {
            for bx in 0..width / 4 {
                let indices: Vec<usize> = (0..16).map(|i| (by * 4 + i / 4) * width + bx * 4 + i % 4).collect();
                if indices.iter().any(|&i| near_light[i]) {
                    continue;
                }
                let block = |img: &[Vec3]| indices.iter().map(|&i| img[i]).sum::<Vec3>() / 16.0;
                let (a, b) = (block(image), block(reference));
                squares += (a - b).length_squared() as f64;
                sum += b.element_sum() as f64;
                count += 3;
            }
        }
        Comparison {
            channel_ratio: mean(image, false) / mean(reference, false),
            light_ratio: lum(mean(image, true)) / lum(mean(reference, true)),
            block_rmse: ((squares / count as f64).sqrt() / (sum / count as f64)) as f32,
        }
    }
}
