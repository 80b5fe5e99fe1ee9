//! The C and C++ examples, built as a user would: the libraries are installed into a temporary
//! prefix with scripts/install-capi.sh, each example is compiled with gcc or g++ against the
//! installed shared library and again against the static one (flags from pkg-config), run in a
//! directory of its own, and the PNG frames it writes are decoded and checked. C and C++ test
//! programs (tests/c, tests/cpp) are built the same way and check themselves; those that open
//! RTUT windows link librtut too, which is shared only. Without the
//! compiler or CMake a test needs, it says so and passes (scripts/test.sh installs them).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use image::RgbaImage;

/// The workspace root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().expect("the workspace root")
}

/// The shared and static libraries, and RTUT's, built for this test run: `cargo test` builds only
/// the crate's Rust library, so this runs `cargo build -p libraystage -p raystage-rtut` once, with
/// the test's own
/// profile and target directory (this executable is `<target>/<profile>/deps/examples-*`), which
/// reuses everything the test build compiled.
fn artifact_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let exe = std::env::current_exe().expect("the test's path");
        let dir = exe.parent().and_then(Path::parent).expect("<target>/<profile>").to_path_buf();
        let target = dir.parent().expect("<target>");
        let profile = match dir.file_name().and_then(|n| n.to_str()) {
            Some("debug") => "dev",
            Some(name) => name,
            None => panic!("no profile directory above {}", exe.display()),
        };
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let mut build = Command::new(cargo);
        build.args(["build", "--quiet", "-p", "libraystage", "-p", "raystage-rtut", "--profile", profile, "--target-dir"]).arg(target).current_dir(root());
        // The library these tests were built for: with MPI (rtInitMPI) if they were.
        if cfg!(feature = "mpi") {
            build.args(["--features", "libraystage/mpi"]);
        }
        run(&mut build);
        for lib in ["libraystage.so", "libraystage.a", "librtut.so"] {
            assert!(dir.join(lib).is_file(), "cargo build did not write {}", dir.join(lib).display());
        }
        dir
    })
}

/// A fresh scratch directory for `name`.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("capi").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// Runs a command, failing the test with its output if it fails; returns its stdout.
fn run(command: &mut Command) -> String {
    let output = command.output().unwrap_or_else(|e| panic!("cannot run {command:?}: {e}"));
    assert!(
        output.status.success(),
        "{command:?} failed ({}):\n{}\n{}",
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout).expect("UTF-8 output")
}

/// The library installed once for the whole test binary; returns the prefix.
fn prefix() -> &'static Path {
    static PREFIX: OnceLock<PathBuf> = OnceLock::new();
    PREFIX.get_or_init(|| {
        let prefix = scratch("prefix");
        run(Command::new("bash").arg(root().join("scripts/install-capi.sh")).arg("--lib-dir").arg(artifact_dir()).arg(&prefix));
        prefix
    })
}

/// `pkg-config` for the installed library.
fn pkg_config(package: &str) -> Vec<String> {
    let out = run(Command::new("pkg-config")
        .env("PKG_CONFIG_PATH", prefix().join("lib/pkgconfig"))
        .args(["--cflags", "--libs", package]));
    out.split_whitespace().map(String::from).collect()
}

#[derive(Clone, Copy, Debug)]
enum Linking {
    Shared,
    Static,
    /// The shared library with RTUT's (`pkg-config rtut`): RTUT is shared only.
    Rtut,
}

/// Whether `tool` cannot be run; if so, says that the calling test skips.
fn missing(tool: &str) -> bool {
    let missing = Command::new(tool).arg("--version").output().is_err();
    if missing {
        eprintln!("{tool} is not installed: skipping (scripts/test.sh installs it)");
    }
    missing
}

/// The command that compiles `source` (a path from the workspace root) into `exe` against the
/// installed library, with warnings as errors: gcc for C99, g++ for C++17.
fn compile(source: &Path, linking: Linking, exe: &Path) -> Command {
    let cpp = source.extension().is_some_and(|e| e == "cpp");
    let mut compile = Command::new(if cpp { "g++" } else { "gcc" });
    compile.args(["-Wall", "-Wextra", "-Werror", "-O1", if cpp { "-std=c++17" } else { "-std=c99" }]);
    compile.arg(source).arg("-o").arg(exe);
    compile.args(pkg_config(match linking {
        Linking::Shared => "raystage",
        Linking::Static => "raystage-static",
        Linking::Rtut => "rtut",
    }));
    compile.arg("-lm");
    compile
}

/// Compiles `source` (a path from the workspace root) against the installed library, runs it
/// with `args` in a directory of its own, and returns that directory.
fn build_and_run(source: &str, linking: Linking, args: &[&str]) -> PathBuf {
    let source = root().join(source);
    let stem = source.file_stem().unwrap().to_string_lossy().into_owned();
    let dir = scratch(&format!("{stem}-{linking:?}"));
    let exe = dir.join(&stem);
    run(&mut compile(&source, linking, &exe));
    run(Command::new(&exe).args(args).current_dir(&dir).env("LD_LIBRARY_PATH", prefix().join("lib")));
    if let Linking::Static = linking {
        let ldd = run(Command::new("ldd").arg(&exe));
        assert!(!ldd.contains("libraystage"), "statically linked, yet: {ldd}");
    }
    dir
}

fn frame(dir: &Path, name: &str) -> RgbaImage {
    image::open(dir.join(name)).unwrap_or_else(|e| panic!("{}: {e}", dir.join(name).display())).to_rgba8()
}

/// Pixels whose channel `c` clearly dominates the other two.
fn dominated_by(image: &RgbaImage, c: usize) -> usize {
    image.pixels().filter(|p| (0..3).filter(|&o| o != c).all(|o| p[c] as i32 > p[o] as i32 + 60)).count()
}

/// The sky: bright and bluish.
fn is_sky(p: &image::Rgba<u8>) -> bool {
    p[2] > 200 && p[2] >= p[1] && p[1] >= p[0]
}

#[test]
fn late_binding_renders_both_triangles_green() {
    for linking in [Linking::Shared, Linking::Static] {
        let image = frame(&build_and_run("examples/c/late_binding.c", linking, &[]), "late_binding.png");
        assert_eq!(image.dimensions(), (160, 80));
        for x in [44, 116] {
            let p = image.get_pixel(x, 45);
            assert!(p[1] > 200 && p[0] < 30 && p[2] < 30, "{linking:?}: triangle at x = {x} is {p:?}, not green");
        }
        assert_eq!(dominated_by(&image, 0), 0, "{linking:?}: nothing is red");
    }
}

#[test]
fn eight_cubes_spin_with_their_vertex_colours() {
    for linking in [Linking::Shared, Linking::Static] {
        let dir = build_and_run("examples/c/eight_cubes.c", linking, &["3", "160", "120"]);
        let (first, last) = (frame(&dir, "eight_cubes_000.png"), frame(&dir, "eight_cubes_002.png"));
        assert_eq!(first.dimensions(), (160, 120));
        assert!(is_sky(first.get_pixel(2, 2)), "{linking:?}: the corner sees the sky");
        // The cube in front, at the centre of the image: its corners' colours are interpolated,
        // so no channel is at the sky's mix.
        let centre = first.get_pixel(80, 60);
        assert!(!is_sky(centre), "{linking:?}: the centre sees a cube, not {centre:?}");
        let cube_pixels = first.pixels().filter(|p| !is_sky(p)).count();
        assert!((3000..12000).contains(&cube_pixels), "{linking:?}: cubes cover {cube_pixels} pixels");
        assert_ne!(first, last, "{linking:?}: the cubes turn");
    }
}

#[test]
fn gears_are_red_green_and_blue() {
    for linking in [Linking::Shared, Linking::Static] {
        let dir = build_and_run("examples/c/gears.c", linking, &["2", "200", "200"]);
        let image = frame(&dir, "gears_000.png");
        let (red, green, blue) = (dominated_by(&image, 0), dominated_by(&image, 1), dominated_by(&image, 2));
        assert!(red > 6000 && green > 1200 && blue > 1200, "{linking:?}: red {red}, green {green}, blue {blue} pixels");
        assert!(red > green && red > blue, "{linking:?}: the big gear is red");
        assert_ne!(image, frame(&dir, "gears_001.png"), "{linking:?}: the gears turn");
    }
}

#[test]
fn textures_show_a_picture_on_a_checkerboard_under_an_hdr_sky() {
    for linking in [Linking::Shared, Linking::Static] {
        let image = frame(&build_and_run("examples/c/textures.c", linking, &[]), "textures.png");
        assert_eq!(image.dimensions(), (240, 160));
        // The picture: red above, a blue disc in the middle, yellow below.
        let (top, middle, bottom) = (image.get_pixel(92, 36), image.get_pixel(120, 68), image.get_pixel(92, 100));
        assert!(top[0] > 150 && top[1] < 80 && top[2] < 80, "{linking:?}: the picture's top is {top:?}, not red");
        assert!(middle[2] > 150 && middle[0] < 80, "{linking:?}: its middle is {middle:?}, not blue");
        assert!(bottom[0] > 150 && bottom[1] > 120 && bottom[2] < 80, "{linking:?}: its bottom is {bottom:?}, not yellow");
        // The sky's map, bluer overhead, is seen above the panel.
        assert!(is_sky(image.get_pixel(4, 2)), "{linking:?}: the corner sees the sky, not {:?}", image.get_pixel(4, 2));
        // The floor's checkerboard: light and dark squares along its front row.
        let row: Vec<u8> = (0..240).map(|x| image.get_pixel(x, 150)[0]).collect();
        let (light, dark) = (row.iter().filter(|&&r| r > 150).count(), row.iter().filter(|&&r| r < 70).count());
        assert!(light > 40 && dark > 40, "{linking:?}: {light} light and {dark} dark floor pixels in the front row");
    }
}

#[test]
fn three_kinds_of_objects_move_as_their_kinds_do() {
    for linking in [Linking::Shared, Linking::Static] {
        let dir = build_and_run("examples/c/three_kinds.c", linking, &["3", "240", "135"]);
        let frames: Vec<RgbaImage> = (0..3).map(|i| frame(&dir, &format!("three_kinds_{i:03}.png"))).collect();
        for image in &frames {
            assert!(dominated_by(image, 0) > 300, "{linking:?}: the red stripes of the flag and the orange cube");
            // The scene brings its own lights and no environment: the backdrop is black.
            assert_eq!(image.get_pixel(120, 5).0, [0, 0, 0, 255], "{linking:?}: black above the scene");
        }
        // The ground (static) stays; the cube and the flag move.
        let ground = |image: &RgbaImage| *image.get_pixel(230, 130);
        assert_eq!(ground(&frames[0]), ground(&frames[2]), "{linking:?}: the ground's corner does not change");
        assert_ne!(frames[0], frames[2], "{linking:?}: the cube and the flag move");
    }
}

/// `three_kinds --mpi` under `mpirun -n 2` and `-n 3` (libraystage built with MPI): every frame
/// is the same PNG as the program writes alone, static, animated and unstructured objects
/// changing between frames; linked shared and static.
#[cfg(feature = "mpi")]
#[test]
fn three_kinds_renders_the_same_frames_on_every_rank_of_an_mpi_job() {
    for linking in [Linking::Shared, Linking::Static] {
        // Its own build (three_kinds_of_objects_move_as_their_kinds_do builds another).
        let exe = scratch(&format!("three_kinds-mpi-{linking:?}")).join("three_kinds");
        run(&mut compile(&root().join("examples/c/three_kinds.c"), linking, &exe));
        let alone = scratch(&format!("three_kinds-mpi-{linking:?}-1"));
        run(Command::new(&exe).args(["3", "160", "90"]).current_dir(&alone).env("LD_LIBRARY_PATH", prefix().join("lib")));
        for ranks in ["2", "3"] {
            let dir = scratch(&format!("three_kinds-mpi-{linking:?}-{ranks}"));
            let output = Command::new("mpirun")
                .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
                .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
                .env("LD_LIBRARY_PATH", prefix().join("lib"))
                // One render thread per rank: the ranks share this machine's cores.
                .env("RAYON_NUM_THREADS", "1")
                .args(["--oversubscribe", "-n", ranks])
                .arg(&exe)
                .args(["3", "160", "90", "--mpi"])
                .current_dir(&dir)
                .output()
                .unwrap();
            let (out, err) = (String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
            assert!(output.status.success(), "{linking:?}, {ranks} ranks: {out}\n{err}");
            // A pass the workers could not render would fall back to rank 0 alone, with a warning.
            assert!(!err.contains("alone"), "{linking:?}, {ranks} ranks: every frame renders across the ranks: {err}");
            assert_eq!(out.matches("rendering on").count(), 1, "only rank 0 runs the program: {out}");
            assert!(out.contains(&format!("rendering on {ranks} MPI ranks")), "{out}");
            for i in 0..3 {
                let name = format!("three_kinds_{i:03}.png");
                let (one, many) = (std::fs::read(alone.join(&name)).unwrap(), std::fs::read(dir.join(&name)).unwrap());
                assert!(one == many, "{linking:?}, {ranks} ranks: {name} differs from the one one process writes");
            }
        }
    }
}

/// Built without MPI, `rtInitMPI` says so and the program renders alone.
#[cfg(not(feature = "mpi"))]
#[test]
fn without_mpi_rt_init_mpi_says_so() {
    let dir = scratch("three_kinds-no-mpi");
    let exe = dir.join("three_kinds");
    run(&mut compile(&root().join("examples/c/three_kinds.c"), Linking::Shared, &exe));
    let output = Command::new(&exe).args(["1", "32", "18", "--mpi"]).current_dir(&dir).env("LD_LIBRARY_PATH", prefix().join("lib")).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success() && stderr.contains("built without MPI"), "{stderr}");
}

#[test]
fn motion_blur_smears_the_sliding_cube() {
    for linking in [Linking::Shared, Linking::Static] {
        let dir = build_and_run("examples/c/motion_blur.c", linking, &["160", "90", "16"]);
        let (blurred, still) = (frame(&dir, "motion_blur.png"), frame(&dir, "motion_blur_still.png"));
        // Pixels redder than blue by `margin`: the ground is grey and the sky bluish, so they
        // show the cube's orange, in full (a large margin) or as a trace of it (a small one).
        let orange = |image: &RgbaImage, margin: i32| image.pixels().filter(|p| p[0] as i32 > p[2] as i32 + margin).count();
        let (full, trace) = ([orange(&still, 100), orange(&blurred, 100)], [orange(&still, 12), orange(&blurred, 12)]);
        assert!(full[0] > 100, "{linking:?}: the still cube covers {} pixels", full[0]);
        assert!(full[1] * 2 < full[0], "{linking:?}: {} pixels keep the full colour in motion", full[1]);
        assert!(trace[1] > trace[0] * 2, "{linking:?}: the smear tints {} pixels, the still cube {}", trace[1], trace[0]);
    }
}

/// Checks the two frames `spin 2 160 120` wrote into `dir`: a teal torus that turns.
fn check_spin_frames(dir: &Path, how: &str) {
    let (first, second) = (frame(dir, "spin_000.png"), frame(dir, "spin_001.png"));
    let teal = |image: &RgbaImage| image.pixels().filter(|p| !is_sky(p) && p[1].min(p[2]) as i32 > p[0] as i32 + 40).count();
    assert!(teal(&first) > 1000, "{how}: the torus covers {} pixels", teal(&first));
    assert_ne!(first, second, "{how}: the torus spins");
}

#[test]
fn the_cpp_wrapper_spins_a_torus() {
    if missing("g++") {
        return;
    }
    for linking in [Linking::Shared, Linking::Static] {
        check_spin_frames(&build_and_run("examples/cpp/spin.cpp", linking, &["2", "160", "120"]), &format!("{linking:?}"));
    }
}

/// The C++ wrapper raystage/rt.hpp (`tests/cpp/wrapper.cpp`): each FrameBuffer renders its own
/// frames and detaches only itself, an exception inside `define` leaves no error pending, kept
/// instances stay, ownership across moves and Context resets, errors as `raystage::Error`, and
/// the GL calls it wraps; the program checks itself.
#[test]
fn cpp_wrapper_checks_pass() {
    if missing("g++") {
        return;
    }
    for linking in [Linking::Shared, Linking::Static] {
        build_and_run("crates/capi/tests/cpp/wrapper.cpp", linking, &[]);
    }
}

/// `raystage::Frame` (`tests/cpp/frames.cpp`): polled to completion with progress reaching 1,
/// cancelled, moved, released once, outliving or following its buffer, on two threads.
#[test]
fn cpp_frame_checks_pass() {
    if missing("g++") {
        return;
    }
    for linking in [Linking::Shared, Linking::Static] {
        build_and_run("crates/capi/tests/cpp/frames.cpp", linking, &[]);
    }
}

/// Dropping an Instance or a Frame at once (`tests/cpp/discarded.cpp`) does not compile: the
/// results are `[[nodiscard]]`. The same file keeping both compiles and runs.
#[test]
fn dropped_instances_and_frames_do_not_compile() {
    if missing("g++") {
        return;
    }
    let source = root().join("crates/capi/tests/cpp/discarded.cpp");
    let dir = scratch("discarded");
    run(&mut compile(&source, Linking::Shared, &dir.join("kept")));
    run(Command::new(dir.join("kept")).env("LD_LIBRARY_PATH", prefix().join("lib")));
    for (define, call) in [("DISCARD_INSTANCE", "Object::instantiate"), ("DISCARD_FRAME", "FrameBuffer::render_async")] {
        let output = compile(&source, Linking::Shared, &dir.join(define)).arg(format!("-D{define}")).output().expect("g++ runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{define}: dropping the result of {call} compiled");
        assert!(stderr.contains("nodiscard") && stderr.contains(call), "{define}: g++ says:\n{stderr}");
    }
}

/// The OpenGL 1.x calls a porter needs (`tests/c/gl_port.c`): orthographic and off-axis
/// cameras, the clear colour, `rtColor4f`, `rtVertex2f`, the double-precision calls, internal
/// formats 3 and 4, the `rtGet*` queries, `rtEndObject` closing a primitive, and
/// `RT_MAX_COORDINATE`, with their errors; the program checks its pixels and errors itself.
#[test]
fn gl_port_checks_pass() {
    for linking in [Linking::Shared, Linking::Static] {
        build_and_run("crates/capi/tests/c/gl_port.c", linking, &[]);
    }
}

/// Asynchronous frames from C (`tests/c/async_frames.c`): an interactive loop that polls
/// progress, an edit while a frame renders, a cancelled frame that stops at once, frames in
/// flight on two threads' contexts, and bad handles; the program checks itself.
#[test]
fn async_frame_checks_pass() {
    for linking in [Linking::Shared, Linking::Static] {
        build_and_run("crates/capi/tests/c/async_frames.c", linking, &[]);
    }
}

/// Sequences of public calls that once broke rt.h's rules (`tests/c/call_sequences.c`): a
/// window resized while the context rendered into its pixels, frame handles reused after
/// `rtResetContext`, a refused `rtutSwapBuffers` that kept its loan, and depths beyond single
/// precision; the program checks itself. Where valgrind is installed it runs again under it,
/// which fails on any access to freed memory (the resize wrote 16 KiB into freed heap).
#[test]
fn call_sequence_checks_pass() {
    let dir = build_and_run("crates/capi/tests/c/call_sequences.c", Linking::Rtut, &[]);
    if missing("valgrind") {
        return;
    }
    run(Command::new("valgrind")
        .args(["--quiet", "--error-exitcode=99", "--errors-for-leak-kinds=none", "./call_sequences"])
        .current_dir(&dir)
        .env("LD_LIBRARY_PATH", prefix().join("lib")));
}

/// rt.h and rtut.h as GL 1.x-era code builds them: a C program including them (twice, as headers
/// get) builds and links against the installed libraries with `-std=c89 -pedantic -Werror`, and
/// with C99, C11, C++98 and C++17 under `-Wall -Wextra -Werror -pedantic`.
#[test]
fn the_header_builds_under_every_c_and_cpp_standard() {
    if missing("gcc") || missing("g++") {
        return;
    }
    let dir = scratch("standards");
    let source = "#include <raystage/rtut.h>\n#include <raystage/rt.h>\n#include <raystage/rtut.h>\n\
                  int main(void) { rtutInit(NULL, NULL); rtResetContext(); return (int)rtGetError(); }\n";
    for (compiler, standard, name) in [("gcc", "c89", "c89.c"), ("gcc", "c99", "c99.c"), ("gcc", "c11", "c11.c"), ("g++", "c++98", "cxx98.cpp"), ("g++", "c++17", "cxx17.cpp")] {
        let file = dir.join(name);
        std::fs::write(&file, source).unwrap();
        let exe = dir.join(format!("{standard}-program"));
        run(Command::new(compiler)
            .args([&format!("-std={standard}"), "-pedantic", "-Wall", "-Wextra", "-Werror"])
            .arg(&file)
            .arg("-o")
            .arg(&exe)
            .args(pkg_config("rtut")));
        run(Command::new(&exe).env("LD_LIBRARY_PATH", prefix().join("lib")));
    }
}

/// A program that opens no window links no window toolkit (issue 37): built against the
/// installed library without RTUT, shared or static, neither `ldd` nor any library it loads
/// names X11, OpenGL, EGL, Wayland or librtut. The libraries are read as well as listed,
/// because the toolkit opens X11 and OpenGL with dlopen, which `ldd` does not show: librtut.so,
/// checked the same way, must name them, or the check would prove nothing.
#[test]
fn a_program_without_rtut_links_no_window_toolkit() {
    let toolkit = ["libX11", "libGL.so", "libEGL", "libwayland-client", "libxkbcommon", "librtut"];
    let names_toolkit = |file: &Path| {
        let bytes = std::fs::read(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        toolkit.iter().filter(|name| bytes.windows(name.len()).any(|w| w == name.as_bytes())).copied().collect::<Vec<_>>()
    };
    for linking in [Linking::Shared, Linking::Static] {
        let dir = build_and_run("examples/c/late_binding.c", linking, &[]);
        let exe = dir.join("late_binding");
        let ldd = run(Command::new("ldd").arg(&exe).env("LD_LIBRARY_PATH", prefix().join("lib")));
        let loaded: Vec<PathBuf> = ldd.lines().filter_map(|l| l.split("=>").nth(1)?.split_whitespace().next()).map(PathBuf::from).collect();
        assert!(loaded.iter().any(|l| l.starts_with("/")), "{linking:?}: ldd lists no library: {ldd}");
        for file in std::iter::once(exe).chain(loaded) {
            let named = names_toolkit(&file);
            assert!(named.is_empty(), "{linking:?}: {} names {named:?}; ldd says:\n{ldd}", file.display());
        }
    }
    let rtut = names_toolkit(&prefix().join("lib/librtut.so.0"));
    assert!(rtut.contains(&"libX11") && rtut.contains(&"libGL.so"), "librtut.so names {rtut:?}: the check above finds nothing");
}

/// The build tree's library has the installed one's name: a program links with `-lraystage`
/// against cargo's output directory as against an install, and finds it by its SONAME.
#[test]
fn the_build_tree_links_with_the_installed_name() {
    let dir = scratch("build-tree");
    let exe = dir.join("late_binding");
    run(Command::new("gcc")
        .args(["-std=c99", "-O1"])
        .arg(root().join("examples/c/late_binding.c"))
        .arg(format!("-I{}", root().join("api/include").display()))
        .arg(format!("-L{}", artifact_dir().display()))
        .args(["-lraystage", "-lm", "-o"])
        .arg(&exe));
    let needed = run(Command::new("readelf").arg("-d").arg(&exe));
    assert!(needed.contains("Shared library: [libraystage.so.0]"), "the versioned SONAME: {needed}");
    run(Command::new(&exe).current_dir(&dir).env("LD_LIBRARY_PATH", artifact_dir()));
    assert!(frame(&dir, "late_binding.png").get_pixel(116, 45)[1] > 200, "triangle B is green");
}

/// The libraries are installed as distributions ship them: `libraystage.so.0.Y.Z` and
/// `librtut.so.0.Y.Z` with the SONAMEs `libraystage.so.0` and `librtut.so.0` and the links a
/// linker and the loader follow, stripped of their debug information, which lies beside them in
/// `lib/.debug` (linked for gdb); the archive stripped too. librtut needs libraystage, as libglut
/// needs libGL.
#[test]
fn the_installed_libraries_are_versioned_and_stripped() {
    let lib = prefix().join("lib");
    let version = env!("CARGO_PKG_VERSION");
    for name in ["libraystage", "librtut"] {
        let real = lib.join(format!("{name}.so.{version}"));
        assert_eq!(std::fs::read_link(lib.join(format!("{name}.so"))).unwrap(), Path::new(&format!("{name}.so.0")));
        assert_eq!(std::fs::read_link(lib.join(format!("{name}.so.0"))).unwrap(), Path::new(&format!("{name}.so.{version}")));
        let dynamic = run(Command::new("readelf").arg("-d").arg(&real));
        assert!(dynamic.contains(&format!("Library soname: [{name}.so.0]")), "{dynamic}");
        if name == "librtut" {
            assert!(dynamic.contains("Shared library: [libraystage.so.0]"), "librtut needs libraystage: {dynamic}");
        }
        let sections = run(Command::new("readelf").arg("-S").arg(&real));
        assert!(!sections.contains(".debug_line") && sections.contains(".gnu_debuglink"), "{name}: stripped, with a debug link: {sections}");
        let debug = run(Command::new("readelf").arg("-S").arg(lib.join(format!(".debug/{name}.so.{version}.debug"))));
        assert!(debug.contains(".debug_line"), "{name}: the line tables kept apart");
    }
    let archive = run(Command::new("readelf").arg("-S").arg(lib.join("libraystage.a")));
    assert!(!archive.contains(".debug_line"), "the archive stripped");
}

/// The installed tree works where it is moved: the `.pc` files find the prefix from their own
/// location, so a program builds and runs against the moved copy with its pkg-config flags.
#[test]
fn a_moved_install_still_builds() {
    let moved = scratch("moved").join("elsewhere");
    run(Command::new("cp").arg("-r").arg(prefix()).arg(&moved));
    let dir = scratch("moved-build");
    for package in ["raystage", "raystage-static"] {
        let flags = run(Command::new("pkg-config").env("PKG_CONFIG_PATH", moved.join("lib/pkgconfig")).args(["--cflags", "--libs", package]));
        assert!(!flags.contains(&prefix().display().to_string()), "{package}: the flags name the old prefix: {flags}");
        let exe = dir.join(package);
        run(Command::new("gcc")
            .args(["-std=c99", "-O1"])
            .arg(root().join("examples/c/late_binding.c"))
            .arg("-o")
            .arg(&exe)
            .args(flags.split_whitespace())
            .arg("-lm"));
        run(Command::new(&exe).current_dir(&dir).env("LD_LIBRARY_PATH", moved.join("lib")));
        assert!(frame(&dir, "late_binding.png").get_pixel(116, 45)[1] > 200, "{package}: triangle B is green");
    }
}

/// `find_package(raystage)` finds the installed library, for the shared and the static target,
/// and RTUT's, `raystage::rtut`, which brings the shared library with it.
#[test]
fn cmake_finds_the_installed_package() {
    if missing("cmake") {
        return;
    }
    let dir = scratch("cmake");
    let source = root().join("examples/c/late_binding.c");
    std::fs::write(
        dir.join("CMakeLists.txt"),
        format!(
            "cmake_minimum_required(VERSION 3.13)\nproject(uses_raystage C)\nfind_package(raystage 0.1 REQUIRED)\n\
             add_executable(shared_example \"{0}\")\ntarget_link_libraries(shared_example raystage::raystage)\n\
             add_executable(static_example \"{0}\")\ntarget_link_libraries(static_example raystage::raystage_static m)\n\
             add_executable(rtut_example \"{1}\")\ntarget_include_directories(rtut_example PRIVATE \"{2}\")\n\
             target_link_libraries(rtut_example raystage::rtut)\n",
            source.display(),
            root().join("crates/capi/tests/c/rtut_window.c").display(),
            root().join("crates/capi/tests/c").display()
        ),
    )
    .unwrap();
    let build = dir.join("build");
    run(Command::new("cmake").arg("-S").arg(&dir).arg("-B").arg(&build).arg(format!("-DCMAKE_PREFIX_PATH={}", prefix().display())));
    run(Command::new("cmake").arg("--build").arg(&build));
    for exe in ["shared_example", "static_example"] {
        run(Command::new(build.join(exe)).current_dir(&build));
        let image = frame(&build, "late_binding.png");
        assert!(image.get_pixel(116, 45)[1] > 200, "{exe}: triangle B is green");
    }
    run(Command::new(build.join("rtut_example")).current_dir(&build).env("RTUT_HEADLESS", "1").env("RTUT_OUTPUT", "rtut"));
    red_square_on_blue(&frame(&build, "rtut-0000.png"), "rtut_example");
}

/// `find_package(raystage)` gives C++ programs `raystage::cpp` and `raystage::cpp_static`, which
/// raise the language standard to the C++17 the wrapper needs: the project asks for C++11, under
/// which rt.hpp refuses to compile.
#[test]
fn cmake_builds_against_the_cpp_targets() {
    if missing("cmake") || missing("g++") {
        return;
    }
    let dir = scratch("cmake-cpp");
    let source = root().join("examples/cpp/spin.cpp");
    std::fs::write(
        dir.join("CMakeLists.txt"),
        format!(
            "cmake_minimum_required(VERSION 3.13)\nproject(uses_raystage_cpp CXX)\nset(CMAKE_CXX_STANDARD 11)\n\
             find_package(raystage 0.1 REQUIRED)\n\
             add_executable(shared_spin \"{0}\")\ntarget_link_libraries(shared_spin raystage::cpp)\n\
             add_executable(static_spin \"{0}\")\ntarget_link_libraries(static_spin raystage::cpp_static m)\n",
            source.display()
        ),
    )
    .unwrap();
    let build = dir.join("build");
    run(Command::new("cmake").arg("-S").arg(&dir).arg("-B").arg(&build).arg(format!("-DCMAKE_PREFIX_PATH={}", prefix().display())));
    run(Command::new("cmake").arg("--build").arg(&build));
    for exe in ["shared_spin", "static_spin"] {
        run(Command::new(build.join(exe)).args(["2", "160", "120"]).current_dir(&build));
        check_spin_frames(&build, exe);
    }
    let ldd = run(Command::new("ldd").arg(build.join("static_spin")));
    assert!(!ldd.contains("libraystage"), "raystage::cpp_static links the shared library: {ldd}");
}

/// Builds `tests/c/rtut_window.c` against the installed shared libraries; returns its path.
fn rtut_program(name: &str) -> PathBuf {
    let source = root().join("crates/capi/tests/c/rtut_window.c");
    let exe = scratch(name).join("rtut_window");
    run(&mut compile(&source, Linking::Rtut, &exe));
    exe
}

/// Pixels of `image` at its centre and its corner: the red square and the blue clear colour.
fn red_square_on_blue(image: &RgbaImage, what: &str) {
    let (w, h) = image.dimensions();
    let centre = image.get_pixel(w / 2, h / 2).0;
    let corner = image.get_pixel(3, 3).0;
    assert!(centre[0] > 200 && centre[1] < 40 && centre[2] < 40, "{what}: the centre is {centre:?}, not the red square");
    assert!(corner[2] > 200 && corner[0] < 40 && corner[1] < 40, "{what}: the corner is {corner:?}, not the blue clear colour");
}

/// RTUT without a display (`tests/c/rtut_window.c`): the main loop calls reshape once, then
/// display as the idle callback posts redisplays, writes each frame as a PNG file and returns
/// after `RTUT_FRAMES`; the program checks the calls' errors itself.
#[test]
fn rtut_runs_headless_without_a_display() {
    let exe = rtut_program("rtut-headless");
    let dir = exe.parent().unwrap();
    let out = run(Command::new(&exe)
        .arg("--animate")
        .current_dir(dir)
        .env("LD_LIBRARY_PATH", prefix().join("lib"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env("RTUT_FRAMES", "3")
        .env("RTUT_OUTPUT", "frame"));
    assert_eq!(out.lines().collect::<Vec<_>>(), ["reshape 160 120", "display 1", "display 2", "display 3", "done 3"]);
    for n in 0..3 {
        let image = frame(dir, &format!("frame-{n:04}.png"));
        assert_eq!(image.dimensions(), (160, 120));
        red_square_on_blue(&image, &format!("frame {n}"));
    }
    assert!(!dir.join("frame-0003.png").exists(), "three frames, no more");
}

/// A virtual X server on a free display, killed when dropped.
struct Xvfb(std::process::Child, String);

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Starts Xvfb on a display no other test of this process's number uses.
fn xvfb() -> Xvfb {
    let first = 600 + std::process::id() % 300;
    for n in first..first + 50 {
        if Path::new(&format!("/tmp/.X{n}-lock")).exists() {
            continue;
        }
        let mut child = Command::new("Xvfb").args([format!(":{n}").as_str(), "-screen", "0", "640x480x24", "-nolisten", "tcp"]).spawn().expect("Xvfb starts");
        for _ in 0..500 {
            if Path::new(&format!("/tmp/.X11-unix/X{n}")).exists() {
                return Xvfb(child, format!(":{n}"));
            }
            if child.try_wait().ok().flatten().is_some() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        let _ = child.kill();
        let _ = child.wait();
    }
    panic!("Xvfb did not start on any display from :{first}");
}

/// RTUT in a window, under Xvfb: the window shows the frame the display callback rendered (a
/// screenshot of it), a click reaches the mouse callback at the pixel rtPick reads, 'r'
/// redisplays and 'q' leaves the main loop, which returns. Input comes from xdotool.
#[test]
fn rtut_shows_frames_in_a_window_and_takes_keys_and_clicks() {
    if missing("Xvfb") || missing("xdotool") {
        assert!(std::env::var_os("CI").is_none(), "Xvfb and xdotool are needed on CI: scripts/test.sh installs them");
        return;
    }
    use std::io::{BufRead, BufReader};
    use std::time::Duration;
    let exe = rtut_program("rtut-window");
    let dir = exe.parent().unwrap().to_path_buf();
    let x = xvfb();
    let mut program = Command::new(&exe)
        .current_dir(&dir)
        .env("LD_LIBRARY_PATH", prefix().join("lib"))
        .env("DISPLAY", &x.1)
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("RTUT_HEADLESS")
        .env("RTUT_SCREENSHOT", dir.join("shot.png"))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let (lines, seen) = std::sync::mpsc::channel();
    let stdout = program.stdout.take().unwrap();
    std::thread::spawn(move || BufReader::new(stdout).lines().map_while(Result::ok).for_each(|l| drop(lines.send(l))));
    let mut log = Vec::new();
    let wait_for = |prefix: &str, log: &mut Vec<String>| loop {
        match seen.recv_timeout(Duration::from_secs(60)) {
            Ok(line) if line.starts_with(prefix) => {
                log.push(line.clone());
                return line;
            }
            Ok(line) => log.push(line),
            Err(_) => panic!("no `{prefix}` line within 60 s; the program printed {log:?}"),
        }
    };
    let xdotool = |args: &[&str]| run(Command::new("xdotool").args(args).env("DISPLAY", &x.1));

    assert_eq!(wait_for("reshape", &mut log), "reshape 160 120");
    wait_for("display 1", &mut log);
    let window = xdotool(&["search", "--sync", "--onlyvisible", "--name", "rtut window test"]).lines().next().expect("the window's id").to_string();
    xdotool(&["windowfocus", "--sync", &window]);
    // The window's centre: the red square.
    xdotool(&["mousemove", "--window", &window, "80", "60", "click", "1"]);
    let down = wait_for("mouse", &mut log);
    let up = wait_for("mouse", &mut log);
    assert_eq!((down.as_str(), up.as_str()), ("mouse 0 0 80 60 hit 1", "mouse 0 1 80 60 hit 1"));
    xdotool(&["key", "r"]);
    assert_eq!(wait_for("key", &mut log), "key r 80 60");
    wait_for("display 2", &mut log);
    xdotool(&["key", "q"]);
    wait_for("key q", &mut log);
    let done = wait_for("done", &mut log);
    let status = program.wait().unwrap();
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut program.stderr.take().unwrap(), &mut stderr).unwrap();
    assert!(status.success() && done == "done 2", "the program ended {status} after {log:?}: {stderr}");
    let shot = frame(&dir, "shot.png");
    assert_eq!(shot.dimensions(), (160, 120), "the window's size");
    red_square_on_blue(&shot, "the window");
}
