#!/usr/bin/env python3
"""A stop ends the server within 5 s, whatever it is doing, and loses nothing acknowledged:
  1. SIGTERM while a large scene builds at start-up (nothing served yet): ends at once;
  2. SIGTERM while a large scene upload builds in a request, after edits were acknowledged:
     ends at once (the stop cancels the build; within the grace, 4 s, in any case), and a restart on the same data directory serves the last
     acknowledged version.
The large scene is `penumbra generate --model torus-knot` (about 20 s to build on 2 cores).
Usage: python3 tests/server/sigterm_stop.py --penumbra build/penumbra
"""
import argparse
import atexit
import http.client
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CUBES = os.path.join(REPO, "scenes", "cubes15.scene.json")
LIMIT_S = 5.0
CHILDREN = []
atexit.register(lambda: [child.kill() for child in CHILDREN if child.poll() is None])


def fail(message):
    sys.exit(f"sigterm_stop: FAIL: {message}")


def serve(penumbra, scene, data):
    proc = subprocess.Popen([penumbra, "serve", scene, "--data", data, "--port", "0"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=data)
    CHILDREN.append(proc)
    return proc


def port_of(proc):
    for line in proc.stdout:
        match = re.search(r"http://[^:]+:(\d+)/", line)
        if match:
            return int(match.group(1))
    fail("the server did not start: " + proc.stderr.read())


def request(port, method, path, body=None, timeout=600):
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    connection.request(method, path, body=body, headers={"Content-Type": "application/json"})
    answer = connection.getresponse()
    return answer.status, answer.read()


def upload_cut_short(port, upload):
    """The upload whose build the stop leaves behind: its connection just closes."""
    try:
        request(port, "POST", "/api/scenes?name=knot", upload)
    except (http.client.HTTPException, OSError):
        pass


def seconds_to_exit(proc):
    start = time.monotonic()
    proc.send_signal(signal.SIGTERM)
    try:
        proc.wait(timeout=30)
    except subprocess.TimeoutExpired:
        fail("the server was still running 30 s after SIGTERM")
    return time.monotonic() - start


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--penumbra", required=True)
    args = parser.parse_args()
    penumbra = os.path.abspath(args.penumbra)
    with tempfile.TemporaryDirectory(prefix="penumbra-sigterm-") as tmp:
        large = os.path.join(tmp, "knot.scene.json")
        subprocess.run([penumbra, "generate", "--model", "torus-knot", "--out", large], check=True,
                       stdout=subprocess.DEVNULL)

        # 1. While the large scene builds at start-up.
        os.makedirs(os.path.join(tmp, "a"))
        proc = serve(penumbra, large, os.path.join(tmp, "a"))
        time.sleep(1.5)
        if proc.poll() is not None:
            fail("the server ended before the stop: " + proc.stderr.read())
        took = seconds_to_exit(proc)
        print(f"stop while building at start-up: {took:.2f} s")
        if took > LIMIT_S:
            fail(f"start-up: {took:.2f} s to stop (limit {LIMIT_S} s)")

        # 2. While an upload builds, after three acknowledged edits.
        data = os.path.join(tmp, "b")
        os.makedirs(data)
        proc = serve(penumbra, CUBES, data)
        port = port_of(proc)
        for step in range(3):
            frame = {"edits": [{"op": "move", "id": "cube_0",
                                "transform": {"translate": [0.1 * step, 0, 0]}}]}
            status, body = request(port, "POST", "/api/scenes/cubes15/edits", json.dumps(frame))
            if status != 200:
                fail(f"edit {step}: {status} {body[:200]}")
        acknowledged = json.loads(request(port, "GET", "/api/scenes/cubes15")[1])["version"]
        with open(large, "rb") as scene:
            upload = scene.read()
        threading.Thread(target=upload_cut_short, args=(port, upload), daemon=True).start()
        time.sleep(1.5)
        took = seconds_to_exit(proc)
        print(f"stop while an upload builds: {took:.2f} s")
        if took > LIMIT_S:
            fail(f"upload: {took:.2f} s to stop (limit {LIMIT_S} s)")

        proc = serve(penumbra, CUBES, data)
        port = port_of(proc)
        version = json.loads(request(port, "GET", "/api/scenes/cubes15")[1])["version"]
        if version != acknowledged:
            fail(f"restart serves version {version}, {acknowledged} was acknowledged")
        took = seconds_to_exit(proc)
        print(f"restart at version {version} (acknowledged {acknowledged}); idle stop {took:.2f} s")
        if took > 2:
            fail(f"an idle server took {took:.2f} s to stop")
    print("sigterm_stop: ok")


if __name__ == "__main__":
    main()
