#!/usr/bin/env python3
"""What a journal snapshot costs the edit that takes it (docs/SERVER.md "Snapshots"): serves SCENE
with --data TMP --snapshot-every EVERY, moves its first transformed object back and forth FRAMES
times (POST /edits on one connection) and prints the median answer time of the other frames and
the answer times of the frames at multiples of EVERY (each waits for the rebase build and the
snapshot's commit). One run; on a shared machine only the ratio means much.
Usage: python3 bench/snapshot_latency.py [--penumbra build/penumbra]
                                         [--scene scenes/cubes15.scene.json] [--frames 100]
                                         [--snapshot-every 25]
"""
import argparse
import http.client
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--penumbra", default="build/penumbra")
    ap.add_argument("--scene", default="scenes/cubes15.scene.json")
    ap.add_argument("--frames", type=int, default=100)
    ap.add_argument("--snapshot-every", type=int, default=25)
    args = ap.parse_args()
    scene_id = os.path.basename(args.scene).split(".")[0]
    every = args.snapshot_every
    with tempfile.TemporaryDirectory(prefix="penumbra-snapshot-") as data:
        proc = subprocess.Popen([os.path.abspath(args.penumbra), "serve", os.path.abspath(args.scene),
                                 "--data", data, "--port", "0", "--snapshot-every", str(every)],
                                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        port = None
        for line in proc.stderr:
            match = re.search(r"listening on port (\d+)", line)
            if match:
                port = int(match.group(1))
                break
        if port is None:
            sys.exit("snapshot_latency: the server did not start")
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=600)
        while True:  # 503 while the scene builds
            conn.request("GET", f"/api/scenes/{scene_id}")
            res = conn.getresponse()
            body = res.read()
            if res.status == 200:
                break
            time.sleep(0.05)
        objects = json.loads(body)["scene"]["objects"]
        obj = next(o for o in objects if "transform" in o)
        transform = obj["transform"]
        x0 = transform["translate"][0]
        seconds = {}
        for i in range(1, args.frames + 1):
            transform["translate"][0] = x0 - 0.05 * math.sin(i / 10)
            frame = json.dumps({"edits": [{"op": "move", "id": obj["id"], "transform": transform}]})
            began = time.perf_counter()
            conn.request("POST", f"/api/scenes/{scene_id}/edits", body=frame,
                         headers={"Content-Type": "application/json"})
            res = conn.getresponse()
            res.read()
            seconds[i] = time.perf_counter() - began
            if res.status != 200:
                sys.exit(f"snapshot_latency: frame {i} answered {res.status}")
        proc.terminate()
        proc.wait()
    taking = [round(1000 * s, 1) for i, s in seconds.items() if i % every == 0]
    others = statistics.median(s for i, s in seconds.items() if i % every != 0)
    print(f"{scene_id}, moving {obj['id']}: other frames median {1000 * others:.1f} ms; "
          f"frames taking a snapshot {taking} ms")


if __name__ == "__main__":
    main()
