//! `raystage view`'s stream settings: `--integrator` and `--max-samples` are what the viewer's
//! stream starts with (seen from the in-process server's statistics, the window under a virtual
//! X server), and values the stream would refuse are refused before a window opens.
//!
//! The window test is skipped with a message where `xvfb-run` is not installed (`scripts/test.sh`
//! installs the `xvfb` package as root); on CI (`CI` set) a missing one is a failure.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::os::unix::process::CommandExt;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// `raystage view` and the virtual X server it runs under, started as a process group of their
/// own and ended together when dropped.
struct Viewer(Child);

impl Drop for Viewer {
    fn drop(&mut self) {
        // xvfb-run's children (Xvfb, raystage) are in the group: end them all.
        let _ = Command::new("kill").args(["-TERM", "--", &format!("-{}", self.0.id())]).status();
        let _ = self.0.wait();
    }
}

/// The body of `GET path` from the server at `addr`.
fn get(addr: &str, path: &str) -> String {
    let mut stream = TcpStream::connect(addr).unwrap();
    write!(stream, "GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n").unwrap();
    let mut response = String::new();
    stream.read_to_string(&mut response).unwrap();
    response.split_once("\r\n\r\n").map(|(_, body)| body.to_string()).unwrap_or_default()
}

#[test]
fn the_stream_starts_with_the_integrator_and_samples_asked_for() {
    if Command::new("xvfb-run").arg("--help").stdout(Stdio::null()).stderr(Stdio::null()).status().is_err() {
        assert!(std::env::var_os("CI").is_none(), "xvfb-run is missing on CI: scripts/test.sh installs the `xvfb` package as root");
        eprintln!("skipped: no xvfb-run (install the `xvfb` package to run the window test)");
        return;
    }
    let mut child = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x768x24 -nolisten tcp", env!("CARGO_BIN_EXE_raystage")])
        .args(["view", "--demo", "cornell", "--integrator", "path", "--max-samples", "3"])
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::piped())
        .process_group(0)
        .spawn()
        .unwrap();
    let stdout = child.stdout.take().unwrap();
    let _viewer = Viewer(child);
    let banner = BufReader::new(stdout).lines().map(|l| l.unwrap()).find(|l| l.starts_with("raystage serving")).expect("view names its server");
    let addr = banner.split("http://").nth(1).and_then(|rest| rest.split('/').next()).expect("the banner names the address").to_string();
    // The stream's frames are the scene's last frame: wait for one that has all its samples.
    let deadline = Instant::now() + Duration::from_secs(120);
    let frame = loop {
        let stats: serde_json::Value = serde_json::from_str(&get(&addr, "/scenes/1/stats")).unwrap();
        let frame = &stats["last_frame"];
        if frame["accumulated_samples"] == 3 {
            break frame.clone();
        }
        assert!(frame["accumulated_samples"].as_u64().unwrap_or(0) <= 3, "{frame}");
        assert!(Instant::now() < deadline, "the viewer's stream did not reach 3 samples per pixel: {stats}");
        std::thread::sleep(Duration::from_millis(100));
    };
    assert_eq!(frame["integrator"], "path", "{frame}");
    // Converged: the stream stops there (it would refine on towards the default of 256).
    std::thread::sleep(Duration::from_secs(2));
    let stats: serde_json::Value = serde_json::from_str(&get(&addr, "/scenes/1/stats")).unwrap();
    assert_eq!(stats["last_frame"]["accumulated_samples"], 3, "{stats}");
}

#[test]
fn samples_the_stream_would_refuse_are_refused_before_a_window_opens() {
    for samples in ["0", "4097"] {
        // No display: an error about the window would mean the check came too late.
        let output = Command::new(env!("CARGO_BIN_EXE_raystage"))
            .args(["view", "--demo", "cornell", "--max-samples", samples])
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success() && stderr.contains(&format!("--max-samples {samples} is not in 1..=4096")), "{stderr}");
    }
    let output = Command::new(env!("CARGO_BIN_EXE_raystage")).args(["view", "--demo", "cornell", "--integrator", "photon"]).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success() && stderr.contains("invalid value 'photon'") && stderr.contains("path"), "{stderr}");
}
