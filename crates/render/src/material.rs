//! Materials: what a shader's parameters mean at a hit point, resolved once per hit from the
//! shader the triangle refers to (frame semantics: the values are the shader's as the frame
//! sees them).

use glam::Vec3;
use raystage_scene::{Frame, ShadingModel, SurfacePoint};

use crate::bsdf::Bsdf;
use crate::texture;

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
    /// Glass: index of refraction and absorption coefficient.
    pub ior: f32,
    pub absorption: Vec3,
    /// Ambient occlusion: how far occluders count.
    pub occlusion_distance: f32,
}

impl Material {
    /// The material at `sp`.
    pub fn at(frame: &Frame<'_>, sp: &SurfacePoint<'_>) -> Material {
        let shader = sp.shader;
        let model = shader.class().model;
        let textured = |base: Vec3| match shader.texture("diffuse_texture").and_then(|t| frame.texture(t)) {
            Some(t) => base * texture::lookup(t, sp.local_position, sp.uv),
            None => base,
        };
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
            ShadingModel::Diffuse => {
                m.albedo = textured(shader.color("diffuse"));
                m.bsdf = Some(Bsdf::Lambert { albedo: m.albedo });
            }
            ShadingModel::VertexColor => {
                m.albedo = shader.color("diffuse") * sp.color.unwrap_or(Vec3::ONE);
                m.bsdf = Some(Bsdf::Lambert { albedo: m.albedo });
            }
            ShadingModel::Constant => m.emission = shader.color("color"),
            ShadingModel::Phong => {
                m.albedo = textured(shader.color("diffuse"));
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
        }
        m
    }
}
