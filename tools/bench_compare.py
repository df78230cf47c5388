#!/usr/bin/python3
"""Compares tools/bench runs before and after a change, figure by figure.

  tools/bench_compare.py --before A.json [A2.json ...] --after B.json [B2.json ...] [--json OUT]

Every number under "targets" is a figure. A figure's run-to-run spread is the largest
difference between two runs of the same side (before with before, after with after). A figure
is worse when the after runs' mean is on the bad side of the before runs' mean by more than that
spread: lower is better for times, sizes, drops and losses (names ending in _ms, _us, _mb,
_total, _window, or holding "dropped"/"lost"), higher for rates and speed-ups (_per_s, the
combine's "x papers" ratios); other numbers are listed, not judged. Exit 1 when a figure is
worse, 0 otherwise."""
import argparse
import json
import statistics
import sys

LOWER = ("_ms", "_us", "_mb", "_total", "_window")
HIGHER = ("_per_s", "cpu_sparse_full", "cpu_incremental_10_changed", "cpu_incremental_95_changed",
          "gles_box_quads_full")


def figures(path):
    with open(path) as f:
        b = json.load(f)
    out = {}

    def walk(prefix, v):
        if isinstance(v, bool):
            return
        if isinstance(v, (int, float)):
            out[prefix] = float(v)
        elif isinstance(v, dict):
            for k, x in v.items():
                walk(f"{prefix}.{k}", x)
        elif isinstance(v, list):
            for i, x in enumerate(v):
                walk(f"{prefix}[{i}]", x)

    for name, t in b.get("targets", {}).items():
        walk(name, t.get("value"))
    return out


def direction(name):
    """The better side of a figure, from its name or (per_set_median_us.<set>) its parent's."""
    parts = [p.split("[")[0] for p in name.split(".")[1:]]
    for leaf in reversed(parts):
        if leaf.endswith(HIGHER) or leaf in HIGHER:
            return "higher"
        if leaf.endswith(LOWER) or "_mb_" in leaf or "dropped" in leaf or "lost" in leaf or \
                "p50_p99" in leaf:
            return "lower"
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", nargs="+", required=True)
    ap.add_argument("--after", nargs="+", required=True)
    ap.add_argument("--json", help="write the comparison here")
    a = ap.parse_args()
    before = [figures(p) for p in a.before]
    after = [figures(p) for p in a.after]
    names = sorted(set.intersection(*map(set, before + after)))
    rows, worse = [], []
    for n in names:
        bv = [r[n] for r in before]
        av = [r[n] for r in after]
        spread = max(max(bv) - min(bv), max(av) - min(av))
        d = direction(n)
        bm, am = statistics.mean(bv), statistics.mean(av)
        bad = (d == "lower" and am - bm > spread) or (d == "higher" and bm - am > spread)
        rows.append({"figure": n, "before": bv, "after": av, "spread": spread,
                     "better": d, "worse": bad})
        if bad:
            worse.append(n)
        print(f"{'WORSE ' if bad else '      '}{n}: before {bv} after {av} spread {spread:.4g}"
              f"{'' if d else ' (not judged)'}")
    print(f"{len(names)} figures, {sum(1 for r in rows if r['better'])} judged, "
          f"{len(worse)} worse than the run-to-run spread")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"before": a.before, "after": a.after, "figures": rows,
                       "worse": worse}, f, indent=1)
    return 1 if worse else 0


if __name__ == "__main__":
    sys.exit(main())
