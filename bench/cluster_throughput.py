#!/usr/bin/env python3
"""Edit throughput of one node against three behind HAProxy (docs/SERVER.md "Many nodes"; figures
in docs/BENCHMARKS.md), on a private PostgreSQL (deploy/loopback.py, fsync on): SCENES copies of
cubes15, CLIENTS threads POSTing drag frames for SECONDS; reports acknowledged edits/s, latency
median and p95, resident memory per scene (the nodes' RSS growth over the scenes they hold), and
what PostgreSQL carried per edit (write-ahead log bytes, commits, frame row bytes). Usage:
  python3 bench/cluster_throughput.py [--penumbra build/penumbra] [--scenes 12] [--clients 8]
                                      [--seconds 10]
"""
import argparse
import json
import os
import random
import statistics
import sys
import threading
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "deploy"))
from loopback import Cluster, request  # noqa: E402


def rss_kib(pid):
    with open(f"/proc/{pid}/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))


def run(penumbra, nodes, through_haproxy, args):
    cluster = Cluster(penumbra, nodes=nodes, lease_seconds=3, haproxy=through_haproxy, fsync=True)
    port = cluster.haproxy_port if through_haproxy else cluster.ports[0]
    with open(os.path.join(REPO, "scenes", "cubes15.scene.json"), "rb") as f:
        source = f.read()
    before = sum(rss_kib(p.pid) for p in cluster.procs.values())
    scenes = [f"tp{k}" for k in range(args.scenes)]
    for scene in scenes:
        status, _, body = request(port, "POST", f"/api/scenes?name={scene}", source)
        if status != 201:
            sys.exit(f"creating {scene}: {status} {body[:200]!r}")
    for scene in scenes:  # each on the node it hashes to (a create may land elsewhere)
        while request(port, "GET", f"/api/scenes/{scene}")[0] != 200:
            time.sleep(0.05)
    per_scene = (sum(rss_kib(p.pid) for p in cluster.procs.values()) - before) / len(scenes)
    wal0 = cluster.sql("SELECT pg_current_wal_lsn(), xact_commit FROM pg_stat_database "
                       "WHERE datname = 'postgres'")[0]
    latencies, stop = [], threading.Event()
    lock = threading.Lock()

    def client(k):
        rng = random.Random(k)
        mine = []
        while not stop.is_set():
            scene = scenes[(k + len(mine)) % len(scenes)] if len(scenes) < args.clients else \
                scenes[k % len(scenes)]
            frame = json.dumps({"edits": [{"op": "move", "id": "cube_0", "transform": {
                "translate": [rng.uniform(-1.5, 1.5), 0.5, 0.3]}}]})
            start = time.monotonic()
            status, _, _ = request(port, "POST", f"/api/scenes/{scene}/edits", frame)
            if status == 200:
                mine.append(time.monotonic() - start)
        with lock:
            latencies.extend(mine)

    threads = [threading.Thread(target=client, args=(k,)) for k in range(args.clients)]
    start = time.monotonic()
    for t in threads:
        t.start()
    time.sleep(args.seconds)
    stop.set()
    for t in threads:
        t.join()
    elapsed = time.monotonic() - start
    wal1 = cluster.sql(f"SELECT pg_current_wal_lsn() - '{wal0[0]}', xact_commit - {wal0[1]} FROM "
                       "pg_stat_database WHERE datname = 'postgres'")[0]
    frame_bytes = cluster.sql("SELECT avg(octet_length(frame) + coalesce(octet_length(parts), 0))"
                              " FROM frames")[0][0]
    cluster.stop()
    edits = len(latencies)
    latencies.sort()
    return {"nodes": nodes, "haproxy": through_haproxy, "edits_per_s": edits / elapsed,
            "median_ms": 1000 * statistics.median(latencies),
            "p95_ms": 1000 * latencies[int(0.95 * (edits - 1))],
            "rss_mib_per_scene": per_scene / 1024,
            "wal_bytes_per_edit": int(wal1[0]) / edits, "commits_per_edit": int(wal1[1]) / edits,
            "frame_row_bytes": float(frame_bytes)}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--penumbra", default=os.path.join(REPO, "build", "penumbra"))
    parser.add_argument("--scenes", type=int, default=12)
    parser.add_argument("--clients", type=int, default=8)
    parser.add_argument("--seconds", type=float, default=10)
    args = parser.parse_args()
    print(f"{args.scenes} cubes15 scenes, {args.clients} clients, {args.seconds:.0f} s each, "
          f"{os.cpu_count()} cores", flush=True)
    for nodes, haproxy in ((1, False), (1, True), (3, True)):
        row = run(args.penumbra, nodes, haproxy, args)
        print(f"{row['nodes']} node{'s' if nodes > 1 else ''} {'via HAProxy' if haproxy else 'direct'}"
              f": {row['edits_per_s']:.0f} edits/s, median {row['median_ms']:.1f} ms, p95 "
              f"{row['p95_ms']:.1f} ms; {row['rss_mib_per_scene']:.1f} MiB per scene; PostgreSQL "
              f"per edit: {row['wal_bytes_per_edit']:.0f} WAL bytes, "
              f"{row['commits_per_edit']:.2f} commits, frame row {row['frame_row_bytes']:.0f} B",
              flush=True)


if __name__ == "__main__":
    main()
