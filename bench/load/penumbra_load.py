#!/usr/bin/env python3
"""Load driver for `penumbra serve` on loopback (README "Load"): N clients spread over S copies
of a scene, each a person dragging a cube (POST /edits, then GET mesh?since=V&format=bin, at most
--edit-rate frames per second, pauses between drags), now and then a small image and the scene,
and one SSE stream each. Reports per endpoint count, p50/p95/p99, errors and timeouts, the
server's resident memory over time (/proc/PID/status), and writes an HTML report with SVG plots.

  python3 bench/load/penumbra_load.py --penumbra build/penumbra --clients 50 --scenes 10 \
      --seconds 600 --html build/load-report.html
  python3 bench/load/penumbra_load.py --url http://127.0.0.1:8080 --pid PID ...   (a running server)

--mode flood: every client edits one scene as fast as it can (no pauses, no pacing).
Checks (exit status 1 when broken): --max-errors, --max-rss-growth (MB, last RSS sample vs the
one after warm-up). Bounded: at most 256 clients, 3600 s; loopback addresses only.
"""
import argparse
import http.client
import json
import math
import multiprocessing
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import urllib.parse

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import load_report  # noqa: E402

TIMEOUT_S = 30.0  # a request taking longer counts as a timeout


class Client:
    """One keep-alive connection; records (endpoint, start s, seconds, status) per request."""

    def __init__(self, host, port, t0, samples):
        self.host, self.port, self.t0, self.samples = host, port, t0, samples
        self.conn = None

    def request(self, endpoint, method, path, body=None, headers=None):
        start = time.perf_counter()
        status, data, hdrs = 0, b"", {}
        for attempt in range(2):
            reused = self.conn is not None
            try:
                if self.conn is None:
                    self.conn = http.client.HTTPConnection(self.host, self.port, timeout=TIMEOUT_S)
                self.conn.request(method, path, body=body, headers=headers or {})
                res = self.conn.getresponse()
                data = res.read()
                status, hdrs = res.status, dict(res.getheaders())
                break
            except TimeoutError:
                status = -1  # timeout
                self.close()
                break
            except (http.client.RemoteDisconnected, BrokenPipeError, ConnectionResetError):
                # The server closed an idle keep-alive connection before reading this request
                # (as browsers do: retry once on a fresh connection).
                status = -2
                self.close()
                if not reused:
                    break
            except (OSError, http.client.HTTPException):
                status = -2  # connection error
                self.close()
                break
        self.samples.append((endpoint, start - self.t0, time.perf_counter() - start, status))
        return status, data, hdrs

    def close(self):
        if self.conn is not None:
            self.conn.close()
            self.conn = None


MESH_LAYOUT = 4  # the binary mesh layout this driver reads (docs/API.md "Binary")


def mesh_version(data):
    """Scene version of a binary mesh answer (docs/API.md "Binary", offset 8); None if the answer
    is not a binary mesh; a binary mesh of another layout is an error."""
    if len(data) < 12 or data[:4] != b"PNMB":
        return None
    layout = int.from_bytes(data[4:8], "little")
    if layout != MESH_LAYOUT:
        raise ValueError(f"binary mesh layout {layout}; this driver reads layout {MESH_LAYOUT}")
    return int.from_bytes(data[8:12], "little")


def event_stream(host, port, scene, deadline, stats):
    """Reads one SSE stream until the deadline; counts events and checks versions only grow."""
    try:
        conn = http.client.HTTPConnection(host, port, timeout=TIMEOUT_S)
        conn.request("GET", f"/api/scenes/{scene}/events")
        res = conn.getresponse()
        if res.status != 200:
            stats["errors"] += 1
            return
        last = -1
        while time.time() < deadline:
            line = res.fp.readline()
            if not line:
                break
            if line.startswith(b"data: "):
                version = json.loads(line[6:])["version"]
                if version < last:
                    stats["out_of_order"] += 1
                last = version
                stats["events"] += 1
        conn.close()
    except (OSError, http.client.HTTPException, ValueError):
        stats["errors"] += 1


def run_client(args, index, scene, obj, t0, deadline, samples, stream_stats):
    """A person: drags `obj` in bursts, reads mesh deltas, now and then an image and the scene."""
    rng = random.Random(args.seed * 1000 + index)
    c = Client(args.host, args.port, t0, samples)
    base = f"/api/scenes/{scene}"
    if args.events:
        threading.Thread(target=event_stream, args=(args.host, args.port, scene, deadline,
                                                    stream_stats), daemon=True).start()
    status, data, _ = c.request("scene", "GET", base)
    if status != 200:
        return
    doc = json.loads(data)
    transform = next(o for o in doc["scene"]["objects"] if o["id"] == obj).get("transform", {})
    centre = list(transform.get("translate", [0, 0, 0]))
    status, data, _ = c.request("mesh_whole", "GET", base + "/mesh?format=bin")
    held = mesh_version(data) or 0
    angle = rng.uniform(0, 2 * math.pi)
    flood = args.mode == "flood"
    while time.time() < deadline:
        steps = 1 << 30 if flood else rng.randint(10, 40)  # one drag
        for _ in range(steps):
            if time.time() >= deadline:
                break
            step_start = time.time()
            angle += 0.08
            translate = [centre[0] + 0.25 * math.cos(angle), centre[1],
                         centre[2] + 0.25 * math.sin(angle)]
            frame = {"edits": [{"op": "move", "id": obj,
                                "transform": {**transform, "translate": translate}}]}
            status, data, hdrs = c.request("edit", "POST", base + "/edits", json.dumps(frame),
                                           {"Content-Type": "application/json",
                                            "X-Penumbra-Client": f"load-{index}"})
            if status == 503:  # busy: wait as told
                time.sleep(min(float(hdrs.get("Retry-After", "1")), 5.0))
                continue
            status, data, _ = c.request("mesh_delta", "GET",
                                        f"{base}/mesh?since={held}&format=bin")
            held = mesh_version(data) or held
            if rng.random() < args.image_share:
                c.request("image", "GET", base + "/image?width=64&height=48")
            if not flood:
                time.sleep(max(0.0, 1.0 / args.edit_rate - (time.time() - step_start)))
        if not flood:  # between drags: looks at the result, reads the scene
            c.request("scene", "GET", base)
            time.sleep(rng.uniform(0.5, args.pause))
    c.close()


def run_group(args, clients, t0, deadline, queue):
    """One process: its clients on threads (so the GIL does not serialise all 50)."""
    samples, stream_stats = [], {"events": 0, "errors": 0, "out_of_order": 0}
    threads = [threading.Thread(target=run_client,
                                args=(args, i, scene, obj, t0, deadline, samples, stream_stats))
               for i, scene, obj in clients]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    queue.put((samples, stream_stats))


def sample_rss(pid, t0, deadline, out):
    while time.time() < deadline:
        try:
            with open(f"/proc/{pid}/status") as f:
                status = f.read()
            rss = int(re.search(r"VmRSS:\s+(\d+)", status).group(1)) / 1024
            threads = int(re.search(r"Threads:\s+(\d+)", status).group(1))
            out.append((time.perf_counter() - t0, rss, threads))
        except (OSError, AttributeError):
            return
        time.sleep(1.0)


def start_server(penumbra, data_dir):
    # A journal of its own: the default one (./penumbra-data) holds earlier runs' scenes, which
    # a start restores first (24 scenes and 44k frames took 3 minutes).
    proc = subprocess.Popen([penumbra, "serve", "--port", "0", "--static", "", "--data", data_dir],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    for line in proc.stdout:
        match = re.search(r"at http://127\.0\.0\.1:(\d+)/", line)
        if match:
            return proc, int(match.group(1))
    raise SystemExit("penumbra serve did not start")


def server_allocator(args):
    """The allocator the server reports in /api/health (jemalloc in `penumbra serve`)."""
    conn = http.client.HTTPConnection(args.host, args.port, timeout=30)
    conn.request("GET", "/api/health")
    health = json.loads(conn.getresponse().read())
    conn.close()
    return health.get("allocator", "unknown")


def create_scenes(args):
    conn = http.client.HTTPConnection(args.host, args.port, timeout=120)
    with open(args.scene_file, "rb") as f:
        body = f.read()
    ids = []
    for k in range(args.scenes):
        conn.request("POST", f"/api/scenes?name=load{k}", body, {"Content-Type": "application/json"})
        res = conn.getresponse()
        data = res.read()
        if res.status != 201:
            raise SystemExit(f"POST /api/scenes: {res.status} {data[:200]!r}")
        ids.append(json.loads(data)["id"])
    objects = [o["id"] for o in json.loads(body)["objects"] if o.get("transform")]
    conn.close()
    return ids, objects


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--penumbra", help="start this binary (`serve --port 0`) and stop it after")
    ap.add_argument("--url", default="http://127.0.0.1:8080", help="else target this server")
    ap.add_argument("--pid", type=int, help="the target server's pid (for RSS)")
    ap.add_argument("--scene-file", default=os.path.join(os.path.dirname(__file__),
                                                         "../../scenes/cubes15.scene.json"))
    ap.add_argument("--clients", type=int, default=50)
    ap.add_argument("--scenes", type=int, default=10)
    ap.add_argument("--seconds", type=float, default=60)
    ap.add_argument("--mode", choices=["drag", "flood"], default="drag")
    ap.add_argument("--edit-rate", type=float, default=4.0, help="edits/s while dragging, at most")
    ap.add_argument("--pause", type=float, default=4.0, help="longest pause between drags, s")
    ap.add_argument("--image-share", type=float, default=0.05, help="share of frames with an image")
    ap.add_argument("--no-events", dest="events", action="store_false")
    ap.add_argument("--procs", type=int, default=5, help="driver processes")
    ap.add_argument("--warmup", type=float, default=10, help="s before the RSS baseline")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--json", help="write samples and summary here")
    ap.add_argument("--html", help="write the HTML report here")
    ap.add_argument("--max-errors", type=int, help="fail when errors + timeouts exceed this")
    ap.add_argument("--max-rss-growth", type=float, help="fail when RSS grows more (MB)")
    ap.add_argument("--expect-allocator", help="fail unless /api/health names this allocator")
    args = ap.parse_args()
    if not (1 <= args.clients <= 256 and 0 < args.seconds <= 3600 and 1 <= args.scenes <= 32):
        raise SystemExit("bounds: 1..256 clients, 1..32 scenes, at most 3600 s")

    proc, data_dir = None, None
    if args.penumbra:
        data_dir = tempfile.mkdtemp(prefix="penumbra-load-")
        proc, args.port = start_server(args.penumbra, data_dir)
        args.host, pid = "127.0.0.1", proc.pid
    else:
        url = urllib.parse.urlparse(args.url)
        args.host, args.port, pid = url.hostname, url.port or 80, args.pid
    if args.host not in ("127.0.0.1", "localhost", "::1"):
        raise SystemExit("loopback only")
    try:
        if args.mode == "flood":
            args.scenes = 1
        allocator = server_allocator(args)
        scenes, objects = create_scenes(args)
        clients = [(i, scenes[i % len(scenes)], objects[(i // len(scenes)) % len(objects)])
                   for i in range(args.clients)]
        t0 = time.perf_counter()
        deadline = time.time() + args.seconds
        rss = []
        if pid:
            threading.Thread(target=sample_rss, args=(pid, t0, deadline + 1, rss),
                             daemon=True).start()
        ctx = multiprocessing.get_context("fork")
        queue = ctx.Queue()
        procs = [ctx.Process(target=run_group, args=(args, clients[k::args.procs], t0, deadline,
                                                     queue))
                 for k in range(min(args.procs, len(clients)))]
        for p in procs:
            p.start()
        samples, streams = [], {"events": 0, "errors": 0, "out_of_order": 0}
        for _ in procs:
            got, stream_stats = queue.get()
            samples += got
            for key in streams:
                streams[key] += stream_stats[key]
        for p in procs:
            p.join()
        time.sleep(1.5)
    finally:
        if proc:
            proc.terminate()
            proc.wait(timeout=30)
        if data_dir:
            shutil.rmtree(data_dir, ignore_errors=True)

    summary = load_report.summarize(samples, rss, streams, args)
    print(load_report.text(summary))
    print(f"server allocator: {allocator}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"summary": summary, "rss": rss}, f)
    if args.html:
        with open(args.html, "w") as f:
            f.write(load_report.html(summary, samples, rss))
        print(f"report: {args.html}")
    broken = []
    if args.max_errors is not None and summary["errors"] + summary["timeouts"] > args.max_errors:
        broken.append(f"{summary['errors']} errors + {summary['timeouts']} timeouts")
    if args.max_rss_growth is not None and summary.get("rss_growth_mb", 0) > args.max_rss_growth:
        broken.append(f"RSS grew {summary['rss_growth_mb']:.1f} MB")
    if args.expect_allocator and allocator != args.expect_allocator:
        broken.append(f"the server runs on {allocator}, not {args.expect_allocator}")
    if broken:
        raise SystemExit("FAILED: " + "; ".join(broken))


if __name__ == "__main__":
    main()
