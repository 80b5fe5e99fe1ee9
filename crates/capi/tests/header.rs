//! The checked-in C headers must be exactly what cbindgen generates from their source, so that
//! they can never drift from the libraries: rt.h from the C ABI's (crates/capi/src/abi), rtut.h
//! from RTUT's (crates/rtut/src/lib.rs). Set `RAYSTAGE_BLESS=1` to rewrite them.

use std::path::Path;

/// Generates the header of the crate in `crate_dir` (with its cbindgen.toml) and compares it
/// with `api/include/raystage/<header>`, or writes it there when blessing.
fn check(crate_dir: &Path, header: &str) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../api/include/raystage").join(header);
    let config = cbindgen::Config::from_file(crate_dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new()
        .with_crate(crate_dir)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header");
    let mut generated = Vec::new();
    bindings.write(&mut generated);
    let generated = String::from_utf8(generated).expect("UTF-8 header");

    if std::env::var_os("RAYSTAGE_BLESS").is_some() {
        std::fs::write(&path, &generated).expect("write the header");
        return;
    }
    let checked_in = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        checked_in == generated,
        "{} is out of date with {}; regenerate it with\n    \
         RAYSTAGE_BLESS=1 cargo test -p raystage-capi --test header\nand commit the result",
        path.display(),
        crate_dir.display()
    );
}

#[test]
fn the_checked_in_header_matches_the_source() {
    check(Path::new(env!("CARGO_MANIFEST_DIR")), "rt.h");
}

#[test]
fn the_checked_in_rtut_header_matches_the_source() {
    check(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../rtut"), "rtut.h");
}

/// rtut.h documents every environment variable RTUT reads (crates/rtut/src/state.rs), and
/// `RTUT_OUTPUT` as the library uses it: the files' name before `-NNNN.png`, not a prefix that
/// the number would follow directly.
#[test]
fn rtut_h_documents_the_environment_rtut_reads() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let source = std::fs::read_to_string(root.join("crates/rtut/src/state.rs")).expect("RTUT's source");
    let header = std::fs::read_to_string(root.join("api/include/raystage/rtut.h")).expect("rtut.h").replace("\n * ", " ");
    let read: Vec<&str> = source.split("env(\"").skip(1).filter_map(|s| s.split('"').next()).filter(|v| v.starts_with("RTUT_")).collect();
    assert!(read.contains(&"RTUT_OUTPUT") && read.len() >= 4, "the variables RTUT reads: {read:?}");
    for variable in read {
        assert!(header.contains(variable), "rtut.h does not document {variable}");
    }
    assert!(header.contains("RTUT_OUTPUT-NNNN.png") && source.contains("\"-{:04}.png\""), "rtut.h names the files as RTUT writes them");
    assert!(!header.contains("prefix"), "RTUT_OUTPUT is followed by -NNNN.png, not by the number alone");
}
