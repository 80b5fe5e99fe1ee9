//! `rtInitMPI` and `rtFinishMPI`: a C program started by `mpirun` renders its frames with every
//! rank of the job, as OpenRT hid its cluster from the application. Rank 0 runs the program; on
//! every other rank `rtInitMPI` does not return: the rank serves as a render worker (the
//! cluster's, `raystage_cluster::work`) until rank 0 calls `rtFinishMPI`, then exits.
//!
//! The scene stays the program's: the context's scene journals its edits (see
//! `raystage_scene::SceneEdit`), and each `rtSwapBuffers` sends the workers what changed since
//! the last frame, then renders across the ranks (`raystage_cluster::Mirror`). Frame
//! semantics hold across the cluster: what the frame sees is the scene when the frame starts,
//! on every rank, and the image is the one a single process renders, to the bit.
//!
//! Built without the `mpi` feature, `rtInitMPI` records `RT_INVALID_OPERATION` saying so and
//! the program renders alone.

use crate::context::Context;
use crate::error::Error;

/// The cluster a context renders with (the `mpi` feature).
#[cfg(feature = "mpi")]
pub(crate) struct Session {
    /// The workers' replica of the scene; dropped before `job`, whose drop finalises MPI.
    mirror: raystage_cluster::Mirror,
    /// Set when the workers could not replay the scene's edits: their replicas differ, so frames
    /// render on rank 0 alone from then on.
    diverged: bool,
    job: raystage_cluster::MpiJob,
}

#[cfg(feature = "mpi")]
impl std::fmt::Debug for Session {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Session").field("ranks", &self.mirror.ranks()).field("diverged", &self.diverged).finish()
    }
}

/// How long rank 0 waits for a worker's answer before giving the workers up (and rendering
/// alone): longer than any frame should take on one rank.
#[cfg(feature = "mpi")]
const WORKER_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(300);

impl Context {
    /// `rtInitMPI`: joins the MPI job; on rank 0 returns the number of ranks, on the others
    /// serves as a worker and ends the process.
    #[cfg(feature = "mpi")]
    pub fn init_mpi(&mut self) -> Result<i32, Error> {
        use raystage_cluster::{Cluster, Mirror, MpiJob, Transport, work};
        if self.cluster.is_some() {
            return Err(Error::invalid_operation("rtInitMPI was called already"));
        }
        let scene = &self.scene;
        let empty = scene.object_ids().next().is_none()
            && scene.instances().next().is_none()
            && scene.shaders().next().is_none()
            && scene.textures().next().is_none()
            && scene.lights().next().is_none()
            && self.objects_generated == 0;
        if !empty {
            return Err(Error::invalid_operation("rtInitMPI must come before the scene is built: the workers start from an empty scene"));
        }
        let job = MpiJob::join().map_err(|e| Error::invalid_operation(format!("cannot join the MPI job: {e}")))?;
        let transport = job.transport();
        let (rank, ranks) = (transport.rank(), transport.ranks());
        if rank != 0 {
            // The program's own C ABI calls would only repeat rank 0's: this rank renders
            // instead, until rank 0 is done, and never returns to the program.
            let limits = raystage_service::Limits { max_scene_bytes: u64::MAX, max_total_scene_bytes: u64::MAX, ..Default::default() };
            let served = work(&transport, raystage_service::Config { token: None, limits }, Vec::new());
            drop(transport);
            drop(job);
            match served {
                Ok(()) => std::process::exit(0),
                Err(e) => {
                    eprintln!("raystage: MPI rank {rank}: {e}");
                    std::process::exit(1)
                }
            }
        }
        let mirror = Mirror::new(Cluster::new(Box::new(transport), WORKER_TIMEOUT)).map_err(|e| Error::internal(format!("cannot start the workers: {e}")))?;
        self.scene.set_journal(true);
        self.cluster = Some(Session { mirror, diverged: false, job });
        Ok(ranks as i32)
    }

    /// Takes over the cluster of the context this one replaced (`rtResetContext`): the workers'
    /// replica starts over empty, as this context's scene does.
    #[cfg(feature = "mpi")]
    pub fn keep_cluster(&mut self, cluster: Option<Session>) {
        if let Some(mut session) = cluster {
            // A restart the workers cannot follow leaves them diverged: frames render alone.
            session.diverged |= session.mirror.restart().is_err();
            self.scene.set_journal(true);
            self.cluster = Some(session);
        }
    }

    /// `rtInitMPI` without the `mpi` feature.
    #[cfg(not(feature = "mpi"))]
    pub fn init_mpi(&mut self) -> Result<i32, Error> {
        Err(Error::invalid_operation("this libraystage was built without MPI (cargo feature `mpi`): it renders in this process alone"))
    }

    /// `rtFinishMPI`: ends the workers and leaves MPI; the program renders alone afterwards.
    #[cfg(feature = "mpi")]
    pub fn finish_mpi(&mut self) -> Result<(), Error> {
        let session = self.cluster.take().ok_or_else(|| Error::invalid_operation("rtFinishMPI without rtInitMPI"))?;
        self.scene.set_journal(false);
        if let Err(why) = session.mirror.cluster().stop() {
            // Workers that were given up cannot be told to stop: the job ends with them.
            eprintln!("raystage: {why}: ending the MPI job");
            mpi::traits::Communicator::abort(&session.job.world(), 1);
        }
        Ok(())
    }

    /// `rtFinishMPI` without the `mpi` feature.
    #[cfg(not(feature = "mpi"))]
    pub fn finish_mpi(&mut self) -> Result<(), Error> {
        Err(Error::invalid_operation("rtFinishMPI without rtInitMPI (this libraystage was built without MPI)"))
    }
}

/// Renders `frame` with `settings` across the ranks of `cluster` (`rtInitMPI`'s), after sending
/// the workers `edits`, the scene's edits since the last frame; `None` where there is no cluster
/// (or its workers diverged), for the caller to render alone.
#[cfg(feature = "mpi")]
pub(crate) fn render_across_ranks(
    cluster: &mut Option<Session>,
    edits: Vec<raystage_scene::SceneEdit>,
    frame: &raystage_scene::Frame<'_>,
    settings: raystage_render::RenderSettings,
) -> Result<Option<raystage_render::Film>, Error> {
    let Some(session) = cluster.as_mut().filter(|s| !s.diverged) else { return Ok(None) };
    if let Err(why) = session.mirror.sync(edits) {
        session.diverged = true;
        return Err(Error::internal(format!("the MPI workers could not follow the scene ({why}): frames render on rank 0 alone from now on")));
    }
    let (film, _, _) = session.mirror.render(frame, settings).map_err(|e| Error::internal(e.to_string()))?;
    Ok(Some(film))
}
