#!/usr/bin/env bash
# Installs raystage's C library, and RTUT's, under PREFIX (any writable directory; no root
# needed):
#
#   PREFIX/lib/libraystage.so.X.Y.Z (SONAME libraystage.so.X), with the links libraystage.so.X
#     and libraystage.so to it; PREFIX/lib/libraystage.a; PREFIX/lib/librtut.so.X.Y.Z (SONAME
#     librtut.so.X, needing libraystage.so.X) with its links: RTUT's windows, shared only. All
#     stripped of debug information, which goes to PREFIX/lib/.debug/ (where gdb looks for a
#     .so's .gnu_debuglink)
#   PREFIX/include/raystage/rt.h, PREFIX/include/raystage/rt.hpp (the C++ wrapper, header-only),
#     PREFIX/include/raystage/rtut.h
#   PREFIX/lib/pkgconfig/raystage.pc          pkg-config --cflags --libs raystage
#   PREFIX/lib/pkgconfig/raystage-static.pc   pkg-config --cflags --libs raystage-static
#   PREFIX/lib/pkgconfig/rtut.pc              pkg-config --cflags --libs rtut (-lrtut -lraystage)
#   PREFIX/lib/cmake/raystage/raystageConfig.cmake (+ ConfigVersion)   find_package(raystage)
#
# Usage: scripts/install-capi.sh [--lib-dir DIR] PREFIX
#   Without --lib-dir, the libraries are built first with
#   `cargo build --release -p libraystage -p raystage-rtut`. With --lib-dir, the libraystage.so,
#   libraystage.a and librtut.so that cargo left in DIR (for example target/debug) are installed
#   as they are: the build tree and the install use the same names.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

usage() {
    echo "usage: $0 [--lib-dir DIR] PREFIX" >&2
    exit 2
}

lib_dir=""
while (($# > 0)); do
    case "$1" in
        --lib-dir) (($# >= 2)) || usage; lib_dir="$2"; shift 2 ;;
        -h | --help) usage ;;
        -*) usage ;;
        *) break ;;
    esac
done
(($# == 1)) || usage
mkdir -p "$1"
prefix="$(cd "$1" && pwd)"

if [[ -z "$lib_dir" ]]; then
    (cd "$root" && cargo build --release -p libraystage -p raystage-rtut)
    lib_dir="${CARGO_TARGET_DIR:-$root/target}/release"
fi
for artifact in libraystage.so libraystage.a librtut.so; do
    [[ -f "$lib_dir/$artifact" ]] || { echo "$0: $lib_dir/$artifact not found" >&2; exit 1; }
done

version="$(sed -n 's/^version = "\(.*\)"/\1/p' "$root/Cargo.toml" | head -n 1)"
# What Rust's standard library needs from the system when linked statically
# (rustc --print native-static-libs).
static_deps=(gcc_s util rt pthread m dl c)
# A library built with the `mpi` feature (rtInitMPI) needs MPI's too, and C++'s standard
# library: its cluster serves glTF uploads, whose compressed buffers meshoptimizer's C++
# decoder reads.
if readelf -d "$lib_dir/libraystage.so" 2>/dev/null | grep -q 'NEEDED.*libstdc++'; then
    static_deps=(stdc++ "${static_deps[@]}")
fi
if readelf -d "$lib_dir/libraystage.so" 2>/dev/null | grep -q 'NEEDED.*libmpi'; then
    static_deps=(mpi "${static_deps[@]}")
fi

install -d "$prefix/lib/pkgconfig" "$prefix/lib/cmake/raystage" "$prefix/include/raystage" "$prefix/lib/.debug"
major="${version%%.*}"
for name in libraystage librtut; do
    install -m 0755 "$lib_dir/$name.so" "$prefix/lib/$name.so.$version"
    ln -sfn "$name.so.$version" "$prefix/lib/$name.so.$major"
    ln -sfn "$name.so.$major" "$prefix/lib/$name.so"
done
install -m 0644 "$lib_dir/libraystage.a" "$prefix/lib/libraystage.a"
# Debug information apart, as distributions ship it (-dbg packages): a program linked against
# the library does not carry it, a debugger still finds it.
for file in "libraystage.so.$version" libraystage.a "librtut.so.$version"; do
    if command -v objcopy >/dev/null; then
        objcopy --only-keep-debug "$prefix/lib/$file" "$prefix/lib/.debug/$file.debug"
        objcopy --strip-debug "$prefix/lib/$file"
        # An archive's members cannot carry a debug link; the .so can.
        if [[ "$file" == *.so.* ]]; then
            objcopy --add-gnu-debuglink="$prefix/lib/.debug/$file.debug" "$prefix/lib/$file"
        fi
    fi
done
install -m 0644 "$root/api/include/raystage/rt.h" "$root/api/include/raystage/rt.hpp" "$root/api/include/raystage/rtut.h" "$prefix/include/raystage/"

# The .pc files find the prefix from their own location (pkg-config's pcfiledir), as the CMake
# config does, so that the installed tree can be moved.
cat >"$prefix/lib/pkgconfig/raystage.pc" <<EOF
prefix=\${pcfiledir}/../..
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: raystage
Description: Ray tracing through an OpenGL-like C API (OpenRT style)
Version: $version
Cflags: -I\${includedir}
Libs: -L\${libdir} -lraystage
EOF

cat >"$prefix/lib/pkgconfig/raystage-static.pc" <<EOF
prefix=\${pcfiledir}/../..
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: raystage-static
Description: raystage's C API, linked statically
Version: $version
Cflags: -I\${includedir}
Libs: \${libdir}/libraystage.a ${static_deps[*]/#/-l}
EOF

# RTUT is written on libraystage.so and needs it: Requires brings -lraystage.
cat >"$prefix/lib/pkgconfig/rtut.pc" <<EOF
prefix=\${pcfiledir}/../..
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: rtut
Description: RTUT, raystage's GLUT: windows for a raystage program's frames (shared only)
Version: $version
Requires: raystage = $version
Cflags: -I\${includedir}
Libs: -L\${libdir} -lrtut
EOF

cat >"$prefix/lib/cmake/raystage/raystageConfig.cmake" <<EOF
# raystage's C library. Imported targets:
#   raystage::raystage         the shared library libraystage.so (SONAME libraystage.so.$major)
#   raystage::raystage_static  the static library libraystage.a, with the system libraries it needs
#   raystage::cpp              the C++ wrapper raystage/rt.hpp (header-only, C++17) on the shared library
#   raystage::cpp_static       the same on the static library
#   raystage::rtut             RTUT's shared library librtut.so (SONAME librtut.so.$major), on raystage::raystage
# The paths are found from this file's location, so the installed tree can be moved.
get_filename_component(_raystage_prefix "\${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET raystage::raystage)
  add_library(raystage::raystage SHARED IMPORTED)
  set_target_properties(raystage::raystage PROPERTIES
    IMPORTED_LOCATION "\${_raystage_prefix}/lib/libraystage.so"
    IMPORTED_SONAME "libraystage.so.$major"
    INTERFACE_INCLUDE_DIRECTORIES "\${_raystage_prefix}/include")
  add_library(raystage::raystage_static STATIC IMPORTED)
  set_target_properties(raystage::raystage_static PROPERTIES
    IMPORTED_LOCATION "\${_raystage_prefix}/lib/libraystage.a"
    INTERFACE_INCLUDE_DIRECTORIES "\${_raystage_prefix}/include"
    INTERFACE_LINK_LIBRARIES "$(IFS=';'; echo "${static_deps[*]}")")
  # The wrapper is only a header: its targets add the C++ standard it needs to a library's.
  add_library(raystage::cpp INTERFACE IMPORTED)
  set_target_properties(raystage::cpp PROPERTIES
    INTERFACE_LINK_LIBRARIES raystage::raystage
    INTERFACE_COMPILE_FEATURES cxx_std_17)
  add_library(raystage::cpp_static INTERFACE IMPORTED)
  set_target_properties(raystage::cpp_static PROPERTIES
    INTERFACE_LINK_LIBRARIES raystage::raystage_static
    INTERFACE_COMPILE_FEATURES cxx_std_17)
  add_library(raystage::rtut SHARED IMPORTED)
  set_target_properties(raystage::rtut PROPERTIES
    IMPORTED_LOCATION "\${_raystage_prefix}/lib/librtut.so"
    IMPORTED_SONAME "librtut.so.$major"
    INTERFACE_LINK_LIBRARIES raystage::raystage)
endif()
set(raystage_INCLUDE_DIRS "\${_raystage_prefix}/include")
set(raystage_LIBRARIES raystage::raystage)
unset(_raystage_prefix)
EOF

cat >"$prefix/lib/cmake/raystage/raystageConfigVersion.cmake" <<EOF
# Any requested version up to $version is satisfied.
set(PACKAGE_VERSION "$version")
if(PACKAGE_FIND_VERSION VERSION_GREATER PACKAGE_VERSION)
  set(PACKAGE_VERSION_COMPATIBLE FALSE)
else()
  set(PACKAGE_VERSION_COMPATIBLE TRUE)
  if(PACKAGE_FIND_VERSION VERSION_EQUAL PACKAGE_VERSION)
    set(PACKAGE_VERSION_EXACT TRUE)
  endif()
endif()
EOF

echo "installed raystage $version under $prefix"
