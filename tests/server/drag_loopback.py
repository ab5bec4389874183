#!/usr/bin/env python3
"""Loopback drag measure: drags one cube of a served scene in small steps, each step
= POST /edits + GET mesh?since=V&format=bin (what the page does per frame), and
prints edits/second and bytes per frame. Usage:
  python3 tests/server/drag_loopback.py --url http://127.0.0.1:8080 --scene cubes150 \
      [--object cube_0] [--steps 60] [--step 0.02] [--gzip]
"""
import argparse
import gzip
import http.client
import json
import statistics
import sys
import time
import urllib.parse

MESH_LAYOUT = 4  # the binary mesh layout this tool reads (docs/API.md "Binary")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--url", default="http://127.0.0.1:8080")
    ap.add_argument("--scene", required=True)
    ap.add_argument("--object", default="cube_0")
    ap.add_argument("--steps", type=int, default=60)
    ap.add_argument("--step", type=float, default=0.02, help="metres per step along x")
    ap.add_argument("--gzip", action="store_true", help="send Accept-Encoding: gzip for the mesh")
    args = ap.parse_args()

    url = urllib.parse.urlparse(args.url)
    conn = http.client.HTTPConnection(url.hostname, url.port, timeout=120)
    base = f"/api/scenes/{args.scene}"

    def request(method, path, body=None, headers=None):
        conn.request(method, path, body=body, headers=headers or {})
        res = conn.getresponse()
        data = res.read()
        if res.status >= 400:
            sys.exit(f"{method} {path}: {res.status} {data[:300]!r}")
        return res, data

    _, data = request("GET", base)
    doc = json.loads(data)
    version = doc["version"]
    obj = next(o for o in doc["scene"]["objects"] if o["id"] == args.object)
    transform = dict(obj.get("transform", {}))
    start = list(transform.get("translate", [0, 0, 0]))

    mesh_headers = {"Accept-Encoding": "gzip" if args.gzip else "identity"}
    step_seconds, edit_seconds, get_seconds, engine_seconds, mesh_seconds = [], [], [], [], []
    wire_bytes, raw_bytes, gzip_bytes, meshed, reused, lit, chunks = [], [], [], [], [], [], []
    t_all = time.perf_counter()
    for i in range(args.steps):
        # Out and back, so the cube stays near where it started.
        k = i + 1 if i < args.steps // 2 else args.steps - i - 1
        translate = [start[0] + k * args.step, start[1], start[2]]
        frame = {"edits": [{"op": "move", "id": args.object,
                            "transform": {**transform, "translate": translate}}]}
        t0 = time.perf_counter()
        _, data = request("POST", base + "/edits", json.dumps(frame),
                          {"Content-Type": "application/json"})
        t1 = time.perf_counter()
        result = json.loads(data)
        res, body = request("GET", f"{base}/mesh?since={version}&format=bin", headers=mesh_headers)
        t2 = time.perf_counter()
        plain = gzip.decompress(body) if res.getheader("Content-Encoding") == "gzip" else body
        raw = len(plain)
        if plain[:4] != b"PNMB":
            sys.exit("not a binary mesh")
        if int.from_bytes(plain[4:8], "little") != MESH_LAYOUT:
            sys.exit(f"binary mesh layout {int.from_bytes(plain[4:8], 'little')}; this tool reads layout {MESH_LAYOUT}")
        version = result["version"]
        step_seconds.append(t2 - t0)
        edit_seconds.append(t1 - t0)
        get_seconds.append(t2 - t1)
        engine_seconds.append(result["seconds"]["total"])
        mesh_seconds.append(result.get("mesh_seconds", float("nan")))
        meshed.append(result.get("meshed_receivers_count", float("nan")))
        cells = result.get("mesh_cells")
        if cells:
            reused.append(cells["reused"])
            lit.append(cells["lit"])
            if "chunks_meshed" in cells:
                chunks.append((cells["chunks_meshed"], cells["chunks_kept"]))
        wire_bytes.append(len(body))
        raw_bytes.append(raw)
        # What a remote client (gzip, level 1 as the server sends it) would receive.
        gzip_bytes.append(len(body) if res.getheader("Content-Encoding") == "gzip"
                          else len(gzip.compress(body, compresslevel=1)))
    total = time.perf_counter() - t_all

    def ms(xs):
        return f"median {1000 * statistics.median(xs):.1f} ms, p90 {1000 * sorted(xs)[int(0.9 * (len(xs) - 1))]:.1f} ms"

    print(f"scene {args.scene}, object {args.object}, {args.steps} steps of {args.step} m, "
          f"mesh {'gzip' if args.gzip else 'identity'}")
    print(f"edits/second: {args.steps / total:.1f}  (step {ms(step_seconds)})")
    print(f"  POST /edits  {ms(edit_seconds)}; engine apply {ms(engine_seconds)}; "
          f"re-mesh {ms(mesh_seconds) if mesh_seconds[0] == mesh_seconds[0] else 'n/a'}")
    print(f"  GET mesh     {ms(get_seconds)}")
    print(f"bytes/frame on the wire: mean {statistics.mean(wire_bytes) / 1e3:.1f} kB, "
          f"max {max(wire_bytes) / 1e3:.1f} kB; uncompressed mean {statistics.mean(raw_bytes) / 1e3:.1f} kB; "
          f"gzip-compressed mean {statistics.mean(gzip_bytes) / 1e3:.1f} kB")
    if meshed[0] == meshed[0]:
        print(f"receivers re-meshed per frame: mean {statistics.mean(meshed):.1f}")
    if reused:
        print(f"their cells per frame: kept mean {statistics.mean(reused):.0f}, lit afresh mean {statistics.mean(lit):.0f}")
    if chunks:
        print(f"their display chunks per frame: assembled again mean {statistics.mean(c[0] for c in chunks):.1f}, "
              f"kept mean {statistics.mean(c[1] for c in chunks):.0f}")


if __name__ == "__main__":
    main()
