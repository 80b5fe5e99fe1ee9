#!/usr/bin/env bash
# Runs every test of the workspace. As root on Debian it first installs the system packages the
# tests need (Embree 3, for the benchmark's side-by-side checks; gcc, g++, pkg-config and CMake,
# to build the C and C++ examples against the installed C library; Xvfb and Mesa, for the
# viewer's and RTUT's window tests, and xdotool to type into RTUT's; Chromium and Firefox, for the
# viewer page's browser tests; Open MPI and libclang, for rendering across MPI ranks); with Embree's
# headers present, the benchmark crate is tested with its `embree` feature, and with Open MPI
# the command line and the C library with their `mpi` features.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

packages=(libembree-dev gcc g++ pkg-config cmake)
# The viewer's window tests (crates/client/tests/window.rs, tests/cli_view.rs): a virtual X server (Xvfb, xvfb-run), Mesa's software
# OpenGL through GLX (llvmpipe), and the X libraries winit loads at run time.
packages+=(xvfb libgl1 libglx-mesa0 libgl1-mesa-dri libegl1 libx11-xcb1 libxcursor1 libxi6 libxkbcommon-x11-0)
# RTUT's window test (crates/capi/tests/examples.rs) types keys and clicks into its window.
packages+=(xdotool)
# The API's schemathesis run (scripts/schemathesis.sh) waits for the server with curl.
packages+=(curl)
# The viewer page's browser tests (crates/server/tests/browser.rs) drive headless Chromium
# (over the DevTools protocol) and headless Firefox (over WebDriver BiDi, which Firefox speaks
# itself: no geckodriver).
packages+=(chromium firefox-esr)
# The C ABI's memory checks (crates/capi/tests: random_calls.rs, examples.rs) run under valgrind.
packages+=(valgrind)
# Rendering across MPI ranks (the root crate's `mpi` feature, tests/cli_mpi.rs): Open MPI, and
# libclang for the bindings rsmpi generates at build time.
packages+=(libopenmpi-dev openmpi-bin libclang1-14 libclang-common-14-dev)

if [[ $(id -u) -eq 0 ]] && command -v apt-get >/dev/null; then
    missing=()
    for package in "${packages[@]}"; do
        dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
    done
    if ((${#missing[@]} > 0)); then
        echo "+ installing ${missing[*]}"
        apt-get update
        DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
    fi
fi

status=0
# The documentation's relative links (README.md, CHANGELOG.md, docs/) name files that exist.
scripts/check-doc-links.sh || status=$?

# --no-fail-fast: one run reports every failing test binary, not just the first.
args=(--workspace --no-fail-fast)
if [[ -f /usr/include/embree3/rtcore.h ]] && grep -qE '^embree[[:space:]]*=' crates/bench/Cargo.toml 2>/dev/null; then
    args+=(--features raystage-bench/embree)
fi
if command -v mpirun >/dev/null && [[ -f /usr/lib/x86_64-linux-gnu/openmpi/include/mpi.h || -f /usr/include/mpi.h ]]; then
    args+=(--features raystage/mpi --features raystage-capi/mpi)
fi
echo "+ cargo test ${args[*]}"
cargo test "${args[@]}" || status=$?

# The API against its OpenAPI description (scripts/schemathesis.sh), with the debug server the
# tests above built (cargo test builds the binary for the command line's tests). As root, schemathesis is installed when missing (the pinned version whose
# checks api/schemathesis.toml was written for); where it cannot be installed, the run is
# skipped with a line saying so.
if ! command -v st >/dev/null && [[ $(id -u) -eq 0 ]] && command -v pip >/dev/null; then
    echo "+ pip install schemathesis==4.32.5"
    pip install -q schemathesis==4.32.5 || pip install -q --break-system-packages schemathesis==4.32.5 || true
fi
if command -v st >/dev/null; then
    scripts/schemathesis.sh "${CARGO_TARGET_DIR:-target}/debug/raystage"
else
    echo "+ skipping scripts/schemathesis.sh: schemathesis (st) is not installed and could not be installed"
fi
exit "$status"
