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

    def __init__(self, lamps, log, *args, sets=SETS, dbc=dbc_path("hd84.dbc"), loop=True):
        cmd = [HDLAMPD, "--replay", log, *(["--loop"] if loop else []), "--dbc", dbc,
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
            self._line(line)
            m = re.search(r"frame stream on .*\(port (\d+)\)", line)
            if m:
                self.stream_port = int(m.group(1))
            m = re.search(r"live view on http://.*\(port (\d+)\)", line)
            if m:
                self.http_port = int(m.group(1))
        threading.Thread(target=lambda: self.log.extend(self.p.stderr), daemon=True).start()

    def _line(self, line):
        """Each line of the start-up (a subclass acts on one)."""

    def get(self, path, method="GET"):
        req = urllib.request.Request(f"http://127.0.0.1:{self.http_port}{path}", method=method)
        with urllib.request.urlopen(req, timeout=10) as r:
            return r.read().decode()

    def metrics(self):
        return {name: {labels: value for _, labels, value in fam["samples"]}
                for name, fam in parse(self.get("/metrics")).items()}

    def wait_frames(self, n, timeout=60):
        """/metrics once n frames were published (an event, not a duration)."""
        until = time.monotonic() + timeout
        while True:
            m = self.metrics()
            if m.get("hdlamp_frames_total", {}).get("", 0) >= n:
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
    # mode "unset": the ECU does not say its beam, so both sets are checked on every frame
    # (a said mode would pick the set of its beam: test_default_modes_*)
    log = hold_log(hdlamp, str(tmp_path), preset, mode="unset")
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
    # the ADB glare table in every beam mode the drive says, not only in its own (glarefree)
    d = Daemon(lamps, log, "--set",
               f"verdict.modes=unset:{ADB},low:{ADB},high:{ADB},glarefree:{ADB}", sets=ADB)
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


# ---- the beam mode of the shipped databases picks the sets (docs/live-verdicts.md, "Beam modes")

PASSING = "unece-r149-01-passing-c"
MODE_SETS = f"{PASSING},{DRIVING}"  # bit 0 passing, bit 1 driving
PHASE = 5


def drive_log(hdlamp, dbc, out_dir):
    """hdlamp scenario's HD84 drive (N low, N high, 2N glare-free, N bend left, N bend right,
    the faults, N low) after 2 s in which only a frame of another ID is on the bus, so that a
    stream client connects before the first cycle, and before 3 s more of that frame alone (the
    lamps time out: their fail-safe frames, then nothing until the replay's last frame). Returns the log and the beam mode names of
    the left lamp's complete cycles in order (decoded from the log; the CRC fault makes the
    first cycle of the fault section incomplete), or None per cycle for a DBC without modes."""
    drive = os.path.join(out_dir, "drive.log")
    run(hdlamp, "scenario", "--dbc", dbc, "--out", drive, "--phase-cycles", PHASE,
        "--start", "1700000002")
    log = os.path.join(out_dir, "quiet-then-drive.log")
    with open(drive) as d:
        text = d.read()
    t_end = float(text.splitlines()[-1].split(")")[0][1:])
    with open(log, "w") as f:
        f.write(f"(1700000000.000000) can0 7FF#00\n{text}({t_end + 3:.6f}) can0 7FF#00\n")
    names = {}
    modes = []
    for line in run(hdlamp, "dbc", "decode", "--dbc", dbc, drive).stdout.splitlines():
        fr = json.loads(line)
        # the frame of each cycle that carries the mode: page 11, frame B
        if (fr["name"] == "HL_Dim_L" and fr["signals"]["HL_Page_L"] == 11 or
                fr["name"] == "HL_DimB_L") and fr["e2e"] != "crc":
            modes.append(fr["signals"].get("HL_Mode_L"))
    if "HL_Mode_L" in open(dbc).read():
        names = dict(re.findall(r'(\d+) "(\w+)"', re.search(r"VAL_ \d+ HL_Mode_L (.*);",
                                                           open(dbc).read()).group(1)))
    modes = [names.get(str(m)) if m is not None else None for m in modes]
    n = PHASE
    assert len(modes) == 7 * n + 6
    del modes[6 * n]  # the CRC error: that cycle of the left lamp never completes
    return log, modes


def frames_seen(d, n_cycles):
    """The frame headers the stream client gets, from before the first cycle to the end of the
    replay (without --loop the daemon then exits; a slow client may be skipped frames, which the
    stream never waits for), and /status once both lamps timed out after the left lamp's last
    cycle."""
    s = connect(d.stream_port)
    hs = []
    status = None
    while True:
        f = read_frame(s)
        if f is None:
            break
        hs.append(f[0])
        if status is None and hs[-1]["cycle_seq_left"] == n_cycles and \
                hs[-1]["flags"] & 0b1010 == 0b1010:
            status = json.loads(d.get("/status"))
    s.close()
    assert status is not None, hs[-3:]
    return hs, status


def run_drive(lamps, log, modes, *args, dbc):
    """The drive replayed once with the passing and driving sets: the frame headers the stream
    client got, /status and the exit status line."""
    d = Daemon(lamps, log, "--set", "render.size=32x18", *args, sets=MODE_SETS, dbc=dbc,
               loop=False)
    try:
        hs, status = frames_seen(d, len(modes))
    finally:
        summary = d.stop()
    assert summary["frames"]["not_published"] == 0
    return hs, status, summary


def mode_of(h, modes):
    """The frame's beam mode name as the daemon takes it: its left lamp's newest cycle (also in
    the fail-safe, which holds it), None before the lamp's first cycle."""
    return modes[h["cycle_seq_left"] - 1] if h["cycle_seq_left"] else None


def recorded(summary, sid):
    """The daemon's own record of every frame for set sid (docs/verdicts.md, "Now and so far":
    the strip holds the last 3000 frames, this whole drive): each frame's cell and beam mode."""
    strip = set_status(summary, sid)["strip"]
    modes = []
    for first, count, mode in strip["modes"]:
        assert first == len(modes)
        modes += [mode] * count
    assert len(modes) == len(strip["cells"])
    return strip["cells"], modes


def check_counts(hs, summary, want_mask):
    """Every frame the daemon published, from its own record: a set was evaluated on it exactly
    when want_mask(its beam mode) says, and the exit line's per-set counts are those sums. The
    frames the stream client got agree: their header's mask, and the mode their left lamp's
    cycle had in the log. Returns the counts and the modes of every frame."""
    n = summary["frames"]["published"]
    counts = []
    for i, sid in enumerate((PASSING, DRIVING)):
        cells, modes = recorded(summary, sid)
        assert len(cells) == n == set_status(summary, sid)["so_far"]["frames"], (len(cells), n)
        for k in range(n):
            assert (cells[k] != "n") == bool(want_mask(modes[k]) & (1 << i)), (sid, k, modes[k])
        counts.append(sum(1 for m in modes if want_mask(m) & (1 << i)))
        assert set_status(summary, sid)["frames"] == counts[-1], sid
        for h in hs:
            assert (cells[h["seq"] - 1] != "n") == bool(h["sets_evaluated"] & (1 << i)), h
    assert len(hs) >= n // 2, (len(hs), n)  # most frames reached the client
    for h in hs:
        assert h["n_sets"] == 2 and h["sets_evaluated"] == want_mask(modes[h["seq"] - 1]), h
    return counts, modes


def test_default_modes_check_each_set_in_its_beam(hdlamp, lamps, tmp_path):
    # the shipped hd84.dbc (HL_Mode_L: 0 unset, 1 low, 2 high, 3 glarefree), verdict.modes
    # empty: the passing set on low-beam and bend frames, the driving set on high-beam frames,
    # neither on glare-free frames (no ADB set configured); every set without a mode
    dbc = dbc_path("hd84.dbc")
    log, modes = drive_log(hdlamp, dbc, str(tmp_path))
    n = PHASE
    assert modes == ["low"] * n + ["high"] * n + ["glarefree"] * 2 * n + ["low"] * (2 * n + 5 + n)
    hs, status, summary = run_drive(lamps, log, modes, dbc=dbc)
    masks = {None: 0b11, "low": 0b01, "high": 0b10, "glarefree": 0b00}
    (passing, driving), seen = check_counts(hs, summary, lambda m: masks[m])
    # the frames' modes as the log has them, in order (a frame may show several cycles)
    for h in hs:
        assert seen[h["seq"] - 1] == mode_of(h, modes), h
    # the passing set was not checked on one high-beam frame: its count is the frames of the
    # low beam and the bends plus those without a mode, and the driving set's the reverse
    assert seen.count("high") > 0 and seen.count("low") > 0 and seen.count("glarefree") > 0
    assert passing == seen.count("low") + seen.count(None)
    assert driving == seen.count("high") + seen.count(None)
    assert status["verdicts"]["mode_aware"] is True
    assert [(s["id"], s["beam"]) for s in status["verdicts"]["sets"]] == [
        (PASSING, "passing"), (DRIVING, "driving")]


def test_explicit_modes_win_over_the_sets_beams(hdlamp, lamps, tmp_path):
    # verdict.modes given: its mapping alone, even against the sets' beams; low, which it does
    # not name, has no set
    dbc = dbc_path("hd84.dbc")
    log, modes = drive_log(hdlamp, dbc, str(tmp_path))
    hs, status, summary = run_drive(
        lamps, log, modes, "--set",
        f"verdict.modes=high:{PASSING},glarefree:{DRIVING}+{PASSING},unset:{DRIVING}", dbc=dbc)
    masks = {None: 0b11, "low": 0b00, "high": 0b01, "glarefree": 0b11}
    (passing, driving), seen = check_counts(hs, summary, lambda m: masks[m])
    for h in hs:
        assert seen[h["seq"] - 1] == mode_of(h, modes), h
    assert passing == seen.count("high") + seen.count("glarefree") + seen.count(None)
    assert seen.count("low") > 0 and passing < summary["frames"]["published"]
    assert status["verdicts"]["modes_configured"] is True


def test_without_a_mode_signal_every_set_on_every_frame(hdlamp, lamps, tmp_path):
    # hd84_fd.dbc without its HL_Mode_L / HL_Mode_R: no beam is said, both sets on every frame
    text = open(dbc_path("hd84_fd.dbc")).read()
    dbc = str(tmp_path / "hd84_fd_no_mode.dbc")
    with open(dbc, "w") as f:
        f.write("".join(l for l in text.splitlines(True) if "HL_Mode_" not in l))
    assert "HdlBeamMode\" SG_" not in open(dbc).read()
    log, modes = drive_log(hdlamp, dbc, str(tmp_path))
    assert modes == [None] * len(modes)
    hs, status, summary = run_drive(lamps, log, modes, dbc=dbc)
    (passing, driving), seen = check_counts(hs, summary, lambda m: 0b11)
    assert seen == [None] * len(seen)
    assert passing == driving == summary["frames"]["published"] > 7 * PHASE
    assert status["verdicts"]["mode_aware"] is False and status["verdicts"]["mode"] is None
