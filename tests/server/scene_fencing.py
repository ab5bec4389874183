#!/usr/bin/env python3
"""A node frozen past its lease is fenced (docs/SERVER.md "Many nodes"): two `penumbra serve` nodes
on one private PostgreSQL database (deploy/loopback.py). Node 1 creates cubes15 and drags it; it is
SIGSTOPped; node 2, asked for the scene, answers 503 until node 1's lease has expired, then takes
it over at node 1's last acknowledged version with a byte-identical mesh and takes edits; node 1,
resumed, has its next edit refused (503) with nothing written, and the journal holds node 1's
frames up to the takeover and only node 2's after it. Exits 1 naming what failed. Usage:
  python3 tests/server/scene_fencing.py --penumbra build/penumbra
"""
import argparse
import json
import os
import signal
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "deploy"))
from loopback import Cluster, request  # noqa: E402

LEASE = 1.5


def fail(message):
    sys.exit(f"scene_fencing: FAIL: {message}")


def move(x):
    return json.dumps({"edits": [{"op": "move", "id": "cube_0",
                                  "transform": {"translate": [x, 0.5, 0.25]}}]})


def edit(port, x):
    status, _, body = request(port, "POST", "/api/scenes/cubes15/edits", move(x))
    return status, json.loads(body) if body else {}


def mesh(port):
    status, _, body = request(port, "GET", "/api/scenes/cubes15/mesh?format=bin")
    if status != 200:
        fail(f"GET mesh answered {status}")
    return body


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--penumbra", required=True)
    args = parser.parse_args()
    cluster = Cluster(args.penumbra, nodes=2, lease_seconds=LEASE, haproxy=False)
    one, two = cluster.ports
    with open(os.path.join(REPO, "scenes", "cubes15.scene.json"), "rb") as f:
        status, _, body = request(one, "POST", "/api/scenes?name=cubes15", f.read())
    if status != 201:
        fail(f"creating the scene answered {status}: {body[:200]!r}")
    sent = {}  # version → the x its frame moved cube_0 to
    for x in (0.11, 0.12, 0.13):
        status, answer = edit(one, x)
        if status != 200:
            fail(f"node 1's edit answered {status}: {answer}")
        sent[answer["version"]] = x
    acked = max(sent)
    acked_mesh = mesh(one)

    cluster.signal_node(0, signal.SIGSTOP)
    stopped = time.monotonic()
    status, headers, _ = request(two, "GET", "/api/scenes/cubes15")
    if status != 503 or headers.get("retry-after") != "1":
        fail(f"node 2 answered {status} (Retry-After {headers.get('retry-after')}) while node 1 "
             "held the lease")
    while True:  # node 1 cannot hand it over: node 2 waits for the lease to expire
        status, _, body = request(two, "GET", "/api/scenes/cubes15")
        if status == 200:
            break
        if status != 503 or time.monotonic() - stopped > LEASE + 10:
            fail(f"node 2 answered {status} {body[:200]!r} {time.monotonic() - stopped:.1f} s "
                 "after node 1 stopped")
        time.sleep(0.05)
    took = time.monotonic() - stopped
    if took < LEASE * 2 / 3 - 0.05:  # renewed a third of a lease before it froze, at worst
        fail(f"node 2 served the scene {took:.2f} s after node 1 froze, before its lease ended")
    if json.loads(body)["version"] != acked or mesh(two) != acked_mesh:
        fail(f"node 2 took over at version {json.loads(body)['version']} (acknowledged: {acked}) "
             "or with another mesh")
    for x in (0.21, 0.22):
        status, answer = edit(two, x)
        if status != 200:
            fail(f"node 2's edit answered {status}: {answer}")
        sent[answer["version"]] = x

    cluster.signal_node(0, signal.SIGCONT)
    status, answer = edit(one, 0.99)  # at once: before or after its renewal notices, refused
    if status != 503:
        fail(f"node 1, resumed after losing its lease, answered {status} to an edit: {answer}")
    code = answer.get("error", {}).get("code")
    if code != "owned_elsewhere":
        fail(f"node 1's refusal says {code}, not owned_elsewhere: {answer}")

    rows = cluster.sql("SELECT f.version, convert_from(f.frame, 'UTF8') FROM frames f "
                       "ORDER BY f.version")
    versions = [int(v) for v, _ in rows]
    if versions != sorted(sent):
        fail(f"the journal holds versions {versions}, acknowledged {sorted(sent)}")
    for version, frame in rows:
        x = json.loads(frame)["edits"][0]["transform"]["translate"][0]
        if abs(x - sent[int(version)]) > 1e-12:
            fail(f"the journal's frame {version} moved to {x}, acknowledged {sent[int(version)]}")
    status, _, body = request(two, "GET", "/api/scenes/cubes15")
    if status != 200 or json.loads(body)["version"] != max(sent):
        fail(f"node 2 answered {status} {body[:200]!r} after node 1 was fenced")
    if "no longer serving scene 'cubes15'" not in cluster.node_log(0):
        fail("node 1 did not say it stopped serving the scene")
    print(f"scene_fencing: ok (node 2 took over {took:.2f} s after node 1 froze, lease {LEASE} s; "
          f"node 1 fenced, journal versions {versions})")
    cluster.stop()


if __name__ == "__main__":
    main()
