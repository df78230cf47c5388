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
