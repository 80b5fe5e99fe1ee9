//! Asynchronous frames (`rtRenderFrameAsync` and the `rtFrame*` calls), after OSPRay's futures
//! (`ospRenderFrame`, `ospIsReady`, `ospWait`, `ospCancel`, `ospGetProgress`): a frame renders on
//! a thread of its own from a snapshot of the scene and the render settings taken when it starts
//! (OpenRT's frame semantics), while the application keeps using its context.
//!
//! The render thread never touches the application's memory: it hands its image back, and the
//! context writes it into the frame buffer on the application's thread, in the call that first
//! finds the frame finished (`rtFrameIsReady`, `rtFrameWait`). So the frame buffer's pointer never
//! crosses threads and needs no lock. Until then the frame is *in flight*, and the calls that
//! would render or replace the frame buffer under it are refused ([`Context::no_frame_in_flight`]),
//! which makes what lands in the frame buffer independent of timing.

use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};
use std::thread::JoinHandle;

use raystage_render::{Cancel, ChannelImage, Film, render_rows};

use crate::abi::enums::{RT_CANCELLED, RT_INTERNAL_ERROR, RT_NO_ERROR};
use crate::abi::types::{RTenum, RTuint};
use crate::context::Context;
use crate::error::Error;

/// What a render thread gives back: the image and its channels, or why there are none.
type Outcome = Result<(Film, Vec<ChannelImage>), raystage_render::Error>;

/// How far a frame got: the image rows finished, counted by the render thread.
#[derive(Debug)]
struct Progress {
    rows: AtomicU32,
    height: u32,
}

#[derive(Debug)]
enum State {
    /// Started and not yet joined (it may have finished).
    InFlight(JoinHandle<Outcome>),
    /// Joined: `RT_NO_ERROR`, `RT_CANCELLED` or `RT_INTERNAL_ERROR`.
    Done(RTenum),
}

/// One asynchronous frame.
#[derive(Debug)]
struct AsyncFrame {
    cancel: Cancel,
    progress: Arc<Progress>,
    state: State,
}

impl Drop for AsyncFrame {
    /// A frame dropped while in flight (released, or its context reset or its thread ended) is
    /// cancelled and joined, so that no render thread keeps working for a context that forgot it.
    fn drop(&mut self) {
        if let State::InFlight(thread) = std::mem::replace(&mut self.state, State::Done(RT_CANCELLED)) {
            self.cancel.cancel();
            // Its outcome is unwanted; a panic in it was already caught by the join.
            let _ = thread.join();
        }
    }
}

/// How many frame handles were handed out, by every context of the process. Handles are never
/// reused, not even by a context that `rtResetContext` made anew, so a released one is told apart
/// from one never issued, and a stale handle never names a newer frame.
static ISSUED: AtomicU32 = AtomicU32::new(0);

/// The next frame handle, unique for the life of the process.
fn issue_handle() -> Result<RTuint, Error> {
    ISSUED
        .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |issued| issued.checked_add(1))
        .map(|issued| issued + 1)
        .map_err(|_| Error::out_of_memory(format!("all {} frame handles were handed out", RTuint::MAX)))
}

/// The asynchronous frames of a context, by handle.
#[derive(Debug, Default)]
pub(crate) struct AsyncFrames {
    frames: HashMap<RTuint, AsyncFrame>,
}

impl AsyncFrames {
    fn get(&mut self, handle: RTuint) -> Result<&mut AsyncFrame, Error> {
        self.frames.get_mut(&handle).ok_or_else(|| match handle {
            0 => Error::invalid_value("frame handle 0 names no frame"),
            h if h <= ISSUED.load(Ordering::Relaxed) => {
                Error::invalid_value(format!("frame {h} was released or belongs to another thread's context"))
            }
            h => Error::invalid_value(format!("frame {h} does not exist")),
        })
    }
}

impl Context {
    /// Fails if a frame of this context is in flight; `what` names the refused call.
    pub fn no_frame_in_flight(&self, what: &str) -> Result<(), Error> {
        match self.async_frames.frames.iter().find(|(_, f)| matches!(f.state, State::InFlight(_))) {
            Some((handle, _)) => Err(Error::invalid_operation(format!(
                "{what} while frame {handle} is in flight: rtFrameWait for it (after rtFrameCancel to stop it) or rtFrameRelease it first"
            ))),
            None => Ok(()),
        }
    }

    /// `rtRenderFrameAsync`: starts rendering the scene as it is now into the frame buffer, on a
    /// thread of its own, and returns the frame's handle.
    pub fn render_frame_async(&mut self) -> Result<RTuint, Error> {
        self.outside_definition("rtRenderFrameAsync")?;
        self.no_frame_in_flight("rtRenderFrameAsync")?;
        let (width, height) = self.frame_buffer_size()?;
        let channels = self.wanted_channels(width, height)?;
        let handle = issue_handle()?;
        // The snapshot: a clone shares the scene's objects and trees, so it is cheap, and edits
        // made after this call change the context's scene, not the frame's.
        let scene = self.scene.clone();
        let rendering = self.rendering.clone();
        let cancel = Cancel::new();
        let progress = Arc::new(Progress { rows: AtomicU32::new(0), height });
        let (thread_cancel, thread_progress) = (cancel.clone(), Arc::clone(&progress));
        let thread = std::thread::Builder::new()
            .name(format!("raystage frame {handle}"))
            .spawn(move || {
                let frame = scene.frame();
                let settings = rendering.settings(&frame, width, height);
                let count = |rows: raystage_render::Rows<'_>| {
                    thread_progress.rows.fetch_add(rows.rows().len() as u32, Ordering::Relaxed);
                };
                let (film, _stats) = render_rows(&frame, &settings, Some(&thread_cancel), count)?;
                Ok((film, raystage_render::render_channels(&frame, width, height, &channels)?))
            })
            .map_err(|e| Error::out_of_memory(format!("cannot start a render thread: {e}")))?;
        self.async_frames.frames.insert(handle, AsyncFrame { cancel, progress, state: State::InFlight(thread) });
        Ok(handle)
    }

    /// `rtFrameIsReady`: whether the frame finished (completed, cancelled or failed); the first
    /// time it finds so, its image lands in the frame buffer.
    pub fn frame_is_ready(&mut self, handle: RTuint) -> Result<bool, Error> {
        let frame = self.async_frames.get(handle)?;
        if let State::InFlight(thread) = &frame.state
            && !thread.is_finished()
        {
            return Ok(false);
        }
        // A failed frame is ready too; its failure is recorded, and rtFrameWait returns it.
        if let Err(e) = self.finish(handle) {
            self.errors.record("rtFrameIsReady", e);
        }
        Ok(true)
    }

    /// `rtFrameWait`: blocks until the frame finished, delivers its image if it completed, and
    /// returns its status.
    pub fn frame_wait(&mut self, handle: RTuint) -> Result<RTenum, Error> {
        self.async_frames.get(handle)?;
        self.finish(handle)
    }

    /// `rtFrameCancel`: asks the frame to stop; returns at once. Nothing if it already finished.
    pub fn frame_cancel(&mut self, handle: RTuint) -> Result<(), Error> {
        self.async_frames.get(handle)?.cancel.cancel();
        Ok(())
    }

    /// `rtFrameProgress`: the share of the frame's rows rendered, 0 to 1.
    pub fn frame_progress(&mut self, handle: RTuint) -> Result<f32, Error> {
        let progress = &self.async_frames.get(handle)?.progress;
        Ok((progress.rows.load(Ordering::Relaxed) as f32 / progress.height as f32).min(1.0))
    }

    /// `rtFrameRelease`: forgets the frame, cancelling it if it is in flight (its image never
    /// reaches the frame buffer then).
    pub fn frame_release(&mut self, handle: RTuint) -> Result<(), Error> {
        self.async_frames.get(handle)?;
        // Dropping it cancels and joins it if it is in flight.
        self.async_frames.frames.remove(&handle);
        Ok(())
    }

    /// Joins frame `handle` if it is in flight, writing its image into the frame buffer if it
    /// completed, and returns its status. A failure other than a cancel is also returned as an
    /// error, the first time only, so that its message is recorded once.
    fn finish(&mut self, handle: RTuint) -> Result<RTenum, Error> {
        let frame = self.async_frames.get(handle)?;
        let thread = match std::mem::replace(&mut frame.state, State::Done(RT_INTERNAL_ERROR)) {
            State::InFlight(thread) => thread,
            done @ State::Done(status) => {
                frame.state = done;
                return Ok(status);
            }
        };
        let (status, result) = match thread.join() {
            Ok(Ok((film, channels))) => {
                self.deliver(film, channels);
                (RT_NO_ERROR, Ok(RT_NO_ERROR))
            }
            Ok(Err(raystage_render::Error::Cancelled)) => (RT_CANCELLED, Ok(RT_CANCELLED)),
            Ok(Err(e)) => (RT_INTERNAL_ERROR, Err(Error::internal(format!("frame {handle} failed: {e}")))),
            Err(_panic) => (RT_INTERNAL_ERROR, Err(Error::internal(format!("frame {handle}'s render thread panicked (please report this bug)")))),
        };
        self.async_frames.get(handle)?.state = State::Done(status);
        result
    }
}
