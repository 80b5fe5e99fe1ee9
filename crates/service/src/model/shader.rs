//! Shaders and their parameters in JSON.

use std::collections::BTreeMap;

use glam::Vec3;
use raystage_scene::{ParamType, ParamValue, Shader, ShaderClass};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::model::refs::Ref;

/// A parameter value as sent: a number, a colour (three numbers), a texture
/// (`{"texture": id}`, in a batch also the label of a texture an earlier command created) or
/// null (no texture). A number written to a colour parameter sets all three channels.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
#[serde(untagged, expecting = "a number, three numbers (a colour), {\"texture\": id} or null")]
pub enum ParamJson {
    /// A number.
    Number(f32),
    /// A linear RGB colour.
    Color([f32; 3]),
    /// A texture, or none.
    Texture(TextureParam),
    /// No texture.
    Null,
}

/// The value of a texture parameter: the texture, or null for none.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct TextureParam {
    /// The texture's id (or, in a batch, its label), or null for none.
    pub texture: Option<Ref>,
}

/// A parameter value as returned.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, ToSchema)]
#[serde(untagged)]
pub enum ParamOut {
    /// A number.
    Number(f32),
    /// A linear RGB colour.
    Color([f32; 3]),
    /// A texture parameter: its texture's id, or null.
    Texture {
        /// The texture, if any.
        texture: Option<u32>,
    },
}

/// A shader: its class and every parameter's value.
#[derive(Clone, Debug, PartialEq, Serialize, ToSchema)]
pub struct ShaderInfo {
    /// The shader's id.
    pub id: u32,
    /// Its class.
    pub class: String,
    /// Its name (a glTF material's), if it has one.
    pub name: Option<String>,
    /// Every parameter of the class with its value.
    pub params: BTreeMap<String, ParamOut>,
}

impl ShaderInfo {
    /// A scene shader as JSON.
    pub fn of(id: u32, shader: &Shader) -> ShaderInfo {
        let params = shader
            .class()
            .params
            .iter()
            .filter_map(|p| {
                let value = match shader.get(p.name)? {
                    ParamValue::Float(f) => ParamOut::Number(f),
                    ParamValue::Color(c) => ParamOut::Color(c.to_array()),
                    ParamValue::Texture(t) => ParamOut::Texture { texture: t.map(|t| t.0) },
                };
                Some((p.name.to_string(), value))
            })
            .collect();
        ShaderInfo { id, class: shader.class().name.to_string(), name: shader.name().map(str::to_string), params }
    }
}

/// A shader as the list of a scene's shaders shows it: id, class and name.
#[derive(Clone, Debug, PartialEq, Serialize, ToSchema)]
pub struct ShaderSummary {
    /// The shader's id.
    pub id: u32,
    /// Its class.
    pub class: String,
    /// Its name (a glTF material's), if it has one.
    pub name: Option<String>,
}

impl ShaderSummary {
    /// A scene shader, in short.
    pub fn of(id: u32, shader: &Shader) -> ShaderSummary {
        ShaderSummary { id, class: shader.class().name.to_string(), name: shader.name().map(str::to_string) }
    }
}

/// A parameter write, converted: a value for the scene, or a texture reference for the caller
/// to resolve (it may be the label of a texture the batch has not created yet).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum ParamWrite {
    /// The value to write.
    Value(ParamValue),
    /// The texture to write, by id or label.
    Texture(Ref),
}

/// The write of parameter `name` of `class` as `value`: `None` if the class has no such
/// parameter (the write is ignored, as in the C ABI). A value of the wrong type is passed on as
/// it is, for the scene to refuse with a message naming the expected type.
pub(crate) fn param_value(class: &ShaderClass, name: &str, value: ParamJson) -> Option<ParamWrite> {
    let declared = class.params.iter().find(|p| p.name == name)?.default.ty();
    Some(match (declared, value) {
        (ParamType::Texture, ParamJson::Texture(TextureParam { texture: Some(texture) })) => ParamWrite::Texture(texture),
        (ParamType::Color, ParamJson::Number(x)) => ParamWrite::Value(ParamValue::Color(Vec3::splat(x))),
        (_, ParamJson::Number(x)) => ParamWrite::Value(ParamValue::Float(x)),
        (_, ParamJson::Color(c)) => ParamWrite::Value(ParamValue::Color(Vec3::from(c))),
        // No texture; or, for a number or colour, a type error the scene reports.
        (_, ParamJson::Null | ParamJson::Texture(_)) => ParamWrite::Value(ParamValue::Texture(None)),
    })
}
