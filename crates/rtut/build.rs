//! Links librtut.so as distributions link a library written on another: with the SONAME
//! `librtut.so.MAJOR` (`librtut.so.0`, a link of that name beside cargo's `librtut.so`, as
//! crates/libraystage/build.rs does for libraystage), and needing `libraystage.so.MAJOR`, which
//! provides the rt.h calls RTUT makes when the program runs, as libglut needs libGL.
//!
//! libraystage.so cannot be linked against here: cargo builds no dependency that is only a C
//! library, and a Rust one would be linked in whole (a second C ABI). So the link names a stub
//! of the same SONAME built into OUT_DIR, with no code: the loader finds the real library by it.

use std::path::PathBuf;
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("linux") {
        return;
    }
    let major = std::env::var("CARGO_PKG_VERSION_MAJOR").expect("cargo sets the version");
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));

    let stub = out.join("stub");
    std::fs::create_dir_all(&stub).expect("the stub's directory");
    std::fs::write(stub.join("raystage.rs"), "").expect("the stub's source");
    let rustc = std::env::var("RUSTC").expect("cargo sets RUSTC");
    let status = Command::new(rustc)
        .args(["--crate-type", "cdylib", "--crate-name", "raystage", "--edition", "2024", "-C", "opt-level=0", "-C", "debuginfo=0"])
        .arg(format!("-Clink-arg=-Wl,-soname,libraystage.so.{major}"))
        .arg("-o")
        .arg(stub.join("libraystage.so"))
        .arg(stub.join("raystage.rs"))
        .status()
        .expect("rustc runs");
    assert!(status.success(), "rustc could not build the libraystage stub");
    println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,librtut.so.{major}");
    // After rustc's own `--as-needed`: the stub has no symbol RTUT uses, yet it must be needed.
    println!("cargo:rustc-cdylib-link-arg=-Wl,--no-as-needed");
    println!("cargo:rustc-cdylib-link-arg=-L{}", stub.display());
    println!("cargo:rustc-cdylib-link-arg=-lraystage");

    // OUT_DIR is <target>/<profile>/build/raystage-rtut-<hash>/out; the library goes to
    // <target>/<profile>.
    if let Some(profile_dir) = out.ancestors().nth(3) {
        let link = profile_dir.join(format!("librtut.so.{major}"));
        let _ = std::fs::remove_file(&link);
        // Relative, so that the target directory can move; it dangles until the library is linked.
        if let Err(e) = std::os::unix::fs::symlink("librtut.so", &link) {
            println!("cargo:warning=cannot link {} to librtut.so: {e}", link.display());
        }
    }
}
