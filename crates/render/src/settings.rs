//! A frame's settings: [`RenderSettings`], everything the renderer needs, and the front ends'
//! view of them. Every front end (the command line, a frame's query string, a stream's query and
//! `settings` message, the C render parameters) takes a [`SettingsPatch`] and applies it with
//! [`FrameSettings::apply`], which checks it and names the setting at fault; the front ends'
//! types are made from one list, [`frame_settings!`](crate::frame_settings), so that a new
//! setting is added in one place: the list, and `apply`.

use raystage_scene::{Background, Light, Scene, SceneError};
use serde::{Deserialize, Serialize};

use crate::{Error, Look};

/// Largest image width or height.
pub const MAX_DIMENSION: u32 = 16_384;
/// Most samples per pixel in one call.
pub const MAX_SAMPLES: u32 = 65_536;
/// Deepest recursion or path.
pub const MAX_DEPTH: u32 = 64;
/// Most shadow rays per extended light at a shading point.
pub const MAX_LIGHT_SAMPLES: u32 = 256;
/// Samples every pixel takes before adaptive sampling may stop its tile: fewer give too
/// uncertain an estimate of the noise.
pub const MIN_ADAPTIVE_SAMPLES: u32 = 16;

/// How a camera ray's colour is computed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Integrator {
    /// Fast preview: a light at the eye, no secondary rays.
    #[default]
    EyeLight,
    /// Whitted 1980: shadows, reflection and refraction, recursively.
    Whitted,
    /// Cook 1984: Whitted's rays distributed over pixel, lens, time, lights and glossy lobes.
    Distribution,
    /// Unbiased path tracing with next-event estimation and multiple importance sampling.
    Path,
}

impl Integrator {
    /// Every integrator.
    pub const ALL: [Integrator; 4] = [Integrator::EyeLight, Integrator::Whitted, Integrator::Distribution, Integrator::Path];

    /// Its name: `eyelight`, `whitted`, `distribution`, `path`.
    pub fn name(self) -> &'static str {
        match self {
            Integrator::EyeLight => "eyelight",
            Integrator::Whitted => "whitted",
            Integrator::Distribution => "distribution",
            Integrator::Path => "path",
        }
    }

    /// Parses a name as printed by [`Integrator::name`].
    pub fn from_name(name: &str) -> Option<Integrator> {
        Integrator::ALL.into_iter().find(|i| i.name() == name)
    }

    /// The integrator `scene` is rendered with when none is named, the one rule every front end
    /// follows (through [`FrameSettings::for_scene`]): the path tracer where an image environment lights it (a studio or
    /// an HDR sky, as a glTF file is lit by default), since the recursive integrators see such
    /// light only through shadow rays and mirror reflections, which turns glossy materials into
    /// mirrors; Whitted's ray tracing where anything else lights it (its lights, an emitting
    /// surface, or the default sky with `default_lights`); the eye-light preview where nothing
    /// does, so that an unlit scene is not black.
    pub fn default_for(scene: &Scene, default_lights: bool) -> Integrator {
        if scene.lights().any(|(_, light)| matches!(light, Light::Environment { map: Some(_), .. })) {
            Integrator::Path
        } else if default_lights || scene.lights().next().is_some() || scene.shaders().any(|(_, s)| s.emits()) {
            Integrator::Whitted
        } else {
            Integrator::EyeLight
        }
    }
}

/// The pixel reconstruction filter. Samples are placed with the filter's distribution around the
/// pixel centre and averaged with equal weight (filter importance sampling), which is unbiased
/// and keeps every sample within its own pixel's accumulator.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum Filter {
    /// Uniform over the pixel.
    #[default]
    Box,
    /// A Gaussian of standard deviation `radius / 3`, cut off at `radius` pixels.
    Gaussian {
        /// Cut-off radius in pixels, in `(0, 4]`.
        radius: f32,
    },
}

impl std::str::FromStr for Filter {
    type Err = Error;

    /// `box`, `gaussian` (radius 1.5 pixels) or `gaussian:RADIUS`.
    fn from_str(text: &str) -> Result<Filter, Error> {
        let bad = |message: String| Error::Setting { field: "filter", message };
        match text.split_once(':') {
            None if text == "box" => Ok(Filter::Box),
            None if text == "gaussian" => Ok(Filter::Gaussian { radius: 1.5 }),
            Some(("gaussian", radius)) => match radius.parse::<f32>() {
                Ok(radius) if radius > 0.0 && radius <= 4.0 => Ok(Filter::Gaussian { radius }),
                _ => Err(bad(format!("the Gaussian's radius `{radius}` is not a number in (0, 4]"))),
            },
            _ => Err(bad(format!("`{text}` is not box, gaussian or gaussian:RADIUS"))),
        }
    }
}

impl Filter {
    /// The offset of a sample from the pixel's top-left corner, from two uniform numbers.
    pub(crate) fn offset(self, u: [f32; 2]) -> [f32; 2] {
        match self {
            Filter::Box => u,
            Filter::Gaussian { radius } => {
                let sigma = radius / 3.0;
                let r = (sigma * (-2.0 * (1.0 - u[0]).ln()).sqrt()).min(radius);
                let phi = std::f32::consts::TAU * u[1];
                [0.5 + r * phi.cos(), 0.5 + r * phi.sin()]
            }
        }
    }
}

/// Everything that decides how a frame is rendered. An MPI cluster's ranks send it to each
/// other as serde writes it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// How camera rays are coloured.
    pub integrator: Integrator,
    /// Samples per pixel.
    pub samples_per_pixel: u32,
    /// Where an accumulation goes on past `samples_per_pixel` (a stream's passes), the samples
    /// per pixel it ends at: each pixel's sample sequence is laid out for that many, and
    /// neighbouring pixels' samples are stratified together up to it (see
    /// docs/design/sampling.md); `None` for `samples_per_pixel`.
    pub planned_samples: Option<u32>,
    /// Deepest recursion (Whitted, distribution) or longest path (path tracer), the path in
    /// segments with the camera ray, as Mitsuba counts them (1: emitters seen directly only).
    pub max_depth: u32,
    /// Shadow rays per area or environment light at each shading point, when soft shadows
    /// are simulated (more rays per point, less noise per sample).
    pub light_samples: u32,
    /// Whether the path tracer may end paths early by Russian roulette (unbiased, cheaper
    /// per sample, noisier); off, paths run to `max_depth` unless they escape.
    pub russian_roulette: bool,
    /// Pixel reconstruction filter.
    pub filter: Filter,
    /// Seed of the sample sequences.
    pub seed: u32,
    /// Adaptive sampling: a tile stops taking samples once each of its pixels' standard error
    /// is below this fraction of its mean luminance (after [`MIN_ADAPTIVE_SAMPLES`]), so that
    /// samples go where the noise is; `None` gives every pixel `samples_per_pixel`.
    pub noise_threshold: Option<f32>,
    /// Whether a scene that nothing lights (no light, no emitting surface, no environment) is
    /// lit by the sky as an environment light, as the frame's statistics then say (the
    /// default); off, it stays dark.
    pub default_lights: bool,
    /// What camera rays that hit nothing show; `None` for the scene's environment light if it
    /// has one, else the scene's background if it sets one, else the sky where the default
    /// lights the scene, else black.
    pub background: Option<Background>,
    /// Whether to run the shading kernel compiled for the frame's effect set (the default).
    /// Off, every frame runs the general kernel with reflection and refraction compiled in, which
    /// computes the same image: the switch exists to measure what specialisation saves.
    pub specialize: bool,
    /// Whether to take the fast paths of docs/design/fast-paths.md (the default): camera rays
    /// traced in packets (and a lone instance walked in place), the first hits' shadows towards
    /// point, spot and directional lights in packets and their matte shading a packet at a
    /// time, the preview's packets. Off, every ray goes the general way, one by one, which
    /// computes the same image bit for bit (`crates/render/tests/fast_paths.rs` holds them to
    /// it): the switch exists to test the fast paths and to measure what they save.
    pub fast_paths: bool,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 640,
            height: 360,
            integrator: Integrator::EyeLight,
            samples_per_pixel: 1,
            planned_samples: None,
            max_depth: 6,
            light_samples: 1,
            russian_roulette: true,
            filter: Filter::Box,
            seed: 0,
            noise_threshold: None,
            default_lights: true,
            background: None,
            specialize: true,
            fast_paths: true,
        }
    }
}

impl RenderSettings {
    /// The samples per pixel the pixels' sample sequences are laid out for: the planned
    /// samples, else `samples_per_pixel`.
    pub fn laid_out_for(&self) -> u32 {
        self.planned_samples.unwrap_or(self.samples_per_pixel)
    }

    /// Checks every value is in its range.
    pub fn validate(&self) -> Result<(), Error> {
        let check = |ok: bool, field: &'static str, message: String| if ok { Ok(()) } else { Err(Error::Setting { field, message }) };
        check((1..=MAX_DIMENSION).contains(&self.width), "width", format!("{} is not in 1..={MAX_DIMENSION}", self.width))?;
        check((1..=MAX_DIMENSION).contains(&self.height), "height", format!("{} is not in 1..={MAX_DIMENSION}", self.height))?;
        check(
            (1..=MAX_SAMPLES).contains(&self.samples_per_pixel),
            "samples_per_pixel",
            format!("{} is not in 1..={MAX_SAMPLES}", self.samples_per_pixel),
        )?;
        if let Some(planned) = self.planned_samples {
            check((1..=MAX_SAMPLES).contains(&planned), "planned_samples", format!("{planned} is not in 1..={MAX_SAMPLES}"))?;
        }
        check((1..=MAX_DEPTH).contains(&self.max_depth), "max_depth", format!("{} is not in 1..={MAX_DEPTH}", self.max_depth))?;
        check(
            (1..=MAX_LIGHT_SAMPLES).contains(&self.light_samples),
            "light_samples",
            format!("{} is not in 1..={MAX_LIGHT_SAMPLES}", self.light_samples),
        )?;
        if let Filter::Gaussian { radius } = self.filter {
            check(radius > 0.0 && radius <= 4.0, "filter.radius", format!("{radius} is not in (0, 4]"))?;
        }
        if let Some(threshold) = self.noise_threshold {
            check(threshold > 0.0 && threshold <= 1.0, "noise_threshold", format!("{threshold} is not in (0, 1]"))?;
        }
        if let Some(Background::Color(c)) = self.background {
            check(c.is_finite() && c.min_element() >= 0.0, "background", format!("{c} is not a finite, non-negative colour"))?;
        }
        Ok(())
    }
}

/// Calls `$then!` with `$head` followed by the list of a frame's settings as the front ends take
/// them, one entry per setting: its documentation, `name: Type`, its limits in brackets (utoipa's
/// `minimum`, `maximum` and `value_type`, for the front ends the OpenAPI document describes) and
/// its command-line flag's attributes in braces (clap's, for `raystage render`). A front end's
/// type is made from the list, with `Option<Type>` for each setting, so that it takes every
/// setting the others take, under the same name, described the same way.
///
/// The sample count is not in the list: a frame's `spp` is the samples it renders, a stream's
/// `max_samples` the samples it refines to, so each front end adds its own. The `value_type`s
/// name `IntegratorName` and `ToneMapName`, and the flags `parse_switch` (`on` or `off`): a
/// front end that uses the limits or the flags has them in scope.
#[macro_export]
macro_rules! frame_settings {
    ($then:ident! { $($head:tt)* }) => {
        $then! {
            $($head)*
            /// Width in pixels (640 unless given; 1920 on the command line).
            width: u32 [minimum = 1] {long},
            /// Height in pixels (360 unless given; 1080 on the command line).
            height: u32 [minimum = 1] {long},
            /// How pixels are shaded: `eyelight`, `whitted`, `distribution` or `path`; by default
            /// `path` where an image environment lights the scene (the studio a glTF file without
            /// lights gets), else `whitted` if anything lights it (a light, an emitting surface,
            /// or the default sky unless `default_lights` is false), else `eyelight`.
            integrator: String [value_type = Option<IntegratorName>] {long},
            /// What camera rays that hit nothing show: `sky`, `black` or `R,G,B`; by default the
            /// environment light if the scene has one, else the scene's choice, else the sky where
            /// the default lights the scene, else black.
            background: String [] {long, allow_hyphen_values = true},
            /// Whether a scene that nothing lights (no light, no emitting surface) is lit by the
            /// default sky; default true (on the command line, `--no-default-lights` turns it off).
            default_lights: bool [] {skip},
            /// Longest path in segments, the camera ray included (as Mitsuba counts), or deepest
            /// recursion: 1 to 64; default 6.
            max_depth: u32 [minimum = 1, maximum = 64] {long},
            /// Whether the path tracer may end paths early by Russian roulette (unbiased, cheaper
            /// per sample, noisier); default true (`on` or `off` on the command line).
            russian_roulette: bool [] {long, value_parser = parse_switch, action = clap::ArgAction::Set},
            /// The pixel filter: `box` (the plain average over the pixel's square), `gaussian` or
            /// `gaussian:RADIUS` (in pixels, up to 4); default `box`.
            filter: String [] {long},
            /// Seed of the sample sequences; default 0.
            seed: u32 [] {long},
            /// Adaptive sampling: tiles stop taking samples once each pixel's standard error is
            /// below this fraction of its brightness, in (0, 1] (after 16 samples); default none
            /// (every pixel gets all its samples).
            noise_threshold: f32 [exclusive_minimum = 0, maximum = 1] {long},
            /// Exposure in stops: the image is scaled by 2 to this power; default 0. A stream
            /// re-grades its image for a new exposure or tone curve without rendering it again.
            exposure: f32 [] {long, allow_hyphen_values = true},
            /// The tone curve of 8-bit images: `clamp` (the default: light as it is, clipped at
            /// white) or `neutral` (the Khronos PBR Neutral tone mapper).
            tonemap: String [value_type = Option<ToneMapName>] {long},
        }
    };
}

/// Makes [`SettingsPatch`] from the list of [`frame_settings!`](crate::frame_settings).
macro_rules! settings_patch {
    ($( $(#[doc = $doc:literal])* $name:ident: $type:ty [$($limits:tt)*] {$($flag:tt)*}, )*) => {
        /// A change to a frame's settings, as a front end takes it: each setting it sets, unset
        /// ones left as they are. Names are given as the front ends take them (`path`,
        /// `gaussian:1.5`), and parsed and checked by [`FrameSettings::apply`].
        #[derive(Clone, Debug, Default, PartialEq)]
        pub struct SettingsPatch {
            /// Samples per pixel (a frame's `spp`).
            pub samples_per_pixel: Option<u32>,
            $( $(#[doc = $doc])* pub $name: Option<$type>, )*
        }

        impl SettingsPatch {
            /// Every setting's name, as the patch spells it.
            pub const NAMES: &[&str] = &["samples_per_pixel", $(stringify!($name)),*];
        }
    };
}

frame_settings!(settings_patch! {});

/// A frame's settings as a front end keeps them between frames: the renderer's, the integrator
/// if one was named, and how the image is graded.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameSettings {
    /// How frames are rendered; [`FrameSettings::for_scene`] replaces the integrator.
    pub render: RenderSettings,
    /// The integrator named; `None` for [`Integrator::default_for`] each frame's scene.
    pub integrator: Option<Integrator>,
    /// How an image is graded: exposure and tone curve.
    pub look: Look,
}

impl FrameSettings {
    /// Applies `patch`: every setting it sets, parsed and checked; on an error (naming the first
    /// setting at fault) nothing changes.
    pub fn apply(&mut self, patch: &SettingsPatch) -> Result<(), Error> {
        // Taken apart field by field, so that a setting added to the list fails to compile here
        // until it is applied.
        let SettingsPatch {
            samples_per_pixel,
            width,
            height,
            integrator,
            background,
            default_lights,
            max_depth,
            russian_roulette,
            filter,
            seed,
            noise_threshold,
            exposure,
            tonemap,
        } = patch;
        let mut next = *self;
        let render = &mut next.render;
        let set = |value: &mut u32, patched: &Option<u32>| *value = patched.unwrap_or(*value);
        set(&mut render.samples_per_pixel, samples_per_pixel);
        set(&mut render.width, width);
        set(&mut render.height, height);
        set(&mut render.max_depth, max_depth);
        set(&mut render.seed, seed);
        render.default_lights = default_lights.unwrap_or(render.default_lights);
        render.russian_roulette = russian_roulette.unwrap_or(render.russian_roulette);
        render.noise_threshold = noise_threshold.or(render.noise_threshold);
        if let Some(name) = integrator {
            let unknown = || Error::Setting { field: "integrator", message: format!("unknown integrator `{name}`: expected eyelight, whitted, distribution or path") };
            next.integrator = Some(Integrator::from_name(name).ok_or_else(unknown)?);
        }
        if let Some(text) = background {
            let background = text.parse().map_err(|e| match e {
                SceneError::OutOfRange { message, .. } => Error::Setting { field: "background", message },
                e => Error::Setting { field: "background", message: e.to_string() },
            })?;
            render.background = Some(background);
        }
        if let Some(text) = filter {
            render.filter = text.parse()?;
        }
        if let Some(exposure) = *exposure {
            if !exposure.is_finite() {
                return Err(Error::Setting { field: "exposure", message: format!("{exposure} is not a number of stops") });
            }
            next.look.exposure = exposure;
        }
        if let Some(text) = tonemap {
            next.look.tone_map = text.parse()?;
        }
        next.render.validate()?;
        *self = next;
        Ok(())
    }

    /// The renderer's settings for a frame of `scene`: the integrator named, else
    /// [`Integrator::default_for`] the scene.
    pub fn for_scene(&self, scene: &Scene) -> RenderSettings {
        let integrator = self.integrator.unwrap_or_else(|| Integrator::default_for(scene, self.render.default_lights));
        RenderSettings { integrator, ..self.render }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_are_checked() {
        let bad = RenderSettings { samples_per_pixel: 0, ..RenderSettings::default() };
        assert_eq!(bad.validate().unwrap_err().to_string(), "samples_per_pixel is out of range: 0 is not in 1..=65536");
        assert!(RenderSettings { filter: Filter::Gaussian { radius: 9.0 }, ..RenderSettings::default() }.validate().is_err());
        let planned = RenderSettings { planned_samples: Some(0), ..RenderSettings::default() };
        assert_eq!(planned.validate().unwrap_err().to_string(), "planned_samples is out of range: 0 is not in 1..=65536");
        assert!(RenderSettings::default().validate().is_ok());
    }

    #[test]
    fn a_patch_is_applied_whole_or_not_at_all_naming_the_setting_at_fault() {
        let mut frame = FrameSettings::default();
        let patch = SettingsPatch { width: Some(32), integrator: Some("path".into()), filter: Some("gaussian:1".into()), exposure: Some(-1.0), ..SettingsPatch::default() };
        frame.apply(&patch).unwrap();
        assert_eq!((frame.render.width, frame.integrator, frame.render.filter, frame.look.exposure), (32, Some(Integrator::Path), Filter::Gaussian { radius: 1.0 }, -1.0));
        for (patch, field) in [
            (SettingsPatch { integrator: Some("radiosity".into()), ..SettingsPatch::default() }, "integrator"),
            (SettingsPatch { background: Some("blue".into()), ..SettingsPatch::default() }, "background"),
            (SettingsPatch { max_depth: Some(0), ..SettingsPatch::default() }, "max_depth"),
            (SettingsPatch { exposure: Some(f32::INFINITY), ..SettingsPatch::default() }, "exposure"),
            (SettingsPatch { tonemap: Some("aces".into()), ..SettingsPatch::default() }, "tonemap"),
            (SettingsPatch { width: Some(8), noise_threshold: Some(2.0), ..SettingsPatch::default() }, "noise_threshold"),
        ] {
            let before = frame;
            match frame.apply(&patch) {
                Err(Error::Setting { field: named, .. }) => assert_eq!(named, field),
                other => panic!("{patch:?}: {other:?}"),
            }
            assert_eq!(frame, before, "{field}: a refused patch changes nothing");
        }
    }
}
