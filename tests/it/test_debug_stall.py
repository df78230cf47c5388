"""The test-only fault switch HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES (docs/daemon.md,
"systemd"): the render thread hangs after N frames; vm_systemd uses it against the watchdog."""
import json
import os
import signal
import subprocess
import time

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
    p = subprocess.Popen(args(lamps, log) + ["--loop"], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True,
                         env={**os.environ, "HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES": "7"})
    time.sleep(3)  # the looped log keeps coming; 7 frames are rendered
    p.send_signal(signal.SIGTERM)
    out, err = p.communicate(timeout=60)
    assert p.returncode == 0, err  # a stop still ends the hang
    status = json.loads(out.strip().splitlines()[-1])
    assert ("hdlampd: HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES=7: test-only fault: the render "
            "thread hangs after 7 frames\n") in err
    assert status["frames"]["rendered"] == 7
    assert status["lamps"][0]["cycles"] > 7  # the CAN thread ran on
