//! `/scenes/{scene}/stream`: a WebSocket that pushes progressively refined frames of a scene
//! and takes camera changes, edits and settings (protocol: `api/stream.md`).
//!
//! Three tasks serve a stream: this module's receiver reads client messages and applies them;
//! [`refine::refine`] renders passes on the blocking pool and publishes the newest frame into a
//! one-slot channel; the sender writes that frame (and replies) to the socket. A slow client
//! holds up only the sender, and the one slot means frames are replaced, never queued.

mod protocol;
mod refine;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use axum::extract::State;
use axum::extract::ws::rejection::WebSocketUpgradeRejection;
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::response::Response;
use futures_util::{SinkExt, StreamExt};
use raystage_render::{FrameSettings, RenderSettings};
use raystage_service::model::Command;
use raystage_service::{AppState, Error, Limits, SceneSlot};
use tokio::sync::{mpsc, watch};

pub use protocol::{ClientMessage, Encoding, FrameMessage, PROTOCOL, ServerMessage, SettingsChange, StreamQuery};
use refine::{Packet, StreamSettings, refine};

use crate::error::{ApiResult, ErrorBody};
use crate::extract::{Params, Target, parse_json};
use crate::render::{check_limits, setting_error};

/// Default samples per pixel a stream refines to.
const DEFAULT_MAX_SAMPLES: u32 = 256;
/// Default JPEG quality: at 1920×1080, a frame of the sphere grid takes 170 KB (its PNG
/// 860 KB; docs/performance.md).
const DEFAULT_QUALITY: u8 = 80;

/// Opens a stream of progressive frames (a WebSocket; see `api/stream.md`).
#[utoipa::path(get, path = "/scenes/{scene}/stream", tag = "frames",
    params(("scene" = u32, Path, description = "The scene's id"), StreamQuery),
    responses(
        (status = 101, description = "Switching to the WebSocket protocol"),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
        (status = 503, description = "Too many open streams", body = ErrorBody),
    ))]
pub(crate) async fn stream(
    State(state): State<AppState>,
    target: Target,
    Params(query): Params<StreamQuery>,
    upgrade: Result<WebSocketUpgrade, WebSocketUpgradeRejection>,
) -> ApiResult<Response> {
    let limits = state.config().limits;
    let mut frame = FrameSettings::default();
    frame.apply(&query.patch()).map_err(|e| setting_error(e, "max_samples"))?;
    let settings = StreamSettings {
        frame,
        max_samples: query.max_samples.unwrap_or(DEFAULT_MAX_SAMPLES.min(limits.max_spp)),
        encoding: query.encoding.as_deref().map(Encoding::parse).transpose()?.unwrap_or_default(),
        quality: query.quality.unwrap_or(DEFAULT_QUALITY),
    };
    check(&settings, &limits)?;
    let guard = state.open_stream()?;
    // A plain HTTP request gets the API's JSON error, naming the header it lacks, not axum's
    // text; only once the settings and the room for a stream are checked, so that a browser,
    // which cannot see why its WebSocket was refused, learns it from the same request without
    // the upgrade.
    let upgrade = upgrade.map_err(|e| Error::bad_request(Some("upgrade".into()), format!("{}: open the stream as a WebSocket", e.body_text())))?;
    let (scene, client) = (target.scene, target.client);
    // A message may come in one frame as large as the message limit (tungstenite's own frame
    // limit, 16 MiB, would drop the connection with no close code well under it).
    let upgrade = upgrade.max_message_size(limits.max_body_bytes).max_frame_size(limits.max_body_bytes);
    Ok(upgrade.on_upgrade(move |socket| async move {
        session(socket, state, scene, client, settings).await;
        drop(guard);
    }))
}

/// Checks a stream's settings as a frame request of `max_samples` samples per pixel, its JPEG
/// quality, and its image against the memory for images being rendered (413 if it could never
/// fit).
fn check(settings: &StreamSettings, limits: &Limits) -> raystage_service::Result<()> {
    if !(1..=100).contains(&settings.quality) {
        return Err(Error::unprocessable(Some("quality".into()), format!("quality {} is not in 1..=100", settings.quality)));
    }
    let render = settings.frame.render;
    check_limits(&RenderSettings { samples_per_pixel: settings.max_samples, ..render }, "max_samples", limits)?;
    let bytes = settings.bytes();
    if bytes > limits.max_render_bytes as u64 {
        let message = format!("a {}×{} stream takes {bytes} bytes: the limit is {}", render.width, render.height, limits.max_render_bytes);
        return Err(Error::too_large(None, message).limit("max_render_bytes").into());
    }
    Ok(())
}

async fn session(socket: WebSocket, state: AppState, slot: Arc<SceneSlot>, client: raystage_service::Client, settings: StreamSettings) {
    let (mut sink, mut incoming) = socket.split();
    let (settings_tx, settings_rx) = watch::channel(settings);
    let (frames_tx, mut frames_rx) = watch::channel::<Option<Arc<Packet>>>(None);
    let (replies_tx, mut replies_rx) = mpsc::channel::<ServerMessage>(16);
    let taken = Arc::new(AtomicBool::new(true));

    let hello = ServerMessage::Hello {
        protocol: PROTOCOL,
        scene: slot.id,
        width: settings.frame.render.width,
        height: settings.frame.render.height,
        integrator: settings.frame.integrator.map(|i| i.name().to_string()),
        max_samples: settings.max_samples,
    };
    let renderer = tokio::spawn(refine(state.clone(), slot.clone(), client, settings_rx, frames_tx, taken.clone(), replies_tx.clone()));
    let mut sender = tokio::spawn(async move {
        let text = |m: &ServerMessage| Message::text(serde_json::to_string(m).expect("messages serialise"));
        if sink.send(text(&hello)).await.is_err() {
            return;
        }
        loop {
            tokio::select! {
                // Replies first: the renderer's last word comes before it goes.
                biased;
                reply = replies_rx.recv() => match reply {
                    Some(reply) => if sink.send(text(&reply)).await.is_err() { return },
                    None => return,
                },
                changed = frames_rx.changed() => {
                    if changed.is_err() {
                        // The renderer stopped (the scene was deleted): so does the stream.
                        let _ = sink.send(Message::Close(None)).await;
                        return;
                    }
                    let packet = frames_rx.borrow_and_update().clone();
                    if let Some(packet) = packet {
                        if sink.send(Message::text(packet.json.clone())).await.is_err()
                            || sink.send(Message::binary(packet.image.clone())).await.is_err()
                        {
                            return;
                        }
                        taken.store(true, Ordering::Release);
                    }
                }
            }
        }
    });

    loop {
        let message = tokio::select! {
            message = incoming.next() => match message {
                Some(Ok(message)) => message,
                _ => break,
            },
            _ = &mut sender => break,
        };
        let reply = match message {
            Message::Text(text) => handle(&state, &slot, &settings_tx, text.as_str()).await,
            Message::Binary(_) => ServerMessage::Error {
                request: None,
                error: Error::bad_request(None, "binary messages are not understood: send JSON text").detail,
            },
            Message::Close(_) => break,
            Message::Ping(_) | Message::Pong(_) => continue,
        };
        if replies_tx.send(reply).await.is_err() {
            break;
        }
    }
    renderer.abort();
    sender.abort();
}

/// Applies one client message; returns the reply.
async fn handle(state: &AppState, slot: &Arc<SceneSlot>, settings: &watch::Sender<StreamSettings>, text: &str) -> ServerMessage {
    let message = match parse_message(text.as_bytes(), state.config().limits.max_commands) {
        Ok(m) => m,
        Err(e) => return ServerMessage::Error { request: None, error: e.detail },
    };
    let (request, outcome) = match message {
        ClientMessage::Camera { request, camera } => (request, slot.commands(state, vec![Command::SetCamera(camera)], false).await),
        ClientMessage::Commands { request, commands } => (request, slot.commands(state, commands, true).await),
        ClientMessage::Settings(change) => {
            let mut new = *settings.borrow();
            let applied = new.frame.apply(&change.patch()).map_err(|e| setting_error(e, "max_samples")).and_then(|()| {
                new.max_samples = change.max_samples.unwrap_or(new.max_samples);
                new.encoding = change.encoding.as_deref().map(Encoding::parse).transpose()?.unwrap_or(new.encoding);
                new.quality = change.quality.unwrap_or(new.quality);
                check(&new, &state.config().limits)
            });
            (change.request, applied.map(|()| {
                settings.send_replace(new);
                (Vec::new(), slot.version())
            }))
        }
    };
    match outcome {
        Ok((results, version)) => ServerMessage::Result { request, version, results },
        Err(e) => ServerMessage::Error { request, error: e.detail },
    }
}

/// A client message. A `commands` message is read with its commands counted as they are
/// parsed (as `POST /commands` reads a batch): the one past `max_commands` ends parsing, so that
/// a huge message costs the memory of the limit, not of all it holds.
fn parse_message(bytes: &[u8], max_commands: usize) -> raystage_service::Result<ClientMessage> {
    if message_type(bytes).as_deref() == Some("commands") {
        let (commands, request) = crate::commands::parse_commands(bytes, max_commands, true)?;
        return Ok(ClientMessage::Commands { request, commands: commands.commands });
    }
    parse_json(bytes)
}

/// The `type` of a message, read without reading the rest: the fields before it are skipped
/// unread, and reading stops at it (`None` if the message is not an object with a string
/// `type` among valid JSON before it).
fn message_type(bytes: &[u8]) -> Option<String> {
    use serde::de::{Deserializer, IgnoredAny, MapAccess, Visitor};

    struct TypeOnly<'a>(&'a std::cell::Cell<Option<String>>);

    impl<'de> Visitor<'de> for TypeOnly<'_> {
        type Value = ();

        fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("a message")
        }

        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
            while let Some(key) = map.next_key::<std::borrow::Cow<'de, str>>()? {
                if key == "type" {
                    self.0.set(Some(map.next_value()?));
                    // Found: stop here rather than read the rest.
                    return Err(serde::de::Error::custom("stop"));
                }
                map.next_value::<IgnoredAny>()?;
            }
            Ok(())
        }
    }

    let found = std::cell::Cell::new(None);
    let _ = serde_json::Deserializer::from_slice(bytes).deserialize_map(TypeOnly(&found));
    found.take()
}
