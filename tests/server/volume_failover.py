#!/usr/bin/env python3
"""A scene with an uploaded volume fails over (docs/SERVER.md "Volumes on many nodes"): two
`penumbra serve` nodes on a private PostgreSQL database behind HAProxy (deploy/loopback.py). A scene
is created through HAProxy, a seeded random NRRD volume uploaded to it (POST .../volumes) and a cube
moved; its owner is then SIGKILLed. Checks, then exits 1 naming the first failure:
  - the other node takes the scene over within 10 s, at the same version, and serves the same
    scene JSON, the byte-identical mesh and image (which shows the volume: it differs from the
    image before the upload), and the same volume preview;
  - the uploaded bytes were fetched from the database into the new owner's data directory, byte for
    byte, and the database holds them once (the `volumes` rows);
  - the scene takes edits on the new owner; deleting it deletes its volume from the database and
    from that node's data directory.
Usage: python3 tests/server/volume_failover.py --penumbra build/penumbra [--seed 39]
"""
import argparse
import glob
import json
import os
import random
import signal
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "deploy"))
from loopback import Cluster, request  # noqa: E402

ANSWER_WITHIN = 10.0  # seconds from the kill to the scene answering again
SCENE = "vol"


def fail(cluster, message):
    for i in range(2):
        lines = cluster.node_log(i).splitlines()[-15:]
        print(f"--- node{i + 1} log:\n" + "\n".join(lines), file=sys.stderr)
    sys.exit(f"volume_failover: FAIL: {message}")


def random_nrrd(rng, side=10):
    """A raw uchar NRRD: a blob of seeded noise around a ball, so its isosurface is not trivial."""
    voxels = bytearray()
    centre = (side - 1) / 2
    for z in range(side):
        for y in range(side):
            for x in range(side):
                r = ((x - centre) ** 2 + (y - centre) ** 2 + (z - centre) ** 2) ** 0.5
                voxels.append(max(0, min(255, int(255 - 50 * r + rng.randint(-20, 20)))))
    header = (f"NRRD0004\ntype: unsigned char\ndimension: 3\nsizes: {side} {side} {side}\n"
              "spacings: 0.08 0.08 0.08\nencoding: raw\n\n")
    return header.encode() + bytes(voxels)


def ask(port, method, path, body=None):
    """request(), again while it answers 503 (nothing was applied: a scene moving between nodes,
    or HAProxy taking the busy owner for down while it renders and sending the request to the
    other node), for up to 10 s, as a client honouring Retry-After does."""
    deadline = time.monotonic() + 10
    while True:
        status, headers, answer = request(port, method, path, body, timeout=60)
        if status != 503 or time.monotonic() > deadline:
            return status, headers, answer
        time.sleep(0.1)


def views(cluster, port):
    """What the scene serves: its JSON (no version-independent noise), mesh, image, preview."""
    base = f"/api/scenes/{SCENE}"
    answers = {}
    for name, path in (("scene", base), ("mesh", base + "/mesh?format=bin"),
                       ("image", base + "/image?width=64&height=48"),
                       ("preview", base + "/volumes/ball/preview?cells=16")):
        status, _, body = ask(port, "GET", path)
        if status != 200:
            fail(cluster, f"GET {path} answered {status}: {body[:200]!r}")
        answers[name] = body
    scene = json.loads(answers["scene"])
    scene.pop("node", None)  # which node answers is what changed
    for volume in scene["scene"]["objects"]:  # named absolute: in that node's data directory
        if volume.get("type") == "volume":
            volume["file"] = os.path.basename(volume["file"])
    answers["scene"] = scene
    return answers


def owner(cluster):
    rows = cluster.sql(f"SELECT owner FROM scene_leases WHERE scene_id = '{SCENE}' AND "
                       "expires > now()")
    return int(rows[0][0][len("node"):]) - 1 if rows else None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--penumbra", required=True)
    parser.add_argument("--seed", type=int, default=39)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    started = time.monotonic()
    cluster = Cluster(args.penumbra, nodes=2, lease_seconds=1.5)
    port = cluster.haproxy_port
    with open(os.path.join(REPO, "scenes", "cubes15.scene.json"), "rb") as f:
        status, _, body = ask(port, "POST", f"/api/scenes?name={SCENE}", f.read())
    if status != 201:
        fail(cluster, f"creating the scene answered {status}: {body[:200]!r}")
    status, _, without = ask(port, "GET", f"/api/scenes/{SCENE}/image?width=64&height=48")
    nrrd = random_nrrd(rng)
    status, _, body = ask(port, "POST", f"/api/scenes/{SCENE}/volumes?id=ball&isovalue=120"
                          "&translate=0.2,1.5,0.1", nrrd)
    if status != 201:
        fail(cluster, f"uploading the volume answered {status}: {body[:200]!r}")
    move = json.dumps({"edits": [{"op": "move", "id": "cube_0",
                                  "transform": {"translate": [rng.uniform(-1, 1), 0.5, 0.3]}}]})
    status, _, body = ask(port, "POST", f"/api/scenes/{SCENE}/edits", move)
    if status != 200:
        fail(cluster, f"an edit answered {status}: {body[:200]!r}")
    before = views(cluster, port)
    if status != 200 or before["image"] == without:
        fail(cluster, f"the image does not show the uploaded volume (before it: {status})")
    first = owner(cluster)
    if first is None:
        fail(cluster, "no node holds the scene's lease")

    killed_at = time.monotonic()
    cluster.signal_node(first, signal.SIGKILL)
    while time.monotonic() - killed_at < ANSWER_WITHIN:
        status, _, body = request(port, "GET", f"/api/scenes/{SCENE}", timeout=5)
        if status == 200:
            break
        time.sleep(0.05)
    else:
        fail(cluster, f"the scene did not answer within {ANSWER_WITHIN} s of its node's kill")
    answered = time.monotonic() - killed_at
    after = views(cluster, port)
    second = owner(cluster)
    if second is None or second == first:
        fail(cluster, f"the scene is owned by node {second}, not taken over from node {first}")
    for name in ("scene", "mesh", "image", "preview"):
        if after[name] != before[name]:
            fail(cluster, f"after the takeover the scene serves another {name}")
    copies = glob.glob(os.path.join(cluster.dir, f"node{second + 1}", "volumes", f"{SCENE}-*.nrrd"))
    if len(copies) != 1 or open(copies[0], "rb").read() != nrrd:
        fail(cluster, f"node{second + 1} holds {len(copies)} copies of the upload, not the bytes sent")
    stored = cluster.sql("SELECT count(*), sum(size) FROM volumes")
    if stored != [["1", str(len(nrrd))]]:
        fail(cluster, f"the database holds volumes {stored}, not the one upload of {len(nrrd)} bytes")

    status, _, body = ask(port, "POST", f"/api/scenes/{SCENE}/edits", move)
    if status != 200:
        fail(cluster, f"an edit on the new owner answered {status}: {body[:200]!r}")
    status, _, body = ask(port, "DELETE", f"/api/scenes/{SCENE}")
    if status != 204:
        fail(cluster, f"deleting the scene answered {status}: {body[:200]!r}")
    left = cluster.sql("SELECT (SELECT count(*) FROM volumes) + (SELECT count(*) FROM volume_chunks)")
    if left != [["0"]] or any(os.path.exists(c) for c in copies):
        fail(cluster, f"the deleted scene's volume is still kept (rows: {left}, local copy: "
             f"{[c for c in copies if os.path.exists(c)]})")
    print(f"volume_failover: ok: node{first + 1} killed, node{second + 1} served the scene with its "
          f"uploaded volume ({len(nrrd)} bytes, fetched from the database) after {answered:.2f} s; "
          f"scene, mesh, image and preview identical; deleted with its volume "
          f"({time.monotonic() - started:.0f} s in all)")
    cluster.stop()


if __name__ == "__main__":
    main()
