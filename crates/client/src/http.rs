//! The few HTTP requests the viewer makes (GETs of JSON resources, POSTs of an image file and
//! of a batch of commands), over plain HTTP/1.1.
//!
//! A handful of requests with JSON answers do not need an HTTP client library: one connection
//! per request (`Connection: close`), the body read to its end, `Content-Length` or chunked.

use std::time::Duration;

use serde::de::DeserializeOwned;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

use crate::Error;
use crate::protocol::ErrorBody;

/// How long one request may take.
const TIMEOUT: Duration = Duration::from_secs(30);
/// The largest body read (a scene of many instances lists them all).
const MAX_BODY: usize = 64 << 20;

/// Where a server is: `host:port`, and its token.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Server {
    /// `host:port`.
    pub authority: String,
    /// The bearer token, if the server needs one.
    pub token: Option<String>,
}

impl Server {
    /// A server from its URL (`http://host:port`, `ws://host:port`, or `host:port`; a path is
    /// not allowed, TLS is not supported).
    pub fn parse(url: &str, token: Option<String>) -> Result<Server, Error> {
        let rest = match url.split_once("://") {
            Some(("http" | "ws", rest)) => rest,
            Some((scheme, _)) => return Err(Error::Url(format!("{url}: the scheme `{scheme}` is not supported (use http://host:port)"))),
            None => url,
        };
        let authority = rest.trim_end_matches('/');
        if authority.is_empty() || authority.contains('/') {
            return Err(Error::Url(format!("{url}: expected http://host:port")));
        }
        let authority = if authority.rsplit_once(':').is_some_and(|(_, port)| port.parse::<u16>().is_ok()) && !authority.ends_with(']') {
            authority.to_string()
        } else {
            format!("{authority}:80")
        };
        Ok(Server { authority, token: token.filter(|t| !t.is_empty()) })
    }

    /// GETs `path` and reads the JSON body as `T`.
    pub async fn get<T: DeserializeOwned>(&self, path: &str) -> Result<T, Error> {
        self.request("GET", path, None).await
    }

    /// POSTs `body` of type `content_type` to `path` and reads the JSON answer as `T`.
    pub async fn post<T: DeserializeOwned>(&self, path: &str, content_type: &str, body: &[u8]) -> Result<T, Error> {
        self.request("POST", path, Some((content_type, body))).await
    }

    /// PUTs JSON `body` to `path` and reads the JSON answer as `T`.
    pub async fn put<T: DeserializeOwned>(&self, path: &str, body: &serde_json::Value) -> Result<T, Error> {
        self.request("PUT", path, Some(("application/json", body.to_string().as_bytes()))).await
    }

    /// Sends a request and reads a successful (2xx) answer's JSON body as `T`; the server's
    /// error message otherwise.
    async fn request<T: DeserializeOwned>(&self, method: &str, path: &str, body: Option<(&str, &[u8])>) -> Result<T, Error> {
        let (status, answer) = tokio::time::timeout(TIMEOUT, self.exchange(method, path, body))
            .await
            .map_err(|_| Error::Http(format!("{method} {path}: no answer in {} s", TIMEOUT.as_secs())))??;
        if !(200..300).contains(&status) {
            let message = match serde_json::from_slice::<ErrorBody>(&answer) {
                Ok(e) => e.error.message,
                Err(_) => String::from_utf8_lossy(&answer).chars().take(200).collect(),
            };
            return Err(Error::Http(format!("{method} {path}: {status} {message}")));
        }
        serde_json::from_slice(&answer).map_err(|e| Error::Http(format!("{method} {path}: unexpected answer: {e}")))
    }

    async fn exchange(&self, method: &str, path: &str, body: Option<(&str, &[u8])>) -> Result<(u16, Vec<u8>), Error> {
        let io = |e: std::io::Error| Error::Http(format!("{method} {path} at {}: {e}", self.authority));
        let mut stream = TcpStream::connect(&self.authority).await.map_err(io)?;
        let auth = self.token.as_deref().map(|t| format!("Authorization: Bearer {t}\r\n")).unwrap_or_default();
        let content = body.map(|(kind, bytes)| format!("Content-Type: {kind}\r\nContent-Length: {}\r\n", bytes.len())).unwrap_or_default();
        let head = format!("{method} {path} HTTP/1.1\r\nHost: {}\r\nAccept: application/json\r\n{auth}{content}Connection: close\r\n\r\n", self.authority);
        stream.write_all(head.as_bytes()).await.map_err(io)?;
        if let Some((_, bytes)) = body {
            stream.write_all(bytes).await.map_err(io)?;
        }
        let mut response = Vec::new();
        (&mut stream).take(MAX_BODY as u64 + 65536).read_to_end(&mut response).await.map_err(io)?;
        parse_response(&response).ok_or_else(|| Error::Http(format!("{method} {path}: not an HTTP response")))
    }
}

/// The status and body of a whole HTTP/1.1 response.
fn parse_response(response: &[u8]) -> Option<(u16, Vec<u8>)> {
    let end = response.windows(4).position(|w| w == b"\r\n\r\n")?;
    let head = std::str::from_utf8(&response[..end]).ok()?;
    let body = &response[end + 4..];
    let mut lines = head.split("\r\n");
    let status = lines.next()?.split(' ').nth(1)?.parse().ok()?;
    let mut chunked = false;
    let mut length = None;
    for line in lines {
        let (name, value) = line.split_once(':')?;
        let value = value.trim();
        if name.eq_ignore_ascii_case("content-length") {
            length = value.parse::<usize>().ok();
        } else if name.eq_ignore_ascii_case("transfer-encoding") && value.eq_ignore_ascii_case("chunked") {
            chunked = true;
        }
    }
    if chunked {
        let mut out = Vec::new();
        let mut rest = body;
        loop {
            let line_end = rest.windows(2).position(|w| w == b"\r\n")?;
            let size = std::str::from_utf8(&rest[..line_end]).ok()?.split(';').next()?.trim();
            let size = usize::from_str_radix(size, 16).ok()?;
            rest = &rest[line_end + 2..];
            if size == 0 {
                return Some((status, out));
            }
            out.extend_from_slice(rest.get(..size)?);
            rest = rest.get(size + 2..)?;
        }
    }
    let body = match length {
        Some(n) => body.get(..n)?,
        None => body,
    };
    Some((status, body.to_vec()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn urls_name_a_host_and_port() {
        assert_eq!(Server::parse("http://127.0.0.1:8080/", None).unwrap().authority, "127.0.0.1:8080");
        assert_eq!(Server::parse("localhost:9000", Some(String::new())).unwrap(), Server { authority: "localhost:9000".into(), token: None });
        assert_eq!(Server::parse("ws://example.invalid", None).unwrap().authority, "example.invalid:80");
        assert!(Server::parse("https://example.invalid", None).is_err());
        assert!(Server::parse("http://host:1/api", None).is_err());
    }

    #[test]
    fn responses_with_a_length_or_in_chunks() {
        let plain = b"HTTP/1.1 200 OK\r\ncontent-length: 2\r\n\r\n[]";
        assert_eq!(parse_response(plain), Some((200, b"[]".to_vec())));
        let chunked = b"HTTP/1.1 404 Not Found\r\nTransfer-Encoding: chunked\r\n\r\n3\r\n{\"a\r\n2\r\n\"}\r\n0\r\n\r\n";
        assert_eq!(parse_response(chunked), Some((404, b"{\"a\"}".to_vec())));
        assert_eq!(parse_response(b"garbage"), None);
    }
}
