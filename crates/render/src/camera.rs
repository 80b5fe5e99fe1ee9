//! Cameras: where primary rays come from.

use raystage_kernel::Ray;

/// Generates the primary ray of each pixel.
///
/// A trait rather than a concrete camera so that the renderer does not depend on where cameras
/// are defined: the demo scenes bring their own today, and the retained scene will own them later.
pub trait Camera: Sync {
    /// The ray through the centre of pixel `(x, y)` of a `width × height` image, row 0 at the top.
    fn primary_ray(&self, x: u32, y: u32, width: u32, height: u32) -> Ray;
}
