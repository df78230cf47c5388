"""hdlampd --replay on the host: exact cycles and fault counters of the drive scenario."""
import json
import os
import signal
import subprocess
import time

import pytest

from scenario import (HDLAMPD, check_against_expectation, dbc_path, generate, hdlampd,
                      parse_output)


@pytest.mark.parametrize("dbc", ["hd84.dbc", "hd84_fd.dbc"])
def test_fast_replay_reports_exactly_the_scenario(hdlamp, tmp_path, dbc):
    log, expect, counters = generate(hdlamp, dbc_path(dbc), tmp_path)
    r = hdlampd("--replay", log, "--fast", "--dbc", dbc_path(dbc), "--no-render",
                "--print-cycles")
    assert r.returncode == 0, r.stderr
    cycles, events, summary = parse_output(r.stdout)
    check_against_expectation(cycles, summary, expect, counters)
    assert summary["ring"]["dropped"] == 0 and summary["ring"]["superseded"] == 0
    assert summary["frames"]["unknown_id"] == 0 and summary["frames"]["short"] == 0

    # Stale exactly timeout_ms after each lamp's last cycle before the silence (log time),
    # recovered with the first cycle after it.
    kinds = [(e["event"], e["lamp"]) for e in events]
    assert kinds == [("stale", "left"), ("stale", "right"), ("recovered", "left"),
                     ("recovered", "right")]
    for lamp in ("left", "right"):
        stale = next(e for e in events if e == {**e, "event": "stale", "lamp": lamp})
        before = [o for _, _, o in cycles[lamp] if o["t_rx_ns"] < 1700000000e9 + stale["t_ns"]]
        last_rx = before[-1]["t_rx_ns"] - 1700000000 * 10**9
        # the cycle completes with its last frame: first frame + 11 (22 for FD: 1) frame gaps
        assert 100e6 <= stale["t_ns"] - last_rx <= 100e6 + 20e6


def test_realtime_replay_gives_the_same_cycles_as_fast(hdlamp, tmp_path):
    log, expect, counters = generate(hdlamp, dbc_path("hd84.dbc"), tmp_path, phase=4)
    t0 = time.monotonic()
    slow = hdlampd("--replay", log, "--dbc", dbc_path("hd84.dbc"), "--no-render",
                   "--print-cycles")
    took = time.monotonic() - t0
    fast = hdlampd("--replay", log, "--fast", "--dbc", dbc_path("hd84.dbc"), "--no-render",
                   "--print-cycles")
    assert slow.returncode == 0 and fast.returncode == 0
    # the log spans (6 phases x 4 + 6 fault cycles) x 20 ms + 300 ms of silence: a replay at
    # the log's pace never ends sooner (a busy machine only makes it later, so no upper bound)
    span = (6 * 4 + 6) * 0.020 + 0.300
    print(f"real-time replay of a {span:.2f} s log: {took:.2f} s")
    assert took >= span - 0.02, took
    c_slow, e_slow, s_slow = parse_output(slow.stdout)
    c_fast, e_fast, s_fast = parse_output(fast.stdout)
    for lamp in ("left", "right"):
        assert [(c, d) for c, d, _ in c_slow[lamp]] == [(c, d) for c, d, _ in c_fast[lamp]]
    assert e_slow == e_fast
    check_against_expectation(c_slow, s_slow, expect, counters)


def test_malformed_lines_are_reported_with_line_numbers_and_skipped(hdlamp, tmp_path):
    log, expect, counters = generate(hdlamp, dbc_path("hd84.dbc"), tmp_path, phase=3)
    lines = open(log).read().splitlines()
    lines.insert(5, "(1700000000.001000) can0 32G#00")
    lines.insert(10, "garbage")
    lines.insert(12, "(1700000000.001100) can0 7AB#0011223344556677")  # not in the DBC
    bad = tmp_path / "bad.log"
    bad.write_text("\n".join(lines) + "\n")
    r = hdlampd("--replay", bad, "--fast", "--no-render", "--print-cycles",
                "--dbc", dbc_path("hd84.dbc"))
    assert r.returncode == 0
    assert f"'{bad}':6:" in r.stderr and f"'{bad}':11:" in r.stderr
    cycles, _, summary = parse_output(r.stdout)
    assert summary["log"]["malformed"] == 2
    assert summary["frames"]["unknown_id"] == 1
    check_against_expectation(cycles, summary, expect, counters)


def test_sigterm_stops_a_looping_replay(hdlamp, tmp_path):
    log, _, counters = generate(hdlamp, dbc_path("hd84.dbc"), tmp_path, phase=2)
    p = subprocess.Popen([HDLAMPD, "--replay", log, "--loop", "--no-render", "--print-cycles",
                          "--dbc", dbc_path("hd84.dbc")], stdout=subprocess.PIPE, text=True)
    # SIGTERM once the second pass has begun: a left cycle beyond the first pass's count (an
    # event in the daemon's output, not a time)
    lines = []
    for line in p.stdout:
        lines.append(line)
        o = json.loads(line)
        if o.get("lamp") == "left" and o.get("seq", 0) > counters["left"]["cycles"]:
            break
    t0 = time.monotonic()
    p.send_signal(signal.SIGTERM)
    out, _ = p.communicate(timeout=30)  # a generous limit for a hang, not a speed
    assert p.returncode == 0
    print(f"SIGTERM to exit: {time.monotonic() - t0:.3f} s")
    _, _, summary = parse_output("".join(lines) + out)
    assert summary["log"]["passes"] >= 2
    assert summary["lamps"]["left"]["cycles"] > counters["left"]["cycles"]


def test_usage_and_input_errors(tmp_path):
    log = tmp_path / "one.log"
    log.write_text("(1700000000.000000) can0 320#96008292B5FFFFFF\n")
    r = hdlampd("--replay", log, "--dbc", dbc_path("hd84.dbc"))  # live mode needs lamps
    assert r.returncode == 2
    assert r.stderr == ("hdlampd: key 'lamps.left' (default): no LID file configured for lamp 1"
                        " of can.lamps (make one with 'hdlamp model --out DIR')\n")
    assert hdlampd("--can", "vcan0", "--replay", "x.log", "--no-render").returncode == 2
    # a configuration error, found at load: exit 2, naming the option and the key
    r = hdlampd("--replay", tmp_path / "absent.log", "--no-render",
                "--dbc", dbc_path("hd84.dbc"))
    assert r.returncode == 2
    assert r.stderr == (f"hdlampd: --replay {tmp_path}/absent.log: key 'can.replay': "
                        f"'{tmp_path}/absent.log': No such file or directory; expected a "
                        "candump -L log\n")
    r = hdlampd("--replay", "-", "--no-render", "--dbc", tmp_path / "none.dbc")
    assert r.returncode == 2
    assert r.stderr == (f"hdlampd: --dbc {tmp_path}/none.dbc: key 'can.dbc': "
                        f"'{tmp_path}/none.dbc': No such file or directory; expected a DBC "
                        "file\n")
    r = hdlampd("--replay", "-", "--no-render", "--dbc", dbc_path("hd84.dbc"),
                "--lamps", "left")
    assert r.returncode == 1
    assert "HdlLamp \"right\" is not a configured lamp" in r.stderr


@pytest.mark.parametrize("dbc", ["hd84.dbc", "hd84_fd.dbc"])
def test_loop_counts_only_the_faults_the_log_injects(hdlamp, tmp_path, dbc):
    """--loop-passes 3: the log's alive counters start again at every pass, which is no fault;
    each fault counter is exactly three times the single pass's, and so are the cycles."""
    log, expect, counters = generate(hdlamp, dbc_path(dbc), tmp_path)
    r = hdlampd("--replay", log, "--fast", "--loop-passes", "3", "--dbc", dbc_path(dbc),
                "--no-render", "--print-cycles")
    assert r.returncode == 0, r.stderr
    cycles, events, summary = parse_output(r.stdout)
    assert summary["log"]["passes"] == 3
    for lamp in ("left", "right"):
        want = {key: 3 * value for key, value in counters[lamp].items()}
        have = {key: summary["lamps"][lamp][key] for key in want}
        assert have == want, lamp
        assert summary["lamps"][lamp]["repeated_frames"] == 0
        got = [(c, d) for c, d, _ in cycles[lamp]]
        assert got == 3 * expect[lamp]
        assert [o["seq"] for _, _, o in cycles[lamp]] == list(range(1, len(got) + 1))
    # the silence of every pass: each lamp stale once and recovered once per pass
    assert [(e["event"], e["lamp"]) for e in events] == 3 * [
        ("stale", "left"), ("stale", "right"), ("recovered", "left"), ("recovered", "right")]


def test_malformed_line_numbers_are_the_files_in_every_pass(hdlamp, tmp_path):
    log, _, _ = generate(hdlamp, dbc_path("hd84.dbc"), tmp_path, phase=2)
    lines = open(log).read().splitlines()
    lines.insert(5, "garbage")
    bad = tmp_path / "bad.log"
    bad.write_text("\n".join(lines) + "\n")
    r = hdlampd("--replay", bad, "--fast", "--loop-passes", "3", "--no-render",
                "--dbc", dbc_path("hd84.dbc"))
    assert r.returncode == 0, r.stderr
    reports = [l for l in r.stderr.splitlines() if "malformed candump line" in l]
    assert [l.split(": malformed")[0] for l in reports] == 3 * [f"hdlampd: '{bad}':6:1"]
    _, _, summary = parse_output(r.stdout)
    assert summary["log"]["malformed"] == 3 and summary["log"]["passes"] == 3
    assert summary["log"]["lines"] == 3 * len(lines)


def test_a_timestamp_going_backwards_is_reported_and_counted(hdlamp, tmp_path):
    log, expect, counters = generate(hdlamp, dbc_path("hd84.dbc"), tmp_path, phase=3)
    lines = open(log).read().splitlines()
    # line 8 stamped 500 us before line 7: as two interfaces' clocks can disagree
    t7 = float(lines[6].split(")")[0][1:])
    stamp = f"({t7 - 0.0005:.6f})"
    lines[7] = stamp + lines[7].split(")", 1)[1]
    back = tmp_path / "back.log"
    back.write_text("\n".join(lines) + "\n")
    r = hdlampd("--replay", back, "--fast", "--no-render", "--print-cycles",
                "--dbc", dbc_path("hd84.dbc"))
    assert r.returncode == 0, r.stderr
    assert r.stderr == (f"hdlampd: '{back}':8:1: timestamp {stamp[1:-1]} is 500 us before the "
                        "previous frame's; expected times that never decrease (replayed at "
                        "the previous frame's time)\n")
    cycles, _, summary = parse_output(r.stdout)
    assert summary["log"]["backwards"] == 1
    check_against_expectation(cycles, summary, expect, counters)  # the frame is not lost


@pytest.mark.parametrize("text", ["", "# only a comment\n\n", "garbage\n"])
def test_a_log_without_frames_stops_the_start(tmp_path, text):
    empty = tmp_path / "empty.log"
    empty.write_text(text)
    r = hdlampd("--replay", empty, "--fast", "--no-render", "--dbc", dbc_path("hd84.dbc"))
    assert r.returncode == 2
    assert r.stderr == (f"hdlampd: --replay {empty}: key 'can.replay': '{empty}': no CAN frame "
                        "in it; expected candump -L lines such as "
                        "'(1700000000.000000) can0 123#11223344'\n")
    assert r.stdout == ""
