"""hdlampd with a scenario (docs/live-scenario.md, "Scenario and glare"): the scenario clock on the
replayed log's time (restarting with each --loop pass), the glare at each road user's eye on
every frame in /status, /metrics, the stream header and /glare.json, equal to 'hdlamp glare' at
the frame's scenario time; poses from a driving simulator over UDP; a bad scenario file stops
the start naming FILE:LINE:COL."""
import json
import math
import os
import re
import socket
import subprocess
import time

import pytest

from proc import run
from scenario import HDLAMPD, dbc_path
from streamclient import connect, read_frame
from test_metrics import parse
from test_verdict_live import REGS, Daemon, hold_log

ADB = "unece-r149-01-adb-glare"
LOG_CYCLES = 50  # 1 s of ECU cycles per pass
STILL_EYE_X = 50.0


@pytest.fixture(scope="module")
def lamps(hdlamp, tmp_path_factory):
    out = tmp_path_factory.mktemp("lamps")
    run(hdlamp, "model", "--out", out)
    return out


def write_scenario(path, duration_s=10.0):
    """The ego standing at s 0 in lane 1 with the default lamps (x 0, y +-0.7 m); a car standing
    oncoming with its eye at x = 50 m, one approaching at 20 m/s, a pedestrian at the edge."""
    doc = {
        "version": 1, "title": "live glare", "duration_s": duration_s,
        "road": {"segments": [{"kind": "straight", "length_m": 400}],
                 "lanes": {"count": 2, "width_m": 3.5}},
        "ego": {"start_s_m": 0, "lane": 1, "speed_mps": 0},
        "actors": [
            {"id": "still", "kind": "car", "role": "oncoming",
             "path": {"lane": 2, "start_s_m": STILL_EYE_X - 1.8, "speed_mps": 0}},
            {"id": "mover", "kind": "car", "role": "oncoming",
             "path": {"lane": 2, "start_s_m": 150, "speed_mps": 20}},
            {"id": "walker", "kind": "pedestrian", "role": "roadside",
             "path": {"waypoints": [{"t_s": 0, "x_m": 30, "y_m": -5}]}},
        ],
    }
    path.write_text(json.dumps(doc, indent=2))
    return path


def log_frames(log):
    """(timestamp ns, CAN id) of every frame of a candump -L log, exactly."""
    out = []
    with open(log) as f:
        for line in f:
            m = re.match(r"\((\d+)\.(\d{6})\) \S+ ([0-9A-Fa-f]+)#", line)
            if m:
                out.append((int(m.group(1)) * 10**9 + int(m.group(2)) * 1000, m.group(3)))
    return out


def cycle_done_s(frames, t_first_ns):
    """The time, from the log's start, of the last frame of the lamp cycle whose first frame is
    at t_first_ns: the same CAN id, before the next ECU period (20 ms)."""
    (ident,) = {i for t, i in frames if t == t_first_ns}
    last = max(t for t, i in frames if i == ident and t_first_ns <= t < t_first_ns + 19_900_000)
    return (last - frames[0][0]) / 1e9


def glare_cli(hdlamp, lamps, scn, t_s, preset="high"):
    r = run(hdlamp, "glare", "--scenario", scn, "--lid", f"{lamps}/hd84_left.lid.exr",
            "--lid", f"{lamps}/hd84_right.lid.exr", "--preset", preset, "--at", repr(t_s),
            "--json", "--regulations", REGS, ok=False)
    assert r.returncode in (0, 1), r.stderr
    return {row["id"]: row for row in map(json.loads, r.stdout.splitlines())}


def close(a, b, rel=0.01):
    return math.isclose(a, b, rel_tol=rel, abs_tol=1e-9)


def test_scenario_time_follows_the_log_and_restarts_with_each_loop_pass(hdlamp, lamps,
                                                                        tmp_path):
    log = hold_log(hdlamp, tmp_path, "high", cycles=LOG_CYCLES)
    frames = log_frames(log)
    scn = write_scenario(tmp_path / "scn.json")
    d = Daemon(lamps, log, "--scenario", scn, sets=ADB)
    try:
        s = connect(d.stream_port)
        hs = []
        while len(hs) < 2 * LOG_CYCLES + 10:  # into the third pass
            f = read_frame(s)
            assert f is not None, "the stream ended"
            hs.append(f[0])
        s.close()
    finally:
        d.stop()
    restarts = 0
    for prev, h in zip(hs, hs[1:]):
        assert h["scene_source"] == 2 and h["n_actors"] == 3, h  # the log's time
        # the log's time of the frame's newest cycle: when its last frame came, from the
        # start of the pass (the log's timestamps restart with each pass)
        want = cycle_done_s(frames, h["t_cycle_rx_ns"])
        assert abs(h["scene_t_s"] - want) < 1e-6, (h["seq"], h["scene_t_s"], want)
        if h["scene_t_s"] < prev["scene_t_s"]:
            restarts += 1
            assert h["scene_t_s"] < 0.05 and prev["scene_t_s"] > 0.9, (prev, h)
    assert restarts >= 1  # a new pass: the scenario starts again


def test_scenario_clock_holds_at_the_end(hdlamp, lamps, tmp_path):
    log = hold_log(hdlamp, tmp_path, "high", cycles=LOG_CYCLES)
    scn = write_scenario(tmp_path / "short.json", duration_s=0.3)
    d = Daemon(lamps, log, "--scenario", scn, sets=ADB)
    try:
        s = connect(d.stream_port)
        hs = [read_frame(s)[0] for _ in range(LOG_CYCLES)]
        s.close()
    finally:
        d.stop()
    ts = [h["scene_t_s"] for h in hs]
    assert max(ts) == 0.3 and min(ts) < 0.3
    assert sum(1 for t in ts if t == 0.3) >= 10  # held, frame after frame


def test_status_and_metrics_carry_the_glare_of_each_road_user(hdlamp, lamps, tmp_path):
    log = hold_log(hdlamp, tmp_path, "high", cycles=LOG_CYCLES)
    scn = write_scenario(tmp_path / "scn.json")
    d = Daemon(lamps, log, "--scenario", scn, sets=ADB)
    try:
        d.wait_frames(5)
        status = json.loads(d.get("/status"))
        text = d.get("/metrics")
        history = json.loads(d.get("/glare.json"))
        s = connect(d.stream_port)
        h, _ = read_frame(s)
        s.close()
    finally:
        d.stop()
    scene = status["scene"]
    assert scene["source"] == "log" and scene["glare_set"] == ADB
    assert scene["title"] == "live glare" and scene["duration_s"] == 10
    t = scene["t_s"]
    assert 0 <= t <= 1.0
    # the daemon's frame against 'hdlamp glare' at the frame's scenario time, within 1 %
    want = glare_cli(hdlamp, lamps, scn, t)
    got = {g["id"]: g for g in status["glare"]}
    assert list(got) == ["still", "mover", "walker"]
    for aid, g in got.items():
        w = want[aid]
        assert (g["kind"], g["role"]) == (w["kind"], w["role"])
        assert close(g["distance_m"], w["distance_m"], 1e-6), (aid, g, w)
        assert close(g["eye_lux"], w["illuminance_lx"]), (aid, g, w)
        assert close(g["cd"]["pair_half"], w["pair_half_cd"]), (aid, g, w)
        assert close(g["cd"]["left"], w["lamps"][0]["intensity_cd"]), (aid, g, w)
        assert close(g["cd"]["right"], w["lamps"][1]["intensity_cd"]), (aid, g, w)
        assert g["limit_cd"] == w["limit_cd"] and g["pass"] == w["pass"], (aid, g, w)
    # the standing car at 50 m: the high beam is over the 625 cd of "Oncoming 50 m"
    assert got["still"]["limit_cd"] == 625 and got["still"]["pass"] is False
    assert got["walker"]["limit_cd"] is None and got["walker"]["pass"] is True
    assert got["still"]["fail_frames"] >= 5
    # /metrics: Prometheus' linter passes; the standing car's values are those of any frame
    lint = subprocess.run(["promtool", "check", "metrics"], input=text, capture_output=True,
                          text=True)
    assert lint.returncode == 0 and not lint.stdout.strip(), lint.stdout + lint.stderr
    fam = {n: {l: v for _, l, v in f["samples"]} for n, f in parse(text).items()}
    still = glare_cli(hdlamp, lamps, scn, 0.0)["still"]
    assert close(fam["hdlamp_glare_lux"]['actor="still"'], still["illuminance_lx"])
    assert close(fam["hdlamp_glare_cd"]['actor="still"'], still["pair_half_cd"])
    assert fam["hdlamp_glare_limit_cd"]['actor="still"'] == 625
    assert 'actor="walker"' not in fam["hdlamp_glare_limit_cd"]  # no limit for its class
    assert fam["hdlamp_glare_fail_frames_total"]['actor="still"'] >= 5
    assert fam["hdlamp_glare_fail_frames_total"]['actor="walker"'] == 0
    # the stream header: the failing road users' bits and the highest eye illuminance
    assert h["glare_failed"] & 1 and not h["glare_failed"] & 4
    want_h = glare_cli(hdlamp, lamps, scn, h["scene_t_s"])
    assert close(h["eye_lux_max"], max(r["illuminance_lx"] for r in want_h.values()), 1e-3)
    # /glare.json: the frames so far, in order, each with the road users' values
    assert history["history_frames"] == 3000 and history["history_overwritten"] == 0
    assert [a["id"] for a in history["actors"]] == ["still", "mover", "walker"]
    seqs = [e["seq"] for e in history["history"]]
    assert seqs == sorted(seqs) and len(seqs) == history["frames_kept"] >= 5
    for e in history["history"]:
        assert e["source"] == "log" and len(e["lux"]) == 3
        # the first frames may show one lamp only: the other's first cycle was not in yet
        if e["seq"] >= 3:
            assert close(e["lux"][0], still["illuminance_lx"], 1e-3), e
        assert e["lux"][0] <= still["illuminance_lx"] * 1.001


def test_glare_history_is_bounded_and_counts_what_it_drops(hdlamp, lamps, tmp_path):
    log = hold_log(hdlamp, tmp_path, "high", cycles=LOG_CYCLES)
    scn = write_scenario(tmp_path / "scn.json")
    d = Daemon(lamps, log, "--scenario", scn, "--set", "scene.glare_history=8", sets=ADB)
    try:
        d.wait_frames(20)
        history = json.loads(d.get("/glare.json"))
    finally:
        d.stop()
    kept = history["history"]
    assert history["history_frames"] == 8 and len(kept) == 8
    assert history["history_overwritten"] == history["frames"] - 8 > 0
    assert [e["seq"] for e in kept] == list(range(kept[0]["seq"], kept[0]["seq"] + 8))


def eye_distance(ego, actor):
    """Horizontal distance from the ego's lamps' midpoint (its origin: lamps at x 0, y +-0.7 m)
    to a car's default eye [-1.8, 0.37] in its body frame."""
    h = math.radians(actor["heading_deg"])
    ex = actor["x_m"] - 1.8 * math.cos(h) - 0.37 * math.sin(h)
    ey = actor["y_m"] - 1.8 * math.sin(h) + 0.37 * math.cos(h)
    return math.hypot(ex - ego["x_m"], ey - ego["y_m"])


def test_poses_over_udp_set_the_scene_and_bad_ones_are_counted(hdlamp, lamps, tmp_path):
    log = hold_log(hdlamp, tmp_path, "high", cycles=LOG_CYCLES)
    scn = write_scenario(tmp_path / "scn.json")
    d = Daemon(lamps, log, "--scenario", scn, "--pose", "udp:127.0.0.1:0", sets=ADB)
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    try:
        port = next(int(m.group(1)) for m in
                    (re.search(r"pose input on udp:127\.0\.0\.1:0 \(port (\d+)\)", l)
                     for l in d.log) if m)
        d.wait_frames(3)
        assert json.loads(d.get("/status"))["scene"]["source"] == "log"  # no pose yet
        bad = [b"not json", b"[1, 2]", b'{"t_s": 1, "ego": {"x_m": 0, "y_m": 0}}',
               b'{"t_s": 1, "ego": {"x_m": 0, "y_m": 0, "heading_deg": 0}, '
               b'"actors": [{"id": "nobody", "x_m": 1, "y_m": 2, "heading_deg": 0}]}']
        for b in bad:
            sock.sendto(b, ("127.0.0.1", port))
        for k, (t, x) in enumerate(((3.25, 60.0), (3.5, 42.5))):
            ego = {"x_m": 5.0, "y_m": -1.75, "heading_deg": 0}
            mover = {"id": "mover", "x_m": x, "y_m": 1.75, "heading_deg": 180, "lamps": True}
            sock.sendto(json.dumps({"t_s": t, "ego": ego, "actors": [mover]}).encode(),
                        ("127.0.0.1", port))
            until = time.monotonic() + 30
            while True:
                st = json.loads(d.get("/status"))
                if st["scene"]["source"] == "pose" and st["scene"]["t_s"] == t:
                    break
                assert time.monotonic() < until, st["scene"]
                time.sleep(0.05)
            g = {x["id"]: x for x in st["glare"]}
            assert math.isclose(g["mover"]["distance_m"], eye_distance(ego, mover),
                                rel_tol=1e-9)
            # the road users the message does not name: where the scenario puts them at t_s
            eye = glare_cli(hdlamp, lamps, scn, t)["still"]["eye_m"]
            assert math.isclose(g["still"]["distance_m"],
                                math.hypot(eye[0] - ego["x_m"], eye[1] - ego["y_m"]),
                                rel_tol=1e-6)
            assert st["pose"]["messages"]["ok"] == k + 1 and st["pose"]["age_s"] >= 0
            assert st["pose"]["t_s"] == t
        # the stream header carries the pose's time
        s = connect(d.stream_port)
        h, _ = read_frame(s)
        s.close()
        assert h["scene_source"] == 3 and h["scene_t_s"] == 3.5
        m = d.metrics()["hdlamp_pose_messages_total"]
        assert m['result="malformed"'] == 2 and m['result="invalid"'] == 1
        assert m['result="unknown_actor"'] == 1 and m['result="ok"'] == 2
        assert d.p.poll() is None  # still running
    finally:
        sock.close()
        final = d.stop()
    assert final["pose"]["messages"]["malformed"] == 2
    text = "".join(d.log)
    assert "pose.listen 'udp:127.0.0.1:0': malformed message: not JSON" in text
    assert "unknown_actor message: actors[0].id 'nobody': no road user of that id" in text


def test_bad_scenario_file_stops_the_start_naming_file_line_column(hdlamp, lamps, tmp_path):
    log = hold_log(hdlamp, tmp_path, "high", cycles=5)
    scn = tmp_path / "bad.json"
    scn.write_text('{\n  "version": 1,\n  "title": "bad",\n  "duration_s": -3\n}\n')
    r = subprocess.run([HDLAMPD, "--replay", log, "--dbc", dbc_path("hd84.dbc"),
                        "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
                        "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
                        "--set", "render.size=160x90", "--set", "stream.tcp=",
                        "--set", "http.listen=", "--scenario", str(scn)],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2, r.stderr
    assert re.search(rf"hdlampd: scene.scenario: {re.escape(str(scn))}:4:3: duration_s: ",
                     r.stderr), r.stderr
    # a missing file: named with the key, before anything starts
    r = subprocess.run([HDLAMPD, "--replay", log, "--dbc", dbc_path("hd84.dbc"),
                        "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
                        "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
                        "--scenario", str(tmp_path / "none.json")],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2
    assert f"--scenario {tmp_path}/none.json: key 'scene.scenario': '{tmp_path}/none.json': " \
           "No such file or directory" in r.stderr, r.stderr


def test_pose_input_needs_a_scenario(hdlamp, lamps, tmp_path):
    log = hold_log(hdlamp, tmp_path, "high", cycles=5)
    r = subprocess.run([HDLAMPD, "--replay", log, "--pose", "udp:127.0.0.1:0"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2
    assert "pose.listen needs scene.scenario" in r.stderr
    r = subprocess.run([HDLAMPD, "--replay", log, "--pose", "tcp:127.0.0.1:1"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2
    assert "--pose tcp:127.0.0.1:1: key 'pose.listen': 'tcp:127.0.0.1:1': expected " \
           "udp:HOST:PORT" in r.stderr, r.stderr


def moving_frames(lamps, log, scn, times):
    """The daemon's display frames (320x180, RGB) within 0.1 s of each scenario time in times,
    by their own header's scenario time over one pass of the log: {scene_t_s: pixels}."""
    import numpy as np  # only this test needs it

    from test_render_scenario import H, W
    d = Daemon(lamps, log, "--scenario", scn, "--set", f"render.size={W}x{H}", sets=ADB)
    out = {}
    try:
        s = connect(d.stream_port)
        last_t = -1.0
        while True:
            f = read_frame(s)
            assert f is not None, "the stream ended"
            h, px = f
            t = h["scene_t_s"]
            if t < last_t:  # the next pass: every time of the log was shown
                break
            last_t = t
            if any(abs(t - want) <= 0.1 for want in times):
                out[t] = np.frombuffer(px, np.uint8).reshape(H, W, 3).copy()
        s.close()
    finally:
        d.stop()
    return out


def test_the_daemon_draws_the_moving_scene(hdlamp, lamps, tmp_path):
    """With a scenario the frames show its moving scene at their own scenario time: the pixels
    that differ from the same replay of the scenario without its road users lie on the
    oncoming car's box as the test projects it from the road geometry at that time, its
    headlamps are the brightest of them, and it grows as it approaches
    (tests/it/test_render_scenario.py does the same for 'hdlamp render --scenario')."""
    import numpy as np

    from test_render_scenario import car_box_px, scenario_path, without_actors
    log = hold_log(hdlamp, tmp_path, "low", cycles=300)  # 6 s per pass
    times = [1.5, 2.5, 4.0, 5.5]
    with_car = moving_frames(lamps, log, scenario_path("straight"), times)
    empty = moving_frames(lamps, log, without_actors("straight", tmp_path), times)
    widths = []
    for want in times:
        # the same instant in both runs (the log's time: the same cycle), nearest to want
        t = min(set(with_car) & set(empty), key=lambda x: abs(x - want))
        assert abs(t - want) < 0.05, (want, t)
        a, b = with_car[t], empty[t]
        assert a.std() > 2, f"{t} s: a uniform frame"
        diff = np.abs(a.astype(int) - b.astype(int)).max(axis=2) > 8
        ys, xs = np.nonzero(diff)
        assert len(xs) > 0, f"{t} s: the car is not seen"
        (x0, y0, x1, y1), mid, span = car_box_px("straight", t)
        m = 4
        inside = (xs >= x0 - m) & (xs <= x1 + m) & (ys >= y0 - m) & (ys <= y1 + m)
        assert inside.all(), (f"{t} s: {np.count_nonzero(~inside)} changed pixels outside the "
                              f"predicted box {x0:.1f}..{x1:.1f} x {y0:.1f}..{y1:.1f}")
        grey = a.astype(float).mean(axis=2)
        by, bx = np.nonzero(diff & (grey >= 250))
        assert len(bx) > 0, f"{t} s: no lamp in the display view"
        assert abs(bx.mean() + 0.5 - mid[0]) <= 1.5 + span / 2, (t, bx.mean(), mid)
        assert abs(by.mean() + 0.5 - mid[1]) <= 1.5, (t, by.mean(), mid)
        widths.append(xs.max() - xs.min() + 1)
    assert all(b >= a for a, b in zip(widths, widths[1:])) and widths[-1] > widths[0], widths
