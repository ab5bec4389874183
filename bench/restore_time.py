#!/usr/bin/env python3
"""Restart time of a journaled scene (README "Durability"): serves SCENE with --data TMP and
--snapshot-every S, drags one cube FRAMES steps back and forth (POST /edits), keeps its binary
mesh, stops the server, then restarts it on copies of the journal and measures, for each:
  - listening: from the start of the process to its "listening on port" line;
  - back: from the start until GET /api/scenes/ID answers 200 (503 "restoring" before), and that
    the binary mesh is byte-identical to the one served before the restart;
  - the seconds of the restore line the server prints.
Restarts: as written (from the newest snapshot, the frames after it); with --unbounded also with
the snapshots dropped (every frame, engine replay, meshed once) and without part changes (frame by
frame, each meshed). And the first build of the scene (a restart with no frames) for scale. One
run; on a shared machine only the ratios mean much.
Usage: python3 bench/restore_time.py [--penumbra build/penumbra] [--scene scenes/cubes15.scene.json]
                                     [--frames 120] [--snapshot-every 200] [--unbounded]
"""
import argparse
import http.client
import json
import math
import os
import re
import shutil
import sqlite3
import subprocess
import sys
import tempfile
import time


def start(penumbra, scene, data, every):
    """Starts a server; returns it, its port, the seconds until it listened (its "listening on
    port" line: bound, answering /api/health and 503 restoring) and when it was started."""
    began = time.perf_counter()
    proc = subprocess.Popen([penumbra, "serve", scene, "--data", data, "--port", "0",
                             "--snapshot-every", str(every)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in proc.stderr:
        match = re.search(r"listening on port (\d+)", line)
        if match:
            return proc, int(match.group(1)), time.perf_counter() - began, began
    sys.exit("restore_time: the server did not start: " + proc.stdout.read())


def stop(proc):
    """Stops the server; returns its stderr after the listening line (the restore lines)."""
    proc.terminate()
    _, err = proc.communicate(timeout=600)
    return err


def get(port, path):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=600)
    try:
        conn.request("GET", path)
        res = conn.getresponse()
        return res.status, res.read()
    finally:
        conn.close()


def wait_back(port, scene_id):
    while True:  # 503 restoring (or building) until it is back
        status = get(port, f"/api/scenes/{scene_id}")[0]
        if status == 200:
            return
        if status not in (503, 404):
            sys.exit(f"restore_time: GET /api/scenes/{scene_id} answered {status} during restore")
        time.sleep(0.005)


def started(penumbra, scene, data, every, scene_id):
    """A server with the scene served; returns it and its port."""
    proc, port, _, _ = start(penumbra, scene, data, every)
    wait_back(port, scene_id)
    return proc, port


def restart(penumbra, scene, data, every, scene_id, mesh):
    """(listening s, back s, restore-line s, the line) of one restart; checks the mesh."""
    proc, port, listening, began = start(penumbra, scene, data, every)
    wait_back(port, scene_id)
    back = time.perf_counter() - began
    status, body = get(port, f"/api/scenes/{scene_id}/mesh?format=bin")
    if status != 200 or body != mesh:
        sys.exit("restore_time: the restored mesh differs from the one served before the restart")
    err = stop(proc)
    lines = [l for l in err.splitlines() if "restored scene" in l]
    if not lines:
        sys.exit("restore_time: no restore line in:\n" + err)
    return listening, back, float(re.search(r"in ([0-9.]+) s", lines[0]).group(1)), lines[0]


def drag(port, scene_id, frames):
    """Moves cube_0 back and forth (so any number of frames stays in the edit volume)."""
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
    conn.request("GET", f"/api/scenes/{scene_id}")
    scene = json.loads(conn.getresponse().read())["scene"]
    cube = next(o for o in scene["objects"] if o["id"] == "cube_0")
    transform = cube["transform"]
    x0 = transform["translate"][0]
    began = time.perf_counter()
    for i in range(frames):
        transform["translate"][0] = x0 - 0.3 * math.sin((i + 1) / 40)
        body = json.dumps({"edits": [{"op": "move", "id": "cube_0", "transform": transform}]})
        conn.request("POST", f"/api/scenes/{scene_id}/edits", body=body,
                     headers={"Content-Type": "application/json"})
        res = conn.getresponse()
        res.read()
        if res.status != 200:
            sys.exit(f"restore_time: frame {i} answered {res.status}")
        if (i + 1) % 500 == 0 or i + 1 == frames:
            print(f"dragging: {i + 1}/{frames} frames, {time.perf_counter() - began:.0f} s",
                  file=sys.stderr, flush=True)


def edited_copy(tmp, source, name, statements):
    copy = os.path.join(tmp, name)
    shutil.copytree(source, copy)
    db = sqlite3.connect(os.path.join(copy, "journal.sqlite3"))
    for statement in statements:
        db.execute(statement)
    db.commit()
    db.close()
    return copy


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--penumbra", default="build/penumbra")
    ap.add_argument("--scene", default="scenes/cubes15.scene.json")
    ap.add_argument("--frames", type=int, default=120)
    ap.add_argument("--snapshot-every", type=int, default=200)
    ap.add_argument("--unbounded", action="store_true",
                    help="also restart without snapshots, and without part changes")
    args = ap.parse_args()
    penumbra = os.path.abspath(args.penumbra)
    scene = os.path.abspath(args.scene)
    scene_id = os.path.basename(scene).split(".")[0]
    every = args.snapshot_every
    with tempfile.TemporaryDirectory(prefix="penumbra-restore-") as tmp:
        fresh = os.path.join(tmp, "fresh")
        proc, port = started(penumbra, scene, fresh, every, scene_id)  # journals the scene
        first_mesh = get(port, f"/api/scenes/{scene_id}/mesh?format=bin")[1]
        stop(proc)
        rows = [("first build (no frames)",
                 restart(penumbra, scene, fresh, every, scene_id, first_mesh))]
        proc, port = started(penumbra, scene, fresh, every, scene_id)
        drag(port, scene_id, args.frames)
        mesh = get(port, f"/api/scenes/{scene_id}/mesh?format=bin")[1]
        stop(proc)
        db = sqlite3.connect(os.path.join(fresh, "journal.sqlite3"))
        snapshots = [v for (v,) in db.execute("SELECT version FROM snapshots ORDER BY version")]
        db.close()
        runs = [(f"{args.frames} frames, snapshots every {every} (kept: {snapshots})", fresh)]
        if args.unbounded:
            runs.append((f"{args.frames} frames, no snapshot, meshed once",
                         edited_copy(tmp, fresh, "whole", ["DELETE FROM snapshots"])))
            runs.append((f"{args.frames} frames, no snapshot, frame by frame",
                         edited_copy(tmp, fresh, "old", ["DELETE FROM snapshots",
                                                         "ALTER TABLE frames DROP COLUMN parts"])))
        for name, data in runs:
            result = restart(penumbra, scene, data, every, scene_id, mesh)
            print(result[3], file=sys.stderr)
            rows.append((name, result))
    build = rows[0][1][2]
    print(f"| restart of {os.path.basename(scene)} | listening s | scene back s | restore s "
          f"| × first build |")
    print("|---|---:|---:|---:|---:|")
    for name, (listening, back, seconds, _) in rows:
        print(f"| {name} | {listening:.2f} | {back:.2f} | {seconds:.2f} | {seconds / build:.1f} |")
    print("(each restart's binary mesh byte-identical to the one served before it)")


if __name__ == "__main__":
    main()
