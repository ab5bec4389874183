#!/usr/bin/env python3
"""What one journaled frame costs on this disk: 300 one-frame transactions (the journal's schema,
WAL) with synchronous=FULL (what the server uses: an fsync per commit) and NORMAL (no fsync per
commit: survives a killed process, not a power loss). Run from the directory the journal lives in:
  (cd build && python3 ../bench/journal_commit.py)
"""
import os
import sqlite3
import statistics
import time

FRAME = (b'{"edits":[{"op":"move","id":"cube_0","transform":{"rotate_deg":[0,70.44,0],'
         b'"scale":[0.86,0.86,0.86],"translate":[2.41,0.43,-2.99]}}]}')

for sync in ["FULL", "NORMAL"]:
    path = f"journal-commit-{sync}.sqlite3"
    files = [path, path + "-wal", path + "-shm"]
    for f in files:
        if os.path.exists(f):
            os.remove(f)
    db = sqlite3.connect(path, isolation_level=None)
    db.execute("PRAGMA journal_mode=WAL")
    db.execute(f"PRAGMA synchronous={sync}")
    db.execute("CREATE TABLE frames (scene INTEGER, version INTEGER, frame BLOB, "
               "PRIMARY KEY (scene, version)) WITHOUT ROWID")
    times = []
    for version in range(300):
        start = time.perf_counter()
        db.execute("BEGIN IMMEDIATE")
        db.execute("INSERT INTO frames VALUES (1, ?, ?)", (version, FRAME))
        db.execute("COMMIT")
        times.append(time.perf_counter() - start)
    db.close()
    for f in files:
        if os.path.exists(f):
            os.remove(f)
    times.sort()
    print(f"synchronous={sync}: commit median {statistics.median(times) * 1e3:.2f} ms, "
          f"p90 {times[int(len(times) * 0.9)] * 1e3:.2f} ms, p99 {times[int(len(times) * 0.99)] * 1e3:.2f} ms")
