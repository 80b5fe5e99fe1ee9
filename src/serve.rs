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
    // Before any thread allocates: the server's resident memory then follows what its scenes
    // count.
    raystage_server::one_allocator_arena();
    let config = Config { token: job.token.clone(), limits: Limits::default() };
    config.check_address(job.addr)?;
    let state = AppState::new(config);
    if let Some(source) = &job.scene {
        let scene = source.load(log, &crate::Environment::default(), true)?;
        let id = state.add_scene(scene, source.name()).map_err(|e| anyhow::anyhow!(e.detail.message))?;
        writeln!(log, "scene {id}: {}", source.name())?;
    }
    listen(job, state, log)
}

/// [`serve`] from every rank of an MPI job started by `mpirun`: rank 0 serves the API and
/// every other rank is a render worker (see [`raystage_cluster`]) until rank 0 stops.
/// Every rank loads the scene of the command line (a vote makes all go on or all stop); from
/// then on rank 0 sends the workers every edit, and renders every frame with them. Rank 0
/// gives up a worker that does not answer within `timeout` and serves alone from then on.
#[cfg(feature = "mpi")]
pub fn serve_mpi(job: &ServeJob, log: &mut impl Write, mpi: &crate::Cluster, timeout: std::time::Duration) -> Result<()> {
    use crate::render::Ranks;
    raystage_server::one_allocator_arena();
    let config = Config { token: job.token.clone(), limits: Limits::default() };
    let root = mpi.rank() == 0;
    let loaded = (|| {
        if root {
            config.check_address(job.addr)?;
        }
        match &job.scene {
            Some(source) if root => source.load(log, &crate::Environment::default(), true).map(|scene| Some((scene, source.name()))),
            Some(source) => source.load(&mut std::io::sink(), &crate::Environment::default(), true).map(|scene| Some((scene, source.name()))),
            None => Ok(None),
        }
    })();
    let loaded = match loaded {
        Ok(loaded) => {
            mpi.agree(Ok(()))?;
            loaded
        }
        Err(e) => return Err(mpi.agree(Err(e)).expect_err("a failure is agreed as one")),
    };
    let transport = mpi.transport();
    if !root {
        // The scene of the command line is scene 1 on every rank.
        let scenes = loaded.into_iter().map(|(scene, name)| (1, scene, name)).collect();
        return raystage_cluster::work(&transport, config, scenes).map_err(|e| anyhow::anyhow!("rank {}: {e}", mpi.rank()));
    }
    let cluster = raystage_cluster::Cluster::new(Box::new(transport), timeout);
    let state = AppState::clustered(config, cluster.clone());
    if let Some((scene, name)) = loaded {
        let id = state.add_scene(scene, name.clone()).map_err(|e| anyhow::anyhow!(e.detail.message))?;
        writeln!(log, "scene {id}: {name}")?;
    }
    writeln!(log, "MPI: {} ranks: rank 0 serves, the others render with it", mpi.size())?;
    let served = listen(job, state, log);
    if let Err(why) = cluster.stop() {
        // Workers that were given up cannot be told to stop: the job ends with them.
        eprintln!("error: {why}: ending the MPI job");
        mpi.abort(1);
    }
    served
}

/// Serves `state` on the job's address until Ctrl-C.
fn listen(job: &ServeJob, state: AppState, log: &mut impl Write) -> Result<()> {
    let runtime = tokio::runtime::Runtime::new().context("cannot start the server's threads")?;
    runtime.block_on(async {
        let listener = tokio::net::TcpListener::bind(job.addr).await.with_context(|| format!("cannot listen on {}", job.addr))?;
        let addr = listener.local_addr()?;
        // One line: scripts and tests read the address from it and may stop reading there.
        let (limits, (usable, source)) = (state.config().limits, raystage_server::usable_memory());
        let gib = |bytes: u64| bytes as f64 / (1u64 << 30) as f64;
        writeln!(
            log,
            "raystage serving http://{addr}/ (API description: http://{addr}/openapi.json; scenes may take {:.1} GiB in all, half of {source} ({:.1} GiB), {:.1} GiB each); Ctrl-C stops",
            gib(limits.max_total_scene_bytes),
            gib(usable),
            gib(limits.max_scene_bytes)
        )?;
        log.flush()?;
        let stop = async {
            let _ = tokio::signal::ctrl_c().await;
        };
        raystage_server::serve(listener, state, stop).await.context("the server failed")
    })
}
