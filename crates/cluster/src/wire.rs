//! The messages between rank 0 and the workers, and their encoding (CBOR).

use raystage_render::RenderSettings;
use raystage_service::{Blob, SceneBuild};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

/// From rank 0 to the workers. `E` is the edit: borrowed when rank 0 encodes it, owned when a
/// worker decodes it (the two encode alike).
#[derive(Serialize, Deserialize)]
pub(crate) enum Message<E> {
    /// A scene built on rank 0 as `build` says, held as `id`. Answered, then a verdict.
    NewScene { id: u32, origin: String, build: SceneBuild },
    /// Scene `id` deleted. Answered, then a verdict.
    DeleteScene { id: u32 },
    /// An edit of scene `scene`. Answered, then a verdict.
    Edit { scene: u32, edit: E },
    /// Whether the edit just answered stands (every rank applied it) or is undone.
    Verdict { stands: bool },
    /// A progressive pass of a frame. Answered with the share's pixels.
    Pass(PassMessage),
    /// The job ends: the worker returns.
    Stop,
}

/// A pass of accumulation `key`: `samples` more samples per pixel of scene `scene` as it was
/// at `version`.
#[derive(Serialize, Deserialize)]
pub(crate) struct PassMessage {
    pub key: u64,
    pub scene: u32,
    pub version: u64,
    /// The renderer's settings, as serde writes them.
    pub settings: RenderSettings,
    pub samples: u32,
    /// The accumulation starts over (its first pass, or rank 0's was cancelled).
    pub reset: bool,
    /// No pass of this accumulation follows.
    pub last: bool,
    /// Accumulations that ended: their state can go.
    pub ended: Vec<u64>,
}

/// From a worker to rank 0.
#[derive(Serialize, Deserialize)]
pub(crate) enum Reply {
    /// The edit (or new scene, or deletion) was applied here.
    Applied,
    /// It could not be, for this reason.
    Refused(String),
    /// A pass's share: its pixels' means (in [`Share::pixels`](raystage_render::Share::pixels)
    /// order, RGB as little-endian `f32`: the very bits rank 0 would have computed), its ray counts
    /// (primary, shadow, reflection, refraction, diffuse, then non-finite samples) and the
    /// seconds it took.
    Share { pixels: Blob, counts: [u64; 6], seconds: f64 },
    /// The pass could not be rendered here, for this reason.
    Failed(String),
}

/// `value` as CBOR.
pub(crate) fn encode<T: Serialize>(value: &T) -> Vec<u8> {
    let mut bytes = Vec::new();
    ciborium::into_writer(value, &mut bytes).expect("writing to memory cannot fail, and every message serialises");
    bytes
}

/// A value from CBOR, or why it cannot be read.
pub(crate) fn decode<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, String> {
    ciborium::from_reader(bytes).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use raystage_render::{FrameSettings, SettingsPatch};
    use raystage_scene::Scene;

    use super::*;

    /// Every setting a front end sets reaches the workers: a patch that sets each one (written
    /// out whole, so that a setting added to the list fails to compile here until it is given a
    /// value) changes the renderer's settings, which travel as serde writes them, and come back
    /// from the wire as they went.
    #[test]
    fn every_setting_reaches_the_workers() {
        let patch = SettingsPatch {
            samples_per_pixel: Some(3),
            width: Some(7),
            height: Some(5),
            integrator: Some("distribution".into()),
            background: Some("0.25,0.5,1".into()),
            default_lights: Some(false),
            max_depth: Some(9),
            russian_roulette: Some(false),
            filter: Some("gaussian:2".into()),
            seed: Some(11),
            noise_threshold: Some(0.5),
            exposure: Some(1.5),
            tonemap: Some("neutral".into()),
        };
        let mut frame = FrameSettings::default();
        frame.apply(&patch).unwrap();
        let settings = frame.for_scene(&Scene::new());
        let sent: RenderSettings = decode(&encode(&settings)).unwrap();
        assert_eq!(sent, settings);
        let d = RenderSettings::default();
        let fields = [
            ("samples_per_pixel", sent.samples_per_pixel != d.samples_per_pixel),
            ("width", sent.width != d.width),
            ("height", sent.height != d.height),
            ("integrator", sent.integrator != d.integrator),
            ("background", sent.background != d.background),
            ("default_lights", sent.default_lights != d.default_lights),
            ("max_depth", sent.max_depth != d.max_depth),
            ("russian_roulette", sent.russian_roulette != d.russian_roulette),
            ("filter", sent.filter != d.filter),
            ("seed", sent.seed != d.seed),
            ("noise_threshold", sent.noise_threshold != d.noise_threshold),
        ];
        for (name, changed) in fields {
            assert!(changed, "`{name}` did not reach the settings the workers get");
        }
        // Exposure and tone curve grade the image on rank 0, where it is encoded.
        let checked: Vec<&str> = fields.iter().map(|&(name, _)| name).chain(["exposure", "tonemap"]).collect();
        assert_eq!(checked, SettingsPatch::NAMES, "every setting is checked here");
        assert_eq!((frame.look.exposure, frame.look.tone_map), (1.5, raystage_render::ToneMap::Neutral));
    }
}
