//! The effect set: what a frame has to simulate, derived from the scene
//! (docs/design/architecture.md, "The effect set"). The integrators run only the effects in the
//! set: a frame without lights traces no shadow rays, an opaque scene no refraction code, a still
//! scene no time samples.

use raystage_scene::{Frame, ShadingModel};

use crate::Integrator;
use crate::lights::SceneLights;

/// The effects a frame simulates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EffectSet {
    /// Shadow rays towards lights (there are lights that cast shadows and something to occlude).
    pub shadows: bool,
    /// Reflection rays (some visible material reflects specularly).
    pub reflection: bool,
    /// Refraction rays, Fresnel and Beer's law (some visible material transmits).
    pub refraction: bool,
    /// Shadows that let light through transmissive surfaces.
    pub transparent_shadows: bool,
    /// Soft shadows: area and environment lights and emitting surfaces, sampled over their extent.
    pub area_lights: bool,
    /// Depth of field: the camera has an aperture.
    pub depth_of_field: bool,
    /// Motion blur: the shutter is open and something moves while it is.
    pub motion_blur: bool,
    /// Ambient-occlusion probes (some material is an ambient-occlusion shader).
    pub ambient_occlusion: bool,
    /// Indirect light (the path tracer).
    pub global_illumination: bool,
    /// More than one sample per pixel.
    pub multisampling: bool,
}

impl EffectSet {
    /// The effects `frame`, lit by `lights`, calls for under `integrator` with `samples` samples
    /// per pixel.
    pub(crate) fn of(frame: &Frame<'_>, lights: &SceneLights<'_>, integrator: Integrator, samples: u32) -> EffectSet {
        let models = frame.shading_models();
        let uses = |f: fn(ShadingModel) -> bool| models.iter().any(|&m| f(m));
        let shading = integrator != Integrator::EyeLight;
        let has_geometry = frame.instance_count() > 0;
        // Every light but the ambient term (which the list does not hold) casts shadows.
        let shadows = shading && has_geometry && lights.len() > 0;
        let reflection = shading && uses(ShadingModel::reflects);
        let refraction = shading && frame.has_transmitters();
        let distributed = matches!(integrator, Integrator::Distribution | Integrator::Path);
        let camera = frame.camera();
        let effects = EffectSet {
            shadows,
            reflection,
            refraction,
            transparent_shadows: shadows && refraction,
            area_lights: distributed && lights.has_extended(),
            depth_of_field: distributed && camera.has_depth_of_field(),
            motion_blur: distributed && camera.has_open_shutter() && frame.has_motion(),
            ambient_occlusion: shading && uses(|m| m == ShadingModel::AmbientOcclusion),
            global_illumination: integrator == Integrator::Path && has_geometry,
            multisampling: samples > 1,
        };
        EffectSet { multisampling: effects.multisampling || effects.depth_of_field || effects.motion_blur, ..effects }
    }

    /// The effects' names, for statistics and logs.
    pub fn names(&self) -> Vec<&'static str> {
        [
            (self.shadows, "shadows"),
            (self.reflection, "reflection"),
            (self.refraction, "refraction"),
            (self.transparent_shadows, "transparent-shadows"),
            (self.area_lights, "area-lights"),
            (self.depth_of_field, "depth-of-field"),
            (self.motion_blur, "motion-blur"),
            (self.ambient_occlusion, "ambient-occlusion"),
            (self.global_illumination, "global-illumination"),
            (self.multisampling, "multisampling"),
        ]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
        .collect()
    }
}
