//! The front ends choose alike: the same scene with no integrator named gets the same integrator
//! and the same pixels from `raystage render`, the HTTP API and the C ABI, since each applies its
//! settings as a `SettingsPatch` and picks the integrator by `Integrator::default_for`.
//!
//! The command line reads scenes from files and the C ABI builds them call by call, so the HTTP
//! API, which does both, is each one's witness: it takes the command line's glTF file, and the
//! calls the C program makes as commands.

mod common;

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::process::Command;

use raystage_capi::abi::*;
use serde_json::{Value, json};

/// A server on a free loopback port, in this process, for as long as the test runs.
fn serve() -> SocketAddr {
    let runtime = tokio::runtime::Runtime::new().unwrap();
    let listener = runtime.block_on(tokio::net::TcpListener::bind("127.0.0.1:0")).unwrap();
    let addr = listener.local_addr().unwrap();
    let state = raystage_server::AppState::new(raystage_server::Config::default());
    std::thread::spawn(move || runtime.block_on(raystage_server::serve(listener, state, std::future::pending())));
    addr
}

/// A request's status line, headers and body.
fn request(addr: SocketAddr, method: &str, path: &str, content_type: &str, body: &[u8]) -> (String, Vec<u8>) {
    let mut stream = TcpStream::connect(addr).unwrap();
    let head = format!("{method} {path} HTTP/1.1\r\nHost: {addr}\r\nContent-Type: {content_type}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n", body.len());
    stream.write_all(head.as_bytes()).unwrap();
    stream.write_all(body).unwrap();
    let mut response = Vec::new();
    stream.read_to_end(&mut response).unwrap();
    let split = response.windows(4).position(|w| w == b"\r\n\r\n").expect("a head and a body");
    let head = String::from_utf8_lossy(&response[..split]).into_owned();
    assert!(head.starts_with("HTTP/1.1 2"), "{method} {path}: {head}\n{}", String::from_utf8_lossy(&response[split..]));
    (head, response[split + 4..].to_vec())
}

/// A JSON request's answer.
fn json(addr: SocketAddr, method: &str, path: &str, body: Value) -> Value {
    serde_json::from_slice(&request(addr, method, path, "application/json", body.to_string().as_bytes()).1).unwrap()
}

/// A frame as the HTTP API renders it: its integrator (`x-integrator`) and RGB pixels.
fn http_frame(addr: SocketAddr, path: &str) -> (String, Vec<u8>) {
    let (head, png) = request(addr, "GET", path, "application/json", b"");
    let integrator = head.lines().find_map(|l| l.strip_prefix("x-integrator: ")).expect("the frame names its integrator").to_string();
    (integrator, image::load_from_memory(&png).unwrap().to_rgb8().into_raw())
}

/// A grey quad (two triangles) before a camera, no lights, as a binary glTF file.
fn glb() -> Vec<u8> {
    let positions: [[f32; 3]; 6] = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]];
    let bin: Vec<u8> = positions.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    let document = json!({
        "asset": { "version": "2.0" },
        "buffers": [{ "byteLength": bin.len() }],
        "bufferViews": [{ "buffer": 0, "byteLength": bin.len() }],
        "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0] }],
        "materials": [{ "pbrMetallicRoughness": { "baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 0.5 } }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "material": 0 }] }],
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.9, "znear": 0.1 } }],
        "nodes": [{ "mesh": 0 }, { "camera": 0, "translation": [0.3, 0.2, 3] }],
        "scenes": [{ "nodes": [0, 1] }]
    });
    let mut text = document.to_string().into_bytes();
    text.resize(text.len().next_multiple_of(4), b' ');
    let mut file = Vec::new();
    let total = 12 + 8 + text.len() + 8 + bin.len();
    // The header (`glTF`, version 2, length), then the JSON chunk's length and type.
    for word in [0x4654_6C67u32, 2, total as u32, text.len() as u32, 0x4E4F_534A] {
        file.extend(word.to_le_bytes());
    }
    file.extend(&text);
    // The binary chunk's length and type (`BIN`).
    file.extend([(bin.len() as u32).to_le_bytes(), 0x004E_4942u32.to_le_bytes()].concat());
    file.extend(&bin);
    file
}

#[test]
fn the_command_line_and_the_http_api_choose_alike_for_a_file() {
    let file = common::temp("front-ends.glb");
    std::fs::write(&file, glb()).unwrap();
    let out = common::temp("front-ends.png");
    // One sample per pixel: at more, the command line renders in passes for its progress bar,
    // and a first pass of one sample looks through pixel centres, which the server's single pass
    // does not (a matter of the progress bar, not of the settings).
    let output = Command::new(env!("CARGO_BIN_EXE_raystage"))
        .args(["render", file.to_str().unwrap(), "--width", "24", "--height", "16", "--spp", "1", "--threads", "2", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{log}{}", String::from_utf8_lossy(&output.stderr));
    let cli_pixels = image::open(&out).unwrap().to_rgb8().into_raw();

    let addr = serve();
    let scene = json(addr, "POST", "/scenes", json!({}))["id"].as_u64().unwrap();
    request(addr, "POST", &format!("/scenes/{scene}/gltf"), "model/gltf-binary", &glb());
    let (integrator, http_pixels) = http_frame(addr, &format!("/scenes/{scene}/frame.png?width=24&height=16&spp=1"));

    // The file has no lights: both light it with the studio, which is path traced.
    assert_eq!(integrator, "path");
    assert!(log.contains(" path at 1 spp "), "{log}");
    assert!(cli_pixels == http_pixels, "the command line and the HTTP API rendered different images");
}

#[test]
fn the_c_abi_and_the_http_api_choose_alike_for_a_scene_nothing_lights() {
    let (w, h) = (24, 16);
    let quad = [[-1.0f32, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]];

    // The C program: a grey diffuse quad, the default camera, no lights, RT_AUTO.
    let class = rtGenShaderClasses(1);
    unsafe { rtNewShaderClass(class, c"Diffuse".as_ptr(), std::ptr::null()) };
    let grey = rtGenShaders(1);
    rtNewShader(grey);
    rtParameter3f(unsafe { rtParameterHandle(c"diffuse".as_ptr()) }, 0.5, 0.5, 0.5);
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBindShader(grey);
    rtBegin(RT_QUADS);
    for [x, y, z] in quad {
        rtVertex3f(x, y, z);
    }
    rtEnd();
    rtEndObject();
    rtInstantiateObject(object);
    let mut rgba = vec![0u8; w * h * 4];
    unsafe { rtFrameBuffer(rgba.as_mut_ptr().cast(), w, h, RT_RGBA8) };
    rtSwapBuffers();
    assert_eq!(rtGetError(), RT_NO_ERROR);
    let c_pixels: Vec<u8> = rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();

    // The same scene through the HTTP API.
    let addr = serve();
    let scene = json(addr, "POST", "/scenes", json!({}))["id"].as_u64().unwrap();
    let shader = json(addr, "POST", &format!("/scenes/{scene}/shaders"), json!({ "class": "Diffuse", "params": { "diffuse": [0.5, 0.5, 0.5] } }));
    let mesh = json!({ "positions": quad, "indices": [[0, 1, 2], [0, 2, 3]], "shader": shader["id"] });
    let object = json(addr, "POST", &format!("/scenes/{scene}/objects"), json!({ "mesh": mesh }));
    json(addr, "POST", &format!("/scenes/{scene}/instances"), json!({ "object": object["id"] }));
    let frame = format!("/scenes/{scene}/frame.png?width={w}&height={h}");
    let (integrator, http_pixels) = http_frame(addr, &frame);

    // Nothing lights the scene but the default sky: Whitted's ray tracing, not the eye-light
    // preview the C ABI used to choose.
    assert_eq!(integrator, "whitted");
    let (_, preview) = http_frame(addr, &format!("{frame}&integrator=eyelight"));
    assert!(preview != http_pixels, "the preview and the sky-lit frame differ");
    assert!(c_pixels == http_pixels, "the C ABI and the HTTP API rendered different images");
}
