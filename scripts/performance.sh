#!/usr/bin/env bash
# Measures the benchmarks and makes docs/performance/'s pages from their reports: for each one,
# `raystage-bench NAME ... --json` writes docs/performance/data/NAME.jsonl (its first line the
# run's stamp: machine, commit, date) and `raystage-bench page` turns that into
# docs/performance/NAME.md. Nothing in those pages is typed by hand; rerun this to refresh them.
#
#   scripts/performance.sh                 # every benchmark this machine can run
#   scripts/performance.sh kernel scaling  # some of them
#
# Embree is measured beside raystage when its headers are installed (`libembree-dev`); the
# path-tracing benchmark needs Mitsuba 3 (`pip install mitsuba`, or PYTHON naming a Python that
# has it) and is skipped without it. Takes about 20 minutes on 2 cores for everything; run it on a
# quiet machine, and commit the pages with the code they measured.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

out=docs/performance
mkdir -p "$out/data"
features=()
if [[ -f /usr/include/embree3/rtcore.h ]]; then
    features=(--features embree)
fi
cargo build --release -p raystage-bench "${features[@]}"
bench="${CARGO_TARGET_DIR:-target}/release/raystage-bench"
python="${PYTHON:-python3}"
# Mitsuba's JIT-vectorised variant is timed too where LLVM 19 is installed for it.
variants=scalar_rgb
llvm=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
if [[ -f $llvm ]]; then
    export DRJIT_LIBLLVM_PATH="${DRJIT_LIBLLVM_PATH:-$llvm}"
    variants=scalar_rgb,llvm_ad_rgb
fi
# Images the benchmarks write beside their reports (plots, renders) stay out of the repository.
scratch="${CARGO_TARGET_DIR:-target}/performance"
mkdir -p "$scratch"

# The arguments of each benchmark's measured run: sizes that finish in minutes on 2 cores.
declare -A args=(
    [kernel]="kernel --scene all --reps 3"
    [dynamic]="dynamic --scene all --frames 20 --threads 2"
    [render]="render --reps 3 --plot $scratch/convergence.png"
    [scaling]="scaling --scene all --reps 3"
    [pathtrace]="pathtrace --scene room --python $python --dir $scratch/pathtrace"
    [pathtrace-spheres]="pathtrace --scene spheres --variants $variants --python $python --dir $scratch/pathtrace"
    [bounces]="bounces --scene all --reps 5"
)
order=(kernel dynamic render scaling pathtrace pathtrace-spheres bounces)
names=("$@")
if ((${#names[@]} == 0)); then
    names=("${order[@]}")
fi

for name in "${names[@]}"; do
    if [[ -z ${args[$name]+set} ]]; then
        echo "unknown benchmark $name (expected: ${order[*]})" >&2
        exit 2
    fi
    if [[ $name == pathtrace* ]] && ! "$python" -c 'import mitsuba' 2>/dev/null; then
        echo "+ skipping $name: $python has no mitsuba (pip install mitsuba, or set PYTHON)"
        continue
    fi
    echo "+ raystage-bench ${args[$name]} --json"
    # shellcheck disable=SC2086 # the arguments are words
    "$bench" ${args[$name]} --json >"$out/data/$name.jsonl.new"
    mv "$out/data/$name.jsonl.new" "$out/data/$name.jsonl"
    "$bench" page "$out/data/$name.jsonl" >"$out/$name.md"
    echo "+ wrote $out/$name.md"
done
