"""hdlampd's live verdicts (docs/live-verdicts.md, "Verdicts"): the shipped regulation sets checked on
every rendered frame of a replayed log, reported in /metrics, /status, the stream header and
captures; a set that is not there stops the start."""
import json
import math
import os
import re
import signal
import subprocess
import threading
import time
import urllib.request

import pytest

from proc import run
from scenario import HDLAMPD, SOURCE_DIR, dbc_path, generate
from streamclient import connect, read_frame
from test_metrics import parse

REGS = os.path.join(SOURCE_DIR, "regulations")
ADB = "unece-r149-01-adb-glare"
DRIVING = "unece-r149-01-driving-b"
SETS = f"{ADB},{DRIVING}"
ONCOMING = f'set="{ADB}",id="Oncoming 50 m",lamp="pair"'


@pytest.fixture(scope="module")
def lamps(hdlamp, tmp_path_factory):
    out = tmp_path_factory.mktemp("lamps")
    run(hdlamp, "model", "--out", out)
    return out


def hold_log(hdlamp, out_dir, preset, cycles=25, dbc=dbc_path("hd84.dbc"), mode=None):
    """A log of the ECU sending one HD84 preset for every cycle (hdlamp scenario --hold), and
    with mode its HdlBeamMode signal set to that VAL_ name."""
    log = os.path.join(out_dir, f"{preset}-{mode}.log")
    run(hdlamp, "scenario", "--dbc", dbc, "--out", log, "--hold", preset, "--phase-cycles",
        cycles, *(["--mode", mode] if mode else []))
    return log


class Daemon:
    """hdlampd replaying a log in a loop, with the stream and HTTP on free ports."""

    def __init__(self, lamps, log, *args, sets=SETS, dbc=dbc_path("hd84.dbc")):
        cmd = [HDLAMPD, "--replay", log, "--loop", "--dbc", dbc,
               "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
               "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
               "--set", "render.size=160x90", "--set", "stream.tcp=127.0.0.1:0",
               "--set", "http.listen=127.0.0.1:0", "--set", f"verdict.sets={sets}",
               "--set", f"verdict.regulations={REGS}", *map(str, args)]
        self.p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.log, self.stream_port, self.http_port = [], None, None
        while self.stream_port is None or self.http_port is None:
            line = self.p.stderr.readline()
            assert line, f"hdlampd exited early: {self.log}"
            self.log.append(line)
            m = re.search(r"frame stream on .*\(port (\d+)\)", line)
            if m:
                self.stream_port = int(m.group(1))
            m = re.search(r"live view on http://.*\(port (\d+)\)", line)
            if m:
                self.http_port = int(m.group(1))
        threading.Thread(target=lambda: self.log.extend(self.p.stderr), daemon=True).start()

    def get(self, path, method="GET"):
        req = urllib.request.Request(f"http://127.0.0.1:{self.http_port}{path}", method=method)
        with urllib.request.urlopen(req, timeout=10) as r:
            return r.read().decode()

    def metrics(self):
        return {name: {labels: value for _, labels, value in fam["samples"]}
                for name, fam in parse(self.get("/metrics")).items()}

    def wait_frames(self, n, timeout=60):
        """/metrics once the set was evaluated on n frames (an event, not a duration)."""
        until = time.monotonic() + timeout
        while True:
            m = self.metrics()
            if m.get("hdlamp_verdict_frames_total", {}).get(f'set="{ADB}"', 0) >= n:
                return m
            assert time.monotonic() < until, "the verdicts did not count frames"
            time.sleep(0.1)

    def stop(self):
        self.p.send_signal(signal.SIGTERM)
        out, _ = self.p.communicate(timeout=20)
        assert self.p.returncode == 0, self.log
        return json.loads(out.strip().splitlines()[-1])


def stream_headers(port, n):
    s = connect(port)
    hs = []
    while len(hs) < n:
        f = read_frame(s)
        assert f is not None, "the stream ended"
        hs.append(f[0])
    s.close()
    return hs


def set_status(status, set_id):
    return next(s for s in status["verdicts"]["sets"] if s["id"] == set_id)


def requirement(part, req_id):
    return next(r for r in part["requirements"] if r["id"] == req_id)


@pytest.mark.parametrize("preset", ["glarefree", "high"])
def test_glarefree_passes_the_oncoming_window_that_high_beam_glares_into(hdlamp, lamps, tmp_path,
                                                                        preset):
    log = hold_log(hdlamp, str(tmp_path), preset)
    d = Daemon(lamps, log, "--set", "http.capture=true", "--set",
               f"capture.dir={tmp_path}/captures")
    try:
        hs = stream_headers(d.stream_port, 10)
        m = d.wait_frames(30)
        status = json.loads(d.get("/status"))
        capture = json.loads(d.get("/capture", method="POST"))["path"]
        page = d.get("/")
    finally:
        summary = d.stop()

    # /metrics: the 50 m oncoming window of the ADB glare table (half the pair's sum)
    margin = m["hdlamp_requirement_margin"][ONCOMING]
    if preset == "glarefree":
        assert margin > 0  # the preset keeps H -6..-2 dark: passes
    else:
        assert margin < 0  # the plain high beam glares into it: fails
    # every frame holds the same beam, except frames with a lamp in its fail-safe (dark until
    # its first cycle): a set that passes fails on those frames at most, one that fails on
    # all the others at least (the exit status line: every count from one moment)
    frames = m["hdlamp_verdict_frames_total"]
    assert frames[f'set="{ADB}"'] == frames[f'set="{DRIVING}"'] >= 30
    failsafe = sum(l["failsafe_frames"] for l in summary["lamps"])
    want_failed = 0
    for i, s in enumerate((ADB, DRIVING)):
        lamps_of = ["pair"] if s == ADB else ["left", "right"]
        passes = [m["hdlamp_verdict_pass"][f'set="{s}",lamp="{l}"'] for l in lamps_of]
        assert set(passes) <= {0, 1}
        st = set_status(summary, s)
        assert st["frames"] == summary["frames"]["published"]
        if all(passes):
            assert st["failed_frames"] <= failsafe, s
        else:
            assert st["failed_frames"] >= st["frames"] - failsafe, s
            want_failed |= 1 << i
    # the ADB set has 8 requirements, the driving set 11 on each lamp: one margin each
    assert len([k for k in m["hdlamp_requirement_margin"] if f'set="{ADB}"' in k]) == 8
    assert len([k for k in m["hdlamp_requirement_margin"] if f'set="{DRIVING}"' in k]) == 22

    # /status: the same values, with the limits and where the deciding value is
    adb = set_status(status, ADB)
    assert adb["applies"] == "pair_half" and adb["evaluated"] is True
    assert [p["lamp"] for p in adb["results"]] == ["pair"]
    r = requirement(adb["results"][0], "Oncoming 50 m")
    assert r["kind"] == "segment" and r["max_cd"] == 625 and r["min_cd"] is None
    assert math.isclose(r["margin"], margin, rel_tol=1e-6)
    assert r["pass"] == (preset == "glarefree")
    assert math.isclose(r["margin"], (625 - r["value_cd"]) / 625, rel_tol=1e-6)
    assert -4.8 - 1e-6 <= r["at_h_deg"] <= -2.0 + 1e-6 and math.isclose(r["at_v_deg"], 0.57,
                                                                        abs_tol=1e-6)
    drv = set_status(status, DRIVING)
    assert [p["lamp"] for p in drv["results"]] == ["left", "right"]
    assert len(drv["results"][0]["requirements"]) == 11

    # the stream header: two sets, both evaluated, the failed ones as /metrics says (frames
    # without a fail-safe)
    hs = [h for h in hs if not h["flags"]]
    assert hs
    for h in hs:
        assert (h["n_sets"], h["sets_evaluated"], h["sets_failed"]) == (2, 0b11, want_failed), h
    # road KPIs: in the header, /status and /metrics alike (the same beam in every frame)
    road = status["road"]
    assert road["levels_lx"] == [1, 3] and road["width_at_m"] == [25, 50]
    h = hs[-1]
    assert [h["centre_range_1_m"], h["centre_range_2_m"]] == pytest.approx(
        road["centre_range_m"], rel=1e-6)
    assert [h["edge_range_1_m"], h["edge_range_2_m"]] == pytest.approx(road["edge_range_m"],
                                                                       rel=1e-6)
    assert [h["width_1_m"], h["width_2_m"]] == pytest.approx(road["width_m"], rel=1e-6)
    assert road["centre_range_m"][0] > road["centre_range_m"][1] > 0
    rng = m["hdlamp_road_range_meters"]
    assert rng['line="centre",level_lx="1"'] == pytest.approx(road["centre_range_m"][0], rel=1e-6)
    assert rng['line="edge",level_lx="3"'] == pytest.approx(road["edge_range_m"][1], rel=1e-6)
    assert m["hdlamp_road_width_meters"]['at_m="25"'] == pytest.approx(road["width_m"][0],
                                                                       rel=1e-6)

    # the capture: verdict.json beside the EXR files, and the same text in hdr.exr
    with open(os.path.join(capture, "verdict.json")) as f:
        cap = json.load(f)
    r = requirement(set_status(cap, ADB)["results"][0], "Oncoming 50 m")
    assert (r["margin"] > 0) == (preset == "glarefree")
    hdr = run("exrheader", os.path.join(capture, "hdr.exr")).stdout
    assert "hdlamp:verdict (type string)" in hdr and '"Oncoming 50 m"' in hdr

    # the live page has the panel that lists the sets from /status
    assert '<div id="verdicts">' in page and "showVerdicts(status.verdicts)" in page

    # the exit status line carries the counts
    assert set_status(summary, ADB)["frames"] >= frames[f'set="{ADB}"']
    # the ADB table's other rows fail both: so far FAIL, whatever the newest frame says
    assert set_status(summary, ADB)["so_far"]["result"] == "FAIL"


def test_drive_scenario_fails_the_glare_table_in_its_high_beam_phase(hdlamp, lamps, tmp_path):
    # the drive: low beam, high beam, the glare-free window sweeping, bends, faults, low beam
    log, _, _ = generate(hdlamp, dbc_path("hd84.dbc"), str(tmp_path), phase=5)
    d = Daemon(lamps, log, sets=ADB)
    try:
        until = time.monotonic() + 60
        while True:
            m = d.metrics()
            if m["hdlamp_verdict_failed_frames_total"][f'set="{ADB}"'] > 0 and \
                    m["hdlamp_verdict_frames_total"][f'set="{ADB}"'] > 60:
                break
            assert time.monotonic() < until, m
            time.sleep(0.1)
        hs = stream_headers(d.stream_port, 40)
    finally:
        summary = d.stop()
    assert m["hdlamp_verdict_frames_total"][f'set="{ADB}"'] <= m["hdlamp_frames_total"][""]
    assert m["hdlamp_verdict_pass"][f'set="{ADB}",lamp="pair"'] in (0, 1)
    assert f'set="{ADB}",id="Oncoming 50 m",lamp="pair"' in m["hdlamp_requirement_margin"]
    # one set, evaluated on every frame; whether it failed is in bit 0
    assert all(h["n_sets"] == 1 and h["sets_evaluated"] == 1 and h["sets_failed"] in (0, 1)
               for h in hs)
    s = set_status(summary, ADB)
    assert s["frames"] == summary["frames"]["published"]
    assert 0 < s["failed_frames"] <= s["frames"]


def test_unknown_set_stops_the_start_naming_it(hdlamp, lamps, tmp_path):
    log = hold_log(hdlamp, str(tmp_path), "low", cycles=2)
    r = subprocess.run([HDLAMPD, "--replay", log, "--dbc", dbc_path("hd84.dbc"),
                        "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
                        "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
                        "--set", "render.size=160x90", "--set", "stream.tcp=",
                        "--set", "http.listen=", "--set", f"verdict.sets={ADB},no-such-set",
                        "--set", f"verdict.regulations={REGS}"],
                       capture_output=True, text=True, timeout=30)
    assert r.returncode == 2, r.stderr
    assert f"hdlampd: verdict.sets: no set 'no-such-set' in '{REGS}' (no file " \
           f"'{REGS}/no-such-set.json'; verdict.regulations names the directory)\n" in r.stderr


MODE_DBC = os.path.join(SOURCE_DIR, "tests", "data", "dbc", "hd84_fd_beam_mode.dbc")


@pytest.mark.parametrize("preset,mode,evaluated", [("high", "high", 0b10),
                                                   ("glarefree", "glarefree", 0b01),
                                                   ("low", "low", 0b00)])
def test_beam_mode_signal_picks_the_sets(hdlamp, lamps, tmp_path, preset, mode, evaluated):
    # hd84_fd.dbc with HL_Mode_L/R (SG_ attribute HdlBeamMode, VAL_ 0 low, 1 high, 2 glarefree):
    # in each cycle only the mode's sets are evaluated, the others are reported as not
    log = hold_log(hdlamp, str(tmp_path), preset, dbc=MODE_DBC, mode=mode)
    d = Daemon(lamps, log, "--set", f"verdict.modes=high:{DRIVING},glarefree:{ADB}",
               dbc=MODE_DBC)
    try:
        hs = stream_headers(d.stream_port, 15)
        status = json.loads(d.get("/status"))
        m = d.metrics()
    finally:
        d.stop()
    assert any("beam mode from signal HL_Mode_L of lamp 'left'" in l for l in d.log)
    # frames of a cycle (no fail-safe; before the first cycle the mode is unknown: every set)
    hs = [h for h in hs if not h["flags"]]
    assert hs and all(h["n_sets"] == 2 and h["sets_evaluated"] == evaluated for h in hs), hs
    assert all(h["sets_failed"] & ~evaluated == 0 for h in hs)
    v = status["verdicts"]
    assert v["mode"] == mode
    for i, s in enumerate((ADB, DRIVING)):
        st = set_status(status, s)
        assert st["evaluated"] is bool(evaluated & (1 << i)), s
        assert (st["results"] != []) is st["evaluated"]
        if not st["evaluated"]:
            assert st["now"]["result"] == "not applicable", st
    # /metrics: the gauges of the evaluated sets only
    passes = m.get("hdlamp_verdict_pass", {})
    assert (f'set="{ADB}",lamp="pair"' in passes) is bool(evaluated & 1)
    assert (f'set="{DRIVING}",lamp="left"' in passes) is bool(evaluated & 2)
    if mode == "glarefree":
        assert m["hdlamp_requirement_margin"][ONCOMING] > 0
