"""sched.realtime_priority (base/sched.c): SCHED_FIFO for the CAN thread, the render thread
and its helpers, one step below for the frame stream thread; the main and HTTP threads stay at
SCHED_OTHER. A refusal is a warning naming the reason, and the daemon runs on."""
import json
import signal
import subprocess
import threading
import time

from scenario import HDLAMPD, dbc_path
from proc import run
from threads import check_policies, thread_policies


def model(hdlamp, tmp_path):
    out = tmp_path / "lamps"
    run(hdlamp, "model", "--out", out)
    log = tmp_path / "hold.log"
    run(hdlamp, "scenario", "--dbc", dbc_path("hd84.dbc"), "--out", log, "--hold", "low",
        "--phase-cycles", "20")
    return out, log


def start(lamps, log, priority, prefix=()):
    """hdlampd replaying log in a loop, with a render helper, the stream and HTTP on; returns
    the process and its stderr lines up to the live view's (every thread is up then)."""
    p = subprocess.Popen([*prefix, HDLAMPD, "--replay", str(log), "--loop",
                          "--dbc", dbc_path("hd84.dbc"),
                          "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
                          "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
                          "--set", "render.size=160x90", "--set", "render.threads=3",
                          "--set", "stream.tcp=127.0.0.1:0", "--set", "http.listen=127.0.0.1:0",
                          "--set", f"sched.realtime_priority={priority}"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lines = []
    while not lines or not lines[-1].startswith("hdlampd: live view on"):
        line = p.stderr.readline()
        assert line, f"hdlampd exited early: {lines}"
        lines.append(line)
    # the CAN thread starts last, right after the outputs
    t0 = time.monotonic()
    while "hl-can" not in [comm for comm, _, _ in thread_policies(p.pid).values()]:
        assert time.monotonic() - t0 < 30, "no hl-can thread"
        time.sleep(0.05)
    return p, lines


def stop(p):
    """SIGTERM; the final status and the rest of stderr. Read through the file objects, not
    communicate(), which would miss what readline() has buffered already."""
    out = []
    p.send_signal(signal.SIGTERM)
    t = threading.Thread(target=lambda: out.append(p.stdout.read()))
    t.start()
    err = p.stderr.read()
    t.join(60)
    assert p.wait(60) == 0, err
    return json.loads(out[0].strip().splitlines()[-1]), err


def test_fifo_for_can_render_and_helpers_only(hdlamp, tmp_path):
    lamps, log = model(hdlamp, tmp_path)
    p, lines = start(lamps, log, 10)
    try:
        threads = check_policies(p.pid, 10)
    finally:
        status, err = stop(p)
    print("\n".join(f"{comm:16} {policy} {prio}" for comm, policy, prio in threads))
    names = [comm for comm, _, _ in threads]
    # the render helpers (render.threads 3: two) and at least main, stream and HTTP besides
    assert sorted(n for n in names if n.startswith("hl-render-")) == ["hl-render-1", "hl-render-2"]
    assert len(names) >= 4 + 3
    text = "".join(lines) + err
    assert "hdlampd: sched: the CAN thread runs at SCHED_FIFO 10\n" in text
    assert "hdlampd: sched: the render thread runs at SCHED_FIFO 10\n" in text
    assert "hdlampd: sched: the stream thread runs at SCHED_FIFO 9\n" in text
    assert "warning" not in text
    assert status["frames"]["rendered"] > 0


def test_priority_0_leaves_every_thread_at_sched_other(hdlamp, tmp_path):
    lamps, log = model(hdlamp, tmp_path)
    p, lines = start(lamps, log, 0)
    try:
        check_policies(p.pid, 0)
    finally:
        _, err = stop(p)
    assert "sched:" not in "".join(lines) + err


def test_refusal_names_rlimit_rtprio_and_the_daemon_runs_on(hdlamp, tmp_path):
    """Root without CAP_SYS_NICE and with RLIMIT_RTPRIO 0: what an unprivileged service user
    without LimitRTPRIO= gets."""
    lamps, log = model(hdlamp, tmp_path)
    rtprio = subprocess.run(["sh", "-c", "ulimit -r"], capture_output=True, text=True).stdout
    assert rtprio.strip() == "0", "this test needs RLIMIT_RTPRIO 0"
    p, lines = start(lamps, log, 10, prefix=("setpriv", "--bounding-set=-sys_nice",
                                              "--inh-caps=-sys_nice"))
    try:
        check_policies(p.pid, 0)
    finally:
        status, err = stop(p)
    text = "".join(lines) + err
    for thread, prio in (("CAN", 10), ("render", 10), ("stream", 9)):
        assert (f"hdlampd: sched: warning: the {thread} thread stays at SCHED_OTHER: "
                f"SCHED_FIFO {prio} refused: Operation not permitted: RLIMIT_RTPRIO is 0, "
                f"below {prio}, "
                "and no CAP_SYS_NICE (raise it with LimitRTPRIO= in the unit, ulimit -r or "
                "prlimit --rtprio)\n") in text, text
    assert status["frames"]["rendered"] > 0
