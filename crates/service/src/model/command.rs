//! Edits: the request bodies of the resource endpoints, and the commands of a batch, which are
//! the same edits named by operation.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::model::camera::CameraPatch;
use crate::model::light::LightSpec;
use crate::model::mesh::{Kind, MeshSpec};
use crate::model::refs::Ref;
use crate::model::shader::ParamJson;
use crate::model::texture::TextureSpec;
use crate::model::transform::Transform;

/// A new object (`POST /scenes/{scene}/objects`, batch `add_object`).
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
// An example whose indices name its vertices: the relation no schema states, so that clients
// and generated tests (schemathesis's examples) have a mesh the server takes.
#[schema(example = json!({ "label": "quad", "kind": "static", "mesh": {
    "positions": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], "indices": [[0, 1, 2], [0, 2, 3]] } }))]
pub struct ObjectBody {
    /// In a batch, a name later commands can use for this object instead of its id.
    pub label: Option<String>,
    /// How its geometry will change; default `static`.
    pub kind: Option<Kind>,
    /// Its geometry.
    pub mesh: MeshSpec,
}

/// New geometry for an object (`PUT /scenes/{scene}/objects/{id}`): every instance follows.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ObjectUpdate {
    /// Its kind from now on; default `unstructured`, whose tree is refitted when the triangle
    /// count stays the same.
    pub kind: Option<Kind>,
    /// Its geometry.
    pub mesh: MeshSpec,
}

/// Batch `define_object`: [`ObjectUpdate`] of object `id`.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct DefineObject {
    /// The object.
    pub id: Ref,
    /// Its kind from now on; default `unstructured`.
    pub kind: Option<Kind>,
    /// Its geometry.
    pub mesh: MeshSpec,
}

/// New vertex positions, same count, same triangles (`PATCH /scenes/{scene}/objects/{id}`):
/// the cheapest way to animate an unstructured object.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct PositionsBody {
    /// The positions.
    pub positions: Option<Vec<[f32; 3]>>,
    /// The positions as base64 of little-endian `f32` triples.
    pub positions_base64: Option<String>,
}

/// Batch `set_positions`: [`PositionsBody`] of object `id`.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SetPositions {
    /// The object.
    pub id: Ref,
    /// The positions.
    pub positions: Option<Vec<[f32; 3]>>,
    /// The positions as base64 of little-endian `f32` triples.
    pub positions_base64: Option<String>,
}

/// A new instance (`POST /scenes/{scene}/instances`, batch `add_instance`).
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct InstanceBody {
    /// In a batch, a name later commands can use for this instance instead of its id.
    pub label: Option<String>,
    /// The object it places.
    pub object: Ref,
    /// Object to world; default the identity.
    #[serde(default)]
    pub transform: Transform,
    /// Object to world when the shutter closes, for motion blur; default: it does not move.
    pub end_transform: Option<Transform>,
}

/// A move of an instance (`PUT /scenes/{scene}/instances/{id}`).
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct InstanceUpdate {
    /// Object to world; default the identity.
    #[serde(default)]
    pub transform: Transform,
    /// Object to world when the shutter closes; default: it does not move.
    pub end_transform: Option<Transform>,
}

/// Batch `set_instance`: [`InstanceUpdate`] of instance `id`.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SetInstance {
    /// The instance.
    pub id: Ref,
    /// Object to world; default the identity.
    #[serde(default)]
    pub transform: Transform,
    /// Object to world when the shutter closes.
    pub end_transform: Option<Transform>,
}

/// A new shader (`POST /scenes/{scene}/shaders`, batch `add_shader`).
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ShaderBody {
    /// In a batch, a name later commands can use for this shader instead of its id.
    pub label: Option<String>,
    /// Its class (`GET /shader-classes` lists them).
    pub class: String,
    /// Parameter values by name; parameters the class does not export are ignored (and listed
    /// in the response).
    #[serde(default)]
    pub params: BTreeMap<String, ParamJson>,
}

/// A shader's replacement (`PUT /scenes/{scene}/shaders/{id}`): a class, parameters at their
/// defaults but for `params`. Every triangle bound to it changes with it.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ShaderUpdate {
    /// Its class.
    pub class: String,
    /// Parameter values by name.
    #[serde(default)]
    pub params: BTreeMap<String, ParamJson>,
}

/// Batch `define_shader`: [`ShaderUpdate`] of shader `id`.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct DefineShader {
    /// The shader.
    pub id: Ref,
    /// Its class.
    pub class: String,
    /// Parameter values by name.
    #[serde(default)]
    pub params: BTreeMap<String, ParamJson>,
}

/// Parameter writes (`PATCH /scenes/{scene}/shaders/{id}`).
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ParamsBody {
    /// Parameter values by name.
    pub params: BTreeMap<String, ParamJson>,
}

/// Batch `set_params`: [`ParamsBody`] of shader `id`.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SetParams {
    /// The shader.
    pub id: Ref,
    /// Parameter values by name.
    pub params: BTreeMap<String, ParamJson>,
}

/// Batch `set_light`: light `id` replaced.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SetLight {
    /// The light.
    pub id: Ref,
    /// What it becomes.
    pub light: LightSpec,
}

/// Batch `set_texture`: texture `id` replaced by a procedural texture (every shader and
/// environment light using it changes with it).
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SetTexture {
    /// The texture.
    pub id: Ref,
    /// What it becomes.
    pub texture: TextureSpec,
}

/// Batch `delete_*`: the resource to delete.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Delete {
    /// Its id or label.
    pub id: Ref,
}

/// Batch `set_time`: the scene posed at a time of its animations (`GET
/// /scenes/{scene}/animations` lists them).
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SetTime {
    /// Seconds into the animation, at least 0; past its end it holds its last keyframe.
    pub seconds: f64,
    /// Which animation: its index, its name, or `all` for all of them together; default the
    /// first.
    pub animation: Option<AnimationRef>,
}

/// An animation: its index in `GET /scenes/{scene}/animations`, its name, or `all` (every
/// animation at once; a name `all` is therefore only reachable by index).
#[derive(Clone, Debug, PartialEq, Eq, Deserialize, Serialize, ToSchema)]
#[serde(untagged, expecting = "an animation's index (a number), its name, or `all` (a string)")]
pub enum AnimationRef {
    /// An index.
    Index(u32),
    /// A name, or `all`.
    Name(String),
}

impl From<raystage_scene::Play> for AnimationRef {
    /// How the API names what a pose plays: its index, or `all`.
    fn from(play: raystage_scene::Play) -> AnimationRef {
        match play {
            raystage_scene::Play::Clip(k) => AnimationRef::Index(k as u32),
            raystage_scene::Play::All => AnimationRef::Name("all".into()),
        }
    }
}

/// One edit of a batch: an object with one key, the operation, whose value is its arguments
/// (`{"add_instance": {"object": 1, "transform": {"translate": [0, 1, 0]}}}`).
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum Command {
    /// Adds an object.
    AddObject(ObjectBody),
    /// Redefines an object's geometry.
    DefineObject(DefineObject),
    /// Moves an object's vertices.
    SetPositions(SetPositions),
    /// Deletes an object and its instances.
    DeleteObject(Delete),
    /// Places an instance.
    AddInstance(InstanceBody),
    /// Moves an instance.
    SetInstance(SetInstance),
    /// Removes an instance.
    DeleteInstance(Delete),
    /// Adds a shader.
    AddShader(ShaderBody),
    /// Replaces a shader.
    DefineShader(DefineShader),
    /// Writes shader parameters.
    SetParams(SetParams),
    /// Deletes a shader (its triangles fall back to the default shader).
    DeleteShader(Delete),
    /// Adds a light.
    AddLight(LightSpec),
    /// Replaces a light.
    SetLight(SetLight),
    /// Removes a light.
    DeleteLight(Delete),
    /// Adds a procedural texture (image textures are uploaded to `/scenes/{scene}/textures`,
    /// not sent in batches).
    AddTexture(TextureSpec),
    /// Replaces a texture with a procedural one.
    SetTexture(SetTexture),
    /// Removes a texture (shaders and lights using it render as if they had none).
    DeleteTexture(Delete),
    /// Changes the camera (fields left out stay).
    SetCamera(CameraPatch),
    /// Poses the scene at a time of its animations.
    SetTime(SetTime),
}

impl Command {
    /// The operation's name, as in JSON.
    pub fn op(&self) -> &'static str {
        match self {
            Command::AddObject(_) => "add_object",
            Command::DefineObject(_) => "define_object",
            Command::SetPositions(_) => "set_positions",
            Command::DeleteObject(_) => "delete_object",
            Command::AddInstance(_) => "add_instance",
            Command::SetInstance(_) => "set_instance",
            Command::DeleteInstance(_) => "delete_instance",
            Command::AddShader(_) => "add_shader",
            Command::DefineShader(_) => "define_shader",
            Command::SetParams(_) => "set_params",
            Command::DeleteShader(_) => "delete_shader",
            Command::AddLight(_) => "add_light",
            Command::SetLight(_) => "set_light",
            Command::DeleteLight(_) => "delete_light",
            Command::AddTexture(_) => "add_texture",
            Command::SetTexture(_) => "set_texture",
            Command::DeleteTexture(_) => "delete_texture",
            Command::SetCamera(_) => "set_camera",
            Command::SetTime(_) => "set_time",
        }
    }
}

/// A batch (`POST /scenes/{scene}/commands`): every command is checked before any is applied,
/// so a batch changes everything it says or nothing.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
// A batch that builds what it uses: a mesh, then an instance of it by its label.
#[schema(example = json!({ "commands": [
    { "add_object": { "label": "quad", "mesh": { "positions": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], "indices": [[0, 1, 2], [0, 2, 3]] } } },
    { "add_instance": { "object": "quad", "transform": { "translate": [0, 1, 0] } } }
] }))]
pub struct Commands {
    /// The edits, applied in order.
    pub commands: Vec<Command>,
}

/// What one command did.
#[derive(Clone, Debug, Default, PartialEq, Serialize, ToSchema)]
pub struct CommandResult {
    /// The id of the resource the command created, if it created one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub id: Option<u32>,
    /// Parameters the shader's class does not export: those writes were ignored.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub ignored: Vec<String>,
}

/// What a batch did, one result per command.
#[derive(Clone, Debug, PartialEq, Serialize, ToSchema)]
pub struct CommandsResult {
    /// The scene's version after the batch (every successful edit adds one).
    pub version: u64,
    /// One per command, in order.
    pub results: Vec<CommandResult>,
}
