//! What the DevTools protocol and WebDriver BiDi share: a browser started with a port of its
//! own, which names its WebSocket address on stderr, and JSON commands over that WebSocket, each
//! answered by a message carrying the command's id; messages without an id are events, kept for
//! the tests to read.

use std::collections::HashMap;
use std::io::BufRead;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use futures_util::stream::SplitSink;
use futures_util::{SinkExt, StreamExt};
use serde_json::Value;
use tokio::sync::oneshot;
use tokio_tungstenite::tungstenite::Message;

use super::PATIENCE;

type Socket = tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

/// Starts `command` and waits for the stderr line that starts with `listening`; the browser and
/// the rest of that line (its address).
pub fn launch(mut command: Command, listening: &'static str) -> (Child, String) {
    let mut process = command.stdin(Stdio::null()).stdout(Stdio::null()).stderr(Stdio::piped()).spawn().expect("the browser starts");
    // The thread reads on after the address, so that the pipe never fills.
    let stderr = process.stderr.take().expect("stderr is piped");
    let (address, found) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in std::io::BufReader::new(stderr).lines().map_while(Result::ok) {
            if let Some(url) = line.strip_prefix(listening) {
                let _ = address.send(url.trim().to_string());
            }
        }
    });
    let url = found.recv_timeout(PATIENCE).unwrap_or_else(|_| panic!("the browser says \"{listening}\""));
    (process, url)
}

/// A WebSocket to the browser: commands answered by id, events kept.
pub struct Connection {
    sink: tokio::sync::Mutex<SplitSink<Socket, Message>>,
    next_id: AtomicU64,
    replies: Mutex<HashMap<u64, oneshot::Sender<Value>>>,
    events: Mutex<Vec<Value>>,
}

impl Connection {
    pub async fn connect(url: &str) -> Arc<Connection> {
        let (socket, _) = tokio_tungstenite::connect_async(url).await.expect("the browser's WebSocket opens");
        let (sink, mut stream) = socket.split();
        let connection = Arc::new(Connection { sink: tokio::sync::Mutex::new(sink), next_id: AtomicU64::new(1), replies: Mutex::default(), events: Mutex::default() });
        let reader = connection.clone();
        tokio::spawn(async move {
            while let Some(Ok(message)) = stream.next().await {
                let Message::Text(text) = message else { continue };
                let value: Value = serde_json::from_str(text.as_str()).expect("the browser sends JSON");
                match value["id"].as_u64() {
                    Some(id) => {
                        if let Some(reply) = reader.replies.lock().unwrap().remove(&id) {
                            let _ = reply.send(value);
                        }
                    }
                    None => reader.events.lock().unwrap().push(value),
                }
            }
        });
        connection
    }

    /// Sends `message` (an object with the command's method and parameters) with an id of its
    /// own; the whole reply, which the protocol's module checks.
    pub async fn send(&self, mut message: Value) -> Value {
        let id = self.next_id.fetch_add(1, Ordering::Relaxed);
        let (reply, answered) = oneshot::channel();
        self.replies.lock().unwrap().insert(id, reply);
        message["id"] = id.into();
        let method = message["method"].clone();
        self.sink.lock().await.send(Message::text(message.to_string())).await.expect("the browser takes the command");
        tokio::time::timeout(PATIENCE, answered).await.unwrap_or_else(|_| panic!("{method}: no answer")).expect("the browser answers")
    }

    /// The events so far, oldest first.
    pub fn events(&self) -> MutexGuard<'_, Vec<Value>> {
        self.events.lock().unwrap()
    }
}
