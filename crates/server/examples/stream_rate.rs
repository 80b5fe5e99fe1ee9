//! Measures a stream's frame rate: connects to `/scenes/{scene}/stream` on a local server,
//! counts the frames that arrive over a few seconds, and prints frames per second with the
//! samples per pixel they reached.
//!
//! ```sh
//! cargo run --release -p raystage-server --example stream_rate -- --addr 127.0.0.1:8080 --query 'width=640&height=360&integrator=eyelight'
//! ```
//!
//! Without `--addr` it starts a server in-process with the sphere grid as scene 1.
//!
//! With `--edits N` it measures edit latency instead: N camera moves, each sent while a pass is
//! rendering, each timed from the message to the first frame that shows it (its
//! `scene_version`); it prints every latency and the pass time beside it, since a change waits
//! for the pass in flight to be stopped and for the first pass of the new image.
//!
//! ```sh
//! cargo run --release -p raystage-server --example stream_rate -- --query 'width=1920&height=1080&integrator=path' --edits 10
//! ```

mod common;

use std::net::SocketAddr;
use std::time::{Duration, Instant};

use common::{Socket, next_json};
use futures_util::{SinkExt, StreamExt};
use tokio_tungstenite::tungstenite::Message;

#[tokio::main]
async fn main() {
    let (mut addr, mut query, mut seconds, mut scene) = (None::<SocketAddr>, "width=640&height=360&integrator=eyelight".to_string(), 5.0, 1);
    let mut edits = 0u32;
    let mut args = std::env::args().skip(1);
    while let Some(flag) = args.next() {
        let value = args.next().unwrap_or_else(|| panic!("{flag} needs a value"));
        match flag.as_str() {
            "--addr" => addr = Some(value.parse().expect("--addr takes host:port")),
            "--query" => query = value,
            "--seconds" => seconds = value.parse().expect("--seconds takes a number"),
            "--scene" => scene = value.parse().expect("--scene takes an id"),
            "--edits" => edits = value.parse().expect("--edits takes a count"),
            _ => panic!("unknown option {flag}: expected --addr, --query, --seconds, --scene, --edits"),
        }
    }
    let addr = common::server(addr).await;
    // Unless the query says: within the frame limit at 1080p (1920 × 1080 × 256 samples) when
    // timing edits.
    if !query.contains("max_samples=") {
        query += &format!("&max_samples={}", if edits > 0 { 64 } else { 1024 });
    }
    let mut socket = common::open_stream(addr, scene, &query).await;
    if edits > 0 {
        return edit_latency(socket, edits).await;
    }
    let (mut frames, mut bytes, mut first, mut last) = (0u32, 0usize, None::<Instant>, serde_json::Value::Null);
    while let Some(Ok(message)) = socket.next().await {
        match message {
            Message::Text(text) => {
                let value: serde_json::Value = serde_json::from_str(text.as_str()).unwrap();
                if value["type"] == "frame" {
                    last = value;
                }
            }
            Message::Binary(image) => {
                // The first frame builds the scene's trees: the clock starts after it.
                let start = *first.get_or_insert_with(Instant::now);
                if start.elapsed() > Duration::ZERO {
                    frames += 1;
                    bytes += image.len();
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
        "{frames} frames in {elapsed:.2} s = {:.1} frames/s, {:.0} KB each; last: {} samples per pixel, passes of {} in {:.1} ms, encoded in {:.1} ms",
        frames as f64 / elapsed,
        bytes as f64 / frames.max(1) as f64 / 1024.0,
        last["samples"],
        last["pass_samples"],
        last["pass_seconds"].as_f64().unwrap_or(0.0) * 1e3,
        last["encode_seconds"].as_f64().unwrap_or(0.0) * 1e3,
    );
}

/// Sends `edits` camera moves, each 0.3 s into a pass, and times each to its first frame.
async fn edit_latency(mut socket: Socket, edits: u32) {
    // The first frame builds the trees: measured after it.
    while next_json(&mut socket).await["type"] != "frame" {}
    let mut latencies = Vec::new();
    for k in 0..edits {
        tokio::time::sleep(Duration::from_millis(300)).await;
        let eye = [(k as f32 * 0.7).sin() * 0.5, 1.0, 6.0];
        let message = serde_json::json!({ "type": "camera", "request": k, "camera": { "eye": eye } });
        let sent = Instant::now();
        socket.send(Message::text(message.to_string())).await.unwrap();
        let mut version = None;
        let frame = loop {
            let value = next_json(&mut socket).await;
            match value["type"].as_str() {
                Some("result") if value["request"] == k => version = value["version"].as_u64(),
                Some("frame") if version.is_some_and(|v| value["scene_version"].as_u64() >= Some(v)) => break value,
                _ => {}
            }
        };
        let latency = sent.elapsed().as_secs_f64();
        let (pass, png) = (frame["pass_seconds"].as_f64().unwrap_or(0.0), frame["encode_seconds"].as_f64().unwrap_or(0.0));
        println!(
            "edit {k}: {:.0} ms to the first frame that shows it (its pass took {:.0} ms, its PNG {:.0} ms: {:.0} ms beside the pass)",
            latency * 1e3,
            pass * 1e3,
            png * 1e3,
            (latency - pass) * 1e3
        );
        latencies.push(latency - pass);
    }
    latencies.sort_by(f64::total_cmp);
    println!(
        "latency beyond the first pass: median {:.0} ms, worst {:.0} ms over {} edits",
        latencies[latencies.len() / 2] * 1e3,
        latencies.last().unwrap() * 1e3,
        latencies.len()
    );
}
