//! Stopping a render that nobody waits for any more.
//!
//! A [`Cancel`] token is shared between whoever renders and whoever may stop it (a server whose
//! client hung up, a time budget that ran out, a C program that abandons an asynchronous
//! frame). The frame loop looks at it before every tile and between a tile's samples, so a
//! cancelled render stops within one sample of one tile per render thread, and returns
//! [`Error::Cancelled`](crate::Error::Cancelled) instead of an image.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// A shared flag that asks a render to stop. Cheap to clone (one reference count) and to check
/// (one atomic load), so the render loop can look at it often; once cancelled it stays so.
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A token that nothing has cancelled yet.
    pub fn new() -> Cancel {
        Cancel::default()
    }

    /// Asks every render holding a clone of this token to stop. Returns at once: the render
    /// threads notice at their next tile or sample.
    pub fn cancel(&self) {
        // Release pairs with the renderers' Acquire: what the canceller wrote before (a reason,
        // say) is seen by the render that stops.
        self.0.store(true, Ordering::Release);
    }

    /// Whether [`Cancel::cancel`] was called on this token or a clone of it.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Acquire)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_clone_sees_the_cancel() {
        let token = Cancel::new();
        let clone = token.clone();
        assert!(!clone.is_cancelled());
        token.cancel();
        assert!(clone.is_cancelled() && token.is_cancelled());
    }
}
