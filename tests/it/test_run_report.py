"""hdlampd's run report and exit code (docs/loop.md): a scenario replayed with --exit-at-end
and --report, no restbus (the host has no CAN), so the glare rule is the strict one: no frame
over a road user's limit. A held high beam glares the oncoming car of the IIHS-like straight
approach (exit 3, the verdict false); a held low beam does not (exit 0). The report's counts
must equal the daemon's own counters of the same run (its status line at exit), and /metrics
with the loop's families must pass promtool's lint."""
import json
import os
import subprocess
import time
import urllib.request

import pytest

from proc import run
from scenario import HDLAMPD, SOURCE_DIR, dbc_path
from test_verdict_live import REGS, hold_log

SCENARIO = os.path.join(SOURCE_DIR, "scenarios", "iihs-approach-straight.json")
CYCLES = 440  # 8.8 s of ECU cycles: the whole scenario (8.388 s)


@pytest.fixture(scope="module")
def lamps(hdlamp, tmp_path_factory):
    out = tmp_path_factory.mktemp("lamps")
    run(hdlamp, "model", "--out", out)
    return out


def replay(lamps, log, report, *args):
    p = subprocess.Popen(
        [HDLAMPD, "--replay", log, "--dbc", dbc_path("hd84.dbc"), "--scenario", SCENARIO,
         "--exit-at-end", "--report", str(report),
         "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
         "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
         "--set", "render.size=160x90", "--set", "stream.tcp=",
         "--set", f"verdict.regulations={REGS}", *args],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return p


def finish(p):
    out, err = p.communicate(timeout=300)
    status = json.loads(out.strip().splitlines()[-1])
    return p.returncode, status, err


def test_held_high_beam_fails_the_glare_verdict_with_exit_3(hdlamp, lamps, tmp_path):
    log = hold_log(hdlamp, tmp_path, "high", cycles=CYCLES)
    report = tmp_path / "high.json"
    p = replay(lamps, log, report, "--set", "http.listen=127.0.0.1:0")
    port = None
    while port is None:
        line = p.stderr.readline()
        assert line, "hdlampd exited early"
        if "live view on http://" in line:
            port = int(line.rsplit("(port ", 1)[1].split(")")[0])
    # a scrape once frames were judged (the main thread judges them without a restbus)
    until = time.monotonic() + 60
    while True:
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/metrics", timeout=10) as r:
            text = r.read().decode()
        if "hdlamp_loop_glare_seconds" in text or time.monotonic() > until:
            break
        time.sleep(0.2)
    with urllib.request.urlopen(f"http://127.0.0.1:{port}/status", timeout=10) as r:
        live = json.loads(r.read().decode())["loop"]
    code, status, err = finish(p)
    lint = subprocess.run(["promtool", "check", "metrics"], input=text, capture_output=True,
                          text=True)
    assert lint.returncode == 0 and not lint.stdout.strip(), lint.stdout + lint.stderr
    assert "hdlamp_loop_latency_seconds_bucket" in text
    # /status's part: the same judge, mid-run (no camera: no event, the strict rule)
    assert live["camera"] is False and live["reaction_ms"] == 60 and live["events"] == 0
    assert [a["id"] for a in live["actors"]] == ["oncoming-car"]
    assert "last_enter" not in live
    assert code == 3, err
    assert "verdict FAILED" in err
    rep = json.loads(report.read_text())
    assert rep["end"] == "replay_end" and rep["verdict"] is False
    assert rep["failed_because"] == [
        "a road user's glare over its limit after the reaction time (or, without a restbus, "
        "at all)"]
    loop = rep["loop"]
    assert loop["camera"] is False and loop["camera_cycles"] == 0 and loop["events"] == 0
    (car,) = loop["actors"]
    (glare,) = status["glare"]
    # the report's frames are the daemon's: every published frame judged, each over-limit
    # frame the one glare_live counted
    assert loop["frames_dropped"] == 0
    assert loop["frames_in"] == loop["frames_judged"] == rep["frames"]["rendered"]
    assert car["frames_over"] == glare["fail_frames"] > 0
    assert car["frames_over_unseen"] == car["frames_over"]  # no camera: never in view
    assert car["passed"] is False and car["max_lux"] > 1.0
    assert 0 < car["glare_total_s"] <= 8.388
    for lamp in ("left", "right"):
        c = rep["cycles"][lamp]
        assert c["complete"] == CYCLES
        assert c["rendered"] + c["not_rendered"] == c["complete"]
        assert c["crc_errors"] == 0 and c["lost"] == 0


def test_held_low_beam_holds_the_verdict_with_exit_0(hdlamp, lamps, tmp_path):
    log = hold_log(hdlamp, tmp_path, "low", cycles=CYCLES)
    report = tmp_path / "low.json"
    code, status, err = finish(replay(lamps, log, report, "--set", "http.listen="))
    assert code == 0, err
    rep = json.loads(report.read_text())
    assert rep["verdict"] is True and rep["failed_because"] == []
    (car,) = rep["loop"]["actors"]
    assert car["frames_over"] == 0 and car["passed"] is True
    assert status["glare"][0]["fail_frames"] == 0
    assert rep["frames"]["rendered"] == rep["loop"]["frames_judged"] > 0


def test_report_needs_a_scenario(hdlamp, lamps, tmp_path):
    log = hold_log(hdlamp, tmp_path, "low", cycles=5)
    r = subprocess.run([HDLAMPD, "--replay", log, "--dbc", dbc_path("hd84.dbc"),
                        "--report", str(tmp_path / "r.json")], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 2
    assert "loop.report needs scene.scenario" in r.stderr


def test_report_refused_without_the_renderer(hdlamp, lamps, tmp_path):
    log = hold_log(hdlamp, tmp_path, "low", cycles=5)
    r = subprocess.run([HDLAMPD, "--replay", log, "--dbc", dbc_path("hd84.dbc"), "--no-render",
                        "--scenario", SCENARIO, "--report", str(tmp_path / "r.json")],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2
    assert "judge rendered frames: not with --no-render" in r.stderr
    assert not (tmp_path / "r.json").exists()


def test_live_page_loop_panel_in_chromium(hdlamp, lamps, tmp_path):
    """The live page's Loop panel, in chromium: no entry yet (no camera), the car's line with
    its unseen frames, marked failing (no camera: the strict rule)."""
    import shutil

    from test_http_browser import BROWSER_DIR, npm_install
    for tool in ("/usr/bin/chromium", shutil.which("node"), shutil.which("npm")):
        if not tool or not os.access(tool, os.X_OK):
            pytest.fail(f"missing {tool}: tools/setup installs chromium, nodejs and npm")
    modules = npm_install()
    log = hold_log(hdlamp, tmp_path, "high", cycles=CYCLES)
    p = subprocess.Popen(
        [HDLAMPD, "--replay", log, "--loop", "--dbc", dbc_path("hd84.dbc"), "--scenario",
         SCENARIO, "--report", str(tmp_path / "r.json"),
         "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
         "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
         "--set", "render.size=160x90", "--set", "stream.tcp=",
         "--set", "http.listen=127.0.0.1:0", "--set", f"verdict.regulations={REGS}"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        port = None
        while port is None:
            line = p.stderr.readline()
            assert line, "hdlampd exited early"
            if "live view on http://" in line:
                port = int(line.rsplit("(port ", 1)[1].split(")")[0])
        r = subprocess.run(["node", os.path.join(BROWSER_DIR, "loop_panel.cjs"),
                            f"http://127.0.0.1:{port}/", str(tmp_path / "profile")],
                           env=dict(os.environ, NODE_PATH=modules), capture_output=True,
                           text=True, timeout=120)
    finally:
        p.send_signal(15)
        p.communicate(timeout=60)
    assert r.returncode == 0, r.stderr
    seen = json.loads(r.stdout.strip().splitlines()[-1])
    print(json.dumps(seen))
    assert seen["pageErrors"] == []
    assert seen["head"] == "no road user entered the camera's view yet"
    (car,) = seen["actors"]
    assert car["id"] == "oncoming-car" and car["cls"] == "bad"
    assert car["text"].startswith("oncoming-car: glared 0.00 s in view (0.00 s after 60 ms), ")
