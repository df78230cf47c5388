"""hdlamp render --kpi: the road KPIs of the HD84 low and high beam against an independent
computation here, and the bird scene's labels.

The independent computation: each lamp's combined distribution from `hdlamp lid combine`, as a
table from `hdlamp lid export` (CSV: the grid's own samples over the lit region), bilinear
lookups of I at road points, the lamp-space angles of docs/design.md §4 written out in numpy,
E = I cos(eps) / r^2 with the road's normal up, both lamps added, and the same crossings found
on lines sampled five times finer than the C code's 0.05 m. Within 1 %."""
import json
import math
import os
import subprocess

import numpy as np
import pytest

from pngio import read_png

HDLAMP = os.environ.get("HDLAMP", "hdlamp")

LANE_CENTRE_Y_M = -1.75
EDGE_Y_M = -3.5
WIDTH_AT_M = (25.0, 50.0)
WIDTH_HALF_M = 30.0
MAX_RANGE_M = 300.0
STEP_M = 0.01  # the C code samples every 0.05 m

DEFAULT_POSES = [
    {"pos": (0.0, 0.7, 0.65), "yaw": 0.0, "pitch": -math.degrees(math.atan(0.01))},
    {"pos": (0.0, -0.7, 0.65), "yaw": 0.0, "pitch": -math.degrees(math.atan(0.01))},
]

# (preset, kpi levels or None for the default 1,3, extra render options, poses)
CASES = {
    "low": ("low", None, [], DEFAULT_POSES),
    "high": ("high", None, [], DEFAULT_POSES),
    # low levels: the width at 50 m is not zero
    "high-0.2-0.5lx": ("high", (0.2, 0.5), [], DEFAULT_POSES),
    # lamps moved and turned: the KPIs follow --left-pos/--left-aim/--right-aim
    "low-posed": (
        "low",
        None,
        ["--left-pos", "0.1,0.75,0.7", "--left-aim", "2,-1.2", "--right-aim", "-1,-0.8"],
        [
            {"pos": (0.1, 0.75, 0.7), "yaw": 2.0, "pitch": -1.2},
            {"pos": (0.0, -0.7, 0.65), "yaw": -1.0, "pitch": -0.8},
        ],
    ),
}


@pytest.fixture(scope="module")
def lamps(tmp_path_factory):
    d = tmp_path_factory.mktemp("lamps")
    subprocess.run([HDLAMP, "model", "--out", str(d)], check=True, capture_output=True)
    return d


def run(*args):
    r = subprocess.run([HDLAMP, *args], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r


class Table:
    """A lamp's combined distribution as exported: bilinear, zero outside the grid's range."""

    def __init__(self, csv_path, h_range, v_range):
        with open(csv_path) as f:
            rows = [line.strip().split(",") for line in f if not line.startswith("#")]
        self.system = rows[0][0]
        assert self.system in ("A", "B")
        self.h = np.array([float(x) for x in rows[0][1:]])
        v = np.array([float(r[0]) for r in rows[1:]])
        vals = np.array([[float(x) for x in r[1:]] for r in rows[1:]])
        order = np.argsort(v)  # rows come by decreasing V
        self.v, self.vals = v[order], vals[order]
        self.h_range, self.v_range = h_range, v_range

    def lookup(self, h_deg, v_deg):
        i = np.clip(np.searchsorted(self.h, h_deg, side="right") - 1, 0, len(self.h) - 2)
        j = np.clip(np.searchsorted(self.v, v_deg, side="right") - 1, 0, len(self.v) - 2)
        tx = (h_deg - self.h[i]) / (self.h[i + 1] - self.h[i])
        ty = (v_deg - self.v[j]) / (self.v[j + 1] - self.v[j])
        a, b = self.vals[j, i], self.vals[j, i + 1]
        c, d = self.vals[j + 1, i], self.vals[j + 1, i + 1]
        val = (a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty
        inside = (
            (h_deg >= self.h_range[0]) & (h_deg <= self.h_range[1])
            & (v_deg >= self.v_range[0]) & (v_deg <= self.v_range[1])
        )
        return np.where(inside, val, 0.0)


def grid_range(info):
    """H and V ranges (deg) from `hdlamp lid info`."""
    out = {}
    for line in info.splitlines():
        for key in ("H:", "V:"):
            if line.startswith(key):
                lo, _, hi = line.split()[1:4]
                out[key[0]] = (float(lo), float(hi))
    return out["H"], out["V"]


def road_e(table, pose, x, y):
    """E (lx) of one lamp at road points (x, y, 0): numpy arrays."""
    px, py, pz = pose["pos"]
    cy, sy = math.cos(math.radians(pose["yaw"])), math.sin(math.radians(pose["yaw"]))
    cp, sp = math.cos(math.radians(pose["pitch"])), math.sin(math.radians(pose["pitch"]))
    ax = np.array([sy, -cy, 0.0])  # lamp x: right
    az = np.array([cp * cy, cp * sy, sp])  # optical axis
    ay = np.cross(ax, az)  # up
    w = np.stack([x - px, y - py, np.full_like(x, -pz)], axis=-1)
    dx, dy, dz = w @ ax, w @ ay, w @ az
    if table.system == "A":
        h, v = np.arctan2(dx, dz), np.arctan2(dy, np.hypot(dx, dz))
    else:
        v, h = np.arctan2(dy, dz), np.arctan2(dx, np.hypot(dy, dz))
    r = np.sqrt((w * w).sum(axis=-1))
    cos_eps = pz / r  # the road's normal is +z
    return table.lookup(np.degrees(h), np.degrees(v)) * cos_eps / (r * r)


def crossings(s, e, level):
    """(first up-crossing or start, last down-crossing or end) where e >= level; None if never."""
    above = e >= level
    if not above.any():
        return None
    i0, i1 = np.argmax(above), len(above) - 1 - np.argmax(above[::-1])
    step = s[1] - s[0]
    lo = s[0] if i0 == 0 else s[i0 - 1] + step * (level - e[i0 - 1]) / (e[i0] - e[i0 - 1])
    hi = s[-1] if i1 == len(s) - 1 else s[i1] + step * (e[i1] - level) / (e[i1] - e[i1 + 1])
    return lo, hi


def independent_kpis(tables, poses, levels):
    def e_at(x, y):
        return sum(road_e(t, p, x, y) for t, p in zip(tables, poses))

    xs = np.arange(0.0, MAX_RANGE_M + STEP_M / 2, STEP_M)
    ys = np.arange(-WIDTH_HALF_M, WIDTH_HALF_M + STEP_M / 2, STEP_M)
    out = {"centre_range_m": [], "edge_range_m": [], "width_m": []}
    for key, y in (("centre_range_m", LANE_CENTRE_Y_M), ("edge_range_m", EDGE_Y_M)):
        e = e_at(xs, np.full_like(xs, y))
        for lv in levels:
            c = crossings(xs, e, lv)
            out[key].append(0.0 if c is None else c[1])
    for x in WIDTH_AT_M:
        c = crossings(ys, e_at(np.full_like(ys, x), ys), levels[0])
        out["width_m"].append(0.0 if c is None else c[1] - c[0])
    return out


def combined_tables(lamps, tmp, preset):
    tables = []
    for side in ("left", "right"):
        lid = tmp / f"{preset}-{side}.lid.exr"
        csv = tmp / f"{preset}-{side}.csv"
        run("lid", "combine", str(lamps / f"hd84_{side}.lid.exr"), str(lamps / f"{preset}.json"),
            "--lamp", side, "--out", str(lid))
        run("lid", "export", str(lid), "--source", "1", "--out", str(csv))
        h_range, v_range = grid_range(run("lid", "info", str(lid)).stdout)
        tables.append(Table(csv, h_range, v_range))
    return tables


def close(got, want):
    """Within 1 %; two zeros are equal."""
    return abs(got - want) <= 0.01 * abs(want) if want else got == 0.0


@pytest.mark.parametrize("case", list(CASES))
def test_kpis_equal_independent_computation(lamps, tmp_path, case):
    preset, levels, extra, poses = CASES[case]
    kpi = tmp_path / "kpi.json"
    args = ["render", "--lamps", str(lamps), "--preset", preset, "--scene", "bird",
            "--size", "160x90", "--out", str(tmp_path / "b.png"), "--kpi", str(kpi), *extra]
    if levels:
        args += ["--kpi-levels", f"{levels[0]},{levels[1]}"]
    r = run(*args)
    assert r.stdout.strip() == str(tmp_path / "b.png")
    got = json.loads(kpi.read_text())
    levels = levels or (1.0, 3.0)
    assert got["levels_lx"] == list(levels)
    assert got["width_lx"] == levels[0]
    assert got["width_at_m"] == list(WIDTH_AT_M)
    want = independent_kpis(combined_tables(lamps, tmp_path, preset), poses, levels)
    print(case, "hdlamp:", got)
    print(case, "numpy: ", want)
    for key in ("centre_range_m", "edge_range_m", "width_m"):
        for g, w in zip(got[key], want[key]):
            assert close(g, w), f"{case} {key}: hdlamp {got[key]}, independent {want[key]}"
    # Nothing degenerate: every range found, the first level reaching farther.
    assert all(v > 10.0 for v in got["centre_range_m"] + got["edge_range_m"])
    assert got["centre_range_m"][0] > got["centre_range_m"][1]
    assert got["width_m"][0] > 2.0


def test_kpi_to_stdout_is_only_json(lamps, tmp_path):
    r = run("render", "--lamps", str(lamps), "--scene", "road", "--size", "64x36",
            "--out", str(tmp_path / "r.png"), "--kpi", "-")
    lines = r.stdout.splitlines()
    assert len(lines) == 1
    assert set(json.loads(lines[0])) == {"levels_lx", "centre_range_m", "edge_range_m",
                                         "width_lx", "width_at_m", "width_m"}


@pytest.mark.parametrize("bad", ["1", "0,3", "1,x", "-1,2"])
def test_kpi_levels_rejected(lamps, tmp_path, bad):
    r = subprocess.run([HDLAMP, "render", "--lamps", str(lamps), "--out", str(tmp_path / "r.png"),
                        "--kpi", "-", "--kpi-levels", bad], capture_output=True, text=True)
    assert r.returncode == 2
    assert f"--kpi-levels '{bad}'" in r.stderr


# The bird scene's camera (render/scene.c): straight down over the road's middle, x to the
# right of the image, y up; the distance labels sit at y = 12 m.
def bird_project(x, y, w, h):
    half_span = (140.0 + 10.0) / 2 + 2.0
    aspect = w / h
    return ((x - (half_span - 12.0)) / half_span + 1) * w / 2, (1 - y * aspect / half_span) * h / 2


WHITE = np.array([255, 255, 255])
CYAN = np.array([0, 220, 255])  # the 1 lx line (render/overlay.c)


def pixels_of(img, colour):
    return (img[..., :3] == colour).all(axis=2)


@pytest.mark.parametrize("preset", ["low", "high"])
def test_bird_labels(lamps, tmp_path, preset):
    w, h = 1280, 720
    out, plain, kpi = tmp_path / "bird.png", tmp_path / "plain.png", tmp_path / "k.json"
    run("render", "--lamps", str(lamps), "--preset", preset, "--scene", "bird",
        "--out", str(out), "--kpi", str(kpi))
    run("render", "--lamps", str(lamps), "--preset", preset, "--scene", "bird",
        "--out", str(plain), "--no-labels")
    img, ref = read_png(out), read_png(plain)
    grey = img[..., :3].astype(float).mean(axis=2)
    assert img.shape == (h, w, 3) and grey.std() > 8, "blank or uniform"
    # The labels are the only difference: none in the plain render.
    assert not pixels_of(ref, WHITE).any() and not pixels_of(ref, CYAN).any()
    # "10 M" ... "130 M": white text on a black box centred on each line's label point.
    for d in range(10, 140, 10):
        cx, cy = (int(round(c)) for c in bird_project(d, 12.0, w, h))
        box = img[cy - 9:cy + 10, cx - 30:cx + 31]
        assert pixels_of(box, WHITE).sum() > 40, f"no label at {d} m"
        changed = (box != ref[cy - 9:cy + 10, cx - 30:cx + 31]).any(axis=2)
        assert changed.sum() > 100, f"no label box at {d} m"
    # The 1 lx line reaches at least as far forward as the 1 lx range along the lane centre
    # (its label is in its colour, beside the tip: more cyan to the right of the line's area).
    k = json.loads(kpi.read_text())
    cyan = pixels_of(img, CYAN)
    assert cyan.sum() > 200
    tip_col = np.nonzero(cyan.any(axis=0))[0].max()
    centre_col, _ = bird_project(k["centre_range_m"][0], LANE_CENTRE_Y_M, w, h)
    assert tip_col >= centre_col - 8  # 8 px ~ 1 m
    assert tip_col <= w - 1
