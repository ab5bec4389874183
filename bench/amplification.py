#!/usr/bin/env python3
"""Peak RSS of `penumbra serve` under small requests that ask for much (docs/BENCHMARKS.md
"Hostile requests"): each case runs on a fresh server (cubes15, ephemeral) and prints the
answers' statuses and the server's VmHWM afterwards.
Usage: python3 bench/amplification.py [--penumbra build/penumbra] [--scene scenes/cubes15.scene.json]
"""
import argparse
import gzip
import re
import socket
import subprocess
import sys
import threading
import urllib.error
import urllib.request


def start(penumbra, scene):
    proc = subprocess.Popen([penumbra, "serve", scene, "--ephemeral", "--port", "0"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    for line in proc.stdout:
        match = re.search(r"open http://[^:]+:(\d+)/\?scene=(\S+)", line)
        if match:
            return proc, int(match.group(1)), match.group(2)
    sys.exit("amplification: the server did not start")


def peak_mib(proc):
    with open(f"/proc/{proc.pid}/status") as status:
        return int(next(l for l in status if l.startswith("VmHWM")).split()[1]) // 1024


def raw(port, head, pieces=()):
    """Sends a request head and body pieces; returns the status line (or what went wrong)."""
    with socket.create_connection(("127.0.0.1", port), timeout=120) as sock:
        try:
            sock.sendall(head)
            for piece in pieces:
                sock.sendall(piece)
        except OSError as error:
            return f"send stopped: {error.strerror}"
        answer = sock.recv(200).split(b"\r\n")[0]
        return answer.decode() or "closed"


def chunked(total, size=1 << 20):
    for _ in range(total // size):
        yield b"%x\r\n" % size + b" " * size + b"\r\n"
    yield b"0\r\n\r\n"


def images(port, scene, query, count):
    statuses = []

    def one():
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/api/scenes/{scene}/image?{query}",
                                        timeout=600) as answer:
                answer.read()
                statuses.append(answer.status)
        except urllib.error.HTTPError as error:
            statuses.append(error.code)
    threads = [threading.Thread(target=one) for _ in range(count)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    return " ".join(str(s) for s in sorted(statuses))


def cases(scene):
    edits = f"/api/scenes/{scene}/edits".encode()
    bomb = gzip.compress(b'{"edits":[' + b" " * (200 << 20) + b"]}", 9)
    yield ("gzip body, %d KB inflating to 200 MiB" % (len(bomb) // 1000),
           lambda port: raw(port, b"POST " + edits + b" HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                            b"Content-Type: application/json\r\nContent-Encoding: gzip\r\n"
                            b"Content-Length: %d\r\n\r\n" % len(bomb) + bomb))
    yield ("chunked body of 300 MiB",
           lambda port: raw(port, b"POST " + edits + b" HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                            b"Content-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n",
                            chunked(300 << 20)))
    yield ("one header line of 100 MiB",
           lambda port: raw(port, b"GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Big: ",
                            [b"a" * (1 << 20)] * 100 + [b"\r\n\r\n"]))
    for query, label in [("width=4096&height=4096&samples=1", "4096² images"),
                         ("width=4096&height=4096&samples=1&gi=sensors&sensor_size=2", "4096² GI images"),
                         ("width=2048&height=2048&samples=1&gi=sensors&sensor_size=2", "2048² GI images")]:
        yield (f"four concurrent {label}", lambda port, q=query: images(port, scene, q, 4))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--penumbra", default="build/penumbra")
    parser.add_argument("--scene", default="scenes/cubes15.scene.json")
    args = parser.parse_args()
    print("| case | answers | peak RSS |\n|---|---|---|")
    for label, run in cases(re.sub(r"\..*", "", args.scene.split("/")[-1])):
        proc, port, scene = start(args.penumbra, args.scene)
        try:
            answers = run(port)
            print(f"| {label} | {answers} | {peak_mib(proc)} MiB |", flush=True)
        finally:
            proc.terminate()
            proc.wait()


if __name__ == "__main__":
    main()
