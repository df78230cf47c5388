"""The test-only fault switch HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES (docs/service.md,
"systemd"): the render thread hangs after N frames; vm_systemd uses it against the watchdog."""
import json
import os
import signal
import subprocess
import time
import re
import urllib.request

from scenario import HDLAMPD, dbc_path
from proc import run


def args(lamps, log):
    return [HDLAMPD, "--replay", str(log), "--dbc", dbc_path("hd84.dbc"),
            "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
            "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
            "--set", "render.size=160x90", "--set", "stream.tcp=", "--set", "http.listen="]


def test_render_thread_hangs_after_n_frames(hdlamp, tmp_path):
    lamps = tmp_path / "lamps"
    run(hdlamp, "model", "--out", lamps)
    log = tmp_path / "hold.log"
    run(hdlamp, "scenario", "--dbc", dbc_path("hd84.dbc"), "--out", log, "--hold", "low",
        "--phase-cycles", "50")
    for value in ("", "0", "-3", "ten", "5x"):
        r = subprocess.run(args(lamps, log), capture_output=True, text=True, timeout=60,
                           env={**os.environ, "HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES": value})
        assert r.returncode == 2, (value, r.stderr)
        assert r.stderr.endswith(f"hdlampd: HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES '{value}': "
                                 "expected a frame count > 0\n"), r.stderr
    p = subprocess.Popen(args(lamps, log) + ["--loop", "--set", "http.listen=127.0.0.1:0"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env={**os.environ, "HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES": "7"})
    # the looped log keeps coming; the render thread stops after 7 frames: wait for them on
    # /status (a loaded machine may take seconds for the first frame), then once more
    err_lines, port = [], None
    while port is None:
        line = p.stderr.readline()
        assert line, f"hdlampd exited early: {err_lines}"
        err_lines.append(line)
        m = re.search(r"live view on http://.*\(port (\d+)\)", line)
        port = int(m.group(1)) if m else None
    deadline = time.monotonic() + 120
    while True:
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/status", timeout=60) as r:
            rendered = json.loads(r.read())["frames"]["rendered"]
        assert rendered <= 7
        if rendered == 7 or time.monotonic() > deadline:
            break
        time.sleep(0.2)
    time.sleep(1)  # a second in which the hung thread renders nothing more
    p.send_signal(signal.SIGTERM)
    out, rest = p.communicate(timeout=60)
    err = "".join(err_lines) + rest
    assert p.returncode == 0, err  # a stop still ends the hang
    status = json.loads(out.strip().splitlines()[-1])
    assert ("hdlampd: HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES=7: test-only fault: the render "
            "thread hangs after 7 frames\n") in err
    assert status["frames"]["rendered"] == 7
    assert status["lamps"][0]["cycles"] > 7  # the CAN thread ran on
