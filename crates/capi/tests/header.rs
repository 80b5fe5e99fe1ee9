//! The checked-in C header must be exactly what cbindgen generates from the ABI's source, so
//! that it can never drift from the library. Set `RAYSTAGE_BLESS=1` to rewrite it.

use std::path::Path;

#[test]
fn the_checked_in_header_matches_the_source() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let header = crate_dir.join("../../api/include/raystage/rt.h");
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
        std::fs::write(&header, &generated).expect("write the header");
        return;
    }
    let checked_in = std::fs::read_to_string(&header).unwrap_or_default();
    assert!(
        checked_in == generated,
        "{} is out of date with crates/capi/src/abi; regenerate it with\n    \
         RAYSTAGE_BLESS=1 cargo test -p raystage-capi --test header\nand commit the result",
        header.display()
    );
}
