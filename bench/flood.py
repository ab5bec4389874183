#!/usr/bin/env python3
"""A flood of costly requests from one client against another client's edits (docs/BENCHMARKS.md
"A flood from one client"): serves cubes15 (the flooder's scene) and cornell (the other client's);
FLOODERS threads from 127.0.0.2 each loop over GI images of cubes15 (320 × 262, sensor GI) and
frames adding then removing LIGHTS lights, while one client from 127.0.0.1 drags a cornell box
(a POST /edits every 100 ms) and asks /api/health every 50 ms. Prints the other client's edit and
health latencies (p50, p99, max) and what the flood got (200, 503 busy, 422 …).
Usage: python3 bench/flood.py --penumbra build/penumbra [--seconds 60] [--flooders 8] [--lights 20]
"""
import argparse
import http.client
import json
import re
import socket
import statistics
import subprocess
import sys
import threading
import time


def start(penumbra, scenes):
    proc = subprocess.Popen([penumbra, "serve", *scenes, "--ephemeral", "--port", "0"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in proc.stdout:
        match = re.search(r"open http://[^:]+:(\d+)/", line)
        if match:
            return proc, int(match.group(1))
    sys.exit("flood: the server did not start: " + proc.stderr.read())


class Connection(http.client.HTTPConnection):
    """An HTTP connection from a chosen loopback address (another client than 127.0.0.1)."""

    def __init__(self, port, source):
        super().__init__("127.0.0.1", port, timeout=600, source_address=(source, 0))


def request(conn, method, path, body=None):
    headers = {"Content-Type": "application/json"} if body is not None else {}
    start = time.perf_counter()
    try:
        conn.request(method, path, body, headers)
        res = conn.getresponse()
        res.read()
        status = res.status
    except (OSError, http.client.HTTPException):
        conn.close()
        status = 0
    return status, time.perf_counter() - start


def lights_frame(count, add):
    edits = []
    for i in range(count):
        x = -2 + 4 * i / max(1, count - 1)
        if add:
            edits.append({"op": "add_light", "light": {
                "id": f"flood{i}", "radiance": [2, 2, 2],
                "polygon": [[x - 0.1, 3.3, -0.1], [x + 0.1, 3.3, -0.1], [x + 0.1, 3.3, 0.1], [x - 0.1, 3.3, 0.1]]}})
        else:
            edits.append({"op": "remove_light", "id": f"flood{i}"})
    return json.dumps({"edits": edits})


def flooder(port, index, lights, stop, statuses, lock):
    conn = Connection(port, "127.0.0.2")
    step = 0
    while not stop.is_set():
        if index % 2 == 0:
            status, _ = request(conn, "GET", f"/api/scenes/cubes15/image?width=320&height=262&gi=sensors&ticket=f{index}-{step}")
            kind = "gi image"
        elif index == 1:  # one client's light frames: add, then remove
            status, _ = request(conn, "POST", "/api/scenes/cubes15/edits", lights_frame(lights, step % 2 == 0))
            kind = f"{lights}-light frame"
        else:
            status, _ = request(conn, "GET", "/api/scenes/cubes15/image?width=512&height=512")
            kind = "image"
        step += 1
        with lock:
            statuses.setdefault(kind, {}).setdefault(status, 0)
            statuses[kind][status] += 1
        if status in (0, 503):
            time.sleep(0.2)


def other_client(port, path_maker, body_maker, every, stop, out):
    conn = Connection(port, "127.0.0.1")
    step = 0
    while not stop.is_set():
        began = time.perf_counter()
        status, seconds = request(conn, "POST" if body_maker else "GET", path_maker(step),
                                  body_maker(step) if body_maker else None)
        out.append((status, seconds))
        step += 1
        time.sleep(max(0.0, every - (time.perf_counter() - began)))


def summary(name, samples):
    times = sorted(s for _, s in samples)
    ok = sum(1 for status, _ in samples if status == 200)
    p = lambda q: times[min(len(times) - 1, int(q * len(times)))] * 1000
    print(f"{name}: {len(samples)} requests, {ok} answered 200; "
          f"p50 {p(0.5):.1f} ms, p99 {p(0.99):.1f} ms, max {times[-1] * 1000:.1f} ms")
    return p(0.99)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--penumbra", default="build/penumbra")
    parser.add_argument("--seconds", type=float, default=60)
    parser.add_argument("--flooders", type=int, default=8)
    parser.add_argument("--lights", type=int, default=20)
    args = parser.parse_args()
    if not (0 < args.seconds <= 600 and 2 <= args.flooders <= 64):
        sys.exit("flood: --seconds in (0, 600], --flooders in [2, 64]")
    proc, port = start(args.penumbra, ["scenes/cubes15.scene.json", "scenes/cornell.scene.json"])
    try:
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
        conn.request("GET", "/api/scenes/cornell")
        scene = json.loads(conn.getresponse().read())["scene"]
        box = next(o for o in scene["objects"] if len(o.get("faces", [])) == 6)
        transform = dict(box.get("transform", {"translate": [0, 0, 0]}))
        base = transform.get("translate", [0, 0, 0])

        def move(step):
            t = dict(transform)
            t["translate"] = [base[0] + 0.02 * (step % 20), base[1], base[2]]
            return json.dumps({"edits": [{"op": "move", "id": box["id"], "transform": t}]})

        stop, lock = threading.Event(), threading.Lock()
        statuses, edits, health = {}, [], []
        # The flood's requests still running at the end (a heavy frame can take minutes) are not
        # waited for: the server is stopped under them.
        flood = [threading.Thread(target=flooder, args=(port, i, args.lights, stop, statuses, lock),
                                  daemon=True) for i in range(args.flooders)]
        others = [threading.Thread(target=other_client, args=(
                      port, lambda s: "/api/scenes/cornell/edits", move, 0.1, stop, edits)),
                  threading.Thread(target=other_client, args=(
                      port, lambda s: "/api/health", None, 0.05, stop, health))]
        for t in flood + others:
            t.start()
        time.sleep(args.seconds)
        stop.set()
        for t in others:
            t.join()
        with lock:
            got = json.dumps(statuses)
        print(f"flood: {args.flooders} flooding connections from 127.0.0.2 for {args.seconds:.0f} s; "
              f"what they got: {got}")
        edit_p99 = summary("the other client's edits (cornell)", edits)
        health_p99 = summary("/api/health", health)
        print(f"edit p99 {'≤' if edit_p99 <= 250 else '>'} 250 ms, health p99 {'≤' if health_p99 <= 50 else '>'} 50 ms")
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            print("flood: the server did not stop within 10 s of SIGTERM; killed")
            proc.kill()
            proc.wait()


if __name__ == "__main__":
    main()
