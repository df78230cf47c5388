"""hdlamp sil --frames: every judged frame as a PNG, the same bytes every run (docs/sil.md,
"Frames"), and the run's report the same with or without them."""
import filecmp
import json
import os
import subprocess

import numpy as np

from pngio import read_png

SOURCE = os.environ.get("HL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
SCENARIO = os.path.join(SOURCE, "scenarios", "iihs-approach-straight.json")
SIZE = "render.size=160x90"


def sil(hdlamp, tmp_path, name, frames):
    report = tmp_path / f"{name}.json"
    args = [hdlamp, "sil", SCENARIO, "--report", str(report), "--set", SIZE]
    if frames:
        args += ["--frames", str(tmp_path / name)]
    proc = subprocess.run(args, capture_output=True, text=True, timeout=600)
    assert proc.returncode in (0, 3), proc.stderr
    return report


def test_frames_same_bytes_every_run(hdlamp, tmp_path):
    reports = [sil(hdlamp, tmp_path, name, True) for name in ("run1", "run2")]
    rendered = json.loads(reports[0].read_text())["frames"]["rendered"]
    files = sorted(os.listdir(tmp_path / "run1"))
    assert rendered > 0
    assert len(files) == rendered
    assert all(f.endswith(".png") for f in files)
    assert files == [f"frame-{i:06d}.png" for i in range(1, rendered + 1)]
    assert sorted(os.listdir(tmp_path / "run2")) == files
    match, mismatch, errors = filecmp.cmpfiles(tmp_path / "run1", tmp_path / "run2", files,
                                               shallow=False)
    assert not mismatch and not errors
    assert reports[0].read_bytes() == reports[1].read_bytes()

    # a frame in the middle of the approach shows the lit road: not one colour
    img = read_png(tmp_path / "run1" / files[len(files) // 2])
    assert img.shape == (90, 160, 3)
    assert len(np.unique(img.reshape(-1, 3), axis=0)) > 10
    assert img.max() > 100

    # the frames change nothing the run judges
    plain = sil(hdlamp, tmp_path, "plain", False)
    assert plain.read_bytes() == reports[0].read_bytes()


def test_frames_directory_that_cannot_be(hdlamp, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    proc = subprocess.run([hdlamp, "sil", SCENARIO, "--frames", str(blocker / "frames")],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert f"--frames '{blocker / 'frames'}'" in proc.stderr
