//! The viewer page (`GET /`, `crates/server/web`) in real browsers: headless Chromium (Debian's
//! `chromium`) over the DevTools protocol and headless Firefox (Debian's `firefox-esr`) over
//! WebDriver BiDi, each through a WebSocket, against a server on a loopback port. The page must
//! load without console errors, show frames whose pixels are the PNG route's for the same
//! camera, move the scene's camera as the egui viewer does, pick, open a dropped glTF file, and
//! ask for a token where the server needs one. Each scenario runs once in each browser (tests
//! `<scenario>::chromium` and `<scenario>::firefox`); the protocols are behind `Page`.
//!
//! Without a browser these tests say so and pass, unless they run as root: `scripts/test.sh`
//! installs both as root, so there a missing browser is a failure. Screenshots go to
//! `$CARGO_TARGET_TMPDIR/browser/<browser>-<name>.png`.

mod common;

#[path = "browser/bidi.rs"]
mod bidi;
#[path = "browser/cdp.rs"]
mod cdp;
#[path = "browser/connection.rs"]
mod connection;

use std::os::unix::fs::MetadataExt;
use std::path::PathBuf;
use std::process::Child;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use axum::body::Body;
use axum::http::StatusCode;
use base64::Engine;
use common::*;
use connection::Connection;
use raystage_server::{AppState, Config};
use serde_json::{Value, json};

/// How long the page has for anything it is waited for: generous, as the machine that runs the
/// tests may be busy compiling beside them.
const PATIENCE: Duration = Duration::from_secs(90);

/// The browsers the page is tested in.
#[derive(Clone, Copy)]
enum Kind {
    Chromium,
    Firefox,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Chromium => "chromium",
            Kind::Firefox => "firefox",
        }
    }

    /// The commands that start it, as Debian and others name them.
    fn executables(self) -> &'static [&'static str] {
        match self {
            Kind::Chromium => &["chromium"],
            Kind::Firefox => &["firefox-esr", "firefox"],
        }
    }

    /// The Debian package that has it, which `scripts/test.sh` installs.
    fn package(self) -> &'static str {
        match self {
            Kind::Chromium => "chromium",
            Kind::Firefox => "firefox-esr",
        }
    }
}

/// A headless browser and the WebSocket that drives it; the process ends when this is dropped.
struct Browser {
    kind: Kind,
    process: Child,
    profile: PathBuf,
    connection: Arc<Connection>,
}

impl Browser {
    /// Starts the browser, or says why not and gives `None` where the test may be skipped.
    async fn start(kind: Kind) -> Option<Browser> {
        let path = std::env::var_os("PATH").unwrap_or_default();
        let Some(executable) = std::env::split_paths(&path).flat_map(|dir| kind.executables().iter().map(move |name| dir.join(name))).find(|p| p.is_file()) else {
            let (name, package) = (kind.name(), kind.package());
            let root = std::fs::metadata("/proc/self").is_ok_and(|m| m.uid() == 0);
            assert!(!root, "{name} is not installed: as root, scripts/test.sh installs it (apt-get install {package})");
            eprintln!("skipped: {name} is not installed (scripts/test.sh installs it when run as root)");
            return None;
        };
        static PROFILES: AtomicU64 = AtomicU64::new(0);
        let profile = std::env::temp_dir().join(format!("raystage-{}-{}-{}", kind.name(), std::process::id(), PROFILES.fetch_add(1, Ordering::Relaxed)));
        std::fs::create_dir_all(&profile).unwrap();
        let (process, connection) = match kind {
            Kind::Chromium => cdp::start(&executable, &profile).await,
            Kind::Firefox => bidi::start(&executable, &profile).await,
        };
        Some(Browser { kind, process, profile, connection })
    }

    /// A new tab with a viewport of `width` × `height` CSS pixels and `scale` device pixels to
    /// each, showing `url`.
    async fn open(&self, url: &str, width: u32, height: u32, scale: f64) -> Page {
        let tab = match self.kind {
            Kind::Chromium => Tab::Cdp(cdp::Tab::open(&self.connection, width, height, scale).await),
            Kind::Firefox => Tab::Bidi(bidi::Tab::open(&self.connection, width, height, scale).await),
        };
        let page = Page { browser: self.kind, tab };
        page.navigate(url).await;
        page
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.process.kill();
        let _ = self.process.wait();
        let _ = std::fs::remove_dir_all(&self.profile);
    }
}

/// A mouse button.
#[derive(Clone, Copy)]
enum Button {
    Left,
    Right,
}

impl Button {
    /// The button as a bit of `MouseEvent.buttons`.
    fn mask(self) -> u8 {
        match self {
            Button::Left => 1,
            Button::Right => 2,
        }
    }
}

/// What the mouse does: each moves it to a point, `Press` and `Release` then press or release a
/// button, and `Move` keeps the pressed button down.
#[derive(Clone, Copy)]
enum Pointer {
    Press,
    Move,
    Release,
}

/// A tab of either browser, through its protocol. Each protocol's module has the same methods.
enum Tab {
    Cdp(cdp::Tab),
    Bidi(bidi::Tab),
}

/// Runs `$body` with `$tab` naming the page's tab, whichever protocol drives it.
macro_rules! on_tab {
    ($page:expr, $tab:ident => $body:expr) => {
        match &$page.tab {
            Tab::Cdp($tab) => $body,
            Tab::Bidi($tab) => $body,
        }
    };
}

/// The page in a tab: what the scenarios do with it, the same in either browser.
struct Page {
    browser: Kind,
    tab: Tab,
}

impl Page {
    /// Loads `url`, and waits until it has loaded.
    async fn navigate(&self, url: &str) {
        on_tab!(self, tab => tab.navigate(url).await);
        self.wait_for("the page to load", &format!("document.readyState === 'complete' && location.href === '{url}'")).await;
    }

    /// The value of a JavaScript expression in the page (awaited if it is a promise), as JSON.
    async fn eval(&self, expression: &str) -> Value {
        on_tab!(self, tab => tab.eval(expression).await)
    }

    /// Waits until `expression` is truthy; its value.
    async fn wait_for(&self, what: &str, expression: &str) -> Value {
        let start = Instant::now();
        loop {
            let value = self.eval(expression).await;
            if !(value.is_null() || value == false || value == "" || value == 0) {
                return value;
            }
            assert!(start.elapsed() < PATIENCE, "waited {PATIENCE:?} for {what} ({expression}); the page says: {}", self.eval("document.getElementById('message').textContent").await);
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    }

    /// What the page reported as errors: console errors, uncaught exceptions, and the loads
    /// that failed (refusals by the Content-Security-Policy too, in Chromium).
    fn errors(&self) -> Vec<String> {
        on_tab!(self, tab => tab.errors())
    }

    /// Saves a screenshot of the tab as `$CARGO_TARGET_TMPDIR/browser/<browser>-<name>.png`.
    async fn screenshot(&self, name: &str) -> PathBuf {
        let png = on_tab!(self, tab => tab.screenshot().await);
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("browser");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(format!("{}-{name}.png", self.browser.name()));
        std::fs::write(&path, png).unwrap();
        eprintln!("screenshot: {}", path.display());
        path
    }

    /// Gives the tab a viewport of `width` × `height` CSS pixels and `scale` device pixels to
    /// each, as a window resized.
    async fn set_viewport(&self, width: u32, height: u32, scale: f64) {
        on_tab!(self, tab => tab.set_viewport(width, height, scale).await)
    }

    /// The pixels of the canvas with id `id`, as the page has them.
    async fn canvas(&self, id: &str) -> image::RgbImage {
        let url = self.eval(&format!("document.getElementById('{id}').toDataURL('image/png')")).await;
        let data = url.as_str().unwrap().strip_prefix("data:image/png;base64,").expect("a PNG data URL");
        image::load_from_memory(&base64::engine::general_purpose::STANDARD.decode(data).unwrap()).unwrap().to_rgb8()
    }

    async fn pointer(&self, action: Pointer, at: (f64, f64), button: Button) {
        on_tab!(self, tab => tab.pointer(action, at, button).await)
    }

    /// A drag with `button` from `from` through `steps` steps of (dx, dy) CSS pixels.
    async fn drag(&self, button: Button, from: (f64, f64), step: (f64, f64), steps: u32) {
        self.pointer(Pointer::Press, from, button).await;
        let mut at = from;
        for _ in 0..steps {
            at = (at.0 + step.0, at.1 + step.1);
            self.pointer(Pointer::Move, at, button).await;
        }
        self.pointer(Pointer::Release, at, button).await;
    }

    async fn click(&self, at: (f64, f64)) {
        self.pointer(Pointer::Press, at, Button::Left).await;
        self.pointer(Pointer::Release, at, Button::Left).await;
    }

    /// Drops the file at `path` on the page at `at`.
    async fn drop_file(&self, at: (f64, f64), path: &std::path::Path) {
        on_tab!(self, tab => tab.drop_file(at, path).await)
    }

    /// Types `text` into the focused element.
    async fn type_text(&self, text: &str) {
        on_tab!(self, tab => tab.type_text(text).await)
    }

    /// Sets a control of the page as a person would, and tells the page it changed.
    async fn choose(&self, id: &str, value: &str) {
        self.eval(&format!("(e => {{ e.value = '{value}'; e.dispatchEvent(new Event('change')); }})(document.getElementById('{id}'))")).await;
    }

    /// The canvas's box in the viewport: left, top, width, height (CSS pixels).
    async fn frame_box(&self) -> [f64; 4] {
        let rect = self.eval("(r => [r.left, r.top, r.width, r.height])(document.getElementById('frame').getBoundingClientRect())").await;
        serde_json::from_value(rect).unwrap()
    }
}

/// Runs `scenario(kind)` as a test in each browser: `scenario::chromium` and `scenario::firefox`.
macro_rules! in_each_browser {
    ($scenario:ident) => {
        mod $scenario {
            #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
            async fn chromium() {
                super::$scenario(super::Kind::Chromium).await
            }

            #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
            async fn firefox() {
                super::$scenario(super::Kind::Firefox).await
            }
        }
    };
}

in_each_browser!(the_page_streams_orbits_picks_and_opens_a_dropped_gltf_file);
in_each_browser!(a_drag_shows_in_a_frame_and_the_page_measures_how_soon);
in_each_browser!(with_a_token_the_page_asks_for_it_and_without_it_says_why_nothing_loads);

/// A scene of two `Constant` squares side by side in front of the default camera (eye at
/// (0, 0, 5), 45° high): red on the left at x = −1, green on the right at x = +1. Its id and
/// the two instances' ids.
async fn two_squares(app: &axum::Router) -> (u64, u64, u64) {
    let s = new_scene(app).await;
    let mut red = square(0.5);
    red["shader"] = json!("red");
    let mut green = square(0.5);
    green["shader"] = json!("green");
    let batch = json!({ "commands": [
        { "add_shader": { "label": "red", "class": "Constant", "params": { "color": [1, 0, 0] } } },
        { "add_shader": { "label": "green", "class": "Constant", "params": { "color": [0, 1, 0] } } },
        { "add_object": { "label": "left", "mesh": red } },
        { "add_object": { "label": "right", "mesh": green } },
        { "add_instance": { "object": "left", "transform": { "translate": [-1, 0, 0] } } },
        { "add_instance": { "object": "right", "transform": { "translate": [1, 0, 0] } } }
    ] });
    let result = ok(app, "POST", &format!("/scenes/{s}/commands"), batch, StatusCode::OK).await;
    (s, result["results"][4]["id"].as_u64().unwrap(), result["results"][5]["id"].as_u64().unwrap())
}

/// Waits until the camera of scene `s`, read over HTTP, has `eye` and `target` (to 10⁻³).
async fn camera_becomes(app: &axum::Router, s: u64, eye: [f32; 3], target: [f32; 3]) {
    let start = Instant::now();
    loop {
        let camera = ok(app, "GET", &format!("/scenes/{s}/camera"), json!(null), StatusCode::OK).await;
        let close = |field: &str, expected: [f32; 3]| {
            let got: [f32; 3] = serde_json::from_value(camera[field].clone()).unwrap();
            got.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-3)
        };
        if close("eye", eye) && close("target", target) {
            return;
        }
        assert!(start.elapsed() < PATIENCE, "the camera did not become eye {eye:?}, target {target:?}: {camera}");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// Mean and largest difference per channel between two images of the same size, in levels.
fn difference(a: &image::RgbImage, b: &image::RgbImage) -> (f64, u8) {
    assert_eq!(a.dimensions(), b.dimensions());
    let (sum, max) = a.as_raw().iter().zip(b.as_raw()).fold((0u64, 0u8), |(sum, max), (&x, &y)| (sum + x.abs_diff(y) as u64, max.max(x.abs_diff(y))));
    (sum as f64 / a.as_raw().len() as f64, max)
}

/// Waits for the page to show the converged frame of the scene's current version at one sample
/// per pixel in `encoding`, and returns its difference from the PNG route's frame of the same
/// size, camera and samples. (One sample: a stream's image of more is the same samples summed
/// over several passes, which differs from one frame's sum in the last bit, and so by a level
/// here and there.)
async fn against_the_png_route(page: &Page, app: &axum::Router, s: u64, encoding: &str) -> (f64, u8) {
    let version = ok(app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await["version"].as_u64().unwrap();
    let shown = format!(
        "document.getElementById('frame').dataset.sceneVersion === '{version}' \
         && document.getElementById('stat-samples').textContent === '1 of 1 per pixel, converged' \
         && document.getElementById('stat-encoding').textContent.startsWith('{}')",
        encoding.to_uppercase()
    );
    page.wait_for(&format!("the converged {encoding} frame of version {version}"), &shown).await;
    let shown = page.canvas("frame").await;
    let (width, height) = shown.dimensions();
    let (status, _, png) = send(app, "GET", &format!("/scenes/{s}/frame.png?width={width}&height={height}&spp=1"), Body::empty(), &[]).await;
    assert_eq!(status, StatusCode::OK);
    difference(&shown, &image::load_from_memory(&png).unwrap().to_rgb8())
}

async fn the_page_streams_orbits_picks_and_opens_a_dropped_gltf_file(kind: Kind) {
    let Some(browser) = Browser::start(kind).await else { return };
    let state = AppState::new(Config::default());
    let app = raystage_server::router(state.clone());
    let (s, left, right) = two_squares(&app).await;
    let addr = listen(state).await;
    // Two device pixels to each CSS pixel, as on a laptop's screen.
    let page = browser.open(&format!("http://{addr}/#scene={s}"), 900, 600, 2.0).await;

    // The first frame is sized to the view and the device pixel ratio.
    page.wait_for("a first frame", "document.getElementById('frame').dataset.seq").await;
    for hidden in ["auth", "drop-hint"] {
        assert_eq!(page.eval(&format!("getComputedStyle(document.getElementById('{hidden}')).display")).await, "none", "#{hidden} shows");
    }
    let sizes = page.eval("(v => [v.clientWidth, v.clientHeight])(document.getElementById('view'))").await;
    let (css_width, css_height) = (sizes[0].as_u64().unwrap(), sizes[1].as_u64().unwrap());
    page.wait_for("a frame of the view's device pixels", &format!("(c => c.width === {} && c.height === {})(document.getElementById('frame'))", 2 * css_width, 2 * css_height))
        .await;

    // Pixels as the PNG route renders them: lossless PNG exactly (the page draws the image it
    // is sent, one pixel to one pixel), the default JPEG within a few levels on average and
    // less than half the range anywhere (ringing at the squares' hard edges).
    page.choose("max-samples", "1").await;
    let (mean, max) = against_the_png_route(&page, &app, s, "jpeg").await;
    eprintln!("JPEG frame against the PNG route: mean {mean:.3} levels, largest {max}");
    assert!(mean < 1.5 && max < 128, "the JPEG frame is not the PNG route's: mean {mean}, largest {max}");
    page.choose("encoding", "png").await;
    let (mean, max) = against_the_png_route(&page, &app, s, "png").await;
    eprintln!("PNG frame against the PNG route: mean {mean:.3} levels, largest {max}");
    assert!(mean == 0.0 && max == 0, "the PNG frame is not the PNG route's: mean {mean}, largest {max}");
    page.screenshot("streamed").await;

    // A click on the red square's centre picks its instance and outlines it.
    let [x, y, width, height] = page.frame_box().await;
    let half_width_at_target = 5.0 * (22.5f64).to_radians().tan() * width / height;
    let centre_of = |world_x: f64| (x + width * (0.5 + world_x / half_width_at_target / 2.0), y + height / 2.0);
    page.click(centre_of(-1.0)).await;
    page.wait_for("the red square picked", &format!("document.getElementById('picked').dataset.instance === '{left}'")).await;
    let text = page.eval("document.getElementById('picked').textContent").await;
    assert!(text.as_str().unwrap().starts_with(&format!("instance {left} of object ")), "{text}");
    page.wait_for("the highlight", &format!("document.getElementById('highlight').dataset.instance === '{left}'")).await;
    let highlight = |(cx, cy): (f64, f64)| {
        format!("document.getElementById('highlight').getContext('2d').getImageData({}, {}, 1, 1).data[3]", ((cx - x) * 2.0) as u32, ((cy - y) * 2.0) as u32)
    };
    assert!(page.eval(&highlight(centre_of(-1.0))).await.as_u64().unwrap() > 0, "the picked square is highlighted");
    assert_eq!(page.eval(&highlight(centre_of(1.0))).await, 0, "the other square is not");
    assert_eq!(page.eval(&format!("document.querySelector('#instances tr.selected').dataset.id === '{left}'")).await, true);
    page.screenshot("picked").await;
    page.click(centre_of(1.0)).await;
    page.wait_for("the green square picked", &format!("document.getElementById('picked').dataset.instance === '{right}'")).await;

    // The mouse moves the camera as the egui viewer does (crates/client/src/orbit.rs: 0.01
    // radian of orbit a point, a distance factor of e^(−0.002) a point of scroll), read back
    // over HTTP. A drag 100 points to the right in ten steps turns the eye one radian about the
    // target; one 50 points down raises it half a radian; a wheel turned 100 points away from
    // the user brings it e^(−0.2) of the way.
    let centre = (x + width / 2.0, y + height / 2.0);
    let before = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await["version"].as_u64().unwrap();
    page.drag(Button::Left, centre, (10.0, 0.0), 10).await;
    let (sin, cos) = (1f32.sin(), 1f32.cos());
    camera_becomes(&app, s, [-5.0 * sin, 0.0, 5.0 * cos], [0.0; 3]).await;
    page.drag(Button::Left, centre, (0.0, 10.0), 5).await;
    let raised = [-5.0 * sin * 0.5f32.cos(), 5.0 * 0.5f32.sin(), 5.0 * cos * 0.5f32.cos()];
    camera_becomes(&app, s, raised, [0.0; 3]).await;
    // (A wheel event of the page's own: DevTools scales the delta of the wheel events it makes
    // by the emulated device pixel ratio.)
    page.eval("document.getElementById('frame').dispatchEvent(new WheelEvent('wheel', { deltaY: -100, deltaMode: 0, cancelable: true }))").await;
    let closer = raised.map(|c| c * (-0.2f32).exp());
    camera_becomes(&app, s, closer, [0.0; 3]).await;
    // A right-drag pans: eye and target move together, sideways (the camera's up is +y, and
    // the drag is horizontal), by the view's height at the target's depth per view height.
    page.drag(Button::Right, centre, (-10.0, 0.0), 5).await;
    let view_height = page.eval("document.getElementById('view').clientHeight").await.as_f64().unwrap() as f32;
    let shift = 50.0 * 2.0 * (5.0 * (-0.2f32).exp()) * 22.5f32.to_radians().tan() / view_height;
    let start = Instant::now();
    let (eye, target) = loop {
        let camera = ok(&app, "GET", &format!("/scenes/{s}/camera"), json!(null), StatusCode::OK).await;
        let (eye, target): ([f32; 3], [f32; 3]) = (serde_json::from_value(camera["eye"].clone()).unwrap(), serde_json::from_value(camera["target"].clone()).unwrap());
        // The drag's moves reach the server one by one: wait for the last, not the first.
        let moved = target.iter().map(|c| c * c).sum::<f32>().sqrt();
        if (moved - shift).abs() < 1e-3 && (0..3).all(|k| (eye[k] - closer[k] - target[k]).abs() < 1e-3) {
            break (eye, target);
        }
        assert!(start.elapsed() < PATIENCE, "the right-drag did not pan {shift} sideways: {camera}");
        tokio::time::sleep(Duration::from_millis(50)).await;
    };
    let forward = [-closer[0], -closer[1], -closer[2]];
    assert!((target.iter().map(|c| c * c).sum::<f32>().sqrt() - shift).abs() < 1e-3 && target[1].abs() < 1e-5, "{target:?} is not {shift} sideways");
    assert!(target.iter().zip(forward).map(|(a, b)| a * b).sum::<f32>().abs() < 1e-4, "{target:?} is not across the view, {eye:?}");
    // The next frames show the new camera: the PNG route's frame of it.
    let after = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await["version"].as_u64().unwrap();
    assert!(after > before);
    let (mean, max) = against_the_png_route(&page, &app, s, "png").await;
    assert!(mean == 0.0 && max == 0, "the frame after the drag is not the PNG route's: mean {mean}, largest {max}");
    page.screenshot("orbited").await;

    // A glTF file dropped on the page becomes a new scene, which the page opens; it has an
    // animation, so the page shows a timeline.
    let file = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("dropped-{}.glb", std::process::id()));
    std::fs::write(&file, animated_glb()).unwrap();
    page.drop_file(centre, &file).await;
    let created = page.wait_for("the dropped file's scene", "document.getElementById('upload-status').dataset.scene").await;
    let created: u64 = created.as_str().unwrap().parse().unwrap();
    let info = ok(&app, "GET", &format!("/scenes/{created}"), json!(null), StatusCode::OK).await;
    assert_eq!((info["origin"].as_str(), info["objects"].as_u64(), info["instances"].as_u64()), (Some("gltf"), Some(1), Some(2)));
    page.wait_for("the new scene's frames", &format!("location.hash === '#scene={created}' && document.getElementById('frame').dataset.seq")).await;
    page.wait_for("the new scene listed", &format!("document.getElementById('scene').value === '{created}'")).await;
    std::fs::remove_file(&file).unwrap();
    page.screenshot("dropped").await;

    // The timeline poses the scene: the time slider at 0.5 s of `slide` (which moves the left
    // square, instance 0 of the file, from x = −0.6 at 0 s to 0.4 at 1 s) is a `set_time`.
    assert_eq!(page.eval("document.getElementById('timeline').hidden").await, false);
    page.eval("(t => { t.value = '0.5'; t.dispatchEvent(new Event('input')); })(document.getElementById('time'))").await;
    let start = Instant::now();
    loop {
        let instances = ok(&app, "GET", &format!("/scenes/{created}/instances"), json!(null), StatusCode::OK).await;
        if (instances[0]["matrix"][0][3].as_f64().unwrap() + 0.1).abs() < 1e-5 {
            break;
        }
        assert!(start.elapsed() < PATIENCE, "the timeline did not pose the scene at 0.5 s: {instances}");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let posed = ok(&app, "GET", &format!("/scenes/{created}"), json!(null), StatusCode::OK).await["version"].as_u64().unwrap();
    page.wait_for("a frame of the pose", &format!("Number(document.getElementById('frame').dataset.sceneVersion) >= {posed}")).await;
    page.screenshot("timeline").await;
    assert_eq!(page.errors(), Vec::<String>::new(), "the page reported errors");

    // Settings past the server's limits are refused with its reason, on an open stream and on
    // one that opens anew (where the browser does not show why: the page asks), and a setting
    // within them opens the stream again.
    page.choose("max-samples", "1024").await;
    page.wait_for("the refusal of 1024 samples", "document.getElementById('message').textContent.includes('more than the limit')").await;
    page.choose("integrator", "").await;
    page.wait_for("the refusal to open", "document.getElementById('message').textContent.startsWith('The stream closed: ') && document.getElementById('message').textContent.includes('more than the limit')").await;
    page.screenshot("refused").await;
    page.choose("max-samples", "1").await;
    page.wait_for("frames again", "document.getElementById('stat-samples').textContent === '1 of 1 per pixel, converged' && document.getElementById('message').textContent === ''").await;
    // The only errors are the browser's notes of the refused stream (its 422, and that it
    // could not connect), each naming its URL.
    let errors = page.errors();
    assert!(!errors.is_empty() && errors.iter().all(|e| e.contains("/stream?") && e.contains("max_samples=1024")), "{errors:?}");
}

/// The latency from a drag to the first frame that shows it, as the page measures it
/// (`performance.now()`, from the drag's first input event to the drawing of the first frame of
/// the scene version the camera change made), and the frame rate as the page receives frames,
/// on the sphere grid (a million triangles): first as the egui viewer's frame rate was measured
/// (docs/performance.md: a 640×360 view, eye light, refining to 1024 samples), then with the
/// page's defaults in a 1280×720 window (the scene's integrator, Whitted as the default sky
/// lights it; 256 samples); each in JPEG at quality 80 and in PNG. Printed; every drag must show.
async fn a_drag_shows_in_a_frame_and_the_page_measures_how_soon(kind: Kind) {
    let Some(browser) = Browser::start(kind).await else { return };
    let state = AppState::new(Config::default());
    let app = raystage_server::router(state.clone());
    let s = ok(&app, "POST", "/scenes", json!({ "demo": "spheres" }), StatusCode::CREATED).await["id"].as_u64().unwrap();
    let addr = listen(state).await;
    let page = browser.open(&format!("http://{addr}/#scene={s}"), 1280, 720, 1.0).await;
    page.wait_for("a first frame", "document.getElementById('frame').dataset.seq").await;
    let drags = 12;
    for (setting, egui_like) in [("640×360 view, eye light, 1024 samples", true), ("1280×720 window, the page's defaults", false)] {
        // The samples change where the image's size keeps them within the server's limit on
        // samples per frame: after the view shrinks, before it grows.
        if !egui_like {
            page.choose("max-samples", "256").await;
        }
        let view = page.eval("(v => [v.clientWidth, v.clientHeight])(document.getElementById('view'))").await;
        let (view_width, view_height) = (view[0].as_i64().unwrap(), view[1].as_i64().unwrap());
        let (window_width, window_height) = if egui_like { (1280 + 640 - view_width, 720 + 360 - view_height) } else { (1280, 720) };
        page.set_viewport(window_width as u32, window_height as u32, 1.0).await;
        let [x, y, width, height] = page.frame_box().await;
        let centre = (x + width / 2.0, y + height / 2.0);
        let view = page.eval("(v => [v.clientWidth, v.clientHeight])(document.getElementById('view'))").await;
        let (width, height) = (view[0].as_i64().unwrap(), view[1].as_i64().unwrap());
        page.wait_for("the stream in the view's size", &format!("document.getElementById('frame').width === {width}")).await;
        if egui_like {
            page.choose("max-samples", "1024").await;
        }
        page.choose("integrator", if egui_like { "eyelight" } else { "" }).await;
        for encoding in ["jpeg", "png"] {
            page.choose("encoding", encoding).await;
            let integrator = if egui_like { "eyelight" } else { "whitted" };
            page.wait_for("the stream's settings", &format!("document.getElementById('stat-image').textContent === '{width}×{height}, {integrator}' && document.getElementById('stat-encoding').textContent.startsWith('{}')", encoding.to_uppercase())).await;
            // Frames a second, as the page receives them, while the image refines.
            let seq = async || page.eval("Number(document.getElementById('frame').dataset.seq)").await.as_f64().unwrap();
            let (first, start) = (seq().await, Instant::now());
            tokio::time::sleep(Duration::from_secs(4)).await;
            let rate = (seq().await - first) / start.elapsed().as_secs_f64();
            let count = async || page.eval("Number(document.getElementById('stat-latency').dataset.count ?? 0)").await.as_u64().unwrap();
            let before = count().await;
            for k in 0..drags {
                // Back and forth, so that the view stays on the spheres.
                let measured = count().await;
                page.drag(Button::Left, centre, (if k % 2 == 0 { 5.0 } else { -5.0 }, 0.0), 6).await;
                page.wait_for("a frame showing the drag", &format!("Number(document.getElementById('stat-latency').dataset.count) > {measured}")).await;
                // Every camera change of the drag shown (a drag may send several, and the page
                // measures one at a time), and a pause, as a person's, while the image refines.
                let version = ok(&app, "GET", &format!("/scenes/{s}"), json!(null), StatusCode::OK).await["version"].as_u64().unwrap();
                page.wait_for("the drag's last frame", &format!("Number(document.getElementById('frame').dataset.sceneVersion) >= {version}")).await;
                tokio::time::sleep(Duration::from_millis(300)).await;
            }
            let new = (count().await - before) as usize;
            let all: Vec<f64> = serde_json::from_str(page.eval("document.getElementById('stat-latency').dataset.samples").await.as_str().unwrap()).unwrap();
            assert!(new <= all.len(), "{new} measurements, {} kept", all.len());
            let mut latencies = all[all.len() - new..].to_vec();
            latencies.sort_by(f64::total_cmp);
            let stats = page.eval("['stat-image', 'stat-pass', 'stat-encoding', 'stat-rate'].map(id => document.getElementById(id).textContent).join('; ')").await;
            eprintln!(
                "{setting}, {encoding}: {rate:.1} frames/s refining; drag to frame over {drags} drags ({new} measured): median {:.0} ms, fastest {:.0} ms, slowest {:.0} ms (last frame: {})",
                latencies[new / 2],
                latencies[0],
                latencies[new - 1],
                stats.as_str().unwrap()
            );
        }
    }
    page.screenshot("spheres").await;
    assert_eq!(page.errors(), Vec::<String>::new(), "the page reported errors");
}

async fn with_a_token_the_page_asks_for_it_and_without_it_says_why_nothing_loads(kind: Kind) {
    let Some(browser) = Browser::start(kind).await else { return };
    let state = AppState::new(Config { token: Some("s3cret".into()), ..Config::default() });
    let app = raystage_server::router(state.clone());
    let (status, _, body) = send(&app, "POST", "/scenes", Body::from("{}"), &[("authorization", "Bearer s3cret")]).await;
    assert_eq!(status, StatusCode::CREATED);
    let s = serde_json::from_slice::<Value>(&body).unwrap()["id"].as_u64().unwrap();
    let addr = listen(state).await;
    let page = browser.open(&format!("http://{addr}/"), 800, 500, 1.0).await;

    // Without the token: the form, and a message saying why nothing loads.
    page.wait_for("the token form", "!document.getElementById('auth').hidden").await;
    let message = page.eval("document.getElementById('message').textContent").await;
    assert_eq!(message, "This server needs an access token. Nothing loads without it.");
    page.screenshot("token-asked").await;
    // The only errors are the browser's notes of the refused requests.
    let errors = page.errors();
    assert!(!errors.is_empty() && errors.iter().all(|e| e.contains("401")), "{errors:?}");

    // A wrong token is refused, and said so.
    page.type_text("wrong").await;
    page.eval("document.getElementById('auth').requestSubmit()").await;
    page.wait_for("the refusal", "document.getElementById('message').textContent.startsWith('The server refused this token')").await;

    // The right one: the page lists the scene and streams it (the stream takes the token as
    // `?token=`), and the tab keeps it.
    page.eval("document.getElementById('token').value = ''").await;
    page.type_text("s3cret").await;
    page.eval("document.getElementById('auth').requestSubmit()").await;
    page.wait_for("a frame", "document.getElementById('frame').dataset.seq").await;
    assert_eq!(page.eval("document.getElementById('auth').hidden").await, true);
    assert_eq!(page.eval("document.getElementById('scene').value").await, s.to_string());
    assert_eq!(page.eval("sessionStorage.getItem('raystage.token')").await, "s3cret");
    page.screenshot("token-given").await;
    let errors = page.errors();
    assert!(errors.iter().all(|e| e.contains("401")), "{errors:?}");
}
