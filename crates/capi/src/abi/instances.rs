//! Instances: an object placed in the world by the modelview matrix, and moving during the
//! shutter for motion blur.

use crate::abi::types::RTuint;
use crate::boundary::call;

/// Places an instance of the defined object `id` with the current modelview matrix (which must
/// be invertible) and returns the instance's id (0 on error). Not allowed while an object is
/// being defined: the scene has two levels, objects hold no instances.
#[unsafe(no_mangle)]
pub extern "C" fn rtInstantiateObject(id: RTuint) -> RTuint {
    call("rtInstantiateObject", |ctx| ctx.instantiate(id))
}

/// Moves instance `instance` to the current modelview matrix. It then stands still during the
/// shutter: a motion set by `rtInstanceMotion` ends.
#[unsafe(no_mangle)]
pub extern "C" fn rtMoveInstance(instance: RTuint) {
    call("rtMoveInstance", |ctx| ctx.move_instance(instance))
}

/// Makes instance `instance` move while the shutter is open (motion blur): from the transform
/// `rtInstantiateObject` or `rtMoveInstance` gave it, at time 0 of the frame, to the current
/// modelview matrix (which must be invertible), at time 1, blending the two matrices in between.
/// Seen with `rtShutter`, `RT_DISTRIBUTION` or `RT_PATH` and several samples per pixel. Call
/// `rtMoveInstance` first, then this, each frame; `rtMoveInstance` alone stops the motion.
#[unsafe(no_mangle)]
pub extern "C" fn rtInstanceMotion(instance: RTuint) {
    call("rtInstanceMotion", |ctx| ctx.instance_motion(instance))
}

/// Removes instance `instance`; its object stays.
#[unsafe(no_mangle)]
pub extern "C" fn rtDeleteInstance(instance: RTuint) {
    call("rtDeleteInstance", |ctx| ctx.delete_instance(instance))
}

/// Removes every instance; the objects stay (the seed's per-frame re-instantiation).
#[unsafe(no_mangle)]
pub extern "C" fn rtDeleteAllInstances() {
    call("rtDeleteAllInstances", |ctx| {
        ctx.delete_all_instances();
        Ok(())
    })
}
