//! Shaders and their parameters in JSON.

use std::collections::BTreeMap;

use glam::Vec3;
use raystage_scene::{ParamType, ParamValue, Shader, ShaderClass};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

/// A parameter value as sent: a number, a colour (three numbers) or null (no texture). A
/// number written to a colour parameter sets all three channels.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, ToSchema)]
#[serde(untagged, expecting = "a number, three numbers (a colour) or null")]
pub enum ParamJson {
    /// A number.
    Number(f32),
    /// A linear RGB colour.
    Color([f32; 3]),
    /// No texture.
    Null,
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
        ShaderInfo { id, class: shader.class().name.to_string(), params }
    }
}

/// The scene's value for parameter `name` of `class` written as `value`: `None` if the class has
/// no such parameter (the write is ignored, as in the C ABI). A value of the wrong type is
/// passed on as it is, for the scene to refuse with a message naming the expected type.
pub(crate) fn param_value(class: &ShaderClass, name: &str, value: ParamJson) -> Option<ParamValue> {
    let declared = class.params.iter().find(|p| p.name == name)?.default.ty();
    Some(match (declared, value) {
        (ParamType::Color, ParamJson::Number(x)) => ParamValue::Color(Vec3::splat(x)),
        (_, ParamJson::Number(x)) => ParamValue::Float(x),
        (_, ParamJson::Color(c)) => ParamValue::Color(Vec3::from(c)),
        (ParamType::Texture, ParamJson::Null) => ParamValue::Texture(None),
        // Null for a number or colour: a type error the scene reports.
        (_, ParamJson::Null) => ParamValue::Texture(None),
    })
}
