//! Reading accessors with every offset checked: a file can declare any offset, count and
//! stride, so each is checked against the bytes actually there before anything is read.

use gltf::Accessor;
use gltf::accessor::{DataType, Dimensions};

use crate::error::ImportError;

/// How an attribute's numbers may be stored: the component types, and whether integers may be
/// plain (read as the whole numbers they are, which a node's transform or a texture transform
/// then scales) rather than normalised. The core specification's choices, or
/// `KHR_mesh_quantization`'s wider ones (integers for positions and texture coordinates, bytes
/// and shorts for directions), which files written by `gltfpack` and glTF-Transform use.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Encoding {
    pub types: &'static [DataType],
    pub plain_integers: bool,
}

impl Encoding {
    /// Floats only: the core specification's positions, normals, tangents, morph targets,
    /// times, translations and scales.
    pub const FLOAT: Encoding = Encoding { types: &[DataType::F32], plain_integers: false };
    /// Floats, or normalised unsigned bytes and shorts: the core specification's texture
    /// coordinates, colours and skin weights.
    pub const UNIT: Encoding = Encoding { types: &[DataType::F32, DataType::U8, DataType::U16], plain_integers: false };
    /// Floats, or any normalised byte or short: the core specification's animated rotations and
    /// morph weights.
    pub const NORMALISED: Encoding =
        Encoding { types: &[DataType::F32, DataType::I8, DataType::U8, DataType::I16, DataType::U16], plain_integers: false };
    /// Floats, or any byte or short, plain or normalised: quantised positions and texture
    /// coordinates.
    pub const QUANTISED: Encoding =
        Encoding { types: &[DataType::F32, DataType::I8, DataType::U8, DataType::I16, DataType::U16], plain_integers: true };
    /// Floats, or signed bytes and shorts, plain or normalised: quantised morph displacements of
    /// positions.
    pub const SIGNED: Encoding = Encoding { types: &[DataType::F32, DataType::I8, DataType::I16], plain_integers: true };
    /// Floats, or normalised signed bytes and shorts: quantised normals and tangents, morph
    /// displacements of normals and tangents, and (without the extension) of positions.
    pub const DIRECTION: Encoding = Encoding { types: &[DataType::F32, DataType::I8, DataType::I16], plain_integers: false };
}

/// The elements of an accessor as `f32` components, `N` per element (normalised integers are
/// mapped to `[0, 1]` or `[-1, 1]` as the glTF specification says, plain ones kept as they are).
pub(crate) fn read_floats<const N: usize>(
    accessor: &Accessor<'_>,
    buffers: &[Vec<u8>],
    encoding: Encoding,
    field: &str,
) -> Result<Vec<[f32; N]>, ImportError> {
    let view = checked(accessor, buffers, N, encoding.types, field)?;
    let ty = accessor.data_type();
    let normalized = accessor.normalized();
    if ty != DataType::F32 && !normalized && !encoding.plain_integers {
        return Err(ImportError::invalid(field, "integer components must be normalized"));
    }
    let values = (0..accessor.count()).map(|i| std::array::from_fn(|c| float(view.component(i, c), ty, normalized))).collect::<Vec<[f32; N]>>();
    if values.iter().flatten().any(|v| !v.is_finite()) {
        return Err(ImportError::invalid(field, "holds a number that is not finite"));
    }
    Ok(values)
}

/// The elements of a scalar unsigned-integer accessor (indices).
pub(crate) fn read_indices(accessor: &Accessor<'_>, buffers: &[Vec<u8>], field: &str) -> Result<Vec<u32>, ImportError> {
    Ok(read_uints::<1>(accessor, buffers, &[DataType::U8, DataType::U16, DataType::U32], field)?.into_iter().map(|[i]| i).collect())
}

/// The elements of an unsigned-integer accessor, `N` components per element, of the `allowed`
/// types (indices, and a skin's `JOINTS_n`).
pub(crate) fn read_uints<const N: usize>(accessor: &Accessor<'_>, buffers: &[Vec<u8>], allowed: &[DataType], field: &str) -> Result<Vec<[u32; N]>, ImportError> {
    let view = checked(accessor, buffers, N, allowed, field)?;
    Ok((0..accessor.count()).map(|i| std::array::from_fn(|c| u32::from_le_bytes(pad(view.component(i, c))))).collect())
}

/// Where an accessor's elements are, checked to lie within their buffer.
struct View<'a> {
    bytes: &'a [u8],
    stride: usize,
    component: usize,
}

impl View<'_> {
    /// The bytes of component `c` of element `i` (within bounds: checked when the view was made).
    fn component(&self, i: usize, c: usize) -> &[u8] {
        let start = i * self.stride + c * self.component;
        &self.bytes[start..start + self.component]
    }
}

/// Checks an accessor's type and bounds; returns the bytes its elements span.
fn checked<'a>(accessor: &Accessor<'_>, buffers: &'a [Vec<u8>], components: usize, allowed: &[DataType], field: &str) -> Result<View<'a>, ImportError> {
    let dims = match components {
        1 => Dimensions::Scalar,
        2 => Dimensions::Vec2,
        3 => Dimensions::Vec3,
        4 => Dimensions::Vec4,
        _ => Dimensions::Mat4,
    };
    if accessor.dimensions() != dims || !allowed.contains(&accessor.data_type()) {
        return Err(ImportError::invalid(
            field,
            format!("has type {:?} of {:?}, expected {dims:?} of one of {allowed:?}", accessor.dimensions(), accessor.data_type()),
        ));
    }
    if accessor.sparse().is_some() {
        return Err(ImportError::invalid(field, "sparse accessors are not supported"));
    }
    let view = accessor.view().ok_or_else(|| ImportError::invalid(field, "has no buffer view"))?;
    let component = accessor.data_type().size();
    let element = component * components;
    let stride = view.stride().unwrap_or(element);
    let count = accessor.count();
    let buffer = buffers.get(view.buffer().index()).ok_or_else(|| ImportError::invalid(field, "names a missing buffer"))?;
    let view_end = view.offset().checked_add(view.length()).filter(|&end| end <= buffer.len());
    let span = count.checked_sub(1).and_then(|last| last.checked_mul(stride)).and_then(|s| s.checked_add(element));
    let start = view.offset().checked_add(accessor.offset());
    match (view_end, span, start) {
        (Some(view_end), Some(span), Some(start)) if stride >= element && start.checked_add(span).is_some_and(|end| end <= view_end) => {
            Ok(View { bytes: &buffer[start..start + span], stride, component })
        }
        _ => Err(ImportError::invalid(
            field,
            format!("{count} elements of {element} bytes (stride {stride}) at offset {} do not fit in their buffer view", accessor.offset()),
        )),
    }
}

/// A little-endian integer of 1, 2 or 4 bytes, widened to 4.
fn pad(bytes: &[u8]) -> [u8; 4] {
    let mut out = [0u8; 4];
    out[..bytes.len()].copy_from_slice(bytes);
    out
}

/// A component as a float: `f32` as it is, normalised integers scaled to their unit range, plain
/// ones as the whole numbers they are.
fn float(bytes: &[u8], ty: DataType, normalized: bool) -> f32 {
    let (value, largest) = match ty {
        DataType::F32 => return f32::from_le_bytes(pad(bytes)),
        DataType::U8 => (bytes[0] as f32, 255.0),
        DataType::I8 => (bytes[0] as i8 as f32, 127.0),
        DataType::U16 => (u16::from_le_bytes([bytes[0], bytes[1]]) as f32, 65535.0),
        DataType::I16 => (i16::from_le_bytes([bytes[0], bytes[1]]) as f32, 32767.0),
        DataType::U32 => (u32::from_le_bytes(pad(bytes)) as f32, u32::MAX as f32),
    };
    // The most negative signed value maps to -1 as well, as the specification says.
    if normalized { (value / largest).max(-1.0) } else { value }
}
