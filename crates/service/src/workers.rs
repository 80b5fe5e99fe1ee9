//! A cluster's render workers as the service sees them (`raystage serve --mpi`): replicas of its
//! scenes that every edit must reach before it stands, and ranks that render shares of its
//! frames. `raystage-cluster` implements them over a transport (MPI); the service knows none.

use std::sync::Arc;

use raystage_render::{Cancel, Error as RenderError, Film, FrameStats, Progressive, RenderSettings};
use raystage_scene::Frame;

use crate::build::SceneBuild;
use crate::edit::Edit;
use crate::error::Result;
use crate::stats::ClusterTimes;

/// The workers of rank 0 of a cluster.
pub trait Workers: Send + Sync {
    /// Ranks rendering now, this one included: 1 once the workers were given up.
    fn ranks(&self) -> u32;

    /// The message that replicates `edit` of scene `scene`, encoded before the edit is applied
    /// here (which consumes it), for [`Workers::replicate`].
    fn edit_message(&self, scene: u32, edit: &Edit) -> Vec<u8>;

    /// Applies on every worker the edit of `message` (see [`Workers::edit_message`]), once this
    /// rank applied it: `Ok` if every rank did (the edit stands), an error naming the rank that
    /// could not (the edit is refused everywhere). Once the workers were given up, this rank's
    /// edit stands alone.
    fn replicate(&self, message: &[u8]) -> Result<()>;

    /// Replicates a new scene that this rank built from `build` and holds as `id`.
    fn replicate_new_scene(&self, id: u32, origin: &str, build: &SceneBuild) -> Result<()>;

    /// Replicates the deletion of scene `id` (a worker that cannot is only logged: the scene is
    /// gone here, which is what clients see).
    fn replicate_delete(&self, id: u32);

    /// An empty accumulation of `settings` rendered by every rank (by this one alone once the
    /// workers fail).
    fn accumulate(self: Arc<Self>, settings: RenderSettings) -> Result<Box<dyn Accumulate>, RenderError>;
}

/// An accumulation of samples, rendered by this process alone ([`Progressive`]) or by every rank
/// of a cluster: a stream's image, or a frame rendered across the ranks.
pub trait Accumulate: Send {
    /// The settings it renders with.
    fn settings(&self) -> &RenderSettings;

    /// Samples per pixel so far.
    fn samples(&self) -> u32;

    /// The image so far.
    fn film(&self) -> Film;

    /// Ranks that rendered the last pass, and where its time went on rank 0 (`None` alone).
    fn times(&self) -> Option<ClusterTimes>;

    /// Adds `samples` samples per pixel of `frame`, of scene `scene_id` at `version`, until
    /// `cancel` says stop. `last` says no pass follows.
    fn add(&mut self, scene_id: u32, frame: &Frame<'_>, version: u64, samples: u32, last: bool, cancel: &Cancel) -> Result<FrameStats, RenderError>;
}

impl Accumulate for Progressive {
    fn settings(&self) -> &RenderSettings {
        Progressive::settings(self)
    }

    fn samples(&self) -> u32 {
        Progressive::samples(self)
    }

    fn film(&self) -> Film {
        Progressive::film(self)
    }

    fn times(&self) -> Option<ClusterTimes> {
        None
    }

    fn add(&mut self, _: u32, frame: &Frame<'_>, _: u64, samples: u32, _: bool, cancel: &Cancel) -> Result<FrameStats, RenderError> {
        self.add_cancellable(frame, samples, cancel)
    }
}
