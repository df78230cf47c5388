"""The HTTP live view in a real browser (Debian's chromium, headless, driven by playwright-core
from npm) and over plain HTTP.

The server under test is HL_HTTP_URL when set (e.g. a running hdlampd); otherwise the tests start
hl-http-fixture (HL_HTTP_FIXTURE), a test fixture that serves frames of the real renderer: the
road scene lit by the HD84 lamps, low and high beam alternating every second.
"""
import json
import os
import shutil
import subprocess
import time
import urllib.error
import urllib.request

import pytest

from pngread import read_png

HERE = os.path.dirname(os.path.abspath(__file__))
BROWSER_DIR = os.path.join(os.path.dirname(HERE), "browser")


def build_dir():
    d = os.environ.get("HL_BUILD_DIR")
    if not d:
        pytest.fail("HL_BUILD_DIR must name the build tree (run through ctest)")
    return d


@pytest.fixture(scope="module")
def http_url(hd84, tmp_path_factory):
    url = os.environ.get("HL_HTTP_URL")
    if url:
        yield url.rstrip("/") + "/"
        return
    fixture = os.environ.get("HL_HTTP_FIXTURE")
    if not fixture or not os.access(fixture, os.X_OK):
        pytest.fail("HL_HTTP_FIXTURE must name the built hl-http-fixture (run through ctest)")
    captures = tmp_path_factory.mktemp("captures")
    proc = subprocess.Popen(
        [fixture, "--lamps", str(hd84), "--listen", "127.0.0.1:0", "--capture-dir", str(captures)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    if not line.startswith("listening on http://"):
        proc.kill()
        pytest.fail(f"hl-http-fixture did not start: {line!r} {proc.stderr.read()}")
    try:
        yield line.split()[-1]
    finally:
        proc.terminate()
        assert proc.wait(timeout=5) == 0, proc.stderr.read()


def get(url, method="GET"):
    req = urllib.request.Request(url, method=method)
    try:
        with urllib.request.urlopen(req, timeout=10) as r:
            return r.status, r.headers.get("Content-Type"), r.read()
    except urllib.error.HTTPError as e:
        return e.code, e.headers.get("Content-Type"), e.read()


def png_stats(path):
    w, h, ch, rows = read_png(path)
    lum = []
    for row in rows:
        for x in range(0, w * ch, ch):
            lum.append((2126 * row[x] + 7152 * row[x + 1] + 722 * row[x + 2]) // 10000)
    mean = sum(lum) / len(lum)
    lit = sum(1 for v in lum if v > 40) / len(lum)
    return w, h, mean, lit, len(set(lum))


def test_http_frames_change_with_the_beam(http_url, tmp_path):
    """/frame.png is a real, lit frame, and it changes within a few seconds (low/high beam)."""
    seen = []
    until = time.monotonic() + 6
    while time.monotonic() < until and len(set(seen)) < 2:
        status, ctype, body = get(http_url + "frame.png")
        assert (status, ctype) == (200, "image/png")
        path = tmp_path / f"frame{len(seen)}.png"
        path.write_bytes(body)
        w, h, mean, lit, levels = png_stats(str(path))
        assert mean > 5 and lit > 0.05 and levels > 50, (mean, lit, levels)
        seen.append(body)
        time.sleep(0.4)
    assert len(set(seen)) == 2, f"{len(seen)} frames in 6 s, all the same"
    status, ctype, body = get(http_url + "status")
    assert (status, ctype) == (200, "application/json")
    json.loads(body)
    status, ctype, body = get(http_url + "metrics")
    assert (status, ctype) == (200, "text/plain; version=0.0.4; charset=utf-8")
    assert b"# TYPE " in body
    assert get(http_url + "nowhere")[0] == 404
    assert get(http_url + "status", method="POST")[0] == 405


def npm_install():
    """playwright-core from the committed lock, into the build tree (npm ci, once per lock)."""
    dest = os.path.join(build_dir(), "browser")
    os.makedirs(dest, exist_ok=True)
    lock = os.path.join(BROWSER_DIR, "package-lock.json")
    stamp = os.path.join(dest, "node_modules", ".hl-lock")
    with open(lock, "rb") as f:
        want = f.read()
    if os.path.exists(stamp) and open(stamp, "rb").read() == want:
        return os.path.join(dest, "node_modules")
    for name in ("package.json", "package-lock.json"):
        shutil.copy(os.path.join(BROWSER_DIR, name), dest)
    subprocess.run(["npm", "ci", "--no-audit", "--no-fund", "--ignore-scripts"], cwd=dest,
                   check=True, timeout=300, capture_output=True)
    with open(stamp, "wb") as f:
        f.write(want)
    return os.path.join(dest, "node_modules")


def test_http_live_page_in_chromium(http_url, tmp_path):
    """chromium loads /, shows a non-black image and counters that change; a screenshot is kept."""
    for tool in ("/usr/bin/chromium", shutil.which("node"), shutil.which("npm")):
        if not tool or not os.access(tool, os.X_OK):
            pytest.fail(f"missing {tool}: tools/setup installs chromium, nodejs and npm")
    modules = npm_install()
    shot = os.path.join(build_dir(), "http-live-view.png")
    if os.path.exists(shot):
        os.unlink(shot)
    env = dict(os.environ, NODE_PATH=modules)
    run = subprocess.run(
        ["node", os.path.join(BROWSER_DIR, "live_view.cjs"), http_url, shot,
         str(tmp_path / "chromium-profile")],
        env=env, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    seen = json.loads(run.stdout.strip().splitlines()[-1])
    print(json.dumps(seen, indent=1))
    assert seen["status"] == 200
    assert seen["title"] == "hdlamp live view"
    assert seen["image"]["mean"] > 10 and seen["image"]["stddev"] > 5
    assert seen["changed"], "no counter changed"
    assert seen["pageErrors"] == []
    if os.environ.get("HL_HTTP_URL"):
        assert seen["capture"].startswith(("written: ", "HTTP 403: captures are disabled"))
    else:
        assert seen["capture"].startswith("written: ")
        with open(seen["capture"][len("written: "):], "rb") as f:
            assert f.read(4) == b"\x76\x2f\x31\x01"  # an EXR file
    # The screenshot, checked independently of the page's own reading.
    w, h, mean, lit, levels = png_stats(shot)
    assert (w, h) == (1280, 800)
    assert lit > 0.05 and levels > 50, (mean, lit, levels)
