//! glTF materials as raystage shaders: the metallic-roughness model mapped onto the nearest
//! built-in shader class.

use glam::Vec3;
use raystage_scene::ParamValue;

/// A shader to create: a built-in class and the parameters to write.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderSpec {
    /// The shader class (one of `raystage_scene::SHADER_CLASSES`).
    pub class: &'static str,
    /// Parameters to write, by name.
    pub params: Vec<(&'static str, ParamValue)>,
    /// The glTF image (by index in the file) whose colours multiply the diffuse colour: the
    /// material's base-colour texture, written to `diffuse_texture` once the image is a texture
    /// of the scene.
    pub texture: Option<usize>,
}

/// The shader nearest to a glTF material (`None`: the primitive has no material), for a
/// primitive with or without vertex colours. In order of precedence:
///
/// - `KHR_materials_unlit` → `Constant` with the base colour;
/// - emissive (`emissiveFactor` × `KHR_materials_emissive_strength` > 0) → `Emissive`;
/// - `KHR_materials_transmission` factor ≥ 0.5 → `Glass` with `KHR_materials_ior` (default 1.5);
/// - metallic ≥ 0.5 → `Mirror` if roughness ≤ 0.05, else `Glossy` with α = roughness²;
/// - vertex colours → `VertexColor` (the base colour multiplies them);
/// - a base-colour texture (on the first set of texture coordinates) → `Diffuse` with the base
///   colour multiplied by the texture;
/// - roughness < 0.5 → `Phong` with a dielectric highlight (4 %, exponent 2/α² − 2);
/// - otherwise `Diffuse` with the base colour.
///
/// Base-colour alpha and the other textures (normal, metallic-roughness, emissive, occlusion)
/// are ignored, and so is a base-colour texture on the shaders above the textured `Diffuse`.
pub fn shader_for(material: Option<&gltf::Material<'_>>, vertex_colors: bool) -> ShaderSpec {
    let Some(m) = material else {
        return if vertex_colors { spec("VertexColor", vec![]) } else { spec("Diffuse", vec![]) };
    };
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, _] = pbr.base_color_factor();
    let base = ParamValue::Color(clean(Vec3::new(r, g, b)).min(Vec3::ONE));
    let roughness = clean(Vec3::splat(pbr.roughness_factor())).x.min(1.0);
    let alpha = (roughness * roughness).clamp(0.01, 1.0);
    let emission = clean(Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0));
    let texture = pbr.base_color_texture().filter(|t| t.tex_coord() == 0).map(|t| t.texture().source().index());
    if m.unlit() {
        spec("Constant", vec![("color", base)])
    } else if emission.max_element() > 0.0 {
        spec("Emissive", vec![("emission", ParamValue::Color(emission))])
    } else if m.transmission().is_some_and(|t| t.transmission_factor() >= 0.5) {
        let ior = m.ior().filter(|i| i.is_finite()).unwrap_or(1.5).clamp(1.0, 4.0);
        spec("Glass", vec![("ior", ParamValue::Float(ior))])
    } else if pbr.metallic_factor() >= 0.5 {
        if roughness <= 0.05 {
            spec("Mirror", vec![("reflectance", base)])
        } else {
            spec("Glossy", vec![("reflectance", base), ("roughness", ParamValue::Float(alpha))])
        }
    } else if vertex_colors {
        spec("VertexColor", vec![("diffuse", base)])
    } else if texture.is_some() {
        ShaderSpec { texture, ..spec("Diffuse", vec![("diffuse", base)]) }
    } else if roughness < 0.5 {
        let shininess = (2.0 / (alpha * alpha) - 2.0).clamp(1.0, 10_000.0);
        spec("Phong", vec![("diffuse", base), ("specular", ParamValue::Color(Vec3::splat(0.04))), ("shininess", ParamValue::Float(shininess))])
    } else {
        spec("Diffuse", vec![("diffuse", base)])
    }
}

fn spec(class: &'static str, params: Vec<(&'static str, ParamValue)>) -> ShaderSpec {
    ShaderSpec { class, params, texture: None }
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
        self.index.insert(key, i);
        i
    }
}
