//! # raystage-capi
//!
//! The OpenGL-like C ABI of raystage, after the OpenRT API of the seed (Wald, *The OpenRT API*,
//! docs/design/seeds.md §1.1–§1.2). A C program builds **objects** between `rtNewObject` and
//! `rtEndObject` with `rtBegin`/`rtVertex3f`/`rtEnd` (or `rtTriangleMesh`), places **instances** of
//! them with the current modelview matrix, binds **shaders** and writes their parameters by name,
//! and calls `rtSwapBuffers` to render a frame into memory it owns, or `rtRenderFrameAsync` to
//! render it on a thread of its own while it goes on (`async_frames`).
//!
//! This crate is the state machine behind those calls: the current object and primitive, the
//! matrix stacks, the current vertex attributes, the bound shader class, shader and texture,
//! the frame buffer, the render settings and the error log. It records everything into a retained
//! [`raystage_scene::Scene`] and renders with [`raystage_render::render`]; references resolve
//! when the frame starts, so a parameter written after the geometry still changes it (frame
//! semantics).
//!
//! Layout: [`abi`] holds every `extern "C"` entry point, grouped by topic; each converts its
//! arguments and calls the context through one boundary (the `boundary` module) that catches
//! panics and records errors. `unsafe` appears only where C memory is touched: the entry points
//! that take pointers, the pointer helpers of `boundary`, and the write into the application's
//! frame buffer (`frames`), each with a SAFETY comment. The C header `api/include/raystage/rt.h`
//! is generated from [`abi`] by cbindgen (`tests/header.rs`).
//!
//! The C library itself, `libraystage.so` and `libraystage.a`, is the `libraystage` crate, which
//! links this one under that name.
//!
//! Not in here: the scene and its shader classes (`raystage-scene`), shading and frame loops
//! (`raystage-render`), the HTTP server.

pub mod abi;
mod assembly;
mod async_frames;
mod boundary;
mod builder;
mod camera;
mod cluster;
mod context;
mod error;
mod frames;
mod geometry;
mod ids;
mod introspection;
mod light_class;
mod matrix;
mod objects;
mod parameters;
mod rendering;
mod shaders;
mod state;
mod textures;
