//! The side panel's timeline, for a scene with animations: an animation chooser, a time slider
//! and play/pause. Every time it shows is sent as a `set_time` command (`api/stream.md`), so
//! every client of the scene sees the pose; as each edit restarts the stream's image, sending
//! faster than [`SEND_INTERVAL`] would only show fewer samples, never more poses.

use std::time::Duration;

use eframe::egui;
use serde_json::json;

use crate::protocol::{AnimationInfo, Request};

/// The least time between two `set_time` commands, in seconds.
const SEND_INTERVAL: f64 = 0.1;

/// The timeline's state: which animation, what time, whether it plays, and what was sent.
pub(crate) struct Timeline {
    /// The animation played, by its place in the scene's list.
    animation: usize,
    /// Seconds into it, as the slider shows.
    seconds: f32,
    /// While it plays, the UI time its clock last advanced at.
    playing: Option<f64>,
    /// The pose last sent (animation, seconds) and the UI time it went.
    sent: (usize, f32, f64),
}

impl Default for Timeline {
    /// A glTF scene opens posed at 0 s of its first animation (docs/guide/gltf.md), so that
    /// pose counts as sent: opening the viewer is no edit.
    fn default() -> Timeline {
        Timeline { animation: 0, seconds: 0.0, playing: None, sent: (0, 0.0, f64::NEG_INFINITY) }
    }
}

impl Timeline {
    /// The controls for `animations` (at least one) in `ui`, and the `set_time` to send, if
    /// the time shown is not the one last sent and the last went long enough ago.
    pub(crate) fn controls(&mut self, ui: &mut egui::Ui, animations: &[AnimationInfo]) -> Option<Request> {
        let now = ui.input(|i| i.time);
        // A fetch of the scene may bring fewer animations than before.
        self.animation = self.animation.min(animations.len().saturating_sub(1));
        if animations.len() > 1 {
            egui::ComboBox::from_label("animation").selected_text(name(animations, self.animation)).show_ui(ui, |ui| {
                for k in 0..animations.len() {
                    ui.selectable_value(&mut self.animation, k, name(animations, k));
                }
            });
        }
        let duration = animations.get(self.animation).map_or(0.0, |a| a.duration.max(0.0));
        if let Some(last) = self.playing {
            // Playing loops: at the end it starts again.
            let advanced = self.seconds + (now - last) as f32;
            self.seconds = if duration > 0.0 { advanced.rem_euclid(duration) } else { 0.0 };
            self.playing = Some(now);
            ui.ctx().request_repaint();
        }
        self.seconds = self.seconds.clamp(0.0, duration);
        ui.add(egui::Slider::new(&mut self.seconds, 0.0..=duration).text("seconds"));
        if ui.button(if self.playing.is_some() { "pause" } else { "play" }).clicked() {
            self.playing = if self.playing.is_some() { None } else { Some(now) };
        }
        self.due(ui.ctx(), now, animations)
    }

    /// The `set_time` of the pose shown, if it is new and may go now; else, if it is new, a
    /// repaint for when it may.
    fn due(&mut self, ctx: &egui::Context, now: f64, animations: &[AnimationInfo]) -> Option<Request> {
        let (animation, seconds, at) = self.sent;
        if (animation, seconds) == (self.animation, self.seconds) {
            return None;
        }
        if now - at < SEND_INTERVAL {
            ctx.request_repaint_after(Duration::from_secs_f64(SEND_INTERVAL - (now - at)));
            return None;
        }
        self.sent = (self.animation, self.seconds, now);
        let index = animations.get(self.animation)?.index;
        Some(Request::Commands(json!([{ "set_time": { "seconds": self.seconds, "animation": index } }])))
    }
}

/// Animation `k` as the chooser shows it: its name, or its index where it has none.
fn name(animations: &[AnimationInfo], k: usize) -> String {
    match animations.get(k) {
        Some(a) if !a.name.is_empty() => a.name.clone(),
        _ => format!("animation {k}"),
    }
}
