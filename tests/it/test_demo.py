"""tools/demo's closed loop (README, docs/sil.md "The demo") on its live page in chromium: the
daemon started by tools/demo-loop exactly as tools/demo starts it (the reference ECU in process
on the virtual bus, no CAN interface; only the ports differ), the page read when the oncoming
car is in the camera's view and masked, its screenshot kept as live-sil.png in the build tree
(and at HL_SIL_SCREENSHOT when set: docs/sil/live-sil.png is made that way)."""
import json
import os
import re
import shutil
import signal
import socket
import subprocess

import pytest

from proc import run
from scenario import HDLAMPD, SOURCE_DIR
from pngread import read_png
from test_http_browser import BROWSER_DIR, build_dir, npm_install

DEMO_LOOP = os.path.join(SOURCE_DIR, "tools", "demo-loop")


def free_port():
    """A port free now: every pass of the loop is a new hdlampd, so the port must be fixed."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_demo_page_shows_the_car_masked_with_glare_and_loop_panels(hdlamp, tmp_path):
    for tool in ("/usr/bin/chromium", shutil.which("node"), shutil.which("npm")):
        if not tool or not os.access(tool, os.X_OK):
            pytest.fail(f"missing {tool}: tools/setup installs chromium, nodejs and npm")
    modules = npm_install()
    run(hdlamp, "model", "--out", tmp_path)
    port = free_port()
    p = subprocess.Popen(
        [DEMO_LOOP, str(tmp_path), "--set", "stream.tcp=", "--set", f"http.listen=127.0.0.1:{port}",
         "--set", f"capture.dir={tmp_path}/captures"],
        env=dict(os.environ, HDLAMPD=HDLAMPD), stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE, text=True)
    shot = os.path.join(build_dir(), "live-sil.png")
    if os.path.exists(shot):
        os.unlink(shot)
    try:
        lines = []
        while not lines or "live view on http://" not in lines[-1]:
            lines.append(p.stderr.readline())
            assert lines[-1], f"demo-loop ended early: {''.join(lines)}"
        r = subprocess.run(["node", os.path.join(BROWSER_DIR, "demo_page.cjs"),
                            f"http://127.0.0.1:{port}/", shot, str(tmp_path / "chromium")],
                           env=dict(os.environ, NODE_PATH=modules), capture_output=True,
                           text=True, timeout=240)
    finally:
        p.send_signal(signal.SIGTERM)
        _, err = p.communicate(timeout=60)
        err = "".join(lines) + err
    assert r.returncode == 0, r.stderr + err
    assert p.returncode == 0, err
    assert "ecu 'reference' in process on the virtual bus vbus0" in err
    seen = json.loads(r.stdout.strip().splitlines()[-1])
    print(json.dumps(seen, indent=1))
    assert seen["pageErrors"] == []
    # the glare table: the car's row, its distance in the window the page was read in, passing
    (row,) = seen["glareRows"]
    assert row["actor"] == "oncoming-car" and row["cells"][0] == "oncoming-car (oncoming)", row
    assert 50 <= float(row["cells"][1]) <= 110, row
    # the limit of its distance band (UN R149 ADB glare table), the eye under it
    assert re.fullmatch(r"[1-9][0-9,]*", row["cells"][4]) and row["cells"][5] == "pass", row
    assert seen["scene"].startswith("IIHS-like approach on a straight") and "(clock)" in seen["scene"]
    # the loop panel: the car's entry at the camera's 250 m with its three latencies
    m = re.fullmatch(r"oncoming-car entered at (\d+\.\d\d) s: input (\d+\.\d) ms, "
                     r"mask (\d+\.\d) ms, frame (\d+\.\d) ms", seen["loopHead"])
    assert m, seen["loopHead"]
    t_enter, lat_in, lat_mask, lat_frame = map(float, m.groups())
    assert 1.0 <= t_enter <= 2.0 and 0 <= lat_in <= lat_mask <= lat_frame, m.groups()
    (car,) = seen["loopActors"]
    assert car["id"] == "oncoming-car" and car["text"].startswith("oncoming-car: glared "), car
    # /status at the same instant says the same
    e = seen["status"]["last_enter"]
    assert e["actor"] == "oncoming-car" and e["masked"] is True
    assert abs(e["latency_ms"]["mask"] - lat_mask) <= 0.05
    # the screenshot: the page 1280 wide down to the loop panel, a lit picture in it
    w, h, ch, rows = read_png(shot)
    assert w == 1280 and 800 < h <= 1100, (w, h)
    assert seen["image"]["mean"] > 10 and seen["image"]["stddev"] > 5, seen["image"]
    dest = os.environ.get("HL_SIL_SCREENSHOT")
    if dest:
        shutil.copy(shot, dest)
