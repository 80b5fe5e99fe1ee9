#!/usr/bin/env python3
# What replicating edits costs `raystage serve --mpi` (2 ranks of one thread) against `raystage
# serve` (one process): a 180,000-triangle object uploaded once, then per frame a small edit (a
# camera move) and a 640x360 path-traced frame at 4 spp; medians of 6 frames, with the frame's
# cluster times (sending the pass, the gather) from /scenes/1/stats. Needs mpirun and a raystage
# built with the `mpi` feature. Usage: scripts/serve-mpi-costs.py target/release/raystage
import json, subprocess, sys, time, urllib.request, os, signal, statistics

def start(cmd):
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env=dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1"))
    for line in p.stdout:
        if "http://" in line:
            return p, line.split("http://")[1].split("/")[0]
    raise SystemExit("no address")

def req(addr, method, path, body=None):
    data = None if body is None else json.dumps(body).encode()
    r = urllib.request.Request(f"http://{addr}{path}", data=data, method=method, headers={"content-type": "application/json"})
    t = time.perf_counter()
    with urllib.request.urlopen(r, timeout=600) as f:
        out = f.read()
    return time.perf_counter() - t, out

def grid(n):
    pos = [[x / n, y / n, 0.3 * ((x * 7 + y * 3) % 5) / 5] for y in range(n + 1) for x in range(n + 1)]
    idx = []
    for y in range(n):
        for x in range(n):
            a = y * (n + 1) + x
            idx += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
    return {"positions": pos, "indices": idx}

exe = sys.argv[1]
results = {}
for label, cmd in [("alone", [exe, "serve", "--addr", "127.0.0.1:0", "--demo", "cornell"]),
                   ("2 ranks", ["mpirun", "--oversubscribe", "--bind-to", "none", "-n", "2", "-x", "RAYON_NUM_THREADS=1", exe, "serve", "--addr", "127.0.0.1:0", "--demo", "cornell", "--mpi"])]:
    p, addr = start(cmd)
    mesh = grid(300)  # 180,000 triangles, 90,601 vertices
    body_mb = len(json.dumps({"mesh": mesh})) / 1e6
    t_upload, out = req(addr, "POST", "/scenes/1/objects", {"kind": "static", "mesh": mesh})
    obj = json.loads(out)["id"]
    req(addr, "POST", "/scenes/1/instances", {"object": obj, "transform": {"translate": [-0.5, 0.2, -0.5], "scale": 0.5}})
    edits, frames, sends, gathers = [], [], [], []
    for f in range(6):
        t_edit, _ = req(addr, "PUT", "/scenes/1/camera", {"eye": [0.1 * f, 1.0, 2.9]})
        t_frame, _ = req(addr, "GET", "/scenes/1/frame.png?width=640&height=360&spp=4&integrator=path")
        stats = json.loads(req(addr, "GET", "/scenes/1/stats")[1])["last_frame"]
        c = stats.get("cluster") or {}
        edits.append(t_edit); frames.append(t_frame); sends.append(c.get("send_seconds", 0)); gathers.append(c.get("gather_seconds", 0))
    results[label] = dict(upload_s=t_upload, body_mb=body_mb, edit_ms=statistics.median(edits) * 1e3, frame_s=statistics.median(frames), send_ms=statistics.median(sends) * 1e3, gather_ms=statistics.median(gathers) * 1e3)
    p.send_signal(signal.SIGTERM); p.wait(timeout=20)
print(json.dumps(results, indent=1))
