"""ASAM OSI ground truth in (docs/osi.md): a scenario written as an OSI trace by
'hdlamp scenario osi' replays through --world osi:file: with the scenario's own glare, frame for
frame; its lane boundaries, polylines, render the scenario's road; bad traces are counted by
reason; hdlampd replays a trace to its end and follows a live stream over UDP in esmini's
framing, its frames showing the car where the OSI pose puts it; every bad datagram is counted in
/status and /metrics by reason, logged once per reason per second, and a silent source turns
the scene to no world. The messages of the tests are built with python3-protobuf
(tests/it/osi_wire.py), apart from hdlamp's C."""
import json
import math
import os
import re
import struct
import subprocess
import threading
import time

import numpy as np
import pytest

import osi_wire as ow
from pngio import read_png
from proc import run
from scenario import HDLAMPD, dbc_path
from streamclient import connect, read_frame
from test_verdict_live import Daemon, hold_log

SOURCE = os.environ.get("HL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
STRAIGHT = os.path.join(SOURCE, "scenarios", "iihs-approach-straight.json")
ADB = "unece-r149-01-adb-glare"
W, H = 320, 180


@pytest.fixture(scope="module")
def lamps(hdlamp, tmp_path_factory):
    out = tmp_path_factory.mktemp("lamps")
    run(hdlamp, "model", "--out", out)
    return out


def lids(lamps):
    return ["--lid", lamps / "hd84_left.lid.exr", "--lid", lamps / "hd84_right.lid.exr"]


def write_trace(hdlamp, scn, out, *args):
    r = run(hdlamp, "scenario", "osi", scn, "--out", out, *args)
    return r


def glare_rows(hdlamp, lamps, *source, frames="0:8.38:0.02"):
    r = run(hdlamp, "glare", *source, *lids(lamps), "--preset", "high", "--json", "--frames",
            frames, ok=False)
    assert r.returncode in (0, 1), r.stderr
    return [json.loads(l) for l in r.stdout.splitlines()], r.stderr


def without_posts(src, out, **change):
    with open(src) as f:
        sc = json.load(f)
    sc["road"].pop("posts", None)
    sc.update(change)
    out.write_text(json.dumps(sc))
    return out


def curve_40(path, actors=()):
    """A 40 km/h left curve of radius 60 m after 20 m of straight, two lanes, no posts."""
    sc = {"version": 1, "title": "a 40 km/h curve, R 60 m", "duration_s": 6,
          "road": {"segments": [{"kind": "straight", "length_m": 20},
                                {"kind": "arc", "length_m": 120, "radius_m": 60,
                                 "turn": "left"}],
                   "lanes": {"count": 2, "width_m": 3.5}},
          "ego": {"start_s_m": 5, "lane": 1, "speed_mps": 40 / 3.6}, "actors": list(actors)}
    path.write_text(json.dumps(sc))
    return path


def test_a_scenario_as_a_trace_replays_with_the_scenarios_glare_frame_for_frame(
        hdlamp, lamps, tmp_path):
    gt = tmp_path / "20261127T000000Z_gt_370_3210_420_iihs.osi"
    r = write_trace(hdlamp, STRAIGHT, gt)
    assert "420 ground-truth messages at 50 Hz" in r.stdout
    msgs = ow.read_trace(gt)
    assert len(msgs) == 420
    first, second = ow.GroundTruth(), ow.GroundTruth()
    first.ParseFromString(msgs[0])
    second.ParseFromString(msgs[1])
    assert first.host_vehicle_id.value == 1 and len(first.moving_object) == 2
    assert (first.version.version_major, first.version.version_minor) == (3, 7)
    assert len(first.lane_boundary) == 3 and not second.lane_boundary  # the road, once
    assert second.timestamp.seconds == 0 and second.timestamp.nanos == 20000000
    car = first.moving_object[1]
    assert car.id.value == 2 and car.type == 2 and car.vehicle_classification.type == 4
    assert car.vehicle_classification.light_state.head_light == 3  # on
    # the oncoming car's box centre: its front at s 350 in lane 2 (y +1.75), facing -x
    assert car.base.position.x == 350.0 + 4.5 / 2
    assert math.isclose(car.base.position.y, 1.75) and car.base.position.z == 1.45 / 2
    assert math.isclose(abs(car.base.orientation.yaw), math.pi)

    direct, _ = glare_rows(hdlamp, lamps, "--scenario", STRAIGHT)
    replay, err = glare_rows(hdlamp, lamps, "--world", f"osi:file:{gt}")
    assert "420 ground-truth messages, 420 taken, 8.380 s" in err
    assert len(direct) == len(replay) == 420
    for a, b in zip(direct, replay):
        assert a["t_s"] == b["t_s"] and b["id"] == "osi-2"
        assert (a["kind"], a["role"], a["pass"], a["limit_id"]) == \
            (b["kind"], b["role"], b["pass"], b["limit_id"])
        for k in ("illuminance_lx", "pair_half_cd", "distance_m", "axis_h_deg"):
            assert math.isclose(a[k], b[k], rel_tol=1e-6, abs_tol=1e-9), (a["t_s"], k, a, b)
        for la, lb in zip(a["lamps"], b["lamps"]):
            assert math.isclose(la["intensity_cd"], lb["intensity_cd"], rel_tol=1e-6,
                                abs_tol=1e-9)
    # the same as SensorViews, named so
    sv = tmp_path / "20261127T000000Z_sv_370_3210_420_iihs.osi"
    write_trace(hdlamp, STRAIGHT, sv, "--message", "sensor-view")
    again, err = glare_rows(hdlamp, lamps, "--world", f"osi:file:{sv}")
    assert "420 sensor-view messages, 420 taken" in err
    assert [x["illuminance_lx"] for x in again] == [x["illuminance_lx"] for x in replay]
    # a name without the convention needs the message named
    plain = tmp_path / "plain.osi"
    plain.write_bytes(gt.read_bytes())
    r = run(hdlamp, "glare", "--world", f"osi:file:{plain}", *lids(lamps), ok=False)
    assert r.returncode == 1 and "--osi-message" in r.stderr, r.stderr
    rows, _ = glare_rows(hdlamp, lamps, "--world", f"osi:file:{plain}", "--osi-message",
                         "ground-truth")
    assert rows == replay


def pixels_differ(a, b, level=8):
    return int(np.count_nonzero(np.abs(a.astype(int) - b.astype(int)).max(axis=2) > level))


@pytest.mark.parametrize("name", ["straight", "curve-40"])
def test_a_trace_renders_the_scenarios_scene_its_road_from_lane_boundaries(
        hdlamp, lamps, tmp_path, name):
    """The road of the trace is its lane boundaries only (polylines): the frame equals the
    scenario's (without posts, which OSI's boundaries do not carry) but for the aliasing of the
    markings' edges within the polyline's 1 cm tolerance."""
    scn = (without_posts(STRAIGHT, tmp_path / "s.json") if name == "straight" else
           curve_40(tmp_path / "s.json", [{"id": "car", "kind": "car", "role": "oncoming",
                                           "path": {"lane": 2, "start_s_m": 110,
                                                    "speed_mps": 40 / 3.6}}]))
    trace = tmp_path / "t_gt_.osi"
    write_trace(hdlamp, scn, trace)
    for t in (0.0, 3.0):
        a, b = tmp_path / f"world-{t}.png", tmp_path / f"scenario-{t}.png"
        run(hdlamp, "render", "--world", f"osi:file:{trace}", "--lamps", lamps, "--at", t,
            "--size", f"{W}x{H}", "--out", a)
        run(hdlamp, "render", "--scenario", scn, "--lamps", lamps, "--at", t,
            "--size", f"{W}x{H}", "--out", b)
        pa, pb = read_png(a), read_png(b)
        grey = pa.astype(float).mean(axis=2)
        assert grey.std() > 8 and grey.max() > 200, f"{t} s: a blank frame"
        # the markings: bright thin lines on the lit road in the lower half
        assert np.count_nonzero(grey[H // 2:] >= 200) > 50, f"{t} s: no markings"
        assert pixels_differ(pa, pb) <= W * H // 200, (t, pixels_differ(pa, pb))


def bad_trace(path):
    """A trace with one of each fault after a good first message, and a cut last message."""
    road = [(1000 + j, [(x, -3.5 + 3.5 * j) for x in range(0, 401, 10)], (3, 4, 3)[j])
            for j in range(3)]

    def good(t, cars=((2, 80.0, 1.75, math.pi, {}),)):
        gt = ow.ground_truth(t, objects=[(1, 2.25, -1.75, 0.0, {}), *cars])
        return gt

    msgs = []
    g = good(0.0)
    for bid, pts, btype in road:
        ow.boundary(g, bid, pts, btype)
    msgs.append(g.SerializeToString())                     # 0 ok
    msgs.append(b"\xff\xff\xff garbage")                   # 1 malformed
    msgs.append(ow.ground_truth(0.04, host=None, objects=[(1, 2.25, -1.75, 0.0, {})])
                .SerializeToString())                      # 2 no_host
    msgs.append(ow.ground_truth(0.06, objects=[(1, float("nan"), -1.75, 0.0, {})])
                .SerializeToString())                      # 3 bad_value
    msgs.append(good(0.08).SerializeToString())            # 4 ok
    msgs.append(good(0.02).SerializeToString())            # 5 past
    msgs.append(good(0.10, cars=((2, 78.0, 1.75, math.pi, {}),
                                 (3, 50.0, 5.0, 0.0, {"otype": 4}),          # an animal
                                 (4, float("inf"), 1.0, 0.0, {}))).SerializeToString())  # 6
    msgs.append(good(5.10).SerializeToString())            # 7 time_jump, taken
    ow.write_trace(path, msgs)
    with open(path, "ab") as f:
        f.write(struct.pack("<I", 500) + b"\x08\x01")       # cut: 500 bytes promised, 2 there
    return path


def test_bad_traces_are_counted_by_reason_and_the_good_messages_replay(hdlamp, lamps, tmp_path):
    trace = bad_trace(tmp_path / "bad_gt_.osi")
    rows, err = glare_rows(hdlamp, lamps, "--world", f"osi:file:{trace}", frames="0:5.1:0.02")
    assert "8 ground-truth messages, 4 taken, 5.100 s" in err, err
    for reason, n, first in (("malformed", 1, 1), ("no_host", 1, 2), ("bad_value", 1, 3),
                             ("past", 1, 5), ("time_jump", 1, 7), ("truncated", 1, 8)):
        assert re.search(rf": {n} {reason}; the first, message {first}: ", err), (reason, err)
    assert "1 unknown_type" in err and "1 object_bad_value" in err
    assert "no host_vehicle_id" in err and "base.position.x nan" in err
    assert "the file ends in a message: at byte" in err and "expected 504 bytes, found 6" in err
    # the car (facing -x) is where the newest taken message puts it: its front 2.25 m before
    # the box's centre, its eye 1.8 m behind the front
    by_t = {r["t_s"]: r for r in rows}
    eye_x = lambda r: r["eye_m"][0]  # noqa: E731
    assert math.isclose(eye_x(by_t[0.0]), 80.0 - 2.25 + 1.8)
    assert math.isclose(eye_x(by_t[0.1]), 78.0 - 2.25 + 1.8)
    # between two taken messages (0.1 s and, after the jump, 5.1 s) the pose is interpolated
    assert math.isclose(eye_x(by_t[2.6]), (eye_x(by_t[0.1]) + eye_x(by_t[5.1])) / 2)
    assert math.isclose(eye_x(by_t[5.1]), 80.0 - 2.25 + 1.8)
    # not a trace: a length over 64 MiB
    junk = tmp_path / "junk_gt_.osi"
    junk.write_bytes(b"\xff\xff\xff\x7f" + b"x" * 100)
    r = run(hdlamp, "glare", "--world", f"osi:file:{junk}", *lids(lamps), ok=False)
    assert r.returncode == 1 and f"{junk}: not an OSI trace" in r.stderr, r.stderr
    r = run(hdlamp, "glare", "--world", f"osi:file:{tmp_path}/none_gt_.osi", *lids(lamps),
            ok=False)
    assert r.returncode == 1 and "No such file or directory" in r.stderr
    r = run(hdlamp, "glare", "--world", "osi:udp:127.0.0.1:1", *lids(lamps), ok=False)
    assert r.returncode == 1 and "the CLI reads a trace" in r.stderr


def test_hdlampd_replays_a_trace_to_its_end(hdlamp, lamps, tmp_path):
    gt = tmp_path / "run_gt_.osi"
    write_trace(hdlamp, STRAIGHT, gt)
    log = hold_log(hdlamp, tmp_path, "low", cycles=500)
    report = tmp_path / "report.json"
    r = subprocess.run(
        [HDLAMPD, "--replay", log, "--dbc", dbc_path("hd84.dbc"), "--world", f"osi:file:{gt}",
         "--exit-at-end", "--report", report,
         "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
         "--set", f"lamps.right={lamps}/hd84_right.lid.exr", "--set", "render.size=160x90",
         "--set", f"scene.glare_set={ADB}"], capture_output=True, text=True, timeout=300)
    assert r.returncode in (0, 3), r.stderr
    assert f"scene.world 'osi:file:{gt}': 420 ground-truth messages, 420 taken" in r.stderr
    rep = json.loads(report.read_text())
    assert rep and "osi-2" in json.dumps(rep), rep


class OsiDaemon(Daemon):
    """hdlampd on a live OSI stream: starts sender(port) once hdlampd waits for the first
    message (it does so before the renderer and the stream exist)."""

    def __init__(self, lamps, log, port, sender, *args):
        self.sender = sender
        self.port = port
        super().__init__(lamps, log, "--world", f"osi:udp:127.0.0.1:{port}", *args, sets=ADB)

    def _line(self, line):
        if "waiting up to" in line and "for the first ground-truth" in line:
            threading.Thread(target=self.sender, args=(self.port,), daemon=True).start()


def send_trace(messages, period=0.02, stop=None):
    """A sender of the messages at their pace, as a simulator would."""
    def go(port):
        sock = ow.socket.socket(ow.socket.AF_INET, ow.socket.SOCK_DGRAM)
        t0 = time.monotonic()
        for k, m in enumerate(messages):
            if stop is not None and stop.is_set():
                break
            time.sleep(max(0.0, t0 + k * period - time.monotonic()))
            ow.send(sock, port, m)
        sock.close()
    return go


def status(d):
    return json.loads(d.get("/status"))


def stream_frames(d, times, until_t):
    """The daemon's display frames nearest each scene time in times (within 0.03 s), by their
    header's scene time, until a frame at or past until_t: {scene_t_s: pixels}."""
    out = {}
    s = connect(d.stream_port)
    try:
        while True:
            f = read_frame(s)
            assert f is not None, "the stream ended"
            h, px = f
            t = round(h["scene_t_s"], 6)
            if h["scene_source"] == 4 and any(abs(t - want) <= 0.03 for want in times):
                out[t] = np.frombuffer(px, np.uint8).reshape(H, W, 3).copy()
            if t >= until_t:
                return out
    finally:
        s.close()


def live_frames(hdlamp, lamps, tmp_path, scn, times, tag):
    trace = tmp_path / f"{tag}_gt_.osi"
    write_trace(hdlamp, scn, trace)
    msgs = ow.read_trace(trace)
    log = hold_log(hdlamp, tmp_path, "low", cycles=100)
    stop = threading.Event()
    d = OsiDaemon(lamps, log, ow.free_udp_port(), send_trace(msgs, stop=stop),
                  "--set", f"render.size={W}x{H}")
    try:
        frames = stream_frames(d, times, max(times) + 0.1)
        st = status(d)
    finally:
        stop.set()
        d.stop()
    return frames, st, d


def test_a_live_stream_moves_the_scene_and_the_frames_show_the_car_where_osi_puts_it(
        hdlamp, lamps, tmp_path):
    """The pixel test of tests/it/test_scene_live.py on OSI input over UDP: the pixels that
    differ from the same stream without the car lie on the car's box as the test projects it
    from the scenario's geometry at the frame's own scene time, its headlamps the brightest."""
    from test_render_scenario import car_box_px, scenario_path, without_actors
    times = [1.5, 2.5, 4.0, 5.5]
    with_car, st, d = live_frames(hdlamp, lamps, tmp_path, scenario_path("straight"), times,
                                  "car")
    assert st["scene"]["source"] == "osi", st["scene"]
    w = st["world"]
    assert w["source"] == "osi:udp" and w["state"] == "live" and w["objects"] == 1, w
    assert w["messages"]["ok"] >= 280 and w["messages"]["malformed"] == 0, w
    g = {x["id"]: x for x in st["glare"]}
    assert set(g) == {"osi-2"}
    assert any("scene.world 'osi:udp:127.0.0.1:" in l and "waiting up to 60 s" in l
               for l in d.log), d.log
    empty, _, _ = live_frames(hdlamp, lamps, tmp_path,
                              without_actors("straight", tmp_path), times, "empty")
    widths = []
    for want in times:
        common = sorted(set(with_car) & set(empty), key=lambda x: abs(x - want))
        assert common and abs(common[0] - want) <= 0.03, (want, sorted(with_car), sorted(empty))
        t = common[0]
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
        widths.append(xs.max() - xs.min() + 1)
    assert all(b >= a for a, b in zip(widths, widths[1:])) and widths[-1] > widths[0], widths


def test_a_live_curve_given_only_as_lane_boundaries_renders_with_its_markings(
        hdlamp, lamps, tmp_path):
    """A 40 km/h curve whose road reaches hdlampd only as the first message's lane boundaries
    (polylines): the frames equal hdlamp render of the scenario (arcs) at the frame's time but
    for the aliasing of marking edges, and the markings are there."""
    scn = curve_40(tmp_path / "curve.json")
    times = [1.0, 3.0]
    frames, st, _ = live_frames(hdlamp, lamps, tmp_path, scn, times, "curve")
    for want in times:
        t = min(frames, key=lambda x: abs(x - want))
        ref = tmp_path / f"ref-{t}.png"
        run(hdlamp, "render", "--scenario", scn, "--lamps", lamps, "--at", t, "--size",
            f"{W}x{H}", "--exposure", "0", "--out", ref)
        a = frames[t]
        grey = a.astype(float).mean(axis=2)
        assert grey.std() > 8, f"{t} s: a uniform frame"
        assert np.count_nonzero(grey[H // 2:] >= 200) > 50, f"{t} s: no markings"
        assert pixels_differ(a, read_png(ref)) <= W * H // 100, (t, pixels_differ(a, read_png(ref)))


def framed(payload):
    return ow.datagrams(payload)


def test_bad_datagrams_are_counted_by_reason_and_a_silent_source_is_no_world(
        hdlamp, lamps, tmp_path):
    road = [(1000 + j, [(x, -3.5 + 3.5 * j) for x in range(0, 401, 10)], (3, 4, 3)[j])
            for j in range(3)]
    first = ow.ground_truth(0.0, objects=[(1, 2.25, -1.75, 0.0, {}),
                                          (2, 80.0, 1.75, math.pi, {})])
    for bid, pts, btype in road:
        ow.boundary(first, bid, pts, btype)
    ego = (1, 2.25, -1.75, 0.0, {})
    good = lambda t, *more: ow.ground_truth(  # noqa: E731
        t, objects=[ego, (2, 80.0 - t, 1.75, math.pi, {}), *more]).SerializeToString()
    bad = [
        [b"\x01\x02\x03"],                                          # bad_framing: no header
        framed(b"\xff\xff\xff not protobuf"),                       # malformed
        framed(ow.ground_truth(0.2, host=None, objects=[ego]).SerializeToString()),  # no_host
        framed(ow.ground_truth(0.3, objects=[(1, float("nan"), 0.0, 0.0, {})])
               .SerializeToString()),                               # bad_value
        framed(good(0.4, (3, 40.0, 5.0, 0.0, {"otype": 4}),         # unknown_type: an animal
                    (4, 1e9, 0.0, 0.0, {}))),                       # object_bad_value
        framed(good(0.1)),                                          # past
        framed(good(5.0)),                                          # time_jump, taken
        framed(ow.ground_truth(5.1, objects=[ego, (7, 30.0, 1.75, math.pi, {})])
               .SerializeToString()),                               # new_object
        ow.datagrams(good(5.2), part=100)[1:],                      # bad_framing: parts lost
    ]
    done = threading.Event()

    def sender(port):
        sock = ow.socket.socket(ow.socket.AF_INET, ow.socket.SOCK_DGRAM)
        ow.send(sock, port, first.SerializeToString())
        done.set()
        sock.close()

    log = hold_log(hdlamp, tmp_path, "low", cycles=100)
    d = OsiDaemon(lamps, log, ow.free_udp_port(), sender,
                  "--set", "scene.world_timeout_s=1.5")
    sock = ow.socket.socket(ow.socket.AF_INET, ow.socket.SOCK_DGRAM)
    try:
        assert done.wait(30)
        frames0 = d.wait_frames(3)["hdlamp_frames_total"][""]
        for dgrams in bad:
            for x in dgrams:
                sock.sendto(x, ("127.0.0.1", d.port))
            time.sleep(0.05)
        until = time.monotonic() + 30
        while True:
            w = status(d)["world"]
            if w["datagrams"] >= 1 + sum(len(b) for b in bad):
                break
            assert time.monotonic() < until, w
            time.sleep(0.1)
        # ok: the first, 0.4 (its two odd objects counted apart), 5.0 and 5.1; bad_framing: the
        # datagram without a header and each part of 5.2 whose first part was lost
        want = {"ok": 4, "bad_framing": len(bad[0]) + len(bad[-1]), "malformed": 1,
                "no_host": 1, "bad_value": 1,
                "unknown_type": 1, "object_bad_value": 1, "past": 1, "time_jump": 1,
                "new_object": 1}
        for k, v in w["messages"].items():
            assert v == want.get(k, 0), (k, w["messages"])
        assert w["t_s"] == 5.1 and w["objects"] == 0  # the newest: only the unknown car 7
        m = d.metrics()["hdlamp_osi_messages_total"]
        assert m['reason="malformed"'] == 1 and m['reason="ok"'] == 4
        assert m['reason="bad_framing"'] == want["bad_framing"] >= 2
        # the renderer kept going; then, silent for longer than the timeout: no world
        assert d.metrics()["hdlamp_frames_total"][""] > frames0
        time.sleep(2.0)
        st = status(d)
        assert st["world"]["state"] == "none" and st["world"]["age_s"] > 1.5, st["world"]
        assert all(not g.get("present", True) for g in st["glare"]), st["glare"]
        assert d.p.poll() is None
    finally:
        sock.close()
        d.stop()
    text = "".join(d.log)
    for reason in want:
        if reason != "ok":
            assert text.count(f"scene.world 'osi:udp:127.0.0.1:{d.port}': {reason}:") == 1, \
                (reason, text)
    assert "no host_vehicle_id: expected the ego vehicle's id" in text
    assert "without esmini's header" in text


def test_the_loop_in_software_on_a_trace_gives_the_scenarios_report(hdlamp, tmp_path):
    """The closed loop (restbus, reference ECU, verdicts; hdlamp sil in virtual time) on the
    trace of a scenario: the restbus tells the ECU about the OSI road user as about the
    scenario's, so the run report is the scenario's but for the names and the trace's end (its
    last message at 8.38 s, the scenario's end at 8.388 s: one cycle less)."""
    gt = tmp_path / "sil_gt_.osi"
    write_trace(hdlamp, STRAIGHT, gt)
    a, b = tmp_path / "direct.json", tmp_path / "osi.json"
    run(hdlamp, "sil", STRAIGHT, "--report", a)
    r = run(hdlamp, "sil", STRAIGHT, "--set", f"scene.world=osi:file:{gt}", "--report", b)
    assert f"scene: 'osi:file:{gt}' (ASAM OSI): 1 road users, 8.4 s" in r.stderr, r.stderr
    da, db = json.loads(a.read_text()), json.loads(b.read_text())
    diffs = []

    def walk(x, y, path):
        if isinstance(x, dict):
            assert set(x) == set(y), path
            for k in x:
                walk(x[k], y[k], f"{path}.{k}")
        elif isinstance(x, list):
            assert len(x) == len(y), path
            for i, (u, v) in enumerate(zip(x, y)):
                walk(u, v, f"{path}[{i}]")
        elif x != y:
            diffs.append((path, x, y))
    walk(da, db, "")
    expected = {".title", ".duration_s", ".loop.actors[0].id", ".loop.event_list[0].actor",
                ".loop.event_list[1].actor", ".loop.event_list[1].t_enter_s", ".frames.rendered",
                ".snapshots.pushed", ".loop.frames_in", ".loop.frames_judged",
                ".cycles.left.rendered", ".cycles.left.complete", ".cycles.right.rendered",
                ".cycles.right.complete"}
    assert {p for p, _, _ in diffs} <= expected, diffs
    for p, x, y in diffs:
        if p.startswith((".frames", ".snapshots", ".loop.frames", ".cycles")):
            assert x - y == 1, (p, x, y)  # the one cycle after the trace's last message
    la, lb = da["loop"], db["loop"]
    assert la["actors"][0]["max_lux"] == lb["actors"][0]["max_lux"] > 0
    assert la["latency_ms"] == lb["latency_ms"] and la["passed"] == lb["passed"]
    assert da["verdict"] == db["verdict"]


def test_a_burst_of_garbage_is_counted_datagram_for_datagram(hdlamp, lamps, tmp_path):
    """3,000 garbage datagrams at once beside the stream: every one is counted (by reason, or
    as the kernel's drop for a full buffer), none lost silently, and the world stays live. How
    many cycles a minute of 10,000 a second costs is tools/bench's (section osi)."""
    import random
    rng = random.Random(7)
    raw = [bytes(rng.getrandbits(8) for _ in range(rng.randint(1, 1400))) for _ in range(1500)]
    framed_garbage = [struct.pack("<iI", -1, len(p) + 1) + b"\xff" + p for p in raw]
    trace = tmp_path / "burst_gt_.osi"
    write_trace(hdlamp, STRAIGHT, trace)
    stop = threading.Event()
    log = hold_log(hdlamp, tmp_path, "low", cycles=100)
    d = OsiDaemon(lamps, log, ow.free_udp_port(), send_trace(ow.read_trace(trace), stop=stop))
    sock = ow.socket.socket(ow.socket.AF_INET, ow.socket.SOCK_DGRAM)
    try:
        d.wait_frames(3)
        before = status(d)["world"]
        for a, b in zip(raw, framed_garbage):
            sock.sendto(a, ("127.0.0.1", d.port))
            sock.sendto(b, ("127.0.0.1", d.port))
        until = time.monotonic() + 30
        while True:
            w = status(d)["world"]
            got = (w["messages"]["bad_framing"] + w["messages"]["malformed"] + w["socket_drops"]
                   - before["messages"]["bad_framing"] - before["messages"]["malformed"]
                   - before["socket_drops"])
            if got >= 3000:
                break
            assert time.monotonic() < until, (got, w)
            time.sleep(0.1)
        assert got == 3000, (got, w)
        if w["socket_drops"] == before["socket_drops"]:  # nothing dropped: each by reason
            assert w["messages"]["malformed"] - before["messages"]["malformed"] == 1500
        assert w["state"] == "live" and w["messages"]["ok"] > before["messages"]["ok"]
    finally:
        stop.set()
        sock.close()
        d.stop()
