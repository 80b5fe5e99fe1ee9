//! The side panel's timeline, for a scene with animations: an animation chooser, a time slider
//! and play/pause, on the scene's clock (`PUT /scenes/{scene}/clock`). The clock plays on the
//! server, so every client of the scene sees the same moment and the viewer sends nothing
//! while it plays: the slider follows the time of the frames shown. Moving the slider sets the
//! clock's time; as each new time restarts the stream's image, sending faster than
//! [`SEND_INTERVAL`] would only show fewer samples, never more poses.

use std::time::Duration;

use eframe::egui;
use serde_json::{Value, json};

use crate::protocol::{AnimationInfo, Clock, Request};

/// The least time between two times sent from the slider, in seconds.
const SEND_INTERVAL: f64 = 0.1;

/// The timeline's state: which animation, what time, whether it plays, and what was sent.
#[derive(Default)]
pub(crate) struct Timeline {
    /// The animation played, by its place in the scene's list.
    animation: usize,
    /// Seconds into it, as the slider shows.
    seconds: f32,
    /// Whether the clock plays (as the server last said, or as asked since).
    playing: bool,
    /// A time the slider was moved to and not yet sent.
    unsent: Option<f32>,
    /// The UI time the slider last sent a time.
    sent_at: Option<f64>,
}

impl Timeline {
    /// Takes the clock as the server has it (with the scene, or after a change).
    pub(crate) fn follow(&mut self, clock: &Clock, animations: &[AnimationInfo]) {
        if let Some(k) = clock.animation.as_u64().and_then(|index| animations.iter().position(|a| u64::from(a.index) == index)) {
            self.animation = k;
        }
        self.playing = clock.playing;
        if self.unsent.is_none() {
            self.seconds = clock.time as f32;
        }
    }

    /// The controls for `animations` (at least one) in `ui`, the slider following `shown` (the
    /// time of the frame on screen) while the clock plays; the clock change to send, if any.
    pub(crate) fn controls(&mut self, ui: &mut egui::Ui, animations: &[AnimationInfo], shown: Option<f64>) -> Option<Request> {
        let now = ui.input(|i| i.time);
        // A fetch of the scene may bring fewer animations than before.
        self.animation = self.animation.min(animations.len().saturating_sub(1));
        let index = animations.get(self.animation)?.index;
        let mut change = None;
        if animations.len() > 1 {
            let before = self.animation;
            egui::ComboBox::from_label("animation").selected_text(name(animations, self.animation)).show_ui(ui, |ui| {
                for k in 0..animations.len() {
                    ui.selectable_value(&mut self.animation, k, name(animations, k));
                }
            });
            if self.animation != before {
                (self.seconds, self.unsent) = (0.0, None);
                change = Some(json!({ "animation": animations[self.animation].index, "time": 0.0 }));
            }
        }
        let duration = animations.get(self.animation).map_or(0.0, |a| a.duration.max(0.0));
        if self.playing
            && self.unsent.is_none()
            && let Some(shown) = shown
        {
            self.seconds = shown as f32;
        }
        self.seconds = self.seconds.clamp(0.0, duration);
        if ui.add(egui::Slider::new(&mut self.seconds, 0.0..=duration).text("seconds")).changed() {
            self.unsent = Some(self.seconds);
        }
        if ui.button(if self.playing { "pause" } else { "play" }).clicked() {
            self.playing = !self.playing;
            // Playing starts from the time on the slider; pausing keeps the clock's.
            let mut clock = json!({ "playing": self.playing, "animation": index });
            if self.playing {
                clock["time"] = json!(self.unsent.take().unwrap_or(self.seconds));
            }
            change = Some(clock);
        }
        change.or_else(|| self.due(ui.ctx(), now, index)).map(Request::Clock)
    }

    /// The time the slider was moved to, if it may go now; else, if one waits, a repaint for
    /// when it may.
    fn due(&mut self, ctx: &egui::Context, now: f64, index: u32) -> Option<Value> {
        let seconds = self.unsent?;
        if let Some(at) = self.sent_at.filter(|at| now - at < SEND_INTERVAL) {
            ctx.request_repaint_after(Duration::from_secs_f64(SEND_INTERVAL - (now - at)));
            return None;
        }
        (self.unsent, self.sent_at) = (None, Some(now));
        Some(json!({ "time": seconds, "animation": index }))
    }
}

/// Animation `k` as the chooser shows it: its name, or its index where it has none.
fn name(animations: &[AnimationInfo], k: usize) -> String {
    match animations.get(k) {
        Some(a) if !a.name.is_empty() => a.name.clone(),
        _ => format!("animation {k}"),
    }
}
