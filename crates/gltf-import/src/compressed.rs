//! Buffer views compressed by meshoptimizer (`EXT_meshopt_compression`, and
//! `KHR_meshopt_compression`, its Khronos successor, which adds a vertex codec version and a
//! colour filter that the same decoder reads): what `gltfpack -c` writes. A compressed view
//! names the bytes it was compressed into and how (`mode`, `filter`, `count`, `byteStride`); its
//! own buffer is then usually a *fallback* buffer that holds nothing, into which the views
//! decode. meshoptimizer's own decoder reads the bitstream: it is safe on any input (a broken
//! stream gives an error code or garbage, never a read out of bounds), but asserts on
//! arguments outside its contract, so every argument is checked here first.

use gltf::Document;
use gltf::json::Value;

use crate::error::ImportError;

/// The extensions' names: the same JSON under either.
const NAMES: [&str; 2] = ["EXT_meshopt_compression", "KHR_meshopt_compression"];

/// The extension's name and object on a buffer or view, if it has one.
fn extension(extensions: Option<&serde_json::Map<String, Value>>) -> Option<(&'static str, &Value)> {
    let extensions = extensions?;
    NAMES.iter().find_map(|name| Some((*name, extensions.get(*name)?)))
}

/// Whether `buffer` is a fallback buffer: one that holds no bytes of its own, only the space
/// the compressed views decode into.
pub(crate) fn is_fallback(buffer: &gltf::Buffer<'_>) -> bool {
    extension(buffer.extensions()).and_then(|(_, e)| e.get("fallback")).and_then(Value::as_bool) == Some(true)
}

/// How a view's elements were encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    /// Vertex attributes (or any array of fixed-size elements, such as keyframes).
    Attributes,
    /// Triangle indices.
    Triangles,
    /// Any other indices.
    Indices,
}

/// What was done to attribute values before they were compressed, which decoding undoes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Filter {
    None,
    /// Unit vectors as two octahedral coordinates.
    Octahedral,
    /// Unit quaternions as three components and the index of the fourth.
    Quaternion,
    /// Floats as a shared exponent and a 24-bit mantissa.
    Exponential,
    /// Colours in YCoCg (`KHR_meshopt_compression` only).
    Color,
}

/// A compressed view: where its compressed bytes are, and what they decode to.
#[derive(Debug)]
struct Compressed {
    buffer: usize,
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    mode: Mode,
    filter: Filter,
}

impl Compressed {
    /// The view's compression, if it is compressed; `view_field` names the view.
    fn of(view: &gltf::buffer::View<'_>, view_field: &str) -> Result<Option<Compressed>, ImportError> {
        let Some((name, e)) = extension(view.extensions()) else { return Ok(None) };
        let field = &format!("{view_field}.extensions.{name}");
        let number = |name: &str, default: Option<u64>| {
            e.get(name)
                .map_or(default, Value::as_u64)
                .and_then(|n| usize::try_from(n).ok())
                .ok_or_else(|| ImportError::invalid(format!("{field}.{name}"), "must be a non-negative integer"))
        };
        let mode = match e.get("mode").and_then(Value::as_str) {
            Some("ATTRIBUTES") => Mode::Attributes,
            Some("TRIANGLES") => Mode::Triangles,
            Some("INDICES") => Mode::Indices,
            other => return Err(ImportError::invalid(format!("{field}.mode"), format!("{other:?} is not ATTRIBUTES, TRIANGLES or INDICES"))),
        };
        let filter = match e.get("filter").map(Value::as_str) {
            None | Some(Some("NONE")) => Filter::None,
            Some(Some("OCTAHEDRAL")) => Filter::Octahedral,
            Some(Some("QUATERNION")) => Filter::Quaternion,
            Some(Some("EXPONENTIAL")) => Filter::Exponential,
            Some(Some("COLOR")) => Filter::Color,
            Some(other) => return Err(ImportError::invalid(format!("{field}.filter"), format!("{other:?} is not a filter meshoptimizer defines"))),
        };
        let compressed = Compressed {
            buffer: number("buffer", None)?,
            offset: number("byteOffset", Some(0))?,
            length: number("byteLength", None)?,
            stride: number("byteStride", None)?,
            count: number("count", None)?,
            mode,
            filter,
        };
        compressed.check(field)?;
        Ok(Some(compressed))
    }

    /// Checks the arguments meshoptimizer's decoder asserts on (the extension requires the same).
    fn check(&self, field: &str) -> Result<(), ImportError> {
        let stride_ok = match self.mode {
            Mode::Attributes => self.stride > 0 && self.stride.is_multiple_of(4) && self.stride <= 256,
            Mode::Triangles | Mode::Indices => self.stride == 2 || self.stride == 4,
        };
        if !stride_ok {
            return Err(ImportError::invalid(format!("{field}.byteStride"), format!("{} does not suit mode {:?}", self.stride, self.mode)));
        }
        if self.mode == Mode::Triangles && !self.count.is_multiple_of(3) {
            return Err(ImportError::invalid(format!("{field}.count"), format!("{} triangle indices are not a multiple of 3", self.count)));
        }
        let filter_ok = match self.filter {
            Filter::None => true,
            _ if self.mode != Mode::Attributes => false,
            Filter::Octahedral | Filter::Color => self.stride == 4 || self.stride == 8,
            Filter::Quaternion => self.stride == 8,
            Filter::Exponential => true,
        };
        if !filter_ok {
            return Err(ImportError::invalid(format!("{field}.filter"), format!("{:?} does not suit mode {:?} and stride {}", self.filter, self.mode, self.stride)));
        }
        Ok(())
    }

    /// The decoded bytes: `count` elements of `stride` bytes.
    fn decode(&self, buffers: &[Vec<u8>], field: &str) -> Result<Vec<u8>, ImportError> {
        let source = self
            .offset
            .checked_add(self.length)
            .and_then(|end| buffers.get(self.buffer)?.get(self.offset..end))
            .ok_or_else(|| ImportError::invalid(field, format!("{} bytes at offset {} of buffers[{}] are not there", self.length, self.offset, self.buffer)))?;
        let size = self.count.checked_mul(self.stride).ok_or_else(|| ImportError::invalid(format!("{field}.count"), "too large"))?;
        let mut out = vec![0u8; size];
        // SAFETY: `out` holds `count` elements of `stride` bytes, which is what each decoder
        // writes; `source` is a slice of `length` bytes, all the decoders read; the strides and
        // counts are those `check` allowed, the decoders' contract.
        let code = unsafe {
            match self.mode {
                Mode::Attributes => meshopt::ffi::meshopt_decodeVertexBuffer(out.as_mut_ptr().cast(), self.count, self.stride, source.as_ptr(), source.len()),
                Mode::Triangles => meshopt::ffi::meshopt_decodeIndexBuffer(out.as_mut_ptr().cast(), self.count, self.stride, source.as_ptr(), source.len()),
                Mode::Indices => meshopt::ffi::meshopt_decodeIndexSequence(out.as_mut_ptr().cast(), self.count, self.stride, source.as_ptr(), source.len()),
            }
        };
        if code != 0 {
            return Err(ImportError::invalid(field, format!("the compressed bytes do not decode (meshoptimizer's error {code})")));
        }
        // SAFETY: the filters rewrite `count` elements of `stride` bytes in place, all within
        // `out`; `check` allowed the stride for the filter.
        unsafe {
            let (data, count, stride) = (out.as_mut_ptr().cast(), self.count, self.stride);
            match self.filter {
                Filter::None => {}
                Filter::Octahedral => meshopt::ffi::meshopt_decodeFilterOct(data, count, stride),
                Filter::Quaternion => meshopt::ffi::meshopt_decodeFilterQuat(data, count, stride),
                Filter::Exponential => meshopt::ffi::meshopt_decodeFilterExp(data, count, stride),
                Filter::Color => meshopt::ffi::meshopt_decodeFilterColor(data, count, stride),
            }
        }
        Ok(out)
    }
}

/// Decodes every compressed view of `document` whose buffer is a fallback buffer into it (a view
/// whose buffer holds bytes of its own has them uncompressed there already).
pub(crate) fn decode_views(document: &Document, buffers: &mut [Vec<u8>], fallback: &[bool]) -> Result<(), ImportError> {
    for view in document.views() {
        let field = format!("bufferViews[{}]", view.index());
        let Some(compressed) = Compressed::of(&view, &field)? else { continue };
        if !fallback.get(view.buffer().index()).copied().unwrap_or(false) {
            continue;
        }
        let decoded = compressed.decode(buffers, &field)?;
        if decoded.len() > view.length() {
            return Err(ImportError::invalid(field, format!("decodes to {} bytes, more than its byteLength of {}", decoded.len(), view.length())));
        }
        let target = view
            .offset()
            .checked_add(decoded.len())
            .and_then(|end| buffers.get_mut(view.buffer().index())?.get_mut(view.offset()..end))
            .ok_or_else(|| ImportError::invalid(&field, "lies past the end of its buffer"))?;
        target.copy_from_slice(&decoded);
    }
    Ok(())
}
