//! Objects: geometry defined once between `rtNewObject` and `rtEndObject`, like an OpenGL
//! display list, and instantiated any number of times.

use crate::abi::types::{RTenum, RTsizei, RTuint};
use crate::boundary::{call, call_in_primitive};

/// Reserves `n` consecutive object ids and returns the first (0 if `n` is 0 or on error). At
/// most `RT_MAX_IDS` object ids per context (`RT_OUT_OF_MEMORY` beyond).
#[unsafe(no_mangle)]
pub extern "C" fn rtGenObjects(n: RTsizei) -> RTuint {
    call("rtGenObjects", |ctx| ctx.gen_objects(n))
}

/// Starts defining object `id` (from `rtGenObjects`); `mode` must be `RT_COMPILE`. Geometry
/// issued until `rtEndObject` belongs to it, transformed by the modelview matrix in force when
/// each vertex is issued. Defining an object that exists replaces its geometry, and every
/// instance of it follows (unstructured motion). Not allowed while an object is being defined.
#[unsafe(no_mangle)]
pub extern "C" fn rtNewObject(id: RTuint, mode: RTenum) {
    call("rtNewObject", |ctx| ctx.new_object(id, mode))
}

/// Commits the object being defined to the scene, with the kind set by `rtObjectKind`. A
/// primitive still open (`rtBegin` without `rtEnd`) is ended first, as `rtEnd` would end it, so
/// its triangles belong to the object. The definition ends even when the object is refused for
/// having no triangles (`RT_INVALID_OPERATION`); it then keeps its previous geometry, if any.
#[unsafe(no_mangle)]
pub extern "C" fn rtEndObject() {
    // Allowed inside a primitive: a GL porter's display list may end without glEnd, and
    // refusing would leave the context inside the primitive, failing every call after.
    call_in_primitive("rtEndObject", |ctx| ctx.end_object())
}

/// Sets the kind of the objects `rtEndObject` commits from now on: `RT_STATIC` (the default;
/// never changes, best tree), `RT_ANIMATED` (moves only through `rtMoveInstance`), or
/// `RT_UNSTRUCTURED` (redefined often; its tree is refitted while that stays cheap).
#[unsafe(no_mangle)]
pub extern "C" fn rtObjectKind(kind: RTenum) {
    call("rtObjectKind", |ctx| ctx.object_kind(kind))
}

/// Deletes the defined objects among ids `first` to `first + n - 1`, and all their instances.
/// Ids that name no defined object are ignored; the ids stay generated and can be defined again.
#[unsafe(no_mangle)]
pub extern "C" fn rtDeleteObjects(first: RTuint, n: RTsizei) {
    call("rtDeleteObjects", |ctx| ctx.delete_objects(first, n))
}
