//! Rendering a frame: settings, the per-pixel sample loop over tiles, and progressive
//! accumulation of samples with a per-pixel variance estimate.

use std::sync::atomic::AtomicU32;
use std::sync::atomic::Ordering::Relaxed;
use std::time::Instant;

use glam::Vec3;
use raystage_kernel::{PACKET_SIZE, Ray};
use raystage_scene::{CameraRays, Frame, SceneHit};

use crate::integrator::first_shadows::{self, KnownShadows};
use crate::integrator::first_hits::FirstHits;
use crate::integrator::{Hit, Tracer, eyelight, first_matte, path, recursive};
use crate::lights::Seen;
use crate::sampler::PixelSampler;
use crate::stats::{FrameStats, PhaseTimes, RayCounts, TaskTimes};
use crate::tiles::{Share, Tile, TileSums, render_tiles_with};
use crate::{Cancel, Error, Film, FrameSettings, Integrator, MIN_ADAPTIVE_SAMPLES, RenderSettings};

/// Renders `settings.samples_per_pixel` samples of every pixel of `frame`, on the current rayon
/// pool.
pub fn render(frame: &Frame<'_>, settings: &RenderSettings) -> Result<(Film, FrameStats), Error> {
    render_rows(frame, settings, None, |_| {})
}

/// [`render`], handing every band of rows to `finished` as soon as its pixels are final, on the
/// render thread that finished them (bands complete out of order, each exactly once): a caller
/// can encode the image while the rest of it renders.
///
/// An adaptive render (`noise_threshold`) takes its samples in passes, [`MIN_ADAPTIVE_SAMPLES`]
/// then twice as many as it has, each pass to the tiles that are still noisy, and hands the
/// whole image on at the end.
///
/// With a `cancel` token, the render stops soon after the token is cancelled (see [`Cancel`])
/// and returns [`Error::Cancelled`]; bands not finished by then are never handed on.
pub fn render_rows(frame: &Frame<'_>, settings: &RenderSettings, cancel: Option<&Cancel>, finished: impl Fn(Rows<'_>) + Sync) -> Result<(Film, FrameStats), Error> {
    render_share_rows(frame, settings, Share::WHOLE, cancel, finished)
}

/// [`render`] of one share of the frame: the pixels [`Share::pixels`] lists are exactly those a
/// whole-frame render gives, the others are left black. Processes (MPI ranks)
/// that each render one share of `Share { index, count }` make the frame between them.
pub fn render_share(frame: &Frame<'_>, settings: &RenderSettings, share: Share) -> Result<(Film, FrameStats), Error> {
    render_share_rows(frame, settings, share, None, |_| {})
}

fn render_share_rows(
    frame: &Frame<'_>,
    settings: &RenderSettings,
    share: Share,
    cancel: Option<&Cancel>,
    finished: impl Fn(Rows<'_>) + Sync,
) -> Result<(Film, FrameStats), Error> {
    if settings.noise_threshold.is_some() {
        let mut progressive = Progressive::new(*settings)?.with_share(share)?;
        let total = settings.samples_per_pixel;
        let mut stats: Option<FrameStats> = None;
        while progressive.samples() < total {
            let pass = progressive.samples().max(MIN_ADAPTIVE_SAMPLES).min(total - progressive.samples());
            let pass_stats = progressive.pass(frame, pass, cancel, |_, _| {}).ok_or(Error::Cancelled)?;
            stats = Some(match stats {
                Some(mut sum) => {
                    sum.merge(&pass_stats);
                    sum
                }
                None => pass_stats,
            });
        }
        let film = progressive.film();
        finished(Rows { first: 0, width: settings.width, sums: film.pixels(), samples: 1 });
        return Ok((film, stats.expect("at least one sample per pixel")));
    }
    // One pass, whose variance nobody asks for: a 1080p frame saves 8 MB of page faults.
    let mut progressive = Progressive::without_variance(*settings)?.with_share(share)?;
    let samples = settings.samples_per_pixel;
    let stats = progressive.pass(frame, samples, cancel, |first, sums| finished(Rows { first, width: settings.width, sums, samples })).ok_or(Error::Cancelled)?;
    Ok((progressive.into_film(), stats))
}

/// Finished rows of a frame being rendered (see [`render_rows`]).
#[derive(Clone, Copy, Debug)]
pub struct Rows<'a> {
    first: u32,
    width: u32,
    /// The rows' sums of samples, row by row.
    sums: &'a [Vec3],
    samples: u32,
}

impl Rows<'_> {
    /// The image rows these are.
    pub fn rows(&self) -> std::ops::Range<u32> {
        self.first..self.first + (self.sums.len() / self.width as usize) as u32
    }

    /// The rows as sRGB RGB8 bytes: exactly what [`Film::rgb8_rows`] gives for them once the
    /// frame is done.
    pub fn rgb8(&self) -> Vec<u8> {
        self.rgb8_with(crate::Look::default())
    }

    /// The rows as sRGB RGB8 bytes seen through `look` (exposed and tone-mapped), as
    /// [`Film::encode`] makes a PNG's.
    pub fn rgb8_with(&self, look: crate::Look) -> Vec<u8> {
        crate::film::rgb8(self.sums, self.samples, look)
    }
}

/// A quick look at `frame`: one sample per pixel of a `width × height` image, with the default
/// settings and the integrator every front end chooses for the scene
/// ([`Integrator::default_for`]). Panics if the size is out of range.
pub fn render_frame(frame: &Frame<'_>, width: u32, height: u32) -> (Film, FrameStats) {
    let settings = RenderSettings { width, height, ..FrameSettings::default().for_scene(frame.scene()) };
    render(frame, &settings).expect("image size within range")
}

/// Progressive accumulation: while the scene and camera stay the same, each call adds samples to
/// every pixel, continuing the pixels' sample sequences; after a change, [`Progressive::reset`]
/// starts over. Keeps each pixel's mean and the variance of that mean.
///
/// The pixels' sample sequences are laid out for the settings' planned samples, else their
/// `samples_per_pixel` ([`RenderSettings::laid_out_for`]): passes that bring the pixels to that
/// count make exactly the render of that count, and samples past it are less stratified.
#[derive(Clone, Debug)]
pub struct Progressive {
    settings: RenderSettings,
    /// Per pixel, the sum of its samples. Before the first pass (`samples` 0) the buffers hold
    /// whatever an old image left there; the first pass writes every pixel.
    sum: Vec<Vec3>,
    /// Sum of squared luminances, for the variance estimate (not kept by one-pass renders).
    sum_sq: Option<Vec<f32>>,
    samples: u32,
    /// Per tile (row-major), the samples its pixels have, when sampling is adaptive: tiles
    /// whose pixels are all within the noise threshold stop taking samples.
    tile_samples: Option<Vec<u32>>,
    /// The part of the frame rendered: the whole frame but in a cluster.
    share: Share,
}

impl Progressive {
    /// An empty accumulation for images of `settings`' size, integrator and filter.
    pub fn new(settings: RenderSettings) -> Result<Progressive, Error> {
        let progressive = Progressive::without_variance(settings)?;
        let tile_samples = settings.noise_threshold.map(|_| vec![0; crate::tiles::tasks(settings.width, settings.height)]);
        Ok(Progressive { sum_sq: Some(vec![0.0; progressive.sum.len()]), tile_samples, ..progressive })
    }

    /// [`Progressive::new`] without the variance estimate, for a single pass.
    fn without_variance(settings: RenderSettings) -> Result<Progressive, Error> {
        settings.validate()?;
        let n = settings.width as usize * settings.height as usize;
        Ok(Progressive { settings, sum: crate::film::reused_pixels(n), sum_sq: None, samples: 0, tile_samples: None, share: Share::WHOLE })
    }

    /// This accumulation restricted to one share of the frame (see [`Share`]): its passes
    /// render only the share's tiles, exactly as a whole-frame accumulation renders them, and
    /// its image is black elsewhere.
    pub fn with_share(mut self, share: Share) -> Result<Progressive, Error> {
        if share.count == 0 || share.index >= share.count {
            return Err(Error::Setting { field: "share", message: format!("share {} of {} does not exist", share.index, share.count) });
        }
        self.share = share;
        Ok(self)
    }

    /// The settings this accumulation renders with.
    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    /// Samples per pixel accumulated so far.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Drops every sample: the next call to [`Progressive::add`] starts a new image.
    pub fn reset(&mut self) {
        // The next pass writes every pixel over what the sums hold.
        self.samples = 0;
        self.tile_samples.iter_mut().flatten().for_each(|n| *n = 0);
    }

    /// Samples per pixel taken on average over the share's pixels: below
    /// [`Progressive::samples`] where adaptive sampling stopped tiles early.
    pub fn mean_samples(&self) -> f64 {
        let owned: Vec<usize> = (0..self.sum.len()).filter(|&i| self.owns(i)).collect();
        owned.iter().map(|&i| self.samples_of(i) as f64).sum::<f64>() / owned.len().max(1) as f64
    }

    /// Whether pixel `i` (row-major) is in the share rendered.
    fn owns(&self, i: usize) -> bool {
        let (w, h) = (self.settings.width, self.settings.height);
        self.share == Share::WHOLE || self.share.owns_tile(crate::tiles::tile_of(i as u32 % w, i as u32 / w, w, h) as u32)
    }

    /// The samples pixel `i` (row-major) has.
    fn samples_of(&self, i: usize) -> u32 {
        let Some(tiles) = &self.tile_samples else { return self.samples };
        let (w, h) = (self.settings.width, self.settings.height);
        tiles[crate::tiles::tile_of(i as u32 % w, i as u32 / w, w, h)]
    }

    /// Adds `samples` samples per pixel of `frame`.
    pub fn add(&mut self, frame: &Frame<'_>, samples: u32) -> FrameStats {
        match self.pass(frame, samples, None, |_, _| {}) {
            Some(stats) => stats,
            None => unreachable!("only a cancel token stops a pass"),
        }
    }

    /// [`Progressive::add`], stopping soon after `cancel` is cancelled (see [`Cancel`]): then
    /// the pass's samples are only partly in, so the accumulation is [reset](Progressive::reset)
    /// (the next pass starts a new image) and the call returns [`Error::Cancelled`].
    pub fn add_cancellable(&mut self, frame: &Frame<'_>, samples: u32, cancel: &Cancel) -> Result<FrameStats, Error> {
        self.pass(frame, samples, Some(cancel), |_, _| {}).ok_or(Error::Cancelled)
    }

    /// [`Progressive::add`], calling `finished(first_row, sums)` for every band of rows once its
    /// samples are in; `None` if `cancel` stopped it (the accumulation is reset then).
    fn pass(&mut self, frame: &Frame<'_>, samples: u32, cancel: Option<&Cancel>, finished: impl Fn(u32, &[Vec3]) + Sync) -> Option<FrameStats> {
        let start = Instant::now();
        let built_before = frame.work().build_seconds;
        let s = self.settings;
        let tracer = Tracer::new(frame, &s, self.samples + samples);
        let effects = tracer.effects;
        let camera = frame.camera().rays(s.width, s.height);
        let first_index = self.samples;
        let counts = std::sync::Mutex::new(Counts::default());
        // Adaptive sampling: each tile's count, the tile's task the only one to touch it.
        let tile_samples: Option<Vec<AtomicU32>> = self.tile_samples.as_ref().map(|t| t.iter().map(|&n| AtomicU32::new(n)).collect());
        let (sum, sum_sq) = (&mut self.sum, self.sum_sq.as_deref_mut());
        let add = |tile: &Tile, sums: &mut TileSums<'_>| {
            let slot = tile_samples.as_ref().map(|t| &t[crate::tiles::tile_of(tile.x0, tile.y0, s.width, s.height)]);
            let first = slot.map_or(first_index, |n| n.load(Relaxed));
            if let (Some(threshold), Some(_)) = (s.noise_threshold, slot)
                && first >= MIN_ADAPTIVE_SAMPLES
                && sums.converged(first, threshold)
            {
                return;
            }
            let task_start = Instant::now();
            let mut work = TileWork::for_tile(tile);
            for index in first..first + samples {
                // Between samples too, so that a tile of many samples does not hold a
                // cancelled render up.
                if cancel.is_some_and(Cancel::is_cancelled) {
                    break;
                }
                work.sample(&tracer, &camera, index, sums);
            }
            if let Some(n) = slot {
                n.store(first + samples, Relaxed);
            }
            work.counts.tasks = TaskTimes::one(task_start.elapsed().as_secs_f64());
            counts.lock().unwrap_or_else(|e| e.into_inner()).add(work.counts);
            work.recycle();
        };
        render_tiles_with(s.width, s.height, self.share, sum, sum_sq, cancel, add, finished);
        if cancel.is_some_and(Cancel::is_cancelled) {
            // Some tiles have the pass's samples, some part of them, some none.
            self.reset();
            return None;
        }
        if let Some(counts) = tile_samples {
            self.tile_samples = Some(counts.into_iter().map(AtomicU32::into_inner).collect());
        }
        self.samples += samples;
        let counts = counts.into_inner().unwrap_or_else(|e| e.into_inner());
        let work = frame.work();
        let seconds = start.elapsed().as_secs_f64();
        Some(FrameStats {
            effects,
            default_lights: tracer.lights.defaulted(),
            non_finite: counts.non_finite,
            rays: counts.rays,
            samples_per_pixel: samples,
            accumulated_samples: self.samples,
            time_samples: counts.time_samples,
            lens_samples: counts.lens_samples,
            phases: PhaseTimes { top_level: frame.top_level_seconds(), object_builds: work.build_seconds - built_before, trace_and_shade: seconds },
            tasks: counts.tasks,
            seconds,
            work,
        })
    }

    /// The image: every pixel's mean so far.
    pub fn film(&self) -> Film {
        Film::from_pixels(self.settings.width, self.settings.height, self.sum.iter().enumerate().map(|(i, s)| self.mean(i, *s)).collect())
    }

    /// The image, taking the accumulation's memory instead of copying it.
    pub fn into_film(mut self) -> Film {
        let mut pixels = std::mem::take(&mut self.sum);
        if self.tile_samples.is_some() || self.samples != 1 || self.share != Share::WHOLE {
            pixels.iter_mut().enumerate().for_each(|(i, p)| *p = self.mean(i, *p));
        }
        Film::from_pixels(self.settings.width, self.settings.height, pixels)
    }

    /// Pixel `i`'s mean, from its `sum`; black outside the share rendered (its sum is stale).
    fn mean(&self, i: usize, sum: Vec3) -> Vec3 {
        if !self.owns(i) {
            return Vec3::ZERO;
        }
        match self.samples_of(i) {
            0 => Vec3::ZERO,
            n => sum / n as f32,
        }
    }

    /// Per pixel, the estimated variance of its mean luminance (zero below two samples).
    pub fn variance(&self) -> Vec<f32> {
        // Every public accumulation keeps the squared sums (`Progressive::new`).
        let Some(sum_sq) = self.sum_sq.as_ref() else {
            return vec![0.0; self.sum.len()];
        };
        self.sum
            .iter()
            .zip(sum_sq)
            .enumerate()
            .map(|(i, (s, sq))| crate::tiles::variance_of_mean(*s, *sq, self.samples_of(i)))
            .collect()
    }
}

/// Counts a tile gathers and the frame sums.
#[derive(Clone, Copy, Debug, Default)]
struct Counts {
    rays: RayCounts,
    time_samples: u64,
    lens_samples: u64,
    non_finite: u64,
    tasks: TaskTimes,
}

impl Counts {
    fn add(&mut self, o: Counts) {
        self.rays += o.rays;
        self.time_samples += o.time_samples;
        self.lens_samples += o.lens_samples;
        self.non_finite += o.non_finite;
        self.tasks += o.tasks;
    }
}

thread_local! {
    /// The buffers of the tile this thread rendered last, for its next one.
    static SPARE_WORK: std::cell::Cell<Option<TileWork>> = const { std::cell::Cell::new(None) };
}

/// A tile's pixels in packet order and the buffers its samples reuse (kept by each render
/// thread from tile to tile).
#[derive(Default)]
struct TileWork {
    /// The tile being rendered.
    tile: Tile,
    /// The tile's pixels, in 4×2 blocks (see [`packet_order`]).
    order: Vec<(u32, u32)>,
    /// This pass's sample of each pixel, in the tile's row-major order.
    samples: Vec<Vec3>,
    /// Per pixel, its sampler and its ray's shutter time, once the camera ray took samples
    /// (both empty for rays through pixel centres at the shutter's opening: those pixels'
    /// samplers start fresh where they are needed).
    samplers: Vec<PixelSampler>,
    rays: Vec<Ray>,
    times: Vec<f32>,
    hits: Vec<Option<SceneHit>>,
    counts: Counts,
}

impl TileWork {
    /// The work of `tile`, in the buffers this thread used for its last tile if it is not
    /// using them still (a thread building a tree lazily may start another tile while the
    /// build's parallel parts run: that tile gets buffers of its own).
    fn for_tile(tile: &Tile) -> TileWork {
        let mut work = SPARE_WORK.with(|spare| spare.take()).unwrap_or_default();
        work.tile = *tile;
        packet_order(tile, &mut work.order);
        work.samples.resize(tile.len(), Vec3::ZERO);
        // Every slot is written by the tile's camera rays before it is read.
        work.hits.resize(work.order.len(), None);
        work.counts = Counts::default();
        work
    }

    /// Hands the buffers back to this thread for its next tile.
    fn recycle(self) {
        SPARE_WORK.with(|spare| spare.set(Some(self)));
    }

    /// One sample (number `index`) of every pixel of the tile, added to the tile's sums (sample
    /// 0 is written over them). A frame of one sample per pixel looks through pixel centres;
    /// with more, samples spread over the pixel by the filter.
    fn sample(&mut self, t: &Tracer<'_, '_>, camera: &CameraRays, index: u32, sums: &mut TileSums<'_>) {
        self.trace_and_shade(t, camera, index);
        // The first sample writes every pixel over what the buffers held.
        sums.add(&self.samples, index == 0);
    }

    /// [`TileWork::sample`] of any frame: the tile's camera rays traced together, then shaded
    /// packet by packet.
    fn trace_and_shade(&mut self, t: &Tracer<'_, '_>, camera: &CameraRays, index: u32) {
        let s = t.settings;
        let shutter = t.frame.camera().shutter;
        let e = t.effects;
        let preview = s.fast_paths && previews_packets(t);
        let (samplers, rays, times) = (&mut self.samplers, &mut self.rays, &mut self.times);
        samplers.clear();
        times.clear();
        if s.fast_paths && through_centres(t) {
            // One sample per pixel, through its centre, at the shutter's opening: each
            // packet's camera rays are made together, over the last tile's (so that a tile of
            // the same size writes each ray once).
            rays.resize(self.order.len(), Ray::new(Vec3::ZERO, Vec3::Z));
            for (pixels, out) in self.order.chunks(PACKET_SIZE).zip(rays.chunks_mut(PACKET_SIZE)) {
                camera.centre_rays(pixels, out);
            }
        } else {
            rays.clear();
            for &(x, y) in &self.order {
                let mut sampler = PixelSampler::new(x, y, s.seed, index, s.laid_out_for());
                let [dx, dy] = if e.multisampling { s.filter.offset(sampler.next_2d()) } else { [0.5, 0.5] };
                let lens = if e.depth_of_field {
                    self.counts.lens_samples += 1;
                    sampler.next_2d()
                } else {
                    [0.5, 0.5]
                };
                let time = if e.motion_blur {
                    self.counts.time_samples += 1;
                    let [open, close] = shutter;
                    open + (close - open) * sampler.next_1d()
                } else {
                    shutter[0]
                };
                rays.push(camera.ray(x as f32 + dx, y as f32 + dy, lens));
                times.push(time);
                samplers.push(sampler);
            }
        }
        // Camera rays of neighbouring pixels go to the scene together; with motion blur each
        // has its own time, so they go one by one.
        if e.motion_blur || !s.fast_paths {
            for ((ray, time), hit) in rays.iter().zip(times.iter()).zip(self.hits.iter_mut()) {
                *hit = t.frame.intersect(ray, *time);
            }
        } else {
            t.frame.intersect_many(rays, &mut self.hits, shutter[0]);
        }
        self.counts.rays.primary += rays.len() as u64;
        let packed_shadows = s.fast_paths && first_shadows::applies(t);
        let packed_matte = packed_shadows && first_matte::applies(t);
        let mut first = FirstHits::new();
        for start in (0..self.order.len()).step_by(PACKET_SIZE) {
            let end = (start + PACKET_SIZE).min(self.order.len());
            // The first hits of a packet's camera rays, resolved together when their shadows
            // go in packets too (else each where it is shaded).
            let mut known = [KnownShadows::NONE; PACKET_SIZE];
            if packed_shadows {
                first.resolve(t, &rays[start..end], &self.hits[start..end], shutter[0]);
                first_shadows::trace(t, &first, shutter[0], &mut self.counts.rays, &mut known[..end - start]);
            }
            let mut matte = [None; PACKET_SIZE];
            if packed_matte {
                first_matte::shade(t, &rays[start..end], &first, &known[..end - start], &mut matte[..end - start]);
            }
            let mut previewed = [Vec3::ZERO; PACKET_SIZE];
            if preview {
                eyelight::shade(t, &rays[start..end], &self.hits[start..end], |k, colour| previewed[k] = colour);
            }
            for k in start..end {
                let (x, y) = self.order[k];
                let colour = if preview {
                    previewed[k - start]
                } else if let Some(colour) = matte[k - start] {
                    colour
                } else {
                    let first = FirstHit { hit: self.hits[k], resolved: first.resolved[k - start].as_ref(), shadows: known[k - start] };
                    let mut fresh = PixelSampler::new(x, y, s.seed, index, s.laid_out_for());
                    let sampler = samplers.get_mut(k).unwrap_or(&mut fresh);
                    let time = times.get(k).copied().unwrap_or(shutter[0]);
                    sample_pixel(t, &rays[k], time, first, sampler, &mut self.counts.rays)
                };
                place(&mut self.samples, &self.tile, (x, y), colour, &mut self.counts.non_finite);
            }
        }
    }
}

/// Whether the frame's camera rays go through pixel centres at the shutter's opening, one per
/// pixel and pass: no samples over the pixel, the lens or the shutter interval.
fn through_centres(t: &Tracer<'_, '_>) -> bool {
    let e = t.effects;
    !e.multisampling && !e.depth_of_field && !e.motion_blur
}

/// Whether the frame is an eye-light preview without area lights (whose light camera rays can
/// meet), which shades each packet of camera rays at once.
fn previews_packets(t: &Tracer<'_, '_>) -> bool {
    t.settings.integrator == Integrator::EyeLight && !t.lights.has_area()
}

/// Puts `colour`, the sample of `pixel`, in its place among the samples of `tile`. A NaN or
/// infinite sample would poison the pixel for good: it goes in as black, and is counted in
/// `non_finite` (the frame statistics report it, and tests fail on it: it is a bug).
#[inline]
fn place(samples: &mut [Vec3], tile: &Tile, (x, y): (u32, u32), colour: Vec3, non_finite: &mut u64) {
    let finite = colour.is_finite();
    *non_finite += !finite as u64;
    samples[tile.index(x, y)] = if finite { colour } else { Vec3::ZERO };
}

/// What is known of a camera ray's first hit before it is shaded.
struct FirstHit<'a, 'f> {
    /// The hit, if any.
    hit: Option<SceneHit>,
    /// What is there, if resolved already.
    resolved: Option<&'a Hit<'f>>,
    /// Its shadows, as far as they were traced in packets.
    shadows: KnownShadows,
}

/// The colour of one camera ray whose first hit is already known.
fn sample_pixel(t: &Tracer<'_, '_>, ray: &Ray, time: f32, first: FirstHit<'_, '_>, sampler: &mut PixelSampler, rays: &mut RayCounts) -> Vec3 {
    // Area lights in front of the first hit; the path tracer counts them itself, with the rest
    // of the path.
    let path = t.settings.integrator == Integrator::Path;
    let emitted = if path { Vec3::ZERO } else { t.emission(ray, first.hit.map(|h| h.t), Seen::Directly) };
    let Some(scene_hit) = first.hit else {
        return t.emission(ray, None, Seen::Directly) + t.background(ray.dir, Seen::Directly);
    };
    let e = t.effects;
    let (reflection, refraction) = if t.settings.specialize { (e.reflection, e.refraction) } else { (true, true) };
    if t.settings.integrator == Integrator::EyeLight {
        let mut colour = Vec3::ZERO;
        eyelight::shade(t, std::slice::from_ref(ray), &[Some(scene_hit)], |_, seen| colour = seen);
        return emitted + colour;
    }
    // Resolved here unless it was for the packet's shadows.
    let resolved_here;
    let hit = match first.resolved {
        Some(hit) => hit,
        None => {
            resolved_here = t.resolve(ray, scene_hit, time);
            &resolved_here
        }
    };
    let known = first.shadows;
    emitted
        + match t.settings.integrator {
            Integrator::EyeLight => unreachable!("shaded above"),
            Integrator::Whitted => match (reflection, refraction) {
                (false, false) => recursive::shade::<false, false, false>(t, ray, hit, time, known, sampler, rays),
                (true, false) => recursive::shade::<true, false, false>(t, ray, hit, time, known, sampler, rays),
                (false, true) => recursive::shade::<false, true, false>(t, ray, hit, time, known, sampler, rays),
                (true, true) => recursive::shade::<true, true, false>(t, ray, hit, time, known, sampler, rays),
            },
            Integrator::Distribution => match (reflection, refraction) {
                (false, false) => recursive::shade::<false, false, true>(t, ray, hit, time, known, sampler, rays),
                (true, false) => recursive::shade::<true, false, true>(t, ray, hit, time, known, sampler, rays),
                (false, true) => recursive::shade::<false, true, true>(t, ray, hit, time, known, sampler, rays),
                (true, true) => recursive::shade::<true, true, true>(t, ray, hit, time, known, sampler, rays),
            },
            Integrator::Path => path::shade(t, ray, *hit, time, sampler, rays),
        }
}

/// The tile's pixels (image coordinates) into `order`, grouped in blocks of 4×2 pixels (fewer at
/// the tile's edges), so that every [`PACKET_SIZE`] consecutive rays are neighbours.
fn packet_order(tile: &Tile, order: &mut Vec<(u32, u32)>) {
    const BLOCK: (u32, u32) = (4, 2);
    const _: () = assert!((BLOCK.0 * BLOCK.1) as usize == PACKET_SIZE);
    let (x1, y1) = (tile.x0 + tile.width, tile.y0 + tile.height);
    order.clear();
    for by in (tile.y0..y1).step_by(BLOCK.1 as usize) {
        for bx in (tile.x0..x1).step_by(BLOCK.0 as usize) {
            for y in by..(by + BLOCK.1).min(y1) {
                order.extend((bx..(bx + BLOCK.0).min(x1)).map(|x| (x, y)));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Filter;

    #[test]
    fn packet_order_visits_every_pixel_once_in_4x2_blocks() {
        for (width, height) in [(16, 16), (5, 3), (1, 1), (7, 16)] {
            let tile = Tile { x0: 3, y0: 5, width, height };
            let mut order = Vec::new();
            packet_order(&tile, &mut order);
            order.sort_unstable_by_key(|&(x, y)| (y, x));
            assert_eq!(order, (0..tile.len()).map(|i| tile.pixel(i)).collect::<Vec<_>>(), "{width}×{height}");
        }
        let mut order = Vec::new();
        packet_order(&Tile { x0: 0, y0: 0, width: 16, height: 16 }, &mut order);
        assert_eq!(&order[..8], &[(0, 0), (1, 0), (2, 0), (3, 0), (0, 1), (1, 1), (2, 1), (3, 1)]);
    }

    #[test]
    fn gaussian_offsets_stay_within_the_radius() {
        let f = Filter::Gaussian { radius: 1.5 };
        for i in 0..100 {
            let [x, y] = f.offset([i as f32 / 100.0, (i * 37 % 100) as f32 / 100.0]);
            assert!(((x - 0.5).powi(2) + (y - 0.5).powi(2)).sqrt() <= 1.5 + 1e-5);
        }
    }
}
