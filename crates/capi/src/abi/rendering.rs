//! Render settings: how `rtSwapBuffers` renders, like OpenGL's `glShadeModel` and
//! `glPixelStorei`. They stay until changed (or `rtResetContext`), and each `rtSwapBuffers`
//! renders its frame from scratch with them.

use crate::abi::types::{RTenum, RTfloat, RTint};
use crate::boundary::call;

/// Chooses how frames are rendered: `RT_AUTO` (the default: the choice of `raystage render` and
/// the HTTP API, see `RT_AUTO`), `RT_EYELIGHT` (a preview lit from the eye), `RT_WHITTED` (shadows,
/// mirrors and glass), `RT_DISTRIBUTION` (soft shadows, glossy reflection, depth of field and
/// motion blur) or `RT_PATH` (global illumination). The last two need several samples per pixel
/// (`RT_SAMPLES_PER_PIXEL`) for a smooth image.
#[unsafe(no_mangle)]
pub extern "C" fn rtRenderMode(mode: RTenum) {
    call("rtRenderMode", |ctx| ctx.render_mode(mode))
}

/// Sets render parameter `pname` to `value`: `RT_SAMPLES_PER_PIXEL` (1 to `RT_MAX_SAMPLES`,
/// default 1), `RT_RAY_DEPTH` (1 to `RT_MAX_RAY_DEPTH`, default 6), `RT_LIGHT_SAMPLES` (1 to
/// `RT_MAX_LIGHT_SAMPLES`, default 1), `RT_RUSSIAN_ROULETTE` (0 or 1, default 1), `RT_SEED`
/// (0 or more, default 0) or `RT_DEFAULT_LIGHTS` (0 or 1, default 1). Another `pname` records `RT_INVALID_ENUM`, a value out of range
/// `RT_INVALID_VALUE`.
#[unsafe(no_mangle)]
pub extern "C" fn rtRenderParameteri(pname: RTenum, value: RTint) {
    call("rtRenderParameteri", |ctx| ctx.render_parameter(pname, value))
}

/// The value of render parameter `pname` (as `rtRenderParameteri` takes it), or with
/// `RT_RENDER_MODE` the mode `rtRenderMode` set. Returns 0 on error (`RT_INVALID_ENUM`).
#[unsafe(no_mangle)]
pub extern "C" fn rtGetRenderParameteri(pname: RTenum) -> RTint {
    call("rtGetRenderParameteri", |ctx| ctx.get_render_parameter(pname))
}

/// Sets the background: what rays that leave the scene show, a colour in linear RGB (each
/// component finite and not negative; values above 1 are brighter than white, as with every
/// colour in raystage). `alpha` must be finite and is kept only as state
/// (`RT_COLOR_CLEAR_VALUE`): frames are opaque. The background is a backdrop, not a light: it
/// lights nothing. Until it is called, the default background applies: the light-blue sky
/// gradient while nothing lights the scene and the default light is on (`RT_DEFAULT_LIGHTS`), the
/// radiance or map of an `EnvironmentLight` if the scene has one, and black otherwise.
#[unsafe(no_mangle)]
pub extern "C" fn rtClearColor(red: RTfloat, green: RTfloat, blue: RTfloat, alpha: RTfloat) {
    call("rtClearColor", |ctx| ctx.clear_color([red, green, blue, alpha]))
}
