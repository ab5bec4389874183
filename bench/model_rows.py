#!/usr/bin/env python3
"""The model rows of issue 35 (docs/BENCHMARKS.md "Models in the dense room"): for each generated
model, size and placing, `penumbra build --threads 2 --stats`: wall seconds and the process's
peak memory, one run each. With a second binary (--before), each row runs both in turn on the same scene file, so
the pair shares the machine's load. With --instructions, each build runs once at one thread under
callgrind instead and the instructions are printed: they do not depend on the load of a shared
machine (a ~1,000-triangle model takes ~1.5 min).

  python3 bench/model_rows.py build/penumbra [--before OLD/penumbra] [--models teapot,bowl]
      [--sizes 1000,6000] [--placings float,rest] [--instructions] [--dir /tmp/model_rows]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time


def timed_build(binary, scene):
    """Wall seconds, peak MB (the child's own, from wait4) and the build's stats at 2 threads."""
    start = time.monotonic()
    child = subprocess.Popen([binary, "build", scene, "--out", os.devnull, "--threads", "2", "--stats"],
                             stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    stats = child.stdout.read()
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.monotonic() - start
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"{binary} build {scene} failed")
    return wall, usage.ru_maxrss // 1024, json.loads(stats)


def instructions(binary, scene):
    out = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=" + os.devnull, binary, "build", scene,
                          "--out", os.devnull, "--threads", "1"], capture_output=True, text=True, check=True)
    found = re.search(r"Collected\s*:\s*(\d+)", out.stderr)
    if not found:
        sys.exit(f"no callgrind total for {scene}")
    return int(found.group(1))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("binary")
    parser.add_argument("--before")
    parser.add_argument("--models", default="teapot,torus-knot,blob,bowl")
    parser.add_argument("--sizes", default="1000,6000")
    parser.add_argument("--placings", default="float,rest")
    parser.add_argument("--instructions", action="store_true")
    parser.add_argument("--dir", default="/tmp/model_rows")
    args = parser.parse_args()
    os.makedirs(args.dir, exist_ok=True)
    binaries = [b for b in (args.before, args.binary) if b]
    for placing in args.placings.split(","):
        for model in args.models.split(","):
            for size in args.sizes.split(","):
                scene = os.path.join(args.dir, f"{model}_{size}_{placing}.json")
                generate = [args.binary, "generate", "--model", model, "--triangles", size, "--out", scene]
                subprocess.run(generate + (["--rest"] if placing == "rest" else []), capture_output=True, check=True)
                cells = []
                for binary in binaries:
                    if args.instructions:
                        cells.append(f"{instructions(binary, scene) / 1e9:.2f} G")
                        continue
                    wall, peak, stats = timed_build(binary, scene)
                    s = stats["seconds"]
                    cells.append(f"{wall:.2f} s {peak} MB (cast {s['casting_and_merging']:.2f} / illuminate "
                                 f"{s['illumination']:.2f} / triangulate {s['triangulation']:.2f}; "
                                 f"{stats['vertices']['total']} DM vertices, {stats['mesh']['triangles']} display "
                                 f"triangles)")
                print(f"{model:10s} {size:>5s} {placing:5s} " + " → ".join(cells), flush=True)


if __name__ == "__main__":
    main()
