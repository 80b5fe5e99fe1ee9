//! The bytes of each buffer (and of images given by URI): the GLB binary chunk, a `data:` URI,
//! or a file beside the glTF.

use std::path::Path;

use base64::Engine;
use gltf::Document;
use gltf::buffer::Source;

use crate::Limits;
use crate::compressed;
use crate::error::ImportError;

/// The bytes of every buffer of `document`, in order, each at least as long as it declares, with
/// the views that meshoptimizer compressed decoded into their fallback buffers (see
/// [`compressed`]). Fallback buffers, which the file declares but does not hold, count against
/// `limits.max_decompressed_bytes` before any is made.
pub(crate) fn load(document: &Document, blob: Option<&[u8]>, base: Option<&Path>, limits: &Limits) -> Result<Vec<Vec<u8>>, ImportError> {
    let fallback: Vec<bool> = document.buffers().map(|b| compressed::is_fallback(&b)).collect();
    let decompressed = document.buffers().filter(|b| fallback[b.index()]).fold(0usize, |sum, b| sum.saturating_add(b.length()));
    if decompressed > limits.max_decompressed_bytes {
        return Err(ImportError::TooLarge { what: "bytes of decompressed buffers", count: decompressed, limit: limits.max_decompressed_bytes });
    }
    let mut buffers = document
        .buffers()
        .map(|buffer| {
            let field = format!("buffers[{}]", buffer.index());
            let data = match buffer.source() {
                _ if fallback[buffer.index()] => vec![0; buffer.length()],
                Source::Bin => blob.ok_or_else(|| ImportError::invalid(&field, "refers to the GLB binary chunk, but there is none"))?.to_vec(),
                Source::Uri(uri) => from_uri(uri, base, &field)?,
            };
            if data.len() < buffer.length() {
                return Err(ImportError::invalid(field, format!("declares {} bytes but holds {}", buffer.length(), data.len())));
            }
            Ok(data)
        })
        .collect::<Result<Vec<_>, _>>()?;
    compressed::decode_views(document, &mut buffers, &fallback)?;
    Ok(buffers)
}

/// The bytes a buffer or image URI names; `field` is the part of the file that names it.
pub(crate) fn from_uri(uri: &str, base: Option<&Path>, field: &str) -> Result<Vec<u8>, ImportError> {
    let field = format!("{field}.uri");
    if let Some(rest) = uri.strip_prefix("data:") {
        let (header, payload) = rest.split_once(',').ok_or_else(|| ImportError::invalid(&field, "a data URI without a comma"))?;
        if !header.ends_with(";base64") {
            return Err(ImportError::invalid(field, "only base64 data URIs are supported"));
        }
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|e| ImportError::invalid(field, format!("bad base64: {e}")));
    }
    let Some(base) = base else {
        return Err(ImportError::invalid(field, "external files cannot be uploaded: send a .glb, or embed buffers and images as data: URIs"));
    };
    if uri.contains("://") {
        return Err(ImportError::invalid(field, format!("`{uri}` is not a relative path")));
    }
    let path = base.join(uri.replace("%20", " "));
    std::fs::read(&path).map_err(|source| ImportError::Io { path, source })
}
