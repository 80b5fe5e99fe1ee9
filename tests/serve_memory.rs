//! What requests past the server's limits cost it in memory: `raystage serve` as users run it
//! (default limits), one server per case, its peak resident memory (`VmHWM`, from /proc) before
//! and after a request that must be refused. Each limit is checked before the memory it guards
//! is spent, so the peak barely moves; without the checks, each case would take hundreds of
//! megabytes to gigabytes (the figures in docs/performance.md, "HTTP server"). And what an
//! accepted scene counts against the budgets is what it holds: its resident memory.

#![cfg(target_os = "linux")]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};

/// A server with default limits and one empty scene (scene 1).
struct Server {
    child: Child,
    addr: String,
}

impl Server {
    fn start() -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_raystage"))
            .args(["serve", "--addr", "127.0.0.1:0"])
            .env_remove("RAYSTAGE_TOKEN")
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        let lines = BufReader::new(child.stdout.take().unwrap()).lines();
        let banner = lines.map(Result::unwrap).find(|l| l.contains("http://")).expect("the server prints its address");
        let addr = banner.split("http://").nth(1).and_then(|rest| rest.split('/').next()).unwrap().to_string();
        let server = Server { child, addr };
        let (status, body) = server.request("POST", "/scenes", "application/json", b"{}");
        assert_eq!(status, 201, "{body}");
        server
    }

    /// The status and body of a request (the connection closed after it).
    fn request(&self, method: &str, path: &str, content_type: &str, body: &[u8]) -> (u16, String) {
        let mut stream = TcpStream::connect(&self.addr).unwrap();
        let head = format!("{method} {path} HTTP/1.1\r\nHost: {}\r\nContent-Type: {content_type}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n", self.addr, body.len());
        stream.write_all(head.as_bytes()).unwrap();
        // A server that answers before reading the whole body may close the connection on the
        // rest: what it answered is still there to read.
        let _ = stream.write_all(body);
        let mut response = Vec::new();
        let _ = stream.read_to_end(&mut response);
        let response = String::from_utf8_lossy(&response).into_owned();
        let status = response.split(' ').nth(1).and_then(|s| s.parse().ok()).unwrap_or_else(|| panic!("no status in {response:?}"));
        (status, response)
    }

    /// The server's peak resident memory so far, in MiB.
    fn peak_mib(&self) -> f64 {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.child.id())).unwrap();
        let line = status.lines().find(|l| l.starts_with("VmHWM:")).expect("Linux reports the peak resident set");
        line.split_whitespace().nth(1).unwrap().parse::<f64>().unwrap() / 1024.0
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Sends a request that must be refused with `status` naming `limit`, on a fresh server, and
/// checks that its peak memory grew by less than `budget_mib` (beyond the request body, which
/// the server holds while it reads it).
fn refused_within(method: &str, path: &str, content_type: &str, body: &[u8], status: u16, limit: &str, budget_mib: f64) {
    let server = Server::start();
    let before = server.peak_mib();
    let (got, response) = server.request(method, path, content_type, body);
    assert!(got == status && response.contains(&format!(r#""limit":"{limit}""#)), "{path}: {response}");
    let grown = server.peak_mib() - before - body.len() as f64 / (1 << 20) as f64;
    assert!(grown < budget_mib, "{path}: the peak grew by {grown:.0} MiB beyond the body, budget {budget_mib} MiB");
}

#[test]
fn an_image_too_large_to_decode_is_refused_without_decoding_it() {
    // 8192² black texels: 0.2 MB of PNG, 768 MiB decoded (the budget is 256 MiB).
    let mut png = std::io::Cursor::new(Vec::new());
    image::RgbImage::new(8192, 8192).write_to(&mut png, image::ImageFormat::Png).unwrap();
    refused_within("POST", "/scenes/1/textures", "image/png", &png.into_inner(), 413, "max_texture_bytes", 32.0);
}

#[test]
fn a_demo_past_the_triangle_limit_is_refused_before_it_is_built() {
    // Four million triangles would take over 500 MiB.
    refused_within("POST", "/scenes", "application/json", br#"{"demo": "museum-4000000"}"#, 422, "max_demo_triangles", 32.0);
}

#[test]
fn channels_larger_than_the_render_budget_are_refused_before_their_images_are_made() {
    // 8192² pixels of every channel: 4 GiB (the budget is 2 GiB for every frame together).
    refused_within("GET", "/scenes/1/channels/depth?width=8192&height=8192", "application/json", b"", 413, "max_render_bytes", 32.0);
}

#[test]
fn a_batch_past_the_command_limit_stops_parsing_at_the_first_command_too_many() {
    // 64 MiB of tiny commands, 3.5 million of them: parsed whole, they took 12 times the body;
    // parsing stops at the 100,001st.
    let command = br#"{"set_camera": {}}, "#;
    let mut body = br#"{"commands": ["#.to_vec();
    while body.len() < 64 << 20 {
        body.extend_from_slice(command);
    }
    body.extend_from_slice(br#"{"set_camera": {}}]}"#);
    refused_within("POST", "/scenes/1/commands", "application/json", &body, 413, "max_commands", 96.0);
}

/// A stream whose client stops reading: the server keeps one frame for it, the newest, instead
/// of queueing every pass's PNG, so its memory stays flat while the renderer goes on refining.
#[test]
fn a_stream_whose_client_does_not_read_is_not_buffered() {
    let server = Server::start();
    let (status, body) = server.request("POST", "/scenes", "application/json", br#"{"demo": "cornell"}"#);
    assert_eq!(status, 201, "{body}");
    let before = server.peak_mib();
    let mut stream = TcpStream::connect(&server.addr).unwrap();
    // A path-traced 512 × 512 stream refining to 2,000 samples: hundreds of noisy PNGs of
    // about half a megabyte each while the client reads nothing.
    let upgrade = format!(
        "GET /scenes/2/stream?width=512&height=512&integrator=path&max_samples=2000 HTTP/1.1\r\nHost: {}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n",
        server.addr
    );
    stream.write_all(upgrade.as_bytes()).unwrap();
    std::thread::sleep(std::time::Duration::from_secs(8));
    let grown = server.peak_mib() - before;
    // The stream was live all along: what it sent is waiting in the socket.
    stream.set_read_timeout(Some(std::time::Duration::from_secs(5))).unwrap();
    let mut received = vec![0u8; 1 << 20];
    let mut got = 0;
    while got < received.len() {
        match stream.read(&mut received[got..]) {
            Ok(0) | Err(_) => break,
            Ok(n) => got += n,
        }
    }
    let text = String::from_utf8_lossy(&received[..got]);
    assert!(text.starts_with("HTTP/1.1 101") && text.contains(r#""type":"frame""#), "the stream sent no frame: {:?}", &text[..text.len().min(300)]);
    assert!(grown < 64.0, "the server's peak grew by {grown:.0} MiB for a stream nobody read");
}

/// The server's resident memory now, in MiB.
fn resident_mib(server: &Server) -> f64 {
    let status = std::fs::read_to_string(format!("/proc/{}/status", server.child.id())).unwrap();
    let line = status.lines().find(|l| l.starts_with("VmRSS:")).expect("Linux reports the resident set");
    line.split_whitespace().nth(1).unwrap().parse::<f64>().unwrap() / 1024.0
}

/// A glTF file of `nodes` nodes side by side, each placing the same one-triangle mesh: an
/// instance each, in a few megabytes of file.
fn many_nodes_glb(nodes: usize) -> Vec<u8> {
    let placed = (0..nodes).map(|k| serde_json::json!({ "mesh": 0, "translation": [k as f32 * 1e-3, 0, 0] })).collect();
    one_triangle_glb(placed, (0..nodes).collect())
}

/// A glTF file of `nodes` (mesh 0 is one triangle), `roots` its scene's nodes.
fn one_triangle_glb(nodes: Vec<serde_json::Value>, roots: Vec<usize>) -> Vec<u8> {
    one_triangle_animated_glb(nodes, roots, None)
}

/// [`one_triangle_glb`], with an animation turning node `turned` (when given) half a turn
/// about y in a second.
fn one_triangle_animated_glb(nodes: Vec<serde_json::Value>, roots: Vec<usize>, turned: Option<usize>) -> Vec<u8> {
    let mut bin: Vec<u8> = [-0.5f32, -0.5, 0.0, 0.5, -0.5, 0.0, 0.5, 0.5, 0.0].iter().flat_map(|f| f.to_le_bytes()).collect();
    bin.extend([0u16, 1, 2, 0].iter().flat_map(|i| i.to_le_bytes()));
    // The animation's keyframes: two times, two rotations (x, y, z, w).
    bin.extend([0.0f32, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0].iter().flat_map(|f| f.to_le_bytes()));
    let mut document = serde_json::json!({
        "asset": { "version": "2.0" },
        "buffers": [{ "byteLength": bin.len() }],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 36 },
            { "buffer": 0, "byteOffset": 36, "byteLength": 6 },
            { "buffer": 0, "byteOffset": 44, "byteLength": 8 },
            { "buffer": 0, "byteOffset": 52, "byteLength": 32 }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 0] },
            { "bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR" },
            { "bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [1.0] },
            { "bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC4" }
        ],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] }],
        "nodes": nodes,
        "scenes": [{ "nodes": roots }],
        "scene": 0
    });
    if let Some(node) = turned {
        document["animations"] = serde_json::json!([{
            "samplers": [{ "input": 2, "output": 3 }],
            "channels": [{ "sampler": 0, "target": { "node": node, "path": "rotation" } }]
        }]);
    }
    raystage_gltf_import::glb(&serde_json::to_vec(&document).unwrap(), &bin)
}

/// A glTF file of `chains` chains of `depth` nodes, each node the child of the one before and
/// the last one placing a one-triangle mesh, the first chain's root turned by an animation: a
/// node hierarchy the scene keeps to animate (a rig), far larger than its few instances.
fn node_chains_glb(chains: usize, depth: usize) -> Vec<u8> {
    let nodes = (0..chains * depth)
        .map(|k| match k % depth + 1 < depth {
            true => serde_json::json!({ "children": [k + 1], "translation": [1e-3, 0, 0] }),
            false => serde_json::json!({ "mesh": 0, "translation": [1e-3, 0, 0] }),
        })
        .collect();
    one_triangle_animated_glb(nodes, (0..chains).map(|c| c * depth).collect(), Some(0))
}

/// A scene of deep node chains counts what it holds: 800 animated chains of 256 nodes (a rig
/// of 204,800 nodes, once counted as nothing) are within 1.5× of the resident memory they add,
/// either way; and so is the same file uploaded three times more, each parse's garbage given
/// back rather than kept in an allocator arena of its own.
#[test]
fn a_scene_of_node_chains_counts_the_memory_it_holds() {
    let server = Server::start();
    let before = resident_mib(&server);
    let file = node_chains_glb(800, 256);
    let mut counted = 0.0;
    for uploads in 1..=4 {
        let (status, body) = server.request("POST", "/scenes", "model/gltf-binary", &file);
        assert_eq!(status, 201, "{body}");
        let info: serde_json::Value = serde_json::from_str(&body[body.find('{').unwrap()..]).unwrap();
        assert_eq!(info["instances"], 800);
        counted += info["memory_bytes"].as_f64().unwrap() / (1 << 20) as f64;
        let grown = resident_mib(&server) - before;
        let ratio = counted / grown;
        assert!((1.0 / 1.5..=1.5).contains(&ratio), "{uploads} scenes count {counted:.1} MiB and the server grew by {grown:.1} MiB: {ratio:.2}×");
    }
}

/// Lights count what they hold: three batches of 100,000 point lights (lights were once counted
/// at half their size) are within 1.5× of the resident memory they add, a frame's copy of them
/// included. (After the first batch alone the server has grown by about 18 MiB more than the
/// 10 MiB its lights count, which the later batches reuse: 0.36×, the fixed cost of parsing a
/// 9 MB batch that the allocator keeps.)
#[test]
fn lights_count_the_memory_they_hold() {
    let server = Server::start();
    let counted = |server: &Server| {
        let (status, body) = server.request("GET", "/scenes/1", "application/json", b"");
        assert_eq!(status, 200, "{body}");
        let info: serde_json::Value = serde_json::from_str(&body[body.find('{').unwrap()..]).unwrap();
        info["memory_bytes"].as_f64().unwrap() / (1 << 20) as f64
    };
    let (before, counted_before) = (resident_mib(&server), counted(&server));
    let commands: Vec<serde_json::Value> =
        (0..100_000).map(|k| serde_json::json!({ "add_light": { "class": "PointLight", "position": [k as f32 * 1e-3, 3, 4], "intensity": 1e-3 } })).collect();
    let batch = serde_json::to_vec(&serde_json::json!({ "commands": commands })).unwrap();
    for _ in 0..3 {
        let (status, body) = server.request("POST", "/scenes/1/commands", "application/json", &batch);
        assert_eq!(status, 200, "{body}");
    }
    let (status, body) = server.request("GET", "/scenes/1/frame.png?width=8&height=8&integrator=eyelight", "application/json", b"");
    assert_eq!(status, 200, "{body}");
    let (grown, counted) = (resident_mib(&server) - before, counted(&server) - counted_before);
    let ratio = counted / grown;
    assert!((1.0 / 1.5..=1.5).contains(&ratio), "the lights count {counted:.1} MiB and the server grew by {grown:.1} MiB: {ratio:.2}×");
}

/// Finished render jobs count what they hold: sixteen path-traced 1024×1024 frames of the Cornell
/// box at 2 samples per pixel, noisy PNGs of about 3 MB each kept until fetched (and counted
/// against `max_job_image_bytes`), are within 1.5× of the resident memory they add once
/// rendered, the films they were rendered into given back (without that: 0.54×). Eight leave
/// 0.64×: about 13 MiB beyond their images stays with the first renders, whatever their number.
#[test]
fn finished_render_jobs_count_the_memory_they_hold() {
    let server = Server::start();
    let (status, body) = server.request("POST", "/scenes", "application/json", br#"{"demo": "cornell"}"#);
    assert_eq!(status, 201, "{body}");
    let json = |body: &str| serde_json::from_str::<serde_json::Value>(&body[body.find('{').unwrap()..]).unwrap();
    // The render threads and the scene's tree come with the first frame: before the measure.
    let (status, _) = server.request("GET", "/scenes/2/frame.png?width=64&height=64&integrator=path", "application/json", b"");
    assert_eq!(status, 200);
    let before = resident_mib(&server);
    let ids: Vec<u64> = (0..16)
        .map(|_| {
            let (status, body) = server.request("POST", "/scenes/2/renders?width=1024&height=1024&integrator=path&spp=2", "application/json", b"");
            assert_eq!(status, 202, "{body}");
            json(&body)["id"].as_u64().unwrap()
        })
        .collect();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(300);
    for id in &ids {
        while json(&server.request("GET", &format!("/renders/{id}"), "application/json", b"").1)["status"] != "done" {
            assert!(std::time::Instant::now() < deadline, "render job {id} did not finish");
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
    }
    let grown = resident_mib(&server) - before;
    let counted: f64 = ids
        .iter()
        .map(|id| {
            let (status, response) = server.request("GET", &format!("/renders/{id}/image.png"), "application/json", b"");
            assert_eq!(status, 200);
            let length = response.lines().find_map(|l| l.to_ascii_lowercase().strip_prefix("content-length:").map(|v| v.trim().parse::<f64>().unwrap()));
            length.expect("the image's length")
        })
        .sum::<f64>()
        / (1 << 20) as f64;
    let ratio = counted / grown;
    assert!((1.0 / 1.5..=1.5).contains(&ratio), "the jobs' images count {counted:.1} MiB and the server grew by {grown:.1} MiB: {ratio:.2}×");
}

/// What a scene counts (`memory_bytes`, which the budgets are checked against) is what it
/// holds: a file of 200,000 nodes (the case that once grew the server by hundreds of megabytes
/// while its scene counted a few hundred bytes) is within 1.5× of the resident memory it adds,
/// either way, once a frame has built the trees it counts for.
#[test]
fn a_scene_of_many_instances_counts_the_memory_it_holds() {
    let server = Server::start();
    let before = resident_mib(&server);
    let (status, body) = server.request("POST", "/scenes", "model/gltf-binary", &many_nodes_glb(200_000));
    assert_eq!(status, 201, "{body}");
    let json = &body[body.find('{').unwrap()..];
    let info: serde_json::Value = serde_json::from_str(json).unwrap();
    assert_eq!(info["instances"], 200_000);
    let (status, body) = server.request("GET", "/scenes/2/frame.png?width=64&height=64&integrator=eyelight", "application/json", b"");
    assert_eq!(status, 200, "{body}");
    let counted = info["memory_bytes"].as_f64().unwrap() / (1 << 20) as f64;
    let grown = resident_mib(&server) - before;
    let ratio = counted / grown;
    assert!((1.0 / 1.5..=1.5).contains(&ratio), "the scene counts {counted:.1} MiB and the server grew by {grown:.1} MiB: {ratio:.2}×");
}
