//! The real window under a virtual X server (Xvfb, Mesa's software OpenGL): the client binary
//! connects to a server, shows a streamed frame, saves a screenshot of itself and exits; the
//! screenshot must show the Cornell room's red and green walls.
//!
//! Skipped with a message where `Xvfb` is not installed (`scripts/test.sh` installs it when run
//! as root); on CI (`CI` set) a missing Xvfb is a failure.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

mod common;

/// A virtual X server on a free display, killed when dropped.
struct Xvfb {
    child: Child,
    display: String,
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn find_in_path(name: &str) -> Option<PathBuf> {
    std::env::split_paths(&std::env::var_os("PATH")?).map(|dir| dir.join(name)).find(|p| p.is_file())
}

/// Starts Xvfb on the first display from a number of this process's own that is free.
fn start_xvfb(binary: &Path) -> Xvfb {
    let first = 100 + std::process::id() % 500;
    for n in first..first + 50 {
        if Path::new(&format!("/tmp/.X{n}-lock")).exists() || Path::new(&format!("/tmp/.X11-unix/X{n}")).exists() {
            continue;
        }
        let mut child = Command::new(binary)
            .args([format!(":{n}").as_str(), "-screen", "0", "1024x768x24", "-nolisten", "tcp"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb starts");
        let socket = PathBuf::from(format!("/tmp/.X11-unix/X{n}"));
        let deadline = Instant::now() + Duration::from_secs(10);
        while Instant::now() < deadline {
            if socket.exists() {
                return Xvfb { child, display: format!(":{n}") };
            }
            if child.try_wait().ok().flatten().is_some() {
                // Lost a race for this display: try the next.
                break;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = child.kill();
        let _ = child.wait();
    }
    panic!("Xvfb did not start on any display from :{first}");
}

#[test]
fn the_window_shows_a_streamed_frame() {
    let Some(xvfb) = find_in_path("Xvfb") else {
        assert!(std::env::var_os("CI").is_none(), "Xvfb is missing on CI: scripts/test.sh installs the `xvfb` package as root");
        eprintln!("skipped: no Xvfb (install the `xvfb` package to run the window test)");
        return;
    };
    let (_runtime, url) = common::server();
    let x = start_xvfb(&xvfb);
    let shot = std::env::temp_dir().join(format!("raystage-client-window-{}.png", std::process::id()));
    let _ = std::fs::remove_file(&shot);

    let mut client = Command::new(env!("CARGO_BIN_EXE_raystage-client"))
        .args(["--server", &url, "--scene", "1", "--integrator", "eyelight", "--width", "800", "--height", "500"])
        .arg("--screenshot")
        .arg(&shot)
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the client starts");
    let deadline = Instant::now() + Duration::from_secs(60);
    let status = loop {
        if let Some(status) = client.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            let _ = client.kill();
            let output = client.wait_with_output().unwrap();
            panic!("the client did not exit within 60 s: {}", String::from_utf8_lossy(&output.stderr));
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let output = client.wait_with_output().unwrap();
    assert!(status.success(), "the client failed ({status}): {}", String::from_utf8_lossy(&output.stderr));

    let image = image::open(&shot).expect("the screenshot is a PNG").to_rgba8();
    assert_eq!(image.dimensions(), (800, 500), "the window's size");
    // The view is left of the side panel (270 points wide by default).
    let view: Vec<_> = (0..500).flat_map(|y| (0..500).map(move |x| (x, y))).map(|(x, y)| image.get_pixel(x, y).0).collect();
    let red = view.iter().filter(|p| i32::from(p[0]) > i32::from(p[1]) + 50).count();
    let green = view.iter().filter(|p| i32::from(p[1]) > i32::from(p[0]) + 30).count();
    let n = view.len();
    assert!(red > n / 50 && green > n / 50, "the Cornell room's walls: red {red}, green {green} of {n} pixels ({})", shot.display());
    let _ = std::fs::remove_file(&shot);
}
