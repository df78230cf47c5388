#!/usr/bin/python3
"""tools/bench's sil section (docs/sil.md, docs/performance.md "Software in the loop"): how fast
the loop runs in virtual time, and the real-time mode's CAN -> frame latency.

  speed         hdlamp sil on the IIHS straight approach (8.388 s of scenario), RUNS times, the
                process pinned to one core: the loop's x real time from its own log line ("the
                loop ran X s of the scenario in Y s (Z x real time; ...)"), and the whole
                process's (scenario s / process wall s, start-up included); with the reference
                ECU in process and with the same ECU exported as an FMU (hdlamp ecu --fmu),
                which runs in a child process of hdlamp sil (fmu/child.h) pinned to the same core
  frames        the same with --frames DIR --set render.size=1280x720: every judged frame
                rendered and written as a PNG; x real time and ms per frame (skipped, with the
                reason, when this build's hdlamp sil has no --frames)
  realtime      hdlampd --ecu reference (the ECU in process on the virtual bus vbus0, no CAN
                interface) in real time on the demo drive (30 s, the scenario with the most
                moving road users), one fresh daemon per pass (--exit-at-end: past its end the
                scenario's clock holds and the scene stands still), passes until SECONDS,
                1280x720 frames to a stream client: CAN -> frame latency (the client's
                CLOCK_MONOTONIC when the whole frame is in minus the header's t_cycle_done_ns, as
                tools/bench's e2e section), p50/p99/max; frames; lamp cycles lost or not rendered
                from the daemon's own counters at each exit (0 expected); CPU; loadavg

Writes DIR/sil.json, DIR/sil_latency_ms.json and DIR/sil.png; tools/bench puts the same object
into bench.json's "sil" key. A bench, not a test: nothing here fails on a speed.

  tools/bench_sil.py [--seconds S] [--runs N] [--out DIR] [--build DIR] [--core C] [--rt]
"""
import argparse
import json
import os
import re
import resource
import shlex
import shutil
import signal
import statistics
import subprocess
import sys
import threading
import time

SRC = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SCENARIO = os.path.join(SRC, "scenarios", "iihs-approach-straight.json")
RT_SCENARIO = os.path.join(SRC, "scenarios", "demo-drive.json")
SIZE = "1280x720"
GOAL_X_REAL_TIME = 200.0  # the goal: the IIHS straight approach, no frames, one core
SPEED_RE = re.compile(r"the loop ran ([0-9.]+) s of the scenario in ([0-9.]+) s "
                      r"\(([0-9.]+) x real time")


def _children_cpu_s():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _stats(v, nd=1):
    v = sorted(v)
    return {"median": round(statistics.median(v), nd), "min": round(v[0], nd),
            "max": round(v[-1], nd), "n": len(v)}


def sil_once(ctx, hdlamp, ecu, core, extra=(), report=None):
    """One hdlamp sil run pinned to core: the loop's figures from its log line, the process's
    wall and CPU time (its children's included: an FMU's child process)."""
    cmd = [hdlamp, "sil", SCENARIO, "--ecu", ecu] + (["--report", report] if report else []) + \
        list(extra)
    cpu0, t0 = _children_cpu_s(), time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True,
                       preexec_fn=lambda: os.sched_setaffinity(0, {core}))
    wall, cpu = time.monotonic() - t0, _children_cpu_s() - cpu0
    if r.returncode not in (0, 3):
        raise RuntimeError(f"hdlamp sil exited {r.returncode}: {r.stderr.strip()[-2000:]}")
    m = SPEED_RE.search(r.stderr)
    if not m:
        raise RuntimeError(f"hdlamp sil: no speed line in: {r.stderr.strip()[-2000:]}")
    scen_s, loop_s, x = float(m.group(1)), float(m.group(2)), float(m.group(3))
    # the log prints x to the unit (from ns) and the loop's seconds to the ms: below a second
    # its x is the finer figure, above it the seconds are (a run with frames: 0.27 prints "0")
    if loop_s >= 1.0:
        x = round(scen_s / loop_s, 3)
    return {"scenario_s": scen_s, "loop_s": loop_s, "loop_x_real_time": x,
            "process_wall_s": round(wall, 4), "process_x_real_time": round(scen_s / wall, 2),
            "process_cpu_s": round(cpu, 3), "exit": r.returncode,
            "command": " ".join(shlex.quote(c) for c in cmd)}


def speed(ctx, hdlamp, ecu, core, runs, what, extra=(), report=None, after=None):
    load0 = ctx["loadavg"]()
    rs = []
    for i in range(runs):
        rs.append(sil_once(ctx, hdlamp, ecu, core, extra, report))
        if after:
            rs[-1].update(after())
    s = {"what": what, "runs": runs, "pinned_to_core": core,
         "scenario": os.path.relpath(SCENARIO, SRC), "scenario_s": rs[0]["scenario_s"],
         "command": rs[0]["command"],
         "loop_x_real_time": _stats([r["loop_x_real_time"] for r in rs], 3),
         "loop_s": _stats([r["loop_s"] for r in rs], 3),
         "process_x_real_time": _stats([r["process_x_real_time"] for r in rs], 2),
         "process_wall_s": _stats([r["process_wall_s"] for r in rs], 3),
         "process_cpu_s": _stats([r["process_cpu_s"] for r in rs], 3),
         "exit_codes": sorted({r["exit"] for r in rs}),
         "loadavg_start": load0, "loadavg_end": ctx["loadavg"]()}
    ctx["log"](f"sil: {what}: loop {s['loop_x_real_time']['median']:g} x real time (median of "
               f"{runs}), process {s['process_x_real_time']['median']:g} x")
    return s, rs


def frames_speed(ctx, hdlamp, core, runs, out):
    """hdlamp sil --frames at 1280x720: x real time and ms per judged frame."""
    h = subprocess.run([hdlamp, "sil", "--help"], capture_output=True, text=True)
    if "--frames" not in h.stdout + h.stderr:
        return {"skipped": f"this build's hdlamp sil has no --frames ({hdlamp} sil --help does "
                           f"not list it)"}
    fdir = os.path.join(out, "sil_frames")
    report = os.path.join(out, "sil_frames_report.json")

    def after():
        names = [n for n in os.listdir(fdir) if n.endswith(".png")]
        nbytes = sum(os.path.getsize(os.path.join(fdir, n)) for n in names)
        shutil.rmtree(fdir)  # 1280x720 PNGs: not kept
        with open(report) as f:
            judged = json.load(f)["frames"]["rendered"]
        return {"pngs": len(names), "png_mb": round(nbytes / 1e6, 1), "frames_judged": judged}

    shutil.rmtree(fdir, ignore_errors=True)
    s, rs = speed(ctx, hdlamp, "reference", core, runs,
                  f"reference ECU in process, --frames at {SIZE}",
                  extra=("--frames", fdir, "--set", f"render.size={SIZE}"), report=report,
                  after=after)
    s["pngs_per_run"] = rs[0]["pngs"]
    s["png_mb_per_run"] = rs[0]["png_mb"]
    s["frames_judged_per_run"] = rs[0]["frames_judged"]
    if not all(r["pngs"] for r in rs):
        raise RuntimeError(f"hdlamp sil --frames wrote no PNG: {s['command']}")
    s["ms_per_frame"] = _stats([1000.0 * r["loop_s"] / r["pngs"] for r in rs], 2)
    s["ms_per_frame_process"] = _stats([1000.0 * r["process_wall_s"] / r["pngs"] for r in rs], 2)
    return s


# ---------------------------------------------------------------- real time

def rt_pass(ctx, cmd, deadline, rt=False):
    """One hdlampd pass: until it exits at the scenario's end or deadline (then SIGTERM).
    Returns the client's rows, the daemon's exit status line and report, wall and CPU."""
    Client, log = ctx["Client"], ctx["log"]
    log("sil: $ " + " ".join(shlex.quote(c) for c in cmd))
    cpu0, t0 = _children_cpu_s(), time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    port, errlog, c = None, [], None
    try:
        while port is None:
            line = p.stderr.readline()
            if not line:
                raise RuntimeError("hdlampd exited early: " + "".join(errlog)[-2000:])
            errlog.append(line)
            m = re.search(r"frame stream on .*\(port (\d+)\)", line)
            if m:
                port = int(m.group(1))
        threading.Thread(target=lambda: errlog.extend(p.stderr), daemon=True).start()
        c = Client(port, rt)  # rt: its reading thread at SCHED_FIFO, below the daemon's
        c.start()
        stopped = False
        while p.poll() is None:
            if time.monotonic() >= deadline and not stopped:
                p.send_signal(signal.SIGTERM)
                stopped = True
            time.sleep(0.05)
    finally:
        if p.poll() is None:
            p.send_signal(signal.SIGTERM)
    out, _ = p.communicate(timeout=30)
    wall, cpu = time.monotonic() - t0, _children_cpu_s() - cpu0
    if c:
        time.sleep(0.2)  # the last frame's bytes, if any, are in the socket
        c.stop.set()
        c.join(5)
        if c.error:
            raise RuntimeError(f"stream client: {c.error}")
    status = None
    for line in out.strip().splitlines()[::-1]:
        try:
            status = json.loads(line)
            break
        except ValueError:
            continue
    if status is None or p.returncode not in (0, 3):
        raise RuntimeError(f"hdlampd exited {p.returncode} without a status line: "
                           + "".join(errlog)[-2000:])
    return {"rows": c.rows, "status": status, "exit": p.returncode, "wall_s": wall,
            "cpu_s": cpu, "stderr": errlog}


def realtime(ctx, build, out, seconds, lamps, rt_prio=0):
    """hdlampd --ecu reference on the demo drive, fresh passes until seconds; rt_prio: the
    daemon's CAN and render threads at SCHED_FIFO rt_prio (sched.realtime_priority, as the
    installed service) and the client's thread two below."""
    fields = {f: i for i, f in enumerate(ctx["FIELDS"])}
    pct = ctx["pct"]
    report = os.path.join(out, "sil_rt_report.json")
    cmd = [os.path.join(build, "daemon", "hdlampd"), "--ecu", "reference",
           "--scenario", RT_SCENARIO, "--dbc", os.path.join(SRC, "dbc", "hd84.dbc"),
           "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
           "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
           "--set", f"render.size={SIZE}", "--set", "render.scene=road",
           "--set", "stream.tcp=127.0.0.1:0", "--set", "http.listen=",
           "--exit-at-end", "--report", report] + \
        (["--set", f"sched.realtime_priority={rt_prio}"] if rt_prio else [])
    load0 = ctx["loadavg"]()
    t_end = time.monotonic() + seconds
    lat, passes = [], []
    while time.monotonic() < t_end - 1.0 or not passes:
        r = rt_pass(ctx, cmd, t_end, rt=bool(rt_prio))
        rows, st = r["rows"], r["status"]
        with open(report) as f:
            rep = json.load(f)
        lat += [(t - h[fields["t_cycle_done_ns"]]) / 1e6 for t, h in rows]
        missing = {}
        for lamp in ("left", "right"):
            seen = sorted({h[fields["cycle_seq_" + lamp]] for _, h in rows})
            missing[lamp] = (seen[-1] - seen[0] + 1 - len(seen)) if seen else None
        seqs = [h[fields["seq"]] for _, h in rows]
        passes.append({
            "exit": r["exit"], "end": rep.get("end"), "verdict": rep.get("verdict"),
            "failed_because": rep.get("failed_because"),
            "wall_s": round(r["wall_s"], 2), "cpu_s": round(r["cpu_s"], 2),
            "frames_received": len(rows),
            "frames_published": st["frames"]["published"],
            "frames_not_published": st["frames"]["not_published"],
            "first_seq_received": seqs[0] if seqs else None,
            "cycles": {l["name"]: l["cycles"] for l in st["lamps"]},
            "cycles_not_rendered": {l["name"]: l["cycles_not_rendered"] for l in st["lamps"]},
            "report_cycles": rep.get("cycles"),
            "ring_dropped": st["ring"]["dropped"], "ring_superseded": st["ring"]["superseded"],
            "stream_frames_skipped": st["stream"]["frames_skipped"],
            "client_seq_gaps": sum(b - a - 1 for a, b in zip(seqs, seqs[1:])),
            "lamp_cycles_missing_at_client": missing,
            "ecu": st.get("ecu"),
            "render_ms_max": st["frames"].get("render_ms_max")})
        p = passes[-1]
        ctx["log"](f"sil: real time pass {len(passes)}: {p['frames_received']} frames, "
                   f"not rendered {p['cycles_not_rendered']}, skipped "
                   f"{p['stream_frames_skipped']}, missing {missing}")
    lat_sorted = sorted(lat)
    # the daemon's own counters at each exit, the whole pass (start-up included)
    lost = {"cycles_not_rendered": sum(sum(p["cycles_not_rendered"].values()) for p in passes),
            "frames_not_published": sum(p["frames_not_published"] for p in passes),
            "ring_dropped": sum(p["ring_dropped"] for p in passes),
            "stream_frames_skipped": sum(p["stream_frames_skipped"] for p in passes)}
    # what the client saw from its first frame on: a cycle the daemon did not render is
    # missing here too, so this is no addition to the above
    client = {"seq_gaps": sum(p["client_seq_gaps"] for p in passes),
              "lamp_cycles_missing": sum(v or 0 for p in passes
                                         for v in p["lamp_cycles_missing_at_client"].values())}
    wall = sum(p["wall_s"] for p in passes)
    with open(os.path.join(out, "sil_latency_ms.json"), "w") as f:
        json.dump(lat, f)
    return {
        "what": "hdlampd --ecu reference in real time, a fresh daemon per pass of the demo drive "
                "(--exit-at-end), a stream client at normal scheduling; every frame the client "
                "received counts (none left out as warm-up)",
        "scenario": os.path.relpath(RT_SCENARIO, SRC), "render_size": SIZE,
        "seconds_asked": seconds, "passes": len(passes),
        "scheduling": f"SCHED_FIFO {rt_prio}" if rt_prio else "normal",
        "seconds_daemons_ran": round(wall, 1),
        "frames_received": len(lat), "cycles": {k: sum(p["cycles"][k] for p in passes)
                                                for k in passes[0]["cycles"]},
        "latency_cycle_done_to_frame_received_ms": {
            "p50": pct(lat_sorted, 50), "p99": pct(lat_sorted, 99),
            "max": lat_sorted[-1] if lat else None, "min": lat_sorted[0] if lat else None},
        "lost": lost, "lost_total": sum(lost.values()), "client_saw": client,
        "cpu_percent_of_one_core": round(100.0 * sum(p["cpu_s"] for p in passes) / wall, 1),
        "exit_codes": sorted({p["exit"] for p in passes}),
        "verdicts_held": sum(1 for p in passes if p["verdict"]),
        "per_pass": passes,
        "command": " ".join(shlex.quote(c) for c in cmd),
        "loadavg_start": load0, "loadavg_end": ctx["loadavg"]()}


# ---------------------------------------------------------------- the section

def section(build, out, seconds, ctx, runs=10, core=None, rt_prio=0):
    """The sil section's object (bench.json "sil"). ctx: tools/bench's Client, FIELDS, pct,
    loadavg, log, run. rt_prio: the real-time run at SCHED_FIFO (0: normal scheduling)."""
    started = time.monotonic()
    hdlamp = os.path.join(build, "tools", "hdlamp")
    usable = sorted(os.sched_getaffinity(0))
    core = usable[-1] if core is None else core
    try:
        commit = subprocess.run(["git", "-C", SRC, "describe", "--always", "--dirty"],
                                capture_output=True, text=True).stdout.strip() or None
    except OSError:
        commit = None
    s = {"schema": 1, "source": commit, "build": build, "loadavg_start": ctx["loadavg"](),
         "goal_x_real_time": GOAL_X_REAL_TIME}
    s["speed_reference"], _ = speed(ctx, hdlamp, "reference", core, runs,
                                    "reference ECU in process")
    fmu = os.path.join(out, "sil_reference.fmu")
    ctx["run"]([hdlamp, "ecu", "--fmu", fmu])
    s["speed_fmu"], _ = speed(ctx, hdlamp, fmu, core, runs,
                              "the reference ECU exported as an FMU (hdlamp ecu --fmu): it runs "
                              "in a child process of hdlamp sil, pinned to the same core; the "
                              "process's wall and CPU include the child and the unpacking")
    s["speed_frames"] = frames_speed(ctx, hdlamp, core, max(1, runs // 3), out)
    lamps = os.path.join(out, "lamps")
    if not os.path.exists(os.path.join(lamps, "hd84_left.lid.exr")):
        ctx["run"]([hdlamp, "model", "--out", lamps])
    s["realtime"] = realtime(ctx, build, out, seconds, lamps, rt_prio)
    s["loadavg_end"] = ctx["loadavg"]()
    s["seconds"] = round(time.monotonic() - started, 1)
    return s


def plot(s, path, footer=""):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5.4), gridspec_kw={"width_ratios": [3, 2]})
    fig.subplots_adjust(bottom=0.24, wspace=0.3, left=0.07, right=0.98)
    rt = s["realtime"]
    lat_path = os.path.join(os.path.dirname(path), "sil_latency_ms.json")
    with open(lat_path) as f:
        lat = sorted(json.load(f))
    L = rt["latency_cycle_done_to_frame_received_ms"]
    if lat:
        ax.plot(lat, [100.0 * (i + 1) / len(lat) for i in range(len(lat))], color="#4477aa",
                label=f"{len(lat)} frames, {rt['passes']} pass{'es' if rt['passes'] != 1 else ''}")
    for k, c in (("p50", "green"), ("p99", "orange"), ("max", "red")):
        if L[k] is not None:
            ax.axvline(L[k], color=c, ls="--", label=f"{k} {L[k]:.2f} ms")
    ax.set_xscale("log")
    ax.set_xlabel("CAN cycle complete → frame received by the stream client (ms)")
    ax.set_ylabel("frames at or below (%)")
    ax.set_title(f"hdlampd --ecu reference, real time ({rt.get('scheduling', 'normal')} "
                 f"scheduling), {rt['scenario']}, {SIZE}\n"
                 f"{rt['seconds_daemons_ran']:.0f} s, lost {rt['lost_total']}, CPU "
                 f"{rt['cpu_percent_of_one_core']} % of a core, load "
                 f"{rt['loadavg_start'][0]} → {rt['loadavg_end'][0]}", fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    ax.grid(True, which="both", alpha=0.3)

    bars = []
    for key, name in (("speed_reference", "reference"), ("speed_fmu", "FMU"),
                      ("speed_frames", f"frames\n{SIZE}")):
        v = s.get(key) or {}
        if "loop_x_real_time" in v:
            bars.append((f"{name}\nloop", v["loop_x_real_time"], "#4477aa"))
            bars.append((f"{name}\nprocess", v["process_x_real_time"], "#999933"))
    xs = range(len(bars))
    med = [b[1]["median"] for b in bars]
    bx.bar(xs, med, color=[b[2] for b in bars],
           yerr=[[b[1]["median"] - b[1]["min"] for b in bars],
                 [b[1]["max"] - b[1]["median"] for b in bars]], capsize=3)
    for x, b in zip(xs, bars):
        bx.text(x, b[1]["max"] * 1.15, f"{b[1]['median']:.3g}×", ha="center", fontsize=8)
    bx.axhline(s["goal_x_real_time"], color="black", lw=1,
               label=f"goal {s['goal_x_real_time']:.0f}× (loop, no frames)")
    bx.axhline(1.0, color="grey", lw=0.8, ls=":", label="real time")
    bx.bar([0], [0], color="#4477aa", label="the loop (its log line)")
    bx.bar([0], [0], color="#999933", label="the process (start-up included)")
    bx.set_yscale("log")
    bx.set_ylim(top=max(b[1]["max"] for b in bars) * 30)  # room for the legend above the bars
    bx.set_xticks(list(xs), [b[0] for b in bars], fontsize=7.5)
    bx.set_ylabel("× real time (median, bars min–max)")
    ref = s["speed_reference"]
    bx.set_title(f"hdlamp sil, {os.path.basename(ref['scenario'])} "
                 f"({ref['scenario_s']} s), one core", fontsize=10)
    bx.legend(fontsize=7, loc="upper right", ncol=2)
    fr = s.get("speed_frames") or {}
    note = (f"frames skipped: {fr['skipped']}" if "skipped" in fr else
            f"frames: {fr['ms_per_frame']['median']} ms per frame (loop), "
            f"{fr['pngs_per_run']} PNGs per run")
    fig.text(0.01, 0.005, f"{footer}\nload {s['loadavg_start']} → {s['loadavg_end']}; {note}\n"
             f"$ {ref['command']}\n$ {rt['command']}", fontsize=6, va="bottom", ha="left",
             family="monospace", wrap=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def bench_ctx():
    """tools/bench's helpers (Client, FIELDS, pct, loadavg, log, run), loaded from its file."""
    from importlib.machinery import SourceFileLoader
    import importlib.util
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bench")
    loader = SourceFileLoader("hdlamp_bench", path)
    spec = importlib.util.spec_from_loader("hdlamp_bench", loader)
    b = importlib.util.module_from_spec(spec)
    loader.exec_module(b)
    return {k: getattr(b, k) for k in ("Client", "FIELDS", "pct", "loadavg", "log", "run",
                                       "machine_info", "RT_PRIO")}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seconds", type=float, default=300.0,
                    help="the real-time run (default 300: ten passes of the 30 s demo drive)")
    ap.add_argument("--runs", type=int, default=10, help="hdlamp sil runs per speed figure")
    ap.add_argument("--out", default=os.path.join(SRC, "bench-out"))
    ap.add_argument("--build", default=os.path.join(SRC, "build"))
    ap.add_argument("--rt", action="store_true",
                    help="the real-time run with the daemon's CAN and render threads at "
                         "SCHED_FIFO 10 (as the installed service) and the client at 8")
    ap.add_argument("--replot", action="store_true",
                    help="measure nothing: draw DIR/sil.png again from DIR/sil.json")
    ap.add_argument("--core", type=int, help="the core the speed runs are pinned to "
                                             "(default the last usable one)")
    a = ap.parse_args()
    if a.seconds <= 0 or a.runs < 1:
        print("bench_sil: --seconds > 0 and --runs >= 1 expected", file=sys.stderr)
        return 2
    os.makedirs(a.out, exist_ok=True)
    if a.replot:
        with open(os.path.join(a.out, "sil.json")) as f:
            s = json.load(f)
        draw(s, a.out)
        print(summary(s))
        return 0
    ctx = bench_ctx()
    try:
        s = section(a.build, a.out, a.seconds, ctx, a.runs, a.core,
                    ctx["RT_PRIO"] if a.rt else 0)
        s["machine"] = ctx["machine_info"](a.build)
        s["command"] = " ".join(shlex.quote(x) for x in sys.argv)
        s["started"] = time.strftime("%Y-%m-%d %H:%M:%S %Z")
        with open(os.path.join(a.out, "sil.json"), "w") as f:
            json.dump(s, f, indent=1)
        draw(s, a.out)
    except (RuntimeError, OSError, subprocess.TimeoutExpired, ValueError, KeyError) as e:
        print(f"bench_sil: failed: {e!r}", file=sys.stderr)
        return 1
    print(summary(s))
    print(os.path.join(a.out, "sil.json") + ", " + os.path.join(a.out, "sil.png"))
    return 0


def draw(s, out):
    m = s["machine"]
    plot(s, os.path.join(out, "sil.png"),
         f"{m['cpu_model']}, {m['cpus_usable']} cores; {s['started']}; source {s['source']}")


def summary(s):
    out = []
    for key in ("speed_reference", "speed_fmu", "speed_frames"):
        v = s.get(key) or {}
        if "skipped" in v:
            out.append(f"{key}: skipped: {v['skipped']}")
            continue
        out.append(f"{key}: loop {v['loop_x_real_time']['median']:g} x real time "
                   f"({v['loop_x_real_time']['min']:g}..{v['loop_x_real_time']['max']:g}), "
                   f"process {v['process_x_real_time']['median']:g} x "
                   f"({v['process_wall_s']['median']:g} s)"
                   + (f", {v['ms_per_frame']['median']:g} ms per frame" if "ms_per_frame" in v
                      else ""))
    rt = s["realtime"]
    L = rt["latency_cycle_done_to_frame_received_ms"]
    out.append(f"realtime: {rt['passes']} passes, {rt['seconds_daemons_ran']:g} s, "
               f"{rt['frames_received']} frames, CAN -> frame p50 {L['p50']:.2f} / p99 "
               f"{L['p99']:.2f} / max {L['max']:.2f} ms, lost {rt['lost_total']} "
               f"{json.dumps(rt['lost'])}, client {json.dumps(rt['client_saw'])}, CPU {rt['cpu_percent_of_one_core']} %")
    return "\n".join(out)


if __name__ == "__main__":
    sys.exit(main())
