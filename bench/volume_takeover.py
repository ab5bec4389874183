#!/usr/bin/env python3
"""What a large uploaded volume costs two nodes sharing a PostgreSQL journal (docs/SERVER.md
"Volumes on many nodes"), on a private database (deploy/loopback.py, no HAProxy): a cubes15 scene
on node1, a SIDE³ unsigned-char NRRD uploaded to it (a ramp along z: the octree stays small, so the
figures are the bytes' way through the journal, not the engine), node1 SIGKILLed, then the time
until node2 serves the scene (the lease's rest, the upload fetched and checked, the scene built).
Reports the upload's answer time, the kill-to-answer time, node2's restore time and the chunks
stored. Usage: python3 bench/volume_takeover.py [--penumbra build/penumbra] [--side 512]
"""
import argparse
import os
import signal
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "deploy"))
from loopback import Cluster, request  # noqa: E402


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--penumbra", default=os.path.join(REPO, "build", "penumbra"))
    parser.add_argument("--side", type=int, default=512)
    args = parser.parse_args()
    side = args.side
    data = b"".join(bytes([z * 255 // side]) * (side * side) for z in range(side))
    nrrd = (f"NRRD0004\ntype: unsigned char\ndimension: 3\nsizes: {side} {side} {side}\n"
            "spacings: 0.004 0.004 0.004\nencoding: raw\n\n").encode() + data
    cluster = Cluster(args.penumbra, nodes=2, lease_seconds=1.5, haproxy=False,
                      serve_flags=("--snapshot-every", "20", "--max-body-mib",
                                   str(len(nrrd) // (1 << 20) + 1)))
    try:
        first, second = cluster.ports
        with open(os.path.join(REPO, "scenes", "cubes15.scene.json"), "rb") as f:
            if request(first, "POST", "/api/scenes?name=big", f.read())[0] != 201:
                sys.exit("volume_takeover: the scene was not created")
        start = time.monotonic()
        status, _, body = request(first, "POST", "/api/scenes/big/volumes?id=ramp&isovalue=128",
                                  nrrd, timeout=600)
        uploaded = time.monotonic() - start
        if status != 201:
            sys.exit(f"volume_takeover: the upload answered {status}: {body[:200]!r}")
        cluster.signal_node(0, signal.SIGKILL)
        killed = time.monotonic()
        while request(second, "GET", "/api/scenes/big", timeout=600)[0] != 200:
            if time.monotonic() - killed > 300:
                sys.exit("volume_takeover: node2 did not serve the scene within 300 s")
            time.sleep(0.05)
        answered = time.monotonic() - killed
        chunks = cluster.sql("SELECT count(*), sum(octet_length(bytes)) FROM volume_chunks")[0]
        restore = [line for line in cluster.node_log(1).splitlines() if "took scene 'big'" in line]
        print(f"volume_takeover: {len(nrrd)} bytes ({side}³): upload answered 201 after "
              f"{uploaded:.2f} s; {chunks[0]} chunks, {chunks[1]} bytes in PostgreSQL; node2 served "
              f"the scene {answered:.2f} s after node1's kill (lease 1.5 s); "
              f"{restore[-1].split(': ', 1)[-1] if restore else 'no takeover logged'}")
    finally:
        cluster.stop()


if __name__ == "__main__":
    main()
