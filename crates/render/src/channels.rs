//! Channels beside the colour: what the first surface seen through each pixel is (its distance,
//! normal, albedo and ids), as OSPRay's and ANARI's frames give them to compositors, denoisers
//! and picking. One ray through each pixel's centre, the lens's centre and the shutter's
//! opening: an id or a depth has no meaningful average over a pixel, and a denoiser wants the
//! albedo and normal of the surface, not of its antialiased edge.

use glam::Vec3;
use image::ImageEncoder;
use image::codecs::png::PngEncoder;
use rayon::prelude::*;
use raystage_scene::Frame;

use crate::error::Error;
use crate::integrator::Tracer;
use crate::{MAX_DIMENSION, RenderSettings};

/// What a channel holds at a pixel whose ray meets nothing: ids `u32::MAX` (ANARI's "no id"),
/// depths infinite, normals and albedo zero.
pub const NO_ID: u32 = u32::MAX;

/// A per-pixel attribute of the first surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Channel {
    /// Distance along the camera ray (world units).
    Depth,
    /// Camera-space depth: the distance from the camera's eye along its view axis.
    Z,
    /// Unit shading normal in the world (normal map applied), facing the camera.
    Normal,
    /// The surface's albedo (base colour, textured and vertex coloured), linear.
    Albedo,
    /// The id of the instance hit.
    Instance,
    /// The id of its object.
    Object,
    /// The index of the triangle in its object's mesh.
    Primitive,
}

impl Channel {
    /// Every channel, in the order of their names.
    pub const ALL: [Channel; 7] = [Channel::Depth, Channel::Z, Channel::Normal, Channel::Albedo, Channel::Instance, Channel::Object, Channel::Primitive];

    /// The channels' names, for messages.
    pub const NAMES: &str = "depth, z, normal, albedo, instance, object or primitive";

    /// Its name, as [`std::str::FromStr`] reads it.
    pub fn name(self) -> &'static str {
        match self {
            Channel::Depth => "depth",
            Channel::Z => "z",
            Channel::Normal => "normal",
            Channel::Albedo => "albedo",
            Channel::Instance => "instance",
            Channel::Object => "object",
            Channel::Primitive => "primitive",
        }
    }

    /// Whether its values are ids (whole numbers), not measurements.
    pub fn is_id(self) -> bool {
        matches!(self, Channel::Instance | Channel::Object | Channel::Primitive)
    }

    /// Whether it has no 8-bit form ([`ChannelImage::png`] refuses it): distances, unbounded.
    pub fn is_distance(self) -> bool {
        matches!(self, Channel::Depth | Channel::Z)
    }

    /// Values per pixel: 3 for normals and albedo, 1 for the rest.
    pub fn components(self) -> usize {
        match self {
            Channel::Normal | Channel::Albedo => 3,
            _ => 1,
        }
    }
}

impl std::str::FromStr for Channel {
    type Err = Error;

    fn from_str(text: &str) -> Result<Channel, Error> {
        Channel::ALL
            .into_iter()
            .find(|c| c.name() == text)
            .ok_or_else(|| Error::Setting { field: "channel", message: format!("`{text}` is not a channel: expected {}", Channel::NAMES) })
    }
}

/// One channel of a `width × height` image, row by row from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelImage {
    /// Which channel it is.
    pub channel: Channel,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// [`Channel::components`] values per pixel; ids as `f32` would lose precision past 2²⁴,
    /// so they are in `ids` instead and this is empty.
    pub values: Vec<f32>,
    /// The ids of an id channel, one per pixel ([`NO_ID`] where the ray met nothing).
    pub ids: Vec<u32>,
}

/// What the ray through one pixel met.
#[derive(Clone, Copy)]
struct FirstHit {
    depth: f32,
    z: f32,
    normal: Vec3,
    albedo: Vec3,
    ids: [u32; 3],
}

const MISSED: FirstHit = FirstHit { depth: f32::INFINITY, z: f32::INFINITY, normal: Vec3::ZERO, albedo: Vec3::ZERO, ids: [NO_ID; 3] };

/// `channels` of a `width × height` image of `frame`, rows traced in parallel (no ray at all
/// for no channel).
pub fn render_channels(frame: &Frame<'_>, width: u32, height: u32, channels: &[Channel]) -> Result<Vec<ChannelImage>, Error> {
    for (field, value) in [("width", width), ("height", height)] {
        if !(1..=MAX_DIMENSION).contains(&value) {
            return Err(Error::Setting { field, message: format!("{value} is not in 1..={MAX_DIMENSION}") });
        }
    }
    if channels.is_empty() {
        return Ok(Vec::new());
    }
    let settings = RenderSettings { width, height, ..RenderSettings::default() };
    let tracer = Tracer::new(frame, &settings, 1);
    let camera = frame.camera();
    let rays = camera.rays(width, height);
    let forward = (camera.target - camera.eye).normalize();
    let hits: Vec<FirstHit> = (0..width * height)
        .into_par_iter()
        .map(|i| {
            let ray = rays.ray((i % width) as f32 + 0.5, (i / width) as f32 + 0.5, [0.5, 0.5]);
            let mut counted = 0;
            let Some(hit) = tracer.trace(&ray, 0.0, &mut counted) else { return MISSED };
            let position = hit.surface.position;
            FirstHit {
                depth: hit.hit.t,
                z: (position - camera.eye).dot(forward),
                normal: hit.surface.shading_normal,
                albedo: hit.material.albedo,
                ids: [hit.hit.instance.0, hit.hit.object.0, hit.hit.prim],
            }
        })
        .collect();
    Ok(channels
        .iter()
        .map(|&channel| {
            let floats = |f: fn(&FirstHit) -> Vec<f32>| hits.iter().flat_map(f).collect::<Vec<f32>>();
            let ids = |k: usize| hits.iter().map(|h| h.ids[k]).collect::<Vec<u32>>();
            let (values, ids) = match channel {
                Channel::Depth => (floats(|h| vec![h.depth]), Vec::new()),
                Channel::Z => (floats(|h| vec![h.z]), Vec::new()),
                Channel::Normal => (floats(|h| h.normal.to_array().to_vec()), Vec::new()),
                Channel::Albedo => (floats(|h| h.albedo.to_array().to_vec()), Vec::new()),
                Channel::Instance => (Vec::new(), ids(0)),
                Channel::Object => (Vec::new(), ids(1)),
                Channel::Primitive => (Vec::new(), ids(2)),
            };
            ChannelImage { channel, width, height, values, ids }
        })
        .collect())
}

impl ChannelImage {
    /// The channel as a PFM (greyscale `Pf` for one value a pixel, `PF` for three): linear,
    /// unclamped, infinite where nothing was hit. Ids are written as floats, exact below 2²⁴,
    /// `-1` where nothing was hit.
    pub fn pfm(&self) -> Vec<u8> {
        let components = if self.channel.is_id() { 1 } else { self.channel.components() };
        let magic = if components == 3 { "PF" } else { "Pf" };
        let mut pfm = format!("{magic}\n{} {}\n-1.0\n", self.width, self.height).into_bytes();
        let row = self.width as usize * components;
        let values: Vec<f32> = if self.channel.is_id() {
            self.ids.iter().map(|&id| if id == NO_ID { -1.0 } else { id as f32 }).collect()
        } else {
            self.values.clone()
        };
        for row in values.chunks(row).rev() {
            pfm.extend(row.iter().flat_map(|v| v.to_le_bytes()));
        }
        pfm
    }

    /// The channel as an 8-bit RGB PNG: normals as `0.5 + 0.5·n`, albedo sRGB-encoded, ids in
    /// 24 bits (red the low byte; white where nothing was hit, and ids of 2²⁴ − 1 and more
    /// saturate to white). Depths have no 8-bit form: an error says to use PFM.
    pub fn png(&self) -> Result<Vec<u8>, Error> {
        let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
        let bytes: Vec<u8> = match self.channel {
            Channel::Depth | Channel::Z => {
                return Err(Error::Setting { field: "format", message: format!("the {} channel is written as PFM, not PNG", self.channel.name()) });
            }
            Channel::Normal => self.values.iter().map(|&n| byte(0.5 + 0.5 * n)).collect(),
            Channel::Albedo => {
                let table = crate::srgb::table();
                self.values.iter().map(|&a| crate::srgb::encode_with(table, a)).collect()
            }
            Channel::Instance | Channel::Object | Channel::Primitive => self.ids.iter().flat_map(|&id| id.min(0xff_ffff).to_le_bytes()[..3].to_vec()).collect(),
        };
        let mut png = Vec::new();
        PngEncoder::new(&mut png).write_image(&bytes, self.width, self.height, image::ExtendedColorType::Rgb8)?;
        Ok(png)
    }
}

/// `film` exposed by `look` and `channels` as one OpenEXR file of 32-bit floats, its channels
/// named as compositors group them into layers: `R`, `G`, `B`, then `depth.Z`, `z.Z`,
/// `normal.X`/`.Y`/`.Z`, `albedo.R`/`.G`/`.B`, and the ids as 32-bit unsigned integers in
/// `instance.id`, `object.id` and `primitive.id` ([`NO_ID`] for none). `channels` must be of the
/// film's size.
pub fn exr_with_channels(film: &crate::Film, look: crate::Look, channels: &[ChannelImage]) -> Result<Vec<u8>, crate::Error> {
    use exr::prelude::*;
    let (width, height) = (film.width() as usize, film.height() as usize);
    for image in channels {
        if (image.width as usize, image.height as usize) != (width, height) {
            let message = format!("the {} channel is {}x{}, the image {width}x{height}", image.channel.name(), image.width, image.height);
            return Err(crate::Error::Setting { field: "channels", message });
        }
    }
    let scale = look.exposure.exp2();
    let component = |values: &[f32], n: usize, k: usize| -> Vec<f32> { values.iter().skip(k).step_by(n).copied().collect() };
    let colour: Vec<f32> = film.pixels().iter().flat_map(|p| (*p * scale).to_array()).collect();
    let mut list: Vec<AnyChannel<FlatSamples>> = ["R", "G", "B"].iter().enumerate().map(|(k, name)| AnyChannel::new(*name, FlatSamples::F32(component(&colour, 3, k)))).collect();
    for image in channels {
        let layer = image.channel.name();
        let names: &[&str] = match image.channel {
            Channel::Depth | Channel::Z => &["Z"],
            Channel::Normal => &["X", "Y", "Z"],
            Channel::Albedo => &["R", "G", "B"],
            Channel::Instance | Channel::Object | Channel::Primitive => &["id"],
        };
        for (k, name) in names.iter().enumerate() {
            let samples = if image.channel.is_id() { FlatSamples::U32(image.ids.clone()) } else { FlatSamples::F32(component(&image.values, names.len(), k)) };
            list.push(AnyChannel::new(format!("{layer}.{name}").as_str(), samples));
        }
    }
    let layer = Layer::new((width, height), LayerAttributes::named("raystage"), Encoding::FAST_LOSSLESS, AnyChannels::sort(SmallVec::from_vec(list)));
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_layer(layer).write().to_buffered(&mut bytes).map_err(|e| crate::Error::Exr(e.to_string()))?;
    Ok(bytes.into_inner())
}
