//! Materials: what a shader's parameters mean at a hit point. Every shader is resolved once when
//! the frame starts (frame semantics: the values are the shader's as the frame sees them, and no
//! hit looks a parameter up by name); a hit then only applies what varies over the surface, its
//! texture and its vertex colours.

use glam::{Vec2, Vec3, Vec4};
use raystage_scene::{Frame, PreviewAttributes, PreviewPoint, Sampler, Shader, ShadingModel, SurfacePoint, Texture};

use crate::bsdf::{Bsdf, Pbr};
use crate::footprint::PixelFootprint;
use crate::sheen;
use crate::texture;

/// The smallest microfacet α of a physically based surface: a mirror-smooth α of 0 would make
/// the GGX lobe a delta, which the BSDF cannot evaluate.
const MIN_ALPHA: f32 = 1e-3;

/// A hit point's material.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Material {
    /// What the surface computes.
    pub model: ShadingModel,
    /// How it scatters light, for the models that do.
    pub bsdf: Option<Bsdf>,
    /// Its colour for previews and ambient terms: the diffuse albedo (textured, vertex
    /// coloured), the reflectance of metals and mirrors, white for glass.
    pub albedo: Vec3,
    /// Light it emits (Emissive), or its fixed colour (Constant).
    pub emission: Vec3,
    /// Glass and transmitting physically based volumes: index of refraction and absorption
    /// coefficient inside.
    pub ior: f32,
    pub absorption: Vec3,
    /// Ambient occlusion: how far occluders count.
    pub occlusion_distance: f32,
}

/// A texture a shader uses, and how it samples it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Slot<'f> {
    texture: &'f Texture,
    sampler: Sampler,
}

impl<'f> Slot<'f> {
    /// Texture slot `slot` of `shader` (its `{slot}_texture` parameter and sampler), if the
    /// shader sets a texture the frame has.
    fn of(frame: &Frame<'f>, shader: &Shader, slot: &str) -> Option<Slot<'f>> {
        let texture = frame.texture(shader.texture(&format!("{slot}_texture"))?)?;
        Some(Slot { texture, sampler: Sampler::of(shader, slot) })
    }

    /// Colour and coverage at a point, for a lookup `footprint` wide in each set of texture
    /// coordinates (see [`texture::sample`]).
    #[inline(always)]
    pub fn at(&self, local_position: Vec3, uvs: [Option<Vec2>; 2], footprint: [f32; 2]) -> Vec4 {
        texture::sample(self.texture, &self.sampler, local_position, uvs, footprint)
    }

    /// Whether the texture is an image (which a lookup filters over its footprint).
    fn is_image(&self) -> bool {
        matches!(self.texture, Texture::Image(_))
    }
}

/// A shader resolved for a frame: its material before texturing and vertex colours.
#[derive(Clone, Debug)]
struct Resolved<'f> {
    base: Material,
    /// Whether any of its textures is an image, whose lookups want a footprint.
    filters: bool,
    /// Whether its surfaces emit from their backs as well ([`Materials::emits_behind`]).
    emits_behind: bool,
    /// The textures it uses, if any: kept aside, so that the record every hit reads stays a few
    /// cache lines for the many shaders that have none.
    slots: Option<Box<Slots<'f>>>,
}

/// The textures of a shader.
#[derive(Clone, Copy, Debug)]
struct Slots<'f> {
    /// The diffuse texture, for the classes that have one and a shader that sets it.
    texture: Option<Slot<'f>>,
    /// A physically based shader's metallic-roughness texture, and its roughness factor (which
    /// the texture's green channel scales before it is squared).
    metallic_roughness: Option<(Slot<'f>, f32)>,
    /// A physically based shader's normal map, and its scale.
    normal: Option<(Slot<'f>, f32)>,
    /// A physically based shader's emissive texture (multiplying its emission).
    emissive: Option<Slot<'f>>,
    /// A physically based shader's occlusion texture, and its strength (the eye light's only).
    occlusion: Option<(Slot<'f>, f32)>,
    /// A physically based shader's textures of glTF's material extensions, if it has any: one
    /// field, so that a textured shader without them pays one test per hit for all seven.
    layers: Option<Layers<'f>>,
}

/// No textures.
const NO_SLOTS: Slots<'static> = Slots { texture: None, metallic_roughness: None, normal: None, emissive: None, occlusion: None, layers: None };

/// A physically based shader's textures of KHR_materials_specular, _transmission, _clearcoat
/// and _sheen. Each multiplies a factor: where glTF's formula is a product of the factor, the
/// factor is the resolved BSDF's own field and the texel multiplies it at the hit; where it is
/// not (a clamp or a floor between the product and the BSDF's field), the factor is kept here.
#[derive(Clone, Copy, Debug, Default)]
struct Layers<'f> {
    /// KHR_materials_specular's texture: its alpha multiplies `specular`, that is f0 and f90.
    specular: Option<Slot<'f>>,
    /// Its colour texture, and the index's reflectance head-on × `specular_color`, which the
    /// texel multiplies before f0 is held to 1.
    specular_color: Option<(Slot<'f>, Vec3)>,
    /// KHR_materials_transmission's texture: red multiplies `transmission`.
    transmission: Option<Slot<'f>>,
    /// KHR_materials_clearcoat's texture: red multiplies the coat's weight.
    clearcoat: Option<Slot<'f>>,
    /// Its roughness texture, and `clearcoat_roughness`, which green multiplies before it is
    /// squared into α.
    clearcoat_roughness: Option<(Slot<'f>, f32)>,
    /// KHR_materials_sheen's colour texture, multiplying `sheen_color`.
    sheen_color: Option<Slot<'f>>,
    /// Its roughness texture, and `sheen_roughness`, which alpha multiplies before it is
    /// floored and squared into α.
    sheen_roughness: Option<(Slot<'f>, f32)>,
}

impl<'f> Layers<'f> {
    /// The extension textures of physically based `shader`, given its index's reflectance
    /// head-on; `None` if it sets none.
    fn of(frame: &Frame<'f>, shader: &Shader, reflectance: f32) -> Option<Layers<'f>> {
        let slot = |name: &str| Slot::of(frame, shader, name);
        let layers = Layers {
            specular: slot("specular"),
            specular_color: slot("specular_color").map(|t| (t, reflectance * shader.color("specular_color"))),
            transmission: slot("transmission"),
            clearcoat: slot("clearcoat"),
            clearcoat_roughness: slot("clearcoat_roughness").map(|t| (t, shader.float("clearcoat_roughness"))),
            sheen_color: slot("sheen_color"),
            sheen_roughness: slot("sheen_roughness").map(|t| (t, shader.float("sheen_roughness"))),
        };
        layers.slots().iter().any(Option::is_some).then_some(layers)
    }

    /// Its slots, whichever are set.
    fn slots(&self) -> [Option<Slot<'f>>; 7] {
        [self.specular, self.specular_color.map(|t| t.0), self.transmission, self.clearcoat, self.clearcoat_roughness.map(|t| t.0), self.sheen_color, self.sheen_roughness.map(|t| t.0)]
    }

    /// `p`, resolved from the factors, with each texture's texel at a point multiplied in as the
    /// extensions say. Texels are held to [0, 1], as the metallic-roughness texture's are, so
    /// that no texel (of a float image the C ABI was given, say) takes the BSDF beyond its light.
    /// Images are looked up over `footprint`.
    fn apply(&self, mut p: Pbr, local_position: Vec3, uvs: [Option<Vec2>; 2], footprint: [f32; 2]) -> Pbr {
        let at = |slot: Slot<'_>| slot.at(local_position, uvs, footprint).clamp(Vec4::ZERO, Vec4::ONE);
        // KHR_materials_specular: f0 = min(reflectance × colour factor × colour texel, 1) × s
        // and f90 = s, with s = factor × alpha; p.f90 holds the factor alone until then.
        if let Some((t, tinted)) = self.specular_color {
            p.f0 = (tinted * at(t).truncate()).min(Vec3::ONE) * p.f90;
        }
        if let Some(t) = self.specular {
            let specular = at(t).w;
            (p.f0, p.f90) = (p.f0 * specular, p.f90 * specular);
        }
        if let Some(t) = self.transmission {
            p.transmission *= at(t).x;
        }
        if let Some(t) = self.clearcoat {
            p.coat *= at(t).x;
        }
        if let Some((t, roughness)) = self.clearcoat_roughness {
            p.coat_alpha = (roughness * at(t).y).powi(2).max(MIN_ALPHA);
        }
        if let Some(t) = self.sheen_color {
            p.sheen *= at(t).truncate();
        }
        if let Some((t, roughness)) = self.sheen_roughness {
            p.sheen_alpha = (roughness * at(t).w).max(sheen::MIN_ROUGHNESS).powi(2);
        }
        p
    }
}

/// What the eye-light preview shows of a shader, worked out when the frame starts: a hit on a
/// surface whose colour does not vary then costs one small lookup.
#[derive(Clone, Copy, Debug)]
struct Preview {
    /// The colour shown, unless it varies over the surface.
    colour: Vec3,
    /// Whether the eye light shades it (the models that reflect light).
    lit: bool,
    /// Whether the colour varies over the surface (a texture or vertex colours scale it).
    varies: bool,
    /// Whether a normal map tilts its normal (the preview then resolves the hit in full).
    normal_mapped: bool,
}

impl Preview {
    fn of(r: &Resolved<'_>) -> Preview {
        match r.base.model {
            ShadingModel::Constant | ShadingModel::Emissive => Preview { colour: r.base.emission, lit: false, varies: false, normal_mapped: false },
            model => Preview {
                colour: r.base.albedo,
                lit: true,
                varies: r.slots().texture.is_some() || matches!(model, ShadingModel::VertexColor | ShadingModel::PhysicallyBased),
                normal_mapped: r.slots().normal.is_some(),
            },
        }
    }
}

/// The frame's shaders, resolved (indexed by shader id), and the default shader.
pub(crate) struct Materials<'f> {
    /// How wide a lookup's share of a pixel is, for the image textures.
    footprint: PixelFootprint,
    by_id: Vec<Option<Resolved<'f>>>,
    default: Resolved<'f>,
    /// Each shader's preview: the default shader's first, then by id (ids without a shader
    /// have the default's).
    previews: Vec<Preview>,
}

impl<'f> Materials<'f> {
    /// Resolves every shader of `frame`, whose image textures are filtered over `footprint`.
    pub fn of(frame: &Frame<'f>, footprint: PixelFootprint) -> Materials<'f> {
        let mut by_id = Vec::new();
        for (id, shader) in frame.shaders() {
            let index = id.0 as usize;
            if by_id.len() <= index {
                by_id.resize(index + 1, None);
            }
            by_id[index] = Some(Resolved::of(frame, shader));
        }
        let default = Resolved::of(frame, frame.default_shader());
        let previews = std::iter::once(Preview::of(&default)).chain(by_id.iter().map(|r| Preview::of(r.as_ref().unwrap_or(&default)))).collect();
        Materials { footprint, by_id, default, previews }
    }

    /// The width of a lookup at `sp` in each set of texture coordinates, given how many units
    /// of each one unit of world length spans there (`density`, asked only of a surface with
    /// image textures; see [`PixelFootprint::in_texture`]): what [`Materials::at`] and
    /// [`Materials::mapped_normal`] filter images over.
    #[inline]
    pub fn footprint(&self, sp: &SurfacePoint<'_>, density: impl Fn(usize) -> Option<f32>) -> [f32; 2] {
        if !self.resolved(sp.shader_id).filters {
            return [0.0; 2];
        }
        self.footprint.in_texture(sp.position, sp.geometric_normal, density)
    }

    /// The material at `sp`, its images looked up over `footprint` (see [`Materials::footprint`]).
    #[inline(always)]
    pub fn at(&self, sp: &SurfacePoint<'_>, footprint: [f32; 2]) -> Material {
        self.resolved(sp.shader_id).apply(sp.local_position, [sp.uv, sp.uv1], sp.color, footprint)
    }

    /// What a preview shows at a preview point: the surface's albedo (textured, vertex
    /// coloured, darkened by an occlusion texture) and `true` for the models that reflect
    /// light, or the emitted or constant colour and `false` for those that do not. The parts of
    /// [`Materials::at`] a preview needs, without making the whole material; `attributes` is
    /// asked only by surfaces whose colour varies, and `density` (see
    /// [`Materials::footprint`]) only by those with image textures. `None` for a normal-mapped
    /// surface, whose normal needs the hit resolved in full.
    #[inline(always)]
    pub fn preview_colour(
        &self,
        pp: &PreviewPoint,
        attributes: impl FnOnce() -> PreviewAttributes,
        density: impl Fn(usize) -> Option<f32>,
    ) -> Option<(Vec3, bool)> {
        let preview = self.preview(pp.shader_id);
        if !preview.varies {
            return Some((preview.colour, preview.lit));
        }
        if preview.normal_mapped {
            return None;
        }
        let r = self.resolved(pp.shader_id);
        let a = attributes();
        let uvs = [a.uv, a.uv1];
        let footprint = if r.filters { self.footprint.in_texture(a.position, pp.normal, density) } else { [0.0; 2] };
        let albedo = r.scale(a.local_position, uvs, a.color, footprint).map_or(r.base.albedo, |s| r.base.albedo * s);
        Some(match r.slots {
            Some(_) => (albedo * r.occlusion(a.local_position, uvs, footprint), true),
            None => (albedo, true),
        })
    }

    /// How much the occlusion texture of shader `id` darkens the eye light's preview at a point
    /// (see [`Materials::preview_colour`]): 1 for a shader without one.
    #[inline]
    pub fn preview_occlusion(&self, id: Option<raystage_scene::ShaderId>, local_position: Vec3, uvs: [Option<Vec2>; 2], footprint: [f32; 2]) -> f32 {
        self.resolved(id).occlusion(local_position, uvs, footprint)
    }

    /// The emissive texture of shader `id`, which multiplies its emission (see
    /// [`Materials::emission`]) point by point.
    pub fn emission_texture(&self, id: Option<raystage_scene::ShaderId>) -> Option<Slot<'f>> {
        self.resolved(id).slots().emissive
    }

    /// The albedo of a shader that is plain matte, an untextured `Diffuse` (its material is
    /// the same at every point); `None` for every other shader.
    #[inline]
    pub fn plain_matte(&self, id: Option<raystage_scene::ShaderId>) -> Option<Vec3> {
        let r = self.resolved(id);
        (r.base.model == ShadingModel::Diffuse && r.slots.is_none()).then_some(r.base.albedo)
    }

    /// The radiance a shader emits if it is a light (an `Emissive` shader, or a physically
    /// based one with an emissive colour, that emits something): at every point of its surfaces,
    /// or, where [`Materials::emission_texture`] has a texture, before the texture multiplies it.
    pub fn emission(&self, id: Option<raystage_scene::ShaderId>) -> Option<Vec3> {
        let m = &self.resolved(id).base;
        (emits(m.model) && m.emission.max_element() > 0.0).then_some(m.emission)
    }

    /// Whether the surfaces of shader `id` emit from their backs as well as their fronts: a
    /// physically based shader that is double-sided does, as glTF's `doubleSided` means (its back
    /// faces are lit "with normals reversed", emission included: every glTF viewer, and Blender's
    /// Cycles, show them glowing); an `Emissive` shader emits from its front only, an area light
    /// as pbrt and Mitsuba make one by default. A surface emits from every side it can be seen
    /// from, then, but for `Emissive` backs (a single-sided shader's back is not seen at all).
    pub fn emits_behind(&self, id: Option<raystage_scene::ShaderId>) -> bool {
        self.resolved(id).emits_behind
    }

    /// The preview record of shader `id`.
    #[inline(always)]
    fn preview(&self, id: Option<raystage_scene::ShaderId>) -> &Preview {
        let index = id.map_or(0, |id| id.0 as usize + 1);
        self.previews.get(index).unwrap_or(&self.previews[0])
    }

    /// The shading normal at `sp` as its shader's normal map tilts it, given the tangent there
    /// for the map's texture coordinates (see [`Frame::tangent`], asked only of normal-mapped
    /// surfaces); `None` where the surface
    /// has no normal map, or where no tangent frame can be made (degenerate texture coordinates
    /// or tangents, a zero normal), or where the map would turn the normal to the surface's far
    /// side: shading then keeps the unmapped normal.
    pub fn mapped_normal(&self, sp: &SurfacePoint<'_>, footprint: [f32; 2], tangent: impl FnOnce(usize) -> Option<Vec4>) -> Option<Vec3> {
        let (slot, scale) = self.resolved(sp.shader_id).slots().normal?;
        // glTF: texels in [0, 1] are components in [−1, 1]; the scale multiplies X and Y. A
        // minified map's averaged normals are shorter; the tilt normalises them.
        let texel = slot.at(sp.local_position, [sp.uv, sp.uv1], footprint).truncate();
        let local = (texel * 2.0 - Vec3::ONE) * Vec3::new(scale, scale, 1.0);
        tilted(sp.shading_normal, sp.geometric_normal, sp.front_face, tangent(slot.sampler.set)?, local)
    }

    fn resolved(&self, id: Option<raystage_scene::ShaderId>) -> &Resolved<'f> {
        id.and_then(|id| self.by_id.get(id.0 as usize)?.as_ref()).unwrap_or(&self.default)
    }
}

/// The normal `local` of a tangent-space normal map in the world, at a point with unit shading
/// normal `n` and geometric normal `ng` (both facing the viewer, on the `front` side or not) and
/// `tangent`; `None` if the frame or the result is degenerate, or the result faces away from
/// `ng`. The frame is built on the outward normal and the result turned with it, as glTF's
/// sample viewer does for back faces.
fn tilted(n: Vec3, ng: Vec3, front: bool, tangent: Vec4, local: Vec3) -> Option<Vec3> {
    let outward = if front { n } else { -n };
    let t = (tangent.truncate() - outward * outward.dot(tangent.truncate())).try_normalize()?;
    let b = outward.cross(t) * tangent.w;
    let mapped = (t * local.x + b * local.y + outward * local.z).try_normalize()?;
    let mapped = if front { mapped } else { -mapped };
    (mapped.dot(ng) > 0.0).then_some(mapped)
}

/// The reflectance head-on of a dielectric of index `ior` in air, ((ior − 1) / (ior + 1))².
fn reflectance(ior: f32) -> f32 {
    ((ior - 1.0) / (ior + 1.0)).powi(2)
}

/// Whether surfaces of `model` emit their material's `emission` as light (a `Constant`'s colour
/// is a flat look, not light).
pub(crate) fn emits(model: ShadingModel) -> bool {
    matches!(model, ShadingModel::Emissive | ShadingModel::PhysicallyBased)
}

impl<'f> Resolved<'f> {
    /// The parameters of `shader` as its class means them.
    fn of(frame: &Frame<'f>, shader: &Shader) -> Resolved<'f> {
        let model = shader.class().model;
        let mut m = Material {
            model,
            bsdf: None,
            albedo: Vec3::ZERO,
            emission: Vec3::ZERO,
            ior: 1.0,
            absorption: Vec3::ZERO,
            occlusion_distance: 0.0,
        };
        match model {
            ShadingModel::Diffuse | ShadingModel::VertexColor => {
                m.albedo = shader.color("diffuse");
                m.bsdf = Some(Bsdf::Lambert { albedo: m.albedo });
            }
            ShadingModel::Constant => m.emission = shader.color("color"),
            ShadingModel::Phong => {
                m.albedo = shader.color("diffuse");
                let specular = shader.color("specular");
                m.bsdf = Some(Bsdf::Phong { diffuse: m.albedo, specular, exponent: shader.float("shininess") });
            }
            ShadingModel::Mirror => {
                m.albedo = shader.color("reflectance");
                m.bsdf = Some(Bsdf::Mirror { reflectance: m.albedo });
            }
            ShadingModel::Glossy => {
                m.albedo = shader.color("reflectance");
                m.bsdf = Some(Bsdf::Glossy { reflectance: m.albedo, alpha: shader.float("roughness") });
            }
            ShadingModel::Glass => {
                m.albedo = Vec3::ONE;
                m.ior = shader.float("ior");
                m.absorption = shader.color("absorption");
            }
            ShadingModel::Emissive => m.emission = shader.color("emission"),
            ShadingModel::AmbientOcclusion => {
                m.albedo = shader.color("diffuse");
                m.occlusion_distance = shader.float("distance");
            }
            ShadingModel::PhysicallyBased => {
                m.albedo = shader.color("base_color");
                m.emission = shader.color("emissive");
                let roughness = shader.float("roughness");
                let ior = shader.float("ior");
                let transmission = shader.float("transmission");
                let thin = shader.float("thickness") == 0.0;
                m.ior = ior;
                if transmission > 0.0 && !thin {
                    // KHR_materials_volume: white light turns `attenuation_color` after
                    // `attenuation_distance`, so σ = −ln(colour) / distance (a black channel
                    // absorbs as fast as floats allow, not infinitely: σ × 0 stays 0).
                    let colour = shader.color("attenuation_color").max(Vec3::splat(1e-6));
                    m.absorption = (-colour.ln() / shader.float("attenuation_distance")).max(Vec3::ZERO);
                }
                m.bsdf = Some(
                    Bsdf::PhysicallyBased(Pbr {
                        base: m.albedo,
                        metallic: shader.float("metallic"),
                        alpha: (roughness * roughness).max(MIN_ALPHA),
                        // KHR_materials_specular: the colour tints the index's reflectance
                        // head-on (at most 1), the factor scales it everywhere.
                        f0: (reflectance(ior) * shader.color("specular_color")).min(Vec3::ONE) * shader.float("specular"),
                        f90: shader.float("specular"),
                        transmission,
                        eta: 1.0,
                        thin,
                        coat: shader.float("clearcoat"),
                        coat_alpha: shader.float("clearcoat_roughness").powi(2).max(MIN_ALPHA),
                        sheen: shader.color("sheen_color"),
                        sheen_alpha: shader.float("sheen_roughness").max(sheen::MIN_ROUGHNESS).powi(2),
                    })
                    // Entering from air, until a path says which media the boundary separates.
                    .across(1.0 / ior)
                    .simplest(),
                );
            }
        }
        let texture_slot = match model {
            ShadingModel::Diffuse | ShadingModel::Phong => Some("diffuse"),
            ShadingModel::PhysicallyBased => Some("base_color"),
            _ => None,
        };
        let texture = texture_slot.and_then(|slot| Slot::of(frame, shader, slot));
        let pbr_slot = |slot: &str| (model == ShadingModel::PhysicallyBased).then(|| Slot::of(frame, shader, slot)).flatten();
        let normal = pbr_slot("normal").map(|t| (t, shader.float("normal_scale")));
        let metallic_roughness = pbr_slot("metallic_roughness").map(|t| (t, shader.float("roughness")));
        let occlusion = pbr_slot("occlusion").map(|t| (t, shader.float("occlusion_strength")));
        let emissive = pbr_slot("emissive");
        let layers = (model == ShadingModel::PhysicallyBased).then(|| Layers::of(frame, shader, reflectance(m.ior))).flatten();
        let slots = [texture, metallic_roughness.map(|t| t.0), normal.map(|t| t.0), emissive, occlusion.map(|t| t.0)];
        let layer_slots = layers.as_ref().map(Layers::slots).unwrap_or_default();
        Resolved {
            base: m,
            filters: slots.iter().chain(&layer_slots).flatten().any(Slot::is_image),
            emits_behind: model == ShadingModel::PhysicallyBased && shader.float("double_sided") != 0.0,
            slots: (slots.iter().any(Option::is_some) || layers.is_some()).then(|| Box::new(Slots { texture, metallic_roughness, normal, emissive, occlusion, layers })),
        }
    }

    /// The textures of the shader (none for most).
    #[inline(always)]
    fn slots(&self) -> &Slots<'f> {
        self.slots.as_deref().unwrap_or(&NO_SLOTS)
    }

    /// glTF's occlusion at a point: 1 + strength × (red − 1), 1 without an occlusion texture.
    #[inline]
    fn occlusion(&self, local_position: Vec3, uvs: [Option<Vec2>; 2], footprint: [f32; 2]) -> f32 {
        self.slots().occlusion.map_or(1.0, |(slot, strength)| 1.0 + strength * (slot.at(local_position, uvs, footprint).x.clamp(0.0, 1.0) - 1.0))
    }

    /// What scales the albedo at a point (see [`Resolved::apply`]): the texture, or the vertex
    /// colour of a `VertexColor` surface; nothing otherwise.
    #[inline(always)]
    fn scale(&self, local_position: Vec3, uvs: [Option<Vec2>; 2], color: Option<Vec3>, footprint: [f32; 2]) -> Option<Vec3> {
        match (self.slots().texture, self.base.model) {
            // glTF: the base colour is factor × texture × vertex colour.
            (texture, ShadingModel::PhysicallyBased) => match (texture.map(|t| t.at(local_position, uvs, footprint).truncate()), color) {
                (Some(t), Some(c)) => Some(t * c),
                (t, c) => t.or(c),
            },
            (Some(t), _) => Some(t.at(local_position, uvs, footprint).truncate()),
            (None, ShadingModel::VertexColor) => Some(color.unwrap_or(Vec3::ONE)),
            (None, _) => None,
        }
    }

    /// The material at a point with object-space position `local_position` and the mesh's
    /// interpolated texture coordinates and colour, if it has them: the diffuse albedo scaled by
    /// the texture or the vertex colour. Images are looked up over `footprint`.
    #[inline(always)]
    fn apply(&self, local_position: Vec3, uvs: [Option<Vec2>; 2], color: Option<Vec3>, footprint: [f32; 2]) -> Material {
        let mut m = self.base;
        let scale = self.scale(local_position, uvs, color, footprint);
        if let Some(emissive) = self.slots().emissive {
            m.emission *= emissive.at(local_position, uvs, footprint).truncate();
        }
        // Nothing varies the BSDF: the resolved one. A shader without textures (most) is told
        // by its missing slots alone, one test, before any slot is read.
        if scale.is_none() && self.slots.as_deref().is_none_or(|s| s.metallic_roughness.is_none() && s.layers.is_none()) {
            return m;
        }
        if let Some(scale) = scale {
            m.albedo *= scale;
        }
        m.bsdf = match m.bsdf {
            Some(Bsdf::Lambert { .. }) => Some(Bsdf::Lambert { albedo: m.albedo }),
            Some(Bsdf::Phong { specular, exponent, .. }) => Some(Bsdf::Phong { diffuse: m.albedo, specular, exponent }),
            Some(Bsdf::PhysicallyBased(p)) => {
                let Pbr { metallic, alpha, .. } = p;
                // glTF: blue is metalness, green roughness, each scaling its factor.
                let (metallic, alpha) = match self.slots().metallic_roughness {
                    Some((t, roughness)) => {
                        let texel = t.at(local_position, uvs, footprint);
                        (metallic * texel.z.clamp(0.0, 1.0), (roughness * texel.y.clamp(0.0, 1.0)).powi(2).max(MIN_ALPHA))
                    }
                    None => (metallic, alpha),
                };
                let p = Pbr { base: m.albedo, metallic, alpha, ..p };
                Some(Bsdf::PhysicallyBased(self.slots().layers.as_ref().map_or(p, |layers| layers.apply(p, local_position, uvs, footprint))))
            }
            other => other,
        };
        m
    }
}


#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3, Vec4};
    use raystage_scene::{Image, Texture};

    use super::*;

    /// A metallic-roughness texture's blue channel scales metalness and its green roughness,
    /// point by point; the vertex colours scale the base colour.
    #[test]
    fn metallic_roughness_textures_vary_the_brdf_over_the_surface() {
        // Left texel: metal, smooth; right: dielectric, rough.
        let texture = Texture::Image(Image::new(2, 1, vec![Vec3::new(0.0, 0.2, 1.0), Vec3::new(0.0, 1.0, 0.0)]).unwrap().into());
        let base = Material {
            model: ShadingModel::PhysicallyBased,
            bsdf: Some(Bsdf::PhysicallyBased(Pbr { base: Vec3::ONE, metallic: 1.0, alpha: 0.25, f0: Vec3::splat(0.04), f90: 1.0, transmission: 0.0, eta: 1.0 / 1.5, thin: true, coat: 0.0, coat_alpha: 0.01, sheen: Vec3::ZERO, sheen_alpha: 0.25 })),
            albedo: Vec3::ONE,
            emission: Vec3::ZERO,
            ior: 1.0,
            absorption: Vec3::ZERO,
            occlusion_distance: 0.0,
        };
        let slot = Slot { texture: &texture, sampler: Sampler::DEFAULT };
        let resolved = Resolved { base, filters: true, emits_behind: false, slots: Some(Box::new(Slots { metallic_roughness: Some((slot, 0.5)), ..NO_SLOTS })) };
        let at = |u: f32| match resolved.apply(Vec3::ZERO, [Some(Vec2::new(u, 0.5)), None], Some(Vec3::new(1.0, 0.5, 0.25)), [0.0; 2]).bsdf {
            Some(Bsdf::PhysicallyBased(Pbr { metallic, alpha, base, .. })) => (metallic, alpha, base),
            other => panic!("{other:?}"),
        };
        let (metallic, alpha, base) = at(0.25);
        assert_eq!((metallic, base), (1.0, Vec3::new(1.0, 0.5, 0.25)), "the vertex colour scales the base colour");
        assert!((alpha - (0.5f32 * 0.2).powi(2)).abs() < 1e-6, "{alpha}");
        let (metallic, alpha, _) = at(0.75);
        assert_eq!((metallic, alpha), (0.0, 0.25));
    }

    /// Each texture of glTF's material extensions varies its own field of the BSDF by its own
    /// channel, as the extension's formula says, and leaves every other field as resolved.
    #[test]
    fn extension_textures_vary_their_own_field_of_the_bsdf_by_their_own_channel() {
        // Every channel different, so that a slot reading the wrong one is seen; the right
        // texel's alpha is low enough for the sheen's floor.
        let (left, right) = (Vec4::new(0.2, 0.4, 0.6, 0.8), Vec4::new(0.9, 0.1, 0.3, 0.1));
        let image = Image::new(2, 1, vec![left.truncate(), right.truncate()]).unwrap().with_alpha(vec![left.w, right.w]).unwrap();
        let texture = Texture::Image(image.into());
        let slot = Slot { texture: &texture, sampler: Sampler { nearest: true, ..Sampler::DEFAULT } };
        // The factors: specular 0.5, specular colour (30, 0.5, 2) at index 1.5 (so that red's
        // reflectance head-on, 1.2, is held to 1 unless a texel darkens it first),
        // transmission 0.8, coat 0.6 of roughness 0.5, sheen (0.9, 0.2, 0.1) of roughness 0.4.
        let tinted = 0.04 * Vec3::new(30.0, 0.5, 2.0);
        let factors = Pbr { base: Vec3::ONE, metallic: 0.0, alpha: 0.25, f0: tinted.min(Vec3::ONE) * 0.5, f90: 0.5, transmission: 0.8, eta: 1.0 / 1.5, thin: true, coat: 0.6, coat_alpha: 0.25, sheen: Vec3::new(0.9, 0.2, 0.1), sheen_alpha: 0.16 };
        let base = Material { model: ShadingModel::PhysicallyBased, bsdf: Some(Bsdf::PhysicallyBased(factors)), albedo: Vec3::ONE, emission: Vec3::ZERO, ior: 1.5, absorption: Vec3::ZERO, occlusion_distance: 0.0 };
        let none = Layers::default();
        // Each case: one slot, and the BSDF glTF's formula gives from the factors at a texel.
        type Expected = fn(Pbr, Vec4) -> Pbr;
        let cases: [(Layers<'_>, Expected); 7] = [
            (Layers { specular: Some(slot), ..none }, |p, t| Pbr { f0: p.f0 * t.w, f90: 0.5 * t.w, ..p }),
            (Layers { specular_color: Some((slot, 0.04 * Vec3::new(30.0, 0.5, 2.0))), ..none }, |p, t| Pbr { f0: (0.04 * Vec3::new(30.0, 0.5, 2.0) * t.truncate()).min(Vec3::ONE) * 0.5, ..p }),
            (Layers { transmission: Some(slot), ..none }, |p, t| Pbr { transmission: 0.8 * t.x, ..p }),
            (Layers { clearcoat: Some(slot), ..none }, |p, t| Pbr { coat: 0.6 * t.x, ..p }),
            (Layers { clearcoat_roughness: Some((slot, 0.5)), ..none }, |p, t| Pbr { coat_alpha: (0.5 * t.y).powi(2), ..p }),
            (Layers { sheen_color: Some(slot), ..none }, |p, t| Pbr { sheen: Vec3::new(0.9, 0.2, 0.1) * t.truncate(), ..p }),
            (Layers { sheen_roughness: Some((slot, 0.4)), ..none }, |p, t| Pbr { sheen_alpha: (0.4 * t.w).max(0.07).powi(2), ..p }),
        ];
        let numbers = |p: Pbr| [p.base.to_array(), p.f0.to_array(), p.sheen.to_array(), [p.metallic, p.alpha, p.f90], [p.transmission, p.eta, p.coat], [p.coat_alpha, p.sheen_alpha, if p.thin { 1.0 } else { 0.0 }]].concat();
        for (k, (layers, expected)) in cases.into_iter().enumerate() {
            let resolved = Resolved { base, filters: true, emits_behind: false, slots: Some(Box::new(Slots { layers: Some(layers), ..NO_SLOTS })) };
            for (u, texel) in [(0.25, left), (0.75, right)] {
                let Some(Bsdf::PhysicallyBased(got)) = resolved.apply(Vec3::ZERO, [Some(Vec2::new(u, 0.5)), None], None, [0.0; 2]).bsdf else { panic!("case {k}: a physically based BSDF") };
                let (got, want) = (numbers(got), numbers(expected(factors, texel)));
                assert!(got.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-6), "case {k}, u = {u}: {got:?} against {want:?}");
            }
        }
        // Where the colour texel is bright, red's reflectance head-on is held to 1 after it
        // multiplies, not before; the sheen's roughness is floored after alpha multiplies.
        assert!(((tinted.x * right.x).min(1.0) - 1.0).abs() < 1e-6 && (tinted.x * left.x) < 1.0 && 0.4 * right.w < 0.07, "the cases reach the clamps");
    }

    /// A normal map tilts the shading normal within the tangent frame, on either side of the
    /// surface; degenerate frames leave it alone.
    #[test]
    fn normal_maps_tilt_the_normal_in_the_tangent_frame() {
        let tangent = Vec4::new(1.0, 0.0, 0.0, 1.0);
        let local = Vec3::new(1.0, 0.0, 1.0);
        // Front: +z outward, the map's +X is the tangent.
        let front = tilted(Vec3::Z, Vec3::Z, true, tangent, local).unwrap();
        assert!((front - Vec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-6, "{front}");
        // +Y is the bitangent n × t (up), turned by the handedness.
        let up = tilted(Vec3::Z, Vec3::Z, true, tangent, Vec3::new(0.0, 1.0, 1.0)).unwrap();
        assert!(up.y > 0.5, "{up}");
        let left_handed = tilted(Vec3::Z, Vec3::Z, true, Vec4::new(1.0, 0.0, 0.0, -1.0), Vec3::new(0.0, 1.0, 1.0)).unwrap();
        assert!(left_handed.y < -0.5, "{left_handed}");
        // Seen from behind: the same tilt of the surface, turned to the viewer's side.
        let back = tilted(-Vec3::Z, -Vec3::Z, false, tangent, local).unwrap();
        assert!((back + front).length() < 1e-6, "{back}");
        // Degenerate tangents, or a tangent along the normal: no tilt.
        assert_eq!(tilted(Vec3::Z, Vec3::Z, true, Vec4::ZERO, local), None);
        assert_eq!(tilted(Vec3::Z, Vec3::Z, true, Vec4::new(0.0, 0.0, 1.0, 1.0), local), None);
        assert_eq!(tilted(Vec3::Z, Vec3::Z, true, tangent, Vec3::new(f32::NAN, 0.0, 1.0)), None);
        // A map that points below the surface is refused.
        assert_eq!(tilted(Vec3::Z, Vec3::Z, true, tangent, Vec3::new(1.0, 0.0, -0.5)), None);
    }
}
