#!/usr/bin/env python3
"""Compares two mesh files written by `penumbra build --out` (format 13): whether each
receiver's positions, triangles and classes are the same, and the largest difference between
their irradiance values. For checking that a change to the engine moved no vertex and no value
beyond rounding: `python3 bench/mesh_diff.py before.mesh.json after.mesh.json`. Exits 1 when
the geometry or the receivers differ."""
import json
import sys


def main(before_path, after_path):
    before = json.load(open(before_path))["receivers"]
    after = json.load(open(after_path))["receivers"]
    if len(before) != len(after):
        print(f"receivers: {len(before)} vs {len(after)}")
        return 1
    geometry = classes = values = differing = 0
    worst = 0.0
    for a, b in zip(before, after):
        if a["positions"] != b["positions"] or a["triangles"] != b["triangles"]:
            geometry += 1
            continue
        classes += a["class"] != b["class"]
        for u, v in zip(a["irradiance"], b["irradiance"]):
            values += 1
            for x, y in zip(u if isinstance(u, list) else [u], v if isinstance(v, list) else [v]):
                differing += x != y
                worst = max(worst, abs(x - y))
    print(f"receivers {len(before)}: geometry differs in {geometry}, classes in {classes}; "
          f"{values} vertices, {differing} values differ, largest difference {worst:.3g}")
    return 1 if geometry else 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
