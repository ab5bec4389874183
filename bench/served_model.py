#!/usr/bin/env python3
"""A generated model as the page meets it (docs/BENCHMARKS.md "Served models"): `penumbra serve` at
its defaults on a free port, the model's scene POSTed (the wall seconds of the answer and its
`build_seconds`), the binary mesh fetched, then --moves moves of the model along x, each a frame
POSTed and its mesh delta fetched (median seconds and delta bytes). With --before OLD/penumbra
each row runs both binaries in turn on the same scene file, so the pair shares the machine's load.

  python3 bench/served_model.py build/penumbra [--before OLD/penumbra] [--model teapot]
      [--triangles 6000] [--moves 5] [--dir /tmp/served_model]
"""
import argparse
import json
import os
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def call(url, body=None, method="GET"):
    request = urllib.request.Request(url, data=body, method=method, headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(request, timeout=600) as answer:
        return answer.read()


def serve(binary, data):
    port = free_port()
    server = subprocess.Popen([binary, "serve", "--port", str(port), "--data", data],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    base = f"http://127.0.0.1:{port}/api"
    for _ in range(600):
        try:
            call(f"{base}/health")
            return server, base
        except OSError:
            time.sleep(0.1)
    server.kill()
    sys.exit(f"{binary} serve did not answer")


def measure(binary, scene_file, model, moves):
    with tempfile.TemporaryDirectory() as data:
        server, base = serve(binary, data)
        try:
            start = time.monotonic()
            created = json.loads(call(f"{base}/scenes?name=m", open(scene_file, "rb").read(), "POST"))
            post = time.monotonic() - start
            mesh = call(f"{base}/scenes/m/mesh?format=bin")
            stats = json.loads(call(f"{base}/scenes/m/stats"))
            version, frames = created["version"], []
            for i in range(moves):
                edit = {"edits": [{"op": "move", "id": model, "transform": {"translate": [0.03 * (i + 1), 0, 0]}}]}
                start = time.monotonic()
                result = json.loads(call(f"{base}/scenes/m/edits", json.dumps(edit).encode(), "POST"))
                delta = call(f"{base}/scenes/m/mesh?since={version}&format=bin")
                frames.append((time.monotonic() - start, len(delta), bool(result.get("full_rebuild"))))
                version = result["version"]
        finally:
            server.terminate()
            server.wait()
    vertices = stats["build"]["vertices"]
    return {"post_s": post, "engine_s": created["build_seconds"], "mesh_triangles": stats["mesh"]["triangles"],
            "mesh_bytes": len(mesh), "dm_vertices_lit": vertices["total"] - vertices.get("not_lit_lattice_display", 0),
            "move_s_median": statistics.median(f[0] for f in frames) if frames else None,
            "delta_bytes_median": statistics.median(f[1] for f in frames) if frames else None,
            "full_rebuilds": sum(f[2] for f in frames)}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("penumbra")
    parser.add_argument("--before")
    parser.add_argument("--model", default="teapot")
    parser.add_argument("--triangles", type=int, default=6000)
    parser.add_argument("--moves", type=int, default=5)
    parser.add_argument("--dir", default=os.path.join(tempfile.gettempdir(), "served_model"))
    args = parser.parse_args()
    os.makedirs(args.dir, exist_ok=True)
    scene = os.path.join(args.dir, f"{args.model}{args.triangles}.json")
    subprocess.run([args.penumbra, "generate", "--model", args.model, "--triangles", str(args.triangles),
                    "--out", scene], check=True, stdout=subprocess.DEVNULL)
    object_id = args.model.replace("-", "_")  # the generator names the object after its model
    for label, binary in ([("before", args.before)] if args.before else []) + [("after", args.penumbra)]:
        row = measure(binary, scene, object_id, args.moves)
        print(json.dumps({"binary": label, "model": args.model, "triangles": args.triangles, **row}))


if __name__ == "__main__":
    main()
