#!/usr/bin/env bash
# Runs schemathesis against `raystage serve` with every check: the server must answer what its
# OpenAPI description (/openapi.json) allows, accept every request the description allows (or
# answer one of the statuses api/schemathesis.toml allows, each with its reason), refuse every
# request it forbids, and never answer 5xx. Builds nothing: the server binary is the first
# argument (default target/debug/raystage, under CARGO_TARGET_DIR if set). A fixed seed and a
# small budget (25 examples an operation) keep the run under a few minutes on two cores.
# Exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

server=${1:-${CARGO_TARGET_DIR:-target}/debug/raystage}
if [[ ! -x $server ]]; then
    echo "schemathesis.sh: no server binary at $server: build it first (cargo build -p raystage)" >&2
    exit 2
fi
command -v st >/dev/null || { echo "schemathesis.sh: schemathesis (st) is not installed" >&2; exit 2; }

# A free loopback port: the kernel picks one for a socket that is closed at once.
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
log=$(mktemp)
"$server" serve --demo spheres --addr "127.0.0.1:$port" >"$log" 2>&1 &
pid=$!
# The exit status stays st's: the trap's own commands do not change it.
trap 'kill "$pid" 2>/dev/null; wait "$pid" 2>/dev/null || true; rm -f "$log"' EXIT
for _ in $(seq 100); do
    curl -sf "http://127.0.0.1:$port/" >/dev/null 2>&1 && break
    kill -0 "$pid" 2>/dev/null || { echo "schemathesis.sh: the server did not start:" >&2; cat "$log" >&2; exit 1; }
    sleep 0.1
done

echo "+ st run http://127.0.0.1:$port/openapi.json (every check, seed 1, 25 examples an operation)"
status=0
PYTHONPATH=api${PYTHONPATH:+:$PYTHONPATH} SCHEMATHESIS_HOOKS=schemathesis_hooks \
    st --config-file api/schemathesis.toml run "http://127.0.0.1:$port/openapi.json" \
    --checks all --max-examples 25 --seed 1 --workers 1 --no-color || status=$?
exit "$status"
