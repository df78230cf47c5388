"""hdlamp batch on a real single-node Slurm cluster (slurm_cluster.py: munged, slurmctld and
slurmd started by the test): a plan of 86 tasks (the FMVSS 108 suite's 28 variants x the
reference ECU without and with the ignore-objects fault and a held high beam, and two recorded
drives) as one job array with %2 and a merge job after it, whose merged JUnit equals the one of
`hdlamp batch run --jobs 2` case for case; then a task cancelled mid-run (scancel of its array
index) and a plan line whose log is missing, both errors with their reason, and a second
submission that runs only the cancelled task.

How many tasks ran at once is read from the tasks' own start and end times (result.json), not
from how fast the scheduler is."""
import json
import os
import re
import shutil
import subprocess
import time

import pytest

from batchlab import junit_cases, make_lab, plan_tasks, result, write_spec
from proc import run
from slurm_cluster import SlurmCluster, require_tools


@pytest.fixture(scope="module")
def slurm(tmp_path_factory):
    require_tools()
    with SlurmCluster(tmp_path_factory.mktemp("slurm")) as cluster:
        yield cluster


@pytest.fixture(scope="module")
def lab(hdlamp, hd84, tmp_path_factory):
    root = str(tmp_path_factory.mktemp("batch slurm"))
    return root, make_lab(hdlamp, hd84, root)


def submit(hdlamp, slurm, plan, out, *args):
    """hdlamp batch slurm; the array jobs' and the merge job's ids from what it prints."""
    r = subprocess_run(hdlamp, slurm, "batch", "slurm", plan, "--out", out, *args)
    arrays = re.findall(r"^array job (\d+):", r.stdout, re.M)
    merge = re.findall(r"^merge job (\d+):", r.stdout, re.M)
    return r, arrays, merge[0] if merge else None


def subprocess_run(hdlamp, slurm, *args):
    r = subprocess.run([hdlamp, *map(str, args)], capture_output=True, text=True,
                       env=slurm.env, timeout=120)
    assert r.returncode == 0, f"hdlamp {args}: exit {r.returncode}: {r.stdout} {r.stderr}"
    return r


def most_at_once(out, n):
    """The most tasks whose [start, start + duration] overlap, from their result.json."""
    spans = [(result(out, i)["started_unix"], result(out, i)["duration_s"]) for i in range(n)]
    events = sorted([(s, 1) for s, _ in spans] + [(s + d, -1) for s, d in spans])
    now = most = 0
    for _, step in events:
        now += step
        most = max(most, now)
    return most


def test_a_plan_as_one_slurm_array_equals_the_local_run(hdlamp, slurm, lab):
    root, base = lab
    spec = write_spec(root, dict(base, suites=[{"suite": "fmvss108-adb"}],
                                 faults=["", "ignore-objects"], presets=["high"]))
    plan = os.path.join(root, "plan.jsonl")
    run(hdlamp, "batch", "plan", spec, "--out", plan)
    head, tasks = plan_tasks(plan)
    assert head["tasks"] == 86 == 28 * 3 + 2

    local = os.path.join(root, "local")
    r = run(hdlamp, "batch", "run", plan, "--jobs", "2", "--out", local, ok=False)
    assert r.returncode == 3, r.stderr  # the held high beam and the ignored objects fail
    r = run(hdlamp, "batch", "merge", local, "--junit", os.path.join(root, "local.xml"),
            ok=False)
    assert r.returncode == 3 and "0 errors" in r.stderr, r.stderr

    out = os.path.join(root, "on slurm")  # a space in the results' path, on purpose
    r, arrays, merge = submit(hdlamp, slurm, plan, out, "--max-parallel", "2")
    assert len(arrays) == 1 and merge, r.stdout
    assert "86 of 86 tasks to run: 0-85" in r.stdout
    states = slurm.wait_jobs([arrays[0], merge], timeout_s=900)
    tasks_states = {k: v for k, v in states.items() if k.startswith(arrays[0] + "_")}
    assert len(tasks_states) == 86, states
    # a task's exit is its verdict: 0 passed (COMPLETED), 3 failed (FAILED); none cancelled
    assert set(tasks_states.values()) <= {"COMPLETED", "FAILED"}, states
    assert states[merge] == "FAILED"  # the merge exits 3: some tasks failed
    assert most_at_once(out, 86) <= 2
    hosts = {result(out, i)["host"] for i in range(86)}
    assert hosts == {result(local, 0)["host"]}

    merged = junit_cases(os.path.join(out, "merged", "junit.xml"))
    assert merged == junit_cases(os.path.join(root, "local.xml"))
    assert len(merged) > 86 * 2
    s = json.load(open(os.path.join(out, "merged", "summary.json")))
    assert (s["tasks"], s["errors"]) == (86, 0)
    assert os.path.exists(os.path.join(out, "merged", "index.html"))
    for t in tasks:
        assert result(out, t["index"])["status"] == result(local, t["index"])["status"], t["id"]

    # nothing left: a second submission submits nothing
    r, arrays, merge = submit(hdlamp, slurm, plan, out)
    assert not arrays and not merge and "all 86 tasks" in r.stdout, r.stdout


def test_a_cancelled_task_and_a_missing_log_are_errors_and_resubmission_runs_the_first(
        hdlamp, slurm, lab, tmp_path):
    root, base = lab
    drives = tmp_path / "drives"
    drives.mkdir()
    for name in ("cancelled", "gone", "low"):
        shutil.copy(os.path.join(root, "drives", "low.log"), drives / f"{name}.log")
        shutil.copy(os.path.join(root, "drives", "low.json"), drives / f"{name}.json")
    spec = write_spec(str(tmp_path), dict(base, suites=[{"suite": "fmvss108-adb",
                                                         "only": ["preceding-straight"]}]))
    plan, out = str(tmp_path / "plan.jsonl"), str(tmp_path / "out")
    run(hdlamp, "batch", "plan", spec, "--out", plan)
    _, tasks = plan_tasks(plan)
    idx = {t["id"]: t["index"] for t in tasks}
    assert len(tasks) == 5
    os.unlink(drives / "gone.log")  # planned, then lost before it runs

    r, arrays, merge = submit(hdlamp, slurm, plan, out, "--max-parallel", "2")
    k = idx["drive/cancelled"]
    started = os.path.join(out, str(k), "started.json")
    t0 = time.monotonic()
    while not os.path.exists(started):
        assert time.monotonic() - t0 < 300, "the task to cancel never started"
        time.sleep(0.05)
    time.sleep(0.5)
    slurm.scancel(f"{arrays[0]}_{k}")
    states = slurm.wait_jobs([arrays[0], merge], timeout_s=600)
    assert states[f"{arrays[0]}_{k}"] == "CANCELLED", states

    s = json.load(open(os.path.join(out, "merged", "summary.json")))
    why = {e["id"]: e["reason"] for e in s["errors_list"]}
    assert set(why) == {"drive/cancelled", "drive/gone"}, why
    assert "stopped by SIGTERM (scancel" in why["drive/cancelled"] or \
        "no result: started on" in why["drive/cancelled"], why
    assert "exit 2 (bad input)" in why["drive/gone"] and "gone.log" in why["drive/gone"]
    assert "No such file or directory" in why["drive/gone"]
    assert (s["passed"], s["errors"], s["verdict"]) == (3, 2, "failed")
    cases = junit_cases(os.path.join(out, "merged", "junit.xml"))
    assert cases[("drive/cancelled", "drive/cancelled", "task")] == "error"
    assert cases[("drive/gone", "drive/gone", "task")] == "error"
    r = run(hdlamp, "batch", "merge", out, ok=False)
    assert r.returncode == 3

    # the second submission: only the cancelled task (the missing log's bad input is final)
    r, arrays, merge = submit(hdlamp, slurm, plan, out, "--max-parallel", "2")
    assert f"1 of 5 tasks to run: {k}\n" in r.stdout, r.stdout
    states = slurm.wait_jobs([arrays[0], merge], timeout_s=600)
    assert list(states) == [f"{arrays[0]}_{k}", merge] or len(states) == 2, states
    assert result(out, k)["status"] == "passed"
    s = json.load(open(os.path.join(out, "merged", "summary.json")))
    assert (s["passed"], s["errors"]) == (4, 1)
    assert s["errors_list"][0]["id"] == "drive/gone"
