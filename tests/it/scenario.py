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


def check_failsafe_frames(hs):
    """Frame headers (streamclient) around the scenario's silence: each lamp's fail-safe is
    entered after its last cycle (both times from the header, CLOCK_MONOTONIC) and before its
    next one, and the first frame showing the lamp's next cycle has it off. Returns the gaps
    in ms, for the log only: how long after the last cycle depends on how busy the machine
    is; the timeout itself is checked exactly on the log's timeline (test_replay.py)."""
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
        assert gap_ms > 0, (key, gap_ms)  # after the last cycle, by the daemon's clock
        first_newer = next(h for h in hs[on:] if h[key] > hs[on][key])
        assert not first_newer["flags"] & bit, key  # off with the next cycle
        gaps.append(round(gap_ms, 1))
    return gaps


def quick_singles(hs, coalesce_ms=5):
    """Frames (after a normal one) that bring one lamp's next cycle only, although the render
    thread did not wait render.coalesce_ms for the other lamp (the daemon's own timestamps:
    from the snapshot's push, t_cycle_done_ns, to render start). The daemon renders a lone lamp
    early only when the other is not due (a fault left it behind); when the other lamp is
    late, however late, it waits the whole window first. Load cannot make a frame quicker."""
    n = 0
    for a, b in zip(hs, hs[1:]):
        if a["flags"] or b["flags"]:
            continue
        dl = b["cycle_seq_left"] - a["cycle_seq_left"]
        dr = b["cycle_seq_right"] - a["cycle_seq_right"]
        if (dl == 0) != (dr == 0) and \
                b["t_render_start_ns"] - b["t_cycle_done_ns"] < coalesce_ms * 1e6:
            n += 1
    return n
