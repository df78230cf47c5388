"""Helpers shared by the tests that run inside the VM."""

import json
import os
import queue
import subprocess
import sys
import threading

HERE = os.path.dirname(os.path.abspath(__file__))


def sh(*args, timeout=60):
    """Run a command; its stdout, or a test failure naming the command and its stderr."""
    r = subprocess.run(args, capture_output=True, text=True, timeout=timeout)
    assert r.returncode == 0, f"{' '.join(args)}: exit {r.returncode}: {r.stderr.strip()}"
    return r.stdout


def peer(*args):
    """Start tests/vm/inside/can_peer.py as its own process (stdout: JSON lines)."""
    return subprocess.Popen([sys.executable, os.path.join(HERE, "can_peer.py"), *args],
                            stdout=subprocess.PIPE, text=True)


class Lines:
    """The lines a process prints (JSON, or text with parse=str), read by a thread so that
    waits can time out."""

    def __init__(self, proc, parse=json.loads):
        self.proc = proc
        self.parse = parse
        self.q = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for line in self.proc.stdout:
            self.q.put(line.rstrip("\n"))
        self.q.put(None)

    def next(self, timeout=60):
        try:
            line = self.q.get(timeout=timeout)
        except queue.Empty:
            raise AssertionError(f"{self.proc.args[0]} printed nothing for {timeout} s") from None
        assert line is not None, f"{self.proc.args[0]} exited ({self.proc.wait()}) early"
        return line if line == "ready" else self.parse(line)


def replay_can(path, fd=False, channel="vcan0", long_gap_s=0.05):
    """python-can sends a log onto a CAN interface with its original timing, but this slow VM
    (TCG, on a machine that may be busy) can fall behind: a sender that catches up would eat
    into the log's silences and a 300 ms silence could reach the daemon as 80 ms, which is no
    silence at all. So every gap of at least long_gap_s in the log is kept whole, counted from
    the frame actually sent before it; the shorter gaps follow the log's schedule as far as the
    sender keeps up. The log is read first: parsing while sending cannot keep up here.
    Returns how late the sender was (ms, median and max) against that schedule."""
    import time

    import can

    msgs = list(can.LogReader(path))
    late_ms = []
    with can.Bus(interface="socketcan", channel=channel, fd=fd) as bus:
        t_base = time.monotonic() - msgs[0].timestamp  # schedule: t_base + msg.timestamp
        prev = None
        for msg in msgs:
            if prev is not None and msg.timestamp - prev.timestamp >= long_gap_s:
                # re-anchor on the previous frame's real send time: the silence stays whole
                t_base = max(t_base, t_sent - prev.timestamp)
            due = t_base + msg.timestamp
            now = time.monotonic()
            if due > now:
                time.sleep(due - now)
            bus.send(msg)
            t_sent = time.monotonic()
            late_ms.append((t_sent - due) * 1e3)
            prev = msg
    late_ms.sort()
    return late_ms[len(late_ms) // 2], late_ms[-1]
