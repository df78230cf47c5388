"""hdlamp render --gi sensor: every scene renders with indirect light (the total never darker
than the direct view, brighter somewhere, nothing blank) with CPU and with GLES sensors
(--sensor-backend), the EXR files carry their component, bad options are refused, auto names
what it picked, the road with and without GI, and the time per sensor at three screen
resolutions for both backends (the paper's Table I metric), written to
HL_BUILD_DIR/gi-timing.json."""
import json
import os
import re
import subprocess

import numpy as np
import pytest

from pngio import read_png

HDLAMP = os.environ.get("HDLAMP", "hdlamp")
BUILD = os.environ.get("HL_BUILD_DIR", ".")
SCENES = ["sphere", "wall", "road", "bird", "bounce"]
SUMMARY = re.compile(
    r"gi: (\d+) sensors for (\d+) surface pixels .*?, ([\d.]+) ms per sensor \((cpu|gles)([^)]*)\), "
    r"sensors (\d+) ms, total (\d+) ms"
)
AUTO = re.compile(r"gi: one batch: cpu ([\d.]+) ms per sensor .*?, gles ([\d.]+) ms per sensor "
                  r"\(batch \d+\): sensors on (cpu|gles)")
BACKENDS = ["cpu", "gles"]


@pytest.fixture(scope="module")
def lamps(tmp_path_factory):
    d = tmp_path_factory.mktemp("lamps")
    subprocess.run([HDLAMP, "model", "--out", str(d)], check=True, capture_output=True)
    return d


def render(lamps, out, *args):
    return subprocess.run(
        [HDLAMP, "render", "--lamps", str(lamps), "--out", str(out), *args],
        capture_output=True, text=True,
    )


def summary(stderr):
    m = SUMMARY.search(stderr)
    assert m, stderr
    return {
        "sensors": int(m.group(1)),
        "surface_pixels": int(m.group(2)),
        "ms_per_sensor": float(m.group(3)),
        "backend": m.group(4),
        "how": m.group(4) + m.group(5),
        "sensor_ms": int(m.group(6)),
        "total_ms": int(m.group(7)),
    }


def grey(path):
    return read_png(path)[..., :3].astype(int).max(axis=2)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("scene", SCENES)
def test_gi_every_scene(lamps, tmp_path, scene, backend):
    out = tmp_path / f"{scene}.png"
    r = render(lamps, out, "--scene", scene, "--preset", "high", "--size", "64x36",
               "--gi", "sensor", "--sensor-size", "16", "--tile", "4",
               "--sensor-backend", backend)
    assert r.returncode == 0, r.stderr
    s = summary(r.stderr)
    assert s["backend"] == backend, r.stderr
    assert 0 < s["sensors"] <= s["surface_pixels"]
    assert "sensors " in r.stderr and "/ ~" in r.stderr  # the progress line
    for suffix in ("direct", "indirect", "total"):
        exr = tmp_path / f"{scene}-{suffix}.exr"
        head = subprocess.run(["exrheader", str(exr)], capture_output=True, text=True,
                              check=True).stdout
        assert f'hdlamp:component (type string): "{suffix}"' in head, head
        assert "hdlamp:gi" in head and "worldToCamera" in head
        assert f"backend={backend}" in head, head
    total, direct = grey(out), grey(tmp_path / f"{scene}-direct.png")
    diff = read_png(tmp_path / f"{scene}-diff.png")
    # The indirect light only adds: not darker anywhere (one level of rounding), brighter
    # somewhere; the difference image is not blank.
    assert (total >= direct - 1).all()
    assert (total > direct).sum() > 0, scene
    if scene != "bird":  # seen from above, the road's bounce (from the posts) stays faint
        assert (total > direct + 2).sum() > 20, scene
    assert diff[..., :3].astype(float).std() > 8


def test_gi_bad_options(lamps, tmp_path):
    for args, what in [
        (["--gi", "path"], "--gi"),
        (["--gi", "sensor", "--sensor-size", "15"], "--sensor-size"),
        (["--gi", "sensor", "--tile", "6"], "--tile"),
        (["--gi", "sensor", "--dradiance", "0"], "--dradiance"),
        (["--gi", "sensor", "--view", "lux"], "--out"),
        (["--gi", "sensor", "--sensor-backend", "gpu"], "--sensor-backend"),
        (["--gi", "sensor", "--sensor-batch", "0"], "--sensor-batch"),
    ]:
        r = render(lamps, tmp_path / "x.png", *args)
        assert r.returncode == 2, (args, r.stderr)
        assert what in r.stderr


def test_gi_auto_picks_the_faster(lamps, tmp_path):
    """auto times one batch of each backend, says what it picked, and runs on it."""
    out = tmp_path / "auto.png"
    r = render(lamps, out, "--scene", "road", "--size", "64x36", "--gi", "sensor")
    assert r.returncode == 0, r.stderr
    m = AUTO.search(r.stderr)
    assert m, r.stderr
    ms_cpu, ms_gles, picked = float(m.group(1)), float(m.group(2)), m.group(3)
    assert ms_cpu > 0 and ms_gles > 0
    assert picked == ("gles" if ms_gles < ms_cpu else "cpu")
    assert summary(r.stderr)["backend"] == picked


def test_gi_gles_without_egl_fails(lamps, tmp_path):
    """Explicit GLES sensors without an EGL display: exit 1 with the reason, no fallback."""
    env = dict(os.environ, EGL_PLATFORM="nonexistent")
    r = subprocess.run([HDLAMP, "render", "--lamps", str(lamps), "--out", str(tmp_path / "x.png"),
                        "--size", "64x36", "--gi", "sensor", "--sensor-backend", "gles"],
                       capture_output=True, text=True, env=env)
    assert r.returncode == 1, r.stderr
    assert "EGL" in r.stderr and "nonexistent" in r.stderr, r.stderr
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize("backend", BACKENDS)
def test_gi_road_with_and_without(lamps, tmp_path, backend):
    """The road at 320x180, low beam: the posts and the far road gain bounce light."""
    plain = tmp_path / "road-plain.png"
    r = render(lamps, plain, "--scene", "road", "--size", "320x180")
    assert r.returncode == 0, r.stderr
    out = tmp_path / "road-gi.png"
    r = render(lamps, out, "--scene", "road", "--size", "320x180", "--gi", "sensor",
               "--sensor-backend", backend)
    assert r.returncode == 0, r.stderr
    s = summary(r.stderr)
    assert s["backend"] == backend
    print(f"road 320x180 low beam: {s}")
    a, b = grey(plain), grey(out)
    assert (grey(tmp_path / "road-gi-direct.png") == a).all()  # the direct view is the plain one
    assert (b >= a - 1).all() and b.mean() > a.mean()
    # Pixels the lamps leave black (post backs, far road) that bounce light makes visible.
    newly_lit = ((a == 0) & (b > 0)).sum()
    print(f"pixels black without GI and lit with it: {newly_lit}")
    assert newly_lit > 50
    assert s["surface_pixels"] >= 5 * s["sensors"]


def test_gi_time_per_sensor_three_resolutions(lamps, tmp_path):
    """Table I of the paper: time per sensor at three screen resolutions (32x32 hemicube),
    CPU and GLES sensors."""
    rows = []
    for backend in BACKENDS:
        for size in ["128x72", "256x144", "512x288"]:
            out = tmp_path / f"road-{size}.png"
            r = render(lamps, out, "--scene", "road", "--size", size, "--gi", "sensor",
                       "--sensor-backend", backend)
            assert r.returncode == 0, r.stderr
            s = summary(r.stderr)
            s["size"] = size
            s["load1"] = os.getloadavg()[0]
            rows.append(s)
            print(f"{backend} {size}: {s['sensors']} sensors of {s['surface_pixels']} surface "
                  f"pixels, {s['ms_per_sensor']:.3f} ms per sensor ({s['how']}), "
                  f"total {s['total_ms'] / 1000:.1f} s, load {s['load1']:.1f}")
    with open(os.path.join(BUILD, "gi-timing.json"), "w") as f:
        json.dump(rows, f, indent=1)
    for backend in BACKENDS:
        mine = [r for r in rows if r["backend"] == backend]
        ms = [r["ms_per_sensor"] for r in mine]
        assert all(m > 0 for m in ms)
        # The cost of a sensor does not depend on the screen (a loaded machine may add noise).
        assert max(ms) < 4 * min(ms), ms
        counts = [r["sensors"] for r in mine]
        assert counts[0] < counts[1] < counts[2]
