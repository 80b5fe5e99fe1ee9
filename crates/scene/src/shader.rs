//! Surface shaders: built-in shader classes with named, typed, documented parameters, and shader
//! instances that hold values for them.
//!
//! As in the OpenRT API (DIGEST §1.1), geometry refers to shaders by id, and parameters are
//! written by name: writing a parameter a class does not export is silently ignored, so a scene
//! graph front end can write the same material fields to every shader. Every class declares its
//! parameters and their defaults in one table, next to their documentation (as pbrt-v4's
//! `ParameterDictionary` readers do).

use glam::Vec3;

use crate::error::SceneError;
use crate::ids::TextureId;

/// The type of a shader parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamType {
    /// One number.
    Float,
    /// A linear RGB colour, three numbers.
    Color,
    /// A texture of the scene, or none.
    Texture,
}

impl ParamType {
    /// How the type is named in error messages and documentation.
    pub fn describe(self) -> &'static str {
        match self {
            ParamType::Float => "a number",
            ParamType::Color => "a colour (three numbers)",
            ParamType::Texture => "a texture id (or none)",
        }
    }
}

/// A shader parameter value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamValue {
    /// One number.
    Float(f32),
    /// A linear RGB colour.
    Color(Vec3),
    /// A texture, looked up by id when a frame starts; `None` for no texture.
    Texture(Option<TextureId>),
}

impl ParamValue {
    /// The value's type.
    pub fn ty(&self) -> ParamType {
        match self {
            ParamValue::Float(_) => ParamType::Float,
            ParamValue::Color(_) => ParamType::Color,
            ParamValue::Texture(_) => ParamType::Texture,
        }
    }

    fn is_finite(&self) -> bool {
        match self {
            ParamValue::Float(f) => f.is_finite(),
            ParamValue::Color(c) => c.is_finite(),
            ParamValue::Texture(_) => true,
        }
    }
}

/// A parameter a shader class exports.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamDecl {
    /// Its name, as written by `rtParameterHandle` or the HTTP API.
    pub name: &'static str,
    /// Its value until written (which also fixes its type).
    pub default: ParamValue,
    /// The allowed range of a number, or of each channel of a colour.
    pub range: [f32; 2],
    /// What it does.
    pub doc: &'static str,
}

/// Any non-negative value.
const NON_NEGATIVE: [f32; 2] = [0.0, f32::INFINITY];
/// A reflectance: light out never exceeds light in.
const FRACTION: [f32; 2] = [0.0, 1.0];

/// What a shader class computes; the renderer dispatches on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShadingModel {
    /// Lambertian reflection of the lights, with shadows.
    Diffuse,
    /// Lambertian reflection with the albedo interpolated from the vertex colours.
    VertexColor,
    /// A fixed colour, unlit.
    Constant,
    /// Lambertian plus a Blinn-Phong highlight.
    Phong,
    /// A perfect mirror.
    Mirror,
    /// Rough metal: a microfacet (GGX) reflector.
    Glossy,
    /// A smooth dielectric: reflects and refracts by Fresnel's equations, absorbs inside by
    /// Beer's law.
    Glass,
    /// A light-emitting surface.
    Emissive,
    /// Ambient occlusion: the albedo scaled by how much of the hemisphere is open.
    AmbientOcclusion,
    /// glTF 2.0's metallic-roughness material: a diffuse base under a specular layer, or a
    /// metal, and what it emits.
    PhysicallyBased,
}

impl ShadingModel {
    /// Whether the surface reflects specularly, so that an integrator traces reflection rays.
    pub fn reflects(self) -> bool {
        matches!(self, ShadingModel::Mirror | ShadingModel::Glossy | ShadingModel::Glass | ShadingModel::PhysicallyBased)
    }

    /// Whether the surface transmits light, so that an integrator traces refraction rays.
    pub fn refracts(self) -> bool {
        self == ShadingModel::Glass
    }
}

/// A built-in shader class.
#[derive(Debug, PartialEq)]
pub struct ShaderClass {
    /// Its name, as given to `rtNewShaderClass` or the HTTP API.
    pub name: &'static str,
    /// What it looks like.
    pub doc: &'static str,
    /// What it computes.
    pub model: ShadingModel,
    /// The parameters it exports.
    pub params: &'static [ParamDecl],
}

const DIFFUSE: ParamDecl = ParamDecl {
    name: "diffuse",
    default: ParamValue::Color(Vec3::splat(0.8)),
    range: FRACTION,
    doc: "Diffuse reflectance (albedo), linear RGB in [0, 1].",
};
const DIFFUSE_TEXTURE: ParamDecl = ParamDecl {
    name: "diffuse_texture",
    default: ParamValue::Texture(None),
    range: NON_NEGATIVE,
    doc: "A texture whose colour multiplies `diffuse`; none by default.",
};

/// Every built-in shader class.
pub static SHADER_CLASSES: &[ShaderClass] = &[
    ShaderClass {
        name: "Diffuse",
        doc: "Matte surface: Lambertian reflection of every light, with shadows.",
        model: ShadingModel::Diffuse,
        params: &[DIFFUSE, DIFFUSE_TEXTURE],
    },
    ShaderClass {
        name: "VertexColor",
        doc: "Matte surface coloured by the mesh's per-vertex colours, interpolated across each triangle.",
        model: ShadingModel::VertexColor,
        params: &[ParamDecl { name: "diffuse", default: ParamValue::Color(Vec3::ONE), range: FRACTION, doc: "Multiplies the vertex colours." }],
    },
    ShaderClass {
        name: "Constant",
        doc: "A flat colour that ignores the lights.",
        model: ShadingModel::Constant,
        params: &[ParamDecl { name: "color", default: ParamValue::Color(Vec3::ONE), range: NON_NEGATIVE, doc: "The colour, linear RGB." }],
    },
    ShaderClass {
        name: "Phong",
        doc: "Plastic: Lambertian diffuse plus a Blinn-Phong specular highlight of each light.",
        model: ShadingModel::Phong,
        params: &[
            ParamDecl { name: "diffuse", default: ParamValue::Color(Vec3::splat(0.5)), range: FRACTION, doc: "Diffuse reflectance, linear RGB." },
            DIFFUSE_TEXTURE,
            ParamDecl { name: "specular", default: ParamValue::Color(Vec3::splat(0.4)), range: FRACTION, doc: "Specular reflectance of the highlight." },
            ParamDecl { name: "shininess", default: ParamValue::Float(40.0), range: [1.0, 10_000.0], doc: "Blinn-Phong exponent: higher is a tighter highlight (1 to 10,000)." },
        ],
    },
    ShaderClass {
        name: "Mirror",
        doc: "A perfect mirror.",
        model: ShadingModel::Mirror,
        params: &[ParamDecl { name: "reflectance", default: ParamValue::Color(Vec3::splat(0.9)), range: FRACTION, doc: "Fraction of light reflected, linear RGB." }],
    },
    ShaderClass {
        name: "Glossy",
        doc: "Rough metal: a GGX microfacet reflector with Schlick's Fresnel term.",
        model: ShadingModel::Glossy,
        params: &[
            ParamDecl { name: "reflectance", default: ParamValue::Color(Vec3::splat(0.9)), range: FRACTION, doc: "Reflectance at normal incidence (the metal's colour)." },
            ParamDecl { name: "roughness", default: ParamValue::Float(0.2), range: [0.01, 1.0], doc: "Microfacet roughness α in (0, 1]: 0.01 is nearly a mirror, 1 very rough." },
        ],
    },
    ShaderClass {
        name: "Glass",
        doc: "A smooth dielectric: reflection and refraction weighted by Fresnel's equations, total internal reflection, and absorption inside by Beer's law. Media nest: a ray leaving a glass object returns to the medium it was in.",
        model: ShadingModel::Glass,
        params: &[
            ParamDecl { name: "ior", default: ParamValue::Float(1.5), range: [1.0, 4.0], doc: "Index of refraction (1 to 4)." },
            ParamDecl { name: "absorption", default: ParamValue::Color(Vec3::ZERO), range: NON_NEGATIVE, doc: "Absorption coefficient σ per unit distance: light travelling d inside keeps exp(−σd)." },
        ],
    },
    ShaderClass {
        name: "Emissive",
        doc: "A surface that glows; it lights the scene through the path tracer's bounces.",
        model: ShadingModel::Emissive,
        params: &[ParamDecl { name: "emission", default: ParamValue::Color(Vec3::ONE), range: NON_NEGATIVE, doc: "Emitted radiance, linear RGB." }],
    },
    ShaderClass {
        name: "PhysicallyBased",
        doc: "glTF 2.0's metallic-roughness material, as ANARI's physicallyBased, OSPRay's principled and Cycles' Principled BSDF share it: a Lambertian base under a GGX specular layer (Fresnel from `ior`), blended by `metallic` with a GGX metal of the base colour; and light it emits. The defaults are glTF's: a white, fully metallic, fully rough surface.",
        model: ShadingModel::PhysicallyBased,
        params: &[
            ParamDecl { name: "base_color", default: ParamValue::Color(Vec3::ONE), range: FRACTION, doc: "Base colour, linear RGB: the diffuse albedo of a dielectric, the reflectance of a metal." },
            ParamDecl { name: "base_color_texture", default: ParamValue::Texture(None), range: NON_NEGATIVE, doc: "A texture whose colour multiplies `base_color` (and the mesh's vertex colours do too); none by default." },
            ParamDecl { name: "metallic", default: ParamValue::Float(1.0), range: FRACTION, doc: "0 for a dielectric, 1 for a metal, blended between." },
            ParamDecl { name: "roughness", default: ParamValue::Float(1.0), range: FRACTION, doc: "Perceptual roughness in [0, 1]; the microfacets' α is its square." },
            ParamDecl { name: "metallic_roughness_texture", default: ParamValue::Texture(None), range: NON_NEGATIVE, doc: "A texture whose blue channel multiplies `metallic` and green channel `roughness` (glTF's; its values are data, not sRGB colours); none by default." },
            ParamDecl { name: "ior", default: ParamValue::Float(1.5), range: [1.0, 4.0], doc: "The dielectric's index of refraction (1.5: 4 % reflected head-on)." },
            ParamDecl { name: "specular", default: ParamValue::Float(1.0), range: FRACTION, doc: "Scales the dielectric's specular reflection (glTF's KHR_materials_specular factor): 0 leaves a pure Lambertian base." },
            ParamDecl { name: "emissive", default: ParamValue::Color(Vec3::ZERO), range: NON_NEGATIVE, doc: "Emitted radiance, linear RGB (glTF's emissive factor × strength): an emitting surface is a light." },
        ],
    },
    ShaderClass {
        name: "AmbientOcclusion",
        doc: "Ambient occlusion: the albedo scaled by the fraction of the (cosine-weighted) hemisphere not blocked within `distance`.",
        model: ShadingModel::AmbientOcclusion,
        params: &[
            DIFFUSE,
            ParamDecl { name: "distance", default: ParamValue::Float(1.0), range: [1e-6, f32::INFINITY], doc: "How far an occluder may be and still darken the point." },
        ],
    },
];

/// The built-in class called `name`.
pub fn shader_class(name: &str) -> Option<&'static ShaderClass> {
    SHADER_CLASSES.iter().find(|c| c.name == name)
}

/// A shader: a class and a value for each of its parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Shader {
    class: &'static ShaderClass,
    values: Vec<ParamValue>,
}

impl Shader {
    /// Whether surfaces of this shader emit light: an `Emissive` shader, or a `PhysicallyBased`
    /// one with an emissive colour, that emits something.
    pub fn emits(&self) -> bool {
        match self.class.model {
            ShadingModel::Emissive => self.color("emission").max_element() > 0.0,
            ShadingModel::PhysicallyBased => self.color("emissive").max_element() > 0.0,
            _ => false,
        }
    }

    /// A shader of the class called `class`, every parameter at its default.
    pub fn new(class: &str) -> Result<Shader, SceneError> {
        let class = shader_class(class).ok_or_else(|| SceneError::UnknownShaderClass(class.to_string()))?;
        Ok(Shader { class, values: class.params.iter().map(|p| p.default).collect() })
    }

    /// The shader's class.
    pub fn class(&self) -> &'static ShaderClass {
        self.class
    }

    /// Writes parameter `name`. Returns `Ok(false)` if the class does not export it (the write
    /// is ignored), an error if the value has the wrong type or is not finite.
    pub fn set(&mut self, name: &str, value: ParamValue) -> Result<bool, SceneError> {
        let Some(index) = self.class.params.iter().position(|p| p.name == name) else {
            return Ok(false);
        };
        let expected = self.class.params[index].default.ty();
        if value.ty() != expected {
            return Err(SceneError::WrongParameterType {
                class: self.class.name,
                name: name.to_string(),
                expected: expected.describe(),
            });
        }
        if !value.is_finite() {
            return Err(SceneError::NotFinite { field: "shader parameter", index });
        }
        let [lo, hi] = self.class.params[index].range;
        let out_of_range = match value {
            ParamValue::Float(f) => !(lo..=hi).contains(&f),
            ParamValue::Color(c) => c.to_array().iter().any(|x| !(lo..=hi).contains(x)),
            ParamValue::Texture(_) => false,
        };
        if out_of_range {
            return Err(SceneError::OutOfRange {
                field: "shader parameter",
                message: format!("`{name}` of shader class `{}` must be within [{lo}, {hi}]", self.class.name),
            });
        }
        self.values[index] = value;
        Ok(true)
    }

    /// The value of parameter `name`, if the class exports it.
    pub fn get(&self, name: &str) -> Option<ParamValue> {
        self.class.params.iter().position(|p| p.name == name).map(|i| self.values[i])
    }

    /// The colour parameter `name` (black if the class has no such colour).
    pub fn color(&self, name: &str) -> Vec3 {
        match self.get(name) {
            Some(ParamValue::Color(c)) => c,
            _ => Vec3::ZERO,
        }
    }

    /// The number parameter `name` (0 if the class has no such number).
    pub fn float(&self, name: &str) -> f32 {
        match self.get(name) {
            Some(ParamValue::Float(f)) => f,
            _ => 0.0,
        }
    }

    /// The texture parameter `name`, if set.
    pub fn texture(&self, name: &str) -> Option<TextureId> {
        match self.get(name) {
            Some(ParamValue::Texture(t)) => t,
            _ => None,
        }
    }
}
