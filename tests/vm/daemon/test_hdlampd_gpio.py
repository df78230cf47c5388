"""hdlampd with a gpio-sim chip (tests/vm/run --gpio-sim): the frame strobe toggles once per
published frame, a trigger edge writes a capture, ECU-enable is held while the daemon runs."""
import json
import os
import re
import signal
import subprocess
import time

import pytest

from proc import run
from scenario import HDLAMPD, dbc_path, generate


def sim(offset, attr):
    return os.path.join(os.environ["HL_GPIO_SIM"], f"sim_gpio{offset}", attr)


def read(path):
    with open(path) as f:
        return f.read().strip()


@pytest.mark.skipif("HL_GPIO_CHIP" not in os.environ, reason="needs tests/vm/run --gpio-sim")
def test_strobe_per_frame_and_trigger_capture(hdlamp, tmp_path):
    chip = os.environ["HL_GPIO_CHIP"]
    run(hdlamp, "model", "--out", tmp_path)
    log, _, _ = generate(hdlamp, dbc_path("hd84.dbc"), str(tmp_path), phase=4)
    cap = tmp_path / "captures"
    with open(sim(3, "pull"), "w") as f:  # hl-in0, the trigger: idle low
        f.write("pull-down")
    p = subprocess.Popen([HDLAMPD, "--replay", log, "--loop", "--dbc", dbc_path("hd84.dbc"),
                          "--set", f"lamps.left={tmp_path}/hd84_left.lid.exr",
                          "--set", f"lamps.right={tmp_path}/hd84_right.lid.exr",
                          "--set", "render.size=64x36", "--set", "render.combine=cpu",
                          "--set", "render.headlight=cpu", "--set", "stream.tcp=",
                          "--set", "http.listen=", "--set", f"capture.dir={cap}",
                          "--set", f"gpio.chip={chip}", "--set", "gpio.strobe=hl-strobe",
                          "--set", "gpio.trigger=hl-in0", "--set", "gpio.ecu_enable=hl-ready"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # frames start once the renderer is up (slow in this VM): wait for its log line
    while "renderer:" not in (line := p.stderr.readline()):
        assert line, "hdlampd exited early"
    time.sleep(1.0)
    assert p.poll() is None
    assert read(sim(1, "value")) == "1"  # ECU-enable held while running
    # watch the strobe line from outside until it changed 10 times with the frames (an event;
    # the limit is for a line that never moves, not a speed)
    levels, t_end, seen = [], time.monotonic() + 60, 0
    while seen < 10 and time.monotonic() < t_end:
        levels.append(read(sim(0, "value")))
        seen += len(levels) > 1 and levels[-1] != levels[-2]
        time.sleep(0.002)
    with open(sim(3, "pull"), "w") as f:  # a rising edge on the trigger
        f.write("pull-up")
    time.sleep(3)
    p.send_signal(signal.SIGTERM)
    out, err = p.communicate(timeout=60)
    assert p.returncode == 0, err
    status = json.loads(out.strip().splitlines()[-1])
    g = status["gpio"]
    print(f"frames published {status['frames']['published']}, strobe toggles "
          f"{g['strobe_toggles']}, trigger edges {g['trigger_edges']}")
    assert g["strobe_toggles"] == status["frames"]["published"]
    assert g["strobe_errors"] == 0
    print(f"strobe changes seen on the line: {seen}")
    assert 10 <= seen <= g["strobe_toggles"]
    assert read(sim(1, "value")) == "0"  # released at exit
    assert g["trigger_edges"] == 1 and status["captures"] == 1
    (d,) = list(cap.iterdir())
    hdr = run("exrheader", d / "hdr.exr").stdout
    assert re.search(r"^\s+R, 16-bit floating-point", hdr, re.M)
    assert "hdlamp:frameSeq" in hdr
    info = run(hdlamp, "lid", "info", d / "right.lid.exr").stdout
    assert "combined distribution (channel I)" in info
