//! Links Embree 3 when the `embree` feature is on; nothing else needs a build script.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var_os("CARGO_FEATURE_EMBREE").is_some() {
        println!("cargo:rustc-link-lib=embree3");
    }
}
