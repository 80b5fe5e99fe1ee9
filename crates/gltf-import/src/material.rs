//! glTF materials as raystage shaders: glTF 2.0's metallic-roughness model is raystage's
//! `PhysicallyBased` class, so every material maps onto it (unlit ones onto `Constant`, and
//! transmissive ones, for now, onto `Glass`); what a material has that raystage does not render
//! yet is said in a note.

use glam::Vec3;
use raystage_scene::ParamValue;

/// A shader to create: a built-in class and the parameters to write.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderSpec {
    /// The shader class (one of `raystage_scene::SHADER_CLASSES`).
    pub class: &'static str,
    /// Parameters to write, by name.
    pub params: Vec<(&'static str, ParamValue)>,
    /// Texture parameters to set once the glTF images they name are textures of the scene.
    pub textures: Vec<TextureUse>,
}

/// A glTF image a shader's texture parameter uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextureUse {
    /// The parameter.
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
/// - `KHR_materials_transmission` factor ≥ 0.5 → `Glass` with `KHR_materials_ior` (default
///   1.5);
/// - everything else → `PhysicallyBased`: base colour (factor, texture on the first texture
///   coordinates; vertex colours multiply it), metallic and roughness (factors, and their
///   texture on the first coordinates), `KHR_materials_ior`,
///   `KHR_materials_specular`'s factor, and emissive factor × `KHR_materials_emissive_strength`.
///
/// [`notes`] says what the material has beyond that.
pub fn shader_for(material: Option<&gltf::Material<'_>>, vertex_colors: bool) -> ShaderSpec {
    let Some(m) = material else {
        return if vertex_colors { spec("VertexColor", vec![]) } else { spec("Diffuse", vec![]) };
    };
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, _] = pbr.base_color_factor();
    let base = ParamValue::Color(clean(Vec3::new(r, g, b)).min(Vec3::ONE));
    let ior = m.ior().filter(|i| i.is_finite()).unwrap_or(1.5).clamp(1.0, 4.0);
    if m.unlit() {
        return spec("Constant", vec![("color", base)]);
    }
    if m.transmission().is_some_and(|t| t.transmission_factor() >= 0.5) {
        return spec("Glass", vec![("ior", ParamValue::Float(ior))]);
    }
    let fraction = |x: f32| if x.is_finite() { x.clamp(0.0, 1.0) } else { 0.0 };
    let emission = clean(Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0));
    let on_first_uvs = |t: Option<gltf::texture::Info<'_>>| t.filter(|t| t.tex_coord() == 0).map(|t| t.texture().source().index());
    let textures = [
        on_first_uvs(pbr.base_color_texture()).map(|image| TextureUse { param: "base_color_texture", image, colour: true }),
        on_first_uvs(pbr.metallic_roughness_texture()).map(|image| TextureUse { param: "metallic_roughness_texture", image, colour: false }),
    ];
    ShaderSpec {
        textures: textures.into_iter().flatten().collect(),
        ..spec(
            "PhysicallyBased",
            vec![
                ("base_color", base),
                ("metallic", ParamValue::Float(fraction(pbr.metallic_factor()))),
                ("roughness", ParamValue::Float(fraction(pbr.roughness_factor()))),
                ("ior", ParamValue::Float(ior)),
                ("specular", ParamValue::Float(m.specular().map_or(1.0, |s| fraction(s.specular_factor())))),
                ("emissive", ParamValue::Color(emission)),
            ],
        )
    }
}

/// What `material` has that its shader does not render, one note each.
pub fn notes(material: &gltf::Material<'_>) -> Vec<String> {
    let name = material.name().map_or_else(|| format!("material {}", material.index().map_or(-1, |i| i as i64)), |n| format!("material `{n}`"));
    let pbr = material.pbr_metallic_roughness();
    let mut left_out = Vec::new();
    if pbr.base_color_texture().is_some_and(|t| t.tex_coord() != 0) {
        left_out.push("a base-colour texture on a second set of texture coordinates".to_string());
    }
    if pbr.metallic_roughness_texture().is_some_and(|t| t.tex_coord() != 0) {
        left_out.push("a metallic-roughness texture on a second set of texture coordinates".to_string());
    }
    for (present, what) in [
        (material.normal_texture().is_some(), "its normal texture"),
        (material.occlusion_texture().is_some(), "its occlusion texture"),
        (material.emissive_texture().is_some(), "its emissive texture"),
        (material.alpha_mode() != gltf::material::AlphaMode::Opaque, "its alpha mode (rendered opaque)"),
        (material.specular().is_some_and(|s| s.specular_texture().is_some() || s.specular_color_texture().is_some() || s.specular_color_factor() != [1.0; 3]), "its specular colour and textures"),
        (!material.double_sided() && !material.unlit(), "single-sidedness (rendered double-sided)"),
    ] {
        if present {
            left_out.push(what.to_string());
        }
    }
    if material.transmission().is_some_and(|t| t.transmission_factor() >= 0.5) {
        left_out.push("its physically based look under the transmission (rendered as clear glass)".to_string());
    }
    left_out.into_iter().map(|what| format!("{name}: {what} is not rendered yet")).collect()
}

fn spec(class: &'static str, params: Vec<(&'static str, ParamValue)>) -> ShaderSpec {
    ShaderSpec { class, params, textures: Vec::new() }
}

/// Finite and non-negative: a factor a file got wrong becomes 0 rather than an error.
fn clean(v: Vec3) -> Vec3 {
    Vec3::from_array(v.to_array().map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 }))
}

/// The shaders an import creates: one per material and vertex-colour combination used.
#[derive(Debug, Default)]
pub(crate) struct MaterialShaders {
    /// The shaders, by local index.
    pub specs: Vec<ShaderSpec>,
    /// What the materials used have that is not rendered, once per material.
    pub notes: Vec<String>,
    index: std::collections::HashMap<(Option<usize>, bool), u32>,
}

impl MaterialShaders {
    /// The local index of the shader for `material` with or without vertex colours, made on
    /// first use.
    pub fn get(&mut self, material: &gltf::Material<'_>, vertex_colors: bool) -> u32 {
        let key = (material.index(), vertex_colors);
        if let Some(&i) = self.index.get(&key) {
            return i;
        }
        let i = self.specs.len() as u32;
        self.specs.push(shader_for(material.index().map(|_| material), vertex_colors));
        if material.index().is_some() && !self.index.keys().any(|(m, _)| *m == material.index()) {
            self.notes.extend(notes(material));
        }
        self.index.insert(key, i);
        i
    }
}
