//! The reference a report measures against: a converged raystage render, or an image the user
//! brings from any renderer (OpenEXR, PFM or a NumPy array of linear RGB).

use std::path::{Path, PathBuf};

use glam::Vec3;
use raystage_render::Film;

use crate::Error;

/// Where the reference comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum ReferenceSource {
    /// raystage's own path tracer at this many samples per pixel: blind to raystage's biases
    /// (its errors are measured against itself), but available for every scene.
    Converged {
        /// Samples per pixel.
        spp: u32,
    },
    /// An image rendered elsewhere (`.exr`, `.pfm` or `.npy`, linear RGB): the report's
    /// resolution is the image's, and bias shows.
    External(PathBuf),
}

impl ReferenceSource {
    /// How the report's first line names it.
    pub fn describe(&self) -> String {
        match self {
            ReferenceSource::Converged { spp } => format!("raystage's own path tracer at {spp} spp (it cannot show raystage's biases)"),
            ReferenceSource::External(path) => format!("the external image {}", path.display()),
        }
    }
}

/// Reads a linear RGB image: OpenEXR (`.exr`), little-endian PFM (`.pfm`) or a NumPy array of
/// shape (height, width, 3 or 4) of 32- or 64-bit floats (`.npy`), chosen by the extension.
pub fn read_image(path: &Path) -> Result<Film, Error> {
    let bad = |message: String| Error::Reference { path: path.to_owned(), message };
    let bytes = std::fs::read(path).map_err(|e| bad(e.to_string()))?;
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("pfm") => Film::from_pfm(&bytes).map_err(|e| bad(e.to_string())),
        Some("exr") => {
            let image = image::load_from_memory_with_format(&bytes, image::ImageFormat::OpenExr).map_err(|e| bad(e.to_string()))?;
            let rgb = image.to_rgb32f();
            let (width, height) = rgb.dimensions();
            let pixels = rgb.pixels().map(|p| Vec3::from_array(p.0)).collect();
            checked(Film::from_pixels(width, height, pixels)).map_err(bad)
        }
        Some("npy") => read_npy(&bytes).and_then(checked).map_err(bad),
        _ => Err(bad("expected a .exr, .pfm or .npy file".into())),
    }
}

/// The film, if every value is finite: a reference with NaNs would make every error NaN.
fn checked(film: Film) -> Result<Film, String> {
    match film.pixels().iter().position(|p| !p.is_finite()) {
        Some(i) => Err(format!("pixel ({}, {}) is not finite", i as u32 % film.width(), i as u32 / film.width())),
        None => Ok(film),
    }
}

/// A NumPy `.npy` file (format 1.0 to 3.0) of little-endian `f4` or `f8`, C order, shape
/// (height, width, 3 or 4): the alpha channel, if any, is dropped.
fn read_npy(bytes: &[u8]) -> Result<Film, String> {
    if bytes.len() < 10 || &bytes[..6] != b"\x93NUMPY" {
        return Err("not a NumPy .npy file".into());
    }
    let (header_len, start) = match bytes[6] {
        1 => (u16::from_le_bytes([bytes[8], bytes[9]]) as usize, 10),
        2 | 3 if bytes.len() >= 12 => (u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize, 12),
        v => return Err(format!(".npy format version {v} is not read here")),
    };
    let header = bytes.get(start..start + header_len).and_then(|h| std::str::from_utf8(h).ok()).ok_or("a truncated .npy header")?;
    let field = |key: &str| header.split_once(&format!("'{key}':")).map(|(_, rest)| rest.trim_start());
    let size = match field("descr") {
        Some(d) if d.starts_with("'<f4'") => 4,
        Some(d) if d.starts_with("'<f8'") => 8,
        _ => return Err(format!("expected little-endian float32 or float64 values ('<f4' or '<f8'), the header says {header}")),
    };
    if field("fortran_order").is_some_and(|f| f.starts_with("True")) {
        return Err("Fortran-ordered arrays are not read here; save with C order".into());
    }
    let shape: Vec<usize> = field("shape")
        .and_then(|s| s.strip_prefix('(')?.split_once(')'))
        .map(|(dims, _)| dims.split(',').filter(|d| !d.trim().is_empty()).map(|d| d.trim().parse::<usize>()).collect::<Result<_, _>>())
        .transpose()
        .map_err(|e| format!("a bad shape: {e}"))?
        .ok_or("no shape in the header")?;
    let [height, width, channels] = shape[..] else { return Err(format!("expected a shape (height, width, 3 or 4), got {shape:?}")) };
    if !(channels == 3 || channels == 4) || width == 0 || height == 0 || width > u32::MAX as usize || height > u32::MAX as usize {
        return Err(format!("expected a shape (height, width, 3 or 4), got {shape:?}"));
    }
    let data = &bytes[start + header_len..];
    let count = height.checked_mul(width).and_then(|n| n.checked_mul(channels)).ok_or("a shape too large")?;
    if data.len() != count.saturating_mul(size) {
        return Err(format!("{} bytes of values where the shape needs {}", data.len(), count.saturating_mul(size)));
    }
    let value = |i: usize| -> f32 {
        let b = &data[i * size..(i + 1) * size];
        if size == 4 { f32::from_le_bytes(b.try_into().expect("4 bytes")) } else { f64::from_le_bytes(b.try_into().expect("8 bytes")) as f32 }
    };
    let pixels = (0..height * width).map(|p| Vec3::new(value(p * channels), value(p * channels + 1), value(p * channels + 2))).collect();
    Ok(Film::from_pixels(width as u32, height as u32, pixels))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn npy(descr: &str, shape: &str, values: &[u8]) -> Vec<u8> {
        let mut header = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
        while (10 + header.len() + 1) % 64 != 0 {
            header.push(' ');
        }
        header.push('\n');
        let mut out = b"\x93NUMPY\x01\x00".to_vec();
        out.extend((header.len() as u16).to_le_bytes());
        out.extend(header.as_bytes());
        out.extend(values);
        out
    }

    #[test]
    fn numpy_arrays_of_floats_and_doubles_are_read() {
        let floats: Vec<u8> = [1.0f32, 2.0, 3.0, 4.0, 5.0, 6.0].iter().flat_map(|v| v.to_le_bytes()).collect();
        let film = read_npy(&npy("<f4", "(1, 2, 3)", &floats)).unwrap();
        assert_eq!((film.width(), film.height()), (2, 1));
        assert_eq!(film.pixel(1, 0), Vec3::new(4.0, 5.0, 6.0));
        let doubles: Vec<u8> = [0.5f64, 0.25, 0.125, 1.0].iter().flat_map(|v| v.to_le_bytes()).collect();
        let film = read_npy(&npy("<f8", "(1, 1, 4)", &doubles)).unwrap();
        assert_eq!(film.pixel(0, 0), Vec3::new(0.5, 0.25, 0.125));
    }

    #[test]
    fn bad_numpy_arrays_are_errors() {
        let floats: Vec<u8> = [1.0f32; 6].iter().flat_map(|v| v.to_le_bytes()).collect();
        assert!(read_npy(&npy("<i4", "(1, 2, 3)", &floats)).unwrap_err().contains("float32"));
        assert!(read_npy(&npy("<f4", "(2, 3)", &floats)).unwrap_err().contains("shape"));
        assert!(read_npy(&npy("<f4", "(2, 2, 3)", &floats)).unwrap_err().contains("bytes of values"));
        assert!(read_npy(b"PF\n1 1\n").unwrap_err().contains("not a NumPy"));
    }
}
