//! Surface shaders: built-in shader classes with named, typed, documented parameters, and shader
//! instances that hold values for them.
//!
//! As in the OpenRT API (docs/design/seeds.md §1.1), geometry refers to shaders by id, and
//! parameters are written by name: writing a parameter a class does not export is silently ignored,
//! so a scene graph front end can write the same material fields to every shader. Every class
//! declares its parameters and their defaults in one table, next to their documentation (as
//! pbrt-v4's `ParameterDictionary` readers do).

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
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
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
    /// The only values a number may take (codes, such as glTF's and OpenGL's wrap modes);
    /// empty for any value in `range`.
    pub choices: &'static [f32],
    /// What it does.
    pub doc: &'static str,
}

/// Any non-negative value.
const NON_NEGATIVE: [f32; 2] = [0.0, f32::INFINITY];
/// A reflectance: light out never exceeds light in.
const FRACTION: [f32; 2] = [0.0, 1.0];
/// Any finite value (the largest finite bounds, so that a listing of the range stays numbers).
const ANY_FINITE: [f32; 2] = [-f32::MAX, f32::MAX];
/// No list of choices: any value in the range.
const ANY: &[f32] = &[];

/// glTF's (and OpenGL's) wrap modes: `REPEAT`, `CLAMP_TO_EDGE`, `MIRRORED_REPEAT`.
pub const WRAP_MODES: &[f32] = &[10497.0, 33071.0, 33648.0];
/// glTF's (and OpenGL's) magnification filters: `NEAREST`, `LINEAR`.
pub const MAG_FILTERS: &[f32] = &[9728.0, 9729.0];

/// The parameters of a texture slot of a class: `{slot}_texture` and how it is sampled, after
/// glTF's `textureInfo`, sampler and `KHR_texture_transform`: wrap modes, magnification filter,
/// which texture coordinates, and an affine map of them (scaled, then rotated, then offset).
macro_rules! texture_slot {
    ($slot:literal, $doc:literal) => {
        [
            ParamDecl { name: concat!($slot, "_texture"), default: ParamValue::Texture(None), range: NON_NEGATIVE, choices: ANY, doc: $doc },
            ParamDecl { name: concat!($slot, "_wrap_s"), default: ParamValue::Float(10497.0), range: [10497.0, 33648.0], choices: WRAP_MODES, doc: concat!("How `", $slot, "_texture` wraps across u: 10497 repeat, 33071 clamp to edge, 33648 mirrored repeat (glTF's and OpenGL's codes).") },
            ParamDecl { name: concat!($slot, "_wrap_t"), default: ParamValue::Float(10497.0), range: [10497.0, 33648.0], choices: WRAP_MODES, doc: concat!("How `", $slot, "_texture` wraps across v, as `", $slot, "_wrap_s`.") },
            ParamDecl { name: concat!($slot, "_filter"), default: ParamValue::Float(9729.0), range: [9728.0, 9729.0], choices: MAG_FILTERS, doc: concat!("How `", $slot, "_texture` is magnified: 9728 nearest texel, 9729 bilinear (glTF's and OpenGL's codes).") },
            ParamDecl { name: concat!($slot, "_texcoord"), default: ParamValue::Float(0.0), range: [0.0, 1.0], choices: &[0.0, 1.0], doc: concat!("Which texture coordinates `", $slot, "_texture` reads: 0 the mesh's first set, 1 its second.") },
            ParamDecl { name: concat!($slot, "_offset_u"), default: ParamValue::Float(0.0), range: ANY_FINITE, choices: ANY, doc: concat!("Added to u after scaling and rotation, for `", $slot, "_texture` (KHR_texture_transform's offset).") },
            ParamDecl { name: concat!($slot, "_offset_v"), default: ParamValue::Float(0.0), range: ANY_FINITE, choices: ANY, doc: concat!("Added to v after scaling and rotation, for `", $slot, "_texture`.") },
            ParamDecl { name: concat!($slot, "_rotation"), default: ParamValue::Float(0.0), range: ANY_FINITE, choices: ANY, doc: concat!("Radians the texture coordinates of `", $slot, "_texture` turn counter-clockwise, after scaling (KHR_texture_transform's rotation).") },
            ParamDecl { name: concat!($slot, "_scale_u"), default: ParamValue::Float(1.0), range: ANY_FINITE, choices: ANY, doc: concat!("Multiplies u first, for `", $slot, "_texture` (KHR_texture_transform's scale).") },
            ParamDecl { name: concat!($slot, "_scale_v"), default: ParamValue::Float(1.0), range: ANY_FINITE, choices: ANY, doc: concat!("Multiplies v first, for `", $slot, "_texture`.") },
        ]
    };
}

/// The number of parameters [`texture_slot!`] declares.
const SLOT_PARAMS: usize = 10;

/// `PhysicallyBased`'s texture slots.
const PHYSICALLY_BASED_SLOTS: [[ParamDecl; SLOT_PARAMS]; 12] = [
    texture_slot!("base_color", "A texture whose colour multiplies `base_color` (and the mesh's vertex colours do too); its alpha multiplies `opacity`. None by default."),
    texture_slot!("metallic_roughness", "A texture whose blue channel multiplies `metallic` and green channel `roughness` (glTF's; its values are data, not sRGB colours); none by default."),
    texture_slot!("normal", "A tangent-space normal map (glTF's: data, +X along increasing u, +Y up the image, +Z out of the surface), tilting the shading normal in every integrator; none by default. Tangents come from the mesh, or from each triangle's texture coordinates."),
    texture_slot!("emissive", "A texture whose colour multiplies `emissive` (glTF's emissive texture, sRGB colours); none by default. Textured emitters light the scene by their texels."),
    texture_slot!("occlusion", "A texture whose red channel darkens the eye-light preview by `occlusion_strength` (glTF's ambient occlusion texture, data); none by default. The path tracer finds occlusion itself and ignores it."),
    texture_slot!("specular", "A texture whose alpha channel multiplies `specular`, at normal and grazing incidence alike (glTF's KHR_materials_specular texture; data, not sRGB); none by default. An image without alpha leaves the factor as it is."),
    texture_slot!("specular_color", "A texture whose colour multiplies `specular_color` before the reflectance head-on is held to 1 (glTF's KHR_materials_specular colour texture, sRGB colours); none by default."),
    texture_slot!("transmission", "A texture whose red channel multiplies `transmission` (glTF's KHR_materials_transmission texture, data); none by default. It cannot make a surface transmit where `transmission` is 0."),
    texture_slot!("clearcoat", "A texture whose red channel multiplies `clearcoat`, the coat's weight (glTF's KHR_materials_clearcoat texture, data); none by default."),
    texture_slot!("clearcoat_roughness", "A texture whose green channel multiplies `clearcoat_roughness` before it is squared (glTF's KHR_materials_clearcoat roughness texture, data); none by default."),
    texture_slot!("sheen_color", "A texture whose colour multiplies `sheen_color` (glTF's KHR_materials_sheen colour texture, sRGB colours); none by default."),
    texture_slot!("sheen_roughness", "A texture whose alpha channel multiplies `sheen_roughness` before it is squared (glTF's KHR_materials_sheen roughness texture, data); none by default. An image without alpha leaves the factor as it is."),
];

/// The parameters of `PhysicallyBased`: its own, then those of each texture slot.
static PHYSICALLY_BASED: [ParamDecl; PHYSICALLY_BASED_OWN.len() + PHYSICALLY_BASED_SLOTS.len() * SLOT_PARAMS] =
    joined(&PHYSICALLY_BASED_OWN, &PHYSICALLY_BASED_SLOTS);

/// `own` followed by every slot's parameters, as one table (`N` must be their total).
const fn joined<const N: usize>(own: &[ParamDecl], slots: &[[ParamDecl; SLOT_PARAMS]]) -> [ParamDecl; N] {
    assert!(own.len() + slots.len() * SLOT_PARAMS == N);
    let mut all = [own[0]; N];
    let mut i = 0;
    while i < N {
        all[i] = if i < own.len() { own[i] } else { slots[(i - own.len()) / SLOT_PARAMS][(i - own.len()) % SLOT_PARAMS] };
        i += 1;
    }
    all
}

/// `PhysicallyBased`'s parameters other than its texture slots.
const PHYSICALLY_BASED_OWN: [ParamDecl; 21] = [
    ParamDecl { name: "base_color", default: ParamValue::Color(Vec3::ONE), range: FRACTION, choices: ANY, doc: "Base colour, linear RGB: the diffuse albedo of a dielectric, the reflectance of a metal." },
    ParamDecl { name: "metallic", default: ParamValue::Float(1.0), range: FRACTION, choices: ANY, doc: "0 for a dielectric, 1 for a metal, blended between." },
    ParamDecl { name: "roughness", default: ParamValue::Float(1.0), range: FRACTION, choices: ANY, doc: "Perceptual roughness in [0, 1]; the microfacets' α is its square." },
    ParamDecl { name: "ior", default: ParamValue::Float(1.5), range: [1.0, 4.0], choices: ANY, doc: "The dielectric's index of refraction (1.5: 4 % reflected head-on); with `transmission`, it also bends the light that goes through." },
    ParamDecl { name: "transmission", default: ParamValue::Float(0.0), range: FRACTION, choices: ANY, doc: "The fraction of the dielectric base that transmits light instead of reflecting it diffusely (glTF's KHR_materials_transmission factor): what the specular layer lets through refracts through the same GGX microfacets (Walter et al. 2007), tinted by `base_color` at each crossing. 0 is opaque; metals never transmit." },
    ParamDecl { name: "thickness", default: ParamValue::Float(0.0), range: NON_NEGATIVE, choices: ANY, doc: "0: a thin wall (a leaf, a window pane, a soap film), light goes through without bending or entering a medium; above 0: the surface bounds a volume of index `ior` that light refracts into and is absorbed in (glTF's KHR_materials_volume). The path length inside comes from the geometry, not from this value." },
    ParamDecl { name: "attenuation_color", default: ParamValue::Color(Vec3::ONE), range: FRACTION, choices: ANY, doc: "The colour white light turns into after `attenuation_distance` inside a volume (Beer–Lambert); white: no absorption. Ignored for thin walls." },
    ParamDecl { name: "attenuation_distance", default: ParamValue::Float(1.0), range: [1e-6, f32::MAX], choices: ANY, doc: "The distance, in world units, after which light inside a volume has the colour `attenuation_color`." },
    ParamDecl { name: "specular", default: ParamValue::Float(1.0), range: FRACTION, choices: ANY, doc: "Scales the dielectric's specular reflection (glTF's KHR_materials_specular factor): 0 leaves a pure Lambertian base." },
    ParamDecl { name: "specular_color", default: ParamValue::Color(Vec3::ONE), range: NON_NEGATIVE, choices: ANY, doc: "Tints the dielectric's specular reflection head-on (glTF's KHR_materials_specular colour factor): its reflectance at normal incidence is that of `ior` times this colour, at most 1, times `specular`; white leaves it grey." },
    ParamDecl { name: "sheen_color", default: ParamValue::Color(Vec3::ZERO), range: FRACTION, choices: ANY, doc: "The colour of a sheen of fibres over the base, as velvet and other cloth have (glTF's KHR_materials_sheen colour factor): a back-scattering rim, brightest at grazing angles, that takes its light from what lies under it; black: none." },
    ParamDecl { name: "sheen_roughness", default: ParamValue::Float(0.0), range: FRACTION, choices: ANY, doc: "The fibres' perceptual roughness in [0, 1] (glTF's sheenRoughnessFactor; their α is the square, at least 0.07²): low for a narrow rim at grazing angles, high for a soft, wide sheen." },
    ParamDecl { name: "clearcoat", default: ParamValue::Float(0.0), range: FRACTION, choices: ANY, doc: "The weight of a clear dielectric coat (index 1.5) over the whole material, as car paint or varnish has (glTF's KHR_materials_clearcoat factor); 0: none. Every integrator renders it: lit through the whole BSDF, and reflecting the scene (Whitted's mirror ray, Cook's and the path tracer's samples of its lobe)." },
    ParamDecl { name: "clearcoat_roughness", default: ParamValue::Float(0.0), range: FRACTION, choices: ANY, doc: "The coat's perceptual roughness in [0, 1] (its microfacets' α is the square): 0 a mirror-smooth coat." },
    ParamDecl { name: "emissive", default: ParamValue::Color(Vec3::ZERO), range: NON_NEGATIVE, choices: ANY, doc: "Emitted radiance, linear RGB (glTF's emissive factor × strength): an emitting surface is a light." },
    ParamDecl { name: "normal_scale", default: ParamValue::Float(1.0), range: ANY_FINITE, choices: ANY, doc: "Scales the X and Y of `normal_texture`'s normals (glTF's normalTexture.scale): 0 flattens the map." },
    ParamDecl { name: "occlusion_strength", default: ParamValue::Float(1.0), range: FRACTION, choices: ANY, doc: "How much `occlusion_texture` darkens: 0 not at all, 1 fully (glTF's occlusionTexture.strength)." },
    ParamDecl { name: "opacity", default: ParamValue::Float(1.0), range: FRACTION, choices: ANY, doc: "Coverage (glTF's base colour alpha factor), multiplied by `base_color_texture`'s alpha; used by the `alpha_mode`s MASK and BLEND." },
    ParamDecl { name: "alpha_mode", default: ParamValue::Float(ALPHA_OPAQUE), range: [ALPHA_OPAQUE, ALPHA_BLEND], choices: &[ALPHA_OPAQUE, ALPHA_MASK, ALPHA_BLEND], doc: "glTF's alpha mode: 0 OPAQUE (coverage ignored), 1 MASK (a cut-out: where coverage is below `alpha_cutoff` the surface is not there, for camera, shadow and every other ray), 2 BLEND (a ray passes with probability 1 − coverage, so that samples average to a blend)." },
    ParamDecl { name: "alpha_cutoff", default: ParamValue::Float(0.5), range: FRACTION, choices: ANY, doc: "The coverage below which a MASK surface is cut out, in [0, 1]." },
    ParamDecl { name: "double_sided", default: ParamValue::Float(1.0), range: FRACTION, choices: &[0.0, 1.0], doc: "1: seen from both sides, and emitting from both where it emits (glTF lights a back face as its front, emission included); 0: single-sided (glTF's default), invisible from behind to every ray: camera rays, and shadow and bounce rays (which run from the shaded point towards the light) that meet its back pass through." },
];

/// `alpha_mode` OPAQUE: coverage is ignored.
pub const ALPHA_OPAQUE: f32 = 0.0;
/// `alpha_mode` MASK: a cut-out at `alpha_cutoff`.
pub const ALPHA_MASK: f32 = 1.0;
/// `alpha_mode` BLEND: rays pass in proportion to transparency.
pub const ALPHA_BLEND: f32 = 2.0;

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
    /// glTF 2.0's metallic-roughness material: a diffuse or transmitting base under a specular
    /// layer, or a metal, and what it emits.
    PhysicallyBased,
}

impl ShadingModel {
    /// Whether the surface reflects specularly, so that an integrator traces reflection rays.
    pub fn reflects(self) -> bool {
        matches!(self, ShadingModel::Mirror | ShadingModel::Glossy | ShadingModel::Glass | ShadingModel::PhysicallyBased)
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
    choices: ANY,
    doc: "Diffuse reflectance (albedo), linear RGB in [0, 1].",
};
/// The texture slot of `Diffuse` and `Phong`, sampled as `PhysicallyBased`'s are (wrap modes,
/// filter, coordinates), so that the C ABI's `rtTexParameteri` has parameters to set.
const DIFFUSE_SLOT: [ParamDecl; SLOT_PARAMS] = texture_slot!("diffuse", "A texture whose colour multiplies `diffuse`; none by default.");

/// The parameters of `Diffuse`.
static DIFFUSE_PARAMS: [ParamDecl; 1 + SLOT_PARAMS] = joined(&[DIFFUSE], &[DIFFUSE_SLOT]);

/// The parameters of `Phong`: its own, then its texture slot's.
static PHONG_PARAMS: [ParamDecl; 3 + SLOT_PARAMS] = joined(
    &[
        ParamDecl { name: "diffuse", default: ParamValue::Color(Vec3::splat(0.5)), range: FRACTION, choices: ANY, doc: "Diffuse reflectance, linear RGB." },
        ParamDecl { name: "specular", default: ParamValue::Color(Vec3::splat(0.4)), range: FRACTION, choices: ANY, doc: "Specular reflectance of the highlight." },
        ParamDecl { name: "shininess", default: ParamValue::Float(40.0), range: [1.0, 10_000.0], choices: ANY, doc: "Blinn-Phong exponent: higher is a tighter highlight (1 to 10,000)." },
    ],
    &[DIFFUSE_SLOT],
);

/// Every built-in shader class.
pub static SHADER_CLASSES: &[ShaderClass] = &[
    ShaderClass {
        name: "Diffuse",
        doc: "Matte surface: Lambertian reflection of every light, with shadows.",
        model: ShadingModel::Diffuse,
        params: &DIFFUSE_PARAMS,
    },
    ShaderClass {
        name: "VertexColor",
        doc: "Matte surface coloured by the mesh's per-vertex colours, interpolated across each triangle.",
        model: ShadingModel::VertexColor,
        params: &[ParamDecl { name: "diffuse", default: ParamValue::Color(Vec3::ONE), range: FRACTION, choices: ANY, doc: "Multiplies the vertex colours." }],
    },
    ShaderClass {
        name: "Constant",
        doc: "A flat colour that ignores the lights.",
        model: ShadingModel::Constant,
        params: &[ParamDecl { name: "color", default: ParamValue::Color(Vec3::ONE), range: NON_NEGATIVE, choices: ANY, doc: "The colour, linear RGB." }],
    },
    ShaderClass {
        name: "Phong",
        doc: "Plastic: Lambertian diffuse plus a Blinn-Phong specular highlight of each light.",
        model: ShadingModel::Phong,
        params: &PHONG_PARAMS,
    },
    ShaderClass {
        name: "Mirror",
        doc: "A perfect mirror.",
        model: ShadingModel::Mirror,
        params: &[ParamDecl { name: "reflectance", default: ParamValue::Color(Vec3::splat(0.9)), range: FRACTION, choices: ANY, doc: "Fraction of light reflected, linear RGB." }],
    },
    ShaderClass {
        name: "Glossy",
        doc: "Rough metal: a GGX microfacet reflector with Schlick's Fresnel term.",
        model: ShadingModel::Glossy,
        params: &[
            ParamDecl { name: "reflectance", default: ParamValue::Color(Vec3::splat(0.9)), range: FRACTION, choices: ANY, doc: "Reflectance at normal incidence (the metal's colour)." },
            ParamDecl { name: "roughness", default: ParamValue::Float(0.2), range: [0.01, 1.0], choices: ANY, doc: "Microfacet roughness α in (0, 1]: 0.01 is nearly a mirror, 1 very rough." },
        ],
    },
    ShaderClass {
        name: "Glass",
        doc: "A smooth dielectric: reflection and refraction weighted by Fresnel's equations, total internal reflection, and absorption inside by Beer's law. Media nest: a ray leaving a glass object returns to the medium it was in.",
        model: ShadingModel::Glass,
        params: &[
            ParamDecl { name: "ior", default: ParamValue::Float(1.5), range: [1.0, 4.0], choices: ANY, doc: "Index of refraction (1 to 4)." },
            ParamDecl { name: "absorption", default: ParamValue::Color(Vec3::ZERO), range: NON_NEGATIVE, choices: ANY, doc: "Absorption coefficient σ per unit distance: light travelling d inside keeps exp(−σd)." },
        ],
    },
    ShaderClass {
        name: "Emissive",
        doc: "A surface that glows; it lights the scene through the path tracer's bounces.",
        model: ShadingModel::Emissive,
        params: &[ParamDecl { name: "emission", default: ParamValue::Color(Vec3::ONE), range: NON_NEGATIVE, choices: ANY, doc: "Emitted radiance, linear RGB." }],
    },
    ShaderClass {
        name: "PhysicallyBased",
        doc: "glTF 2.0's metallic-roughness material, as ANARI's physicallyBased, OSPRay's principled and Cycles' Principled BSDF share it: a Lambertian base under a GGX specular layer (Fresnel from `ior`), blended by `metallic` with a GGX metal of the base colour; `transmission` turns the base into rough refraction through the same microfacets, through a thin wall or into a volume that absorbs (`thickness`, `attenuation_color`, `attenuation_distance`); and light it emits. The defaults are glTF's: a white, fully metallic, fully rough, opaque surface.",
        model: ShadingModel::PhysicallyBased,
        params: &PHYSICALLY_BASED,
    },
    ShaderClass {
        name: "AmbientOcclusion",
        doc: "Ambient occlusion: the albedo scaled by the fraction of the (cosine-weighted) hemisphere not blocked within `distance`.",
        model: ShadingModel::AmbientOcclusion,
        params: &[
            DIFFUSE,
            ParamDecl { name: "distance", default: ParamValue::Float(1.0), range: [1e-6, f32::INFINITY], choices: ANY, doc: "How far an occluder may be and still darken the point." },
        ],
    },
];

/// The built-in class called `name`.
pub fn shader_class(name: &str) -> Option<&'static ShaderClass> {
    SHADER_CLASSES.iter().find(|c| c.name == name)
}

/// The longest shader name, in bytes.
pub const MAX_SHADER_NAME: usize = 1024;

/// A shader: a class, a value for each of its parameters, and a name if it was given one.
#[derive(Clone, Debug, PartialEq)]
pub struct Shader {
    class: &'static ShaderClass,
    values: Vec<ParamValue>,
    name: Option<String>,
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

    /// Whether surfaces of this shader let light through, so that an integrator traces
    /// refraction rays: a `Glass` shader, or a `PhysicallyBased` one with some transmission.
    pub fn transmits(&self) -> bool {
        match self.class.model {
            ShadingModel::Glass => true,
            ShadingModel::PhysicallyBased => self.float("transmission") > 0.0,
            _ => false,
        }
    }

    /// A shader of the class called `class`, every parameter at its default.
    pub fn new(class: &str) -> Result<Shader, SceneError> {
        let class = shader_class(class).ok_or_else(|| SceneError::UnknownShaderClass(class.to_string()))?;
        Ok(Shader { class, values: class.params.iter().map(|p| p.default).collect(), name: None })
    }

    /// The shader's name (a glTF material's, say), if it has one.
    pub fn name(&self) -> Option<&str> {
        self.name.as_deref()
    }

    /// Names the shader (`None`: no name). Names are labels for people: they need not be
    /// unique, but are at most [`MAX_SHADER_NAME`] bytes.
    pub fn set_name(&mut self, name: Option<&str>) -> Result<(), SceneError> {
        if let Some(name) = name.filter(|n| n.len() > MAX_SHADER_NAME) {
            return Err(SceneError::OutOfRange { field: "shader name", message: format!("{} bytes is longer than {MAX_SHADER_NAME}", name.len()) });
        }
        self.name = name.map(str::to_string);
        Ok(())
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
        let choices = self.class.params[index].choices;
        if let ParamValue::Float(f) = value
            && !choices.is_empty()
            && !choices.contains(&f)
        {
            return Err(SceneError::OutOfRange {
                field: "shader parameter",
                message: format!("`{name}` of shader class `{}` must be one of {choices:?}", self.class.name),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coded_parameters_take_only_their_codes() {
        let mut shader = Shader::new("PhysicallyBased").unwrap();
        assert_eq!(shader.set("base_color_wrap_s", ParamValue::Float(33648.0)), Ok(true));
        let error = shader.set("base_color_wrap_s", ParamValue::Float(20000.0)).unwrap_err();
        assert!(error.to_string().contains("`base_color_wrap_s`") && error.to_string().contains("10497"), "{error}");
        assert!(shader.set("base_color_filter", ParamValue::Float(9730.0)).is_err());
        assert!(shader.set("base_color_texcoord", ParamValue::Float(0.5)).is_err());
        assert_eq!(shader.get("base_color_wrap_s"), Some(ParamValue::Float(33648.0)), "a refused write changes nothing");
        // Alpha: a cut-off outside [0, 1] is refused with its name; modes are codes.
        let error = shader.set("alpha_cutoff", ParamValue::Float(1.5)).unwrap_err();
        assert!(error.to_string().contains("`alpha_cutoff`") && error.to_string().contains("[0, 1]"), "{error}");
        assert!(shader.set("alpha_cutoff", ParamValue::Float(-0.1)).is_err());
        assert!(shader.set("alpha_mode", ParamValue::Float(1.5)).is_err());
        assert_eq!(shader.set("alpha_mode", ParamValue::Float(ALPHA_BLEND)), Ok(true));
        // Transforms take any finite number.
        assert_eq!(shader.set("base_color_offset_u", ParamValue::Float(-3.5)), Ok(true));
        assert!(shader.set("base_color_scale_v", ParamValue::Float(f32::INFINITY)).is_err());
    }
}
