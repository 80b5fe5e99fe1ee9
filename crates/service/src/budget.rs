//! Renders within the server's budgets: each waits for its client's turn ([`crate::turns`]),
//! holds memory for its image while it runs, and stops past the time limit. The render itself
//! runs on a blocking thread (on the rayon pool, never on the reactor).

use std::sync::Arc;
use std::time::Duration;

use raystage_render::Cancel;
use raystage_scene::Scene;

use crate::config::Limits;
use crate::error::{Error, Result};
use crate::state::{AppState, SceneSlot};
use crate::turns::{Client, Urgency};

/// Runs `work` on a snapshot of `slot` (`snapshot` if given, else the scene as it is when the
/// turn comes) and its version, on a blocking thread, once `bytes` of memory for images are
/// reserved (refused at once if they cannot be) and `client`'s turn to render has come. `work` should
/// stop when its cancel token says so: when the returned future is dropped (the client hung up,
/// a render job was deleted) or past [`Limits::max_render_seconds`] (the render budget). Either way the turn
/// and the memory go to the next render only once the work has stopped.
pub async fn on_a_turn<T: Send + 'static>(
    state: &AppState,
    slot: &Arc<SceneSlot>,
    client: Client,
    snapshot: Option<(Arc<Scene>, u64)>,
    bytes: u64,
    work: impl FnOnce(Arc<Scene>, u64, &Cancel) -> Result<T> + Send + 'static,
) -> Result<T> {
    // Before waiting for a turn: work that cannot have its memory fails at once.
    let memory = state.reserve_render_memory(bytes)?;
    let turn = state.render_permit(client, Urgency::InTurn).await;
    let (scene, version) = match snapshot {
        Some(snapshot) => snapshot,
        None => {
            // A clock that cannot move the scene pauses itself: the frame then shows the
            // scene as it is.
            let _ = slot.follow_clock(state).await;
            slot.snapshot().await
        }
    };
    let cancel = CancelOnDrop(Cancel::new());
    let token = cancel.0.clone();
    let task = tokio::task::spawn_blocking(move || {
        let _running = turn.running();
        let _memory = memory;
        work(scene, version, &token)
        // The turn is dropped here, when the work has stopped, and not when the client goes.
    });
    within_budget(&state.config().limits, task).await?
}

/// Waits for a render's blocking task for at most [`Limits::max_render_seconds`]: past it, an error
/// naming the limit. The caller's [`CancelOnDrop`] then stops the render as it returns.
pub async fn within_budget<T>(limits: &Limits, work: tokio::task::JoinHandle<T>) -> Result<T> {
    let budget = limits.max_render_seconds;
    match tokio::time::timeout(Duration::from_secs(budget), work).await {
        Ok(joined) => joined.map_err(|e| Error::internal(format!("a render failed: {e}"))),
        Err(_) => Err(Error::render_budget(
            "max_render_seconds",
            format!("the render ran past the server's limit of {budget} s: ask for fewer pixels or samples, or a faster integrator"),
        )),
    }
}

/// Returns the allocator's free memory to the system (glibc's `malloc_trim`; nothing where the
/// C library is another). glibc keeps what a large render freed (its film: 16 bytes a pixel)
/// for later, raising the size it hands out from its heap rather than mapping afresh, and what a
/// glTF file's parse freed (tens of megabytes for a file of a few hundred thousand nodes), each
/// in the arena of the thread that did it; so after a render or an upload that leaves something
/// behind, the resident memory would stay at its peak instead of following what the budgets
/// count. Blocks for as long as the allocator takes to walk its arenas: call it off the reactor.
pub fn give_back_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        unsafe extern "C" {
            fn malloc_trim(pad: usize) -> std::ffi::c_int;
        }
        // SAFETY: malloc_trim takes any padding and releases only memory nobody holds.
        unsafe {
            malloc_trim(0);
        }
    }
}

/// Makes the allocator keep one arena for every thread (glibc's `M_ARENA_MAX`, unless the
/// `MALLOC_ARENA_MAX` environment variable already says how many; nothing where the C library is
/// another). By default glibc gives threads that allocate at the same time arenas of their own,
/// up to eight per core, and [`give_back_memory`] cannot shrink the others as it does the first:
/// each glTF file parsed on a new thread left its parse's tens of megabytes resident for good
/// (four uploads of a file of 200,000 nodes held 146 MiB that no scene counted; with one arena,
/// 121 MiB against 116 MiB counted). Each thread's small allocations still come from its own
/// cache without a lock, and the render loops do not allocate. Call it before the server's
/// threads start.
pub fn one_allocator_arena() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    if std::env::var_os("MALLOC_ARENA_MAX").is_none() {
        unsafe extern "C" {
            fn mallopt(param: std::ffi::c_int, value: std::ffi::c_int) -> std::ffi::c_int;
        }
        /// glibc's `M_ARENA_MAX` (malloc.h).
        const M_ARENA_MAX: std::ffi::c_int = -8;
        // SAFETY: mallopt only sets a parameter of the allocator; one arena is a valid value.
        unsafe {
            mallopt(M_ARENA_MAX, 1);
        }
    }
}

/// Cancels a render when dropped: held by whatever waits for the render (a request's future,
/// a stream's loop), so that the render stops as soon as nobody waits for it, whichever way
/// the waiting ends (the client hung up and hyper dropped the future, a budget ran out, a
/// stream closed).
pub struct CancelOnDrop(pub Cancel);

impl Drop for CancelOnDrop {
    fn drop(&mut self) {
        self.0.cancel();
    }
}
