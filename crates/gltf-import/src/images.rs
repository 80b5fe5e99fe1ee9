//! The images that textures of the file use: PNG or JPEG bytes in a buffer view, a `data:` URI
//! or a file beside the glTF, decoded to linear light (their sRGB values decoded, as glTF's
//! colour textures are sRGB) or, for data textures (metallic-roughness), as stored.

use std::borrow::Cow;
use std::path::Path;
use std::time::Instant;

use gltf::Document;
use raystage_scene::Image;
use rayon::prelude::*;

use crate::error::ImportError;
use crate::{Limits, buffers};

/// An image decoded: its index, whether it holds colours, and its texels.
pub(crate) type Decoded = ((usize, bool), Image);

/// The images `used` (each an index and whether it holds colours) of `document`, decoded, from
/// the buffers already loaded (`buffers`) or URIs resolved against `base`. Every image's header
/// is read first, so that an image, or all of them together, larger than the limits allow is
/// refused before anything is decoded; then they are decoded in parallel, none started past
/// [`Limits::max_decode_seconds`] from the first (a small file naming many large images would
/// otherwise hold a core for minutes).
pub(crate) fn load_all(
    document: &Document,
    used: Vec<(usize, bool)>,
    buffers: &[Vec<u8>],
    base: Option<&Path>,
    limits: &Limits,
) -> Result<Vec<Decoded>, ImportError> {
    let encoded = used.iter().map(|&(index, _)| bytes_of(document, index, buffers, base)).collect::<Result<Vec<_>, _>>()?;
    let mut total = 0usize;
    for (&(index, _), bytes) in used.iter().zip(&encoded) {
        total = total.saturating_add(decoded_size(index, bytes, limits)?);
        if total > limits.max_images_bytes {
            return Err(ImportError::TooLarge { what: "bytes of images once decoded", count: total, limit: limits.max_images_bytes });
        }
    }
    let start = Instant::now();
    let decode = |(&(index, colour), bytes): (&(usize, bool), &Cow<'_, [u8]>)| {
        if start.elapsed() > limits.max_decode_seconds {
            return Err(ImportError::TooSlow { what: "decoding its images", limit: limits.max_decode_seconds });
        }
        let image = if colour { Image::decode(bytes) } else { Image::decode_data(bytes) };
        Ok(((index, colour), image.map_err(|e| ImportError::invalid(format!("images[{index}]"), e.to_string()))?))
    };
    used.par_iter().zip(encoded.par_iter()).map(decode).collect()
}

/// The encoded bytes of image `index`: a slice of a buffer, or a file or `data:` URI read.
fn bytes_of<'b>(document: &Document, index: usize, buffers: &'b [Vec<u8>], base: Option<&Path>) -> Result<Cow<'b, [u8]>, ImportError> {
    let field = format!("images[{index}]");
    // Read from the JSON itself: `gltf::Image::source` unwraps a `mimeType` that a file with a
    // buffer view may lack, and the format is told from the bytes anyway.
    let json = document.as_json().images.get(index).ok_or_else(|| ImportError::invalid(&field, "no such image"))?;
    match (&json.buffer_view, &json.uri) {
        (Some(view), _) => {
            let view = document.views().nth(view.value()).ok_or_else(|| ImportError::invalid(format!("{field}.bufferView"), "names no buffer view"))?;
            let buffer = &buffers[view.buffer().index()];
            let slice = view
                .offset()
                .checked_add(view.length())
                .and_then(|end| buffer.get(view.offset()..end))
                .ok_or_else(|| ImportError::invalid(format!("bufferViews[{}]", view.index()), "runs past the end of its buffer"))?;
            Ok(Cow::Borrowed(slice))
        }
        (None, Some(uri)) => Ok(Cow::Owned(buffers::from_uri(uri, base, &field)?)),
        (None, None) => Err(ImportError::invalid(field, "has neither a uri nor a bufferView")),
    }
}

/// The bytes image `index` takes decoded (three colour channels and coverage, as `f32`), from its
/// header; refused past the limits on one image.
fn decoded_size(index: usize, bytes: &[u8], limits: &Limits) -> Result<usize, ImportError> {
    let (width, height) = Image::dimensions(bytes).map_err(|e| ImportError::invalid(format!("images[{index}]"), e.to_string()))?;
    let side = width.max(height) as usize;
    if side > limits.max_image_side {
        return Err(ImportError::TooLarge { what: "texels on a side of an image", count: side, limit: limits.max_image_side });
    }
    let decoded = width as usize * height as usize * 16;
    if decoded > limits.max_image_bytes {
        return Err(ImportError::TooLarge { what: "bytes of an image once decoded", count: decoded, limit: limits.max_image_bytes });
    }
    Ok(decoded)
}
