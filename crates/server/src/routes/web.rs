//! The viewer page (`crates/server/web`): `GET /` answers a browser (a request that accepts
//! `text/html`) with a page that drives this API as the egui viewer does, and everyone else
//! with the JSON index. The page's three files are compiled into the binary, so the server has
//! nothing to find at run time and the page needs nothing from anywhere else: no build step, no
//! third-party script, and a Content-Security-Policy that allows the page's own files and its
//! own server only.
//!
//! The page and its files hold no data, so they are served without the access token (the page
//! asks for it, and sends it on every request it makes); see [`is_public`].

use axum::extract::Request;
use axum::http::{HeaderMap, HeaderValue, Method, header};
use axum::response::{IntoResponse, Response};

const INDEX_HTML: &str = include_str!("../../web/index.html");
const VIEWER_JS: &str = include_str!("../../web/viewer.js");
const VIEWER_CSS: &str = include_str!("../../web/viewer.css");

/// Where the page's script and style sheet are served.
pub(crate) const SCRIPT_PATH: &str = "/web/viewer.js";
pub(crate) const STYLE_PATH: &str = "/web/viewer.css";

/// The page's own files and its own server (HTTP and WebSocket) only: no inline script or
/// style, no other origin, no forms sent anywhere, no framing. The frames are drawn from
/// WebSocket messages, which `connect-src` covers; the icon is an empty `data:` URL, so that the
/// browser asks for no `/favicon.ico`.
const CONTENT_SECURITY_POLICY: &str = "default-src 'none'; script-src 'self'; style-src 'self'; connect-src 'self'; img-src data:; \
     base-uri 'none'; form-action 'none'; frame-ancestors 'none'";

/// `GET /`: the viewer page for a browser, the JSON index ([`super::index`]) for anyone else.
pub(crate) async fn root(headers: HeaderMap) -> Response {
    let mut response = if wants_page(&headers) { page(INDEX_HTML, "text/html; charset=utf-8") } else { super::index().await.into_response() };
    // Caches keep the two answers apart.
    response.headers_mut().insert(header::VARY, HeaderValue::from_static("accept"));
    response
}

/// `GET /web/viewer.js`.
pub(crate) async fn script() -> Response {
    page(VIEWER_JS, "text/javascript; charset=utf-8")
}

/// `GET /web/viewer.css`.
pub(crate) async fn style() -> Response {
    page(VIEWER_CSS, "text/css; charset=utf-8")
}

/// Whether `request` is for the page or one of its files, which are served without a token.
pub(crate) fn is_public(request: &Request) -> bool {
    let path = request.uri().path();
    (request.method() == Method::GET || request.method() == Method::HEAD)
        && ((path == "/" && wants_page(request.headers())) || path == SCRIPT_PATH || path == STYLE_PATH)
}

/// Whether a request for `/` asks for a page: browsers name `text/html` in `Accept`; API
/// clients (curl's `*/*`, the egui viewer, scripts) do not.
fn wants_page(headers: &HeaderMap) -> bool {
    headers.get(header::ACCEPT).and_then(|v| v.to_str().ok()).is_some_and(|accept| {
        accept.split(',').any(|range| range.split(';').next().is_some_and(|t| t.trim().eq_ignore_ascii_case("text/html")))
    })
}

/// One of the page's files, with the headers every one of them gets: the policy, no sniffing of
/// types, no referrer, and revalidation (a new server binary brings a new page).
fn page(body: &'static str, content_type: &'static str) -> Response {
    let headers = [
        (header::CONTENT_TYPE, content_type),
        (header::CONTENT_SECURITY_POLICY, CONTENT_SECURITY_POLICY),
        (header::X_CONTENT_TYPE_OPTIONS, "nosniff"),
        (header::REFERRER_POLICY, "no-referrer"),
        (header::CACHE_CONTROL, "no-cache"),
    ];
    (headers, body).into_response()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn browsers_get_the_page_and_api_clients_the_index() {
        let accepts = |value: &str| wants_page(&HeaderMap::from_iter([(header::ACCEPT, HeaderValue::from_str(value).unwrap())]));
        // Chromium's and Firefox's Accept for a page.
        assert!(accepts("text/html,application/xhtml+xml,application/xml;q=0.9,image/avif,image/webp,*/*;q=0.8"));
        assert!(accepts("TEXT/HTML"));
        for value in ["*/*", "application/json", "text/plain", "text/html-fragment"] {
            assert!(!accepts(value), "{value}");
        }
        assert!(!wants_page(&HeaderMap::new()));
    }

    #[test]
    fn the_page_names_its_files_where_they_are_served() {
        assert!(INDEX_HTML.contains(&format!("src=\"{SCRIPT_PATH}\"")) && INDEX_HTML.contains(&format!("href=\"{STYLE_PATH}\"")));
    }
}
