#!/usr/bin/env python3
"""Restart time of a journaled scene (README "Durability"): serves SCENE with --data TMP, drags
one cube FRAMES steps (POST /edits), stops the server, then restarts it three times on copies of
the journal and reads the restore line it prints:
  - as written (each frame's part changes journaled: engine replay, meshed once);
  - with the part changes dropped (a journal from before them: frame by frame, each meshed);
and the first build of the scene (a restart with no frames) for scale. One run; on a shared
machine only the ratios mean much.
Usage: python3 bench/restore_time.py [--penumbra build/penumbra] [--scene scenes/cubes15.scene.json]
                                     [--frames 120]
"""
import argparse
import http.client
import json
import os
import re
import shutil
import sqlite3
import subprocess
import sys
import tempfile


def start(penumbra, scene, data):
    proc = subprocess.Popen([penumbra, "serve", scene, "--data", data, "--port", "0"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in proc.stdout:
        match = re.search(r"serving .* at http://[^:]+:(\d+)/", line)
        if match:
            return proc, int(match.group(1))
    sys.exit("restore_time: the server did not start: " + proc.stderr.read())


def stop(proc):
    """Stops the server; returns its stderr (the restore lines)."""
    proc.terminate()
    _, err = proc.communicate(timeout=120)
    return err


def restore_line(penumbra, scene, data):
    proc, _ = start(penumbra, scene, data)
    err = stop(proc)
    lines = [l for l in err.splitlines() if "restored scene" in l]
    if not lines:
        sys.exit("restore_time: no restore line in:\n" + err)
    seconds = float(re.search(r"in ([0-9.]+) s", lines[0]).group(1))
    return seconds, lines[0]


def drag(port, scene_id, frames):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
    conn.request("GET", f"/api/scenes/{scene_id}")
    scene = json.loads(conn.getresponse().read())["scene"]
    cube = next(o for o in scene["objects"] if o["id"] == "cube_0")
    transform = cube["transform"]
    for i in range(frames):
        transform["translate"][0] -= 0.01
        body = json.dumps({"edits": [{"op": "move", "id": "cube_0", "transform": transform}]})
        conn.request("POST", f"/api/scenes/{scene_id}/edits", body=body,
                     headers={"Content-Type": "application/json"})
        res = conn.getresponse()
        res.read()
        if res.status != 200:
            sys.exit(f"restore_time: frame {i} answered {res.status}")
        if (i + 1) % 20 == 0 or i + 1 == frames:
            print(f"dragging: {i + 1}/{frames} frames", file=sys.stderr, flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--penumbra", default="build/penumbra")
    ap.add_argument("--scene", default="scenes/cubes15.scene.json")
    ap.add_argument("--frames", type=int, default=120)
    args = ap.parse_args()
    penumbra = os.path.abspath(args.penumbra)
    scene = os.path.abspath(args.scene)
    scene_id = os.path.basename(scene).split(".")[0]
    with tempfile.TemporaryDirectory(prefix="penumbra-restore-") as tmp:
        fresh = os.path.join(tmp, "fresh")
        stop(start(penumbra, scene, fresh)[0])  # journals the scene
        build_seconds, _ = restore_line(penumbra, scene, fresh)  # a restart with no frames
        proc, port = start(penumbra, scene, fresh)
        drag(port, scene_id, args.frames)
        stop(proc)
        rows = [("first build (no frames)", build_seconds)]
        old = os.path.join(tmp, "old")
        shutil.copytree(fresh, old)
        db = sqlite3.connect(os.path.join(old, "journal.sqlite3"))
        db.execute("ALTER TABLE frames DROP COLUMN parts")
        db.commit()
        db.close()
        for name, data in [("meshed once", fresh), ("frame by frame", old)]:
            seconds, line = restore_line(penumbra, scene, data)
            print(line, file=sys.stderr)
            rows.append((f"{args.frames} frames, {name}", seconds))
    print(f"| restore of {os.path.basename(scene)} | seconds | × first build |")
    print("|---|---:|---:|")
    for name, seconds in rows:
        print(f"| {name} | {seconds:.2f} | {seconds / build_seconds:.1f} |")


if __name__ == "__main__":
    main()
