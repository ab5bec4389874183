#!/usr/bin/env python3
"""kill -9 of nodes behind HAProxy (docs/SERVER.md "Many nodes"): three `penumbra serve` nodes on a
private PostgreSQL database with HAProxy in front (deploy/loopback.py), SCENES copies of cubes15
created and dragged through HAProxy (one client thread per scene: POST an edit, then GET the mesh
of each acknowledged version). KILLS times, mid-drag, a seeded random node is SIGKILLed; the drags
go on through HAProxy, which sends the dead node's scenes to the next node on its ring, which takes
them over when their leases expire; the node is then started again (its scenes go back to it).
Checks, then exits 1 naming the first failure:
  - after each kill, every scene of the killed node answers again within 10 s (kill-to-answer
    times reported: median, p95, max), at its last acknowledged version (or one past it: a frame
    committed whose answer the kill cut off) with the byte-identical mesh received for it;
  - at the end, the journal holds every acknowledged frame at its version, each frame row is one a
    client sent, and no version has two writers (0 split-brain writes);
  - an event stream of the first scene through HAProxy, reconnecting as a browser does, followed
    the scene from node to node and announces its last version.
Usage: python3 tests/server/failover.py --penumbra build/penumbra [--kills 3] [--scenes 6]
       [--seed 1] [--lease-seconds 1.5] [--pause 0.05]      (bench/failover: 20 kills over 20 scenes)
"""
import argparse
import http.client
import json
import os
import random
import signal
import statistics
import sys
import threading
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "deploy"))
from loopback import Cluster, request  # noqa: E402

ANSWER_WITHIN = 10.0  # seconds from a kill to the scene answering again: a failure past this


CLUSTER = []  # the cluster, for its logs on failure


def fail(message):
    for cluster in CLUSTER:  # what the nodes said last
        for i in range(3):
            lines = cluster.node_log(i).splitlines()[-15:]
            print(f"--- node{i + 1} log:\n" + "\n".join(lines), file=sys.stderr)
    sys.exit(f"failover: FAIL: {message}")


class Drag(threading.Thread):
    """Drags cube_0 of one scene through HAProxy until stopped; records what was acknowledged."""

    def __init__(self, port, scene, rng_seed, pause):
        super().__init__(daemon=True)
        self.pause = pause  # between an answer and the next frame
        self.port, self.scene = port, scene
        self.rng = random.Random(rng_seed)
        self.lock = threading.Lock()
        self.running = threading.Event()
        self.paused = threading.Event()
        self.acked = {}       # version → x of the frame acknowledged at it
        self.sent = set()     # every x sent (an unanswered one may be journaled)
        self.mesh = (0, None)  # the last acknowledged version and the mesh received right after
        self.last = 0         # the last acknowledged version
        self.answers = []     # monotonic times of every 200 answer
        self.errors = []

    def run(self):
        base = f"/api/scenes/{self.scene}"
        while self.running.is_set():
            if self.paused.is_set():
                time.sleep(0.01)
                continue
            x = round(self.rng.uniform(-1.5, 1.5), 9)
            self.sent.add(x)
            frame = json.dumps({"edits": [{"op": "move", "id": "cube_0",
                                           "transform": {"translate": [x, 0.5, 0.3]}}]})
            status, _, body = request(self.port, "POST", base + "/edits", frame, timeout=20)
            if status != 200:
                if status not in (0, 502, 503):
                    self.errors.append(f"{self.scene}: POST /edits answered {status}: {body[:200]!r}")
                time.sleep(0.05)
                continue
            version = json.loads(body)["version"]
            status, headers, mesh = request(self.port, "GET", base + "/mesh?format=bin", timeout=20)
            with self.lock:
                self.acked[version] = x
                self.last = max(self.last, version)
                self.answers.append(time.monotonic())
                # Only this thread edits the scene: the mesh is the acknowledged version's unless
                # a node died in between (then it is checked again after the kill).
                ok = status == 200 and headers.get("x-penumbra-version") == str(version)
                self.mesh = (version, mesh if ok else None)
            time.sleep(self.pause)


class Watch(threading.Thread):
    """An event stream of one scene through HAProxy, reconnecting as a browser's EventSource does
    (after its `retry:`) whenever the stream ends or breaks; records the versions announced."""

    def __init__(self, port, scene):
        super().__init__(daemon=True)
        self.port, self.scene = port, scene
        self.running = threading.Event()
        self.running.set()
        self.connections = 0
        self.last_version = None

    def run(self):
        while self.running.is_set():
            conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=15)
            try:
                conn.request("GET", f"/api/scenes/{self.scene}/events")
                answer = conn.getresponse()
                if answer.status == 200:
                    self.connections += 1
                    while self.running.is_set():
                        line = answer.readline()
                        if not line:
                            break  # ended (its node gave the scene up) or cut (killed)
                        if line.startswith(b"data: "):
                            self.last_version = json.loads(line[6:])["version"]
            except (OSError, http.client.HTTPException, ValueError):
                pass
            finally:
                conn.close()
            time.sleep(1.0)  # the stream's retry: 1000


def wait_answer(port, scene, since, deadline):
    """The first moment after `since` scene answers GET 200 through HAProxy; None past deadline."""
    while time.monotonic() < deadline:
        status, _, body = request(port, "GET", f"/api/scenes/{scene}", timeout=5)
        if status == 200:
            return time.monotonic(), json.loads(body)["version"]
        time.sleep(0.02)
    return None, None


def percentile(values, p):
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(p / 100 * (len(ordered) - 1))))]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--penumbra", required=True)
    parser.add_argument("--kills", type=int, default=3)
    parser.add_argument("--scenes", type=int, default=6)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--lease-seconds", type=float, default=1.5)
    parser.add_argument("--pause", type=float, default=0.05, help="seconds between a drag's frames")
    args = parser.parse_args()
    rng = random.Random(args.seed)
    started = time.monotonic()
    cluster = Cluster(args.penumbra, nodes=3, lease_seconds=args.lease_seconds)
    CLUSTER.append(cluster)
    port = cluster.haproxy_port
    with open(os.path.join(REPO, "scenes", "cubes15.scene.json"), "rb") as f:
        source = f.read()
    scenes = [f"fo{k}" for k in range(args.scenes)]
    for scene in scenes:
        status, _, body = request(port, "POST", f"/api/scenes?name={scene}", source)
        if status != 201 or json.loads(body)["id"] != scene:
            fail(f"creating {scene} through HAProxy answered {status}: {body[:200]!r}")
    drags = {scene: Drag(port, scene, rng.random(), args.pause) for scene in scenes}
    for drag in drags.values():
        drag.running.set()
        drag.start()
    watch = Watch(port, scenes[0])
    watch.start()

    kill_to_answer = []
    meshes_checked = 0
    for kill in range(args.kills):
        time.sleep(rng.uniform(0.5, 1.5))  # mid-drag
        owners = {}  # node index → the scenes it serves now
        for scene_id, owner in cluster.sql("SELECT scene_id, owner FROM scene_leases WHERE "
                                           "expires > now()"):
            owners.setdefault(int(owner[len("node"):]) - 1, []).append(scene_id)
        victim = rng.choice(sorted(owners))  # a node serving something
        owned = owners[victim]
        killed_at = time.monotonic()
        cluster.signal_node(victim, signal.SIGKILL)
        for scene in owned:
            answered, _ = wait_answer(port, scene, killed_at, killed_at + ANSWER_WITHIN)
            if answered is None:
                fail(f"kill {kill + 1}: scene {scene} of node{victim + 1} did not answer within "
                     f"{ANSWER_WITHIN} s")
            kill_to_answer.append(answered - killed_at)
        # Every scene of the dead node is back at its last acknowledged version (or one past:
        # the frame in flight committed, its answer cut off), its mesh byte for byte.
        for scene in owned:
            drag = drags[scene]
            drag.paused.set()
        time.sleep(0.3)  # the requests in flight answer
        for scene in owned:
            drag = drags[scene]
            with drag.lock:
                last, mesh = drag.last, drag.mesh[1] if drag.mesh[0] == drag.last else None
            status, _, body = request(port, "GET", f"/api/scenes/{scene}")
            version = json.loads(body)["version"] if status == 200 else None
            if version not in (last, last + 1):
                fail(f"kill {kill + 1}: scene {scene} is back at version {version}, last "
                     f"acknowledged {last}")
            if version == last and mesh is not None:
                status, _, served = request(port, "GET", f"/api/scenes/{scene}/mesh?format=bin")
                if served != mesh:
                    fail(f"kill {kill + 1}: scene {scene} at version {last} serves another mesh "
                         "than the one acknowledged")
                meshes_checked += 1
            drag.paused.clear()
        cluster.start_node(victim)
        print(f"failover: kill {kill + 1}: node{victim + 1} with {len(owned)} scene(s); answered "
              f"again after {', '.join(f'{t:.2f}' for t in kill_to_answer[-len(owned):])} s",
              flush=True)
        # Back up (HAProxy's checks), the node gets its scenes back as the drags ask for them.
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline and not cluster.sql(
                f"SELECT 1 FROM scene_leases WHERE owner = 'node{victim + 1}' AND expires > now()"):
            time.sleep(0.1)

    time.sleep(1.0)
    for drag in drags.values():
        drag.running.clear()
    for drag in drags.values():
        drag.join(30)
        if drag.errors:
            fail(drag.errors[0])
    # The event stream followed the scene from node to node: reconnected, and announces its last
    # version (once the stream's poll has seen it).
    final = drags[scenes[0]].last
    deadline = time.monotonic() + 5
    while watch.last_version != final and time.monotonic() < deadline:
        time.sleep(0.05)
    watch.running.clear()
    moved = sum(1 for line in cluster.node_log(0).splitlines() + cluster.node_log(1).splitlines()
                + cluster.node_log(2).splitlines() if f"took scene '{scenes[0]}' over" in line)
    if watch.last_version != final or (moved and watch.connections < 2):
        fail(f"the event stream of {scenes[0]} (taken over {moved} times) connected "
             f"{watch.connections} times and last announced version {watch.last_version}, "
             f"the scene is at {final}")

    # The journal: every acknowledged frame at its version; each row one a client sent.
    lost = split = 0
    for scene, drag in drags.items():
        rows = cluster.sql(
            "SELECT f.version, convert_from(f.frame, 'UTF8') FROM frames f JOIN scenes s ON "
            f"s.key = f.scene WHERE s.id = '{scene}' ORDER BY f.version")
        journaled = {int(v): json.loads(t)["edits"][0]["transform"]["translate"][0]
                     for v, t in rows}
        if sorted(journaled) != list(range(1, len(journaled) + 1)):
            fail(f"{scene}: the journal's versions have a gap: {sorted(journaled)}")
        for version, x in drag.acked.items():
            if journaled.get(version) != x:
                lost += 1
                print(f"failover: {scene} version {version}: acknowledged {x}, journal "
                      f"{journaled.get(version)}", file=sys.stderr)
        split += sum(1 for x in journaled.values() if x not in drag.sent)
    acked = sum(len(d.acked) for d in drags.values())
    if lost or split:
        fail(f"{lost} acknowledged version(s) lost or changed, {split} frame(s) nobody sent")
    if not kill_to_answer or not meshes_checked:
        fail(f"{len(kill_to_answer)} takeovers, {meshes_checked} meshes compared: nothing checked")
    print(f"failover: ok: {args.kills} kills over {args.scenes} scenes, {acked} acknowledged "
          f"versions, 0 lost, 0 split-brain writes, {meshes_checked} meshes byte-identical after "
          f"takeover; kill-to-answer median "
          f"{statistics.median(kill_to_answer):.2f} s, p95 {percentile(kill_to_answer, 95):.2f} s, "
          f"max {max(kill_to_answer):.2f} s over {len(kill_to_answer)} scene takeovers "
          f"(lease {args.lease_seconds} s; {time.monotonic() - started:.0f} s in all); the event "
          f"stream of {scenes[0]} reconnected {watch.connections - 1} times and is current")
    cluster.stop()


if __name__ == "__main__":
    main()
