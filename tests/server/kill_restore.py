#!/usr/bin/env python3
"""SIGKILL test of the journal (README "Durability"): starts `penumbra serve SCENE --data DIR
--port 0`, drags cubes (POST /edits, then GET /mesh?format=bin of each acknowledged version),
SIGKILLs the server at a seeded random moment (during the drag, or during start-up and restore),
restarts it on the same DIR (or, a third of the time, on DIR moved to another path: issue 36),
and checks after each restart:
  - the scene is back at the last acknowledged version (or one past it: a frame committed whose
    answer the kill cut off; never more, never less);
  - its binary mesh is byte-identical to the one received for that version;
  - the journal holds every acknowledged frame, byte for byte as sent (the first run also uploads
    a NRRD volume: that frame is the server's, naming the file relative to DIR).
At the end, a frame in the middle is garbled in the file: the restart must serve the version
before it (stalled, byte-identical mesh, edits 409, health degraded) and keep every frame; then
the directory is removed while serving: an edit must answer 503 and health durable: false.
Exits 1 naming the first acknowledged version lost or changed. Usage:
  python3 tests/server/kill_restore.py --penumbra build/penumbra [--kills 10] [--seed 1]
"""
import argparse
import atexit
import hashlib
import http.client
import json
import os
import random
import re
import shutil
import sqlite3
import subprocess
import sys
import tempfile
import threading
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE_ID = "cubes15"
OBJECTS = ["cube_0", "cube_1", "cube_2"]
UPLOAD = "<the volume upload's frame>"  # journaled by the server, not sent as text
SMOKE = os.path.join(REPO, "scenes", "volumes", "smoke64.nrrd")


STDERRS = []  # every server's stderr lines
SERVE_FLAGS = []  # more `penumbra serve` options (--snapshot-every N)
CHILDREN = []  # every server started, killed at exit (a failure leaves none running)
atexit.register(lambda: [child.kill() for child in CHILDREN if child.poll() is None])


def fail(message):
    sys.exit(f"kill_restore: FAIL: {message}")


class Server:
    """One `penumbra serve` child; port is None until it printed its URL."""

    def __init__(self, penumbra, scene, data):
        self.proc = subprocess.Popen(
            [penumbra, "serve", scene, "--data", data, "--port", "0"] + SERVE_FLAGS,
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=data)
        CHILDREN.append(self.proc)
        self.port = None
        self.ready = threading.Event()
        self.stderr = []
        STDERRS.append(self.stderr)
        threading.Thread(target=self._read_stdout, daemon=True).start()
        threading.Thread(target=lambda: self.stderr.extend(self.proc.stderr), daemon=True).start()

    def _read_stdout(self):
        for line in self.proc.stdout:
            match = re.search(r"serving .* at http://[^:]+:(\d+)/", line)
            if match and self.port is None:
                self.port = int(match.group(1))
                self.ready.set()
        self.ready.set()  # exited

    def kill(self):
        self.proc.kill()  # SIGKILL
        self.proc.wait()


def request(port, method, path, body=None, content_type="application/json"):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    try:
        conn.request(method, path, body=body, headers={"Accept-Encoding": "identity",
                                                        "Content-Type": content_type})
        res = conn.getresponse()
        return res.status, dict(res.getheaders()), res.read()
    finally:
        conn.close()


def drag_until_killed(port, rng, state):
    """Edits until the connection breaks; records every acknowledged frame and its mesh."""
    base = f"/api/scenes/{SCENE_ID}"
    _, _, body = request(port, "GET", base)
    starts = {o["id"]: o["transform"] for o in json.loads(body)["scene"]["objects"] if o["id"] in OBJECTS}
    if not state["uploaded"]:  # a volume, so that moving the directory has a file to find
        state["in_flight"] = UPLOAD
        with open(SMOKE, "rb") as f:
            status, _, answer = request(port, "POST", base + "/volumes?name=smoke.nrrd&translate=0,1,0",
                                        f.read(), "application/octet-stream")
        if status != 201:
            fail(f"POST /volumes answered {status}: {answer[:300]!r}")
        state["frames"][json.loads(answer)["version"]] = UPLOAD
        state["acked"] = json.loads(answer)["version"]
        state["in_flight"] = None
        state["uploaded"] = True
    while True:
        obj = rng.choice(OBJECTS)
        transform = dict(starts[obj])
        x, y, z = transform["translate"]
        transform["translate"] = [x + rng.uniform(-0.06, 0.06), y, z + rng.uniform(-0.06, 0.06)]
        text = json.dumps({"edits": [{"op": "move", "id": obj, "transform": transform}]})
        state["in_flight"] = text
        status, _, answer = request(port, "POST", base + "/edits", text)
        if status != 200:
            fail(f"POST /edits answered {status}: {answer[:300]!r}")
        version = json.loads(answer)["version"]
        state["frames"][version] = text
        state["acked"] = version
        state["in_flight"] = None
        status, headers, mesh = request(port, "GET", base + "/mesh?format=bin")
        if status != 200 or int(headers["X-Penumbra-Version"]) != version:
            fail(f"GET /mesh after version {version}: {status}, version {headers.get('X-Penumbra-Version')}")
        state["meshes"][version] = hashlib.sha256(mesh).hexdigest()


def check_restored(port, data, state, stats):
    base = f"/api/scenes/{SCENE_ID}"
    status, headers, mesh = request(port, "GET", base + "/mesh?format=bin")
    if status != 200:
        fail(f"after restart GET /mesh answered {status}")
    version = int(headers["X-Penumbra-Version"])
    acked = state["acked"]
    if version == acked + 1 and state["in_flight"] is not None:
        # Committed, then killed before the answer: kept, as the journal says (README).
        state["frames"][version] = state["in_flight"]
        state["acked"] = version
        stats["committed_unanswered"] += 1
    elif version != acked:
        fail(f"restored version {version}, last acknowledged {acked}")
    state["in_flight"] = None
    if version in state["meshes"]:
        if hashlib.sha256(mesh).hexdigest() != state["meshes"][version]:
            fail(f"version {version}: the restored mesh differs from the one served before the kill")
        stats["meshes_compared"] += 1
    db = sqlite3.connect(f"file:{os.path.join(data, 'journal.sqlite3')}?mode=ro", uri=True)
    rows = dict(db.execute("SELECT f.version, f.frame FROM frames f JOIN scenes s ON s.key = f.scene "
                           "WHERE s.id = ?", (SCENE_ID,)).fetchall())
    db.close()
    for v, text in state["frames"].items():
        if text == UPLOAD:
            if v not in rows or b'"volumes/' not in bytes(rows[v]):
                fail(f"the upload's frame {v} is missing or names its file outside the data directory")
            state["uploaded"] = True
            continue
        if v <= version and (v not in rows or bytes(rows[v]).decode() != text):
            fail(f"acknowledged version {v} is missing from the journal or changed "
                 f"(journal versions {sorted(rows)[:5]}..{len(rows)}, server {version}, sent: {text:.100})")
    if max(rows, default=0) != version:
        fail(f"the journal ends at version {max(rows, default=0)}, the server at {version}")
    _, _, body = request(port, "GET", base)
    if len(json.loads(body)["volumes"]) != (1 if UPLOAD in state["frames"].values() else 0):
        fail("the uploaded volume did not come back")


def health(port):
    return json.loads(request(port, "GET", "/api/health")[2])


def final_faults(args, data, state):
    """A garbled frame in the middle: stalled at the version before, every frame kept; then the
    data directory removed while serving: 503 and durable: false."""
    middle = max(v for v, text in state["frames"].items() if text != UPLOAD and v > 1) // 2 + 1
    db = sqlite3.connect(os.path.join(data, "journal.sqlite3"))
    # Snapshots past it would cover it (restored whole, the damage only reported): those go.
    db.execute("DELETE FROM snapshots WHERE version >= ?", (middle,))
    before = db.execute("SELECT COUNT(*) FROM frames").fetchone()[0]
    db.execute("UPDATE frames SET frame = CAST('{\"edits\": garbled' AS BLOB) WHERE version = ?", (middle,))
    db.commit()
    db.close()
    server = Server(args.penumbra, args.scene, data)
    if not server.ready.wait(60) or server.port is None:
        fail("server did not start on the garbled journal: " + "".join(server.stderr)[-2000:])
    base = f"/api/scenes/{SCENE_ID}"
    status, headers, mesh = request(server.port, "GET", base + "/mesh?format=bin")
    if int(headers["X-Penumbra-Version"]) != middle - 1:
        fail(f"garbled frame {middle}: served version {headers['X-Penumbra-Version']}, not {middle - 1}")
    if middle - 1 in state["meshes"] and hashlib.sha256(mesh).hexdigest() != state["meshes"][middle - 1]:
        fail(f"garbled frame {middle}: the stalled version's mesh differs from the one served before")
    move = json.dumps({"edits": [{"op": "move", "id": "cube_0", "transform": {"translate": [0.1, 0.5, 0.1]}}]})
    if request(server.port, "POST", base + "/edits", move)[0] != 409:
        fail("an edit to the stalled scene was not refused with 409")
    if health(server.port)["status"] != "degraded":
        fail("health does not report the stalled scene")
    db = sqlite3.connect(f"file:{os.path.join(data, 'journal.sqlite3')}?mode=ro", uri=True)
    after = db.execute("SELECT COUNT(*) FROM frames").fetchone()[0]
    db.close()
    if after != before:
        fail(f"the restart changed the journal: {before} frames before, {after} after")
    # Make the scene editable again for the last check: delete it and serve the file afresh.
    request(server.port, "DELETE", base)
    status, _, body = request(server.port, "POST", "/api/scenes?name=again", open(args.scene, "rb").read())
    if status != 201:
        fail(f"POST /api/scenes answered {status}")
    again = json.loads(body)["id"]
    shutil.rmtree(data)
    status, _, answer = request(server.port, "POST", f"/api/scenes/{again}/edits", move)
    if status != 503:
        fail(f"an edit with the data directory removed answered {status}: {answer[:200]!r}")
    if health(server.port)["durable"] is not False:
        fail("health says durable with the data directory removed")
    server.proc.terminate()
    server.proc.wait()
    return middle


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--penumbra", default=os.path.join(REPO, "build", "penumbra"), type=os.path.abspath)
    ap.add_argument("--scene", default=os.path.join(REPO, "scenes", "cubes15.scene.json"), type=os.path.abspath)
    ap.add_argument("--kills", type=int, default=10)
    ap.add_argument("--snapshot-every", type=int, default=7,
                    help="serve's --snapshot-every: small, so that restarts start from snapshots")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--max-drag-seconds", type=float, default=1.0,
                    help="a kill lands within this long after the server is up")
    args = ap.parse_args()
    SERVE_FLAGS.extend(["--snapshot-every", str(args.snapshot_every)])
    rng = random.Random(args.seed)
    state = {"frames": {}, "meshes": {}, "acked": 0, "in_flight": None, "uploaded": False}
    stats = {"kills": 0, "during_startup": 0, "committed_unanswered": 0, "meshes_compared": 0, "moves": 0}
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="penumbra-kill-") as parent:
        data = os.path.join(parent, "data-0")
        os.mkdir(data)
        server = Server(args.penumbra, args.scene, data)
        for kill in range(args.kills + 1):
            during_startup = kill < args.kills and rng.random() < 0.2
            delay = rng.uniform(0, 1.0) if during_startup else rng.uniform(0, args.max_drag_seconds)
            if during_startup:  # killed while it builds, replays or has just bound
                timer = threading.Timer(delay, server.kill)
                timer.start()
                server.ready.wait(60)
                timer.join()
                stats["during_startup"] += 1
            else:
                if not server.ready.wait(60) or server.port is None:
                    fail("server did not start: " + "".join(server.stderr)[-2000:])
                check_restored(server.port, data, state, stats)
                if kill == args.kills:
                    break
                timer = threading.Timer(delay, server.kill)
                timer.start()
                try:
                    drag_until_killed(server.port, random.Random(rng.random()), state)
                except (ConnectionError, http.client.HTTPException, OSError):
                    pass  # the kill
                timer.join()
            stats["kills"] += 1
            if rng.random() < 1 / 3:  # the data directory moved to another path
                moved = os.path.join(parent, f"data-{kill + 1}")
                os.rename(data, moved)
                data = moved
                stats["moves"] += 1
            server = Server(args.penumbra, args.scene, data)
        server.proc.terminate()
        server.proc.wait()
        garbled = final_faults(args, data, state)
    seconds = time.perf_counter() - start
    from_snapshot = sum(1 for lines in STDERRS for line in lines if "(snapshot at " in line)
    print(f"kill_restore: {stats['kills']} SIGKILLs ({stats['during_startup']} during start-up, "
          f"{stats['moves']} restarts on a moved data directory), "
          f"{state['acked']} versions acknowledged, 0 lost; {stats['meshes_compared']} restored meshes "
          f"byte-identical; {stats['committed_unanswered']} committed frames whose answer the kill cut "
          f"off (kept); garbled frame {garbled}: stalled before it, every frame kept; data directory "
          f"removed while serving: 503, durable false; {from_snapshot} restores started from a "
          f"snapshot (--snapshot-every {args.snapshot_every}); {seconds:.1f} s (seed {args.seed})")


if __name__ == "__main__":
    main()
