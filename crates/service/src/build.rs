//! How a new scene is built: the description a request gives (empty, a demo, a glTF file), which
//! a cluster's workers build their replicas from too.

use raystage_demo::animated::Demo;
use raystage_scene::Scene;
use serde::{Deserialize, Serialize};

use crate::config::Limits;
use crate::edit::Blob;
use crate::error::{Error, Result};
use crate::gltf::{add_environment, import_limits, parse_environment};

/// How a new scene is built: what `POST /scenes` was given.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SceneBuild {
    /// What it starts as.
    pub start: SceneStart,
    /// The environment to light it with (`studio`, `none`, `R,G,B` or one number); `None`
    /// for the default (the studio for a glTF file without lights).
    pub environment: Option<String>,
}

/// What a new scene starts as.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub enum SceneStart {
    /// Nothing.
    Empty,
    /// A built-in demo at a frame of its animation.
    Demo { name: String, frame: u32 },
    /// A glTF 2.0 file.
    Gltf(Blob),
}

impl SceneBuild {
    /// Builds the scene (on a blocking thread: demos and files take time), and its origin's
    /// name (`empty`, `demo:NAME`, `gltf`); unprocessable naming the field that is wrong.
    pub fn build(&self, limits: &Limits) -> Result<(Scene, String)> {
        let environment = self.environment.as_deref().map(parse_environment).transpose()?;
        let (mut scene, origin, unlit) = match &self.start {
            SceneStart::Empty => (Scene::new(), "empty".to_string(), false),
            SceneStart::Gltf(file) => {
                let import = raystage_gltf_import::read(&file.0, None, &import_limits(limits))?;
                let unlit = import.lights().is_empty();
                (import.into_scene()?, "gltf".to_string(), unlit)
            }
            SceneStart::Demo { name, frame } => {
                let demo =
                    Demo::from_name(name).ok_or_else(|| Error::unprocessable(Some("demo".into()), format!("unknown demo scene `{name}`: expected {}", Demo::NAMES)))?;
                if let Demo::Museum(triangles) = demo
                    && triangles > limits.max_demo_triangles
                {
                    let max = limits.max_demo_triangles;
                    return Err(Error::unprocessable(Some("demo".into()), format!("`{name}` has {triangles} triangles: the limit is {max}")).limit("max_demo_triangles"));
                }
                let scene = demo.scene(*frame).map_err(|e| Error::internal(format!("cannot build the demo scene: {e}")))?;
                (scene, format!("demo:{}", demo.name()), false)
            }
        };
        add_environment(&mut scene, environment, unlit)?;
        Ok((scene, origin))
    }
}
