//! Headless Chromium over the Chrome DevTools Protocol: one flattened session per tab.

use std::path::Path;
use std::process::{Child, Command};
use std::sync::Arc;

use base64::Engine;
use serde_json::{Value, json};

use super::connection::{Connection, launch};
use super::{Button, Pointer};

/// Starts Chromium with `profile` as its user data directory.
pub async fn start(executable: &Path, profile: &Path) -> (Child, Arc<Connection>) {
    let mut command = Command::new(executable);
    command
        .args(["--headless", "--disable-gpu", "--no-first-run", "--no-default-browser-check", "--disable-extensions", "--disable-background-networking", "--disable-sync"])
        // Chromium's sandbox refuses to run as root, as CI does.
        .arg("--no-sandbox")
        .arg("--remote-debugging-port=0")
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("about:blank");
    let (process, url) = launch(command, "DevTools listening on ");
    (process, Connection::connect(&url).await)
}

/// A tab, attached to by a session of its own.
pub struct Tab {
    devtools: Arc<Connection>,
    session: String,
}

impl Tab {
    /// A new tab with the given viewport, on `about:blank`.
    pub async fn open(devtools: &Arc<Connection>, width: u32, height: u32, scale: f64) -> Tab {
        let target = call(devtools, None, "Target.createTarget", json!({ "url": "about:blank" })).await;
        let attached = call(devtools, None, "Target.attachToTarget", json!({ "targetId": target["targetId"], "flatten": true })).await;
        let tab = Tab { devtools: devtools.clone(), session: attached["sessionId"].as_str().unwrap().to_string() };
        for domain in ["Runtime.enable", "Log.enable", "Page.enable"] {
            tab.call(domain, json!({})).await;
        }
        tab.set_viewport(width, height, scale).await;
        tab
    }

    async fn call(&self, method: &str, params: Value) -> Value {
        call(&self.devtools, Some(&self.session), method, params).await
    }

    /// Loads `url`; the caller waits for it to be complete.
    pub async fn navigate(&self, url: &str) {
        self.call("Page.navigate", json!({ "url": url })).await;
    }

    pub async fn set_viewport(&self, width: u32, height: u32, scale: f64) {
        self.call("Emulation.setDeviceMetricsOverride", json!({ "width": width, "height": height, "deviceScaleFactor": scale, "mobile": false })).await;
    }

    pub async fn eval(&self, expression: &str) -> Value {
        let result = self.call("Runtime.evaluate", json!({ "expression": expression, "awaitPromise": true, "returnByValue": true })).await;
        assert!(result.get("exceptionDetails").is_none(), "{expression}: {}", result["exceptionDetails"]);
        result["result"]["value"].clone()
    }

    /// Console errors, uncaught exceptions, and the browser's own error log (failed loads,
    /// refusals by the Content-Security-Policy).
    pub fn errors(&self) -> Vec<String> {
        let events = self.devtools.events();
        let mine = events.iter().filter(|e| e["sessionId"] == self.session.as_str());
        mine.filter_map(|e| {
            let p = &e["params"];
            match e["method"].as_str()? {
                "Runtime.consoleAPICalled" if p["type"] == "error" || p["type"] == "assert" => Some(format!("console: {}", p["args"])),
                "Runtime.exceptionThrown" => Some(format!("exception: {}", p["exceptionDetails"])),
                "Log.entryAdded" if p["entry"]["level"] == "error" => Some(format!("log: {} {}", p["entry"]["text"], p["entry"]["url"])),
                _ => None,
            }
        })
        .collect()
    }

    pub async fn screenshot(&self) -> Vec<u8> {
        let shot = self.call("Page.captureScreenshot", json!({ "format": "png" })).await;
        base64::engine::general_purpose::STANDARD.decode(shot["data"].as_str().unwrap()).unwrap()
    }

    pub async fn pointer(&self, action: Pointer, (x, y): (f64, f64), button: Button) {
        let (kind, buttons) = match action {
            Pointer::Press => ("mousePressed", button.mask()),
            Pointer::Move => ("mouseMoved", button.mask()),
            Pointer::Release => ("mouseReleased", 0),
        };
        let button = match button {
            Button::Left => "left",
            Button::Right => "right",
        };
        self.call("Input.dispatchMouseEvent", json!({ "type": kind, "x": x, "y": y, "button": button, "buttons": buttons, "clickCount": 1 })).await;
    }

    /// Drags the file at `path` from outside the browser onto (x, y), as a person drops one
    /// from a file manager.
    pub async fn drop_file(&self, (x, y): (f64, f64), path: &Path) {
        let data = json!({ "items": [], "files": [path.to_str().unwrap()], "dragOperationsMask": 1 });
        for kind in ["dragEnter", "dragOver", "drop"] {
            self.call("Input.dispatchDragEvent", json!({ "type": kind, "x": x, "y": y, "data": data })).await;
        }
    }

    /// Types `text` into the focused element.
    pub async fn type_text(&self, text: &str) {
        self.call("Input.insertText", json!({ "text": text })).await;
    }
}

/// Runs `method` (in the tab of `session`, or the browser's); its result.
async fn call(devtools: &Connection, session: Option<&str>, method: &str, params: Value) -> Value {
    let mut message = json!({ "method": method, "params": params });
    if let Some(session) = session {
        message["sessionId"] = json!(session);
    }
    let reply = devtools.send(message).await;
    assert!(reply.get("error").is_none(), "{method}: {}", reply["error"]);
    reply["result"].clone()
}
