//! Headless Firefox over WebDriver BiDi, which Firefox speaks itself (no geckodriver): one
//! session for the browser, a browsing context for each tab. Script results come back as
//! JSON text made in the page, so that they read as the DevTools protocol's values by value do.

use std::path::Path;
use std::process::{Child, Command};
use std::sync::Arc;

use base64::Engine;
use serde_json::{Value, json};

use super::connection::{Connection, launch};
use super::{Button, Pointer};

/// Starts Firefox with `profile` as its profile, and opens a BiDi session that hears of the
/// pages' console entries and responses.
pub async fn start(executable: &Path, profile: &Path) -> (Child, Arc<Connection>) {
    let mut command = Command::new(executable);
    // Port 0: the system picks a free one, which Firefox names on stderr. (`--remote-debugging-port`
    // turns on the remote agent, and with it the preferences automation needs: no first-run
    // pages, no updates, no telemetry.)
    command.args(["--headless", "--no-remote", "--remote-debugging-port", "0", "--profile"]).arg(profile).arg("about:blank");
    let (process, address) = launch(command, "WebDriver BiDi listening on ");
    let bidi = Connection::connect(&format!("{address}/session")).await;
    call(&bidi, "session.new", json!({ "capabilities": {} })).await;
    call(&bidi, "session.subscribe", json!({ "events": ["log.entryAdded", "network.responseCompleted"] })).await;
    (process, bidi)
}

/// A tab: a top-level browsing context.
pub struct Tab {
    bidi: Arc<Connection>,
    context: String,
}

impl Tab {
    /// A new tab, in front (a tab behind would be throttled), with the given viewport.
    pub async fn open(bidi: &Arc<Connection>, width: u32, height: u32, scale: f64) -> Tab {
        let created = call(bidi, "browsingContext.create", json!({ "type": "tab" })).await;
        let tab = Tab { bidi: bidi.clone(), context: created["context"].as_str().unwrap().to_string() };
        tab.set_viewport(width, height, scale).await;
        tab
    }

    async fn call(&self, method: &str, mut params: Value) -> Value {
        params["context"] = json!(self.context);
        call(&self.bidi, method, params).await
    }

    /// Loads `url`, up to its `load` event.
    pub async fn navigate(&self, url: &str) {
        self.call("browsingContext.navigate", json!({ "url": url, "wait": "complete" })).await;
    }

    pub async fn set_viewport(&self, width: u32, height: u32, scale: f64) {
        self.call("browsingContext.setViewport", json!({ "viewport": { "width": width, "height": height }, "devicePixelRatio": scale })).await;
    }

    pub async fn eval(&self, expression: &str) -> Value {
        // (`undefined` has no JSON; it reads as null, as it does by value over DevTools.)
        let json = format!("Promise.resolve((\n{expression}\n)).then((value) => JSON.stringify(value) ?? 'null')");
        let params = json!({ "expression": json, "target": { "context": self.context }, "awaitPromise": true, "resultOwnership": "none" });
        let result = call(&self.bidi, "script.evaluate", params).await;
        assert_eq!(result["type"], "success", "{expression}: {}", result["exceptionDetails"]);
        serde_json::from_str(result["result"]["value"].as_str().unwrap()).unwrap()
    }

    /// Console errors and uncaught exceptions, and responses with an error status (which the
    /// DevTools protocol's log names, and BiDi's does not).
    pub fn errors(&self) -> Vec<String> {
        let events = self.bidi.events();
        events
            .iter()
            .filter_map(|e| {
                let p = &e["params"];
                match e["method"].as_str()? {
                    "log.entryAdded" if p["source"]["context"] == self.context.as_str() && p["level"] == "error" => Some(format!("{}: {}", p["type"].as_str()?, p["text"])),
                    "network.responseCompleted" if p["context"] == self.context.as_str() && p["response"]["status"].as_u64()? >= 400 => {
                        Some(format!("network: {} {}", p["response"]["status"], p["response"]["url"]))
                    }
                    _ => None,
                }
            })
            .collect()
    }

    pub async fn screenshot(&self) -> Vec<u8> {
        let shot = self.call("browsingContext.captureScreenshot", json!({})).await;
        base64::engine::general_purpose::STANDARD.decode(shot["data"].as_str().unwrap()).unwrap()
    }

    pub async fn pointer(&self, action: Pointer, (x, y): (f64, f64), button: Button) {
        let button = match button {
            Button::Left => 0,
            Button::Right => 2,
        };
        let to = json!({ "type": "pointerMove", "x": x, "y": y, "origin": "viewport" });
        let steps = match action {
            Pointer::Press => vec![to, json!({ "type": "pointerDown", "button": button })],
            Pointer::Move => vec![to],
            Pointer::Release => vec![to, json!({ "type": "pointerUp", "button": button })],
        };
        let mouse = json!({ "type": "pointer", "id": "mouse", "parameters": { "pointerType": "mouse" }, "actions": steps });
        self.call("input.performActions", json!({ "actions": [mouse] })).await;
    }

    /// Drops the file at `path` on (x, y). BiDi cannot drag from outside the browser, so the
    /// page gets the events a drop makes, carrying the file, from a script.
    pub async fn drop_file(&self, (x, y): (f64, f64), path: &Path) {
        let bytes = base64::engine::general_purpose::STANDARD.encode(std::fs::read(path).unwrap());
        let name = path.file_name().unwrap().to_str().unwrap();
        self.eval(&format!(
            "(() => {{
                const data = new DataTransfer();
                data.items.add(new File([Uint8Array.from(atob('{bytes}'), (c) => c.charCodeAt(0))], '{name}'));
                const target = document.elementFromPoint({x}, {y});
                for (const type of ['dragenter', 'dragover', 'drop']) {{
                    target.dispatchEvent(new DragEvent(type, {{ bubbles: true, cancelable: true, clientX: {x}, clientY: {y}, dataTransfer: data }}));
                }}
            }})()"
        ))
        .await;
    }

    /// Types `text` into the focused element, a key at a time.
    pub async fn type_text(&self, text: &str) {
        let keys: Vec<Value> = text.chars().flat_map(|c| [json!({ "type": "keyDown", "value": c }), json!({ "type": "keyUp", "value": c })]).collect();
        self.call("input.performActions", json!({ "actions": [{ "type": "key", "id": "keyboard", "actions": keys }] })).await;
    }
}

/// Runs `method`; its result.
async fn call(bidi: &Connection, method: &str, params: Value) -> Value {
    let reply = bidi.send(json!({ "method": method, "params": params })).await;
    assert_eq!(reply["type"], "success", "{method}: {} {}", reply["error"], reply["message"]);
    reply["result"].clone()
}
