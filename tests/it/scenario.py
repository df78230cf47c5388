"""Helpers for the drive scenario: generate it, run hdlampd on it, compare with expectations."""
import json
import os
import subprocess

from proc import run

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.environ.get("HL_SOURCE_DIR", os.path.join(HERE, "..", ".."))
BUILD_DIR = os.environ.get("HL_BUILD_DIR", os.path.join(SOURCE_DIR, "build"))
HDLAMPD = os.path.join(BUILD_DIR, "daemon", "hdlampd")


def dbc_path(name):
    return os.path.join(SOURCE_DIR, "dbc", name)


def generate(hdlamp, dbc, out_dir, phase=25, iface="can0"):
    log = os.path.join(out_dir, "scenario.log")
    expect = os.path.join(out_dir, "scenario.expect.jsonl")
    run(hdlamp, "scenario", "--dbc", dbc, "--out", log, "--expect", expect,
        "--phase-cycles", str(phase), "--iface", iface)
    cycles = {"left": [], "right": []}
    counters = None
    with open(expect) as f:
        for line in f:
            obj = json.loads(line)
            if obj.get("expect") == "counters":
                counters = obj
            else:
                cycles[obj["lamp"]].append((obj["counter"], obj["dims"]))
    return log, cycles, counters


def parse_output(text):
    """hdlampd's JSON lines: cycles per lamp, events in order, the summary."""
    cycles = {}
    events, summary = [], None
    for line in text.splitlines():
        obj = json.loads(line)
        if "lamp" in obj and "i" in obj:
            dims = [round(v * 63) for v in obj["i"]]
            assert all(abs(v * 63 - round(v * 63)) < 1e-4 for v in obj["i"]), obj
            cycles.setdefault(obj["lamp"], []).append((obj["counter"], dims, obj))
        elif obj.get("event") == "summary":
            summary = obj
        else:
            events.append(obj)
    return cycles, events, summary


def check_against_expectation(cycles, summary, expect_cycles, expect_counters):
    for lamp in ("left", "right"):
        got = [(c, d) for c, d, _ in cycles.get(lamp, [])]
        assert len(got) == len(expect_cycles[lamp]), (lamp, len(got), len(expect_cycles[lamp]))
        for n, (g, e) in enumerate(zip(got, expect_cycles[lamp])):
            assert g == e, f"{lamp} cycle {n}: got counter {g[0]}, expected {e[0]}"
        seqs = [o["seq"] for _, _, o in cycles[lamp]]
        assert seqs == list(range(1, len(seqs) + 1))
        want = expect_counters[lamp]
        have = summary["lamps"][lamp]
        for key, value in want.items():
            assert have[key] == value, (lamp, key, have[key], value)
        assert have["repeated_frames"] == 0 and have["out_of_range"] == 0


def hdlampd(*args, **kw):
    return subprocess.run([HDLAMPD, *[str(a) for a in args]], capture_output=True, text=True,
                          **kw)


def lamp_status(status, name):
    """A lamp's entry in hdlampd's live status (a list of lamps, each with its name)."""
    return next(l for l in status["lamps"] if l["name"] == name)


def check_failsafe_frames(hs, timeout_ms=100, tol_ms=20):
    """Frame headers (streamclient) around the scenario's silence: each lamp's fail-safe is
    entered timeout ± tol after its last cycle (both times from the header, CLOCK_MONOTONIC),
    and every frame showing a newer cycle of that lamp has it off. Returns the gaps in ms."""
    gaps = []
    for bit, key, done in ((0b10, "cycle_seq_left", "t_lamp_done_left"),
                           (0b1000, "cycle_seq_right", "t_lamp_done_right")):
        starts = [i for i, h in enumerate(hs)
                  if h["flags"] & bit and h[key] > 0 and (i == 0 or not hs[i - 1]["flags"] & bit)]
        # the silence: a fail-safe after a cycle that a newer cycle ends (not the start-up,
        # not the end of the replay)
        silence = [i for i in starts if any(h[key] > hs[i][key] for h in hs[i:])]
        assert silence, f"{key}: no fail-safe between two cycles"
        on = silence[-1]
        gap_ms = (hs[on]["t_cycle_done_ns"] - hs[on][done]) / 1e6
        assert timeout_ms - tol_ms <= gap_ms <= timeout_ms + tol_ms, (key, gap_ms)
        assert all(not h["flags"] & bit for h in hs[on:] if h[key] > hs[on][key]), key
        gaps.append(round(gap_ms, 1))
    return gaps
