#!/usr/bin/env python3
"""Penumbra nodes behind HAProxy on loopback (docs/SERVER.md "Many nodes"): a private PostgreSQL 15
cluster (initdb in a temporary directory, a unix socket only, run as the user postgres when root),
N `penumbra serve --journal ... --restore on-request` nodes sharing it, and HAProxy with
deploy/haproxy.cfg in front (the compose file's config, its addresses given by environment
variables). As a program it starts them, prints the URL and stops everything on Ctrl-C:
  python3 deploy/loopback.py --penumbra build/penumbra [--nodes 3] [--lease-seconds 3]
As a module, Cluster is what tests/server/scene_fencing.py, tests/server/failover.py and
bench/failover.py start. Everything it starts is stopped when the process exits."""
import argparse
import atexit
import http.client
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
PG_BIN = "/usr/lib/postgresql/15/bin"  # Debian's postgresql-15
HAPROXY = shutil.which("haproxy") or "/usr/sbin/haproxy"
PG_USER = "penumbra"  # the cluster's superuser, whoever runs it


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def request(port, method, path, body=None, timeout=30):
    """(status, headers with lower-case names (as HAProxy sends them), body bytes); status 0 when
    the connection failed or was cut."""
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    try:
        conn.request(method, path, body=body,
                     headers={"Content-Type": "application/json"} if body is not None else {})
        answer = conn.getresponse()
        return answer.status, {k.lower(): v for k, v in answer.getheaders()}, answer.read()
    except (OSError, http.client.HTTPException):
        return 0, {}, b""
    finally:
        conn.close()


class Cluster:
    """The private database, `nodes` servers and (haproxy=True) HAProxy; stop() ends them all.
    A snapshot every 20 versions (serve_flags) bounds what a takeover replays: the failover time
    is the lease's rest plus that restore."""

    def __init__(self, penumbra, nodes=3, lease_seconds=3.0, haproxy=True, fsync=False,
                 serve_flags=("--snapshot-every", "20")):
        self.penumbra = os.path.abspath(penumbra)
        self.dir = tempfile.mkdtemp(prefix="penumbra-cluster-")
        os.chmod(self.dir, 0o755)
        self.lease_seconds = lease_seconds
        self.serve_flags = list(serve_flags)
        self.procs = {}  # node index → Popen
        self.ports = [free_port() for _ in range(nodes)]
        self.haproxy = None
        self.haproxy_port = free_port() if haproxy else None
        atexit.register(self.stop)
        self._start_database(fsync)
        for i in range(nodes):
            self.start_node(i)
        if haproxy:
            self._start_haproxy()

    # The database ------------------------------------------------------------------------------
    def _as_owner(self, args):
        prefix = ["runuser", "-u", "postgres", "--"] if os.geteuid() == 0 else []
        subprocess.run(prefix + args, check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)

    def _start_database(self, fsync):
        self.pg = os.path.join(self.dir, "pg")
        os.mkdir(self.pg)
        if os.geteuid() == 0:
            shutil.chown(self.pg, "postgres")
        self._as_owner([f"{PG_BIN}/initdb", "--no-sync", "--auth=trust", "-E", "UTF8", "-U",
                        PG_USER, "-D", f"{self.pg}/data"])
        options = f"-k {self.pg} -c listen_addresses= -c max_connections=200"
        if not fsync:
            options += " -c fsync=off"
        self._as_owner([f"{PG_BIN}/pg_ctl", "-D", f"{self.pg}/data", "-l", f"{self.pg}/log", "-o",
                        options, "-w", "start"])
        self.database_running = True
        self.uri = f"postgresql://{PG_USER}@/postgres?host={self.pg}"

    def sql(self, query):
        """The rows of `query` as lists of strings (psql, unaligned)."""
        out = subprocess.run(["psql", self.uri, "-At", "-F", "\t", "-c", query], check=True,
                             capture_output=True, text=True).stdout
        return [line.split("\t") for line in out.splitlines() if line]

    # The nodes ---------------------------------------------------------------------------------
    def start_node(self, i):
        data = os.path.join(self.dir, f"node{i + 1}")
        os.makedirs(data, exist_ok=True)
        log = open(os.path.join(self.dir, f"node{i + 1}.log"), "a")
        self.procs[i] = subprocess.Popen(
            [self.penumbra, "serve", "--journal", self.uri, "--data", data, "--port",
             str(self.ports[i]), "--node-id", f"node{i + 1}", "--restore", "on-request",
             "--lease-seconds", str(self.lease_seconds)] + self.serve_flags,
            stdout=log, stderr=log, cwd=data)
        deadline = time.monotonic() + 30
        while request(self.ports[i], "GET", "/api/health", timeout=2)[0] != 200:
            if self.procs[i].poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"node{i + 1} did not start (see {log.name})")
            time.sleep(0.05)

    def signal_node(self, i, sig):
        self.procs[i].send_signal(sig)
        if sig == signal.SIGKILL:
            self.procs[i].wait()

    def node_log(self, i):
        with open(os.path.join(self.dir, f"node{i + 1}.log")) as f:
            return f.read()

    # HAProxy -----------------------------------------------------------------------------------
    def haproxy_env(self):
        env = dict(os.environ, PENUMBRA_LISTEN=f"127.0.0.1:{self.haproxy_port}")
        for i in range(3):  # the config names three nodes
            port = self.ports[i] if i < len(self.ports) else free_port()
            env[f"PENUMBRA_NODE{i + 1}"] = f"127.0.0.1:{port}"
        return env

    def _start_haproxy(self):
        log = open(os.path.join(self.dir, "haproxy.log"), "a")
        self.haproxy = subprocess.Popen([HAPROXY, "-db", "-f", os.path.join(HERE, "haproxy.cfg")],
                                        env=self.haproxy_env(), stdout=log, stderr=log)
        deadline = time.monotonic() + 10
        while request(self.haproxy_port, "GET", "/api/health", timeout=2)[0] != 200:
            if self.haproxy.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"haproxy did not start (see {log.name})")
            time.sleep(0.05)

    def stop(self):
        for proc in list(self.procs.values()) + ([self.haproxy] if self.haproxy else []):
            if proc.poll() is None:
                proc.send_signal(signal.SIGCONT)
                proc.kill()
                proc.wait()
        if getattr(self, "database_running", False):
            self._as_owner([f"{PG_BIN}/pg_ctl", "-D", f"{self.pg}/data", "-m", "immediate",
                            "stop"])
            self.database_running = False
        shutil.rmtree(self.dir, ignore_errors=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--penumbra", default=os.path.join(HERE, "..", "build", "penumbra"))
    parser.add_argument("--nodes", type=int, default=3, choices=[1, 2, 3])
    parser.add_argument("--lease-seconds", type=float, default=3.0)
    args = parser.parse_args()
    cluster = Cluster(args.penumbra, args.nodes, args.lease_seconds)
    print(f"penumbra: {args.nodes} nodes behind HAProxy at http://127.0.0.1:{cluster.haproxy_port}/"
          f" (nodes on ports {', '.join(map(str, cluster.ports))}; files in {cluster.dir})",
          flush=True)
    try:
        signal.sigwait({signal.SIGINT, signal.SIGTERM})
    finally:
        cluster.stop()


if __name__ == "__main__":
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    main()
