"""tools/bench --soak MINUTES: hdlampd replaying the drive scenario in a loop at 50 Hz for that
long, as a service runs for hours, with a stream client reading every frame and /status and
/metrics scraped every SAMPLE_S seconds. Samples the daemon's RSS, open file descriptors and
threads and its own counters; writes DIR/soak.json and DIR/soak.png.

What it reports (and judges, in soak.json "verdict"):
  frames         published by the daemon, received by the client
  cycles lost    lamp cycles no frame showed (cycles_not_rendered), frames not published,
                 ring snapshots dropped, frames the stream skipped for the client, kernel drops
                 (a live bus only): 0 expected
  E2E faults     the log's own (one CRC error, one missing page, one counter jump by 3 and a
                 300 ms silence per pass): counted per pass, so they grow with the passes
  RSS            after the warm-up and at the end: growth < 1 MiB expected
  fds, threads   after the warm-up: steady (the same at every sample) expected
"""
import json
import os
import re
import shlex
import signal
import subprocess
import threading
import time
import urllib.request

SAMPLE_S = 10.0
RSS_GROWTH_MAX_KB = 1024


def _proc_counts(pid):
    with open(f"/proc/{pid}/status") as f:
        kv = dict(line.split(":", 1) for line in f if ":" in line)
    return {"rss_kb": int(kv["VmRSS"].split()[0]), "hwm_kb": int(kv["VmHWM"].split()[0]),
            "threads": int(kv["Threads"]), "fds": len(os.listdir(f"/proc/{pid}/fd"))}


def _get(port, path):
    with urllib.request.urlopen(f"http://127.0.0.1:{port}{path}", timeout=10) as r:
        return r.read().decode()


def _lost(st):
    """The daemon's losses: lamp cycles no frame showed, ring drops, stream skips, kernel."""
    return {"cycles_not_rendered": sum(l["cycles_not_rendered"] for l in st["lamps"]),
            "frames_not_published": st["frames"]["not_published"],
            "ring_dropped": st["ring"]["dropped"],
            "stream_frames_skipped": st["stream"]["frames_skipped"],
            "kernel_drops": st.get("socket", {}).get("kernel_drops", 0)}


def soak(a, minutes, ctx):
    """ctx: tools/bench's Client, daemon_cmd, run and log. Returns soak.json's object."""
    Client, daemon_cmd, run, log = ctx["Client"], ctx["daemon_cmd"], ctx["run"], ctx["log"]
    src = ctx["SRC"]
    hdlamp = os.path.join(a.build, "tools", "hdlamp")
    lamps = os.path.join(a.out, "lamps")
    logfile = os.path.join(a.out, "drive.log")
    run([hdlamp, "model", "--out", lamps])
    run([hdlamp, "scenario", "--dbc", os.path.join(src, "dbc", "hd84.dbc"), "--out", logfile])
    seconds = minutes * 60.0
    warmup_s = min(120.0, seconds / 5)
    # --rt: the CAN and render threads at SCHED_FIFO as the installed service runs them
    # (sched.realtime_priority), and the client's reading thread one step below, so that other
    # jobs on the machine cannot take their CPU
    cmd = daemon_cmd(a.build, lamps, logfile) + ["--set", "http.listen=127.0.0.1:0"] + \
        (["--set", f"sched.realtime_priority={ctx['RT_PRIO']}"] if a.rt else [])
    log("soak: $ " + " ".join(shlex.quote(c) for c in cmd))
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    stream_port = http_port = None
    errlog = []
    samples = []
    try:
        while stream_port is None or http_port is None:
            line = p.stderr.readline()
            if not line:
                raise RuntimeError("hdlampd exited early: " + "".join(errlog)[-2000:])
            errlog.append(line)
            m = re.search(r"frame stream on .*\(port (\d+)\)", line)
            if m:
                stream_port = int(m.group(1))
            m = re.search(r"live view on http://.*\(port (\d+)\)", line)
            if m:
                http_port = int(m.group(1))
        threading.Thread(target=lambda: errlog.extend(p.stderr), daemon=True).start()
        # the reader one step below the daemon's threads: it must not take their CPU either
        c = Client(stream_port, a.rt, ctx["RT_PRIO"] - 2)
        c.start()
        t0 = time.monotonic()
        while True:
            t = time.monotonic() - t0
            pc = _proc_counts(p.pid)  # before the scrape: its connection is not counted
            st = json.loads(_get(http_port, "/status"))
            metrics_lines = _get(http_port, "/metrics").count("\n")
            s = {"t_s": round(t, 1), **pc, "frames_received": len(c.rows),
                 "frames_published": st["frames"]["published"],
                 "cycles": {l["name"]: l["cycles"] for l in st["lamps"]},
                 "lost": _lost(st), "metrics_lines": metrics_lines}
            samples.append(s)
            if len(samples) % 6 == 1:
                log(f"soak: {t / 60:.1f} of {minutes} min: {s['frames_received']} frames, "
                    f"RSS {s['rss_kb']} kB, fds {s['fds']}, threads {s['threads']}, "
                    f"lost {sum(s['lost'].values())}")
            if c.error:
                raise RuntimeError(f"stream client: {c.error}")
            if t >= seconds:
                break
            time.sleep(min(SAMPLE_S, max(0.0, seconds - t)))
    finally:
        p.send_signal(signal.SIGTERM)
    out, _ = p.communicate(timeout=30)
    c.stop.set()
    c.join(5)
    final = json.loads(out.strip().splitlines()[-1])
    after = [s for s in samples if s["t_s"] >= warmup_s]
    warm, end = after[0], after[-1]
    lost = _lost(final)
    faults = {l["name"]: {k: l[k] for k in ("cycles", "crc_errors", "incomplete",
                                             "lost_cycles", "stale_events")}
              for l in final["lamps"]}
    result = {
        "schema": 1, "command": " ".join(shlex.quote(x) for x in cmd),
        "minutes": minutes, "warmup_s": warmup_s, "rt": bool(a.rt), "sample_s": SAMPLE_S,
        "exit_code": p.returncode,
        "frames_published": final["frames"]["published"],
        "frames_received": len(c.rows),
        "cycles_lost": lost, "cycles_lost_total": sum(lost.values()),
        "log_faults_counted": faults,
        "rss_kb": {"after_warmup": warm["rss_kb"], "end": end["rss_kb"],
                   "growth": end["rss_kb"] - warm["rss_kb"], "peak_vmhwm": end["hwm_kb"]},
        "fds": {"after_warmup": warm["fds"], "min": min(s["fds"] for s in after),
                "max": max(s["fds"] for s in after)},
        "threads": {"after_warmup": warm["threads"], "min": min(s["threads"] for s in after),
                    "max": max(s["threads"] for s in after)},
        "samples": samples,
    }
    result["verdict"] = {
        "exit_0": p.returncode == 0,
        "no_cycle_lost": result["cycles_lost_total"] == 0,
        "rss_growth_under_1_mib": result["rss_kb"]["growth"] < RSS_GROWTH_MAX_KB,
        "fds_steady": result["fds"]["min"] == result["fds"]["max"],
        "threads_steady": result["threads"]["min"] == result["threads"]["max"],
    }
    with open(os.path.join(a.out, "soak.json"), "w") as f:
        json.dump(result, f, indent=1)
    _plot(result, os.path.join(a.out, "soak.png"))
    return result


def _plot(r, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s = r["samples"]
    t = [x["t_s"] / 60 for x in s]
    fig, ax = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    ax[0].plot(t, [x["rss_kb"] / 1024 for x in s], label="RSS")
    ax[0].axvline(r["warmup_s"] / 60, color="grey", ls=":", label="end of warm-up")
    ax[0].set_ylabel("MiB")
    ax[0].legend()
    ax[1].plot(t, [x["fds"] for x in s], label="open fds")
    ax[1].plot(t, [x["threads"] for x in s], label="threads")
    ax[1].legend()
    fps = [0.0] + [(b["frames_received"] - a_["frames_received"]) / max(1e-9, b["t_s"] - a_["t_s"])
                   for a_, b in zip(s, s[1:])]
    ax[2].plot(t, fps, label="frames/s received")
    ax[2].plot(t, [sum(x["lost"].values()) for x in s], label="cycles lost (total)")
    ax[2].set_xlabel("minutes")
    ax[2].legend()
    fig.suptitle(f"hdlampd soak, {r['minutes']} min: {r['frames_received']} frames, "
                 f"{r['cycles_lost_total']} cycles lost, RSS growth {r['rss_kb']['growth']} kB")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
