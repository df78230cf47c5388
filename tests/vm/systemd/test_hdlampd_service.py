"""The hdlamp package's hdlampd.service under systemd 252 as PID 1 (docs/service.md, "systemd"):
installed from the .deb, started on a vcan the test brings up, reloaded under a CAN replay,
killed by the watchdog when its renderer hangs (a test-only fault switch) and restarted.

The tests run in file order and share one installation; each leaves the service running or
stopped as the next one expects. Frames are tiny (64x36): this VM is ~50x slower (TCG)."""
import json
import os
import pwd
import re
import subprocess
import tempfile
import threading
import time
import urllib.request

import pytest

from threads import check_policies
from vmutil import replay_can, sh

CONF = "/etc/hdlampd/hdlampd.conf"
DROPIN = "/etc/systemd/system/hdlampd.service.d/test-stall.conf"
LAMPS = "/var/lib/hdlampd/lamps"
DBC = "/usr/share/hdlamp/dbc/hd84.dbc"
IFACE = "vcan1"  # brought up by the test: READY must wait for it
RELOAD_CYCLES = 250  # 5 s of ECU cycles (the VM's sender needs ~25 s) across the reload
WATCHDOG_S = 4


def show(prop):
    return sh("systemctl", "show", "-p", prop, "--value", "hdlampd.service").strip()


def wait_for(pred, timeout, what):
    t0 = time.monotonic()
    while True:
        v = pred()
        if v:
            return time.monotonic() - t0
        assert time.monotonic() - t0 < timeout, f"{what}: not within {timeout} s"
        time.sleep(0.5)


def journal():
    """The unit's journal: the daemon's lines and systemd's about the unit, messages only."""
    return sh("journalctl", "-u", "hdlampd.service", "--no-pager", "-o", "cat").splitlines()


def status():
    with urllib.request.urlopen("http://127.0.0.1:8080/status", timeout=30) as r:
        return json.loads(r.read())


def lamp(st, name):
    return next(l for l in st["lamps"] if l["name"] == name)


def set_conf(changes):
    """Sets SECTION.KEY values in the installed hdlampd.conf, each line found once."""
    lines, section, done = open(CONF).read().splitlines(), "", set()
    for i, line in enumerate(lines):
        m = re.match(r"\[(\w+)\]", line)
        if m:
            section = m.group(1)
        m = re.match(r"(\w+) =", line)
        if m and f"{section}.{m.group(1)}" in changes:
            key = f"{section}.{m.group(1)}"
            lines[i] = f"{m.group(1)} = {changes[key]}"
            done.add(key)
    assert done == set(changes), set(changes) - done
    open(CONF, "w").write("\n".join(lines) + "\n")


def hold_log(tmp, cycles):
    """A candump log of `cycles` low-beam ECU cycles without faults, and its counters."""
    log, expect = os.path.join(tmp, f"hold{cycles}.log"), os.path.join(tmp, f"hold{cycles}.jsonl")
    sh("hdlamp", "scenario", "--dbc", DBC, "--out", log, "--expect", expect, "--hold", "low",
       "--phase-cycles", str(cycles), "--iface", IFACE, timeout=300)
    counters = [json.loads(l) for l in open(expect) if '"counters"' in l][-1]
    return log, counters


@pytest.fixture(scope="module")
def installed():
    """dpkg -i of the package; the HD84 lamps; the config on IFACE with tiny frames."""
    deb = os.environ.get("HL_DEB")
    assert deb and os.path.isfile(deb), "HL_DEB must name the hdlamp .deb"
    t0 = time.monotonic()
    # man-db's trigger would rebuild the whole man index, minutes under TCG (its own switch)
    if os.path.exists("/var/lib/man-db/auto-update"):
        os.remove("/var/lib/man-db/auto-update")
    sh("dpkg", "-i", deb, timeout=600)
    print(f"\ndpkg -i {os.path.basename(deb)}: {time.monotonic() - t0:.1f} s")
    tmp = tempfile.mkdtemp(prefix="hl-systemd-", dir="/var/tmp")
    t0 = time.monotonic()
    sh("hdlamp", "model", "--out", LAMPS, timeout=900)
    print(f"hdlamp model --out {LAMPS}: {time.monotonic() - t0:.1f} s")
    set_conf({"can.interface": IFACE, "render.size": "64x36", "render.combine": "cpu",
              "render.headlight": "cpu", "render.threads": "2",
              # a sender in this slow VM may pause longer than the ECU's 100 ms
              "can.timeout_ms": "1000"})
    return tmp


def test_package_creates_user_groups_and_unit(installed):
    u = pwd.getpwnam("hdlampd")  # systemd-sysusers in postinst
    assert u.pw_dir == "/var/lib/hdlampd" and u.pw_shell == "/usr/sbin/nologin"
    groups = sh("id", "-nG", "hdlampd").split()
    assert sorted(groups) == ["gpio", "hdlampd", "render"]
    assert show("LoadState") == "loaded"
    assert show("FragmentPath") in ("/lib/systemd/system/hdlampd.service",
                                    "/usr/lib/systemd/system/hdlampd.service")
    assert show("LimitRTPRIO") == "10"
    assert show("CPUSchedulingPolicy") == "0"  # SCHED_OTHER: the unit sets no policy itself
    assert show("ActiveState") == "inactive"
    assert os.stat("/var/lib/hdlampd/captures").st_uid == u.pw_uid  # systemd-tmpfiles


def test_ready_only_once_lamps_renderer_and_bus_are_up(installed):
    assert not os.path.exists(f"/sys/class/net/{IFACE}")
    t0 = time.monotonic()
    sh("systemctl", "start", "--no-block", "hdlampd.service")
    # lamps loaded and renderer up: the daemon says so; the bus is not there yet
    wait_for(lambda: any(l.startswith("hdlampd: renderer:") for l in journal()), 600,
             "the renderer line in the journal")
    t_renderer = time.monotonic() - t0
    time.sleep(3)
    assert (show("ActiveState"), show("SubState")) == ("activating", "start")
    # STATUS lines come every second from the start; READY=1 waits for the bus
    assert re.fullmatch(r"(left: 0 cycles[^;]*; right: 0 cycles[^;]*; \d+ frames, bus down)?",
                        show("StatusText")), show("StatusText")
    renderer = next(l for l in journal() if l.startswith("hdlampd: renderer:"))
    print(f"{renderer} (after {t_renderer:.1f} s)")
    # No GPU in this VM (no /dev/dri): the hardened unit's EGL context is Mesa's llvmpipe.
    assert "llvmpipe" in renderer and "combine on cpu, headlight pass on cpu" in renderer
    print("/dev/dri: " + (" ".join(sorted(os.listdir("/dev/dri")))
                          if os.path.isdir("/dev/dri") else "none in this VM"))

    t1 = time.monotonic()
    sh("hl-vcan", "add", IFACE)
    waited = wait_for(lambda: show("ActiveState") == "active", 120, "READY after the bus")
    print(f"READY {waited:.1f} s after {IFACE} came up ({time.monotonic() - t0:.1f} s after start)")
    assert show("SubState") == "running"
    assert f"hdlampd: can: '{IFACE}': up" in journal()
    # the STATUS line the event loop sends every second
    wait_for(lambda: re.fullmatch(r"left: 0 cycles[^;]*; right: 0 cycles[^;]*; \d+ frames, "
                                  r"bus (?!down)\S+", show("StatusText")), 60,
             "the counters' STATUS line")
    out = subprocess.run(["systemctl", "status", "--no-pager", "hdlampd.service"],
                         capture_output=True, text=True).stdout
    assert re.search(r'Status: "left: 0 cycles[^;]*; right: 0 cycles[^;]*; \d+ frames, bus ', out), out
    assert time.monotonic() - t1 < 120


def test_threads_in_the_service_fifo_only_for_can_and_render(installed):
    pid = int(show("MainPID"))
    assert pid > 0
    uid = pwd.getpwnam("hdlampd").pw_uid
    st = open(f"/proc/{pid}/status").read()
    assert re.search(rf"^Uid:\s+{uid}\s+{uid}\s+{uid}\s+{uid}$", st, re.M), st
    assert re.search(r"^CapEff:\s+0+$", st, re.M)  # no capabilities: LimitRTPRIO does it
    limits = open(f"/proc/{pid}/limits").read()
    assert re.search(r"^Max realtime priority\s+10\s+10\s*$", limits, re.M), limits
    threads = check_policies(pid, 10)
    print("\n".join(f"  {comm:16} {policy} {prio}" for comm, policy, prio in threads))
    assert [c for c, _, _ in threads].count("hl-render-1") == 1  # render.threads 2: one helper
    j = journal()
    assert "hdlampd: sched: the CAN thread runs at SCHED_FIFO 10" in j
    assert "hdlampd: sched: the render thread runs at SCHED_FIFO 10" in j
    assert not [l for l in j if "sched: warning" in l]


def test_reload_during_a_replay_loses_no_cycle(installed):
    log, counters = hold_log(installed, RELOAD_CYCLES)
    assert counters["left"]["cycles"] == counters["right"]["cycles"] == RELOAD_CYCLES
    pid = show("MainPID")
    before = status()
    c0 = {n: lamp(before, n)["cycles"] for n in ("left", "right")}
    late = []
    sender = threading.Thread(target=lambda: late.append(replay_can(log, channel=IFACE)))
    sender.start()
    wait_for(lambda: lamp(status(), "left")["cycles"] >= c0["left"] + 50, 120,
             "50 cycles before the reload")
    set_conf({"render.exposure_ev": "1.5"})
    at_reload = lamp(status(), "left")["cycles"] - c0["left"]
    t0 = time.monotonic()
    sh("systemctl", "reload", "hdlampd.service", timeout=120)
    t_reload = time.monotonic() - t0
    after_reload = lamp(status(), "left")["cycles"] - c0["left"]
    sender.join(600)
    assert not sender.is_alive()

    def settled():
        a = status()
        time.sleep(1)
        b = status()
        return b if [lamp(a, n)["cycles"] for n in c0] == [lamp(b, n)["cycles"] for n in c0] \
            else None
    wait_for(settled, 120, "the counters to settle")
    end = status()
    print(f"reload at cycle {at_reload}, back in {t_reload:.2f} s at cycle {after_reload} of "
          f"{RELOAD_CYCLES}; sender late (median, max) {late[0][0]:.1f}, {late[0][1]:.1f} ms; "
          f"frames rendered {end['frames']['rendered']}")
    # the replay ran on both sides of the reload
    assert 0 < at_reload < RELOAD_CYCLES and after_reload < RELOAD_CYCLES
    for n in ("left", "right"):
        got = lamp(end, n)
        assert got["cycles"] - c0[n] == RELOAD_CYCLES, (n, got)
        assert (got["lost_cycles"], got["crc_errors"], got["incomplete"]) == (0, 0, 0), (n, got)
    assert show("MainPID") == pid and show("NRestarts") == "0"
    assert show("StatusText").startswith("left: ")  # STATUS lines again after the reload
    j = journal()
    assert ("hdlampd: reloaded: lamps.failsafe and render.exposure_ev applied; other keys take "
            "effect at restart") in j
    assert not [l for l in j if l.startswith("hdlampd: reload:")]  # no reload error
    set_conf({"render.exposure_ev": "0"})


def test_watchdog_kills_a_stuck_renderer_and_systemd_restarts_it(installed):
    log, _ = hold_log(installed, 60)
    os.makedirs(os.path.dirname(DROPIN), exist_ok=True)
    with open(DROPIN, "w") as f:
        f.write(f"[Service]\nWatchdogSec={WATCHDOG_S}s\n"
                "Environment=HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES=10\n")
    try:
        sh("systemctl", "daemon-reload")
        sh("systemctl", "restart", "hdlampd.service", timeout=600)
        n0, pid0 = int(show("NRestarts")), show("MainPID")
        assert show("WatchdogUSec") == f"{WATCHDOG_S}s"
        skip = len(journal())
        # no cycle, no frame: the idle daemon pings its watchdog and lives on
        time.sleep(2 * WATCHDOG_S)
        assert (int(show("NRestarts")), show("MainPID")) == (n0, pid0)
        t0 = time.monotonic()
        replay_can(log, channel=IFACE)  # 60 cycles: the renderer hangs after 10 frames
        wait_for(lambda: int(show("NRestarts")) == n0 + 1 and show("ActiveState") == "active"
                 and show("MainPID") not in ("0", pid0), 600, "the restart after the watchdog")
        print(f"killed by the watchdog and READY again {time.monotonic() - t0:.1f} s after "
              "the replay started")
        j = journal()[skip:]
        print("\n".join("  " + l for l in j if "atchdog" in l or "test-only" in l))
        assert f"hdlampd.service: Watchdog timeout (limit {WATCHDOG_S}s)!" in j
        assert any("Killing process " + pid0 in l and "SIGABRT" in l for l in j), j
        assert "hdlampd.service: Failed with result 'watchdog'." in j
        assert ("hdlampd: HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES=10: test-only fault: the render "
                "thread hangs after 10 frames") in j
        # the new process renders nothing yet, so it does not hang: no second restart
        time.sleep(2 * WATCHDOG_S)
        assert int(show("NRestarts")) == n0 + 1 and show("ActiveState") == "active"
    finally:
        os.remove(DROPIN)
        sh("systemctl", "daemon-reload")


def test_stop_and_the_journal_shows_the_daemon(installed):
    sh("systemctl", "stop", "hdlampd.service", timeout=120)
    assert show("ActiveState") == "inactive"
    j = journal()
    for want in ("hdlampd: renderer: EGL ", "hdlampd: frame stream on ",
                 "hdlampd: live view on http://127.0.0.1:8080/",
                 "hdlampd: Terminated: stopping"):
        assert any(l.startswith(want) for l in j), want
    # the run's status, printed on stdout at exit, is the last thing the daemon wrote
    last = [l for l in j if l.startswith('{"')][-1]
    assert lamp(json.loads(last), "left")["lost_cycles"] == 0
