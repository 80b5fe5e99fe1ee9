//! The images that textures of the file use: PNG or JPEG bytes in a buffer view, a `data:` URI
//! or a file beside the glTF, decoded to linear light (their sRGB values decoded, as glTF's
//! colour textures are sRGB) or, for data textures (metallic-roughness), as stored.

use std::path::Path;

use gltf::Document;
use raystage_scene::Image;

use crate::error::ImportError;
use crate::{Limits, buffers};

/// Image `index` of `document`, decoded as `colour`s or as data, from the buffers already
/// loaded (`buffers`) or a URI resolved against `base`. Its header is read first, so that an
/// image larger than the limits allow is refused before it is decoded.
pub(crate) fn load(document: &Document, index: usize, colour: bool, buffers: &[Vec<u8>], base: Option<&Path>, limits: &Limits) -> Result<Image, ImportError> {
    let field = format!("images[{index}]");
    // Read from the JSON itself: `gltf::Image::source` unwraps a `mimeType` that a file with a
    // buffer view may lack, and the format is told from the bytes anyway.
    let json = document.as_json().images.get(index).ok_or_else(|| ImportError::invalid(&field, "no such image"))?;
    let owned;
    let bytes: &[u8] = match (&json.buffer_view, &json.uri) {
        (Some(view), _) => {
            let view = document.views().nth(view.value()).ok_or_else(|| ImportError::invalid(format!("{field}.bufferView"), "names no buffer view"))?;
            let buffer = &buffers[view.buffer().index()];
            view.offset()
                .checked_add(view.length())
                .and_then(|end| buffer.get(view.offset()..end))
                .ok_or_else(|| ImportError::invalid(format!("bufferViews[{}]", view.index()), "runs past the end of its buffer"))?
        }
        (None, Some(uri)) => {
            owned = buffers::from_uri(uri, base, &field)?;
            &owned
        }
        (None, None) => return Err(ImportError::invalid(field, "has neither a uri nor a bufferView")),
    };
    let unreadable = |e: raystage_scene::SceneError| ImportError::invalid(&field, e.to_string());
    let (width, height) = Image::dimensions(bytes).map_err(unreadable)?;
    let side = width.max(height) as usize;
    if side > limits.max_image_side {
        return Err(ImportError::TooLarge { what: "texels on a side of an image", count: side, limit: limits.max_image_side });
    }
    // Three colour channels and coverage, as f32: what the decoded image may take.
    let decoded = width as usize * height as usize * 16;
    if decoded > limits.max_image_bytes {
        return Err(ImportError::TooLarge { what: "bytes of an image once decoded", count: decoded, limit: limits.max_image_bytes });
    }
    if colour { Image::decode(bytes) } else { Image::decode_data(bytes) }.map_err(unreadable)
}
