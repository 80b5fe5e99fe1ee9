//! Frames: the application's frame buffer (seed: *The OpenRT API* §2.5.3, "an
//! application-supplied memory region"), `rtSwapBuffers` which resolves every reference and
//! renders (frame semantics, §2.5.1), picking, and PNG output of the last frame.

use std::ffi::OsStr;
use std::os::unix::ffi::OsStrExt;
use std::ptr::NonNull;

use raystage_render::{Film, render};
use raystage_scene::SceneHit;

use crate::abi::enums::{RT_MAX_FRAMEBUFFER_SIZE, RT_RGBA8, RT_RGBA32F};
use crate::abi::types::RTenum;
use crate::context::Context;
use crate::error::Error;

/// The pixel layouts a frame buffer can have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PixelFormat {
    /// sRGB bytes, alpha 255.
    Rgba8,
    /// Linear floats in native byte order, alpha 1.
    Rgba32F,
}

impl PixelFormat {
    /// The format named by an `RT_*` constant.
    pub fn from_enum(format: RTenum) -> Result<PixelFormat, Error> {
        match format {
            RT_RGBA8 => Ok(PixelFormat::Rgba8),
            RT_RGBA32F => Ok(PixelFormat::Rgba32F),
            _ => Err(Error::invalid_enum(format!("{format:#x} is not a pixel format (RT_RGBA8 or RT_RGBA32F)"))),
        }
    }

    fn bytes_per_pixel(self) -> usize {
        match self {
            PixelFormat::Rgba8 => 4,
            PixelFormat::Rgba32F => 16,
        }
    }
}

/// Memory the application lent for frames: `width × height` pixels, row 0 at the top.
#[derive(Debug)]
pub(crate) struct FrameBuffer {
    pixels: NonNull<u8>,
    pub width: u32,
    pub height: u32,
    format: PixelFormat,
}

impl FrameBuffer {
    /// Checks the size and takes the memory.
    ///
    /// # Safety
    /// `pixels` must point to `width × height × (4 or 16)` bytes of writable memory that stay
    /// valid until the frame buffer is replaced or detached (the promise `rtFrameBuffer`
    /// documents), and that nothing else writes while `rtSwapBuffers` runs.
    pub unsafe fn new(pixels: NonNull<u8>, width: usize, height: usize, format: PixelFormat) -> Result<FrameBuffer, Error> {
        let size = 1..=RT_MAX_FRAMEBUFFER_SIZE;
        if !size.contains(&width) || !size.contains(&height) {
            return Err(Error::invalid_value(format!(
                "a frame buffer of {width} × {height} pixels; each side must be 1 to {RT_MAX_FRAMEBUFFER_SIZE}"
            )));
        }
        Ok(FrameBuffer { pixels, width: width as u32, height: height as u32, format })
    }

    /// Writes `film` (of the same size) into the application's memory.
    fn write(&self, film: &Film) {
        let len = self.width as usize * self.height as usize * self.format.bytes_per_pixel();
        // SAFETY: `new`'s contract: `len` writable bytes, not touched by anyone else meanwhile.
        let bytes = unsafe { std::slice::from_raw_parts_mut(self.pixels.as_ptr(), len) };
        match self.format {
            PixelFormat::Rgba8 => bytes.copy_from_slice(&film.to_rgba8()),
            PixelFormat::Rgba32F => {
                let pixels = (0..self.height).flat_map(|y| (0..self.width).map(move |x| film.pixel(x, y)));
                for (out, p) in bytes.chunks_exact_mut(16).zip(pixels) {
                    for (o, v) in out.chunks_exact_mut(4).zip([p.x, p.y, p.z, 1.0]) {
                        o.copy_from_slice(&v.to_ne_bytes());
                    }
                }
            }
        }
    }
}

/// The frame state of a context.
#[derive(Debug, Default)]
pub(crate) struct Frames {
    /// Where `rtSwapBuffers` writes.
    pub target: Option<FrameBuffer>,
    /// The last frame rendered, for `rtWritePNG`.
    pub last: Option<Film>,
}

impl Context {
    /// `rtSwapBuffers`: renders the scene as it is now into the frame buffer, with the render
    /// settings as they are now.
    pub fn swap_buffers(&mut self) -> Result<(), Error> {
        self.outside_definition("rtSwapBuffers")?;
        self.no_frame_in_flight("rtSwapBuffers")?;
        let (width, height) = self.frame_buffer_size()?;
        let frame = self.scene.frame();
        let settings = self.rendering.settings(&frame, width, height);
        // The settings were checked as they were set, and the size as the frame buffer was lent.
        let (film, _stats) = render(&frame, &settings).map_err(|e| Error::internal(e.to_string()))?;
        self.deliver(film);
        Ok(())
    }

    /// `rtFrameBuffer`: lends the frame buffer, or detaches it (`None`). Refused while a frame is
    /// in flight, since that frame's image is written into the frame buffer it started with.
    pub fn set_frame_buffer(&mut self, target: Option<FrameBuffer>) -> Result<(), Error> {
        self.no_frame_in_flight("rtFrameBuffer")?;
        self.frames.target = target;
        Ok(())
    }

    /// Puts a rendered frame where `rtSwapBuffers` puts it: into the frame buffer (of the
    /// film's size, since it cannot change while a frame renders) and as the last frame.
    pub fn deliver(&mut self, film: Film) {
        if let Some(target) = &self.frames.target {
            target.write(&film);
        }
        self.frames.last = Some(film);
    }

    /// The frame buffer's width and height, or an error if there is none.
    pub fn frame_buffer_size(&self) -> Result<(u32, u32), Error> {
        self.frame_buffer().map(|t| (t.width, t.height))
    }

    /// `rtPick`: what pixel `(x, y)` of the frame buffer sees.
    pub fn pick(&mut self, x: u32, y: u32) -> Result<Option<SceneHit>, Error> {
        let target = self.frame_buffer()?;
        let (width, height) = (target.width, target.height);
        if x >= width || y >= height {
            return Err(Error::invalid_value(format!("pixel ({x}, {y}) is outside the {width} × {height} frame buffer")));
        }
        Ok(self.scene.frame().pick(x, y, width, height))
    }

    /// `rtWritePNG`: writes the last frame rendered as a PNG file at `path` (any bytes but NUL).
    pub fn write_png(&self, path: &[u8]) -> Result<(), Error> {
        let film = self
            .frames
            .last
            .as_ref()
            .ok_or_else(|| Error::invalid_operation("no frame has been rendered yet: call rtSwapBuffers first"))?;
        film.write_png(OsStr::from_bytes(path)).map_err(|e| Error::io(e.to_string()))
    }

    fn frame_buffer(&self) -> Result<&FrameBuffer, Error> {
        self.frames.target.as_ref().ok_or_else(|| Error::invalid_operation("no frame buffer: call rtFrameBuffer first"))
    }
}
