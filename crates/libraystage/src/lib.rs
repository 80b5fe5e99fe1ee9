//! # libraystage
//!
//! raystage's C library as C programs link it: `libraystage.so` (its SONAME `libraystage.so`)
//! and `libraystage.a`, exporting every `rt*` entry point of `rt.h`. The entry points are
//! `raystage-capi`'s; this crate only gives the library its name, which cargo takes from the
//! crate's (`raystage-capi`'s own library is `raystage_capi`, for its Rust tests, because the
//! root package's Rust library is already `raystage`).

// Linking the C ABI in is what exports it: a shared library exports the `#[no_mangle]`
// functions of every crate it links, a static one holds them all.
pub use raystage_capi::abi::*;
