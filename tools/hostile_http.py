#!/usr/bin/python3
"""Hostile HTTP load on hdlampd, for the numbers of docs/performance.md (not part of the test suite).

Starts hdlampd on the drive scenario replayed in a loop at real time (frame stream and HTTP on
free loopback ports), connects a healthy frame stream reader, then runs one load for a bounded
time: `wrk` on a route, or N slowloris connections (a request line, then one header line every
2 s) while /status is asked once a second. Prints one JSON object: the cycles, the frames the
reader got per cycle, cycles_not_rendered, the 503s wrk saw and the daemon counted, the
daemon's RSS (VmHWM and the largest VmRSS sampled) and how long SIGTERM took.

  tools/hostile_http.py --build build --wrk /frame.png --seconds 30
  tools/hostile_http.py --build build --wrk /frame.exr --seconds 30
  tools/hostile_http.py --build build --slowloris 200 --seconds 30

Only 127.0.0.1 is ever targeted. Exit 0 (ran), 1 (failed), 2 (usage).
"""
import argparse
import json
import os
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

HEADER = struct.Struct("<IHHQIIIIII5q2Q2BB5x2qB3xII6fIfBB2xd16x")  # docs/outputs.md, "Frame stream" (v3)
LUA = """
local threads = {}
function setup(thread) table.insert(threads, thread) end
function init(args) statuses = {} end
function response(status, headers, body) statuses[status] = (statuses[status] or 0) + 1 end
function done(summary, latency, requests)
  local total = {}
  for _, t in ipairs(threads) do
    for k, v in pairs(t:get("statuses")) do total[k] = (total[k] or 0) + v end
  end
  for k, v in pairs(total) do io.write(string.format("status %d %d\\n", k, v)) end
  local e = summary.errors
  io.write(string.format("socket errors %d %d %d %d\\n", e.connect, e.read, e.write, e.timeout))
end
"""


def recv_exact(s, n):
    buf = bytearray()
    while len(buf) < n:
        chunk = s.recv(n - len(buf))
        if not chunk:
            return None
        buf += chunk
    return bytes(buf)


class Reader(threading.Thread):
    """The healthy stream client: every frame's (seq, left cycle, right cycle)."""

    def __init__(self, port):
        super().__init__(daemon=True)
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=10)
        self.frames = []
        self.start()

    def run(self):
        try:
            while True:
                raw = recv_exact(self.sock, HEADER.size)
                if raw is None:
                    return
                h = HEADER.unpack(raw)
                if recv_exact(self.sock, h[8]) is None:
                    return
                self.frames.append((h[3], h[15], h[16]))
        except OSError:
            return


def rss_kb(pid):
    vals = {}
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            k, _, v = line.partition(":")
            if k in ("VmRSS", "VmHWM"):
                vals[k] = int(v.split()[0])
    return vals


def status(port):
    with urllib.request.urlopen(f"http://127.0.0.1:{port}/status", timeout=10) as r:
        return json.loads(r.read())


def lamp(st, name, key):
    return next(l for l in st["lamps"] if l["name"] == name)[key]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build", help="the build directory (default build)")
    ap.add_argument("--source", default=os.path.join(os.path.dirname(__file__), ".."))
    ap.add_argument("--wrk", metavar="ROUTE", help="run wrk -c CONNS on this route")
    ap.add_argument("--conns", type=int, default=50)
    ap.add_argument("--slowloris", type=int, metavar="N", help="N slowloris connections")
    ap.add_argument("--idle", action="store_true", help="no load: the baseline")
    ap.add_argument("--load-nice", type=int, default=0, metavar="N",
                    help="run wrk at nice N (default 0: it competes with the renderer)")
    ap.add_argument("--seconds", type=int, default=30)
    ap.add_argument("--size", default="160x90", help="render.size (default 160x90)")
    ap.add_argument("--rt", type=int, default=0, metavar="PRIO",
                    help="sched.realtime_priority (the installed service: 10; default 0)")
    a = ap.parse_args()
    if (bool(a.wrk) + bool(a.slowloris) + a.idle) != 1 or a.seconds < 1 or a.seconds > 300:
        ap.print_usage(sys.stderr)
        print("hostile_http: expected one of --wrk ROUTE, --slowloris N or --idle, and 1..300 s",
              file=sys.stderr)
        return 2
    if a.wrk and not shutil.which("wrk"):
        print("hostile_http: wrk is not installed", file=sys.stderr)
        return 1
    hdlamp = os.path.join(a.build, "tools", "hdlamp")
    hdlampd = os.path.join(a.build, "daemon", "hdlampd")
    dbc = os.path.join(a.source, "dbc", "hd84.dbc")
    tmp = tempfile.mkdtemp(prefix="hostile_http.")
    subprocess.run([hdlamp, "model", "--out", tmp], check=True, capture_output=True)
    log = os.path.join(tmp, "scenario.log")
    subprocess.run([hdlamp, "scenario", "--dbc", dbc, "--out", log, "--expect",
                    os.path.join(tmp, "expect.jsonl"), "--phase-cycles", "5"], check=True,
                   capture_output=True)
    p = subprocess.Popen([hdlampd, "--replay", log, "--loop", "--dbc", dbc,
                          "--set", f"lamps.left={tmp}/hd84_left.lid.exr",
                          "--set", f"lamps.right={tmp}/hd84_right.lid.exr",
                          "--set", f"render.size={a.size}", "--set", "stream.tcp=127.0.0.1:0",
                          "--set", "http.listen=127.0.0.1:0",
                          "--set", f"sched.realtime_priority={a.rt}"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    sport = hport = None
    while hport is None:
        line = p.stderr.readline()
        if not line:
            print("hostile_http: hdlampd exited early", file=sys.stderr)
            return 1
        m = re.search(r"frame stream on .*\(port (\d+)\)", line)
        sport = int(m.group(1)) if m else sport
        m = re.search(r"live view on http://.*\(port (\d+)\)", line)
        hport = int(m.group(1)) if m else hport
    threading.Thread(target=lambda: [None for _ in p.stderr], daemon=True).start()
    while status(hport)["frames"]["published"] == 0:
        time.sleep(0.05)
    reader = Reader(sport)
    time.sleep(0.5)
    rss_max, done = 0, threading.Event()

    def sample():
        nonlocal rss_max
        while not done.wait(0.1):
            rss_max = max(rss_max, rss_kb(p.pid).get("VmRSS", 0))

    threading.Thread(target=sample, daemon=True).start()
    rss_start = rss_kb(p.pid)["VmRSS"]
    before = status(hport)
    out = {"load": f"wrk -c{a.conns} {a.wrk} (nice {a.load_nice})" if a.wrk else
           f"slowloris {a.slowloris}" if a.slowloris else "none",
           "seconds": a.seconds, "size": a.size}
    if a.wrk:
        script = os.path.join(tmp, "status.lua")
        with open(script, "w") as f:
            f.write(LUA)
        r = subprocess.run(["nice", "-n", str(a.load_nice), "wrk", "-t2", f"-c{a.conns}", f"-d{a.seconds}s", "--timeout", "10s",
                            "-s", script, f"http://127.0.0.1:{hport}{a.wrk}"],
                           capture_output=True, text=True)
        out["wrk_statuses"] = {m[0]: int(m[1]) for m in
                               re.findall(r"^status (\d+) (\d+)$", r.stdout, re.M)}
        out["wrk_socket_errors"] = re.search(r"^socket errors (.*)$", r.stdout, re.M).group(1)
        m = re.search(r"Requests/sec:\s+(\S+)", r.stdout)
        out["wrk_requests_per_s"] = float(m.group(1)) if m else None
    elif a.idle:
        time.sleep(a.seconds)
    else:
        socks, answered, asked = [], 0, 0
        for _ in range(a.slowloris):
            s = socket.create_connection(("127.0.0.1", hport), timeout=10)
            s.sendall(b"GET /status HTTP/1.1\r\nHost: 127.0.0.1\r\n")
            socks.append(s)
        t_end, i = time.monotonic() + a.seconds, 0
        while time.monotonic() < t_end:
            for s in socks:
                try:
                    s.sendall(b"X-Slow-%d: 1\r\n" % i)
                except OSError:
                    pass
            i += 1
            for _ in range(2):
                asked += 1
                try:
                    status(hport)
                    answered += 1
                except OSError:
                    pass
                time.sleep(1)
        out["status_answered"] = f"{answered}/{asked}"
        for s in socks:
            s.close()
    after = status(hport)
    done.set()
    cycles = {n: lamp(after, n, "cycles") - lamp(before, n, "cycles") for n in ("left", "right")}
    # frames the reader got for the cycles of the window (left lamp's cycle_seq)
    first, last = lamp(before, "left", "cycles"), lamp(after, "left", "cycles")
    t_wait = time.monotonic() + 10
    while (not reader.frames or reader.frames[-1][1] < last) and time.monotonic() < t_wait:
        time.sleep(0.05)
    seen = {f[1] for f in reader.frames if first < f[1] <= last}
    out.update({
        "cycles": cycles,
        "reader_frames_with_a_new_left_cycle": len(seen),
        "reader_frames_per_cycle": round(len(seen) / max(1, last - first), 4),
        "cycles_not_rendered": {n: lamp(after, n, "cycles_not_rendered") -
                                lamp(before, n, "cycles_not_rendered") for n in ("left", "right")},
        "frames_not_published": after["frames"]["not_published"] - before["frames"]["not_published"],
        "http": {k: v - before["http"][k] if isinstance(v, int) else v
                 for k, v in after.get("http", {}).items()},
        "rss_kb": {"start": rss_start, "max_sampled": rss_max, **rss_kb(p.pid)},
    })
    t0 = time.monotonic()
    p.send_signal(signal.SIGTERM)
    code = p.wait(60)
    out["sigterm_s"] = round(time.monotonic() - t0, 3)
    out["exit"] = code
    print(json.dumps(out))
    shutil.rmtree(tmp, ignore_errors=True)
    return 0 if code == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
