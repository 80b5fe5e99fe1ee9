//! What the examples share: a server to measure (a local one, or one started in-process), HTTP
//! exchanges on a kept-alive connection, and a stream's messages.

// Each example is its own crate and uses only part of this module.
#![allow(dead_code)]

use std::net::SocketAddr;

use futures_util::StreamExt;
use tokio::io::{AsyncBufReadExt, AsyncReadExt, AsyncWriteExt, BufReader};
use tokio::net::TcpStream;
use tokio_tungstenite::tungstenite::Message;

/// `addr` if given (only loopback addresses: these measure a local server), else a server
/// started in-process with the sphere grid as scene 1.
pub async fn server(addr: Option<SocketAddr>) -> SocketAddr {
    if let Some(addr) = addr {
        assert!(addr.ip().is_loopback(), "only loopback addresses are measured");
        return addr;
    }
    let state = raystage_server::AppState::new(raystage_server::Config::default());
    let scene = raystage_demo::StandardScene::Spheres.scene().expect("the sphere grid builds");
    state.add_scene(scene, "demo:spheres").expect("room for a scene");
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    tokio::spawn(raystage_server::serve(listener, state, std::future::pending()));
    addr
}

/// An HTTP/1.1 request to `addr`, kept alive, with a JSON `body` if it is not empty.
pub fn request(addr: SocketAddr, method: &str, path: &str, body: &str) -> Vec<u8> {
    format!("{method} {path} HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}", body.len()).into_bytes()
}

/// Sends one request on the connection and reads the whole response; returns its status and
/// body.
pub async fn exchange(stream: &mut BufReader<TcpStream>, request: &[u8]) -> std::io::Result<(u16, Vec<u8>)> {
    stream.get_mut().write_all(request).await?;
    let mut line = String::new();
    stream.read_line(&mut line).await?;
    let status = line.split(' ').nth(1).and_then(|s| s.parse().ok()).ok_or_else(|| std::io::Error::other(format!("bad status line {line:?}")))?;
    let mut length = 0;
    loop {
        line.clear();
        stream.read_line(&mut line).await?;
        if line == "\r\n" || line.is_empty() {
            break;
        }
        if let Some((name, value)) = line.split_once(':')
            && name.eq_ignore_ascii_case("content-length")
        {
            length = value.trim().parse().map_err(std::io::Error::other)?;
        }
    }
    let mut body = vec![0; length];
    stream.read_exact(&mut body).await?;
    Ok((status, body))
}

/// A connection to the server, for [`exchange`].
pub async fn connect(addr: SocketAddr) -> BufReader<TcpStream> {
    BufReader::new(TcpStream::connect(addr).await.expect("the server accepts connections"))
}

/// A stream's WebSocket.
pub type Socket = tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<TcpStream>>;

/// Opens `/scenes/{scene}/stream?{query}`.
pub async fn open_stream(addr: SocketAddr, scene: u32, query: &str) -> Socket {
    let url = format!("ws://{addr}/scenes/{scene}/stream?{query}");
    tokio_tungstenite::connect_async(url).await.expect("the stream opens").0
}

/// The next text message, as JSON (images skipped).
pub async fn next_json(socket: &mut Socket) -> serde_json::Value {
    loop {
        match socket.next().await.expect("the stream stays open").expect("no socket error") {
            Message::Text(text) => return serde_json::from_str(text.as_str()).unwrap(),
            _ => continue,
        }
    }
}

/// The value at fraction `p` (0 to 1) of `sorted`, in milliseconds (0 if it is empty).
pub fn percentile_ms(sorted: &[f64], p: f64) -> f64 {
    sorted.get(((sorted.len() as f64 * p) as usize).min(sorted.len().saturating_sub(1))).map_or(0.0, |s| s * 1e3)
}

/// The machine's load averages (1, 5 and 15 minutes) as `/proc/loadavg` gives them, or "?".
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg").map_or_else(|_| "?".into(), |l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
}
