//! Frames: the application's frame buffer (seed: *The OpenRT API* §2.5.3, "an
//! application-supplied memory region"), `rtSwapBuffers` which resolves every reference and
//! renders (frame semantics, §2.5.1), picking, and PNG output of the last frame.
//!
//! The frame buffer and the channel buffers are the only memory the library keeps a pointer to
//! without owning it: the application's, valid by `rtFrameBuffer`'s and `rtChannelBuffer`'s
//! promise until it is replaced, taken back or the context reset, and written only inside the
//! calls that deliver a frame. Everything else a call is given (vertices, meshes, texture pixels,
//! strings) is copied before it returns. A window toolkit (RTUT) lends no memory at all: its
//! frames go to a frame buffer the library keeps (`rtSwapBuffersKept`), and it copies them out
//! with `rtReadPixels`, so no window resize can free memory a frame still goes to.

use std::ffi::OsStr;
use std::os::unix::ffi::OsStrExt;
use std::ptr::NonNull;

use raystage_render::{Channel, ChannelImage, Film, NO_ID, render, render_channels};
use raystage_scene::SceneHit;

use crate::abi::enums::{
    RT_ALBEDO_CHANNEL, RT_DEPTH_CHANNEL, RT_INSTANCE_ID_CHANNEL, RT_MAX_FRAMEBUFFER_SIZE, RT_NORMAL_CHANNEL, RT_OBJECT_ID_CHANNEL,
    RT_PRIMITIVE_ID_CHANNEL, RT_RGBA8, RT_RGBA32F, RT_Z_CHANNEL,
};
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

    pub fn bytes_per_pixel(self) -> usize {
        match self {
            PixelFormat::Rgba8 => 4,
            PixelFormat::Rgba32F => 16,
        }
    }

    /// Writes the `width × height` pixels of `film` from `(x, y)` on, row by row, into `out` in
    /// this layout: sRGB bytes or linear floats in native byte order, alpha opaque.
    fn write(self, film: &Film, (x, y): (u32, u32), (width, height): (u32, u32), out: &mut [u8]) {
        let rows = y..y + height;
        match self {
            PixelFormat::Rgba8 => {
                let (row, film_row) = (width as usize * 4, film.width() as usize * 4);
                let bytes = film.to_rgba8();
                for (out, y) in out.chunks_exact_mut(row).zip(rows) {
                    let start = y as usize * film_row + x as usize * 4;
                    out.copy_from_slice(&bytes[start..start + row]);
                }
            }
            PixelFormat::Rgba32F => {
                let pixels = rows.flat_map(|y| (x..x + width).map(move |x| film.pixel(x, y)));
                for (out, p) in out.chunks_exact_mut(16).zip(pixels) {
                    for (o, v) in out.chunks_exact_mut(4).zip([p.x, p.y, p.z, 1.0]) {
                        o.copy_from_slice(&v.to_ne_bytes());
                    }
                }
            }
        }
    }
}

/// Where a frame buffer's pixels live.
#[derive(Debug)]
enum Memory {
    /// The application's memory (`rtFrameBuffer`), valid by its promise.
    Lent(NonNull<u8>),
    /// None of the application's: the frame is kept as the last one (`rtSwapBuffersKept`), for
    /// `rtReadPixels`.
    Kept,
}

/// Where frames go: `width × height` pixels, row 0 at the top.
#[derive(Debug)]
pub(crate) struct FrameBuffer {
    memory: Memory,
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
        let (width, height) = lent_size("a frame buffer", width, height)?;
        Ok(FrameBuffer { memory: Memory::Lent(pixels), width, height, format })
    }

    /// A frame buffer of `width × height` pixels in no memory of the application's: its frames
    /// are only kept as the last one.
    pub fn kept(width: usize, height: usize) -> Result<FrameBuffer, Error> {
        let (width, height) = lent_size("a frame buffer", width, height)?;
        Ok(FrameBuffer { memory: Memory::Kept, width, height, format: PixelFormat::Rgba8 })
    }

    /// Writes `film` (of the same size) into the frame buffer's memory, if it has any.
    fn write(&self, film: &Film) {
        let Memory::Lent(pixels) = self.memory else { return };
        let len = self.width as usize * self.height as usize * self.format.bytes_per_pixel();
        // SAFETY: `new`'s contract: `len` writable bytes, not touched by anyone else meanwhile.
        let bytes = unsafe { std::slice::from_raw_parts_mut(pixels.as_ptr(), len) };
        self.format.write(film, (0, 0), (self.width, self.height), bytes);
    }
}

/// The size of memory lent for frames (`what`), checked: each side 1 to
/// `RT_MAX_FRAMEBUFFER_SIZE`.
fn lent_size(what: &str, width: usize, height: usize) -> Result<(u32, u32), Error> {
    let size = 1..=RT_MAX_FRAMEBUFFER_SIZE;
    if !size.contains(&width) || !size.contains(&height) {
        return Err(Error::invalid_value(format!("{what} of {width} × {height} pixels; each side must be 1 to {RT_MAX_FRAMEBUFFER_SIZE}")));
    }
    Ok((width as u32, height as u32))
}

/// The channel named by an `RT_*_CHANNEL` constant.
pub(crate) fn channel_from_enum(channel: RTenum) -> Result<Channel, Error> {
    Ok(match channel {
        RT_DEPTH_CHANNEL => Channel::Depth,
        RT_Z_CHANNEL => Channel::Z,
        RT_NORMAL_CHANNEL => Channel::Normal,
        RT_ALBEDO_CHANNEL => Channel::Albedo,
        RT_INSTANCE_ID_CHANNEL => Channel::Instance,
        RT_OBJECT_ID_CHANNEL => Channel::Object,
        RT_PRIMITIVE_ID_CHANNEL => Channel::Primitive,
        _ => return Err(Error::invalid_enum(format!("{channel:#x} is not a channel (RT_DEPTH_CHANNEL ... RT_PRIMITIVE_ID_CHANNEL)"))),
    })
}

/// Memory the application lent for one channel: `width × height` values of 4 bytes
/// ([`Channel::components`] of them per pixel), row 0 at the top.
#[derive(Debug)]
pub(crate) struct ChannelBuffer {
    pub channel: Channel,
    data: NonNull<u8>,
    width: u32,
    height: u32,
}

impl ChannelBuffer {
    /// Checks the size and takes the memory.
    ///
    /// # Safety
    /// As [`FrameBuffer::new`]'s, for `width × height × components × 4` bytes.
    pub unsafe fn new(channel: Channel, data: NonNull<u8>, width: usize, height: usize) -> Result<ChannelBuffer, Error> {
        let (width, height) = lent_size("a channel buffer", width, height)?;
        Ok(ChannelBuffer { channel, data, width, height })
    }

    /// Writes `image` (of the same channel and size) into the application's memory: floats, or
    /// ids as C names them (scene id + 1, 0 for none; triangles from 0, `RT_NO_PRIMITIVE` for
    /// none).
    fn write(&self, image: &ChannelImage) {
        let len = self.width as usize * self.height as usize * self.channel.components();
        // SAFETY: `new`'s contract: `len` writable 4-byte values, not touched by anyone else.
        let out = unsafe { std::slice::from_raw_parts_mut(self.data.as_ptr(), len * 4) };
        let words: Box<dyn Iterator<Item = [u8; 4]> + '_> = match image.channel {
            Channel::Instance | Channel::Object => Box::new(image.ids.iter().map(|&id| if id == NO_ID { 0u32 } else { crate::ids::to_c(id) }.to_ne_bytes())),
            Channel::Primitive => Box::new(image.ids.iter().map(|id| id.to_ne_bytes())),
            _ => Box::new(image.values.iter().map(|v| v.to_ne_bytes())),
        };
        for (o, w) in out.chunks_exact_mut(4).zip(words) {
            o.copy_from_slice(&w);
        }
    }
}

/// The frame state of a context.
#[derive(Debug, Default)]
pub(crate) struct Frames {
    /// Where `rtSwapBuffers` writes.
    pub target: Option<FrameBuffer>,
    /// Channel buffers lent, one per channel at most.
    pub channels: Vec<ChannelBuffer>,
    /// The last frame rendered, for `rtWritePNG`.
    pub last: Option<Film>,
}

impl Context {
    /// `rtSwapBuffers`: renders the scene as it is now into the frame buffer, with the render
    /// settings as they are now.
    pub fn swap_buffers(&mut self) -> Result<(), Error> {
        let (width, height) = self.frame_buffer_size()?;
        let (film, channels) = self.render_frame("rtSwapBuffers", width, height)?;
        self.deliver(film, channels);
        Ok(())
    }

    /// `rtSwapBuffersKept`: renders a `width × height` frame as `rtSwapBuffers` does and, once it
    /// rendered, makes the frame buffer one of that size that the library keeps.
    /// Everything that can fail comes before the frame buffer changes, so a refused call leaves
    /// the program's frame buffer, its last frame and its memory as they were.
    pub fn swap_buffers_kept(&mut self, width: usize, height: usize) -> Result<(), Error> {
        let target = FrameBuffer::kept(width, height)?;
        let (film, channels) = self.render_frame("rtSwapBuffersKept", target.width, target.height)?;
        // Cannot fail: `render_frame` found no frame in flight.
        self.set_frame_buffer(Some(target))?;
        self.deliver(film, channels);
        Ok(())
    }

    /// Renders a `width × height` frame of the scene as it is now, with the channels lent, and
    /// changes nothing else: [`Context::deliver`] puts it where it goes. `what` names the call.
    fn render_frame(&mut self, what: &str, width: u32, height: u32) -> Result<(Film, Vec<ChannelImage>), Error> {
        self.outside_definition(what)?;
        self.no_frame_in_flight(what)?;
        let wanted = self.wanted_channels(width, height)?;
        // What `rtInitMPI`'s workers have not seen yet (nothing without MPI), taken before the
        // frame borrows the scene.
        #[cfg(feature = "mpi")]
        let edits = self.scene.take_edits();
        let frame = self.scene.frame();
        let settings = self.rendering.settings(&frame, width, height);
        // Across the MPI job's ranks if `rtInitMPI` joined one.
        #[cfg(feature = "mpi")]
        let across = crate::cluster::render_across_ranks(&mut self.cluster, edits, &frame, settings)?;
        #[cfg(not(feature = "mpi"))]
        let across = None;
        // The settings were checked as they were set, and the size as the frame buffer was lent.
        let film = match across {
            Some(film) => film,
            None => render(&frame, &settings).map_err(|e| Error::internal(e.to_string()))?.0,
        };
        let channels = render_channels(&frame, width, height, &wanted).map_err(|e| Error::internal(e.to_string()))?;
        Ok((film, channels))
    }

    /// The channels lent, checked against the frame's size `width × height` (an error names the
    /// first that differs: its memory was lent for another size).
    pub fn wanted_channels(&self, width: u32, height: u32) -> Result<Vec<Channel>, Error> {
        for c in &self.frames.channels {
            if (c.width, c.height) != (width, height) {
                return Err(Error::invalid_operation(format!(
                    "the {} channel buffer is {} × {} and the frame buffer {width} × {height}: lend them at the same size",
                    c.channel.name(),
                    c.width,
                    c.height
                )));
            }
        }
        Ok(self.frames.channels.iter().map(|c| c.channel).collect())
    }

    /// `rtChannelBuffer`: lends memory for `channel`, or takes it back (`None`). Refused while a
    /// frame is in flight, as `rtFrameBuffer` is.
    pub fn set_channel_buffer(&mut self, channel: Channel, buffer: Option<ChannelBuffer>) -> Result<(), Error> {
        self.no_frame_in_flight("rtChannelBuffer")?;
        self.frames.channels.retain(|c| c.channel != channel);
        self.frames.channels.extend(buffer);
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
    /// film's size, since it cannot change while a frame renders), its channels into their
    /// buffers, and as the last frame.
    pub fn deliver(&mut self, film: Film, channels: Vec<ChannelImage>) {
        if let Some(target) = &self.frames.target {
            target.write(&film);
        }
        for image in &channels {
            if let Some(buffer) = self.frames.channels.iter().find(|c| c.channel == image.channel) {
                buffer.write(image);
            }
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

    /// `rtReadPixels`: copies the `width × height` pixels of the last frame rendered from
    /// `(x, y)` on into `pixels`, in `format`.
    ///
    /// # Safety
    /// `pixels` must point to `width × height` pixels of `format` of writable memory.
    pub unsafe fn read_pixels(&self, (x, y): (usize, usize), (width, height): (usize, usize), format: PixelFormat, pixels: NonNull<u8>) -> Result<(), Error> {
        let film = self.last_frame()?;
        let (film_width, film_height) = (film.width() as usize, film.height() as usize);
        if x.checked_add(width).is_none_or(|right| right > film_width) || y.checked_add(height).is_none_or(|bottom| bottom > film_height) {
            return Err(Error::invalid_value(format!(
                "{width} × {height} pixels from ({x}, {y}) are not all inside the last frame, {film_width} × {film_height}"
            )));
        }
        // SAFETY: the caller's promise, for a rectangle now known to be inside a frame.
        let out = unsafe { std::slice::from_raw_parts_mut(pixels.as_ptr(), width * height * format.bytes_per_pixel()) };
        format.write(film, (x as u32, y as u32), (width as u32, height as u32), out);
        Ok(())
    }

    /// `rtWritePNG`: writes the last frame rendered as a PNG file at `path` (any bytes but NUL).
    pub fn write_png(&self, path: &[u8]) -> Result<(), Error> {
        self.last_frame()?.write_png(OsStr::from_bytes(path)).map_err(|e| Error::io(e.to_string()))
    }

    fn last_frame(&self) -> Result<&Film, Error> {
        self.frames.last.as_ref().ok_or_else(|| Error::invalid_operation("no frame has been rendered yet: call rtSwapBuffers first"))
    }

    fn frame_buffer(&self) -> Result<&FrameBuffer, Error> {
        self.frames.target.as_ref().ok_or_else(|| Error::invalid_operation("no frame buffer: call rtFrameBuffer first"))
    }
}
