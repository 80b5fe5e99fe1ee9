//! The film: the frame's pixels in linear light, and their encoding: sRGB RGBA8 and PNG (after
//! an exposure and a tone curve), or linear OpenEXR and PFM for whoever grades the image.

use std::path::Path;
use std::sync::Mutex;

use glam::Vec3;
use image::ImageEncoder;
use image::codecs::png::PngEncoder;
use rayon::prelude::*;

use crate::{Error, Share, srgb};

/// A `width × height` image of linear RGB pixels, stored row by row with row 0 at the top.
///
/// Pixels stay linear (and unclamped) until they are encoded, so that later passes can
/// accumulate samples and tone-map before quantising to 8 bits.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    pixels: Vec<Vec3>,
}

/// The pixel buffer of the film dropped last, kept for the next frame: a 1080p film is 24 MB,
/// which a fresh allocation faults in (and the kernel clears) on every frame of a render loop,
/// on one thread before the frame can start.
static SPARE: Mutex<Vec<Vec3>> = Mutex::new(Vec::new());

/// A buffer of `n` pixels for a frame to write: the spare buffer of a dropped film if it fits
/// (neither too small nor more than twice too large), its pixels left as the old image had
/// them; else new storage on huge pages, black. The caller writes every pixel before it reads
/// one (clearing 24 MB first would cost a pass over memory per frame).
pub(crate) fn reused_pixels(n: usize) -> Vec<Vec3> {
    let spare = SPARE.lock().map(|mut spare| std::mem::take(&mut *spare)).unwrap_or_default();
    let mut pixels = if (n..=2 * n).contains(&spare.capacity()) { spare } else { raystage_kernel::huge_page_vec(n) };
    pixels.truncate(n);
    pixels.resize(n, Vec3::ZERO);
    pixels
}

impl Drop for Film {
    /// Keeps the pixel buffer as the spare for the next frame.
    fn drop(&mut self) {
        if let Ok(mut spare) = SPARE.lock() {
            *spare = std::mem::take(&mut self.pixels);
        }
    }
}

impl Film {
    /// A black film of `width × height` pixels.
    pub fn new(width: u32, height: u32) -> Film {
        Film { width, height, pixels: vec![Vec3::ZERO; width as usize * height as usize] }
    }

    /// A film of the given linear RGB pixels, row by row from the top; panics if there are not
    /// `width × height` of them.
    pub fn from_pixels(width: u32, height: u32, pixels: Vec<Vec3>) -> Film {
        assert_eq!(pixels.len(), width as usize * height as usize, "one pixel per position");
        Film { width, height, pixels }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Every pixel's linear RGB, row by row from the top.
    pub fn pixels(&self) -> &[Vec3] {
        &self.pixels
    }

    /// The linear RGB value of pixel `(x, y)`; panics outside the film.
    pub fn pixel(&self, x: u32, y: u32) -> Vec3 {
        assert!(x < self.width && y < self.height, "pixel ({x}, {y}) outside a {}×{} film", self.width, self.height);
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// The pixels of `share` (in [`Share::pixels`] order), three floats each: what a rank of a
    /// cluster sends of the share it rendered, the very bits the frame is put together from.
    pub fn share_values(&self, share: Share) -> Vec<f32> {
        share.pixels(self.width, self.height).flat_map(|(x, y)| self.pixel(x, y).to_array()).collect()
    }

    /// Puts `values` (as [`Film::share_values`] gives them) into the pixels of `share`; `false`,
    /// changing nothing, if there are not three per pixel of the share.
    pub fn set_share_values(&mut self, share: Share, values: &[f32]) -> bool {
        if values.len() != share.pixel_count(self.width, self.height) * 3 {
            return false;
        }
        for ((x, y), v) in share.pixels(self.width, self.height).zip(values.chunks_exact(3)) {
            self.pixels[y as usize * self.width as usize + x as usize] = Vec3::new(v[0], v[1], v[2]);
        }
        true
    }

    /// Rows `rows` of the film seen through `look`, as sRGB-encoded RGB8, row by row from the
    /// top: a band of a PNG that an encoder can compress while later bands are still being
    /// converted. Panics if the rows are not in the film.
    pub fn rgb8_rows(&self, rows: std::ops::Range<u32>, look: Look) -> Vec<u8> {
        assert!(rows.start <= rows.end && rows.end <= self.height, "rows {rows:?} outside a film of {} rows", self.height);
        let width = self.width as usize;
        rgb8(&self.pixels[rows.start as usize * width..rows.end as usize * width], 1, look)
    }

    /// The pixels as sRGB-encoded RGBA8 (opaque), row by row: the layout of an application's
    /// frame buffer and of the PNG.
    pub fn to_rgba8(&self) -> Vec<u8> {
        let table = srgb::table();
        let mut bytes = vec![0u8; self.pixels.len() * 4];
        bytes.par_chunks_mut(4).zip(self.pixels.par_iter()).for_each(|(out, p)| {
            out.copy_from_slice(&[srgb::encode_with(table, p.x), srgb::encode_with(table, p.y), srgb::encode_with(table, p.z), 255]);
        });
        bytes
    }

    /// The film encoded as an RGBA8 sRGB PNG.
    pub fn encode_png(&self) -> Result<Vec<u8>, Error> {
        let mut png = Vec::new();
        PngEncoder::new(&mut png).write_image(
            &self.to_rgba8(),
            self.width,
            self.height,
            image::ExtendedColorType::Rgba8,
        )?;
        Ok(png)
    }

    /// Encodes the film as PNG and writes it to `path`, replacing any existing file.
    pub fn write_png(&self, path: impl AsRef<Path>) -> Result<(), Error> {
        let path = path.as_ref();
        std::fs::write(path, self.encode_png()?).map_err(|source| Error::Write { path: path.to_owned(), source })
    }

    /// The film as `format` seen through `look`: PNG exposed, tone-mapped and sRGB-encoded;
    /// OpenEXR (32-bit float RGB) and PFM exposed but otherwise linear and unclamped.
    pub fn encode(&self, format: OutputFormat, look: Look) -> Result<Vec<u8>, Error> {
        let scale = look.scale();
        match format {
            OutputFormat::Png => {
                if look == Look::default() {
                    return self.encode_png();
                }
                let graded: Vec<Vec3> = self.pixels.par_iter().map(|&p| look.tone_map.apply(p * scale)).collect();
                Film::from_pixels(self.width, self.height, graded).encode_png()
            }
            OutputFormat::Exr => {
                let floats: Vec<f32> = self.pixels.iter().flat_map(|p| (*p * scale).to_array()).collect();
                let mut exr = std::io::Cursor::new(Vec::new());
                image::codecs::openexr::OpenExrEncoder::new(&mut exr).write_image(
                    bytemuck_f32(&floats),
                    self.width,
                    self.height,
                    image::ExtendedColorType::Rgb32F,
                )?;
                Ok(exr.into_inner())
            }
            OutputFormat::Pfm => {
                // "PF", the size, a negative scale for little-endian, then rows from the bottom.
                let mut pfm = format!("PF\n{} {}\n-1.0\n", self.width, self.height).into_bytes();
                for row in self.pixels.chunks(self.width as usize).rev() {
                    pfm.extend(row.iter().flat_map(|p| (*p * scale).to_array()).flat_map(f32::to_le_bytes));
                }
                Ok(pfm)
            }
        }
    }
}

impl Film {
    /// A film from a little-endian RGB PFM (as [`Film::encode`] writes one, rows from the
    /// bottom): an error naming what is wrong for anything else.
    pub fn from_pfm(bytes: &[u8]) -> Result<Film, Error> {
        let bad = |what: &str| Error::Decode(format!("not a little-endian RGB PFM: {what}"));
        let mut parts = bytes.splitn(4, |&b| b == b'\n');
        let (kind, dims, scale, data) = (parts.next(), parts.next(), parts.next(), parts.next().unwrap_or_default());
        if kind != Some(b"PF") {
            return Err(bad("no `PF` header"));
        }
        let dims = dims.and_then(|d| std::str::from_utf8(d).ok()).ok_or_else(|| bad("no size"))?;
        let (width, height) = dims.split_once(' ').and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?))).ok_or_else(|| bad("no size"))?;
        if !scale.and_then(|s| std::str::from_utf8(s).ok()?.trim().parse::<f32>().ok()).is_some_and(|s| s < 0.0) {
            return Err(bad("not little-endian"));
        }
        if width == 0 || data.len() as u64 != width as u64 * height as u64 * 12 {
            return Err(bad("the pixels do not match the size"));
        }
        let rows: Vec<Vec3> = data.chunks_exact(12).map(|c| Vec3::from_array(std::array::from_fn(|i| f32::from_le_bytes(c[4 * i..4 * i + 4].try_into().expect("4 bytes"))))).collect();
        Ok(Film::from_pixels(width, height, rows.chunks_exact(width as usize).rev().flatten().copied().collect()))
    }
}

/// The little-endian bytes of `floats`, as image encoders take float pixels.
fn bytemuck_f32(floats: &[f32]) -> &[u8] {
    // Safety: f32 has no padding and any byte pattern of its size is a valid u8 sequence; the
    // slice covers exactly the floats' memory. (The machines this builds for are little-endian,
    // as the encoders expect native order.)
    unsafe { std::slice::from_raw_parts(floats.as_ptr().cast::<u8>(), std::mem::size_of_val(floats)) }
}

/// An image file format a film can be written as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// 8-bit sRGB PNG, tone-mapped.
    Png,
    /// OpenEXR, 32-bit float linear RGB.
    Exr,
    /// Portable float map, 32-bit float linear RGB.
    Pfm,
}

impl OutputFormat {
    /// The format a file name's extension asks for (`.png`, `.exr`, `.pfm`, in any case); an
    /// error naming the extension for anything else.
    pub fn from_path(path: &Path) -> Result<OutputFormat, Error> {
        let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("png") => Ok(OutputFormat::Png),
            Some("exr") => Ok(OutputFormat::Exr),
            Some("pfm") => Ok(OutputFormat::Pfm),
            _ => Err(Error::UnknownFormat { path: path.to_owned() }),
        }
    }
}

/// How linear light becomes what a display shows: an exposure, then a tone curve (for PNG).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Look {
    /// Exposure in stops: the image is scaled by 2 to this power (every format).
    pub exposure: f32,
    /// The curve that brings light into [0, 1] for 8-bit images.
    pub tone_map: ToneMap,
}

impl Look {
    /// The factor the exposure scales the light by.
    fn scale(&self) -> f32 {
        self.exposure.exp2()
    }
}

/// A tone curve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ToneMap {
    /// Each channel clipped to [0, 1]: light as it is, up to white (the default).
    #[default]
    Clamp,
    /// The Khronos PBR Neutral tone mapper: colours below 0.76 as they are (base colours under
    /// white light come out as authored), brighter ones compressed towards white without
    /// shifting their hue.
    Neutral,
}

impl std::str::FromStr for ToneMap {
    type Err = Error;

    fn from_str(text: &str) -> Result<ToneMap, Error> {
        match text {
            "clamp" | "none" => Ok(ToneMap::Clamp),
            "neutral" => Ok(ToneMap::Neutral),
            _ => Err(Error::Setting { field: "tonemap", message: format!("`{text}` is not clamp (or none) or neutral") }),
        }
    }
}

impl ToneMap {
    /// The curve applied to linear colour `c`.
    pub fn apply(self, c: Vec3) -> Vec3 {
        match self {
            ToneMap::Clamp => c.clamp(Vec3::ZERO, Vec3::ONE),
            ToneMap::Neutral => {
                // Khronos PBR Neutral (2024), as its reference code has it.
                const START: f32 = 0.8 - 0.04;
                const DESATURATION: f32 = 0.15;
                let low = c.min_element();
                let offset = if low < 0.08 { low - 6.25 * low * low } else { 0.04 };
                let c = c - Vec3::splat(offset);
                let peak = c.max_element();
                if peak < START {
                    return c.max(Vec3::ZERO);
                }
                let d = 1.0 - START;
                let new_peak = 1.0 - d * d / (peak + d - START);
                let c = c * (new_peak / peak);
                let g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
                c.lerp(Vec3::splat(new_peak), g).clamp(Vec3::ZERO, Vec3::ONE)
            }
        }
    }
}

/// Sums of `samples` samples per pixel as sRGB RGB8 bytes, seen through `look`: the pixels are
/// the sums divided by the count, exactly as a progressive film divides them.
pub(crate) fn rgb8(sums: &[Vec3], samples: u32, look: Look) -> Vec<u8> {
    let table = srgb::table();
    let n = samples.max(1) as f32;
    let scale = look.scale();
    let mut bytes = vec![0u8; sums.len() * 3];
    for (out, s) in bytes.chunks_exact_mut(3).zip(sums) {
        let mut p = if n != 1.0 { *s / n } else { *s };
        if look != Look::default() {
            p = look.tone_map.apply(p * scale);
        }
        out.copy_from_slice(&[srgb::encode_with(table, p.x), srgb::encode_with(table, p.y), srgb::encode_with(table, p.z)]);
    }
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A film whose pixels all differ: a ramp in red and green, blue by parity.
    fn ramp(width: u32, height: u32) -> Film {
        let pixels = (0..height)
            .flat_map(|y| (0..width).map(move |x| Vec3::new(x as f32 / width as f32, y as f32 / height as f32, ((x + y) % 2) as f32)))
            .collect();
        Film::from_pixels(width, height, pixels)
    }

    #[test]
    fn a_frame_reuses_the_buffer_of_a_dropped_film_that_fits() {
        // Sizes no other test renders, so that the spare is this test's own.
        for (n, previous) in [(1000, 1000), (999, 1000), (1000, 1500), (1000, 3000)] {
            let film = Film::from_pixels(previous as u32, 1, vec![Vec3::ONE; previous]);
            let storage = film.pixels.as_ptr();
            drop(film);
            let pixels = reused_pixels(n);
            assert_eq!(pixels.len(), n);
            // Too large a spare (more than twice the size) is not kept for a small frame.
            assert_eq!(pixels.as_ptr() == storage, previous <= 2 * n, "{n} pixels after a film of {previous}");
        }
    }

    #[test]
    fn png_round_trip_keeps_size_and_pixels() {
        let film = ramp(37, 21);
        let decoded = image::load_from_memory(&film.encode_png().unwrap()).unwrap().to_rgba8();
        assert_eq!(decoded.dimensions(), (37, 21));
        assert_eq!(decoded.into_raw(), film.to_rgba8());
    }

    #[test]
    fn write_png_writes_a_decodable_file() {
        let path = std::env::temp_dir().join(format!("raystage-film-{}.png", std::process::id()));
        let film = ramp(16, 9);
        film.write_png(&path).unwrap();
        let decoded = image::open(&path).unwrap().to_rgba8();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(decoded.dimensions(), (16, 9));
        assert_eq!(decoded.into_raw(), film.to_rgba8());
    }

    #[test]
    fn write_png_to_a_missing_directory_is_an_error_naming_the_path() {
        let err = ramp(4, 4).write_png("/nonexistent-raystage-dir/frame.png").unwrap_err();
        assert!(err.to_string().contains("/nonexistent-raystage-dir/frame.png"), "{err}");
    }

    #[test]
    fn rgb8_rows_are_the_rgba8_bytes_without_alpha() {
        let film = ramp(13, 7);
        let rgba = film.to_rgba8();
        let rgb = |rows: std::ops::Range<u32>| -> Vec<u8> {
            rgba[rows.start as usize * 13 * 4..rows.end as usize * 13 * 4].chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect()
        };
        assert_eq!(film.rgb8_rows(0..7, Look::default()), rgb(0..7));
        assert_eq!(film.rgb8_rows(2..5, Look::default()), rgb(2..5));
        assert!(film.rgb8_rows(3..3, Look::default()).is_empty());
    }

    #[test]
    fn rgba8_is_srgb_encoded_and_opaque() {
        let film = Film::from_pixels(2, 1, vec![Vec3::new(0.0, 0.5, 1.0), Vec3::splat(2.0)]);
        assert_eq!(film.to_rgba8(), [0, 188, 255, 255, 255, 255, 255, 255]);
    }
}

#[cfg(test)]
mod format_tests {
    use super::*;

    #[test]
    fn extensions_choose_the_format_and_others_are_refused() {
        assert_eq!(OutputFormat::from_path(Path::new("a/frame.PNG")).unwrap(), OutputFormat::Png);
        assert_eq!(OutputFormat::from_path(Path::new("frame.exr")).unwrap(), OutputFormat::Exr);
        assert_eq!(OutputFormat::from_path(Path::new("frame.pfm")).unwrap(), OutputFormat::Pfm);
        let err = OutputFormat::from_path(Path::new("frame.tiff")).unwrap_err().to_string();
        assert_eq!(err, "cannot write frame.tiff: its name must end in .png, .exr or .pfm");
        assert!(OutputFormat::from_path(Path::new("frame")).is_err());
    }

    /// Linear formats keep light above 1 (times the exposure), bit for bit; the PNG tone-maps.
    #[test]
    fn linear_formats_keep_the_light_and_png_grades_it() {
        let film = Film::from_pixels(2, 1, vec![Vec3::new(4.0, 0.5, 0.25), Vec3::new(0.1, 0.2, 0.3)]);
        let look = Look { exposure: 1.0, tone_map: ToneMap::Neutral };
        let pfm = film.encode(OutputFormat::Pfm, look).unwrap();
        assert!(pfm.starts_with(b"PF\n2 1\n-1.0\n"));
        let first = f32::from_le_bytes(pfm[pfm.len() - 24..pfm.len() - 20].try_into().unwrap());
        assert_eq!(first, 8.0, "4 exposed by one stop");
        let exr = film.encode(OutputFormat::Exr, look).unwrap();
        let decoded = image::load_from_memory(&exr).unwrap().to_rgb32f();
        assert_eq!(decoded.get_pixel(0, 0).0, [8.0, 1.0, 0.5]);
        // Neutral keeps dark colours as they are and brings bright ones under white, hue kept.
        assert!((ToneMap::Neutral.apply(Vec3::new(0.5, 0.3, 0.2)) - Vec3::new(0.46, 0.26, 0.16)).abs().max_element() < 1e-5);
        let bright = ToneMap::Neutral.apply(Vec3::new(8.0, 1.0, 0.5));
        assert!(bright.max_element() <= 1.0 && bright.x > bright.y && bright.y > bright.z, "{bright}");
        assert_ne!(film.encode(OutputFormat::Png, look).unwrap(), film.encode_png().unwrap());
        // A PFM reads back as it was written.
        let back = Film::from_pfm(&pfm).unwrap();
        assert_eq!((back.width(), back.height(), back.pixel(0, 0), back.pixel(1, 0)), (2, 1, Vec3::new(8.0, 1.0, 0.5), Vec3::new(0.2, 0.4, 0.6)));
        assert!(Film::from_pfm(&pfm[..pfm.len() - 1]).is_err() && Film::from_pfm(b"P6\n1 1\n255\n").is_err());
    }
}
