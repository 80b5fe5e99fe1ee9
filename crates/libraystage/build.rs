//! Names the shared library `libraystage.so` (its SONAME), the name it is installed under, so
//! programs linked against the installed library look for that name whatever file cargo wrote.

fn main() {
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libraystage.so");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
