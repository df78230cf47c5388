#!/usr/bin/python3
"""tools/bench's suite section (docs/lab.md "Speed", docs/performance.md "The ADB lab's suites"):
how long the whole FMVSS 108 ADB suite takes in software in the loop, and what the photometers
cost per frame.

  whole suite   hdlamp suite run fmvss108-adb (all 28 variants, no frames), RUNS times, the process
                pinned to one core: wall and CPU seconds with the reference ECU in the loop
                (restbus, virtual bus, traces written) and with the high beam held (no ECU, no
                bus); the scenario seconds the suite drives and its x real time; the same with
                the ECU exported as an FMU (hdlamp ecu --fmu, its child process on the same core)
  per frame     build/tools/hdlamp-bench-suite: hl_suite_measure_frame on the HD84 pair's high
                beam at every frame of the scenario of each shipped suite with the most photometers (FMVSS: the
                stimulus vehicle's photometers; R149: the glare table at the driver's eye; IIHS:
                both road edges and the glare line, 1 m apart): median and p99 in µs

Writes DIR/suite.json and DIR/suite.png; tools/bench puts the same object into bench.json's
"suite" key. A bench, not a test: nothing here fails on a speed (the goal, every variant in
under 10 s on one core, is reported as met or not).

  tools/bench_suite.py [--runs N] [--out DIR] [--build DIR] [--core C]
"""
import argparse
import json
import os
import resource
import shlex
import statistics
import subprocess
import sys
import tempfile
import time

SRC = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
GOAL_S = 10.0  # the goal: every variant of the FMVSS suite in SIL, one core, no frames


def _children_cpu_s():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _stats(xs, nd=3):
    return {"median": round(statistics.median(xs), nd), "min": round(min(xs), nd),
            "max": round(max(xs), nd), "n": len(xs)}


def _loadavg():
    with open("/proc/loadavg") as f:
        return [float(x) for x in f.read().split()[:3]]


def suite_once(hdlamp, core, args, out):
    cmd = [hdlamp, "suite", "run", "fmvss108-adb", "--out", out] + list(args)
    cpu0, t0 = _children_cpu_s(), time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True,
                       preexec_fn=lambda: os.sched_setaffinity(0, {core}))
    wall, cpu = time.monotonic() - t0, _children_cpu_s() - cpu0
    if r.returncode not in (0, 3):
        raise RuntimeError(f"hdlamp suite exited {r.returncode}: {r.stderr.strip()[-2000:]}")
    with open(os.path.join(out, "report.json")) as f:
        rep = json.load(f)
    scen_s = 0.0
    for v in rep["variants"]:
        with open(os.path.join(out, v["scenario_file"])) as f:
            scen_s += json.load(f)["duration_s"]
    return {"wall_s": wall, "cpu_s": cpu, "variants": len(rep["variants"]),
            "frames": sum(v["frames"] for v in rep["variants"]), "scenario_s": scen_s,
            "cases": rep["totals"]["cases"], "failed": rep["totals"]["failed"],
            "exit": r.returncode, "command": " ".join(shlex.quote(c) for c in cmd)}


def whole(hdlamp, core, runs, what, args, tmp, log):
    load0 = _loadavg()
    rs = [suite_once(hdlamp, core, args, os.path.join(tmp, f"run{i}")) for i in range(runs)]
    r0 = rs[0]
    s = {"what": what, "runs": runs, "pinned_to_core": core, "command": r0["command"],
         "variants": r0["variants"], "frames": r0["frames"], "cases": r0["cases"],
         "failed": r0["failed"], "scenario_s": round(r0["scenario_s"], 3),
         "wall_s": _stats([r["wall_s"] for r in rs]),
         "cpu_s": _stats([r["cpu_s"] for r in rs]),
         "x_real_time": _stats([r["scenario_s"] / r["wall_s"] for r in rs], 1),
         "ms_per_variant": _stats([1000 * r["wall_s"] / r["variants"] for r in rs], 2),
         "exit_codes": sorted({r["exit"] for r in rs}),
         "loadavg_start": load0, "loadavg_end": _loadavg()}
    log(f"suite: {what}: {s['wall_s']['median']:g} s for {s['variants']} variants "
        f"({s['x_real_time']['median']:g} x real time), median of {runs}")
    return s


def section(build, out, runs=5, core=None, log=print):
    hdlamp = os.path.join(build, "tools", "hdlamp")
    bench = os.path.join(build, "tools", "hdlamp-bench-suite")
    for p in (hdlamp, bench):
        if not os.access(p, os.X_OK):
            raise RuntimeError(f"{p}: not built")
    if core is None:
        core = max(os.sched_getaffinity(0))
    s = {"source": "tools/bench_suite.py", "goal_s": GOAL_S}
    with tempfile.TemporaryDirectory(prefix="hl-bench-suite-") as tmp:
        fmu = os.path.join(tmp, "ref.fmu")
        subprocess.run([hdlamp, "ecu", "--fmu", fmu], check=True, capture_output=True)
        s["reference"] = whole(hdlamp, core, runs, "the reference ECU in the loop", [], tmp, log)
        s["fmu"] = whole(hdlamp, core, runs, "the reference exported as an FMU",
                         ["--ecu", fmu], tmp, log)
        s["preset_high"] = whole(hdlamp, core, runs, "the high beam held (no ECU, no bus)",
                                 ["--preset", "high"], tmp, log)
    r = subprocess.run(["taskset", "-c", str(core), bench, os.path.join(SRC, "suites"),
                        "--runs", "200"], capture_output=True, text=True, check=True)
    s["per_frame"] = json.loads(r.stdout)
    s["goal_met"] = s["reference"]["wall_s"]["median"] < GOAL_S
    with open(os.path.join(out, "suite.json"), "w") as f:
        json.dump(s, f, indent=1)
    return s


def plot(s, path, footer=""):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.8))
    keys = [("reference", "reference ECU"), ("fmu", "ECU as FMU"), ("preset_high", "high held")]
    med = [s[k]["wall_s"]["median"] for k, _ in keys]
    lo = [s[k]["wall_s"]["median"] - s[k]["wall_s"]["min"] for k, _ in keys]
    hi = [s[k]["wall_s"]["max"] - s[k]["wall_s"]["median"] for k, _ in keys]
    a1.bar([n for _, n in keys], med, yerr=[lo, hi], color=["#3070b0", "#70a0d0", "#909090"],
           capsize=6)
    a1.axhline(s["goal_s"], color="#c03030", ls="--", label=f"goal {s['goal_s']:g} s")
    for i, k in enumerate(k for k, _ in keys):
        a1.text(i, med[i], f"{med[i]:.2f} s\n{s[k]['x_real_time']['median']:g}x",
                ha="center", va="bottom", fontsize=9)
    r = s["reference"]
    a1.set_title(f"FMVSS 108 ADB suite, {r['variants']} variants, {r['scenario_s']:.0f} s of "
                 f"scenario, one core", fontsize=10)
    a1.set_ylabel("wall time (s), median of runs")
    a1.legend()
    pf = s["per_frame"]
    names = list(pf)
    a2.bar(names, [pf[n]["median_us"] for n in names], color="#3070b0")
    for i, n in enumerate(names):
        a2.text(i, pf[n]["median_us"], f"{pf[n]['median_us']:.2f} µs\n"
                f"{pf[n]['readings_per_frame']:g} readings", ha="center", va="bottom", fontsize=9)
    a2.set_yscale("log")
    a2.set_ylim(top=max(pf[n]["median_us"] for n in names) * 5)
    a1.set_ylim(top=max(med + [s["goal_s"]]) * 1.15)
    a2.set_ylabel("µs per frame (median)")
    a2.set_title("measuring a frame (hdlamp-bench-suite)", fontsize=10)
    fig.text(0.01, 0.01, footer, fontsize=7, color="#555555")
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def summary(s):
    out = []
    for k in ("reference", "fmu", "preset_high"):
        v = s[k]
        out.append(f"{v['what']}: {v['wall_s']['median']:g} s ({v['wall_s']['min']:g}.."
                   f"{v['wall_s']['max']:g}) for {v['variants']} variants, "
                   f"{v['x_real_time']['median']:g} x real time, {v['failed']} cases failed")
    for n, v in s["per_frame"].items():
        out.append(f"per frame, {n} ({v['scenario']}): {v['median_us']:g} µs median, "
                   f"p99 {v['p99_us']:g} µs, {v['readings_per_frame']:g} readings")
    out.append(f"goal (reference ECU, all variants < {s['goal_s']:g} s on one core): "
               f"{'met' if s['goal_met'] else 'not met'}")
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--out", default=os.path.join(SRC, "bench-out"))
    ap.add_argument("--build", default=os.path.join(SRC, "build"))
    ap.add_argument("--core", type=int)
    ap.add_argument("--replot", action="store_true",
                    help="measure nothing: draw DIR/suite.png again from DIR/suite.json")
    a = ap.parse_args()
    if a.runs < 1:
        print("bench_suite: --runs >= 1 expected", file=sys.stderr)
        return 2
    os.makedirs(a.out, exist_ok=True)
    if a.replot:
        with open(os.path.join(a.out, "suite.json")) as f:
            s = json.load(f)
        plot(s, os.path.join(a.out, "suite.png"), f"{s['machine']['cpu_model']}, "
             f"{s['machine']['cpus_usable']} cores; {s['started']}; {s['command']}")
        print(summary(s))
        return 0
    try:
        s = section(a.build, a.out, a.runs, a.core)
    except (RuntimeError, OSError, subprocess.CalledProcessError, ValueError, KeyError) as e:
        print(f"bench_suite: failed: {e!r}", file=sys.stderr)
        return 1
    s["command"] = " ".join(shlex.quote(x) for x in sys.argv)
    s["started"] = time.strftime("%Y-%m-%d %H:%M:%S %Z")
    with open("/proc/cpuinfo") as f:
        cpu = next((ln.split(":", 1)[1].strip() for ln in f if ln.startswith("model name")), "?")
    s["machine"] = {"cpu_model": cpu, "cpus_usable": len(os.sched_getaffinity(0))}
    with open(os.path.join(a.out, "suite.json"), "w") as f:
        json.dump(s, f, indent=1)
    plot(s, os.path.join(a.out, "suite.png"),
         f"{cpu}, {s['machine']['cpus_usable']} cores; {s['started']}; {s['command']}")
    print(summary(s))
    print(os.path.join(a.out, "suite.json") + ", " + os.path.join(a.out, "suite.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
