//! `/shader-classes`: the built-in surface and light classes with their parameters.

use axum::Json;
use raystage_scene::{ParamValue, SHADER_CLASSES};
use raystage_service::model::{LIGHT_CLASSES, ParamOut};
use serde::Serialize;
use utoipa::ToSchema;


/// A shader class.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct ClassInfo {
    /// Its name, as `class` in requests.
    pub name: String,
    /// `surface` (for `/shaders`) or `light` (for `/lights`).
    pub kind: &'static str,
    /// What it does (surfaces only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub doc: Option<String>,
    /// Its parameters.
    pub params: Vec<ParamInfo>,
}

/// A parameter of a class.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct ParamInfo {
    /// Its name.
    pub name: String,
    /// Its default (surfaces only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub default: Option<ParamOut>,
    /// The allowed range of a number or of each colour channel (surfaces only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub range: Option<[f32; 2]>,
    /// What it does (surfaces only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub doc: Option<String>,
}

/// Every built-in class: surface classes for shaders, light classes for lights.
#[utoipa::path(get, path = "/shader-classes", tag = "shaders", responses((status = 200, description = "Success", body = [ClassInfo])))]
pub(crate) async fn list() -> Json<Vec<ClassInfo>> {
    let surfaces = SHADER_CLASSES.iter().map(|c| ClassInfo {
        name: c.name.into(),
        kind: "surface",
        doc: Some(c.doc.into()),
        params: c
            .params
            .iter()
            .map(|p| ParamInfo {
                name: p.name.into(),
                default: Some(match p.default {
                    ParamValue::Float(f) => ParamOut::Number(f),
                    ParamValue::Color(c) => ParamOut::Color(c.to_array()),
                    ParamValue::Texture(t) => ParamOut::Texture { texture: t.map(|t| t.0) },
                }),
                // JSON has no infinity: an open range ends at the largest number.
                range: Some(p.range.map(|r| r.min(f32::MAX))),
                doc: Some(p.doc.into()),
            })
            .collect(),
    });
    let lights = LIGHT_CLASSES.iter().map(|(name, params)| ClassInfo {
        name: name.to_string(),
        kind: "light",
        doc: None,
        params: params.iter().map(|p| ParamInfo { name: p.to_string(), default: None, range: None, doc: None }).collect(),
    });
    Json(surfaces.chain(lights).collect())
}
