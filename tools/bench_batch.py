#!/usr/bin/python3
"""tools/bench's batch section (docs/scale.md "Measured"): how many tasks a minute hdlamp batch
runs on one core and on two, locally and as a Slurm array, and what the merge costs.

  throughput   a plan of the FMVSS 108 ADB suite's 28 variants with the reference ECU (each task
               one `hdlamp suite run --only ID` process): `hdlamp batch run --jobs 1` and
               `--jobs 2`, and on a real single-node Slurm cluster (tests/it/slurm_cluster.py:
               munged, slurmctld and slurmd started here) as one array with %1 and with %2; tasks
               a minute from the first task's start to the last one's end (result.json), and the
               whole submission's wall time (sbatch to the merge job's end); and %2 with
               --chunk 4 (each array element runs 4 tasks)
  merge        `hdlamp batch merge` of N synthetic task results (result.json and a junit.xml of
               9 cases each; a tenth failed, a hundredth an error, a hundredth missing) for N =
               1,000 and 10,000: wall seconds and peak RSS (the merge streams: its memory must
               not grow with N)

Writes DIR/batch.json and DIR/batch.png; tools/bench puts the same object into bench.json's
"batch" key. A bench, not a test: nothing here fails on a speed.

  tools/bench_batch.py [--out DIR] [--build DIR] [--tasks N] [--no-slurm]
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

SRC = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def _loadavg():
    with open("/proc/loadavg") as f:
        return [float(x) for x in f.read().split()[:3]]


def _run(argv, env=None, ok=(0,)):
    r = subprocess.run([str(a) for a in argv], capture_output=True, text=True, env=env)
    if r.returncode not in ok:
        raise RuntimeError(f"{argv[:4]} exited {r.returncode}: {r.stderr[-2000:]}")
    return r


def _span(out, n):
    """First start to last end of the tasks (their result.json), seconds."""
    res = [json.load(open(os.path.join(out, str(i), "result.json"))) for i in range(n)]
    t0 = min(r["started_unix"] for r in res)
    t1 = max(r["started_unix"] + r["duration_s"] for r in res)
    return t1 - t0, sum(r["duration_s"] for r in res) / n


def throughput(hdlamp, work, tasks, slurm, log):
    spec = os.path.join(work, "spec.json")
    with open(spec, "w") as f:
        json.dump({"spec": "hdlamp batch", "version": 1,
                   "suites": [{"suite": "fmvss108-adb"}]}, f)
    plan = os.path.join(work, "plan.jsonl")
    _run([hdlamp, "batch", "plan", spec, "--out", plan])
    with open(plan) as f:
        n = json.loads(f.readline())["tasks"]
    if tasks and tasks < n:  # the first N tasks only
        with open(plan) as f:
            lines = f.readlines()
        head = json.loads(lines[0])
        head["tasks"] = tasks
        with open(plan, "w") as f:
            f.write(json.dumps(head) + "\n" + "".join(lines[1:tasks + 1]))
        n = tasks
    out = {"tasks": n, "task": "hdlamp suite run fmvss108-adb --only VARIANT (reference ECU)"}
    for jobs in (1, 2):
        d = os.path.join(work, f"local-{jobs}")
        t = time.monotonic()
        _run([hdlamp, "batch", "run", plan, "--jobs", jobs, "--out", d], ok=(0, 3))
        wall = time.monotonic() - t
        span, per = _span(d, n)
        out[f"local_jobs_{jobs}"] = {"wall_s": round(wall, 2), "span_s": round(span, 2),
                                     "task_s_mean": round(per, 3),
                                     "tasks_per_min": round(60 * n / span, 1)}
        log(f"batch: --jobs {jobs}: {n} tasks in {span:.1f} s, {60 * n / span:.0f}/min")
    if slurm is None:
        out["slurm"] = {"skipped": "no Slurm (tools/setup installs munge, slurmctld, slurmd, "
                                   "slurm-client)"}
        return out
    for par, chunk in ((1, 1), (2, 1), (2, 4)):
        d = os.path.join(work, f"slurm-{par}-{chunk}")
        t = time.monotonic()
        r = _run([hdlamp, "batch", "slurm", plan, "--out", d, "--max-parallel", par,
                  "--chunk", chunk], env=slurm.env)
        ids = [line.split()[2].rstrip(":") for line in r.stdout.splitlines()
               if line.startswith(("array job", "merge job"))]
        slurm.wait_jobs(ids, timeout_s=3600)
        wall = time.monotonic() - t
        span, per = _span(d, n)
        out[f"slurm_max_parallel_{par}" + (f"_chunk_{chunk}" if chunk > 1 else "")] = {"wall_s": round(wall, 2), "span_s": round(span, 2),
                                            "task_s_mean": round(per, 3),
                                            "tasks_per_min": round(60 * n / span, 1)}
        log(f"batch: slurm %{par} --chunk {chunk}: {n} tasks in {span:.1f} s, {60 * n / span:.0f}/min "
            f"(submit to merged: {wall:.1f} s)")
    return out


CASES = 9


def synthetic(root, n):
    """A plan of n suite tasks and their results in root (see the module's docstring)."""
    os.makedirs(root, exist_ok=True)
    with open(os.path.join(root, "plan.jsonl"), "w") as plan:
        plan.write(json.dumps({"plan": "hdlamp batch plan", "version": 1, "tasks": n,
                               "spec": "synthetic"}) + "\n")
        for i in range(n):
            ecu = ["reference", "/fmus/ecu-a.fmu", "/fmus/ecu-b.fmu"][i % 3]
            fault = ["", "late=100", "ignore-objects", "stuck-counter"][i % 4]
            tid = f"suite/fmvss108-adb/variant-{i % 28}/{os.path.basename(ecu)}/{fault or 'none'}/{i}"
            plan.write(json.dumps({"index": i, "id": tid, "kind": "suite",
                                   "suite": "fmvss108-adb", "variant": f"variant-{i % 28}",
                                   "ecu": ecu, "fault": fault, "preset": "", "samples": 2,
                                   "config": "", "set": []}) + "\n")
            if i % 100 == 99:
                continue  # missing: never ran
            d = os.path.join(root, str(i))
            os.makedirs(d, exist_ok=True)
            failed = i % 10 == 3
            error = i % 100 == 42
            res = {"result": "hdlamp batch task", "version": 1, "index": i, "id": tid,
                   "kind": "suite", "suite": "fmvss108-adb", "variant": f"variant-{i % 28}",
                   "scenario": "", "log": "", "ecu": ecu, "fault": fault, "preset": "",
                   "status": "error" if error else "failed" if failed else "passed",
                   "exit": 1 if error else 3 if failed else 0, "signal": 0,
                   "reason": "crashed: signal 11 (Segmentation fault)" if error else "",
                   "host": f"node{i % 100:03d}", "started_unix": 1.8e9 + i,
                   "duration_s": 0.4, "tests": CASES, "failures": CASES if failed else 0,
                   "errors": 0, "worst": {"case": "oncoming 15.0-29.9 m, photometer driver",
                                          "margin_lx": (i % 997) / 100 - (5 if failed else 0)},
                   "latency_ms": {"n": 1, "p50": 20 + (i % 13), "p99": 25 + (i % 17),
                                  "max": 26 + (i % 17)}}
            with open(os.path.join(d, "result.json"), "w") as f:
                json.dump(res, f)
            with open(os.path.join(d, "junit.xml"), "w") as f:
                f.write('<?xml version="1.0" encoding="UTF-8"?>\n<testsuites>\n'
                        f'  <testsuite name="variant-{i % 28}" tests="{CASES}">\n')
                for c in range(CASES):
                    fail = ('><failure message="maximum 4.1 lx over the limit 3.1 lx"/>'
                            '</testcase>') if failed else "/>"
                    f.write(f'    <testcase classname="fmvss108-adb.variant-{i % 28}" '
                            f'name="oncoming bin {c}, photometer driver"{fail}\n')
                f.write("  </testsuite>\n</testsuites>\n")


def merge_cost(hdlamp, work, n, log):
    root = os.path.join(work, f"synthetic-{n}")
    synthetic(root, n)
    m = os.path.join(work, f"merged-{n}")
    t = time.monotonic()
    p = subprocess.Popen([hdlamp, "batch", "merge", root, "--junit", f"{m}/junit.xml", "--html",
                          f"{m}/index.html", "--json", f"{m}/summary.json"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.monotonic() - t
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 3:
        raise RuntimeError(f"merge of {n}: exit {p.returncode}")
    s = json.load(open(f"{m}/summary.json"))
    r = {"tasks": n, "wall_s": round(wall, 3), "cpu_s": round(ru.ru_utime + ru.ru_stime, 3),
         "peak_rss_mb": round(ru.ru_maxrss / 1024, 1), "junit_mb":
         round(os.path.getsize(f"{m}/junit.xml") / 2**20, 1),
         "passed": s["passed"], "failed": s["failed"], "errors": s["errors"]}
    log(f"batch: merge of {n}: {wall:.2f} s, peak RSS {r['peak_rss_mb']} MB")
    shutil.rmtree(root)
    return r


def section(build, out, log=print, tasks=0, use_slurm=True):
    hdlamp = os.path.join(build, "tools", "hdlamp")
    work = tempfile.mkdtemp(prefix="hl-bench-batch-")
    s = {"loadavg_start": _loadavg(), "cores": os.cpu_count()}
    try:
        slurm = None
        if use_slurm:
            sys.path.insert(0, os.path.join(SRC, "tests", "it"))
            import slurm_cluster
            if not slurm_cluster.missing_tools():
                slurm = slurm_cluster.SlurmCluster(os.path.join(work, "slurm"))
                slurm.start()
        try:
            s["throughput"] = throughput(hdlamp, work, tasks, slurm, log)
        finally:
            if slurm:
                slurm.stop()
        s["merge"] = [merge_cost(hdlamp, work, n, log) for n in (1000, 10000)]
    finally:
        shutil.rmtree(work, ignore_errors=True)
    s["loadavg_end"] = _loadavg()
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "batch.json"), "w") as f:
        json.dump(s, f, indent=1)
    return s


def plot(s, path, footer=""):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    t = s["throughput"]
    names, vals = [], []
    for key, label in (("local_jobs_1", "--jobs 1"), ("local_jobs_2", "--jobs 2"),
                       ("slurm_max_parallel_1", "Slurm %1"), ("slurm_max_parallel_2", "Slurm %2"),
                       ("slurm_max_parallel_2_chunk_4", "Slurm %2\n--chunk 4")):
        if key in t:
            names.append(label)
            vals.append(t[key]["tasks_per_min"])
    bars = a1.bar(names, vals, color=["#4a7", "#4a7", "#47a", "#47a", "#339"][:len(vals)])
    for b, v in zip(bars, vals):
        a1.text(b.get_x() + b.get_width() / 2, v, f"{v:.0f}", ha="center", va="bottom")
    a1.set_ylabel("tasks per minute")
    a1.set_title(f"{t['tasks']} FMVSS suite tasks (one process each)")
    ms = s["merge"]
    a2.bar([f"{m['tasks']:,}" for m in ms], [m["wall_s"] for m in ms], color="#a74",
           label="wall s")
    a2.set_ylabel("merge wall s")
    a2.set_xlabel("task results merged")
    ax = a2.twinx()
    ax.plot([f"{m['tasks']:,}" for m in ms], [m["peak_rss_mb"] for m in ms], "ko-",
            label="peak RSS MB")
    ax.set_ylabel("peak RSS (MB)")
    ax.set_ylim(0, max(m["peak_rss_mb"] for m in ms) * 1.5)
    a2.set_title("hdlamp batch merge")
    if footer:
        fig.text(0.01, 0.01, footer, fontsize=7, color="#555")
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="bench-out")
    ap.add_argument("--build", default=os.path.join(SRC, "build"))
    ap.add_argument("--tasks", type=int, default=0, help="the first N of the 28 tasks")
    ap.add_argument("--no-slurm", action="store_true")
    a = ap.parse_args()
    s = section(a.build, a.out, log=lambda m: print(m, file=sys.stderr), tasks=a.tasks,
                use_slurm=not a.no_slurm)
    plot(s, os.path.join(a.out, "batch.png"),
         footer=f"load average {s['loadavg_start']} -> {s['loadavg_end']}, "
                f"{s['cores']} cores, {time.strftime('%Y-%m-%d')}")
    json.dump(s, sys.stdout, indent=1)
    print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
