//! The viewer's window: the newest frame filling the central panel, mouse controls that move
//! the camera, and a side panel with the render settings, the scene's environment light, its
//! animations' timeline, the frame statistics and the scene's objects and instances.
//!
//! [`Viewer`] is all UI state and no I/O: what it learns comes from [`Link::events`], what it
//! wants goes out on [`Link::requests`], so a test can play the server on the other end of the
//! same channels ([`Link::pair`]).

use std::collections::VecDeque;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use eframe::egui::{self, Color32, ColorImage, PointerButton, Rect, Sense, TextureHandle, TextureOptions};

use crate::net::{Event, Link, SceneSnapshot};
use crate::orbit::Orbit;
use crate::protocol::{FrameStats, Hello, LightInfo, Request, Settings};
use crate::timeline::Timeline;

/// The integrators a stream can use, as the server names them.
pub const INTEGRATORS: [&str; 4] = ["eyelight", "whitted", "distribution", "path"];
/// The choices of samples per pixel to refine to.
pub const MAX_SAMPLES: [u32; 8] = [1, 4, 16, 64, 256, 1024, 2048, 4096];
/// Samples in one frame the server allows by default (`Limits::max_frame_samples`): a stream
/// asking for more is refused, so the client lowers its samples per pixel at large sizes.
pub const MAX_FRAME_SAMPLES: u64 = 1920 * 1080 * 256;
/// How long the view's size must stay the same before the stream follows it (seconds): a
/// window being resized would otherwise restart the image at every step.
pub const RESIZE_DEBOUNCE: f64 = 0.3;
/// Frame arrivals the frame rate is measured over.
const RATE_WINDOW: Duration = Duration::from_secs(2);

/// What the viewer starts with.
#[derive(Clone, Debug, Default)]
pub struct ViewerOptions {
    /// The integrator to ask for, or `None` for the server's choice.
    pub integrator: Option<String>,
    /// Samples per pixel to refine to.
    pub max_samples: u32,
    /// Once a frame is shown, take a screenshot of the window, put it here, and close the
    /// window (also close it, with no screenshot, if the connection ends).
    pub screenshot: Option<ScreenshotSlot>,
    /// Seconds to keep streaming after the first frame is shown before the screenshot.
    pub screenshot_delay: f64,
}

/// Where a screenshot goes.
pub type ScreenshotSlot = Arc<Mutex<Option<Arc<ColorImage>>>>;

/// The viewer's state.
pub struct Viewer {
    link: Link,
    options: ViewerOptions,
    /// The scene as last fetched.
    scene: Option<SceneSnapshot>,
    /// The camera the mouse moves (from the scene's camera, then ours).
    orbit: Option<Orbit>,
    hello: Option<Hello>,
    texture: Option<TextureHandle>,
    stats: Option<FrameStats>,
    arrivals: VecDeque<Instant>,
    /// The integrator chosen here (`None`: the server's default).
    integrator: Option<String>,
    max_samples: u32,
    /// Exposure in stops, and whether the neutral tone curve grades the image (else clamping).
    exposure: f32,
    neutral: bool,
    /// Image pixels per screen pixel: 1, 1/2, 1/4.
    scale: f32,
    size: SizeFollower,
    problem: Option<String>,
    closed: Option<String>,
    /// The scene version whose first frame last made the viewer fetch the scene again.
    refetched_after: Option<u64>,
    /// Passes run with a frame on screen (the screenshot waits for one to be painted), and
    /// the UI time of the first.
    passes_with_frame: u32,
    first_shown: Option<f64>,
    screenshot: Screenshot,
    /// The scene's environment light as the lighting controls edit it.
    environment: Option<Environment>,
    /// The image file the lighting controls would load.
    environment_file: String,
    /// The animations' clock, for a scene with animations.
    timeline: Timeline,
}

/// The scene's (first) environment light, as the panel shows and edits it: every change is a
/// batch of commands on the stream, so every client of the scene sees it.
#[derive(Clone, Debug, PartialEq)]
struct Environment {
    /// Whether it is in the scene.
    state: Presence,
    /// Its map (the studio, an HDR sky), if any.
    map: Option<u32>,
    /// The last map it had, so that the image can be chosen again after `uniform`.
    last_map: Option<u32>,
    /// Its radiance divided by `intensity`.
    colour: [f32; 3],
    /// The largest component of its radiance.
    intensity: f32,
    /// Its turn about +y, in degrees.
    rotate: f32,
}

/// Where the environment light is.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Presence {
    /// In the scene, with this id.
    On(u32),
    /// Switched off here: deleted, its parameters kept to add it again.
    Off,
    /// Added again, its id not fetched yet.
    Adding,
}

impl Environment {
    /// The panel's view of `light`, an `EnvironmentLight`, after `before` (the panel's view
    /// of it until now).
    fn of(light: &LightInfo, before: Option<&Environment>) -> Environment {
        let radiance = light.radiance.unwrap_or([1.0; 3]);
        let intensity = radiance.into_iter().fold(0.0f32, f32::max);
        let colour = if intensity > 0.0 { radiance.map(|c| c / intensity) } else { [1.0; 3] };
        let last_map = light.map.or(before.and_then(|e| e.last_map));
        Environment { state: Presence::On(light.id), map: light.map, last_map, colour, intensity, rotate: light.rotate.unwrap_or(0.0) }
    }

    /// The controls of the light in `ui`, and the requests their changes make.
    fn controls(&mut self, ui: &mut egui::Ui) -> Vec<Request> {
        ui.label(if self.map.is_some() { "environment: image (a studio or a sky)" } else { "environment: uniform" });
        let mut on = self.state != Presence::Off;
        let switched = ui.checkbox(&mut on, "environment on").changed();
        let mut moved = false;
        if let Some(last_map) = self.last_map {
            ui.horizontal(|ui| {
                moved |= ui.selectable_value(&mut self.map, Some(last_map), "image").changed();
                moved |= ui.selectable_value(&mut self.map, None, "uniform").changed();
            });
        }
        let settle = |r: egui::Response| r.drag_stopped() || (r.changed() && !r.dragged());
        moved |= settle(ui.add(egui::Slider::new(&mut self.intensity, 0.0..=4.0).step_by(0.05).text("intensity")));
        if self.map.is_some() {
            moved |= settle(ui.add(egui::Slider::new(&mut self.rotate, -180.0..=180.0).step_by(5.0).text("rotation (degrees)")));
        }
        match (switched, self.state) {
            (true, Presence::On(id)) => {
                self.state = Presence::Off;
                vec![Request::Commands(serde_json::json!([{ "delete_light": { "id": id } }]))]
            }
            // Back on: a new light, whose id the next fetch of the scene tells.
            (true, Presence::Off) => {
                self.state = Presence::Adding;
                vec![Request::Commands(serde_json::json!([{ "add_light": self.spec() }])), Request::RefreshScene]
            }
            (false, Presence::On(id)) if moved => vec![Request::Commands(serde_json::json!([{ "set_light": { "id": id, "light": self.spec() } }]))],
            _ => Vec::new(),
        }
    }

    /// A white uniform environment of radiance 1, not yet in the scene.
    fn uniform() -> Environment {
        Environment { state: Presence::Off, map: None, last_map: None, colour: [1.0; 3], intensity: 1.0, rotate: 0.0 }
    }

    /// The light as the API describes it.
    fn spec(&self) -> serde_json::Value {
        serde_json::json!({
            "class": "EnvironmentLight",
            "radiance": self.colour.map(|c| c * self.intensity),
            "map": self.map,
            "rotate": self.rotate,
        })
    }
}

/// The stream's resolution follows the view's, once it has stopped changing.
#[derive(Default)]
struct SizeFollower {
    /// The size last sent.
    sent: Option<[u32; 2]>,
    /// The size wanted now, and since when (UI time).
    wanted: Option<([u32; 2], f64)>,
}

#[derive(Clone, Copy, Default, PartialEq, Eq)]
enum Screenshot {
    #[default]
    NotYet,
    Requested,
    Done,
}

impl Viewer {
    /// A viewer on `link`.
    pub fn new(link: Link, options: ViewerOptions) -> Viewer {
        Viewer {
            link,
            integrator: options.integrator.clone(),
            max_samples: options.max_samples.max(1),
            exposure: 0.0,
            neutral: false,
            options,
            scene: None,
            orbit: None,
            hello: None,
            texture: None,
            stats: None,
            arrivals: VecDeque::new(),
            scale: 1.0,
            size: SizeFollower::default(),
            problem: None,
            closed: None,
            refetched_after: None,
            passes_with_frame: 0,
            first_shown: None,
            screenshot: Screenshot::NotYet,
            environment: None,
            environment_file: String::new(),
            timeline: Timeline::default(),
        }
    }

    /// The statistics of the frame on screen.
    pub fn stats(&self) -> Option<&FrameStats> {
        self.stats.as_ref()
    }

    /// The camera as the viewer has it.
    pub fn orbit(&self) -> Option<&Orbit> {
        self.orbit.as_ref()
    }

    /// Frames per second over the last two seconds of arrivals.
    pub fn frame_rate(&self) -> Option<f64> {
        let (first, last) = (self.arrivals.front()?, self.arrivals.back()?);
        let seconds = last.duration_since(*first).as_secs_f64();
        (self.arrivals.len() >= 2 && seconds > 0.0).then(|| (self.arrivals.len() - 1) as f64 / seconds)
    }

    fn send(&mut self, request: Request) {
        // The connection ends only when the viewer drops its link, or with a `Closed` event.
        let _ = self.link.requests.send(request);
    }

    /// Takes in what the connection sent.
    fn receive(&mut self, ctx: &egui::Context) {
        while let Ok(event) = self.link.events.try_recv() {
            match event {
                Event::Scene(snapshot) => {
                    // The camera is the scene's until the mouse moves it.
                    if self.orbit.is_none() {
                        self.orbit = Some(Orbit::from_camera(&snapshot.info.camera));
                    }
                    // The scene's environment light, unless the panel has it switched off.
                    if self.environment.as_ref().is_none_or(|e| e.state != Presence::Off) {
                        let before = self.environment.as_ref();
                        self.environment = snapshot.lights.iter().find(|l| l.class == "EnvironmentLight").map(|l| Environment::of(l, before));
                    }
                    if let Some(clock) = &snapshot.clock {
                        self.timeline.follow(clock, &snapshot.animations);
                    }
                    self.scene = Some(*snapshot);
                }
                Event::Clock(clock) => {
                    if let Some(scene) = &self.scene {
                        self.timeline.follow(&clock, &scene.animations);
                    }
                }
                Event::Connected(hello) => {
                    if self.integrator.is_none() {
                        self.integrator = hello.integrator.clone();
                    }
                    self.hello = Some(hello);
                    self.closed = None;
                }
                Event::Frame(frame) => {
                    match &mut self.texture {
                        Some(texture) => texture.set(frame.image, TextureOptions::LINEAR),
                        None => self.texture = Some(ctx.load_texture("frame", frame.image, TextureOptions::LINEAR)),
                    }
                    self.arrivals.push_back(frame.received);
                    while self.arrivals.front().is_some_and(|t| frame.received.duration_since(*t) > RATE_WINDOW) {
                        self.arrivals.pop_front();
                    }
                    // A frame builds the trees its rays reach: fetch the scene once after the
                    // first frame of each version while some object shows as not built, so that
                    // the panel tells which ones were.
                    let version = frame.stats.scene_version;
                    let unbuilt = self.scene.as_ref().is_some_and(|s| s.objects.iter().any(|o| !o.built));
                    if unbuilt && self.refetched_after != Some(version) {
                        self.refetched_after = Some(version);
                        self.send(Request::RefreshScene);
                    }
                    self.stats = Some(frame.stats);
                }
                Event::Problem(problem) => self.problem = Some(problem),
                Event::Closed(reason) => {
                    // Also for a terminal: the window may close on it (screenshot mode).
                    eprintln!("raystage-client: disconnected: {reason}");
                    self.closed = Some(reason);
                }
            }
        }
    }

    /// Shows the viewer in `ui` (the whole window).
    pub fn ui(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        self.receive(&ctx);
        egui::Panel::right("side").default_size(270.0).show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| self.side_panel(ui));
        });
        egui::Panel::bottom("status").show(ui, |ui| self.status_line(ui));
        egui::CentralPanel::no_frame().show(ui, |ui| self.view(ui));
        self.follow_size(&ctx);
        self.screenshot(&ctx);
    }

    /// The frame, and the mouse controls over it.
    fn view(&mut self, ui: &mut egui::Ui) {
        let rect = ui.max_rect();
        let now = ui.input(|i| i.time);
        ui.painter().rect_filled(rect, 0.0, Color32::from_gray(24));
        let response = ui.allocate_rect(rect, Sense::click_and_drag());
        if let Some(texture) = &self.texture {
            // Fit the image into the view, keeping its aspect (it differs while the stream
            // catches up with a resize).
            let size = texture.size_vec2();
            let fit = (rect.width() / size.x).min(rect.height() / size.y);
            let shown = Rect::from_center_size(rect.center(), size * fit);
            ui.painter().image(texture.id(), shown, Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)), Color32::WHITE);
            // A frame counts as shown once it has the size asked for (or the server refused it).
            let asked = self.size.sent.map(|[w, h]| [w as usize, h as usize]);
            if asked.is_none_or(|asked| asked == texture.size()) || self.problem.is_some() {
                self.passes_with_frame += 1;
                self.first_shown.get_or_insert(now);
            }
        } else {
            let text = match &self.closed {
                Some(reason) => format!("not connected: {reason}"),
                None => "waiting for the first frame…".to_string(),
            };
            ui.painter().text(rect.center(), egui::Align2::CENTER_CENTER, text, egui::FontId::proportional(16.0), Color32::GRAY);
        }

        // Wanted pixels: the view's, at the chosen scale.
        let pixels = rect.size() * ui.ctx().pixels_per_point() * self.scale;
        let wanted = [(pixels.x.round() as u32).clamp(16, 8192), (pixels.y.round() as u32).clamp(16, 8192)];
        if self.size.wanted.is_none_or(|(size, _)| size != wanted) {
            self.size.wanted = Some((wanted, now));
        }

        let Some(orbit) = &mut self.orbit else { return };
        let before = *orbit;
        let delta = response.drag_delta();
        if response.dragged_by(PointerButton::Primary) {
            orbit.orbit(delta.x, delta.y);
        } else if response.dragged_by(PointerButton::Secondary) || response.dragged_by(PointerButton::Middle) {
            orbit.pan(delta.x, delta.y, rect.height());
        }
        if response.contains_pointer() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                orbit.zoom(scroll);
            }
        }
        if *orbit != before {
            let patch = orbit.patch();
            self.send(Request::Camera(patch));
        }
    }

    /// Sends the view's size to the stream once it has held still; at once the first time.
    fn follow_size(&mut self, ctx: &egui::Context) {
        let Some((wanted, since)) = self.size.wanted else { return };
        if self.size.sent == Some(wanted) {
            return;
        }
        let waited = ctx.input(|i| i.time) - since;
        if self.size.sent.is_some() && waited < RESIZE_DEBOUNCE {
            ctx.request_repaint_after(Duration::from_secs_f64(RESIZE_DEBOUNCE - waited));
            return;
        }
        self.size.sent = Some(wanted);
        let settings = Settings { width: Some(wanted[0]), height: Some(wanted[1]), max_samples: Some(self.samples_for(wanted)), ..Settings::default() };
        self.send(Request::Settings(settings));
    }

    /// Samples per pixel to ask for at `size`: the choice, lowered to the server's frame limit.
    fn samples_for(&self, size: [u32; 2]) -> u32 {
        let pixels = u64::from(size[0]) * u64::from(size[1]);
        (MAX_FRAME_SAMPLES / pixels.max(1)).clamp(1, u64::from(self.max_samples)) as u32
    }

    fn side_panel(&mut self, ui: &mut egui::Ui) {
        ui.heading("raystage");
        match &self.scene {
            Some(scene) => {
                let info = &scene.info;
                ui.label(format!("scene {} ({})", info.id, info.origin));
                ui.label(format!("{}, {}, {}", count(info.triangles, "triangle"), count(info.instances, "instance"), count(info.lights, "light")));
            }
            None => {
                ui.label("connecting…");
            }
        }
        ui.separator();

        ui.strong("Render");
        // Until one is chosen here, the server's choice (the scene's lights decide) is shown.
        let current = self.integrator.clone().or_else(|| self.stats.as_ref().map(|s| s.integrator.clone()));
        ui.horizontal_wrapped(|ui| {
            for name in INTEGRATORS {
                let chosen = current.as_deref() == Some(name);
                if ui.selectable_label(chosen, name).clicked() && !chosen {
                    self.integrator = Some(name.to_string());
                    self.send(Request::Settings(Settings { integrator: Some(name.to_string()), ..Settings::default() }));
                }
            }
        });
        let before = (self.max_samples, self.scale);
        egui::ComboBox::from_label("samples per pixel").selected_text(self.max_samples.to_string()).show_ui(ui, |ui| {
            for n in MAX_SAMPLES {
                ui.selectable_value(&mut self.max_samples, n, n.to_string());
            }
        });
        egui::ComboBox::from_label("resolution").selected_text(scale_name(self.scale)).show_ui(ui, |ui| {
            for scale in [1.0, 0.5, 0.25] {
                ui.selectable_value(&mut self.scale, scale, scale_name(scale));
            }
        });
        // The server re-grades the image it has: these cost no new samples.
        if ui.add(egui::Slider::new(&mut self.exposure, -4.0..=4.0).step_by(0.25).text("exposure (stops)")).changed() {
            self.send(Request::Settings(Settings { exposure: Some(self.exposure), ..Settings::default() }));
        }
        if ui.checkbox(&mut self.neutral, "neutral tone map").changed() {
            let tonemap = if self.neutral { "neutral" } else { "clamp" };
            self.send(Request::Settings(Settings { tonemap: Some(tonemap.into()), ..Settings::default() }));
        }
        if (self.max_samples, self.scale) != before {
            if self.scale != before.1 {
                // The size follows at once (no resize to wait out).
                self.size.sent = None;
                self.size.wanted = None;
            } else if let Some(size) = self.size.sent {
                let max_samples = self.samples_for(size);
                self.send(Request::Settings(Settings { max_samples: Some(max_samples), ..Settings::default() }));
            }
        }
        ui.separator();

        self.lighting(ui);
        ui.separator();

        if let Some(scene) = self.scene.as_ref().filter(|s| !s.animations.is_empty()) {
            ui.strong("Timeline");
            let shown = self.stats.as_ref().and_then(|s| s.scene_time);
            let request = self.timeline.controls(ui, &scene.animations, shown);
            ui.separator();
            if let Some(request) = request {
                self.send(request);
            }
        }

        ui.strong("Statistics");
        egui::Grid::new("stats").num_columns(2).show(ui, |ui| {
            let rows: Vec<(&str, String)> = match &self.stats {
                Some(s) => vec![
                    ("frame", format!("{:.1} ms for {} spp", s.pass_seconds * 1e3, s.pass_samples)),
                    ("rate", format!("{:.1} Mrays/s", s.mrays_per_second)),
                    ("samples", format!("{} / {}{}", s.samples, self.target_samples(), if s.converged { ", converged" } else { "" })),
                    ("rays", thousands(s.rays.total)),
                    ("image", format!("{} × {}, {}", s.width, s.height, s.integrator)),
                    ("stream", self.frame_rate().map_or("–".into(), |r| format!("{r:.1} frames/s"))),
                    ("PNG", format!("{:.1} ms", s.encode_seconds * 1e3)),
                    ("version", format!("{} (frame {})", s.scene_version, s.seq)),
                ],
                None => vec![("frame", "–".into())],
            };
            for (name, value) in rows {
                ui.label(name);
                ui.label(value);
                ui.end_row();
            }
        });
        // Its own line, wrapped: a scene with every effect would widen the panel.
        if let Some(s) = &self.stats {
            let effects = if s.effects.is_empty() { "none".to_string() } else { s.effects.join(", ") };
            ui.add(egui::Label::new(format!("effects: {effects}")).wrap());
        }
        ui.separator();

        let Some(scene) = &self.scene else { return };
        egui::CollapsingHeader::new(format!("Objects ({})", scene.objects.len())).default_open(true).show(ui, |ui| {
            let row = ui.text_style_height(&egui::TextStyle::Body);
            egui::ScrollArea::vertical().id_salt("objects").max_height(160.0).show_rows(ui, row, scene.objects.len(), |ui, range| {
                for o in &scene.objects[range] {
                    let built = if o.built { "built" } else { "not built" };
                    ui.label(format!("#{} {}: {} triangles, {built}", o.id, o.kind, thousands(o.triangles as u64)));
                }
            });
        });
        egui::CollapsingHeader::new(format!("Instances ({})", scene.instances.len())).default_open(true).show(ui, |ui| {
            let row = ui.text_style_height(&egui::TextStyle::Body);
            egui::ScrollArea::vertical().id_salt("instances").max_height(200.0).show_rows(ui, row, scene.instances.len(), |ui, range| {
                for i in &scene.instances[range] {
                    let m = i.matrix;
                    ui.label(format!("#{}: object {} at ({:.2}, {:.2}, {:.2})", i.id, i.object, m[0][3], m[1][3], m[2][3]));
                }
            });
        });
        if ui.button("Refresh scene").clicked() {
            self.send(Request::RefreshScene);
        }
    }

    /// The environment light's controls: on or off, an image or uniform, its intensity and, for
    /// an image, its turn; and an image file on this machine to light the scene with. Sliders
    /// send their value when let go (or when moved by keys), not at every step of a drag.
    fn lighting(&mut self, ui: &mut egui::Ui) {
        ui.strong("Lighting");
        let mut requests = Vec::new();
        match &mut self.environment {
            None => {
                ui.label("no environment light");
                if ui.button("add a uniform environment").clicked() {
                    let uniform = Environment { state: Presence::Adding, ..Environment::uniform() };
                    requests.extend([Request::Commands(serde_json::json!([{ "add_light": uniform.spec() }])), Request::RefreshScene]);
                    self.environment = Some(uniform);
                }
            }
            Some(environment) => requests.extend(environment.controls(ui)),
        }
        // An image on this machine: uploaded, then the environment's map (or a new light's).
        ui.horizontal(|ui| {
            ui.add(egui::TextEdit::singleline(&mut self.environment_file).hint_text("HDR, PNG or JPEG file").desired_width(160.0));
            let path = self.environment_file.trim();
            if ui.add_enabled(!path.is_empty(), egui::Button::new("load")).clicked() {
                let environment = self.environment.get_or_insert_with(Environment::uniform);
                let id = match environment.state {
                    Presence::On(id) => Some(id),
                    Presence::Off | Presence::Adding => None,
                };
                environment.state = id.map_or(Presence::Adding, Presence::On);
                requests.push(Request::EnvironmentImage { path: path.into(), id, light: environment.spec() });
            }
        });
        for request in requests {
            self.send(request);
        }
    }

    /// Samples per pixel the stream refines to.
    fn target_samples(&self) -> u32 {
        self.size.sent.map_or_else(|| self.hello.as_ref().map_or(self.max_samples, |h| h.max_samples), |size| self.samples_for(size))
    }

    fn status_line(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            if let Some(reason) = &self.closed {
                ui.colored_label(Color32::LIGHT_RED, format!("disconnected: {reason}"));
            } else if self.hello.is_some() {
                ui.label("streaming");
            } else {
                ui.label("connecting…");
            }
            if let Some(problem) = &self.problem {
                ui.separator();
                ui.colored_label(Color32::YELLOW, problem);
            }
            ui.separator();
            ui.weak("left-drag orbits · right- or middle-drag pans · scroll zooms");
        });
    }

    /// With a screenshot slot: once a frame has been painted, takes a screenshot and closes
    /// the window when it is in the slot; closes it at once if the connection ended.
    fn screenshot(&mut self, ctx: &egui::Context) {
        let Some(slot) = self.options.screenshot.clone() else { return };
        if self.screenshot == Screenshot::Done {
            return;
        }
        if self.closed.is_some() && self.screenshot == Screenshot::NotYet {
            self.screenshot = Screenshot::Done;
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        } else if self.screenshot == Screenshot::NotYet && self.passes_with_frame >= 2 {
            let waited = ctx.input(|i| i.time) - self.first_shown.unwrap_or_default();
            if waited < self.options.screenshot_delay {
                ctx.request_repaint_after(Duration::from_secs_f64(self.options.screenshot_delay - waited));
                return;
            }
            // Two passes with the frame: the first one's paint is on screen by the second.
            let waker = ctx.clone();
            ctx.request_screenshot(move |image| {
                *slot.lock().unwrap_or_else(|e| e.into_inner()) = Some(image);
                waker.request_repaint();
            });
            self.screenshot = Screenshot::Requested;
        } else if self.screenshot == Screenshot::Requested && slot.lock().unwrap_or_else(|e| e.into_inner()).is_some() {
            self.screenshot = Screenshot::Done;
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }
}

impl eframe::App for Viewer {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        Viewer::ui(self, ui);
    }
}

fn scale_name(scale: f32) -> &'static str {
    if scale >= 1.0 {
        "full"
    } else if scale >= 0.5 {
        "1/2"
    } else {
        "1/4"
    }
}

/// `3 lights`, `1 light`.
fn count(n: usize, what: &str) -> String {
    format!("{} {what}{}", thousands(n as u64), if n == 1 { "" } else { "s" })
}

/// `1234567` as `1,234,567`.
fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn thousands_are_grouped() {
        assert_eq!(super::thousands(1_000_002), "1,000,002");
        assert_eq!(super::thousands(999), "999");
    }
}
