//! A stream's render loop: progressive passes while the scene and settings stay the same,
//! starting over when either changes, and the newest image encoded (PNG or JPEG) whenever the
//! sender has delivered the previous one. A slow client therefore gets fewer, newer frames: nothing
//! queues.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use raystage_render::{Cancel, Film, FrameSettings, Look, RenderSettings};
use raystage_scene::Scene;
use raystage_service::{Accumulate, AppState, CancelOnDrop, Error, FrameReport, RenderTurn, SceneSlot, Urgency, scene_time};
use tokio::sync::{OwnedSemaphorePermit, mpsc, watch};

use crate::render::STREAM_BYTES_PER_PIXEL;
use crate::stream::protocol::{Encoding, FrameMessage, ServerMessage};

/// A pass aims to take about this long: short enough for interactive frame rates, long enough
/// that encoding a PNG per pass is a small part of it.
const TARGET_PASS_SECONDS: f64 = 0.05;
/// Most samples per pixel in one pass.
const MAX_PASS_SAMPLES: u32 = 64;

/// How long a stream whose image found no room waits before it tries again (if nothing changes
/// meanwhile).
const MEMORY_RETRY: std::time::Duration = std::time::Duration::from_secs(1);

/// A stream's image settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct StreamSettings {
    /// What the frames render (their samples per pixel are each pass's), and how they are graded.
    pub frame: FrameSettings,
    /// Samples per pixel the image refines to.
    pub max_samples: u32,
    /// How its frames are encoded.
    pub encoding: Encoding,
    /// JPEG quality, 1 to 100.
    pub quality: u8,
}

impl StreamSettings {
    /// The memory the stream's image takes while the stream is open.
    pub fn bytes(&self) -> u64 {
        self.frame.render.width as u64 * self.frame.render.height as u64 * STREAM_BYTES_PER_PIXEL
    }

    /// How the image is graded and encoded: what may change without new samples.
    fn presentation(&self) -> (Look, Encoding, u8) {
        (self.frame.look, self.encoding, self.quality)
    }

    /// Whether `other` renders the same image: it may only grade or encode it differently
    /// (exposure and tone curve apply when a frame is encoded), which needs no new samples.
    fn same_image(&self, other: &StreamSettings) -> bool {
        let unpresented = |s: &StreamSettings| StreamSettings { frame: FrameSettings { look: Look::default(), ..s.frame }, encoding: Encoding::Png, quality: 0, ..*s };
        unpresented(self) == unpresented(other)
    }

    /// The render settings for `scene`: a sample per pixel (each pass filters textures as a
    /// frame of one sample does), the sample sequences laid out for the samples the stream ends
    /// at, so that its pixels' samples are stratified up to there.
    fn render_settings(&self, scene: &Scene) -> RenderSettings {
        RenderSettings { samples_per_pixel: 1, planned_samples: Some(self.max_samples), ..self.frame.for_scene(scene) }
    }
}

/// A frame ready to send: its statistics as JSON text, and its image.
pub(crate) struct Packet {
    pub json: String,
    pub image: Vec<u8>,
}

/// The accumulation in progress.
struct Accumulation {
    /// What it renders, and how its last frame was graded.
    settings: StreamSettings,
    version: u64,
    progressive: Box<dyn Accumulate>,
    /// Its share of the memory for images being rendered, given back with it.
    memory: OwnedSemaphorePermit,
    /// The statistics of the last frame sent, sent again with a re-graded image.
    sent: Option<FrameMessage>,
}

/// Renders until the session ends (`settings` closes) or the scene is deleted (then it says so
/// on `replies` and returns). `out` holds the newest packet; `taken` says whether the sender has
/// delivered the last one. Each pass waits for `client`'s turn to render (see
/// [`raystage_service::Client`]), so a stream's passes and other clients' frames alternate.
///
/// A pass yields to a change of the scene or of the image (an edit, a camera move, new
/// settings): it is stopped at once, since its frame would show what is no longer wanted, and
/// its turn goes to the pass that starts over with the change, which would otherwise wait for
/// every other client's render first: the edit's frame comes one pass after it, not one round
/// of the turns after it. That pass runs to its end whatever changes meanwhile, and gives the
/// turn back: a stream whose scene changes faster than it renders (a drag, a playing clock that
/// other renders move) still shows frames, and takes turns with the others. A pass that shows a
/// change waits for its turn as an edit, ahead of the round ([`Urgency::Edit`]), and so does a
/// refining pass that a change overtakes while it waits.
pub(crate) async fn refine(
    state: AppState,
    slot: Arc<SceneSlot>,
    client: raystage_service::Client,
    mut settings: watch::Receiver<StreamSettings>,
    out: watch::Sender<Option<Arc<Packet>>>,
    taken: Arc<AtomicBool>,
    replies: mpsc::Sender<ServerMessage>,
) {
    let mut versions = slot.watch();
    let mut accumulation: Option<Accumulation> = None;
    let mut pass_samples = 1;
    let mut seq = 0;
    let mut out_of_memory = false;
    // The turn of a pass a change cut short, for the pass that starts over.
    let mut cut_short: Option<RenderTurn> = None;
    loop {
        if slot.is_deleted() {
            let error = Error::not_found(Some("scene".into()), format!("scene {} was deleted", slot.id));
            let _ = replies.send(ServerMessage::Error { request: None, error: error.detail }).await;
            return;
        }
        // A playing clock moves the scene before the pass (a failing one pauses itself).
        let _ = slot.follow_clock(&state).await;
        let wanted = *settings.borrow_and_update();
        let converged = accumulation
            .as_ref()
            .is_some_and(|a| a.settings.same_image(&wanted) && a.version == slot.version() && a.progressive.samples() >= wanted.max_samples);
        if converged {
            let acc = accumulation.as_mut().expect("converged");
            if acc.settings.presentation() != wanted.presentation() {
                // Only the grading or the encoding changed: the finished image is encoded again.
                acc.settings = wanted;
                let film = acc.progressive.film();
                let encoded = tokio::task::spawn_blocking(move || timed_encode(&film, &wanted)).await;
                if let (Ok(Some((image, encode_seconds))), Some(sent)) = (encoded, acc.sent.clone()) {
                    seq += 1;
                    let message = FrameMessage { seq, encoding: wanted.encoding, encode_seconds, ..sent };
                    send(&out, &taken, message, image);
                }
                continue;
            }
            // Nothing to render: a turn held for it goes to the others.
            cut_short = None;
            tokio::select! {
                changed = versions.changed() => if changed.is_err() { return },
                changed = settings.changed() => if changed.is_err() { return },
                () = slot.clock_due() => {}
            }
            continue;
        }
        if accumulation.as_ref().is_some_and(|a| !a.settings.same_image(&wanted)) {
            // Its memory is needed for the new image.
            accumulation = None;
        }
        let memory = match &accumulation {
            Some(_) => None,
            None => match state.reserve_render_memory(wanted.bytes()) {
                Ok(memory) => Some(memory),
                Err(error) => {
                    // Said once; tried again at the next change, or when others may have
                    // finished.
                    if !out_of_memory {
                        out_of_memory = true;
                        let _ = replies.send(ServerMessage::Error { request: None, error: error.detail }).await;
                    }
                    cut_short = None;
                    tokio::select! {
                        changed = versions.changed() => if changed.is_err() { return },
                        changed = settings.changed() => if changed.is_err() { return },
                        () = tokio::time::sleep(MEMORY_RETRY) => {}
                    }
                    continue;
                }
            },
        };
        out_of_memory = false;
        let (turn, restart) = match cut_short.take() {
            Some(turn) => (turn, true),
            None => {
                let shown = accumulation.as_ref().map(|a| (a.version, a.settings));
                let (turn, changed) = pass_turn(&state, client, &slot, &mut versions, &mut settings, shown, wanted).await;
                if changed {
                    // What this pass was to render is out of date: the loop starts over with
                    // the change, on this turn.
                    cut_short = Some(turn);
                    continue;
                }
                (turn, false)
            }
        };
        let (scene, version) = slot.snapshot().await;
        let mut acc = match (accumulation.take(), memory) {
            (Some(a), _) if a.version == version => Accumulation { settings: wanted, ..a },
            (old, memory) => {
                pass_samples = 1;
                let Some(memory) = memory.or_else(|| old.map(|a| a.memory)) else {
                    return; // One of the two holds the memory.
                };
                let Ok(progressive) = state.accumulator(wanted.render_settings(&scene)) else {
                    return; // The settings were checked when they were received.
                };
                Accumulation { settings: wanted, version, progressive, memory, sent: None }
            }
        };
        let samples = pass_samples.min(wanted.max_samples - acc.progressive.samples());
        let last = acc.progressive.samples() + samples >= wanted.max_samples;
        let sent = taken.clone();
        let scene_id = slot.id;
        // Dropped with this future when the stream closes (the session aborts it), which stops
        // the pass; cancelled by hand when a change supersedes it (unless it restarts).
        let cancel = CancelOnDrop(Cancel::new());
        let token = cancel.0.clone();
        let mut pass = tokio::task::spawn_blocking(move || {
            let _running = turn.running();
            let stats = acc.progressive.add(scene_id, &scene.frame(), acc.version, samples, false, &token);
            let time = scene_time(&scene);
            drop(scene);
            // Decided after the pass, which gave the sender its duration to deliver the last frame.
            let image = (stats.is_ok() && (last || sent.load(Ordering::Acquire))).then(|| timed_encode(&acc.progressive.film(), &acc.settings));
            // The turn goes to the next render here, once the work has stopped, unless a change
            // cut the pass short: then to the pass that starts over (never a restart's turn).
            let kept = (stats.is_err() && !restart).then_some(turn);
            (acc, stats, image.flatten(), time, kept)
        });
        let joined = if restart {
            pass.await
        } else {
            tokio::select! {
                joined = &mut pass => joined,
                () = superseded(&slot, &mut versions, &mut settings, version, wanted) => {
                    cancel.0.cancel();
                    pass.await
                }
            }
        };
        let Ok((mut acc, stats, image, time, kept)) = joined else {
            return;
        };
        let Ok(stats) = stats else {
            // Superseded: the accumulation was reset, and the loop starts what is wanted now.
            accumulation = Some(acc);
            cut_short = kept;
            continue;
        };
        pass_samples = if stats.seconds < TARGET_PASS_SECONDS / 2.0 {
            (pass_samples * 2).min(MAX_PASS_SAMPLES)
        } else if stats.seconds > TARGET_PASS_SECONDS * 2.0 {
            (pass_samples / 2).max(1)
        } else {
            pass_samples
        };
        if let Some((image, encode_seconds)) = image {
            seq += 1;
            let mut report = FrameReport::new(acc.progressive.settings(), &stats, encode_seconds, acc.version, time);
            report.cluster = acc.progressive.times();
            let message = FrameMessage {
                seq,
                scene_version: acc.version,
                scene_time: report.scene_time,
                width: report.width,
                height: report.height,
                integrator: report.integrator.clone(),
                samples: report.accumulated_samples,
                pass_samples: report.samples_per_pixel,
                pass_seconds: report.render_seconds,
                encoding: acc.settings.encoding,
                encode_seconds,
                rays: report.rays,
                mrays_per_second: report.mrays_per_second,
                effects: report.effects.clone(),
                converged: acc.progressive.samples() >= wanted.max_samples,
            };
            *slot.last_frame.lock().unwrap_or_else(|e| e.into_inner()) = Some(report);
            acc.sent = Some(message.clone());
            send(&out, &taken, message, image);
        }
        accumulation = Some(acc);
    }
}

/// A turn for a stream's next pass, and whether the scene or the image changed while it
/// waited. A pass that shows a change not yet shown (the stream's first image, an edit, new
/// settings: anything but another pass of the image `shown`, the accumulation's version and
/// settings) waits as an edit ([`Urgency::Edit`]); a refining pass waits in turn, and becomes an
/// edit if a change comes meanwhile.
async fn pass_turn(
    state: &AppState,
    client: raystage_service::Client,
    slot: &SceneSlot,
    versions: &mut watch::Receiver<u64>,
    settings: &mut watch::Receiver<StreamSettings>,
    shown: Option<(u64, StreamSettings)>,
    wanted: StreamSettings,
) -> (RenderTurn, bool) {
    if let Some((version, rendering)) = shown
        && version == slot.version()
        && rendering.same_image(&wanted)
    {
        tokio::select! {
            turn = state.render_permit(client, Urgency::InTurn) => return (turn, false),
            () = superseded(slot, versions, settings, version, rendering) => {}
        }
        return (state.render_permit(client, Urgency::Edit).await, true);
    }
    (state.render_permit(client, Urgency::Edit).await, false)
}

/// `film` graded and encoded as `settings` say, and the seconds encoding took (`None` if it
/// failed).
fn timed_encode(film: &Film, settings: &StreamSettings) -> Option<(Vec<u8>, f64)> {
    let start = Instant::now();
    let image = match settings.encoding {
        Encoding::Png => crate::png::encode(film, settings.frame.look).ok()?,
        Encoding::Jpeg => jpeg(film, settings.frame.look, settings.quality).ok()?,
    };
    Some((image, start.elapsed().as_secs_f64()))
}

/// `film` as a baseline JPEG (sRGB, colour at full resolution) graded by `look`.
fn jpeg(film: &Film, look: Look, quality: u8) -> image::ImageResult<Vec<u8>> {
    let (width, height) = (film.width(), film.height());
    let rgb = film.rgb8_rows(0..height, look);
    let mut out = Vec::with_capacity(rgb.len() / 10);
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, quality).encode(&rgb, width, height, image::ExtendedColorType::Rgb8)?;
    Ok(out)
}

/// Makes `message` and its image the newest packet, for the sender to deliver.
fn send(out: &watch::Sender<Option<Arc<Packet>>>, taken: &AtomicBool, message: FrameMessage, image: Vec<u8>) {
    let json = serde_json::to_string(&ServerMessage::Frame(message)).expect("frames serialise");
    taken.store(false, Ordering::Release);
    out.send_replace(Some(Arc::new(Packet { json, image })));
}

/// Completes once a pass rendering `version` of `slot`'s scene with `rendering` settings is
/// out of date: the scene changed or was deleted, or the image the stream asks for changed (a
/// new grading does not count: the pass's samples serve it). Judged by what they are, not by
/// whether they were changed since last looked at: a change that came before the pass's
/// snapshot is in the pass. Never completes once the session has gone (its settings' sender is
/// dropped): the session aborts the loop then.
async fn superseded(
    slot: &SceneSlot,
    versions: &mut watch::Receiver<u64>,
    settings: &mut watch::Receiver<StreamSettings>,
    version: u64,
    rendering: StreamSettings,
) {
    loop {
        if *versions.borrow_and_update() != version || slot.is_deleted() || !settings.borrow_and_update().same_image(&rendering) {
            return;
        }
        let open = tokio::select! {
            changed = versions.changed() => changed.is_ok(),
            changed = settings.changed() => changed.is_ok(),
        };
        if !open {
            std::future::pending::<()>().await;
        }
    }
}
