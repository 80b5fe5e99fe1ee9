//! The scenes a report can be made of: the built-in ones, and glTF files (through
//! `raystage-gltf-import`, as `raystage render` reads them).

use std::path::PathBuf;

use raystage_demo::StandardScene;
use raystage_demo::shading::{area_lit_spheres, cornell_room, glass_over_checker};
use raystage_scene::Scene;

use crate::Error;

/// The built-in report scenes, each small and each exercising some knob most.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BuiltinScene {
    /// The closed Cornell-style room with a glass sphere: global illumination, every knob.
    Cornell,
    /// Spheres under two area lights against a black sky: soft shadows (light samples).
    AreaSpheres,
    /// A glass sphere over a checkered floor under a sky: path depth.
    Glass,
    /// The benchmark's 10×10 sphere grid (1,000,002 triangles) under two directional lights:
    /// the BVH builders on a large mesh.
    SphereGrid,
}

impl BuiltinScene {
    /// Every built-in scene.
    pub const ALL: [BuiltinScene; 4] = [BuiltinScene::Cornell, BuiltinScene::AreaSpheres, BuiltinScene::Glass, BuiltinScene::SphereGrid];

    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            BuiltinScene::Cornell => "cornell",
            BuiltinScene::AreaSpheres => "area-spheres",
            BuiltinScene::Glass => "glass",
            BuiltinScene::SphereGrid => "spheres",
        }
    }

    /// A phrase for the report's title.
    pub fn description(self) -> &'static str {
        match self {
            BuiltinScene::Cornell => "the Cornell room (closed, one area light, a glass sphere and a box)",
            BuiltinScene::AreaSpheres => "three spheres under two area lights",
            BuiltinScene::Glass => "a glass sphere over a checkered floor under a sky",
            BuiltinScene::SphereGrid => "the 10×10 sphere grid (1,000,002 triangles) under two directional lights",
        }
    }

    /// Builds the scene.
    pub fn scene(self) -> Result<Scene, Error> {
        Ok(match self {
            BuiltinScene::Cornell => cornell_room()?,
            BuiltinScene::AreaSpheres => area_lit_spheres()?,
            BuiltinScene::Glass => glass_over_checker()?,
            BuiltinScene::SphereGrid => StandardScene::Spheres.scene()?,
        })
    }
}

/// Where a report's scene comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SceneSource {
    /// A built-in scene.
    Builtin(BuiltinScene),
    /// A glTF 2.0 file (`.gltf` or `.glb`), seen through its camera or one that frames
    /// everything, lit by its lights and emitting materials or, if nothing lights it, by the
    /// renderer's default sky.
    Gltf(PathBuf),
}

impl SceneSource {
    /// Parses a built-in scene's name, or a path ending in `.glb` or `.gltf`.
    pub fn parse(name: &str) -> Result<SceneSource, Error> {
        if let Some(builtin) = BuiltinScene::ALL.into_iter().find(|s| s.name() == name) {
            return Ok(SceneSource::Builtin(builtin));
        }
        let lower = name.to_ascii_lowercase();
        if lower.ends_with(".glb") || lower.ends_with(".gltf") {
            return Ok(SceneSource::Gltf(PathBuf::from(name)));
        }
        let names: Vec<&str> = BuiltinScene::ALL.iter().map(|s| s.name()).collect();
        Err(Error::Unsupported(format!("unknown scene `{name}`: expected {} or a .glb or .gltf file", names.join(", "))))
    }

    /// Its name in the report.
    pub fn name(&self) -> String {
        match self {
            SceneSource::Builtin(s) => s.name().to_string(),
            SceneSource::Gltf(path) => path.display().to_string(),
        }
    }

    /// A phrase for the report's title.
    pub fn description(&self) -> String {
        match self {
            SceneSource::Builtin(s) => s.description().to_string(),
            SceneSource::Gltf(path) => format!("the glTF scene {}", path.display()),
        }
    }

    /// Builds the scene, with the width-to-height ratio its camera was authored for if it
    /// says (a glTF camera's `aspectRatio`).
    pub fn scene(&self) -> Result<(Scene, Option<f32>), Error> {
        match self {
            SceneSource::Builtin(s) => Ok((s.scene()?, None)),
            SceneSource::Gltf(path) => {
                let import = |source| Error::Import { path: path.clone(), source };
                let file = raystage_gltf_import::read_file(path, &raystage_gltf_import::Limits::default()).map_err(import)?;
                let aspect = file.aspect_ratio();
                Ok((file.into_scene().map_err(import)?, aspect))
            }
        }
    }
}
