//! A load generator for the server: many keep-alive HTTP/1.1 clients on loopback sending the
//! same request, a fixed number of requests in all; prints throughput and latency percentiles.
//!
//! ```sh
//! cargo run --release -p raystage-server --example load -- --clients 32 --requests 2000
//! cargo run --release -p raystage-server --example load -- --addr 127.0.0.1:8080 --path '/scenes/1/frame.png?width=256&height=256'
//! ```
//!
//! Without `--addr` it starts a server in-process with the sphere grid as scene 1 (and renders
//! one frame first, so the lazy tree build is not measured). Only loopback addresses are
//! accepted: this is for measuring a local server.

mod common;

use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use common::{exchange, percentile_ms};
use tokio::io::BufReader;
use tokio::net::TcpStream;

struct Options {
    addr: Option<SocketAddr>,
    path: String,
    clients: usize,
    requests: usize,
}

fn options() -> Options {
    let mut o = Options { addr: None, path: "/scenes/1/frame.png?width=256&height=256&integrator=eyelight".into(), clients: 32, requests: 2000 };
    let mut args = std::env::args().skip(1);
    while let Some(flag) = args.next() {
        let value = args.next().unwrap_or_else(|| panic!("{flag} needs a value"));
        match flag.as_str() {
            "--addr" => o.addr = Some(value.parse().expect("--addr takes host:port")),
            "--path" => o.path = value,
            "--clients" => o.clients = value.parse().expect("--clients takes a number"),
            "--requests" => o.requests = value.parse().expect("--requests takes a number"),
            _ => panic!("unknown option {flag}: expected --addr, --path, --clients, --requests"),
        }
    }
    o
}

/// What one client saw: latencies of successful requests, and failures.
#[derive(Default)]
struct Tally {
    latencies: Vec<f64>,
    errors: Vec<String>,
}

async fn client(addr: SocketAddr, request: Arc<Vec<u8>>, next: Arc<AtomicUsize>, total: usize) -> Tally {
    let mut tally = Tally::default();
    let mut connection: Option<BufReader<TcpStream>> = None;
    while next.fetch_add(1, Ordering::Relaxed) < total {
        let start = Instant::now();
        let stream = match &mut connection {
            Some(stream) => stream,
            None => match TcpStream::connect(addr).await {
                Ok(s) => connection.insert(BufReader::new(s)),
                Err(e) => {
                    tally.errors.push(format!("connect: {e}"));
                    continue;
                }
            },
        };
        match exchange(stream, &request).await {
            Ok((200, _)) => tally.latencies.push(start.elapsed().as_secs_f64()),
            Ok((status, _)) => tally.errors.push(format!("status {status}")),
            Err(e) => {
                tally.errors.push(e.to_string());
                connection = None;
            }
        }
    }
    tally
}

#[tokio::main]
async fn main() {
    let o = options();
    let addr = common::server(o.addr).await;
    let request = Arc::new(common::request(addr, "GET", &o.path, ""));
    // One request first: it builds the scene's trees, which is not what is measured.
    let (status, _) = exchange(&mut common::connect(addr).await, &request).await.expect("the server answers");
    assert_eq!(status, 200, "GET {} answers {status}", o.path);

    let next = Arc::new(AtomicUsize::new(0));
    let start = Instant::now();
    let clients: Vec<_> = (0..o.clients).map(|_| tokio::spawn(client(addr, request.clone(), next.clone(), o.requests))).collect();
    let mut all = Tally::default();
    for c in clients {
        let t = c.await.unwrap();
        all.latencies.extend(t.latencies);
        all.errors.extend(t.errors);
    }
    let wall = start.elapsed().as_secs_f64();
    all.latencies.sort_by(f64::total_cmp);
    let pct = |p: f64| percentile_ms(&all.latencies, p);
    println!(
        "GET {} x {} from {} clients: {} ok, {} errors in {wall:.2} s = {:.1} requests/s; latency p50 {:.1} ms, p90 {:.1} ms, p99 {:.1} ms, max {:.1} ms",
        o.path,
        o.requests,
        o.clients,
        all.latencies.len(),
        all.errors.len(),
        all.latencies.len() as f64 / wall,
        pct(0.5),
        pct(0.9),
        pct(0.99),
        pct(1.0)
    );
    if let Some(first) = all.errors.first() {
        println!("first error: {first}");
        std::process::exit(1);
    }
}
