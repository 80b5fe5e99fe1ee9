//! Request extractors whose failures are [`ApiError`]s naming the field at fault: JSON bodies,
//! raw bodies, query strings, and the scene and resource ids of the path.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::Duration;

use axum::body::Bytes;
use axum::extract::{FromRequest, FromRequestParts, Path, Request};
use axum::http::StatusCode;
use axum::http::request::Parts;
use raystage_service::{AppState, Client, Error, ErrorKind, Result, SceneSlot};
use serde::de::{DeserializeOwned, DeserializeSeed};

use crate::error::ApiError;

/// Bodies larger than this are parsed on a blocking thread, off the reactor.
const PARSE_INLINE_BYTES: usize = 1 << 20;

/// A JSON body. Unlike axum's `Json`, it accepts any content type (so `curl -d` works) and
/// reports errors as [`ApiError`]s: 400 naming the field for malformed JSON, 422 for a number
/// that is not finite (`NaN`, `Infinity`), 413 past the body limit.
pub struct JsonBody<T>(pub T);

impl<T: DeserializeOwned + Send + 'static> FromRequest<AppState> for JsonBody<T> {
    type Rejection = ApiError;

    async fn from_request(req: Request, state: &AppState) -> Result<Self, ApiError> {
        let bytes = RawBody::from_request(req, state).await?.0;
        Ok(JsonBody(parse_body(bytes, |bytes| parse_json(bytes)).await?))
    }
}

/// Runs `parse` on a body: inline if it is small, else on a blocking thread, off the reactor.
pub(crate) async fn parse_body<T: Send + 'static>(bytes: Bytes, parse: impl FnOnce(&[u8]) -> Result<T> + Send + 'static) -> Result<T> {
    if bytes.len() > PARSE_INLINE_BYTES {
        tokio::task::spawn_blocking(move || parse(&bytes)).await.map_err(|e| Error::internal(e.to_string()))?
    } else {
        parse(&bytes)
    }
}

/// The body's bytes, within the body limit (413 past it) and the time limit (408 past
/// [`Limits::body_read_seconds`](crate::Limits::body_read_seconds): a client that trickles its
/// body would otherwise hold a connection and a task forever).
pub struct RawBody(pub Bytes);

impl FromRequest<AppState> for RawBody {
    type Rejection = ApiError;

    async fn from_request(req: Request, state: &AppState) -> Result<Self, ApiError> {
        let seconds = state.config().limits.body_read_seconds;
        let read = tokio::time::timeout(Duration::from_secs(seconds), Bytes::from_request(req, state)).await.map_err(|_| {
            ApiError::timeout("body_read_seconds", format!("the request body did not arrive within the server's limit of {seconds} s"))
        })?;
        let body = read.map_err(|e| {
            if e.status() == StatusCode::PAYLOAD_TOO_LARGE {
                Error::too_large(None, "the request body is larger than the server's limit").limit("max_body_bytes")
            } else {
                Error::bad_request(None, e.body_text())
            }
        })?;
        Ok(RawBody(body))
    }
}

/// Parses JSON, naming the field where parsing failed.
pub(crate) fn parse_json<T: DeserializeOwned>(bytes: &[u8]) -> Result<T> {
    parse_json_seed(bytes, std::marker::PhantomData::<T>)
}

/// [`parse_json`] through a seed: a deserializer that knows more than the type, such as a
/// limit to check while parsing.
///
/// JSON Schema counts `2.0` as the integer 2, and so does the API's description: when a body
/// fails to parse as its type and holds whole numbers written with a fraction or an exponent,
/// it is parsed again with those written as integers (serde reads `2.0` as a float only, which
/// an id or an index refuses). Bodies that parse the first time are not copied.
pub(crate) fn parse_json_seed<V, S: for<'de> DeserializeSeed<'de, Value = V> + Clone>(bytes: &[u8], seed: S) -> Result<V> {
    // Every body the API takes is an object; serde would also read a struct from an array of its
    // fields in order (`[null, null]` as `{}`), which no client means and the description forbids.
    if bytes.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'[') {
        return Err(Error::bad_request(None, "the body must be a JSON object, not an array"));
    }
    let first = parse_json_once(bytes, seed.clone());
    match first {
        Err(ref e) if e.kind == ErrorKind::BadRequest => match integers_as_integers(bytes) {
            Some(rewritten) => parse_json_once(&rewritten, seed),
            None => first,
        },
        _ => first,
    }
}

/// One parse of [`parse_json_seed`].
fn parse_json_once<V, S: for<'de> DeserializeSeed<'de, Value = V>>(bytes: &[u8], seed: S) -> Result<V> {
    let mut de = serde_json::Deserializer::from_slice(bytes);
    let mut track = serde_path_to_error::Track::new();
    let value = seed.deserialize(serde_path_to_error::Deserializer::new(&mut de, &mut track)).map_err(|inner| {
        let path = track.path().to_string();
        let field = (path != ".").then_some(path);
        if inner.is_syntax() && non_finite_literal_at(bytes, inner.line(), inner.column()) {
            Error::unprocessable(field, "numbers must be finite: JSON has no NaN or Infinity")
        } else if inner.is_eof() {
            Error::bad_request(field, format!("the JSON ends early: {inner}"))
        } else {
            Error::bad_request(field, inner.to_string())
        }
    })?;
    de.end().map_err(|e| Error::bad_request(None, e.to_string()))?;
    Ok(value)
}

/// `bytes` with every number outside strings that is a whole number written with a fraction or
/// an exponent (`2.0`, `1e3`) written as an integer instead, or `None` if there is none. Whole
/// numbers past 2⁵³, where a float stops spelling every integer, and negative zero, which an
/// integer cannot keep, stay as they are.
fn integers_as_integers(bytes: &[u8]) -> Option<Vec<u8>> {
    let mut out = Vec::new();
    let (mut copied, mut i, mut in_string, mut changed) = (0, 0, false, false);
    while i < bytes.len() {
        let b = bytes[i];
        if in_string {
            match b {
                b'\\' => i += 1,
                b'"' => in_string = false,
                _ => {}
            }
            i += 1;
            continue;
        }
        if b == b'"' {
            in_string = true;
            i += 1;
            continue;
        }
        if !(b == b'-' || b.is_ascii_digit()) {
            i += 1;
            continue;
        }
        let start = i;
        while i < bytes.len() && matches!(bytes[i], b'-' | b'+' | b'.' | b'e' | b'E' | b'0'..=b'9') {
            i += 1;
        }
        let token = &bytes[start..i];
        if !token.iter().any(|c| matches!(c, b'.' | b'e' | b'E')) {
            continue;
        }
        let Some(value) = std::str::from_utf8(token).ok().and_then(|t| t.parse::<f64>().ok()) else { continue };
        if value.fract() != 0.0 || value.abs() > (1u64 << 53) as f64 || (value == 0.0 && token[0] == b'-') {
            continue;
        }
        out.extend_from_slice(&bytes[copied..start]);
        out.extend_from_slice((value as i64).to_string().as_bytes());
        copied = i;
        changed = true;
    }
    changed.then(|| {
        out.extend_from_slice(&bytes[copied..]);
        out
    })
}

/// Whether a syntax error at `line`, `column` (1-based, as serde_json reports them) is a `NaN`
/// or `Infinity` literal, which some JSON writers emit for non-finite numbers.
fn non_finite_literal_at(bytes: &[u8], line: usize, column: usize) -> bool {
    let Some(text) = bytes.split(|&b| b == b'\n').nth(line.saturating_sub(1)) else {
        return false;
    };
    let from = column.saturating_sub(2).min(text.len());
    let window = &text[from..(from + 12).min(text.len())];
    [&b"NaN"[..], b"Infinity", b"inf"].iter().any(|lit| window.windows(lit.len()).any(|w| w.eq_ignore_ascii_case(lit)))
}

/// A query string, parsed with unknown parameters refused (400 naming the parameter).
pub struct Params<T>(pub T);

impl<S: Send + Sync, T: DeserializeOwned> FromRequestParts<S> for Params<T> {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut Parts, _: &S) -> Result<Self, ApiError> {
        let query = parts.uri.query().unwrap_or("");
        let de = serde_urlencoded::Deserializer::new(form_urlencoded::parse(query.as_bytes()));
        let params = serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            Error::bad_request((path != ".").then_some(path), format!("bad query string: {}", e.into_inner()))
        })?;
        Ok(Params(params))
    }
}

/// The scene named by the path's `{scene}` (404 if there is none), and the path's `{id}` if
/// the route has one.
pub struct Target {
    /// The scene.
    pub scene: Arc<SceneSlot>,
    /// The resource id of the path, if any.
    pub id: Option<u32>,
    /// Who asked: the request's connection, whose renders take their turns fairly with other
    /// clients' (see [`raystage_service::Client`]).
    pub(crate) client: Client,
}

impl Target {
    /// The path's resource id (routes with an `{id}` always have one).
    pub fn id(&self) -> u32 {
        self.id.expect("the route has an {id}")
    }
}

impl FromRequestParts<AppState> for Target {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut Parts, state: &AppState) -> Result<Self, ApiError> {
        let Path(params) = Path::<HashMap<String, String>>::from_request_parts(parts, state)
            .await
            .map_err(|e| Error::bad_request(None, e.body_text()))?;
        let number = |key: &str| -> Result<Option<u32>> {
            params
                .get(key)
                .map(|v| v.parse::<u32>().map_err(|_| Error::not_found(Some(key.into()), format!("`{v}` is not an id: ids are numbers"))))
                .transpose()
        };
        let scene_id = number("scene")?.ok_or_else(|| Error::internal("route without a scene"))?;
        let scene = state.scene(scene_id)?;
        let client = parts.extensions.get::<Client>().copied().unwrap_or(Client::ANY);
        Ok(Target { scene, id: number("id")?, client })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    #[allow(dead_code)]
    struct Point {
        xyz: [f32; 3],
    }

    #[test]
    fn errors_name_the_field_and_tell_nan_from_bad_syntax() {
        let err = parse_json::<Point>(br#"{"xyz": [1, "two", 3]}"#).unwrap_err();
        assert_eq!((ApiError(err.clone()).status(), err.detail.field.as_deref()), (StatusCode::BAD_REQUEST, Some("xyz[1]")));
        let err = parse_json::<Point>(br#"{"xyz": [1, NaN, 3]}"#).unwrap_err();
        assert_eq!((ApiError(err.clone()).status(), err.detail.field.as_deref()), (StatusCode::UNPROCESSABLE_ENTITY, Some("xyz[1]")));
        let err = parse_json::<Point>(b"{\n  \"xyz\": [1, 2,\n -Infinity]}").unwrap_err();
        assert_eq!(ApiError(err).status(), StatusCode::UNPROCESSABLE_ENTITY);
        let err = parse_json::<Point>(br#"{"xyz": [1, 2, 3}"#).unwrap_err();
        assert_eq!(ApiError(err).status(), StatusCode::BAD_REQUEST);
        let err = parse_json::<Point>(br#"{"xyz": [1, 2, 3]} trailing"#).unwrap_err();
        assert_eq!(ApiError(err).status(), StatusCode::BAD_REQUEST);
        assert!(parse_json::<Point>(br#"{"xyz": [1, 2, 3]}"#).is_ok());
        let err = parse_json::<Point>(br#" [[1, 2, 3]]"#).unwrap_err();
        assert_eq!(ApiError(err).status(), StatusCode::BAD_REQUEST);
    }

    #[test]
    fn whole_numbers_with_a_fraction_are_integers_as_json_schema_counts_them() {
        #[derive(Debug, PartialEq, serde::Deserialize)]
        struct Ids {
            ids: Vec<u32>,
            name: String,
            x: f32,
        }
        let ids = parse_json::<Ids>(br#"{"ids": [2.0, 1e3, 7], "name": "1.0", "x": -0.0}"#).unwrap();
        assert_eq!(ids, Ids { ids: vec![2, 1000, 7], name: "1.0".into(), x: -0.0 });
        assert!(ids.x.is_sign_negative());
        let err = parse_json::<Ids>(br#"{"ids": [2.5], "name": "", "x": 0}"#).unwrap_err();
        assert_eq!((ApiError(err.clone()).status(), err.detail.field.as_deref()), (StatusCode::BAD_REQUEST, Some("ids[0]")));
        assert_eq!(integers_as_integers(br#"{"a": "2.0", "b": [1.5, 3.0, 1e300]}"#).as_deref(), Some(&br#"{"a": "2.0", "b": [1.5, 3, 1e300]}"#[..]));
    }
}
