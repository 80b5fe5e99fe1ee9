//! Instances: an object placed in the world by the modelview matrix.

use crate::abi::types::RTuint;
use crate::boundary::call;

/// Places an instance of the defined object `id` with the current modelview matrix (which must
/// be invertible) and returns the instance's id (0 on error). Not allowed while an object is
/// being defined: the scene has two levels, objects hold no instances.
#[unsafe(no_mangle)]
pub extern "C" fn rtInstantiateObject(id: RTuint) -> RTuint {
    call("rtInstantiateObject", |ctx| ctx.instantiate(id))
}

/// Moves instance `instance` to the current modelview matrix.
#[unsafe(no_mangle)]
pub extern "C" fn rtMoveInstance(instance: RTuint) {
    call("rtMoveInstance", |ctx| ctx.move_instance(instance))
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
