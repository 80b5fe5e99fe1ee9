//! Gives the shared library the SONAME `libraystage.so.MAJOR` (`libraystage.so.0`), as
//! distributions version a C library: programs linked against it look for that name, which
//! scripts/install-capi.sh links to the installed `libraystage.so.MAJOR.MINOR.PATCH`. In the build
//! tree, where cargo writes `libraystage.so`, a link `libraystage.so.MAJOR` beside it lets programs
//! linked there (`-Ltarget/release -lraystage`) find it at run time too.

use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("linux") {
        return;
    }
    let major = std::env::var("CARGO_PKG_VERSION_MAJOR").expect("cargo sets the version");
    let soname = format!("libraystage.so.{major}");
    println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,{soname}");
    // OUT_DIR is <target>/<profile>/build/libraystage-<hash>/out; the library goes to
    // <target>/<profile>.
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    if let Some(profile_dir) = out.ancestors().nth(3) {
        let link = profile_dir.join(&soname);
        let _ = std::fs::remove_file(&link);
        // Relative, so that the target directory can move; it dangles until the library is linked.
        if let Err(e) = std::os::unix::fs::symlink("libraystage.so", &link) {
            println!("cargo:warning=cannot link {} to libraystage.so: {e}", link.display());
        }
    }
}
