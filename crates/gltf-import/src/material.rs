//! glTF materials as raystage shaders: glTF 2.0's metallic-roughness model is raystage's
//! `PhysicallyBased` class, so every material maps onto it (unlit ones onto `Constant`),
//! transmission and volume included; what a material has that raystage does not render yet is
//! said in a note.

use glam::Vec3;
use gltf::json::Value;
use raystage_scene::{ParamValue, shader_class};

/// A shader to create: a built-in class and the parameters to write.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderSpec {
    /// The shader class (one of `raystage_scene::SHADER_CLASSES`).
    pub class: &'static str,
    /// Parameters to write, by name.
    pub params: Vec<(&'static str, ParamValue)>,
    /// Texture parameters to set once the glTF images they name are textures of the scene.
    pub textures: Vec<TextureUse>,
    /// The glTF material's name, if it has one (cut to `raystage_scene::MAX_SHADER_NAME` bytes).
    pub name: Option<String>,
}

/// A glTF image a shader's texture parameter uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextureUse {
    /// The parameter (`{slot}_texture`).
    pub param: &'static str,
    /// The image, by its index in the file.
    pub image: usize,
    /// Whether the image holds colours (sRGB-encoded, decoded to linear light) rather than data
    /// (read as stored).
    pub colour: bool,
}

/// The shader for a glTF material (`None`: the primitive has no material; raystage gives it
/// `Diffuse`, or `VertexColor` with vertex colours, as viewers do). In order of precedence:
///
/// - `KHR_materials_unlit` → `Constant` with the base colour;
/// - everything else → `PhysicallyBased`: base colour (factor, texture; vertex colours
///   multiply it), metallic and roughness (factors, and their texture), `KHR_materials_ior`,
///   `KHR_materials_specular`'s factor and colour, `KHR_materials_sheen`'s colour and roughness,
///   `KHR_materials_clearcoat`'s weight and roughness, `KHR_materials_transmission`'s factor
///   (the textures of these four extensions too),
///   `KHR_materials_volume`'s thickness factor (0 or absent: a thin wall) with its attenuation
///   colour and distance, emissive factor × `KHR_materials_emissive_strength`,
///   the normal texture with its scale, the emissive texture (multiplying the emission), the
///   occlusion texture with its strength, the base colour's alpha as `opacity` with the alpha
///   mode and cut-off, and single- or double-sidedness (a volume's boundary is seen from both
///   sides, as KHR_materials_volume says: a ray inside must meet it).
///   Each texture keeps its sampler (wrap modes, magnification filter), its texture coordinate
///   set (the first or second) and its `KHR_texture_transform`. `document` is the file the
///   material is of: the clearcoat and sheen extensions, which the gltf crate does not parse,
///   name their textures by index in it.
///
/// [`notes`] says what the material has beyond that.
pub fn shader_for(material: Option<&gltf::Material<'_>>, vertex_colors: bool, document: &gltf::Document) -> ShaderSpec {
    let Some(m) = material else {
        return if vertex_colors { spec("VertexColor", vec![]) } else { spec("Diffuse", vec![]) };
    };
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, a] = pbr.base_color_factor();
    let base = ParamValue::Color(clean(Vec3::new(r, g, b)).min(Vec3::ONE));
    let ior = m.ior().filter(|i| i.is_finite()).unwrap_or(1.5).clamp(1.0, 4.0);
    if m.unlit() {
        return spec("Constant", vec![("color", base)]);
    }
    let fraction = |x: f32| if x.is_finite() { x.clamp(0.0, 1.0) } else { 0.0 };
    let transmission = m.transmission().map_or(0.0, |t| fraction(t.transmission_factor()));
    // KHR_materials_volume only bounds a volume where light goes through.
    let volume = m.volume().filter(|v| transmission > 0.0 && v.thickness_factor().is_finite() && v.thickness_factor() > 0.0);
    let emission = clean(Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0));
    let mut shader = spec(
        "PhysicallyBased",
        vec![
            ("base_color", base),
            ("metallic", ParamValue::Float(fraction(pbr.metallic_factor()))),
            ("roughness", ParamValue::Float(fraction(pbr.roughness_factor()))),
            ("ior", ParamValue::Float(ior)),
            ("specular", ParamValue::Float(m.specular().map_or(1.0, |s| fraction(s.specular_factor())))),
            ("emissive", ParamValue::Color(emission)),
            ("opacity", ParamValue::Float(fraction(a))),
            ("alpha_mode", ParamValue::Float(alpha_mode(m.alpha_mode()))),
            ("double_sided", ParamValue::Float(if m.double_sided() || volume.is_some() { 1.0 } else { 0.0 })),
            ("transmission", ParamValue::Float(transmission)),
        ],
    );
    if let Some(v) = volume {
        shader.params.push(("thickness", ParamValue::Float(v.thickness_factor())));
        // An infinite attenuation distance (glTF's default) absorbs nothing: the defaults.
        let distance = v.attenuation_distance();
        if distance.is_finite() && distance > 0.0 {
            shader.params.push(("attenuation_color", ParamValue::Color(clean(Vec3::from(v.attenuation_color())).min(Vec3::ONE))));
            shader.params.push(("attenuation_distance", ParamValue::Float(distance.clamp(1e-6, f32::MAX))));
        }
    }
    // KHR_materials_clearcoat, which the gltf crate does not parse: read from the raw JSON.
    if let Some(coat) = clearcoat(m) {
        let factor = |key: &str| coat.get(key).and_then(Value::as_f64).map_or(0.0, |v| fraction(v as f32));
        shader.params.push(("clearcoat", ParamValue::Float(factor("clearcoatFactor"))));
        shader.params.push(("clearcoat_roughness", ParamValue::Float(factor("clearcoatRoughnessFactor"))));
    }
    if let Some(specular) = m.specular() {
        // glTF allows colour factors above 1 (the reflectance head-on is clamped to 1 later).
        shader.params.push(("specular_color", ParamValue::Color(clean(Vec3::from(specular.specular_color_factor())))));
    }
    // KHR_materials_sheen, which the gltf crate does not parse either.
    if let Some(sheen) = sheen(m) {
        let colour = sheen.get("sheenColorFactor").and_then(Value::as_array).filter(|c| c.len() == 3).map(|c| Vec3::from_array([0, 1, 2].map(|i| c[i].as_f64().unwrap_or(0.0) as f32)));
        shader.params.push(("sheen_color", ParamValue::Color(clean(colour.unwrap_or(Vec3::ZERO)).min(Vec3::ONE))));
        let roughness = sheen.get("sheenRoughnessFactor").and_then(Value::as_f64).map_or(0.0, |v| fraction(v as f32));
        shader.params.push(("sheen_roughness", ParamValue::Float(roughness)));
    }
    // Checked by the importer (`read`): outside [0, 1] the file is refused.
    if let Some(cutoff) = m.alpha_cutoff() {
        shader.params.push(("alpha_cutoff", ParamValue::Float(cutoff)));
    }
    if let Some(n) = m.normal_texture() {
        shader.params.push(("normal_scale", ParamValue::Float(finite_or(n.scale(), 1.0))));
    }
    if let Some(o) = m.occlusion_texture() {
        shader.params.push(("occlusion_strength", ParamValue::Float(fraction(o.strength()))));
    }
    for t in textures(m, document) {
        if let Ok(texture) = &t.texture {
            shader.add_texture(t.slot, texture, t.colour);
        }
    }
    shader
}

/// A texture a material uses in a slot of `PhysicallyBased`.
struct SlotTexture {
    /// The slot.
    slot: &'static str,
    /// What the file calls it, for notes ("clearcoat texture").
    what: &'static str,
    /// The texture, or why it cannot be used.
    texture: Result<TextureRef, String>,
    /// Whether its image holds colours (sRGB) rather than data.
    colour: bool,
}

/// Every texture of `m` that a slot of `PhysicallyBased` renders, in `document`, the file `m` is
/// of. Colour textures are glTF's sRGB ones (base colour, emissive, and the specular and sheen
/// colours); every other one is data.
fn textures(m: &gltf::Material<'_>, document: &gltf::Document) -> Vec<SlotTexture> {
    let info = |t: gltf::texture::Info<'_>| Ok(TextureRef::of(t.texture(), t.tex_coord(), t.extension_value(TRANSFORM)));
    let pbr = m.pbr_metallic_roughness();
    let specular = m.specular();
    let (coat, sheen) = (clearcoat(m), sheen(m));
    let raw = |extension: Option<&Value>, key: &str| raw_texture(extension?.get(key)?, document);
    [
        ("base_color", "base-colour texture", pbr.base_color_texture().map(info), true),
        ("metallic_roughness", "metallic-roughness texture", pbr.metallic_roughness_texture().map(info), false),
        ("normal", "normal texture", m.normal_texture().map(|n| Ok(TextureRef::of(n.texture(), n.tex_coord(), n.extension_value(TRANSFORM)))), false),
        ("emissive", "emissive texture", m.emissive_texture().map(info), true),
        ("occlusion", "occlusion texture", m.occlusion_texture().map(|o| Ok(TextureRef::of(o.texture(), o.tex_coord(), o.extension_value(TRANSFORM)))), false),
        ("specular", "specular texture", specular.as_ref().and_then(|s| s.specular_texture()).map(info), false),
        ("specular_color", "specular colour texture", specular.as_ref().and_then(|s| s.specular_color_texture()).map(info), true),
        ("transmission", "transmission texture", m.transmission().and_then(|t| t.transmission_texture()).map(info), false),
        ("clearcoat", "clearcoat texture", raw(coat, "clearcoatTexture"), false),
        ("clearcoat_roughness", "clearcoat roughness texture", raw(coat, "clearcoatRoughnessTexture"), false),
        ("sheen_color", "sheen colour texture", raw(sheen, "sheenColorTexture"), true),
        ("sheen_roughness", "sheen roughness texture", raw(sheen, "sheenRoughnessTexture"), false),
    ]
    .into_iter()
    .filter_map(|(slot, what, texture, colour)| Some(SlotTexture { slot, what, texture: texture?, colour }))
    .collect()
}

/// A `textureInfo` (index, texture coordinate set, `KHR_texture_transform`) read from the raw
/// JSON of an extension the gltf crate does not parse, which has therefore not checked it: an
/// index that names no texture of `document` is an error to note, not a panic.
fn raw_texture(info: &Value, document: &gltf::Document) -> Option<Result<TextureRef, String>> {
    let index = info.get("index");
    let texture = index.and_then(Value::as_u64).and_then(|i| document.textures().nth(usize::try_from(i).ok()?));
    let Some(texture) = texture else {
        return Some(Err(match index {
            Some(i) => format!("index {i} names no texture of the file"),
            None => "it has no index".to_string(),
        }));
    };
    let tex_coord = info.get("texCoord").and_then(Value::as_u64).unwrap_or(0).min(u32::MAX as u64) as u32;
    Some(Ok(TextureRef::of(texture, tex_coord, info.get("extensions").and_then(|e| e.get(TRANSFORM)))))
}

/// The name of `KHR_texture_transform` in a `textureInfo`'s extensions.
const TRANSFORM: &str = "KHR_texture_transform";

/// A material's reference to a texture (a `textureInfo`): which image, sampled how.
struct TextureRef {
    image: usize,
    /// The texture coordinate set, `KHR_texture_transform`'s override applied.
    set: u32,
    wrap: [f32; 2],
    nearest: bool,
    /// `KHR_texture_transform`'s offset, rotation and scale.
    offset: [f32; 2],
    rotation: f32,
    scale: [f32; 2],
}

impl TextureRef {
    /// The reference to `texture` on coordinate set `tex_coord`, with the `KHR_texture_transform`
    /// extension `transform` if it has one (fields missing or not numbers keep their defaults).
    fn of(texture: gltf::Texture<'_>, tex_coord: u32, transform: Option<&Value>) -> TextureRef {
        let sampler = texture.sampler();
        let number = |key: &str| transform?.get(key)?.as_f64().map(|x| x as f32).filter(|x| x.is_finite());
        let pair = |key: &str, default: [f32; 2]| {
            let Some(Value::Array(v)) = transform.and_then(|t| t.get(key)) else { return default };
            let at = |i: usize, d: f32| v.get(i).and_then(Value::as_f64).map(|x| x as f32).filter(|x| x.is_finite()).unwrap_or(d);
            [at(0, default[0]), at(1, default[1])]
        };
        TextureRef {
            image: texture.source().index(),
            set: coordinate_set(tex_coord, transform).min(u32::MAX as u64) as u32,
            wrap: [sampler.wrap_s().as_gl_enum() as f32, sampler.wrap_t().as_gl_enum() as f32],
            nearest: sampler.mag_filter() == Some(gltf::texture::MagFilter::Nearest),
            offset: pair("offset", [0.0, 0.0]),
            rotation: number("rotation").unwrap_or(0.0),
            scale: pair("scale", [1.0, 1.0]),
        }
    }
}

impl ShaderSpec {
    /// Uses `texture` in texture slot `slot` of a `PhysicallyBased` shader: the image, and the
    /// slot's sampler parameters. A texture on a coordinate set raystage lacks (a third or
    /// later) is left out ([`notes`] says so).
    fn add_texture(&mut self, slot: &str, texture: &TextureRef, colour: bool) {
        if texture.set > 1 {
            return;
        }
        let values = [
            ("wrap_s", texture.wrap[0]),
            ("wrap_t", texture.wrap[1]),
            ("filter", if texture.nearest { 9728.0 } else { 9729.0 }),
            ("texcoord", texture.set as f32),
            ("offset_u", texture.offset[0]),
            ("offset_v", texture.offset[1]),
            ("rotation", texture.rotation),
            ("scale_u", texture.scale[0]),
            ("scale_v", texture.scale[1]),
        ];
        let Some(param) = param_name(self.class, &format!("{slot}_texture")) else { return };
        self.textures.push(TextureUse { param, image: texture.image, colour });
        for (suffix, value) in values {
            if let Some(name) = param_name(self.class, &format!("{slot}_{suffix}")) {
                self.params.push((name, ParamValue::Float(value)));
            }
        }
    }
}

/// The name of parameter `name` of shader class `class`, as the class table spells it (a name
/// that lives as long as the program), if the class has it.
fn param_name(class: &str, name: &str) -> Option<&'static str> {
    shader_class(class)?.params.iter().find(|p| p.name == name).map(|p| p.name)
}

/// The texture coordinate set a normal texture reads (see [`coordinate_set`]), as a mesh's
/// index of it.
pub(crate) fn normal_coordinate_set(normal: &gltf::material::NormalTexture<'_>) -> usize {
    coordinate_set(normal.tex_coord(), normal.extension_value(TRANSFORM)).min(usize::MAX as u64) as usize
}

/// The texture coordinate set a `textureInfo` reads, `KHR_texture_transform`'s override applied.
fn coordinate_set(tex_coord: u32, transform: Option<&Value>) -> u64 {
    transform.and_then(|t| t.get("texCoord")?.as_u64()).unwrap_or(tex_coord as u64)
}

/// The material's `KHR_materials_clearcoat` object, if it has one.
fn clearcoat<'a>(material: &'a gltf::Material<'_>) -> Option<&'a Value> {
    material.extensions()?.get("KHR_materials_clearcoat").filter(|c| c.is_object())
}

/// The material's `KHR_materials_sheen` object, if it has one.
fn sheen<'a>(material: &'a gltf::Material<'_>) -> Option<&'a Value> {
    material.extensions()?.get("KHR_materials_sheen").filter(|c| c.is_object())
}

/// What `material` (of the file `document`) has that its shader does not render, one note
/// each: what raystage does not render yet, and textures a file names wrongly.
pub fn notes(material: &gltf::Material<'_>, document: &gltf::Document) -> Vec<String> {
    let name = material.name().map_or_else(|| format!("material {}", material.index().map_or(-1, |i| i as i64)), |n| format!("material `{n}`"));
    let mut notes = Vec::new();
    let mut left_out = Vec::new();
    for t in textures(material, document) {
        match t.texture {
            Ok(texture) if texture.set > 1 => {
                let article = if t.what.starts_with(['a', 'e', 'i', 'o', 'u']) { "an" } else { "a" };
                left_out.push(format!("{article} {} on a third or later set of texture coordinates", t.what));
            }
            Ok(_) => {}
            Err(why) => notes.push(format!("{name}: its {} is left out: {why}", t.what)),
        }
    }
    for (present, what) in [
        (material.alpha_mode() != gltf::material::AlphaMode::Opaque && material.unlit(), "its alpha mode (rendered opaque)"),
        (material.volume().is_some_and(|v| v.thickness_texture().is_some()), "its thickness texture (the path length inside comes from the geometry)"),
        (clearcoat(material).is_some_and(|c| c.get("clearcoatNormalTexture").is_some()), "its clearcoat normal texture (the coat takes the surface's normal)"),
    ] {
        if present {
            left_out.push(what.to_string());
        }
    }
    notes.extend(left_out.into_iter().map(|what| format!("{name}: {what} is not rendered yet")));
    notes
}

fn spec(class: &'static str, params: Vec<(&'static str, ParamValue)>) -> ShaderSpec {
    ShaderSpec { class, params, textures: Vec::new(), name: None }
}

/// The `alpha_mode` parameter of a glTF alpha mode.
fn alpha_mode(mode: gltf::material::AlphaMode) -> f32 {
    match mode {
        gltf::material::AlphaMode::Opaque => raystage_scene::ALPHA_OPAQUE,
        gltf::material::AlphaMode::Mask => raystage_scene::ALPHA_MASK,
        gltf::material::AlphaMode::Blend => raystage_scene::ALPHA_BLEND,
    }
}

/// `x`, or `default` where it is not finite.
fn finite_or(x: f32, default: f32) -> f32 {
    if x.is_finite() { x } else { default }
}

/// Finite and non-negative: a factor a file got wrong becomes 0 rather than an error.
fn clean(v: Vec3) -> Vec3 {
    Vec3::from_array(v.to_array().map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 }))
}

/// The shaders an import creates: one per material and vertex-colour combination used.
#[derive(Debug)]
pub(crate) struct MaterialShaders<'d> {
    /// The shaders, by local index.
    pub specs: Vec<ShaderSpec>,
    /// What the materials used have that is not rendered, once per material.
    pub notes: Vec<String>,
    index: std::collections::HashMap<(Option<usize>, bool), u32>,
    /// The file, whose textures the extensions the gltf crate does not parse name by index.
    document: &'d gltf::Document,
}

impl<'d> MaterialShaders<'d> {
    /// No shaders yet, for the materials of `document`.
    pub fn new(document: &'d gltf::Document) -> MaterialShaders<'d> {
        MaterialShaders { specs: Vec::new(), notes: Vec::new(), index: std::collections::HashMap::new(), document }
    }

    /// The local index of the shader for `material` with or without vertex colours, made on
    /// first use.
    pub fn get(&mut self, material: &gltf::Material<'_>, vertex_colors: bool) -> u32 {
        let key = (material.index(), vertex_colors);
        if let Some(&i) = self.index.get(&key) {
            return i;
        }
        let i = self.specs.len() as u32;
        let name = material.name().map(|n| {
            // Cut at a character boundary within the limit.
            let end = (0..=n.len().min(raystage_scene::MAX_SHADER_NAME)).rev().find(|&i| n.is_char_boundary(i)).unwrap_or(0);
            n[..end].to_string()
        });
        self.specs.push(ShaderSpec { name, ..shader_for(material.index().map(|_| material), vertex_colors, self.document) });
        if material.index().is_some() && !self.index.keys().any(|(m, _)| *m == material.index()) {
            self.notes.extend(notes(material, self.document));
        }
        self.index.insert(key, i);
        i
    }
}
