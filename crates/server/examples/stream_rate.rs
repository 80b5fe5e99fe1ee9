//! Measures a stream's frame rate: connects to `/scenes/{scene}/stream` on a local server,
//! counts the frames that arrive over a few seconds, and prints frames per second with the
//! samples per pixel they reached.
//!
//! ```sh
//! cargo run --release -p raystage-server --example stream_rate -- --addr 127.0.0.1:8080 --query 'width=640&height=360&integrator=eyelight'
//! ```
//!
//! Without `--addr` it starts a server in-process with the sphere grid as scene 1.

use std::net::SocketAddr;
use std::time::{Duration, Instant};

use futures_util::StreamExt;
use tokio_tungstenite::tungstenite::Message;

#[tokio::main]
async fn main() {
    let (mut addr, mut query, mut seconds, mut scene) = (None::<SocketAddr>, "width=640&height=360&integrator=eyelight".to_string(), 5.0, 1);
    let mut args = std::env::args().skip(1);
    while let Some(flag) = args.next() {
        let value = args.next().unwrap_or_else(|| panic!("{flag} needs a value"));
        match flag.as_str() {
            "--addr" => addr = Some(value.parse().expect("--addr takes host:port")),
            "--query" => query = value,
            "--seconds" => seconds = value.parse().expect("--seconds takes a number"),
            "--scene" => scene = value.parse().expect("--scene takes an id"),
            _ => panic!("unknown option {flag}: expected --addr, --query, --seconds, --scene"),
        }
    }
    let addr = match addr {
        Some(addr) => {
            assert!(addr.ip().is_loopback(), "only loopback addresses are measured");
            addr
        }
        None => {
            let state = raystage_server::AppState::new(raystage_server::Config::default());
            state.add_scene(raystage_demo::StandardScene::Spheres.scene().expect("the sphere grid builds"), "demo:spheres").unwrap();
            let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
            let addr = listener.local_addr().unwrap();
            tokio::spawn(raystage_server::serve(listener, state, std::future::pending()));
            addr
        }
    };
    let url = format!("ws://{addr}/scenes/{scene}/stream?{query}&max_samples=1024");
    let (mut socket, _) = tokio_tungstenite::connect_async(url).await.expect("the stream opens");
    let (mut frames, mut bytes, mut first, mut last) = (0u32, 0usize, None::<Instant>, serde_json::Value::Null);
    while let Some(Ok(message)) = socket.next().await {
        match message {
            Message::Text(text) => {
                let value: serde_json::Value = serde_json::from_str(text.as_str()).unwrap();
                if value["type"] == "frame" {
                    last = value;
                }
            }
            Message::Binary(png) => {
                // The first frame builds the scene's trees: the clock starts after it.
                let start = *first.get_or_insert_with(Instant::now);
                if start.elapsed() > Duration::ZERO {
                    frames += 1;
                    bytes += png.len();
                }
                if start.elapsed().as_secs_f64() >= seconds {
                    break;
                }
            }
            _ => {}
        }
    }
    let elapsed = first.map_or(0.0, |f| f.elapsed().as_secs_f64());
    println!(
        "{frames} frames in {elapsed:.2} s = {:.1} frames/s, {:.0} KB each; last: {} samples per pixel, passes of {} in {:.1} ms, PNG {:.1} ms",
        frames as f64 / elapsed,
        bytes as f64 / frames.max(1) as f64 / 1024.0,
        last["samples"],
        last["pass_samples"],
        last["pass_seconds"].as_f64().unwrap_or(0.0) * 1e3,
        last["encode_seconds"].as_f64().unwrap_or(0.0) * 1e3,
    );
}
