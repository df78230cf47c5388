"""hdlampd's frame stream and its clients (docs/outputs.md): a client that half-closes keeps its
frames, clients that stop reading are dropped after stream.stall_timeout_ms or replaced by a
new client when all slots are taken, and a client that sends anything is closed while a reader
beside it gets every frame. Every wait is for an event the daemon reports (/status, a socket
closed), with a limit only a broken daemon reaches; times are compared on CLOCK_MONOTONIC, the
daemon's own clock."""
import json
import re
import socket
import subprocess
import threading
import time
import urllib.request

import pytest

from proc import run
from scenario import HDLAMPD, dbc_path, lamp_status
from streamclient import HEADER, FIELDS, connect, read_frame, recv_exact

SIZE = (160, 90)
FRAME_BYTES = HEADER.size + SIZE[0] * SIZE[1] * 3
LIMIT_S = 60  # only a broken daemon makes a wait this long


@pytest.fixture(scope="module")
def lamps(hdlamp, tmp_path_factory):
    out = tmp_path_factory.mktemp("lamps")
    run(hdlamp, "model", "--out", out)
    return out


def start(lamps, log, *args):
    """hdlampd replaying log (at its pace) with the stream and HTTP on free loopback ports:
    (process, stream port, http port or None)."""
    cmd = [HDLAMPD, "--replay", log, "--dbc", dbc_path("hd84.dbc"),
           "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
           "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
           "--set", f"render.size={SIZE[0]}x{SIZE[1]}", "--set", "stream.tcp=127.0.0.1:0",
           *map(str, args)]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    stream = http = None
    want_http = "http.listen=" not in args
    log_lines = []
    while stream is None or (want_http and http is None):
        line = p.stderr.readline()
        assert line, f"hdlampd exited early: {log_lines}"
        log_lines.append(line)
        if m := re.search(r"frame stream on .*\(port (\d+)\)", line):
            stream = int(m.group(1))
        if m := re.search(r"live view on http://.*\(port (\d+)\)", line):
            http = int(m.group(1))
    threading.Thread(target=lambda: log_lines.extend(p.stderr), daemon=True).start()
    return p, stream, http


def stop(p):
    p.send_signal(15)
    out, _ = p.communicate(timeout=30)
    assert p.returncode == 0
    return json.loads(out.strip().splitlines()[-1])


def status(http):
    with urllib.request.urlopen(f"http://127.0.0.1:{http}/status", timeout=10) as r:
        return json.loads(r.read())


def metrics(http):
    with urllib.request.urlopen(f"http://127.0.0.1:{http}/metrics", timeout=10) as r:
        return r.read().decode()


def wait_status(http, what, pred):
    """The first /status for which pred holds; fails naming what it waited for."""
    until = time.monotonic() + LIMIT_S
    while True:
        st = status(http)
        if pred(st):
            return st
        assert time.monotonic() < until, f"waited {LIMIT_S} s for {what}: {st['stream']}"
        time.sleep(0.02)


def now_ns():
    return time.clock_gettime_ns(time.CLOCK_MONOTONIC)


def non_reader(port):
    """A client that reads its first frame's header, then nothing: (socket, header). The
    small receive buffer (set before connecting) keeps what the daemon can queue small."""
    s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    s.settimeout(10)
    s.connect(("127.0.0.1", port))
    raw = recv_exact(s, HEADER.size)
    assert raw is not None, "the daemon closed a new client at once (refused)"
    return s, dict(zip(FIELDS, HEADER.unpack(raw)))


def closed_by_daemon(s, limit_bytes=64 << 20):
    """Reads what is queued until the daemon's close (end of file or reset): how it ended."""
    got = 0
    try:
        while got < limit_bytes:
            chunk = s.recv(1 << 16)
            if not chunk:
                return "eof"
            got += len(chunk)
    except ConnectionResetError:
        return "reset"
    except socket.timeout:
        return "open"
    return "open"


def behind_for_sure(s, first_seq):
    """A published frame number by which a client that stopped reading after frame first_seq's
    header is behind (sending a frame 3 or more older than the newest) whatever the kernel
    queued: at most its send buffer (net.ipv4.tcp_wmem's maximum) and receive buffer (twice,
    for the window's rounding) of frames after that one."""
    with open("/proc/sys/net/ipv4/tcp_wmem") as f:
        wmem_max = int(f.read().split()[2])
    rcvbuf = s.getsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF)
    return first_seq + (wmem_max + 2 * rcvbuf) // FRAME_BYTES + 1 + 3


def read_frames(port, n):
    """A reader: n frames in a row; their headers."""
    s = connect(port)
    hs = []
    for _ in range(n):
        f = read_frame(s)
        assert f is not None, f"the daemon closed a reader after {len(hs)} frames"
        hs.append(f[0])
    return s, hs


def hold_log(hdlamp, tmp_path, cycles):
    """A drive without faults: both lamps' low beam, a cycle every 20 ms."""
    log = tmp_path / "hold.log"
    run(hdlamp, "scenario", "--dbc", dbc_path("hd84.dbc"), "--out", log, "--hold", "low",
        "--phase-cycles", cycles)
    return log


def test_half_closed_client_keeps_receiving(hdlamp, lamps, tmp_path):
    # shutdown(SHUT_WR), as "nc -N" does: not input, the client stays and gets its frames
    log = hold_log(hdlamp, tmp_path, 25)
    p, port, http = start(lamps, log, "--loop")
    try:
        s = connect(port)
        s.shutdown(socket.SHUT_WR)
        seqs = []
        for _ in range(25):
            f = read_frame(s)
            assert f is not None, f"half-closed client closed after {len(seqs)} frames"
            seqs.append(f[0]["seq"])
        assert seqs == sorted(set(seqs))
        st = status(http)["stream"]
        assert st["clients"] == 1 and st["accepted"] == 1
        assert st["dropped"] == {"disconnected": 0, "stalled": 0, "evicted": 0, "input": 0}
        # its end of file read once, never again (a socket at EOF is readable for ever: a
        # stream polling it for input spun, 15k-54k reads in 3 s)
        assert st["input_reads"] == 1
        s.close()
    finally:
        stop(p)


def test_non_readers_over_the_limit_make_room_for_a_reader(hdlamp, lamps, tmp_path):
    # a regression seen before: with max_clients non-readers connected a new reader got end of file at once.
    # Now a new client replaces the client behind that took no byte for longest.
    log = hold_log(hdlamp, tmp_path, 50)
    p, port, http = start(lamps, log, "--loop", "--set", "stream.max_clients=4",
                          "--set", "stream.stall_timeout_ms=600000")
    try:
        first = [non_reader(port) for _ in range(4)]
        last_first = max(h["seq"] for _, h in first)
        by = max(behind_for_sure(s, h["seq"]) for s, h in first)
        wait_status(http, f"frame {by} published (the first 4 behind)",
                    lambda st: st["frames"]["published"] >= by)
        # 4 more non-readers: each is accepted (it reads a header) in place of one of the first
        second = [non_reader(port) for _ in range(4)]
        assert all(h["seq"] >= last_first for _, h in second)
        for s, _ in first:
            assert closed_by_daemon(s) in ("eof", "reset")
            s.close()
        by = max(behind_for_sure(s, h["seq"]) for s, h in second)
        wait_status(http, f"frame {by} published (the second 4 behind)",
                    lambda st: st["frames"]["published"] >= by)
        reader, hs = read_frames(port, 25)
        seqs = [h["seq"] for h in hs]
        assert seqs == sorted(set(seqs))
        st = status(http)["stream"]
        print(f"stream after 8 non-readers and a reader: {st}")
        assert st["accepted"] == 9 and st["refused"] == 0 and st["clients"] == 4
        assert st["dropped"] == {"disconnected": 0, "stalled": 0, "evicted": 5, "input": 0}
        text = metrics(http)
        assert 'hdlamp_stream_clients_dropped_total{reason="evicted"} 5\n' in text
        assert "hdlamp_stream_clients_accepted_total 9\n" in text
        assert "hdlamp_stream_clients_refused_total 0\n" in text
        # the 4 left (3 non-readers and the reader) still connected: the reader gets frames
        assert read_frame(reader) is not None
        for s, _ in second:
            s.close()
        reader.close()
    finally:
        stop(p)


def test_clients_that_stop_reading_are_dropped_after_the_stall_timeout(hdlamp, lamps,
                                                                       tmp_path):
    # a regression seen before: clients that stopped reading were never dropped; they held their slots for ever
    log = hold_log(hdlamp, tmp_path, 50)
    stall_ms = 1000
    p, port, http = start(lamps, log, "--loop", "--set", "stream.max_clients=4",
                          "--set", f"stream.stall_timeout_ms={stall_ms}")
    try:
        stalled = [non_reader(port) for _ in range(4)]  # each accepted: it read a header
        wait_status(http, "the 4 that stopped reading dropped",
                    lambda st: st["stream"]["clients"] == 0)
        t_seen = now_ns()
        # none went before it had taken nothing for stall_ms: its last byte went after the
        # daemon stamped its first frame (t_sent_ns, CLOCK_MONOTONIC)
        assert t_seen >= max(h["t_sent_ns"] for _, h in stalled) + stall_ms * 1_000_000
        for s, _ in stalled:
            assert closed_by_daemon(s) in ("eof", "reset")
            s.close()
        reader, hs = read_frames(port, 25)  # a slot is free again
        st = status(http)["stream"]
        print(f"stream after 4 stalled clients and a reader: {st}")
        assert st["accepted"] == 5 and st["refused"] == 0 and st["clients"] == 1
        assert st["dropped"] == {"disconnected": 0, "stalled": 4, "evicted": 0, "input": 0}
        assert 'hdlamp_stream_clients_dropped_total{reason="stalled"} 4\n' in metrics(http)
        reader.close()
    finally:
        stop(p)


def test_a_client_sending_garbage_is_closed_and_a_reader_beside_it_misses_nothing(
        hdlamp, lamps, tmp_path):
    # a regression seen before: a client sending garbage had 2 GB read and dropped, was never closed, and the
    # stream thread's reading cost the renderer cycles (84 not rendered in 25 s). Now its
    # first byte closes it: one read. What the reader missed - frames it skipped, cycles not
    # rendered - is what a busy machine costs, counted exactly by the daemon (printed).
    log = hold_log(hdlamp, tmp_path, 250)  # 5 s of cycles
    p, port, _ = start(lamps, log, "--set", "http.listen=")
    frames, first = [], threading.Event()

    def collect():
        s = connect(port, timeout=30)
        while (f := read_frame(s)) is not None:
            frames.append(f[0])
            first.set()
        s.close()

    t = threading.Thread(target=collect)
    t.start()
    assert first.wait(LIMIT_S), "the reader got no frame"
    g = socket.create_connection(("127.0.0.1", port), timeout=10)
    junk = bytes(range(256)) * 256
    sent, ended = 0, None
    try:
        while sent < (64 << 20):  # bounded: 64 MiB
            sent += g.send(junk)
    except (BrokenPipeError, ConnectionResetError) as e:
        ended = type(e).__name__
    except socket.timeout:
        ended = "timeout"
    running = p.poll() is None
    assert ended in ("BrokenPipeError", "ConnectionResetError") and running, \
        f"the garbage client sent {sent} bytes, then {ended}; daemon running: {running}"
    g.close()
    summary = json.loads(p.communicate(timeout=60)[0].strip().splitlines()[-1])
    assert p.returncode == 0
    t.join(30)
    st = summary["stream"]
    print(f"garbage: {sent} bytes sent before {ended}; stream {st}; reader {len(frames)} "
          f"frames from {frames[0]['seq']}")
    assert st["dropped"] == {"disconnected": 0, "stalled": 0, "evicted": 0, "input": 1}
    assert st["accepted"] == 2 and st["refused"] == 0
    assert st["input_reads"] == 1  # the garbage client's first byte; the reader sent nothing
    # the reader: every frame from its first to its last but those the daemon counted as
    # skipped, and every cycle of both lamps between but those counted as not rendered or in
    # a frame it skipped
    seqs = [h["seq"] for h in frames]
    gaps = sum(b - a - 1 for a, b in zip(seqs, seqs[1:]))
    assert seqs == sorted(set(seqs)) and seqs[-1] <= summary["frames"]["published"]
    assert gaps <= st["frames_skipped"]
    for lamp in ("left", "right"):
        cycles = {h["cycle_seq_" + lamp] for h in frames} - {0}
        missing = max(cycles) - min(cycles) + 1 - len(cycles)
        not_rendered = lamp_status(summary, lamp)["cycles_not_rendered"]
        print(f"{lamp}: {len(cycles)} cycles in {len(frames)} frames, {missing} missing, "
              f"{not_rendered} not rendered, {gaps} frames skipped")
        assert missing <= not_rendered + gaps, lamp
