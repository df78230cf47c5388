"""hdlampd refuses a start that would do harm or silently ignore its configuration."""
import os
import signal
import socket
import subprocess

from scenario import HDLAMPD, dbc_path
from proc import run


def model(hdlamp, tmp_path):
    out = tmp_path / "lamps"
    run(hdlamp, "model", "--out", out)
    log = tmp_path / "hold.log"
    run(hdlamp, "scenario", "--dbc", dbc_path("hd84.dbc"), "--out", log, "--hold", "low",
        "--phase-cycles", "2")
    return out, log


def daemon(lamps, log, *args):
    return [HDLAMPD, "--replay", str(log), "--dbc", dbc_path("hd84.dbc"),
            "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
            "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
            "--set", "render.size=160x90", "--set", "stream.tcp=", "--set", "http.listen=",
            *args]


def test_config_that_is_a_directory_is_refused(tmp_path):
    r = subprocess.run([HDLAMPD, "--config", str(tmp_path)], capture_output=True, text=True,
                       timeout=30)
    assert r.returncode == 2
    assert r.stderr == f"hdlampd: '{tmp_path}': a directory; expected an INI file\n"


def test_stream_unix_never_deletes_what_is_not_a_stale_socket(hdlamp, tmp_path):
    lamps, log = model(hdlamp, tmp_path)
    # a regular file: refused, kept as it was
    f = tmp_path / "precious"
    f.write_text("keep me\n")
    r = subprocess.run(daemon(lamps, log, "--set", f"stream.unix={f}"), capture_output=True,
                       text=True, timeout=60)
    assert r.returncode != 0
    assert f"stream.unix '{f}': exists and is not a socket; refusing to replace it" in r.stderr
    assert f.read_text() == "keep me\n"
    # a directory: the same
    d = tmp_path / "dir"
    d.mkdir()
    r = subprocess.run(daemon(lamps, log, "--set", f"stream.unix={d}"), capture_output=True,
                       text=True, timeout=60)
    assert r.returncode != 0 and "is not a socket" in r.stderr and d.is_dir()
    # a socket another process listens on: refused, that listener untouched
    live = tmp_path / "live.sock"
    other = socket.socket(socket.AF_UNIX)
    other.bind(str(live))
    other.listen(1)
    try:
        r = subprocess.run(daemon(lamps, log, "--set", f"stream.unix={live}"),
                           capture_output=True, text=True, timeout=60)
        assert r.returncode != 0
        assert f"stream.unix '{live}': another process listens on it" in r.stderr
        c = socket.socket(socket.AF_UNIX)
        c.connect(str(live))  # still the other process's socket
        c.close()
    finally:
        other.close()


def test_stream_unix_replaces_a_stale_socket(hdlamp, tmp_path):
    lamps, log = model(hdlamp, tmp_path)
    stale = tmp_path / "stale.sock"
    s = socket.socket(socket.AF_UNIX)
    s.bind(str(stale))
    s.close()  # the file stays, nobody listens: what a crashed run leaves
    assert stale.is_socket()
    p = subprocess.Popen(daemon(lamps, log, "--set", f"stream.unix={stale}", "--loop"),
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        lines = []
        while True:
            line = p.stderr.readline()
            assert line, f"hdlampd exited early: {lines}"
            lines.append(line)
            if line.startswith("hdlampd: frame stream on") and str(stale) in line:
                break
        c = socket.socket(socket.AF_UNIX)
        c.connect(str(stale))  # the daemon's socket now
        c.close()
    finally:
        p.send_signal(signal.SIGINT)
        p.communicate(timeout=30)
    assert p.returncode == 0
    assert not os.path.exists(stale)  # removed at exit
