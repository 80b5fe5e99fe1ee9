//! The connection to a server, off the UI thread: a thread with a single-threaded tokio runtime
//! reads the WebSocket stream and fetches the scene over HTTP; a second thread decodes the
//! frames' PNGs. The viewer sees only two channels ([`Link`]): [`Event`]s in, [`Request`]s
//! out. It never waits on either.
//!
//! Flow control follows the server's (`api/stream.md`): the decoder holds one frame, the newest,
//! so a frame the UI has not had time for is replaced, never queued. Camera changes are sent one
//! at a time: while one waits for its reply, newer ones replace each other, so a fast drag sends
//! as many edits as the server can apply, the latest position always last.

use std::sync::mpsc;
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

use eframe::egui::ColorImage;
use futures_util::{SinkExt, StreamExt};
use tokio::sync::mpsc::{UnboundedReceiver, UnboundedSender, unbounded_channel};
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::tungstenite::client::IntoClientRequest;
use tokio_tungstenite::tungstenite::http::HeaderValue;

use crate::Error;
use crate::http::Server;
use crate::protocol::{AnimationInfo, CameraPatch, Clock, FrameStats, Hello, InstanceInfo, LightInfo, ObjectInfo, PROTOCOL, Request, SceneInfo, ServerMessage, Settings};

/// A camera change whose reply has not come in this long is taken as lost.
const CAMERA_REPLY_TIMEOUT: Duration = Duration::from_secs(2);
/// How long a stream opened without a size waits for the viewer's.
const FIRST_SIZE_WAIT: Duration = Duration::from_millis(500);

/// What the connection tells the viewer.
#[derive(Debug)]
pub enum Event {
    /// The scene's summary, objects, instances, lights and animations (over HTTP, at the start and on request).
    Scene(Box<SceneSnapshot>),
    /// The stream is open, with these settings.
    Connected(Hello),
    /// A frame, decoded.
    Frame(Frame),
    /// The scene's clock, as a change left it.
    Clock(Clock),
    /// The server refused a request (the stream goes on), or a fetch failed.
    Problem(String),
    /// The connection ended, for this reason.
    Closed(String),
}

/// The scene as the side panel shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSnapshot {
    /// The summary: origin, counts, camera.
    pub info: SceneInfo,
    /// Every object.
    pub objects: Vec<ObjectInfo>,
    /// Every instance.
    pub instances: Vec<InstanceInfo>,
    /// Every light.
    pub lights: Vec<LightInfo>,
    /// Every animation (none for most scenes: they come with glTF files).
    pub animations: Vec<AnimationInfo>,
    /// The clock that plays them, once the scene was posed.
    pub clock: Option<Clock>,
}

/// A frame: its statistics and its pixels.
#[derive(Debug)]
pub struct Frame {
    /// The statistics (the `frame` message).
    pub stats: FrameStats,
    /// The image, decoded from the PNG.
    pub image: ColorImage,
    /// When its PNG arrived.
    pub received: Instant,
}

/// The viewer's end of a connection.
pub struct Link {
    /// What the connection tells the viewer.
    pub events: mpsc::Receiver<Event>,
    /// What the viewer asks of it.
    pub requests: UnboundedSender<Request>,
}

/// The far end of a [`Link`], where the connection (or a test standing in for one) sits.
pub struct Remote {
    /// Events for the viewer.
    pub events: mpsc::Sender<Event>,
    /// The viewer's requests.
    pub requests: UnboundedReceiver<Request>,
}

impl Link {
    /// A link and its far end, unconnected: the connection's thread takes the far end, or a
    /// test plays the server with it.
    pub fn pair() -> (Link, Remote) {
        let (event_tx, event_rx) = mpsc::channel();
        let (request_tx, request_rx) = unbounded_channel();
        (Link { events: event_rx, requests: request_tx }, Remote { events: event_tx, requests: request_rx })
    }
}

/// What to connect to.
#[derive(Clone, Debug, PartialEq)]
pub struct StreamConfig {
    /// The server.
    pub server: Server,
    /// The scene, or `None` for the first the server lists.
    pub scene: Option<u32>,
    /// The stream's first settings (requests sent before it opens are merged in).
    pub settings: Settings,
}

/// Connects to a server in a background thread. `wake` is called after every event (the UI
/// asks for a repaint there). The connection ends when the [`Link`] is dropped.
pub fn connect(config: StreamConfig, wake: impl Fn() + Send + Sync + 'static) -> Link {
    let (link, remote) = Link::pair();
    let events = Events { tx: remote.events, wake: Arc::new(wake) };
    let mut requests = remote.requests;
    std::thread::Builder::new()
        .name("raystage-net".into())
        .spawn(move || {
            let runtime = match tokio::runtime::Builder::new_current_thread().enable_all().build() {
                Ok(runtime) => runtime,
                Err(e) => {
                    events.send(Event::Closed(format!("cannot start the network thread's runtime: {e}")));
                    return;
                }
            };
            let decoder = Decoder::spawn(events.clone());
            let outcome = runtime.block_on(session(config, &events, &mut requests, &decoder));
            decoder.close();
            if let Err(e) = outcome {
                events.send(Event::Closed(e.to_string()));
            }
        })
        .expect("a thread can be spawned");
    link
}

/// The sending half of the event channel, with the UI's waker.
#[derive(Clone)]
struct Events {
    tx: mpsc::Sender<Event>,
    wake: Arc<dyn Fn() + Send + Sync>,
}

impl Events {
    /// Sends an event; false once the viewer is gone.
    fn send(&self, event: Event) -> bool {
        let sent = self.tx.send(event).is_ok();
        (self.wake)();
        sent
    }
}

/// Runs one connection until the viewer goes (`Ok`) or the connection fails (`Err`).
async fn session(config: StreamConfig, events: &Events, requests: &mut UnboundedReceiver<Request>, decoder: &Decoder) -> Result<(), Error> {
    let server = config.server;
    let scene = match config.scene {
        Some(scene) => scene,
        None => {
            let scenes: Vec<SceneInfo> = server.get("/scenes").await?;
            scenes.iter().map(|s| s.id).min().ok_or_else(|| Error::Stream("the server has no scenes: create one (POST /scenes) or start it with --demo".into()))?
        }
    };
    let snapshot = fetch_scene(&server, scene).await?;
    if !events.send(Event::Scene(Box::new(snapshot))) {
        return Ok(());
    }

    // What the viewer asked for while the scene was fetched shapes the stream from its start.
    // Without a size, wait a moment for the viewer's (it sends one in its first pass), so that
    // the first frame already fills the window.
    let mut settings = config.settings;
    let mut camera = CameraQueue::default();
    // Edits asked for before the stream opens go out once it has.
    let mut edits = Vec::new();
    let deadline = tokio::time::Instant::now() + FIRST_SIZE_WAIT;
    loop {
        let request = if settings.width.is_some() {
            match requests.try_recv() {
                Ok(request) => request,
                Err(_) => break,
            }
        } else {
            match tokio::time::timeout_at(deadline, requests.recv()).await {
                Ok(Some(request)) => request,
                Ok(None) => return Ok(()),
                Err(_) => break,
            }
        };
        match request {
            Request::Settings(s) => settings = settings.merged(s),
            Request::Camera(c) => camera.pending = Some(c),
            Request::Commands(commands) => edits.push(Request::Commands(commands)),
            Request::EnvironmentImage { path, id, light } => spawn_environment_image(&server, scene, events, path, id, light),
            Request::Clock(change) => spawn_clock(&server, scene, events, change),
            Request::RefreshScene => {}
        }
    }
    let query = settings.query();
    let url = format!("ws://{}/scenes/{scene}/stream{}{query}", server.authority, if query.is_empty() { "" } else { "?" });
    let mut upgrade = url.as_str().into_client_request().map_err(|e| Error::Stream(format!("{url}: {e}")))?;
    if let Some(token) = &server.token {
        let value = HeaderValue::from_str(&format!("Bearer {token}")).map_err(|_| Error::Url("the token is not a valid header value".into()))?;
        upgrade.headers_mut().insert("authorization", value);
    }
    let (mut socket, _) = tokio_tungstenite::connect_async(upgrade).await.map_err(|e| Error::Stream(format!("cannot open {url}: {e}")))?;

    let mut next_request = 1u64;
    for edit in edits {
        let message = edit.message(next_request).expect("commands are stream messages");
        next_request += 1;
        socket.send(Message::text(message.to_string())).await.map_err(|e| Error::Stream(format!("sending: {e}")))?;
    }
    let mut frame_stats: Option<FrameStats> = None;
    loop {
        // A camera change waiting for its turn goes out as soon as the last one is answered.
        if let Some(message) = camera.next(&mut next_request) {
            socket.send(Message::text(message)).await.map_err(|e| Error::Stream(format!("sending: {e}")))?;
        }
        tokio::select! {
            message = socket.next() => {
                let message = match message {
                    None | Some(Ok(Message::Close(_))) => return Err(Error::Stream("the server closed the stream".into())),
                    Some(Err(e)) => return Err(Error::Stream(e.to_string())),
                    Some(Ok(message)) => message,
                };
                match message {
                    Message::Text(text) => match serde_json::from_str::<ServerMessage>(text.as_str()) {
                        Ok(ServerMessage::Hello(hello)) => {
                            if hello.protocol != PROTOCOL {
                                return Err(Error::Stream(format!("the server speaks stream protocol {}, this client {PROTOCOL}", hello.protocol)));
                            }
                            if !events.send(Event::Connected(hello)) {
                                return Ok(());
                            }
                        }
                        Ok(ServerMessage::Frame(stats)) => frame_stats = Some(stats),
                        Ok(ServerMessage::Result { request, .. }) => camera.answered(request),
                        Ok(ServerMessage::Error { request, error }) => {
                            camera.answered(request);
                            let field = error.field.map(|f| format!(" ({f})")).unwrap_or_default();
                            if !events.send(Event::Problem(format!("the server refused: {}{field}", error.message))) {
                                return Ok(());
                            }
                        }
                        // A message type from a newer server.
                        Err(_) => {}
                    },
                    Message::Binary(png) => {
                        if let Some(stats) = frame_stats.take() {
                            decoder.offer(stats, png.to_vec());
                        }
                    }
                    _ => {}
                }
            }
            request = requests.recv() => match request {
                None => {
                    let _ = socket.close(None).await;
                    return Ok(());
                }
                Some(Request::Camera(patch)) => camera.pending = Some(patch),
                Some(Request::RefreshScene) => {
                    let (server, events) = (server.clone(), events.clone());
                    tokio::spawn(async move {
                        let event = match fetch_scene(&server, scene).await {
                            Ok(snapshot) => Event::Scene(Box::new(snapshot)),
                            Err(e) => Event::Problem(e.to_string()),
                        };
                        events.send(event);
                    });
                }
                Some(Request::EnvironmentImage { path, id, light }) => spawn_environment_image(&server, scene, events, path, id, light),
                Some(Request::Clock(change)) => spawn_clock(&server, scene, events, change),
                Some(request) => {
                    let message = request.message(next_request).expect("settings and commands are stream messages");
                    next_request += 1;
                    socket.send(Message::text(message.to_string())).await.map_err(|e| Error::Stream(format!("sending: {e}")))?;
                }
            },
        }
    }
}

/// Camera changes: one in flight, the newest waiting.
#[derive(Default)]
struct CameraQueue {
    pending: Option<CameraPatch>,
    in_flight: Option<(u64, Instant)>,
}

impl CameraQueue {
    /// The message to send now, if one waits and none is in flight.
    fn next(&mut self, next_request: &mut u64) -> Option<String> {
        if self.in_flight.is_some_and(|(_, sent)| sent.elapsed() < CAMERA_REPLY_TIMEOUT) {
            return None;
        }
        let patch = self.pending.take()?;
        let request = *next_request;
        *next_request += 1;
        self.in_flight = Some((request, Instant::now()));
        Request::Camera(patch).message(request).map(|m| m.to_string())
    }

    /// A reply to `request` came in.
    fn answered(&mut self, request: Option<u64>) {
        if self.in_flight.is_some_and(|(r, _)| Some(r) == request) {
            self.in_flight = None;
        }
    }
}

/// The largest image file the viewer uploads as an environment: larger than any the server's
/// default limits take, and small enough that reading it is not the problem.
const MAX_ENVIRONMENT_FILE: u64 = 1 << 30;

/// Uploads an environment image and gives it to the light off the stream's loop (a large file
/// takes a while), then sends the scene as it now is, or what went wrong.
fn spawn_environment_image(server: &Server, scene: u32, events: &Events, path: std::path::PathBuf, id: Option<u32>, light: serde_json::Value) {
    let (server, events) = (server.clone(), events.clone());
    tokio::spawn(async move {
        let event = match environment_image(&server, scene, &path, id, light).await {
            Ok(snapshot) => Event::Scene(Box::new(snapshot)),
            Err(e) => Event::Problem(format!("{}: {e}", path.display())),
        };
        events.send(event);
    });
}

/// See [`Request::EnvironmentImage`].
async fn environment_image(server: &Server, scene: u32, path: &std::path::Path, id: Option<u32>, mut light: serde_json::Value) -> Result<SceneSnapshot, Error> {
    let file = tokio::fs::File::open(path).await.map_err(|e| Error::Http(e.to_string()))?;
    let length = file.metadata().await.map_err(|e| Error::Http(e.to_string()))?.len();
    if length > MAX_ENVIRONMENT_FILE {
        return Err(Error::Http(format!("the file is {length} bytes, more than the viewer uploads ({MAX_ENVIRONMENT_FILE})")));
    }
    let mut bytes = Vec::new();
    tokio::io::AsyncReadExt::read_to_end(&mut tokio::io::AsyncReadExt::take(file, MAX_ENVIRONMENT_FILE), &mut bytes).await.map_err(|e| Error::Http(e.to_string()))?;
    // The server reads the format from the bytes (PNG, JPEG, WebP or Radiance HDR).
    #[derive(serde::Deserialize)]
    struct Created {
        id: u32,
    }
    let texture: Created = server.post(&format!("/scenes/{scene}/textures"), "application/octet-stream", &bytes).await?;
    light["map"] = serde_json::json!(texture.id);
    let command = match id {
        Some(id) => serde_json::json!({ "set_light": { "id": id, "light": light } }),
        None => serde_json::json!({ "add_light": light }),
    };
    let batch = serde_json::json!({ "commands": [command] });
    let _: serde_json::Value = server.post(&format!("/scenes/{scene}/commands"), "application/json", batch.to_string().as_bytes()).await?;
    fetch_scene(server, scene).await
}

/// The scene's summary, objects, instances, lights and animations.
async fn fetch_scene(server: &Server, scene: u32) -> Result<SceneSnapshot, Error> {
    let info = server.get(&format!("/scenes/{scene}")).await?;
    let objects = server.get(&format!("/scenes/{scene}/objects")).await?;
    let instances = server.get(&format!("/scenes/{scene}/instances")).await?;
    let lights = server.get(&format!("/scenes/{scene}/lights")).await?;
    let animations: Vec<AnimationInfo> = server.get(&format!("/scenes/{scene}/animations")).await?;
    // A scene never posed has no clock yet (404).
    let clock = if animations.is_empty() { None } else { server.get(&format!("/scenes/{scene}/clock")).await.ok() };
    Ok(SceneSnapshot { info, objects, instances, lights, animations, clock })
}

/// Changes the scene's clock in the background ([`Request::Clock`]): the clock it left, or
/// the server's refusal, comes back as an event.
fn spawn_clock(server: &Server, scene: u32, events: &Events, change: serde_json::Value) {
    let (server, events) = (server.clone(), events.clone());
    tokio::spawn(async move {
        let event = match server.put(&format!("/scenes/{scene}/clock"), &change).await {
            Ok(clock) => Event::Clock(clock),
            Err(e) => Event::Problem(e.to_string()),
        };
        events.send(event);
    });
}

/// The frame decoder: a thread that decodes the newest PNG offered to it.
struct Decoder(Arc<DecoderSlot>);

#[derive(Default)]
struct DecoderSlot {
    state: Mutex<DecoderState>,
    ready: Condvar,
}

#[derive(Default)]
struct DecoderState {
    /// The newest frame not yet decoded: statistics, PNG, arrival.
    frame: Option<(FrameStats, Vec<u8>, Instant)>,
    /// Whether the decoder should stop.
    closed: bool,
}

impl Decoder {
    fn spawn(events: Events) -> Decoder {
        let slot = Arc::new(DecoderSlot::default());
        let shared = slot.clone();
        std::thread::Builder::new()
            .name("raystage-decode".into())
            .spawn(move || {
                loop {
                    let (stats, png, received) = {
                        let mut state = shared.state.lock().unwrap_or_else(|e| e.into_inner());
                        loop {
                            if state.closed {
                                return;
                            }
                            if let Some(frame) = state.frame.take() {
                                break frame;
                            }
                            state = shared.ready.wait(state).unwrap_or_else(|e| e.into_inner());
                        }
                    };
                    let event = match decode(&png) {
                        Ok(image) => Event::Frame(Frame { stats, image, received }),
                        Err(e) => Event::Problem(format!("frame {}: {e}", stats.seq)),
                    };
                    if !events.send(event) {
                        return;
                    }
                }
            })
            .expect("a thread can be spawned");
        Decoder(slot)
    }

    /// Hands a frame to the decoder, replacing one it has not started on.
    fn offer(&self, stats: FrameStats, png: Vec<u8>) {
        self.0.state.lock().unwrap_or_else(|e| e.into_inner()).frame = Some((stats, png, Instant::now()));
        self.0.ready.notify_one();
    }

    fn close(&self) {
        self.0.state.lock().unwrap_or_else(|e| e.into_inner()).closed = true;
        self.0.ready.notify_one();
    }
}

/// A PNG as an egui image.
fn decode(png: &[u8]) -> Result<ColorImage, image::ImageError> {
    let image = image::load_from_memory_with_format(png, image::ImageFormat::Png)?.to_rgba8();
    let size = [image.width() as usize, image.height() as usize];
    Ok(ColorImage::from_rgba_unmultiplied(size, image.as_raw()))
}
