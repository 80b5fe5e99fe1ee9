//! `raystage serve`: the HTTP/JSON server, optionally with a scene loaded at start.

use std::io::Write;
use std::net::SocketAddr;

use anyhow::{Context, Result};
use raystage_server::{AppState, Config, Limits};

use crate::render::SceneSource;

/// How to serve.
#[derive(Clone, Debug, PartialEq)]
pub struct ServeJob {
    /// The address to listen on. Anything but a loopback address needs a token.
    pub addr: SocketAddr,
    /// The bearer token requests must carry, if any.
    pub token: Option<String>,
    /// A scene to load as scene 1 before serving, if any.
    pub scene: Option<SceneSource>,
}

/// Serves the API until Ctrl-C, logging the address (and the scene loaded) to `log`.
pub fn serve(job: &ServeJob, log: &mut impl Write) -> Result<()> {
    let config = Config { token: job.token.clone(), limits: Limits::default() };
    config.check_address(job.addr)?;
    let state = AppState::new(config);
    if let Some(source) = &job.scene {
        let scene = source.load(log)?;
        let id = state.add_scene(scene, source.name()).map_err(|e| anyhow::anyhow!(e.detail.message))?;
        writeln!(log, "scene {id}: {}", source.name())?;
    }
    let runtime = tokio::runtime::Runtime::new().context("cannot start the server's threads")?;
    runtime.block_on(async {
        let listener = tokio::net::TcpListener::bind(job.addr).await.with_context(|| format!("cannot listen on {}", job.addr))?;
        let addr = listener.local_addr()?;
        writeln!(log, "raystage serving http://{addr}/ (API description: http://{addr}/openapi.json); Ctrl-C stops")?;
        log.flush()?;
        let stop = async {
            let _ = tokio::signal::ctrl_c().await;
        };
        raystage_server::serve(listener, state, stop).await.context("the server failed")
    })
}
