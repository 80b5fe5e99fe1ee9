//! Render settings (`rtRenderMode`, `rtRenderParameteri`): how `rtSwapBuffers` renders. They
//! are the renderer's own [`FrameSettings`], the parameters applied as every front end applies
//! its settings and checked when set, so that a frame never fails on them; the image size is the
//! frame buffer's, and `RT_AUTO` picks the integrator per frame by the rule every front end
//! follows.

use std::ops::RangeInclusive;

use raystage_render::{FrameSettings, Integrator, RenderSettings, SettingsPatch};
use glam::Vec3;
use raystage_scene::{Background, Frame};

use crate::abi::enums::{
    RT_AUTO, RT_DEFAULT_LIGHTS, RT_DISTRIBUTION, RT_EYELIGHT, RT_LIGHT_SAMPLES, RT_MAX_LIGHT_SAMPLES, RT_MAX_RAY_DEPTH, RT_MAX_SAMPLES, RT_PATH,
    RT_RAY_DEPTH, RT_RENDER_MODE, RT_RUSSIAN_ROULETTE, RT_SAMPLES_PER_PIXEL, RT_SEED, RT_WHITTED,
};
use crate::abi::types::{RTenum, RTint};
use crate::context::Context;
use crate::error::{Error, finite};

/// The render modes of `rtRenderMode` and the integrators they name; `RT_AUTO` names none.
const MODES: [(RTenum, Option<Integrator>); 5] = [
    (RT_AUTO, None),
    (RT_EYELIGHT, Some(Integrator::EyeLight)),
    (RT_WHITTED, Some(Integrator::Whitted)),
    (RT_DISTRIBUTION, Some(Integrator::Distribution)),
    (RT_PATH, Some(Integrator::Path)),
];

/// How the context renders; cloned into each asynchronous frame as it starts.
#[derive(Clone, Debug, Default)]
pub(crate) struct Rendering {
    /// The render parameters and the integrator `rtRenderMode` chose (`None` for `RT_AUTO`);
    /// the size is filled in at each frame.
    frame: FrameSettings,
    /// What `rtClearColor` set (its colour is the settings' background), for the queries.
    pub clear_color: Option<[f32; 4]>,
}

impl Rendering {
    /// The settings of a `width × height` frame of `frame`. `RT_AUTO` chooses as the command
    /// line and the HTTP API do ([`Integrator::default_for`], with `RT_DEFAULT_LIGHTS`).
    pub fn settings(&self, frame: &Frame<'_>, width: u32, height: u32) -> RenderSettings {
        RenderSettings { width, height, ..self.frame.for_scene(frame.scene()) }
    }
}

/// The settings `rtRenderParameteri` writes.
#[derive(Clone, Copy, Debug)]
enum Setting {
    SamplesPerPixel,
    RayDepth,
    LightSamples,
    RussianRoulette,
    Seed,
    DefaultLights,
}

impl Setting {
    /// The setting `pname` names, with its C name and the values it takes.
    fn from_enum(pname: RTenum) -> Result<(Setting, &'static str, RangeInclusive<RTint>), Error> {
        Ok(match pname {
            RT_SAMPLES_PER_PIXEL => (Setting::SamplesPerPixel, "RT_SAMPLES_PER_PIXEL", 1..=RT_MAX_SAMPLES),
            RT_RAY_DEPTH => (Setting::RayDepth, "RT_RAY_DEPTH", 1..=RT_MAX_RAY_DEPTH),
            RT_LIGHT_SAMPLES => (Setting::LightSamples, "RT_LIGHT_SAMPLES", 1..=RT_MAX_LIGHT_SAMPLES),
            RT_RUSSIAN_ROULETTE => (Setting::RussianRoulette, "RT_RUSSIAN_ROULETTE", 0..=1),
            RT_SEED => (Setting::Seed, "RT_SEED", 0..=RTint::MAX),
            RT_DEFAULT_LIGHTS => (Setting::DefaultLights, "RT_DEFAULT_LIGHTS", 0..=1),
            RT_RENDER_MODE => return Err(Error::invalid_enum("RT_RENDER_MODE is set with rtRenderMode")),
            _ => {
                return Err(Error::invalid_enum(format!(
                    "{pname:#x} is not a render parameter (RT_SAMPLES_PER_PIXEL, RT_RAY_DEPTH, RT_LIGHT_SAMPLES, \
                     RT_RUSSIAN_ROULETTE, RT_SEED or RT_DEFAULT_LIGHTS)"
                )));
            }
        })
    }

    fn get(self, s: &RenderSettings) -> RTint {
        // Every value fits: each was set from an RTint in range.
        match self {
            Setting::SamplesPerPixel => s.samples_per_pixel as RTint,
            Setting::RayDepth => s.max_depth as RTint,
            Setting::LightSamples => s.light_samples as RTint,
            Setting::RussianRoulette => s.russian_roulette as RTint,
            Setting::Seed => s.seed as RTint,
            Setting::DefaultLights => s.default_lights as RTint,
        }
    }

    /// Writes `value`, which [`Setting::from_enum`]'s range admits (so it is not negative), as
    /// the other front ends write their settings: through a [`SettingsPatch`].
    fn set(self, frame: &mut FrameSettings, value: RTint) -> Result<(), Error> {
        let (unsigned, switch) = (Some(value as u32), Some(value == 1));
        let patch = match self {
            Setting::SamplesPerPixel => SettingsPatch { samples_per_pixel: unsigned, ..SettingsPatch::default() },
            Setting::RayDepth => SettingsPatch { max_depth: unsigned, ..SettingsPatch::default() },
            Setting::RussianRoulette => SettingsPatch { russian_roulette: switch, ..SettingsPatch::default() },
            Setting::Seed => SettingsPatch { seed: unsigned, ..SettingsPatch::default() },
            Setting::DefaultLights => SettingsPatch { default_lights: switch, ..SettingsPatch::default() },
            // The renderer's own knob, which no other front end takes.
            Setting::LightSamples => {
                frame.render.light_samples = value as u32;
                return Ok(());
            }
        };
        frame.apply(&patch).map_err(|e| Error::invalid_value(e.to_string()))
    }
}

impl Context {
    /// `rtRenderMode`: the integrator of the frames from now on.
    pub fn render_mode(&mut self, mode: RTenum) -> Result<(), Error> {
        let (_, integrator) = MODES.into_iter().find(|&(e, _)| e == mode).ok_or_else(|| {
            Error::invalid_enum(format!(
                "{mode:#x} is not a render mode (RT_AUTO, RT_EYELIGHT, RT_WHITTED, RT_DISTRIBUTION or RT_PATH)"
            ))
        })?;
        self.rendering.frame.integrator = integrator;
        Ok(())
    }

    /// `rtRenderParameteri`: one render parameter, checked against its range.
    pub fn render_parameter(&mut self, pname: RTenum, value: RTint) -> Result<(), Error> {
        let (setting, name, range) = Setting::from_enum(pname)?;
        if !range.contains(&value) {
            return Err(Error::invalid_value(format!("{name} is {value}, not in {}..={}", range.start(), range.end())));
        }
        setting.set(&mut self.rendering.frame, value)
    }

    /// `rtClearColor`: the background colour of the frames from now on.
    pub fn clear_color(&mut self, rgba: [f32; 4]) -> Result<(), Error> {
        finite("(red, green, blue, alpha)", &rgba)?;
        let [red, green, blue, _] = rgba;
        let background = Background::Color(Vec3::new(red, green, blue));
        background.validate()?;
        (self.rendering.frame.render.background, self.rendering.clear_color) = (Some(background), Some(rgba));
        Ok(())
    }

    /// `rtGetRenderParameteri`: the render mode or a render parameter.
    pub fn get_render_parameter(&self, pname: RTenum) -> Result<RTint, Error> {
        if pname == RT_RENDER_MODE {
            let (mode, _) = MODES.into_iter().find(|&(_, i)| i == self.rendering.frame.integrator).expect("every integrator has a mode");
            return Ok(mode as RTint);
        }
        let (setting, ..) = Setting::from_enum(pname)?;
        Ok(setting.get(&self.rendering.frame.render))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_limits_are_the_renderers() {
        assert_eq!(RT_MAX_SAMPLES as u32, raystage_render::MAX_SAMPLES);
        assert_eq!(RT_MAX_RAY_DEPTH as u32, raystage_render::MAX_DEPTH);
        assert_eq!(RT_MAX_LIGHT_SAMPLES as u32, raystage_render::MAX_LIGHT_SAMPLES);
    }

    #[test]
    fn every_value_in_range_makes_valid_settings() {
        let mut ctx = Context::default();
        for pname in [RT_SAMPLES_PER_PIXEL, RT_RAY_DEPTH, RT_LIGHT_SAMPLES, RT_RUSSIAN_ROULETTE, RT_SEED, RT_DEFAULT_LIGHTS] {
            let (_, _, range) = Setting::from_enum(pname).unwrap();
            for value in [*range.start(), *range.end()] {
                ctx.render_parameter(pname, value).unwrap();
                assert_eq!(ctx.get_render_parameter(pname), Ok(value));
                ctx.rendering.frame.render.validate().unwrap();
            }
        }
    }
}
