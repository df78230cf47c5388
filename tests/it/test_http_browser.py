"""The HTTP live view in a real browser (Debian's chromium, headless, driven by playwright-core
from npm) and over plain HTTP.

The server under test is hdlampd replaying the drive scenario in a loop (low/high beam, the
glare-free sweep, bend light, faults) on the road scene, or HL_HTTP_URL when set.
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
    """hdlampd itself: the drive scenario replayed in a loop, the road scene, HTTP on a free
    port with captures allowed (or HL_HTTP_URL, a server started elsewhere)."""
    url = os.environ.get("HL_HTTP_URL")
    if url:
        yield url.rstrip("/") + "/"
        return
    from scenario import HDLAMPD, dbc_path, generate
    from proc import run

    work = tmp_path_factory.mktemp("live")
    log, _, _ = generate(os.environ["HDLAMP"], dbc_path("hd84.dbc"), str(work), phase=25)
    proc = subprocess.Popen(
        [HDLAMPD, "--replay", log, "--loop", "--dbc", dbc_path("hd84.dbc"),
         "--set", f"lamps.left={hd84}/hd84_left.lid.exr",
         "--set", f"lamps.right={hd84}/hd84_right.lid.exr",
         "--set", "render.size=640x360", "--set", "stream.tcp=",
         "--set", "http.listen=127.0.0.1:0", "--set", "http.capture=true",
         "--set", f"capture.dir={work}/captures"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    port = None
    while port is None:
        line = proc.stderr.readline()
        if not line:
            pytest.fail(f"hdlampd did not start: {proc.stdout.read()}")
        if "live view on http://" in line:
            port = int(line.rsplit("(port ", 1)[1].split(")")[0])
    try:
        yield f"http://127.0.0.1:{port}/"
    finally:
        proc.send_signal(2)
        assert proc.wait(timeout=10) == 0


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
    until = time.monotonic() + 60  # a generous wait for the beam to change, not a speed
    while time.monotonic() < until and len(set(seen)) < 2:
        status, ctype, body = get(http_url + "frame.png")
        if status == 503 and not seen:  # nothing rendered yet: the first cycle is on its way
            time.sleep(0.1)
            continue
        assert (status, ctype) == (200, "image/png")
        path = tmp_path / f"frame{len(seen)}.png"
        path.write_bytes(body)
        w, h, mean, lit, levels = png_stats(str(path))
        assert mean > 5 and lit > 0.05 and levels > 50, (mean, lit, levels)
        seen.append(body)
        time.sleep(0.4)
    assert len(set(seen)) == 2, f"{len(seen)} frames in 60 s, all the same"
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
        written = seen["capture"][len("written: "):]  # the capture's directory
        for name in ("hdr.exr", "lux.exr", "left.lid.exr", "right.lid.exr"):
            with open(os.path.join(written, name), "rb") as f:
                assert f.read(4) == b"\x76\x2f\x31\x01"  # an EXR file
    # The screenshot, checked independently of the page's own reading.
    w, h, mean, lit, levels = png_stats(shot)
    assert (w, h) == (1280, 800)
    assert lit > 0.05 and levels > 50, (mean, lit, levels)
