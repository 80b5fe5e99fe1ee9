//! The images of a report side by side.

use std::path::Path;

use raystage_render::Film;

use crate::Error;

/// White pixels between two images.
const GAP: u32 = 4;

/// Writes `films` (tone-mapped to sRGB) side by side, left to right with a white gap, to `path`
/// as PNG. Films of different heights are top-aligned on white.
pub fn strip(path: &Path, films: &[&Film]) -> Result<(), Error> {
    let fail = |message: String| Error::Draw { path: path.to_owned(), message };
    if films.is_empty() {
        return Err(fail("no images".into()));
    }
    let width = films.iter().map(|f| f.width()).sum::<u32>() + GAP * (films.len() as u32 - 1);
    let height = films.iter().map(|f| f.height()).max().unwrap_or(1);
    let mut out = image::RgbaImage::from_pixel(width, height, image::Rgba([255, 255, 255, 255]));
    let mut x0 = 0;
    for film in films {
        let rgba = film.to_rgba8();
        for y in 0..film.height() {
            for x in 0..film.width() {
                let i = 4 * (y * film.width() + x) as usize;
                out.put_pixel(x0 + x, y, image::Rgba([rgba[i], rgba[i + 1], rgba[i + 2], 255]));
            }
        }
        x0 += film.width() + GAP;
    }
    out.save(path).map_err(|e| fail(e.to_string()))
}
