#!/usr/bin/env python3
"""Render time of GET /api/scenes/{id}/image on a microfacet scene (README "Rendering"): serves
SCENE with each binary given (--penumbra, and --penumbra2 to compare, e.g. a build whose route
takes every face as a possible occluder against one reading the DM cells' occluder lists), asks
ROUNDS images of each SAMPLES count, the binaries interleaved, and prints the median
X-Penumbra-Render-Seconds per binary and count; then drags the gold box FRAMES steps and prints
the median `occluder_seconds` the edits spent freezing occluder lists (0 when a build has none).
Usage: python3 bench/image_route.py --penumbra build/penumbra [--penumbra2 OTHER/build/penumbra]
       [--scene scenes/materials.scene.json] [--width 320 --height 240] [--samples 1,4,16]
       [--rounds 5] [--frames 40]
"""
import argparse
import http.client
import json
import re
import statistics
import subprocess
import sys


def start(penumbra, scene):
    proc = subprocess.Popen([penumbra, "serve", scene, "--ephemeral", "--port", "0"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in proc.stdout:
        match = re.search(r"open http://[^:]+:(\d+)/\?scene=(\S+)", line)
        if match:
            return proc, int(match.group(1)), match.group(2)
    sys.exit("image_route: the server did not start: " + proc.stderr.read())


def image_seconds(port, scene_id, width, height, samples):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=600)
    conn.request("GET", f"/api/scenes/{scene_id}/image?width={width}&height={height}&samples={samples}")
    res = conn.getresponse()
    res.read()
    if res.status != 200:
        sys.exit(f"image_route: GET image answered {res.status}")
    return float(res.getheader("X-Penumbra-Render-Seconds"))


def drag(port, scene_id, frames):
    """Moves the gold box in small steps; returns the edits' occluder_seconds."""
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=600)
    conn.request("GET", f"/api/scenes/{scene_id}")
    scene = json.loads(conn.getresponse().read())["scene"]
    box = next(o for o in scene["objects"] if o["id"] == "gold_box")
    transform = dict(box.get("transform", {}))
    seconds = []
    for step in range(frames):
        transform["translate"] = [transform["translate"][0] + 0.02, *transform["translate"][1:]]
        body = json.dumps({"edits": [{"op": "move", "id": "gold_box", "transform": transform}]})
        conn.request("POST", f"/api/scenes/{scene_id}/edits", body, {"Content-Type": "application/json"})
        answer = json.loads(conn.getresponse().read())
        seconds.append(answer.get("occluder_seconds", 0.0))
    return seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--penumbra", default="build/penumbra")
    parser.add_argument("--penumbra2")
    parser.add_argument("--scene", default="scenes/materials.scene.json")
    parser.add_argument("--width", type=int, default=320)
    parser.add_argument("--height", type=int, default=240)
    parser.add_argument("--samples", default="1,4,16")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--frames", type=int, default=40)
    args = parser.parse_args()
    binaries = [b for b in (args.penumbra, args.penumbra2) if b]
    servers = [start(b, args.scene) for b in binaries]
    try:
        counts = [int(s) for s in args.samples.split(",")]
        times = {(b, s): [] for b in binaries for s in counts}
        for _ in range(args.rounds):
            for binary, (_, port, scene_id) in zip(binaries, servers):
                for s in counts:
                    times[(binary, s)].append(image_seconds(port, scene_id, args.width, args.height, s))
        for (binary, s), values in times.items():
            print(f"{binary}: {args.width}x{args.height}, samples {s}: median {statistics.median(values):.3f} s "
                  f"(min {min(values):.3f}, max {max(values):.3f}, {len(values)} images)")
        for binary, (_, port, scene_id) in zip(binaries, servers):
            frozen = drag(port, scene_id, args.frames)
            print(f"{binary}: {args.frames} edits, occluder_seconds median {1000 * statistics.median(frozen):.3f} ms, "
                  f"max {1000 * max(frozen):.3f} ms")
    finally:
        for proc, _, _ in servers:
            proc.terminate()
            proc.wait(timeout=60)


if __name__ == "__main__":
    main()
