//! `raystage serve` end to end: the binary listens on loopback and answers; a public address
//! without a token is refused before anything listens.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};

#[test]
fn serves_on_loopback_with_a_demo_scene_loaded() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_raystage"))
        .args(["serve", "--addr", "127.0.0.1:0", "--demo", "cornell"])
        .env_remove("RAYSTAGE_TOKEN")
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    assert_eq!(lines.next().unwrap().unwrap(), "scene 1: cornell");
    let banner = lines.next().unwrap().unwrap();
    let addr = banner.split("http://").nth(1).and_then(|rest| rest.split('/').next()).expect("the banner names the address").to_string();
    let mut stream = TcpStream::connect(&addr).unwrap();
    write!(stream, "GET /scenes/1 HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n").unwrap();
    let mut response = String::new();
    stream.read_to_string(&mut response).unwrap();
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(response.starts_with("HTTP/1.1 200"), "{response}");
    assert!(response.contains(r#""origin":"cornell""#), "{response}");
}

#[test]
fn a_public_address_needs_a_token() {
    let output = Command::new(env!("CARGO_BIN_EXE_raystage")).args(["serve", "--addr", "0.0.0.0:0"]).env_remove("RAYSTAGE_TOKEN").output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success() && stderr.contains("refusing to serve on 0.0.0.0:0 without a token"), "{stderr}");
}
