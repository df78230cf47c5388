#!/usr/bin/python3
"""tools/bench's loop section (docs/loop.md): the closed loop, hdlampd (the IIHS-like straight
approach, restbus) <-> hdlamp ecu (glare-free high beam), run again and again for SECONDS at
50 Hz; each run's report (--exit-at-end --report) gives the oncoming car's enter event: the
latency from the camera cycle that first carried it to the restbus's send (input), the first
dimming cycle under its glare limit (mask) and the first frame under it (frame).

Where the host has a CAN interface that is up (vcan or real: `ip -j link`), the loop runs on it
and the latencies are reported in ms (p50, p99). Where it has none, the section runs itself
inside the test VM (tests/vm/run, vcan0 under TCG) and reports the latencies in ECU cycles of
20 ms: TCG runs everything ~50x slower than the host, so its milliseconds are no speed figure.

  tools/bench_loop.py [--seconds S] [--out DIR] [--build DIR] [--size WxH] [--iface IFACE]
"""
import argparse
import json
import os
import platform
import signal
import statistics
import subprocess
import sys
import tempfile
import time

SRC = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SCENARIO = os.path.join(SRC, "scenarios", "iihs-approach-straight.json")
ECU_CYCLE_MS = 20.0


def log(msg):
    print(f"bench loop: {msg}", file=sys.stderr, flush=True)


def can_interfaces():
    """CAN interfaces (vcan or real) that are up, from `ip -j link`."""
    try:
        links = json.loads(subprocess.run(["ip", "-j", "-d", "link"], capture_output=True,
                                          text=True, check=True).stdout)
    except (OSError, subprocess.CalledProcessError, ValueError):
        return []
    out = []
    for link in links:
        kind = link.get("linkinfo", {}).get("info_kind")
        if (kind in ("can", "vcan") or link.get("link_type") == "can") and \
                "UP" in link.get("flags", []):
            out.append(link["ifname"])
    return out


def pct(values, p):
    if not values:
        return None
    v = sorted(values)
    k = max(0, min(len(v) - 1, int(-(-p * len(v) // 1)) - 1))
    return round(v[k], 3)


def run_loop(build, iface, seconds, size, out_dir):
    """The closed loop on iface for at least seconds: the ECU runs throughout, hdlampd once per
    scenario pass. Returns the section's dict."""
    hdlamp = os.path.join(build, "tools", "hdlamp")
    hdlampd = os.path.join(build, "daemon", "hdlampd")
    lamps = os.path.join(tempfile.gettempdir(), "hdlamp_bench_loop_lamps")
    if not os.path.exists(os.path.join(lamps, "hd84_left.lid.exr")):
        subprocess.run([hdlamp, "model", "--out", lamps], check=True, capture_output=True)
    ecu = subprocess.Popen([hdlamp, "ecu", "--can", iface, "--lamps", lamps],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    start = json.loads(ecu.stdout.readline())
    if start.get("event") != "start":
        raise RuntimeError(f"hdlamp ecu did not start: {start}")
    runs, events, verdicts, codes = [], [], [], []
    t_end = time.monotonic() + seconds
    try:
        while time.monotonic() < t_end or not runs:
            report = os.path.join(out_dir, "loop_report.json")
            r = subprocess.run(
                [hdlampd, "--can", iface, "--dbc", os.path.join(SRC, "dbc", "hd84.dbc"),
                 "--scenario", SCENARIO, "--restbus", iface, "--exit-at-end",
                 "--report", report,
                 "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
                 "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
                 "--set", f"render.size={size}", "--set", "stream.tcp=",
                 "--set", "http.listen=", "--set", "restbus.light_switch=high"],
                capture_output=True, text=True, timeout=600)
            codes.append(r.returncode)
            if r.returncode not in (0, 3):
                raise RuntimeError(f"hdlampd exit {r.returncode}: {r.stderr[-1000:]}")
            with open(report) as f:
                rep = json.load(f)
            verdicts.append(rep["verdict"])
            enter = [e for e in rep["loop"]["event_list"] if e["event"] == "enter"]
            runs.append({"frames": rep["frames"], "cycles": rep["cycles"],
                         "verdict": rep["verdict"], "exit": r.returncode,
                         "frame_latency_ms": [e["latency_ms"].get("frame") for e in enter],
                         "frames_over_late": sum(a["frames_over_late"]
                                                 for a in rep["loop"]["actors"])})
            events += [e for e in rep["loop"]["event_list"]
                       if e["event"] == "enter" and e["masked"]]
    finally:
        ecu.send_signal(signal.SIGINT)
        try:
            ecu.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            ecu.kill()
    lat = {k: [e["latency_ms"][k] for e in events] for k in ("input", "mask", "frame")}
    return {"interface": iface, "scenario": os.path.relpath(SCENARIO, SRC),
            "render_size": size, "seconds_asked": seconds, "runs": len(runs),
            "runs_verdict_held": sum(1 for v in verdicts if v), "exit_codes": codes,
            "enter_events_masked": len(events),
            "latency_ms": {k: {"p50": pct(v, 0.5), "p99": pct(v, 0.99), "max": pct(v, 1.0),
                               "n": len(v)} for k, v in lat.items()},
            "latency_cycles": {k: {"p50": pct([x / ECU_CYCLE_MS for x in v], 0.5),
                                   "p99": pct([x / ECU_CYCLE_MS for x in v], 0.99),
                                   "max": pct([x / ECU_CYCLE_MS for x in v], 1.0)}
                               for k, v in lat.items()},
            "per_run": [{k: r[k] for k in ("exit", "frame_latency_ms", "frames_over_late")}
                        for r in runs],
            "frames_rendered_per_run": statistics.median(r["frames"]["rendered"] for r in runs),
            "cycles_not_rendered_total": sum(c["not_rendered"] for r in runs
                                             for c in r["cycles"].values())}


def section(build, out_dir, seconds, size=None, iface=None):
    """The loop section: on the host's CAN interface (frames of size, default 320x180), or in
    the VM (default 64x36: TCG renders ~50x slower)."""
    load_start = os.getloadavg()
    s = measure_section(build, out_dir, seconds, size, iface)
    s["loadavg_host"] = {"start": [round(x, 2) for x in load_start],
                         "end": [round(x, 2) for x in os.getloadavg()]}
    return s


def measure_section(build, out_dir, seconds, size, iface):
    ifaces = [iface] if iface else can_interfaces()
    if ifaces:
        s = run_loop(build, ifaces[0], seconds, size or "320x180", out_dir)
        s["where"] = "host"
        s["timing"] = "host: the latencies in ms are speed figures of this machine"
        return s
    vm_out = os.path.join(out_dir, "loop_vm")
    os.makedirs(vm_out, exist_ok=True)
    cmd = [os.path.join(SRC, "tests", "vm", "run"), "--out", vm_out, "--timeout",
           str(int(seconds * 3 + 900)), "--", sys.executable, os.path.abspath(__file__),
           "--inside", "--seconds", str(seconds), "--build", build, "--size", size or "64x36"]
    log(f"no CAN interface on the host: running the loop in the VM ({seconds:g} s)")
    r = subprocess.run(cmd, capture_output=True, text=True)
    path = os.path.join(vm_out, "loop.json")
    if r.returncode != 0 or not os.path.exists(path):
        raise RuntimeError(f"tests/vm/run: exit {r.returncode}: {r.stderr[-2000:]}")
    with open(path) as f:
        s = json.load(f)
    s["where"] = "vm"
    s["timing"] = ("QEMU/TCG VM on vcan0 (the host has no CAN): everything runs ~50x slower "
                   "than on the host, so the ms are no speed figure; read latency_cycles "
                   "(ECU cycles of 20 ms) as the loop's behaviour")
    s["host"] = {"machine": platform.machine(), "cpus": os.cpu_count()}
    return s


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=float, default=300.0)
    ap.add_argument("--out", default=os.path.join(SRC, "bench-out"))
    ap.add_argument("--build", default=os.path.join(SRC, "build"))
    ap.add_argument("--size", help="render size (default 320x180 on the host, 64x36 in the VM)")
    ap.add_argument("--iface", help="the CAN interface (default: the first one up)")
    ap.add_argument("--inside", action="store_true", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.inside:  # in the VM: vcan0, results under $HL_VM_OUT
        out = os.environ["HL_VM_OUT"]
        s = run_loop(a.build, "vcan0", a.seconds, a.size or "64x36", out)
        with open(os.path.join(out, "loop.json"), "w") as f:
            json.dump(s, f, indent=1)
        return 0
    os.makedirs(a.out, exist_ok=True)
    s = section(a.build, a.out, a.seconds, a.size, a.iface)
    with open(os.path.join(a.out, "loop.json"), "w") as f:
        json.dump(s, f, indent=1)
    print(json.dumps(s, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
