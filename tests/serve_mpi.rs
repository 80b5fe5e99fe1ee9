//! `mpirun -n N raystage serve --mpi` end to end (built with the `mpi` feature): over HTTP,
//! the same edits and frames as a single `raystage serve`, and the same PNG bytes back,
//! rendered by every rank (the frame's statistics say so); a worker that stops answering is
//! given up within `--mpi-timeout` and rank 0 serves alone; a worker killed ends the job with
//! an error naming it, never a hang.

#![cfg(feature = "mpi")]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

mod common;

/// A server process: one `raystage serve`, or `mpirun` running one per rank.
struct Server {
    child: Child,
    addr: String,
}

impl Server {
    /// Starts `raystage serve` on a free loopback port, on `ranks` MPI ranks if given (one
    /// thread each, within the machine's two cores), with `args` after `serve`.
    fn start(ranks: Option<u32>, args: &[&str]) -> Server {
        let mut command = match ranks {
            None => Command::new(env!("CARGO_BIN_EXE_raystage")),
            Some(n) => {
                let mut command = common::mpirun();
                command.env("RAYON_NUM_THREADS", "1").args(["-n", &n.to_string()]).arg(env!("CARGO_BIN_EXE_raystage"));
                command
            }
        };
        command.arg("serve").args(["--addr", "127.0.0.1:0"]).args(args).env_remove("RAYSTAGE_TOKEN");
        if ranks.is_some() {
            command.arg("--mpi");
        }
        let mut child = command.stdout(Stdio::piped()).spawn().expect("the server starts");
        let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
        let addr = loop {
            let line = lines.next().expect("the server names its address before it ends").unwrap();
            if let Some(rest) = line.split("http://").nth(1) {
                break rest.split('/').next().unwrap().to_string();
            }
        };
        // The rest of its log is read (and dropped) so that the server never waits on a pipe.
        std::thread::spawn(move || lines.for_each(drop));
        Server { child, addr }
    }

    /// Sends a request; returns the status and the body.
    fn request(&self, method: &str, path: &str, content_type: &str, body: &[u8]) -> (u16, Vec<u8>) {
        let mut stream = TcpStream::connect(&self.addr).unwrap();
        stream.set_read_timeout(Some(Duration::from_secs(120))).unwrap();
        let head = format!(
            "{method} {path} HTTP/1.1\r\nHost: {}\r\nContent-Type: {content_type}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
            self.addr,
            body.len()
        );
        stream.write_all(head.as_bytes()).unwrap();
        stream.write_all(body).unwrap();
        let mut response = Vec::new();
        stream.read_to_end(&mut response).unwrap();
        let split = response.windows(4).position(|w| w == b"\r\n\r\n").expect("a response has a head");
        let status = String::from_utf8_lossy(&response[9..12]).parse().unwrap();
        (status, response[split + 4..].to_vec())
    }

    /// A JSON request that must answer `expected`; returns the body as JSON.
    fn json(&self, method: &str, path: &str, body: &str, expected: u16) -> serde_json::Value {
        let (status, bytes) = self.request(method, path, "application/json", body.as_bytes());
        assert_eq!(status, expected, "{method} {path}: {}", String::from_utf8_lossy(&bytes));
        serde_json::from_slice(&bytes).unwrap()
    }

    /// A frame's PNG.
    fn png(&self, path: &str) -> Vec<u8> {
        let (status, bytes) = self.request("GET", path, "application/json", b"");
        assert_eq!(status, 200, "{path}: {}", String::from_utf8_lossy(&bytes));
        bytes
    }

    /// The process of rank `rank` of the job: a child of `mpirun` with that rank.
    fn rank(&self, rank: u32) -> u32 {
        let parent = |pid: u32| {
            let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
            stat.rsplit(") ").next()?.split_whitespace().nth(1)?.parse::<u32>().ok()
        };
        let pids = std::fs::read_dir("/proc").unwrap().filter_map(|e| e.ok()?.file_name().to_str()?.parse::<u32>().ok());
        pids.into_iter().find(|&pid| parent(pid) == Some(self.child.id()) && rank_of(pid) == Some(rank)).expect("the rank runs")
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        // mpirun ends its ranks on SIGTERM (a SIGKILL would orphan them).
        let _ = Command::new("kill").args(["-TERM", &self.child.id().to_string()]).stderr(Stdio::null()).status();
        let start = Instant::now();
        while self.child.try_wait().ok().flatten().is_none() && start.elapsed() < Duration::from_secs(10) {
            std::thread::sleep(Duration::from_millis(50));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Scene `s`'s frames by every integrator: the same bytes from both servers, the second's
/// rendered by its `ranks` ranks.
fn same_frames(alone: &Server, many: &Server, ranks: u32, s: u64, what: &str) {
    for integrator in ["eyelight", "whitted", "distribution", "path"] {
        let path = format!("/scenes/{s}/frame.png?width=64&height=40&spp=3&integrator={integrator}");
        assert!(alone.png(&path) == many.png(&path), "{what}, {integrator}: {ranks} ranks rendered other bytes");
        let stats = many.json("GET", &format!("/scenes/{s}/stats"), "", 200);
        assert_eq!(stats["last_frame"]["cluster"]["ranks"], ranks, "{what}, {integrator}: {stats}");
    }
}

/// The same request to both servers, answered alike.
fn both(alone: &Server, many: &Server, method: &str, path: &str, body: &str, expected: u16) -> serde_json::Value {
    let one = alone.json(method, path, body, expected);
    assert_eq!(one, many.json(method, path, body, expected), "{method} {path}");
    one
}

#[test]
fn a_server_on_two_and_three_ranks_answers_and_renders_as_one_process_does() {
    let png = {
        let mut file = Vec::new();
        let checker = image::RgbImage::from_fn(4, 4, |x, y| if (x + y) % 2 == 0 { image::Rgb([250, 20, 20]) } else { image::Rgb([20, 20, 250]) });
        checker.write_to(&mut std::io::Cursor::new(&mut file), image::ImageFormat::Png).unwrap();
        file
    };
    // The command line's glTF file as a GLB (an upload carries its buffers).
    let gltf = {
        let path = common::write_gltf();
        let bin = path.with_extension("bin");
        let uri = format!(r#", "uri": "{}""#, bin.file_name().unwrap().to_str().unwrap());
        let document = std::fs::read_to_string(&path).unwrap().replace(&uri, "");
        raystage_gltf_import::glb(document.as_bytes(), &std::fs::read(&bin).unwrap())
    };
    for ranks in [2, 3] {
        let (alone, many) = (Server::start(None, &["--demo", "cornell"]), Server::start(Some(ranks), &["--demo", "cornell"]));
        // The scene of the command line, on every rank.
        same_frames(&alone, &many, ranks, 1, "the command line's scene");
        // Edits: the camera, a batch, moved vertices, an image texture on the new square.
        both(&alone, &many, "PUT", "/scenes/1/camera", r#"{"fov_y_degrees": 50}"#, 200);
        let batch = r#"{"commands": [
            {"add_shader": {"label": "green", "class": "Phong", "params": {"diffuse": [0, 0.8, 0]}}},
            {"add_object": {"label": "square", "kind": "unstructured", "mesh": {"positions": [[-0.2, -0.2, 0.5], [0.2, -0.2, 0.5], [0.2, 0.2, 0.5], [-0.2, 0.2, 0.5]], "indices": [[0, 1, 2], [0, 2, 3]], "shader": "green"}}},
            {"add_instance": {"object": "square", "transform": {"translate": [0, 0.5, 0]}}}
        ]}"#;
        let result = both(&alone, &many, "POST", "/scenes/1/commands", batch, 200);
        let (shader, object) = (&result["results"][0]["id"], &result["results"][1]["id"]);
        let moved = r#"{"positions": [[-0.3, -0.1, 0.4], [0.2, -0.2, 0.5], [0.2, 0.3, 0.5], [-0.2, 0.2, 0.6]]}"#;
        both(&alone, &many, "PATCH", &format!("/scenes/1/objects/{object}"), moved, 200);
        for server in [&alone, &many] {
            assert_eq!(server.request("POST", "/scenes/1/textures", "image/png", &png).0, 201);
        }
        let textured = r#"{"params": {"diffuse": 1, "diffuse_texture": {"texture": 0}}}"#;
        both(&alone, &many, "PATCH", &format!("/scenes/1/shaders/{shader}"), textured, 200);
        same_frames(&alone, &many, ranks, 1, "the room after edits");
        // A glTF file as a new scene; an animated demo at two frames.
        for server in [&alone, &many] {
            let (status, body) = server.request("POST", "/scenes", "model/gltf-binary", &gltf);
            assert_eq!(status, 201, "{}", String::from_utf8_lossy(&body));
        }
        same_frames(&alone, &many, ranks, 2, "a glTF file");
        for (s, frame) in [(3, 0), (4, 7)] {
            both(&alone, &many, "POST", "/scenes", &format!(r#"{{"demo": "robots", "frame": {frame}}}"#), 201);
            same_frames(&alone, &many, ranks, s, &format!("robots at frame {frame}"));
        }
    }
}

#[test]
fn a_worker_that_stops_answering_is_given_up_and_rank_0_serves_alone() {
    let many = Server::start(Some(2), &["--demo", "cornell", "--mpi-timeout", "2"]);
    let alone = Server::start(None, &["--demo", "cornell"]);
    let path = "/scenes/1/frame.png?width=48&height=32&spp=2&integrator=path";
    assert!(many.png(path) == alone.png(path));
    // The worker stopped (SIGSTOP: alive, answering nothing).
    let worker = many.rank(1);
    assert!(Command::new("kill").args(["-STOP", &worker.to_string()]).status().unwrap().success());
    let start = Instant::now();
    assert!(many.png(path) == alone.png(path), "rank 0 renders the same image alone");
    assert!(start.elapsed() < Duration::from_secs(30), "given up within the timeout: {:?}", start.elapsed());
    let stats = many.json("GET", "/scenes/1/stats", "", 200);
    assert!(stats["last_frame"]["cluster"].is_null(), "rank 0 rendered it alone: {stats}");
    both(&alone, &many, "PUT", "/scenes/1/camera", r#"{"fov_y_degrees": 30}"#, 200);
    assert!(many.png(path) == alone.png(path));
    let _ = Command::new("kill").args(["-CONT", &worker.to_string()]).status();
}

/// The MPI rank of process `pid` (Open MPI's `OMPI_COMM_WORLD_RANK` in its environment).
fn rank_of(pid: u32) -> Option<u32> {
    let environ = std::fs::read(format!("/proc/{pid}/environ")).ok()?;
    environ.split(|&b| b == 0).find_map(|v| std::str::from_utf8(v).ok()?.strip_prefix("OMPI_COMM_WORLD_RANK=")?.parse().ok())
}

#[test]
fn a_worker_killed_ends_the_job_with_an_error() {
    let mut many = Server::start(Some(2), &["--demo", "cornell"]);
    many.json("GET", "/scenes/1", "", 200);
    let worker = many.rank(1);
    assert!(Command::new("kill").args(["-KILL", &worker.to_string()]).status().unwrap().success());
    let start = Instant::now();
    let status = loop {
        if let Some(status) = many.child.try_wait().unwrap() {
            break status;
        }
        assert!(start.elapsed() < Duration::from_secs(60), "the job still runs a minute after its worker was killed: hung");
        std::thread::sleep(Duration::from_millis(50));
    };
    assert!(!status.success(), "mpirun reports the lost rank in its status");
    assert!(TcpStream::connect(&many.addr).is_err(), "rank 0 is gone with the job: nothing half-served");
}
