//! Meshes in JSON: attribute arrays as nested JSON arrays, or as base64 of little-endian
//! binary (`f32` triples for positions, `u32` triples for indices), which is about four times
//! smaller and much faster to parse.

use base64::Engine;
use glam::{Vec2, Vec3};
use raystage_scene::{Mesh, ObjectKind};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::config::Limits;
use crate::error::{Error, Result};
use crate::model::refs::Ref;

/// How an object's geometry changes (see the scene's object kinds).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, serde::Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// Never changes: the best tree, built once.
    #[default]
    Static,
    /// Moves only through its instances.
    Animated,
    /// Redefined through the same id: its tree is refitted or rebuilt.
    Unstructured,
}

impl Kind {
    /// The scene's kind.
    pub fn to_scene(self) -> ObjectKind {
        match self {
            Kind::Static => ObjectKind::Static,
            Kind::Animated => ObjectKind::Animated,
            Kind::Unstructured => ObjectKind::Unstructured,
        }
    }

    /// From the scene's kind.
    pub fn from_scene(kind: ObjectKind) -> Kind {
        match kind {
            ObjectKind::Static => Kind::Static,
            ObjectKind::Animated => Kind::Animated,
            ObjectKind::Unstructured => Kind::Unstructured,
        }
    }
}

/// A triangle mesh. Each attribute comes either as a JSON array or as base64 (the `_base64`
/// field), not both. Without indices, every three positions make a triangle.
#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// Vertex positions.
    pub positions: Option<Vec<[f32; 3]>>,
    /// Vertex positions as base64 of little-endian `f32` x, y, z.
    pub positions_base64: Option<String>,
    /// Three vertex indices per triangle, counter-clockwise seen from the front.
    pub indices: Option<Vec<[u32; 3]>>,
    /// Indices as base64 of little-endian `u32`, three per triangle.
    pub indices_base64: Option<String>,
    /// Per-vertex shading normals.
    pub normals: Option<Vec<[f32; 3]>>,
    /// Normals as base64 of little-endian `f32` triples.
    pub normals_base64: Option<String>,
    /// Per-vertex linear RGB colours (for the VertexColor shader class).
    pub colors: Option<Vec<[f32; 3]>>,
    /// Colours as base64 of little-endian `f32` triples.
    pub colors_base64: Option<String>,
    /// Per-vertex texture coordinates.
    pub uvs: Option<Vec<[f32; 2]>>,
    /// Texture coordinates as base64 of little-endian `f32` pairs.
    pub uvs_base64: Option<String>,
    /// The shader of every triangle (without one, the scene's default: Diffuse grey).
    pub shader: Option<Ref>,
    /// One shader per triangle (instead of `shader`).
    pub shaders: Option<Vec<Ref>>,
}

/// Which shaders a mesh's triangles use.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Binding<T> {
    /// The scene's default shader.
    Default,
    /// One shader for all.
    All(T),
    /// One per triangle.
    Each(Vec<T>),
}

impl MeshSpec {
    /// The mesh (without shaders) and which shaders it binds, decoded and checked against the
    /// limits (413 past them, 400 for bad base64, 422 for bad numbers or indices).
    pub(crate) fn decode(self, limits: &Limits) -> Result<(Mesh, Binding<Ref>)> {
        let positions = vectors(self.positions, self.positions_base64, "positions", limits.max_vertices)?
            .ok_or_else(|| Error::bad_request(Some("positions".into()), "a mesh needs `positions` or `positions_base64`"))?;
        let indices = match pick(self.indices, self.indices_base64, "indices")? {
            Some(Either::Json(indices)) => {
                check_count(indices.len(), limits.max_triangles, "indices", "triangles")?;
                indices
            }
            Some(Either::Base64(text)) => {
                check_count(text.len() / 16, limits.max_triangles, "indices_base64", "triangles")?;
                let words: Vec<u32> = decode_words(&text, "indices_base64", 12)?.into_iter().map(u32::from_le_bytes).collect();
                words.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
            }
            None => {
                check_count(positions.len() / 3, limits.max_triangles, "positions", "triangles")?;
                (0..positions.len() as u32 / 3).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect()
            }
        };
        let normals = vectors(self.normals, self.normals_base64, "normals", limits.max_vertices)?.unwrap_or_default();
        let colors = vectors(self.colors, self.colors_base64, "colors", limits.max_vertices)?.unwrap_or_default();
        let uvs: Vec<Vec2> = match pick(self.uvs, self.uvs_base64, "uvs")? {
            Some(Either::Json(uvs)) => uvs.into_iter().map(Vec2::from).collect(),
            Some(Either::Base64(text)) => floats(&text, "uvs_base64", 8)?.chunks_exact(2).map(|c| Vec2::new(c[0], c[1])).collect(),
            None => Vec::new(),
        };
        check_count(uvs.len(), limits.max_vertices, "uvs", "vertices")?;
        let binding = match (self.shader, self.shaders) {
            (Some(_), Some(_)) => return Err(Error::unprocessable(Some("shaders".into()), "give `shader` or `shaders`, not both")),
            (Some(one), None) => Binding::All(one),
            (None, Some(each)) => Binding::Each(each),
            (None, None) => Binding::Default,
        };
        let mesh = Mesh { positions, indices, normals, colors, uvs, ..Mesh::default() };
        Ok((mesh, binding))
    }
}

/// Positions for a PATCH of an object's vertices: JSON or base64, one of them.
pub(crate) fn decode_positions(json: Option<Vec<[f32; 3]>>, base64: Option<String>, limits: &Limits) -> Result<Vec<Vec3>> {
    vectors(json, base64, "positions", limits.max_vertices)?
        .ok_or_else(|| Error::unprocessable(Some("positions".into()), "give `positions` or `positions_base64`"))
}

enum Either<T> {
    Json(T),
    Base64(String),
}

/// The one of an attribute's two spellings that is present. Both is 422, as is neither for the
/// positions (above): each field is well formed, their combination is refused, as other
/// relations between a mesh's fields are (indices in range); the description says it in words,
/// since a schema of every pair's exclusion is more than schema-driven clients can generate from.
fn pick<T>(json: Option<T>, base64: Option<String>, name: &str) -> Result<Option<Either<T>>> {
    match (json, base64) {
        (Some(_), Some(_)) => Err(Error::unprocessable(Some(format!("{name}_base64")), format!("give `{name}` or `{name}_base64`, not both"))),
        (Some(j), None) => Ok(Some(Either::Json(j))),
        (None, Some(b)) => Ok(Some(Either::Base64(b))),
        (None, None) => Ok(None),
    }
}

/// A per-vertex attribute of three numbers, in either spelling.
fn vectors(json: Option<Vec<[f32; 3]>>, base64: Option<String>, name: &str, limit: usize) -> Result<Option<Vec<Vec3>>> {
    let out: Option<Vec<Vec3>> = match pick(json, base64, name)? {
        Some(Either::Json(v)) => Some(v.into_iter().map(Vec3::from).collect()),
        Some(Either::Base64(text)) => {
            check_count(text.len() / 16, limit, &format!("{name}_base64"), "vertices")?;
            Some(floats(&text, &format!("{name}_base64"), 12)?.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect())
        }
        None => None,
    };
    if let Some(v) = &out {
        check_count(v.len(), limit, name, "vertices")?;
    }
    Ok(out)
}

/// 413 when `count` is past `limit`.
fn check_count(count: usize, limit: usize, field: &str, what: &str) -> Result<()> {
    if count > limit {
        return Err(Error::too_large(Some(field.into()), format!("{count} {what}: the limit is {limit}")));
    }
    Ok(())
}

/// Base64 of little-endian `f32`s, `element` bytes per element.
fn floats(text: &str, field: &str, element: usize) -> Result<Vec<f32>> {
    Ok(decode_words(text, field, element)?.into_iter().map(f32::from_le_bytes).collect())
}

/// Standard base64 as the description's pattern states it: padded, with whatever bits the last
/// character carries past the data (some encoders leave them set; they hold nothing) ignored.
const BASE64: base64::engine::GeneralPurpose =
    base64::engine::GeneralPurpose::new(&base64::alphabet::STANDARD, base64::engine::GeneralPurposeConfig::new().with_decode_allow_trailing_bits(true));

/// Base64 of 4-byte little-endian words, whose length is a multiple of `element` bytes.
fn decode_words(text: &str, field: &str, element: usize) -> Result<Vec<[u8; 4]>> {
    let bytes = BASE64
        .decode(text)
        .map_err(|e| Error::bad_request(Some(field.into()), format!("not base64: {e}")))?;
    if bytes.len() % element != 0 {
        return Err(Error::unprocessable(Some(field.into()), format!("{} bytes is not a whole number of {element}-byte elements", bytes.len())));
    }
    Ok(bytes.chunks_exact(4).map(|w| [w[0], w[1], w[2], w[3]]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::ErrorKind;

    fn b64(bytes: &[u8]) -> String {
        base64::engine::general_purpose::STANDARD.encode(bytes)
    }

    #[test]
    fn base64_whose_last_character_carries_stray_bits_decodes_as_its_pattern_allows() {
        // `a=` ends 8 bytes with 2 bits set past the data (`Y=` would be canonical): the
        // description's pattern allows it, so the decoder does.
        assert_eq!(floats("0kLUj79v7fa=", "positions_base64", 12).unwrap_err().kind, ErrorKind::Unprocessable);
        assert_eq!(decode_words("AAAAAAAAAAB=", "f", 4).unwrap(), decode_words("AAAAAAAAAAA=", "f", 4).unwrap());
        assert_eq!(decode_words("AAAA!", "f", 4).unwrap_err().kind, ErrorKind::BadRequest);
    }

    #[test]
    fn base64_and_json_spellings_decode_alike() {
        let positions = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let json = MeshSpec { positions: Some(positions.to_vec()), indices: Some(vec![[0, 1, 2]]), ..MeshSpec::default() };
        let bytes: Vec<u8> = positions.iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
        let index_bytes: Vec<u8> = [0u32, 1, 2].iter().flat_map(|i| i.to_le_bytes()).collect();
        let binary = MeshSpec { positions_base64: Some(b64(&bytes)), indices_base64: Some(b64(&index_bytes)), ..MeshSpec::default() };
        let (a, _) = json.decode(&Limits::default()).unwrap();
        let (b, _) = binary.decode(&Limits::default()).unwrap();
        assert_eq!(a, b);
        // Without indices, every three positions are a triangle.
        let soup = MeshSpec { positions: Some(positions.to_vec()), ..MeshSpec::default() };
        assert_eq!(soup.decode(&Limits::default()).unwrap().0.indices, vec![[0, 1, 2]]);
    }

    #[test]
    fn bad_spellings_and_sizes_are_refused() {
        let limits = Limits { max_vertices: 2, ..Limits::default() };
        let big = MeshSpec { positions: Some(vec![[0.0; 3]; 3]), ..MeshSpec::default() };
        assert_eq!(big.decode(&limits).unwrap_err().kind, ErrorKind::TooLarge);
        let both = MeshSpec { positions: Some(vec![]), positions_base64: Some(String::new()), ..MeshSpec::default() };
        assert_eq!(both.decode(&Limits::default()).unwrap_err().detail.field.as_deref(), Some("positions_base64"));
        let ragged = MeshSpec { positions_base64: Some(b64(&[0; 13])), ..MeshSpec::default() };
        assert_eq!(ragged.decode(&Limits::default()).unwrap_err().kind, ErrorKind::Unprocessable);
        let garbage = MeshSpec { positions_base64: Some("%%%".into()), ..MeshSpec::default() };
        assert_eq!(garbage.decode(&Limits::default()).unwrap_err().kind, ErrorKind::BadRequest);
    }
}
