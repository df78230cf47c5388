"""The HTTP live view under hostile load (docs/outputs.md): slow clients, many image requests, SIGTERM.

hdlampd replays the drive scenario in a loop at real time (160x90) with its frame stream and
HTTP on free loopback ports. Every check reads the daemon's own counters (/status) and the
frames' headers, never a rate: the renderer must show every cycle, a healthy stream reader must
get one frame per cycle, and every HTTP answer is 200 or a counted 503.
"""
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import threading
import time
import urllib.error
import urllib.request

import pytest

from scenario import HDLAMPD, dbc_path, generate, lamp_status
from streamclient import connect, read_frame

SIZE = "320x180"
WRK = shutil.which("wrk")
# wrk's Lua: every answer's status, summed over wrk's threads, printed as "status CODE N" lines.
WRK_STATUS_LUA = """
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
  io.write(string.format("socket errors %d %d %d %d %d\\n", e.connect, e.read, e.write,
                         e.timeout, e.status))
end
"""


class Daemon:
    """hdlampd on the looped drive scenario; its ports, stderr lines, and at the end stdout."""

    def __init__(self, lamps, log, *args):
        cmd = [HDLAMPD, "--replay", log, "--loop", "--dbc", dbc_path("hd84.dbc"),
               "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
               "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
               "--set", f"render.size={SIZE}", "--set", "stream.tcp=127.0.0.1:0",
               "--set", "http.listen=127.0.0.1:0", *args]
        self.p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.log = []
        self.stream_port = self.http_port = None
        while self.http_port is None:
            line = self.p.stderr.readline()
            assert line, f"hdlampd exited early: {self.log}"
            self.log.append(line)
            m = re.search(r"frame stream on .*\(port (\d+)\)", line)
            if m:
                self.stream_port = int(m.group(1))
            m = re.search(r"live view on http://.*\(port (\d+)\)", line)
            if m:
                self.http_port = int(m.group(1))
        self.tail = threading.Thread(target=lambda: self.log.extend(self.p.stderr), daemon=True)
        self.tail.start()
        self.url = f"http://127.0.0.1:{self.http_port}"

    def get(self, path, timeout=10):
        with urllib.request.urlopen(self.url + path, timeout=timeout) as r:
            return r.status, r.read()

    def status(self):
        return json.loads(self.get("/status")[1])

    def stop(self):
        """SIGTERM: the exit code, the seconds it took and the summary printed on stdout."""
        t0 = time.monotonic()
        self.p.send_signal(signal.SIGTERM)
        self.p.wait(60)
        took = time.monotonic() - t0
        out = self.p.stdout.read()
        self.tail.join(10)
        lines = out.strip().splitlines()
        return self.p.returncode, took, json.loads(lines[-1]) if lines else None

    def kill(self):
        if self.p.poll() is None:
            self.p.kill()
            self.p.wait()


@pytest.fixture(scope="module")
def scenario_log(hd84, tmp_path_factory):
    out = tmp_path_factory.mktemp("scenario")
    log, _, _ = generate(os.environ["HDLAMP"], dbc_path("hd84.dbc"), str(out), phase=5)
    return log


@pytest.fixture
def daemon(hd84, scenario_log):
    d = Daemon(hd84, scenario_log)
    # the first frame is published (a frame route answers 503 before it)
    until = time.monotonic() + 30
    while d.status()["frames"]["published"] == 0:
        assert time.monotonic() < until, "no frame published"
        time.sleep(0.05)
    yield d
    d.kill()


class Reader(threading.Thread):
    """A healthy frame stream client: reads every frame's header as it comes."""

    def __init__(self, port):
        super().__init__(daemon=True)
        self.sock = connect(port)
        self.headers = []
        self.stop = threading.Event()
        self.start()

    def run(self):
        while not self.stop.is_set():
            f = read_frame(self.sock)
            if f is None:
                break
            self.headers.append(f[0])

    def until_cycle(self, left, timeout=20):
        """Reads on until a frame shows the left lamp's cycle left; then stops."""
        until = time.monotonic() + timeout
        while not self.headers or self.headers[-1]["cycle_seq_left"] < left:
            assert time.monotonic() < until, f"no frame with left cycle {left}"
            time.sleep(0.02)
        self.stop.set()
        self.join(10)
        self.sock.close()


def not_rendered(st):
    return sum(lamp_status(st, lamp)["cycles_not_rendered"] for lamp in ("left", "right"))


def check_every_cycle(reader, control, before, after):
    """Rendering kept up under the load, judged from the daemon's counters and valid on a busy
    machine: during the load no more cycles went unrendered than twice those of the control
    window of the same length just before it (where the machine's own load shows) plus 10 % of
    the load window's cycles (the machine's load changes from one window to the next; the
    encoding that starved the renderer left 25 to 70 % unrendered); and every cycle rendered
    during the load reached the reader, except those the stream counted as skipped."""
    base, loaded = not_rendered(before) - not_rendered(control), \
        not_rendered(after) - not_rendered(before)
    cycles = sum(lamp_status(after, lamp)["cycles"] - lamp_status(before, lamp)["cycles"]
                 for lamp in ("left", "right"))
    assert loaded <= 2 * base + cycles // 10, \
        f"{loaded} of {cycles} cycles not rendered under load, {base} in the control window"
    last = {lamp: lamp_status(after, lamp)["cycles"] for lamp in ("left", "right")}
    reader.until_cycle(last["left"])
    skipped = after["stream"]["frames_skipped"] - before["stream"]["frames_skipped"]
    for lamp in ("left", "right"):
        first = lamp_status(before, lamp)["cycles"]
        nr = lamp_status(after, lamp)["cycles_not_rendered"] - \
            lamp_status(before, lamp)["cycles_not_rendered"]
        seen = {h[f"cycle_seq_{lamp}"] for h in reader.headers}
        missing = [c for c in range(first + 1, last[lamp] + 1) if c not in seen]
        assert len(missing) <= nr + skipped, \
            f"the reader got no frame for {len(missing)} of {last[lamp] - first} {lamp} " \
            f"cycles; {nr} not rendered, {skipped} skipped by the stream"
    print(f"{len(reader.headers)} frames read; cycles not rendered: {base} in the control "
          f"window, {loaded} of {cycles} under load; stream skipped {skipped}")


def wrk(url, seconds, conns=50):
    """wrk's answers by status and its socket errors (connect, read, write, timeout, status)."""
    script = os.path.join(os.environ.get("HL_BUILD_DIR", "."), "wrk-status.lua")
    with open(script, "w") as f:
        f.write(WRK_STATUS_LUA)
    # wrk shares this machine's CPUs with the renderer only because the test runs on one host:
    # at nice 19, what the check measures is what the daemon's own threads take from it.
    r = subprocess.run(["nice", "-n", "19", WRK, "-t2", f"-c{conns}", f"-d{seconds}s", "--timeout", "10s",
                        "-s", script, url], capture_output=True, text=True, timeout=seconds + 60)
    assert r.returncode == 0, r.stderr
    statuses = {int(m[0]): int(m[1]) for m in re.findall(r"^status (\d+) (\d+)$", r.stdout, re.M)}
    errors = [int(x) for x in re.search(r"^socket errors (.*)$", r.stdout, re.M).group(1).split()]
    return statuses, errors, r.stdout


@pytest.mark.skipif(WRK is None, reason="wrk is not installed")
@pytest.mark.parametrize("route", ["/frame.png", "/frame.exr"])
def test_image_load_leaves_rendering_and_the_stream_alone(daemon, route):
    reader = Reader(daemon.stream_port)
    time.sleep(0.5)
    control = daemon.status()
    time.sleep(5)
    before = daemon.status()
    statuses, errors, out = wrk(daemon.url + route, 5)
    after = daemon.status()
    print(f"{route}: {out}")
    check_every_cycle(reader, control, before, after)
    # every answer 200 or 503, each 503 counted
    assert set(statuses) <= {200, 503}, statuses
    assert statuses.get(200, 0) > 0
    assert errors[:4] == [0, 0, 0, 0], f"socket errors {errors}"
    # The daemon counts what it answered, wrk what it read: they differ by the answers in
    # flight when wrk stopped, at most one per connection.
    http_after, http_before = after["http"], before["http"]
    d = {k: http_after[k] - http_before[k] for k in ("requests", "errors", "overloaded")}
    assert d["errors"] == d["overloaded"], "every error under this load is a counted 503"
    assert 0 <= d["overloaded"] - statuses.get(503, 0) <= 50, (d, statuses)
    # (+1: the /status request that read after)
    assert 0 <= d["requests"] - 1 - sum(statuses.values()) <= 50, (d, statuses)
    # each image kind encoded at most once per published frame, whatever the requests
    kind = route.rsplit(".", 1)[1]
    encoded = http_after["encoded"][kind] - http_before["encoded"][kind]
    assert 0 < encoded <= after["frames"]["published"] - before["frames"]["published"] + 1
    assert statuses.get(200, 0) >= encoded
    code, took, summary = daemon.stop()
    assert code == 0 and summary["http"]["overloaded"] >= http_after["overloaded"]


def slowloris(port, n, stop, opened):
    """n connections that each send a request line, then one header line every 2 s."""
    socks = []
    for _ in range(n):
        s = socket.create_connection(("127.0.0.1", port), timeout=10)
        s.sendall(b"GET /status HTTP/1.1\r\nHost: 127.0.0.1\r\n")
        socks.append(s)
    opened.set()
    i = 0
    while not stop.wait(2):
        for s in socks:
            try:
                s.sendall(b"X-Slow-%d: 1\r\n" % i)
            except OSError:
                pass
        i += 1
    return socks


def test_slowloris_does_not_starve_status(daemon):
    before = daemon.status()
    stop, opened, box = threading.Event(), threading.Event(), []
    t = threading.Thread(target=lambda: box.append(slowloris(daemon.http_port, 200, stop, opened)))
    t.start()
    assert opened.wait(30), "could not open 200 connections"
    answered = []
    for _ in range(15):
        try:
            answered.append(daemon.get("/status", timeout=5)[0])
        except (urllib.error.URLError, OSError) as e:
            answered.append(repr(e))
        time.sleep(0.2)
    stop.set()
    t.join(10)
    assert answered == [200] * 15, answered
    # the header deadline: none of the slow requests completed in time, each was closed (on the
    # next connection accepted after the deadline) and counted
    time.sleep(10.5 - 3.0)
    after = daemon.status()
    closed = 0
    for s in box[0]:
        s.settimeout(5)
        try:
            closed += s.recv(1024) == b""
        except ConnectionResetError:
            closed += 1
        s.close()
    assert closed == 200
    assert after["http"]["header_timeouts"] - before["http"]["header_timeouts"] == 200
    assert after["http"]["connections_refused"] == before["http"]["connections_refused"]


def test_per_address_limit_refuses_and_counts(daemon):
    """256 connections from 127.0.0.1 (the per-address limit) are served; the 257th is closed
    at once and counted (read from the summary at exit: /status could not get in either)."""
    socks = []
    try:
        for _ in range(257):
            s = socket.create_connection(("127.0.0.1", daemon.http_port), timeout=10)
            s.sendall(b"GET /status HTTP/1.1\r\n")
            socks.append(s)
        closed = []
        for i, s in enumerate(socks):
            s.settimeout(0.05 if i < 256 else 5)
            try:
                if s.recv(64) == b"":
                    closed.append(i)
            except socket.timeout:
                pass
            except ConnectionResetError:
                closed.append(i)
        code, _, summary = daemon.stop()
    finally:
        for s in socks:
            s.close()
    assert closed == [256]
    assert code == 0
    assert summary["http"]["connections_refused"] == 1
    assert summary["http"]["header_timeouts"] == 0


@pytest.mark.skipif(WRK is None, reason="wrk is not installed")
def test_sigterm_under_load_exits_cleanly(daemon):
    reader = Reader(daemon.stream_port)
    mjpeg = urllib.request.urlopen(daemon.url + "/stream.mjpg", timeout=10)
    assert mjpeg.read(64).startswith(b"--hlframe")
    w = subprocess.Popen([WRK, "-t2", "-c50", "-d20s", daemon.url + "/frame.exr"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        time.sleep(2)
        code, took, summary = daemon.stop()
    finally:
        w.kill()
        w.wait()
    print(f"SIGTERM under /frame.exr load, a stream and an MJPEG client: exited in {took:.3f} s")
    assert code == 0
    assert summary["http"]["requests"] > 0
    assert took < 10
    # the daemon ended both streams
    reader.join(10)
    assert not reader.is_alive()
    mjpeg.close()


def test_non_loopback_listen_warns(hd84, scenario_log):
    d = Daemon(hd84, scenario_log, "--set", "http.listen=0.0.0.0:0")
    try:
        code, _, _ = d.stop()
    finally:
        d.kill()
    assert code == 0
    warn = [l for l in d.log if "warning" in l and "0.0.0.0:0" in l]
    assert warn, "".join(d.log)
    assert "not a loopback address" in warn[0]
