//! Which hits count: single-sided surfaces are not there from behind, and cut-out or partly
//! transparent surfaces (glTF's alpha modes MASK and BLEND) are not there where their coverage
//! says so. The frame tests every hit traversal finds on an instance whose shaders ask for it,
//! and continues the ray past a hit that does not count, so camera rays, shadow rays and every
//! other ray see the same surfaces.

use glam::Vec2;

use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::shader::{ALPHA_BLEND, ALPHA_MASK, Shader, ShadingModel};
use crate::texture::{Image, Texture};

/// How coverage decides whether a hit counts.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Alpha {
    /// Every hit counts.
    Opaque,
    /// Hits where coverage is below the cut-off do not.
    Mask(f32),
    /// A hit counts with probability equal to the coverage.
    Blend,
}

/// What decides whether hits on a shader's surfaces count.
#[derive(Clone, Copy, Debug)]
pub(super) struct Visibility<'a> {
    single_sided: bool,
    alpha: Alpha,
    /// Coverage before the texture's.
    opacity: f32,
    /// The base colour texture, whose alpha multiplies the coverage, if it has alpha.
    texture: Option<(&'a Image, Sampler)>,
}

impl<'a> Visibility<'a> {
    /// The visibility of `shader`'s surfaces in `scene`; `None` where every hit counts (every
    /// class but `PhysicallyBased`, and physically based shaders that are double-sided and
    /// opaque).
    pub fn of(shader: &Shader, scene: &'a Scene) -> Option<Visibility<'a>> {
        if shader.class().model != ShadingModel::PhysicallyBased {
            return None;
        }
        let alpha = match shader.float("alpha_mode") {
            ALPHA_MASK => Alpha::Mask(shader.float("alpha_cutoff")),
            ALPHA_BLEND => Alpha::Blend,
            _ => Alpha::Opaque,
        };
        let single_sided = shader.float("double_sided") == 0.0;
        let texture = match shader.texture("base_color_texture").and_then(|id| scene.texture(id).ok()) {
            Some(Texture::Image(image)) if image.has_alpha() => Some((&**image, Sampler::of(shader, "base_color"))),
            _ => None,
        };
        let opacity = shader.float("opacity");
        let cuts = match alpha {
            Alpha::Opaque => false,
            // A cut-off of 0 keeps everything: only coverage below it is cut.
            Alpha::Mask(cutoff) => cutoff > 0.0 && (opacity < cutoff || texture.is_some()),
            Alpha::Blend => opacity < 1.0 || texture.is_some(),
        };
        (single_sided || cuts).then_some(Visibility { single_sided, alpha, opacity, texture })
    }

    /// Whether a hit counts that is on the surface's front or not (`front`), with the mesh's
    /// texture coordinates there (`uvs`, asked only of textured coverage); `key` identifies the
    /// ray and the triangle, for BLEND's coin (the same ray meeting the same triangle decides
    /// the same way, so that a frame renders the same every time; asked only by BLEND).
    pub fn admits(&self, front: bool, uvs: impl FnOnce() -> [Option<Vec2>; 2], key: impl FnOnce() -> u32) -> bool {
        if self.single_sided && !front {
            return false;
        }
        if self.alpha == Alpha::Opaque {
            return true;
        }
        // The image's own coverage, never a mip level's: a cut-out keeps its shape at any
        // distance (averaged coverage would erode thin cut-outs, leaves and fences, to nothing).
        let coverage = self.opacity * self.texture.map_or(1.0, |(image, sampler)| sampler.image(image, sampler.uv(uvs()).unwrap_or(Vec2::ZERO), 0.0).w);
        match self.alpha {
            Alpha::Mask(cutoff) => coverage >= cutoff,
            // The top 24 bits of the key as a fraction in [0, 1).
            _ => ((key() >> 8) as f32) * (1.0 / (1u32 << 24) as f32) < coverage,
        }
    }
}
