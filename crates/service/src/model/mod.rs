//! The JSON types of the API: what requests send and responses return, with their OpenAPI
//! schemas, and their conversion to and from the scene's own types.

mod camera;
mod command;
mod light;
mod mesh;
mod refs;
mod shader;
mod texture;
mod transform;

pub use camera::{CameraJson, CameraPatch};
pub use command::{
    AnimationRef, Command, CommandResult, Commands, CommandsResult, Delete, DefineObject, DefineShader, InstanceBody, InstanceUpdate, ObjectBody,
    ObjectUpdate, ParamsBody, PositionsBody, SetInstance, SetLight, SetParams, SetPositions, SetTexture, SetTime, ShaderBody, ShaderUpdate,
};
pub use light::{LIGHT_CLASSES, LightInfo, LightSpec, Rgb};
pub use mesh::{Kind, MeshSpec};
pub use refs::Ref;
pub use shader::{ParamJson, ParamOut, ShaderInfo, ShaderSummary, TextureParam};
pub use texture::{TextureDescription, TextureInfo, TextureKind, TextureSpec, decode_image};
pub use transform::{Rotation, Scale, Transform};

/// A file or image in the body, as it is.
#[derive(utoipa::ToSchema)]
#[schema(value_type = String, format = Binary)]
pub struct Binary(#[allow(dead_code, reason = "a schema only")] Vec<u8>);

pub(crate) use mesh::{Binding, decode_positions};
pub(crate) use shader::{ParamWrite, param_value};
