"""hdlamp render --scenario: the shipped IIHS-like approaches (straight, 250 m left curve) at
several times. The oncoming car's pixels (the difference to the same scenario without it) lie
where the test projects its body from the road geometry and grow as it approaches; its
headlamps light up the display view; no frame is black or uniform; the approaches as
sequences (display and lux) match references.

HL_UPDATE_REFS=1 rewrites the references in tests/data/render-ref/scenario/ (look at them
first)."""
import json
import math
import os
import shutil
import subprocess

import numpy as np
import pytest

from pngio import read_png

HDLAMP = os.environ.get("HDLAMP", "hdlamp")
SOURCE = os.environ.get("HL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
REFS = os.path.join(SOURCE, "tests", "data", "render-ref", "scenario")
W, H = 320, 180
TIMES = [1.5, 2.5, 4.0, 5.5]  # on the curve the car enters the view at ~1 s
SCENARIOS = {
    "straight": "iihs-approach-straight.json",
    "curve250": "iihs-approach-curve-250m-left.json",
}

# The default driver's camera (docs/scenarios.md) and car body (world/scenario.c).
CAM_POS = np.array([-1.8, 0.37, 1.2])
CAM_DIR = np.array([1.0, 0.0, -0.03])
FOV_Y_DEG = 36.0
CAR = (4.5, 1.8, 1.45)
HEADLAMPS = [(0.0, 0.65, 0.65), (0.0, -0.65, 0.65)]


@pytest.fixture(scope="module")
def lamps(tmp_path_factory):
    d = tmp_path_factory.mktemp("lamps")
    subprocess.run([HDLAMP, "model", "--out", str(d)], check=True, capture_output=True)
    return d


def scenario_path(name):
    return os.path.join(SOURCE, "scenarios", SCENARIOS[name])


def render(lamps, scenario, out, *args):
    r = subprocess.run(
        [HDLAMP, "render", "--scenario", str(scenario), "--lamps", str(lamps), "--out",
         str(out), "--size", f"{W}x{H}", *args],
        capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r


def frames(lamps, tmp_path, scenario, tag, *args):
    """Renders TIMES as a sequence; returns the images in order."""
    a, b = TIMES[0], TIMES[-1]
    # The sequence's step must hit every time of TIMES: 0.5 s, then pick.
    r = render(lamps, scenario, tmp_path / f"{tag}.png", "--frames", f"{a}:{b}:0.5", *args)
    paths = r.stdout.split()
    assert len(paths) == int(round((b - a) / 0.5)) + 1
    assert paths[0].endswith(f"{tag}-0000.png")
    return [read_png(paths[int(round((t - a) / 0.5))]) for t in TIMES]


def assert_not_blank(img, what):
    grey = img[..., :3].astype(float).mean(axis=2)
    assert grey.max() > 60, f"{what}: black"
    assert grey.std() > 8, f"{what}: uniform (std {grey.std():.1f})"
    assert (grey > 20).mean() > 0.05, f"{what}: almost all dark"


def without_actors(name, tmp_path):
    with open(scenario_path(name)) as f:
        sc = json.load(f)
    sc["actors"] = []
    p = tmp_path / f"{name}-empty.json"
    p.write_text(json.dumps(sc))
    return p


# The road's geometry, written here from docs/scenarios.md: s along the centre line, d left.
def road_point(name, s, d):
    if name == "straight" or s <= 50.0:
        return np.array([s, d]), 0.0
    r, phi = 250.0, (s - 50.0) / 250.0
    return np.array([50.0 + (r - d) * math.sin(phi), r - (r - d) * math.cos(phi)]), phi


def ego_and_car(name, t):
    with open(scenario_path(name)) as f:
        sc = json.load(f)
    v_ego = sc["ego"]["speed_mps"]
    car = sc["actors"][0]["path"]
    ego, h_ego = road_point(name, sc["ego"]["start_s_m"] + v_ego * t, -1.75)
    pos, h = road_point(name, car["start_s_m"] - car["speed_mps"] * t, 1.75)
    return (ego, h_ego), (pos, h + math.pi)


def project(p):
    """Ego-frame point to pixel (x, y), as world/camera.c."""
    f = CAM_DIR / np.linalg.norm(CAM_DIR)
    r = np.cross(f, [0.0, 0.0, 1.0])
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    d = p - CAM_POS
    z = d @ f
    th = math.tan(math.radians(FOV_Y_DEG) / 2)
    return ((d @ r) / z / (th * W / H) + 1) * W / 2, (1 - (d @ u) / z / th) * H / 2


def to_ego(ego, h_ego, pos, h, local):
    c, s = math.cos(h), math.sin(h)
    w = pos + np.array([local[0] * c - local[1] * s, local[0] * s + local[1] * c])
    dx = w - ego
    ce, se = math.cos(h_ego), math.sin(h_ego)
    return np.array([dx[0] * ce + dx[1] * se, -dx[0] * se + dx[1] * ce, local[2]])


def car_box_px(name, t):
    """The pixel bounding box of the oncoming car's body and its headlamps' midpoint."""
    (ego, h_ego), (pos, h) = ego_and_car(name, t)
    pts = [project(to_ego(ego, h_ego, pos, h, (x, y, z)))
           for x in (-CAR[0], 0.0) for y in (-CAR[1] / 2, CAR[1] / 2) for z in (0.0, CAR[2])]
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    lamps_px = [project(to_ego(ego, h_ego, pos, h, l)) for l in HEADLAMPS]
    mid = np.mean(lamps_px, axis=0)
    return (min(xs), min(ys), max(xs), max(ys)), mid, abs(lamps_px[0][0] - lamps_px[1][0])


@pytest.mark.parametrize("name", list(SCENARIOS))
def test_oncoming_car_moves_as_predicted(lamps, tmp_path, name):
    with_car = frames(lamps, tmp_path, scenario_path(name), f"{name}-car")
    empty = frames(lamps, tmp_path, without_actors(name, tmp_path), f"{name}-empty")
    widths, spans = [], []
    for t, a, b in zip(TIMES, with_car, empty):
        assert_not_blank(a, f"{name} at {t} s")
        diff = np.abs(a.astype(int) - b.astype(int)).max(axis=2) > 8
        ys, xs = np.nonzero(diff)
        assert len(xs) > 0, f"{name} at {t} s: the car is not seen"
        (x0, y0, x1, y1), mid, span = car_box_px(name, t)
        # Every changed pixel lies on the car's box or in its lamps' glow (a few pixels).
        m = 4
        inside = (xs >= x0 - m) & (xs <= x1 + m) & (ys >= y0 - m) & (ys <= y1 + m)
        assert inside.all(), (f"{name} at {t} s: {np.count_nonzero(~inside)} changed pixels "
                              f"outside the predicted box {x0:.1f}..{x1:.1f} x {y0:.1f}..{y1:.1f}")
        # Its headlamps: the brightest changed pixels sit at the lamps' projection.
        grey = a[..., :3].astype(float).mean(axis=2)
        bright = diff & (grey >= 250)
        by, bx = np.nonzero(bright)
        assert len(bx) > 0, f"{name} at {t} s: no lamp in the display view"
        assert abs(bx.mean() + 0.5 - mid[0]) <= 1.5 + span / 2, (name, t, bx.mean(), mid)
        assert abs(by.mean() + 0.5 - mid[1]) <= 1.5, (name, t, by.mean(), mid)
        widths.append(xs.max() - xs.min() + 1)
        spans.append(span)
    # Approaching: the predicted lamp spacing and the car's pixel width grow frame to frame.
    assert all(b > a for a, b in zip(spans, spans[1:])), spans
    assert all(b >= a for a, b in zip(widths, widths[1:])), widths
    assert widths[-1] > widths[0]


SEQUENCE = (1.5, 5.5, 1.0)  # the reference sequences: 1.5, 2.5, 3.5, 4.5, 5.5 s


@pytest.mark.parametrize("view", ["display", "lux"])
@pytest.mark.parametrize("name", list(SCENARIOS))
def test_sequence_matches_reference(lamps, tmp_path, name, view):
    """The approach as a sequence: every frame not blank, each differs from the one before (the
    car and the ego's light move), and each matches its reference within a tolerance."""
    a, b, step = SEQUENCE
    tag = f"{name}_{view}"
    r = render(lamps, scenario_path(name), tmp_path / f"{tag}.png", "--frames",
               f"{a}:{b}:{step}", "--view", view)
    paths = r.stdout.split()
    times = [a + k * step for k in range(int(round((b - a) / step)) + 1)]
    assert len(paths) == len(times)
    prev = None
    for t, path in zip(times, paths):
        ref_name = f"{tag}_t{t:.1f}.png"
        img = read_png(path)
        assert img.shape == (H, W, 3)
        assert_not_blank(img, ref_name)
        if prev is not None:
            moved = np.abs(img.astype(int) - prev.astype(int)).max(axis=2) > 8
            assert moved.sum() > 20, f"{ref_name}: the same as the frame before"
        prev = img
        ref_path = os.path.join(REFS, ref_name)
        if os.environ.get("HL_UPDATE_REFS"):
            os.makedirs(REFS, exist_ok=True)
            shutil.copy(path, ref_path)
        ref = read_png(ref_path)
        d = np.abs(img.astype(int) - ref.astype(int)).max(axis=2)
        assert d.mean() <= 0.5 and (d > 24).mean() <= 0.002, \
            f"{ref_name}: mean diff {d.mean():.2f}, {100 * (d > 24).mean():.2f} % pixels off"


def test_bird_and_lux_exr(lamps, tmp_path):
    out = tmp_path / "bird.png"
    render(lamps, scenario_path("curve250"), out, "--at", "5", "--scene", "bird")
    assert_not_blank(read_png(out), "bird")
    exr = tmp_path / "lux.exr"
    render(lamps, scenario_path("straight"), exr, "--at", "1", "--view", "lux")
    assert exr.stat().st_size > 1000
    with open(exr, "rb") as f:
        head = f.read(4096)
    assert head[:4] == b"\x76\x2f\x31\x01"  # OpenEXR magic
    assert b"hdlamp:scenarioTime" in head


def test_bad_arguments(lamps, tmp_path):
    def run(*args):
        return subprocess.run([HDLAMP, "render", "--lamps", str(lamps), *args],
                              capture_output=True, text=True)

    sc = scenario_path("straight")
    r = run("--scenario", sc, "--out", str(tmp_path / "x.png"))
    assert r.returncode == 2 and "--at T or --frames" in r.stderr
    r = run("--scenario", sc, "--frames", "3:1:0.5", "--out", str(tmp_path / "x.png"))
    assert r.returncode == 2 and "--frames '3:1:0.5'" in r.stderr
    r = run("--scenario", sc, "--at", "1", "--scene", "wall", "--out", str(tmp_path / "x.png"))
    assert r.returncode == 2 and "--scene 'wall'" in r.stderr
    bad = tmp_path / "bad.json"
    bad.write_text('{"version": 1, "duration_s": 1, "road": {"segments": []}}')
    r = run("--scenario", str(bad), "--at", "0", "--out", str(tmp_path / "x.png"))
    assert r.returncode == 1 and "bad.json:1:" in r.stderr and "segments" in r.stderr
