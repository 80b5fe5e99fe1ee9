//! Scenes that hold glTF 2.0's metallic-roughness material (raystage's `PhysicallyBased`) to
//! account against another renderer: spheres across metallic × roughness, a textured,
//! normal-mapped quad under a grazing light, an alpha-masked cut-out casting its shadow, and
//! transmitting spheres (KHR_materials_transmission and KHR_materials_volume) before a checker
//! wall; and, for Blender's Cycles only, spheres across metallic × roughness in a white furnace
//! and a sphere painted by vertex colours.
//! Each is a glTF file with its buffers and PNG images inline, so that raystage's importer and
//! `scripts/references/materials.py` (which renders it with Mitsuba 3) or
//! `scripts/references/cycles_gltf.py` (Blender's glTF importer and Cycles) read the very same
//! arrays and texels; `tests/materials_reference.rs` and `tests/cycles_reference.rs` compare
//! them.
//!
//! Every scene is lit by a uniform environment (its radiance is the scene's
//! `extras.environment`, since glTF has no environment light) and, but the transmitting
//! spheres and the furnace, by an emissive quad out of the camera's view, so that highlights show (behind glass
//! it would cast caustics, which unidirectional path tracers resolve slowly); camera rays that
//! miss everything see black.
//! The scene's `extras.image_size` is the size it is compared at.
//! Texture layouts are unmirrored (the bitangent, up the image, is normal × tangent), where
//! every tangent-frame convention agrees with glTF's.

use base64::Engine;
use glam::{Mat3, Quat, Vec2, Vec3};
use serde_json::{Value, json};

use crate::shading::sphere_mesh;

/// Radiance of the uniform environment of every scene but the furnace.
pub const ENVIRONMENT: [f32; 3] = [0.25, 0.25, 0.25];
/// Radiance of the furnace's environment: white, the only light.
pub const FURNACE_ENVIRONMENT: [f32; 3] = [1.0, 1.0, 1.0];
/// The rows of the furnace's spheres, top to bottom: metallic and base colour. A white
/// dielectric (which keeps all the light it receives: it vanishes into the furnace where the
/// layers keep their energy), a coloured one, and a copper.
pub const FURNACE_ROWS: [(f32, [f32; 3]); 3] = [(0.0, [1.0, 1.0, 1.0]), (0.0, DIELECTRIC_BASE), (1.0, METAL_BASE)];
/// The roughness of the spheres' columns, left to right: above ~0.1 only, where a test-sized
/// sample count still resolves the highlights.
pub const ROUGHNESS: [f32; 4] = [0.1, 0.3, 0.6, 1.0];
/// The base colour of the dielectric (upper) row of spheres.
pub const DIELECTRIC_BASE: [f32; 3] = [0.75, 0.2, 0.1];
/// The base colour of the metal (lower) row of spheres, a copper.
pub const METAL_BASE: [f32; 3] = [0.95, 0.64, 0.54];
/// The roughness of the transmitting spheres' columns, left to right: from smooth to where a
/// single-scattering BTDF's masking terms start to differ between renderers (raystage's
/// height-correlated Smith, Mitsuba's separable one).
pub const TRANSMISSION_ROUGHNESS: [f32; 4] = [0.0, 0.1, 0.25, 0.4];
/// The index of refraction of the transmitting spheres.
pub const TRANSMISSION_IOR: f32 = 1.5;
/// The lower row of transmitting spheres: its base colour (tinting the light at each
/// crossing), and the colour white light turns into after one sphere's diameter inside.
pub const ABSORBING: ([f32; 3], [f32; 3]) = ([1.0, 0.9, 0.8], [0.9, 0.55, 0.25]);

/// One of the comparison scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaterialScene {
    /// Two rows of spheres (dielectric above, metal below) across [`ROUGHNESS`], each in its
    /// own square cell of the image.
    Spheres,
    /// A quad with a checker base-colour texture and a normal map of domes and dimples, lit
    /// from the back left, 35° above it.
    NormalMapped,
    /// An alpha-masked quad (a disc with a star-shaped hole) standing on a floor, lit from
    /// above: the camera and the shadow rays see through the cut-out.
    Cutout,
    /// Two rows of transmitting spheres (volumes of index [`TRANSMISSION_IOR`]: clear above;
    /// tinted and absorbing, [`ABSORBING`], below) across [`TRANSMISSION_ROUGHNESS`], before a
    /// matte checker wall that their refraction shows, bent and blurred.
    Transmission,
    /// Three rows of spheres ([`FURNACE_ROWS`]) across [`ROUGHNESS`] in a uniform white
    /// environment ([`FURNACE_ENVIRONMENT`]), each in its own square cell: how much light each
    /// material keeps, at every angle its sphere shows.
    Furnace,
    /// A sphere whose base colour is its `COLOR_0` (a hue that turns around the camera's axis
    /// and pales towards the middle) over a base colour factor of 1, lit as the material spheres are.
    VertexColours,
    /// A double-sided emitting panel standing on a floor, seen from behind: glTF's back faces
    /// are lit as the front "with normals reversed", emission included, so the panel glows on
    /// both sides and lights the floor on both (Mitsuba's area lights are one-sided).
    EmitterBacks,
}

impl MaterialScene {
    /// The scenes Mitsuba renders (`scripts/references/materials.py`): every material of
    /// theirs is one it translates.
    pub const MITSUBA: [MaterialScene; 4] = [MaterialScene::Spheres, MaterialScene::NormalMapped, MaterialScene::Cutout, MaterialScene::Transmission];
    /// The scenes Blender's Cycles renders (`scripts/references/cycles_gltf.py`).
    pub const CYCLES: [MaterialScene; 7] = [
        MaterialScene::Spheres,
        MaterialScene::Furnace,
        MaterialScene::NormalMapped,
        MaterialScene::Cutout,
        MaterialScene::VertexColours,
        MaterialScene::Transmission,
        MaterialScene::EmitterBacks,
    ];
    /// Every scene.
    pub const ALL: [MaterialScene; 7] = [
        MaterialScene::Spheres,
        MaterialScene::NormalMapped,
        MaterialScene::Cutout,
        MaterialScene::Transmission,
        MaterialScene::Furnace,
        MaterialScene::VertexColours,
        MaterialScene::EmitterBacks,
    ];

    /// The name of the scene's files (`NAME.gltf`, `tests/references/NAME.pfm`).
    pub fn name(self) -> &'static str {
        match self {
            MaterialScene::Spheres => "material_spheres",
            MaterialScene::NormalMapped => "normal_mapped_quad",
            MaterialScene::Cutout => "alpha_cutout",
            MaterialScene::Transmission => "transmission_spheres",
            MaterialScene::Furnace => "furnace_spheres",
            MaterialScene::VertexColours => "vertex_colours",
            MaterialScene::EmitterBacks => "emitter_backs",
        }
    }

    /// The image size the scene is compared at, width and height: small, so that its reference
    /// is a small file.
    pub fn size(self) -> (u32, u32) {
        match self {
            MaterialScene::Spheres | MaterialScene::Transmission => (96, 48),
            MaterialScene::NormalMapped | MaterialScene::Cutout | MaterialScene::VertexColours | MaterialScene::EmitterBacks => (64, 64),
            MaterialScene::Furnace => (96, 72),
        }
    }

    /// The radiance of the scene's uniform environment (its `extras.environment`).
    pub fn environment(self) -> [f32; 3] {
        if self == MaterialScene::Furnace { FURNACE_ENVIRONMENT } else { ENVIRONMENT }
    }

    /// The scene as a glTF 2.0 JSON document.
    pub fn gltf(self) -> String {
        let mut doc = Document::default();
        let (width, height) = self.size();
        let aspect = width as f32 / height as f32;
        match self {
            MaterialScene::Spheres => {
                doc.sphere_grid(&[(0.0, DIELECTRIC_BASE), (1.0, METAL_BASE)]);
                // Up, left and in front: its reflection sits in the upper left of each sphere.
                doc.light(Vec3::new(-2.5, 3.0, 4.0), Vec3::ZERO, 1.2, 30.0);
                // Cells of 1 × 1 at the spheres' plane, 6 away: the 2 rows fill the height.
                doc.camera(Vec3::new(0.0, 0.0, 6.0), Vec3::ZERO, 2.0 * (1.0f32 / 6.0).atan(), aspect);
            }
            MaterialScene::NormalMapped => {
                let (colors, normals) = (doc.texture(&checker(), 3, true), doc.texture(&bumps(), 3, true));
                let material = doc.material(json!({
                    "name": "checker, domes and dimples",
                    "pbrMetallicRoughness": {
                        "baseColorTexture": { "index": colors },
                        "metallicFactor": 0.0,
                        "roughnessFactor": 0.5,
                    },
                    "normalTexture": { "index": normals },
                }));
                doc.quad(2.0, 0.0, material);
                // From the back left, 35° above the quad: both of the map's axes tilt the
                // normal towards the light or away (a green channel read upside down shows),
                // while the base's coupling to the specular layer, where renderers differ most
                // (grazing light), stays out of play.
                doc.light(Vec3::new(-2.1, 2.1, -2.1), Vec3::ZERO, 0.6, 120.0);
                doc.camera(Vec3::new(0.0, 1.9, 2.1), Vec3::ZERO, 45f32.to_radians(), aspect);
            }
            MaterialScene::Cutout => {
                let floor = doc.material(json!({
                    "name": "floor",
                    "pbrMetallicRoughness": { "baseColorFactor": [0.6, 0.6, 0.6, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.9 },
                }));
                // Large enough to fill the view behind the cut-out.
                doc.quad(40.0, 0.0, floor);
                let texture = doc.texture(&cutout(), 4, false);
                let leaf = doc.material(json!({
                    "name": "cut-out",
                    "pbrMetallicRoughness": {
                        "baseColorTexture": { "index": texture },
                        "metallicFactor": 0.0,
                        "roughnessFactor": 0.6,
                    },
                    "alphaMode": "MASK",
                    "alphaCutoff": 0.5,
                    "doubleSided": true,
                }));
                doc.standing_quad(1.6, 0.1, leaf);
                doc.light(Vec3::new(0.8, 4.0, 1.5), Vec3::new(0.0, 0.0, -0.5), 1.0, 40.0);
                doc.camera(Vec3::new(0.0, 3.2, 3.0), Vec3::new(0.0, 0.5, 0.0), 40f32.to_radians(), aspect);
            }
            MaterialScene::Transmission => {
                let rows = [([1.0; 3], None), (ABSORBING.0, Some(ABSORBING.1))];
                let diameter = 0.84;
                for (row, (base, attenuation)) in rows.into_iter().enumerate() {
                    for (column, roughness) in TRANSMISSION_ROUGHNESS.into_iter().enumerate() {
                        let mut volume = json!({ "thicknessFactor": diameter });
                        if let Some(colour) = attenuation {
                            volume["attenuationColor"] = json!(colour);
                            volume["attenuationDistance"] = json!(diameter);
                        }
                        let material = doc.material(json!({
                            "name": format!("transmitting, row {row}, roughness {roughness}"),
                            "pbrMetallicRoughness": { "baseColorFactor": [base[0], base[1], base[2], 1.0], "metallicFactor": 0.0, "roughnessFactor": roughness },
                            "extensions": {
                                "KHR_materials_transmission": { "transmissionFactor": 1.0 },
                                "KHR_materials_volume": volume,
                                "KHR_materials_ior": { "ior": TRANSMISSION_IOR },
                            },
                        }));
                        let centre = Vec3::new(column as f32 - 1.5, 0.5 - row as f32, 0.0);
                        let mesh = sphere_mesh(centre, diameter / 2.0, 48, 24);
                        doc.mesh(&mesh.positions, &mesh.normals, &mesh.uvs, None, &mesh.indices, material);
                    }
                }
                // A Lambertian checker (no specular layer: `KHR_materials_specular` factor 0),
                // 1.5 behind the spheres, its tiles a quarter of a cell.
                let texture = doc.texture(&checker(), 3, true);
                let wall = doc.material(json!({
                    "name": "checker wall",
                    "pbrMetallicRoughness": { "baseColorTexture": { "index": texture }, "metallicFactor": 0.0, "roughnessFactor": 1.0 },
                    "extensions": { "KHR_materials_specular": { "specularFactor": 0.0 } },
                }));
                doc.wall(Vec2::new(8.0, 4.0), -1.5, 4.0, wall);
                doc.camera(Vec3::new(0.0, 0.0, 6.0), Vec3::ZERO, 2.0 * (1.0f32 / 6.0).atan(), aspect);
            }
            MaterialScene::Furnace => {
                doc.sphere_grid(&FURNACE_ROWS);
                // Cells of 1 × 1 at the spheres' plane, 6 away: the 3 rows fill the height.
                doc.camera(Vec3::new(0.0, 0.0, 6.0), Vec3::ZERO, 2.0 * (1.5f32 / 6.0).atan(), aspect);
            }
            MaterialScene::VertexColours => {
                let material = doc.material(json!({
                    "name": "vertex colours",
                    "pbrMetallicRoughness": { "metallicFactor": 0.0, "roughnessFactor": 0.5 },
                }));
                let mesh = sphere_mesh(Vec3::ZERO, 0.9, 48, 24);
                let colours: Vec<Vec3> = mesh.positions.iter().map(|p| paint(*p / 0.9)).collect();
                doc.mesh(&mesh.positions, &mesh.normals, &mesh.uvs, Some(&colours), &mesh.indices, material);
                doc.light(Vec3::new(-2.5, 3.0, 4.0), Vec3::ZERO, 1.2, 30.0);
                doc.camera(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 2.0 * (1.0f32 / 5.0).atan(), aspect);
            }
            MaterialScene::EmitterBacks => {
                let floor = doc.material(json!({
                    "name": "floor",
                    "pbrMetallicRoughness": { "baseColorFactor": [0.6, 0.6, 0.6, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.9 },
                }));
                doc.quad(6.0, 0.0, floor);
                // Facing +z, a little above the floor; the camera sees its back from −z and the
                // side, and the floor it lights on either side.
                let panel = doc.emitter("panel", 4.0, true);
                doc.square(Vec3::new(0.0, 0.6, 0.0), Vec3::Z, 0.8, panel);
                doc.camera(Vec3::new(1.5, 1.6, -2.4), Vec3::new(0.0, 0.3, 0.3), 50f32.to_radians(), aspect);
            }
        }
        doc.finish(self.name(), self.size(), self.environment())
    }
}

/// A glTF document being written: arrays and a binary buffer that grow together.
#[derive(Default)]
struct Document {
    bin: Vec<u8>,
    buffer_views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
    materials: Vec<Value>,
    textures: Vec<Value>,
    images: Vec<Value>,
    samplers: Vec<Value>,
    nodes: Vec<Value>,
    cameras: Vec<Value>,
}

impl Document {
    /// Adds `material`, returning its index.
    fn material(&mut self, material: Value) -> usize {
        self.materials.push(material);
        self.materials.len() - 1
    }

    /// Adds an RGBA image (`width` texels wide) as an inline PNG, sampled bilinearly or
    /// nearest (`linear`), repeating; returns the texture's index.
    fn texture(&mut self, (width, texels): &(u32, Vec<[u8; 4]>), channels: usize, linear: bool) -> usize {
        let height = texels.len() as u32 / width;
        let mut png = Vec::new();
        let mut encoder = png::Encoder::new(&mut png, *width, height);
        encoder.set_color(if channels == 4 { png::ColorType::Rgba } else { png::ColorType::Rgb });
        encoder.set_depth(png::BitDepth::Eight);
        let data: Vec<u8> = texels.iter().flat_map(|t| t[..channels].to_vec()).collect();
        encoder.write_header().and_then(|mut w| w.write_image_data(&data)).expect("PNG encoding into memory cannot fail");
        let uri = format!("data:image/png;base64,{}", base64::engine::general_purpose::STANDARD.encode(&png));
        // LINEAR / NEAREST for both magnification and minification: no mipmaps, which the
        // other renderer would not filter alike.
        let filter = if linear { 9729 } else { 9728 };
        self.samplers.push(json!({ "magFilter": filter, "minFilter": filter, "wrapS": 10497, "wrapT": 10497 }));
        self.images.push(json!({ "uri": uri }));
        self.textures.push(json!({ "source": self.images.len() - 1, "sampler": self.samplers.len() - 1 }));
        self.textures.len() - 1
    }

    /// Appends `bytes` as a buffer view and an accessor of `count` elements of `kind` and
    /// `component` type, with `bounds` (glTF asks for them on positions); returns the
    /// accessor's index.
    fn accessor(&mut self, bytes: Vec<u8>, count: usize, kind: &str, component: u32, bounds: Option<(Vec3, Vec3)>) -> usize {
        self.buffer_views.push(json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len() }));
        self.bin.extend(bytes);
        let mut accessor = json!({ "bufferView": self.buffer_views.len() - 1, "componentType": component, "count": count, "type": kind });
        if let Some((lo, hi)) = bounds {
            accessor["min"] = json!(lo.to_array());
            accessor["max"] = json!(hi.to_array());
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// Adds a triangle mesh (world coordinates, with normals, texture coordinates and perhaps
    /// linear vertex colours) of one material, and a node that holds it.
    fn mesh(&mut self, positions: &[Vec3], normals: &[Vec3], uvs: &[Vec2], colours: Option<&[Vec3]>, indices: &[[u32; 3]], material: usize) {
        let floats = |values: &mut dyn Iterator<Item = f32>| values.flat_map(f32::to_le_bytes).collect::<Vec<u8>>();
        let bounds = positions.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        let position = self.accessor(floats(&mut positions.iter().flat_map(|p| p.to_array())), positions.len(), "VEC3", 5126, Some(bounds));
        let normal = self.accessor(floats(&mut normals.iter().flat_map(|n| n.normalize().to_array())), normals.len(), "VEC3", 5126, None);
        let uv = self.accessor(floats(&mut uvs.iter().flat_map(|t| t.to_array())), uvs.len(), "VEC2", 5126, None);
        let index_bytes = indices.iter().flatten().flat_map(|i| i.to_le_bytes()).collect();
        let index = self.accessor(index_bytes, indices.len() * 3, "SCALAR", 5125, None);
        let mut attributes = json!({ "POSITION": position, "NORMAL": normal, "TEXCOORD_0": uv });
        if let Some(colours) = colours {
            attributes["COLOR_0"] = json!(self.accessor(floats(&mut colours.iter().flat_map(|c| c.to_array())), colours.len(), "VEC3", 5126, None));
        }
        self.meshes.push(json!({ "primitives": [{ "attributes": attributes, "indices": index, "material": material }] }));
        self.nodes.push(json!({ "mesh": self.meshes.len() - 1 }));
    }

    /// Spheres in cells of 1 × 1 centred on the origin in the plane z = 0: a row for each
    /// (metallic, base colour) of `rows`, top to bottom, a column for each of [`ROUGHNESS`].
    fn sphere_grid(&mut self, rows: &[(f32, [f32; 3])]) {
        for (row, (metallic, base)) in rows.iter().enumerate() {
            for (column, roughness) in ROUGHNESS.into_iter().enumerate() {
                let material = self.material(json!({
                    "name": format!("metallic {metallic} roughness {roughness}"),
                    "pbrMetallicRoughness": { "baseColorFactor": [base[0], base[1], base[2], 1.0], "metallicFactor": metallic, "roughnessFactor": roughness },
                }));
                let centre = Vec3::new(column as f32 - 1.5, (rows.len() - 1) as f32 / 2.0 - row as f32, 0.0);
                let mesh = sphere_mesh(centre, 0.42, 48, 24);
                self.mesh(&mesh.positions, &mesh.normals, &mesh.uvs, None, &mesh.indices, material);
            }
        }
    }

    /// A square of side `size` in the plane y = `height`, facing up, its texture's u along +x
    /// and v along +z, so that the top of the image lies towards −z (unmirrored).
    fn quad(&mut self, size: f32, height: f32, material: usize) {
        let h = size / 2.0;
        let corners = [Vec3::new(-h, height, -h), Vec3::new(-h, height, h), Vec3::new(h, height, h), Vec3::new(h, height, -h)];
        let uvs = [Vec2::new(0.0, 0.0), Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(1.0, 0.0)];
        self.mesh(&corners, &[Vec3::Y; 4], &uvs, None, &[[0, 1, 2], [0, 2, 3]], material);
    }

    /// A square of side `size` standing upright in the plane z = 0 on y = `lift`, facing +z,
    /// its image upright seen from +z.
    fn standing_quad(&mut self, size: f32, lift: f32, material: usize) {
        let h = size / 2.0;
        let (bottom, top) = (lift, lift + size);
        let corners = [Vec3::new(-h, top, 0.0), Vec3::new(-h, bottom, 0.0), Vec3::new(h, bottom, 0.0), Vec3::new(h, top, 0.0)];
        let uvs = [Vec2::new(0.0, 0.0), Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(1.0, 0.0)];
        self.mesh(&corners, &[Vec3::Z; 4], &uvs, None, &[[0, 1, 2], [0, 2, 3]], material);
    }

    /// A `size` rectangle centred on the z axis in the plane z = `depth`, facing +z, its texture
    /// repeated `repeats` times across its height (and as often across its width), upright.
    fn wall(&mut self, size: Vec2, depth: f32, repeats: f32, material: usize) {
        let (w, h) = (size.x / 2.0, size.y / 2.0);
        let corners = [Vec3::new(-w, h, depth), Vec3::new(-w, -h, depth), Vec3::new(w, -h, depth), Vec3::new(w, h, depth)];
        let (u, v) = (repeats * size.x / size.y, repeats);
        let uvs = [Vec2::new(0.0, 0.0), Vec2::new(0.0, v), Vec2::new(u, v), Vec2::new(u, 0.0)];
        self.mesh(&corners, &[Vec3::Z; 4], &uvs, None, &[[0, 1, 2], [0, 2, 3]], material);
    }

    /// A square emitter of side `size` at `centre` facing `target`, emitting `radiance` from its
    /// front only and reflecting nothing (a black Lambertian: `KHR_materials_specular` factor 0),
    /// opaque from behind: Mitsuba's area light, one-sided on a black surface. In glTF that is
    /// two single-sided squares, the emitter and a black one just behind it facing the other
    /// way (a double-sided emitter glows from its back as well).
    fn light(&mut self, centre: Vec3, target: Vec3, size: f32, radiance: f32) {
        let normal = (target - centre).normalize();
        let emitter = self.emitter("light", radiance, false);
        self.square(centre, normal, size, emitter);
        let back = self.material(json!({
            "name": "light's back",
            "pbrMetallicRoughness": { "baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0 },
            "extensions": { "KHR_materials_specular": { "specularFactor": 0.0 } },
        }));
        self.square(centre - normal * (size * 1e-3), -normal, size, back);
    }

    /// The material of an emitter of `radiance` that reflects nothing, glowing from both sides
    /// if `double_sided`.
    fn emitter(&mut self, name: &str, radiance: f32, double_sided: bool) -> usize {
        self.material(json!({
            "name": name,
            "pbrMetallicRoughness": { "baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0 },
            "emissiveFactor": [1.0, 1.0, 1.0],
            "doubleSided": double_sided,
            "extensions": { "KHR_materials_emissive_strength": { "emissiveStrength": radiance }, "KHR_materials_specular": { "specularFactor": 0.0 } },
        }))
    }

    /// A square of side `size` at `centre` facing along unit `normal`.
    fn square(&mut self, centre: Vec3, normal: Vec3, size: f32, material: usize) {
        let u = normal.any_orthonormal_vector() * (size / 2.0);
        let v = normal.cross(u);
        // Counter-clockwise seen from the front (where `normal` points).
        let corners = [centre - u - v, centre + u - v, centre + u + v, centre - u + v];
        let uvs = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
        self.mesh(&corners, &[normal; 4], &uvs, None, &[[0, 1, 2], [0, 2, 3]], material);
    }

    /// A perspective camera at `eye` looking at `target` (+y up), with vertical field of view
    /// `yfov` radians.
    fn camera(&mut self, eye: Vec3, target: Vec3, yfov: f32, aspect: f32) {
        let rotation = look_at(eye, target);
        self.cameras.push(json!({ "type": "perspective", "perspective": { "yfov": yfov, "aspectRatio": aspect, "znear": 0.01 } }));
        self.nodes.push(json!({ "name": "camera", "camera": self.cameras.len() - 1, "translation": eye.to_array(), "rotation": rotation.to_array() }));
    }

    /// The finished JSON document, its buffer inline (a `data:` URI), with the environment's
    /// radiance and the size the scene is compared at in the scene's `extras`.
    fn finish(self, name: &str, (width, height): (u32, u32), environment: [f32; 3]) -> String {
        let uri = format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&self.bin));
        let mut document = json!({
            "asset": { "version": "2.0", "generator": format!("raystage-demo material_scenes {name}") },
            "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_materials_specular", "KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior"],
            "scene": 0,
            "scenes": [{ "nodes": (0..self.nodes.len()).collect::<Vec<_>>(), "extras": { "environment": environment, "image_size": [width, height] } }],
            "nodes": self.nodes,
            "cameras": self.cameras,
            "meshes": self.meshes,
            "materials": self.materials,
            "accessors": self.accessors,
            "bufferViews": self.buffer_views,
            "buffers": [{ "byteLength": self.bin.len(), "uri": uri }],
        });
        if !self.textures.is_empty() {
            document["textures"] = json!(self.textures);
            document["images"] = json!(self.images);
            document["samplers"] = json!(self.samplers);
        }
        serde_json::to_string_pretty(&document).expect("JSON values serialise")
    }
}

/// The rotation of a glTF camera node at `eye` that looks at `target` with +y up (glTF cameras
/// look down their −z with +y up).
pub(crate) fn look_at(eye: Vec3, target: Vec3) -> Quat {
    let back = (eye - target).normalize();
    let right = Vec3::Y.cross(back).normalize();
    Quat::from_mat3(&Mat3::from_cols(right, back.cross(right), back))
}

/// The vertex colour at `p` on the unit sphere: a hue that turns once around the z axis (the
/// camera's), saturated at the rim that the camera sees at grazing angles and pale where the
/// sphere faces it (linear, in [0.05, 0.9]).
fn paint(p: Vec3) -> Vec3 {
    let angle = p.y.atan2(p.x);
    let hue = Vec3::new(angle.cos(), (angle - std::f32::consts::TAU / 3.0).cos(), (angle + std::f32::consts::TAU / 3.0).cos()) * 0.5 + Vec3::splat(0.5);
    let pale = p.z.abs();
    (hue * (1.0 - pale) + Vec3::splat(0.6 * pale)) * 0.85 + Vec3::splat(0.05)
}

/// 8-bit sRGB of a linear value in [0, 1].
fn srgb(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let encoded = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (encoded * 255.0).round() as u8
}

/// A 16×16 checker of 4×4 tiles, 4 texels each (sRGB): a warm yellow and a blue. Magnified
/// on the quad, so that no renderer's minification filter comes into play.
fn checker() -> (u32, Vec<[u8; 4]>) {
    let (a, b) = ([0.8, 0.6, 0.15], [0.15, 0.3, 0.7]);
    let texels = (0..16 * 16)
        .map(|i| {
            let c: [f32; 3] = if (i % 16 / 4 + i / 16 / 4) % 2 == 0 { a } else { b };
            [srgb(c[0]), srgb(c[1]), srgb(c[2]), 255]
        })
        .collect();
    (16, texels)
}

/// A 32×32 normal map of 4×4 cells, each a smooth dome or dimple (alternating), as glTF
/// encodes normals: (n + 1) / 2, +x to the right, +y up the image.
fn bumps() -> (u32, Vec<[u8; 4]>) {
    const SIZE: usize = 32;
    const CELL: f32 = 8.0;
    let texels = (0..SIZE * SIZE)
        .map(|i| {
            // Texel centres, y up the image; each cell a cosine bump whose slope is at most
            // 0.18π (tilting the normal up to 30°, so that no shading normal turns away from
            // the camera, where renderers differ: raystage shades it black, Mitsuba flips it).
            let (x, y) = ((i % SIZE) as f32 + 0.5, (SIZE - i / SIZE) as f32 - 0.5);
            let (cx, cy) = ((x / CELL).floor(), (y / CELL).floor());
            let sign = if (cx + cy) as i32 % 2 == 0 { 1.0 } else { -1.0 };
            let (dx, dy) = ((x / CELL).fract() - 0.5, (y / CELL).fract() - 0.5);
            let r = (dx * dx + dy * dy).sqrt();
            let slope = if r < 0.5 { sign * 0.18 * std::f32::consts::PI * (std::f32::consts::TAU * r).sin() } else { 0.0 };
            // The height falls with r (domes) or rises (dimples): its gradient, then the normal.
            let (gx, gy) = if r > 0.0 { (-slope * dx / r, -slope * dy / r) } else { (0.0, 0.0) };
            let n = Vec3::new(-gx, -gy, 1.0).normalize();
            let byte = |c: f32| ((c * 0.5 + 0.5) * 255.0).round() as u8;
            [byte(n.x), byte(n.y), byte(n.z), 255]
        })
        .collect();
    (SIZE as u32, texels)
}

/// A 32×32 green disc with a star-shaped hole, opaque inside the disc and transparent
/// elsewhere (alpha 255 or 0: a cut-out, sampled nearest).
fn cutout() -> (u32, Vec<[u8; 4]>) {
    const SIZE: usize = 32;
    let texels = (0..SIZE * SIZE)
        .map(|i| {
            let (x, y) = ((i % SIZE) as f32 + 0.5 - 16.0, (i / SIZE) as f32 + 0.5 - 16.0);
            let (r, angle) = ((x * x + y * y).sqrt(), y.atan2(x));
            let star = 4.0 + 3.5 * (5.0 * angle).cos();
            let opaque = r < 15.0 && r > star;
            [srgb(0.2), srgb(0.55), srgb(0.15), if opaque { 255 } else { 0 }]
        })
        .collect();
    (SIZE as u32, texels)
}
