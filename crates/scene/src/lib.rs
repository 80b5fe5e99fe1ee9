//! # raystage-scene
//!
//! The retained two-level scene of raystage (seed: Wald, *Handling Dynamic Scenes* and *The
//! OpenRT API*, docs/design/seeds.md §1.1–§1.3). Objects own geometry and their own acceleration
//! structure; instances place objects in the world with a transform; shaders, lights and the camera
//! complete the description. Everything refers to everything else by id, and [`Scene::frame`]
//! resolves the ids when a frame starts, so a shader parameter written after the geometry was
//! issued still changes that geometry (OpenRT's frame semantics).
//!
//! Objects come in three kinds ([`ObjectKind`]): static ones get the best tree once, animated
//! ones move only through their instances and are never rebuilt, unstructured ones are redefined
//! and refitted or rebuilt. Every object tree is built lazily, by the first ray that needs it, so
//! an object no ray reaches costs nothing; [`Frame::work`] counts what was built and skipped.
//!
//! Not in here: shading arithmetic and frame loops (`raystage-render`), the C ABI and HTTP
//! server that edit scenes, and SIMD (the kernel's).

mod animation;
mod builds;
mod camera;
mod distribution;
mod error;
mod frame;
mod ids;
mod instance;
mod journal;
mod light;
mod mesh;
mod object;
mod sampling;
mod scene;
mod shader;
mod spawn;
mod studio;
mod tangents;
mod texture;

pub use animation::{AnimationChoice, AnimationInfo, Binding, Channel, Clip, Deformer, Evaluated, Interpolation, Keyframes, Local, MorphTarget, Node, Play, Pose, Rig, Skin, Target, Vertices};
pub use camera::{Camera, CameraRays, Projection};
pub use distribution::{Distribution, EnvironmentTables, luminance};
pub use error::SceneError;
pub use frame::{Frame, FrameWork, PreviewAttributes, PreviewPoint, SceneHit, SurfacePoint, WorldTriangle};
pub use ids::{InstanceId, LightId, ObjectId, ShaderId, TextureId};
pub use journal::SceneEdit;
pub use light::Light;
pub use mesh::Mesh;
pub use object::{ObjectKind, REBUILD_DEGRADATION};
pub use sampling::{Sampler, Wrap, hash};
pub use scene::{Background, Scene, TREE_BYTES_PER_TRIANGLE, parse_color};
pub use shader::{ALPHA_BLEND, ALPHA_MASK, ALPHA_OPAQUE, MAX_SHADER_NAME, ParamDecl, ParamType, ParamValue, SHADER_CLASSES, Shader, ShaderClass, ShadingModel, shader_class};
pub use studio::studio_environment;
pub use texture::{Image, Level, Texture, srgb_to_linear};
