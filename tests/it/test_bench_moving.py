"""hdlamp-bench-moving: the moving-scene benchmark runs every variant in one run and writes its
JSON (few frames here; its timings are its output, never asserted), and refuses bad options."""
import json
import os
import subprocess

HDLAMP = os.environ.get("HDLAMP", "hdlamp")
BENCH = os.path.join(os.path.dirname(HDLAMP), "hdlamp-bench-moving")


def test_bench_moving_json(tmp_path):
    out = tmp_path / "moving.json"
    r = subprocess.run([BENCH, "--frames", "4", "--gles-frames", "3", "--out", str(out)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    j = json.loads(out.read_text())
    for key, n, threads in (("moving_frame", 4, 2), ("moving_frame_1_thread", 4, 1),
                            ("still_frame", 4, 2), ("gles_moving_frame", 3, 2)):
        s = j[key]
        assert s["n"] == n and s["threads"] == threads
        assert 0 < s["min_ms"] <= s["median_ms"] <= s["p99_ms"] <= s["max_ms"]
        assert 0 <= s["caller_cpu_min_ms"] <= s["caller_cpu_median_ms"]
    # road users move: some pixels change every frame, most do not
    ch = j["changed_pixels"]
    assert 0 < ch["min"] <= ch["median"] <= ch["max"] < 1280 * 720
    assert abs(ch["median_fraction"] - ch["median"] / (1280 * 720)) < 1e-4
    assert j["target_median_ms"] == 10.0
    assert j["met"] == (j["moving_frame"]["median_ms"] <= 10.0)
    assert j["gles_renderer"]  # GLES ran, on the context named here


def test_bench_moving_usage():
    r = subprocess.run([BENCH, "--help"], capture_output=True, text=True)
    assert r.returncode == 0 and "--gles-frames" in r.stdout
    for bad in (["--frames", "2"], ["--threads", "0"], ["--gles-frames", "1"], ["extra"]):
        r = subprocess.run([BENCH, *bad], capture_output=True, text=True)
        assert r.returncode == 2, (bad, r.stderr)
