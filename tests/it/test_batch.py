"""hdlamp batch on this machine (docs/scale.md): the plan's matrix and its refusals, a plan run
with --jobs and merged into one JUnit, JSON and page, and every way a task can fail to give a
result — a missing log, a crash, an OOM kill, a scancel (SIGTERM), a lost node (SIGKILL of the
task's runner), a half-written or foreign result, a task never run — each an error with its
reason in the merge, and a second run that runs only what has no finished result. The same on
a real Slurm cluster: test_batch_slurm.py."""
import json
import os
import shutil
import signal
import subprocess
import time

import pytest

from batchlab import junit_cases, make_lab, plan_tasks, result, write_spec
from proc import run
from scenario import SOURCE_DIR


@pytest.fixture(scope="module")
def lab(hdlamp, hd84, tmp_path_factory):
    root = str(tmp_path_factory.mktemp("batch lab"))  # a space in the path, on purpose
    base = make_lab(hdlamp, hd84, root)
    spec = dict(base, suites=[{"suite": "fmvss108-adb", "only": ["preceding-straight"]}],
                scenarios=["../preceding-car.json"], faults=["", "late=100"], presets=["high"])
    shutil.copy(os.path.join(SOURCE_DIR, "scenarios", "preceding-car.json"),
                os.path.join(root, ".."))
    return root, base, write_spec(root, spec)


def test_plan_expands_the_matrix_with_stable_ids(hdlamp, lab):
    root, _, spec = lab
    plan = os.path.join(root, "plan.jsonl")
    run(hdlamp, "batch", "plan", spec, "--out", plan)
    head, tasks = plan_tasks(plan)
    assert head == {"plan": "hdlamp batch plan", "version": 1, "tasks": 10,
                    "spec": os.path.realpath(spec)}
    ids = [t["id"] for t in tasks]
    assert ids == [
        "suite/fmvss108-adb/preceding-straight-60mph/reference/none",
        "suite/fmvss108-adb/preceding-straight-60mph/reference/late=100",
        "suite/fmvss108-adb/preceding-straight-60mph/preset/high",
        "suite/fmvss108-adb/preceding-straight-70mph/reference/none",
        "suite/fmvss108-adb/preceding-straight-70mph/reference/late=100",
        "suite/fmvss108-adb/preceding-straight-70mph/preset/high",
        "sil/preceding-car/reference/none",
        "sil/preceding-car/reference/late=100",
        "drive/high",
        "drive/low",
    ]
    assert [t["index"] for t in tasks] == list(range(10))
    drive = tasks[8]
    assert drive["kind"] == "drive" and drive["log"] == os.path.join(root, "drives", "high.log")
    assert drive["scenario"] == os.path.join(root, "drives", "high.json")
    # resolved against the spec's folder
    assert os.path.isabs(tasks[6]["scenario"])
    assert os.path.realpath(tasks[6]["scenario"]) == os.path.realpath(
        os.path.join(root, "..", "preceding-car.json"))
    assert all(t["set"] == json.load(open(spec))["set"] for t in tasks)
    # the same spec, the same plan, byte for byte
    again = os.path.join(root, "plan-again.jsonl")
    run(hdlamp, "batch", "plan", spec, "--out", again)
    assert open(again).read() == open(plan).read()


@pytest.mark.parametrize("change, expected", [
    ({"version": 2}, "key 'version': expected 1"),
    ({"colour": "red"}, "key 'colour': unknown key"),
    ({"scenarios": ["nowhere.json"]}, "key 'scenarios[0]'"),
    ({"scenarios": [7]}, "key 'scenarios[0]': expected a string"),
    ({"suites": [{"suite": "no-such-suite"}]}, "no suite named 'no-such-suite'"),
    ({"suites": [{"suite": "fmvss108-adb", "only": ["nothing"]}]},
     "key 'suites[0].only[0]': no scenario or variant"),
    ({"suites": [{"suite": "fmvss108-adb", "samples": 1}]}, "key 'suites[0].samples'"),
    ({"faults": ["", ""]}, "two tasks with the id"),
    ({"drives": ["no-such-folder"]}, "key 'drives[0]'"),
])
def test_plan_refuses_a_bad_spec(hdlamp, lab, change, expected):
    root, base, _ = lab
    spec = write_spec(root, {**base, "suites": [{"suite": "fmvss108-adb",
                                                 "only": ["preceding-straight-60mph"]}],
                             **change}, "bad.json")
    r = run(hdlamp, "batch", "plan", spec, "--out", os.path.join(root, "bad.jsonl"), ok=False)
    assert r.returncode == 2, r.stderr
    assert expected in r.stderr and os.path.realpath(spec) in r.stderr, r.stderr
    assert not os.path.exists(os.path.join(root, "bad.jsonl"))


def test_plan_refuses_a_drive_without_its_scenario(hdlamp, lab, tmp_path):
    _, base, _ = lab
    (tmp_path / "drives").mkdir()
    (tmp_path / "drives" / "lonely.log").write_text("")
    spec = write_spec(str(tmp_path), dict(base))
    r = run(hdlamp, "batch", "plan", spec, "--out", tmp_path / "p.jsonl", ok=False)
    assert r.returncode == 2
    assert "drive" in r.stderr and "lonely.json" in r.stderr, r.stderr


def test_jobs_run_every_task_and_merge_them(hdlamp, lab):
    root, _, spec = lab
    plan, out = os.path.join(root, "plan.jsonl"), os.path.join(root, "out")
    run(hdlamp, "batch", "plan", spec, "--out", plan)
    r = run(hdlamp, "batch", "run", plan, "--jobs", "2", "--out", out, ok=False)
    assert r.returncode == 3, r.stderr  # the held high beam fails
    _, tasks = plan_tasks(plan)
    status = {t["id"]: result(out, t["index"])["status"] for t in tasks}
    assert status["drive/low"] == "passed" and status["drive/high"] == "failed"
    assert status["suite/fmvss108-adb/preceding-straight-60mph/preset/high"] == "failed"
    assert status["suite/fmvss108-adb/preceding-straight-60mph/reference/none"] == "passed"
    assert "error" not in status.values(), status
    for t in tasks:
        res = result(out, t["index"])
        assert res["id"] == t["id"] and res["exit"] == {"passed": 0, "failed": 3}[res["status"]]
        assert os.path.exists(os.path.join(out, str(t["index"]), "junit.xml"))
    # a suite task's worst margin, a SIL task's loop latency
    assert result(out, 2)["worst"]["margin_lx"] < 0
    assert result(out, 6)["latency_ms"]["n"] >= 1

    m = os.path.join(root, "merged")
    r = run(hdlamp, "batch", "merge", out, "--junit", f"{m}/junit.xml", "--html",
            f"{m}/index.html", "--json", f"{m}/summary.json", ok=False)
    assert r.returncode == 3, r.stderr
    s = json.load(open(f"{m}/summary.json"))
    assert (s["tasks"], s["errors"], s["verdict"]) == (10, 0, "failed")
    assert s["passed"] == list(status.values()).count("passed")
    assert s["failed"] == list(status.values()).count("failed")
    assert {g["key"]: (g["passed"], g["failed"]) for g in s["by_preset"]} == {"high": (0, 2)}
    assert s["worst"][0]["margin_lx"] == min(w["margin_lx"] for w in s["worst"])
    assert s["latency_ms"]["tasks"] == 2
    # the merged JUnit: every task's cases, under the task's id
    merged = junit_cases(f"{m}/junit.xml")
    n = 0
    for t in tasks:
        own = junit_cases(os.path.join(out, str(t["index"]), "junit.xml"))
        for (_, _, name), outcome in own.items():
            assert merged[(t["id"], t["id"], name)] == outcome
        n += len(own)
    assert len(merged) == n == s["tests"]
    page = open(f"{m}/index.html").read()
    assert "FAILED" in page and "../out/2/index.html" in page
    # everything finished: a second run runs nothing
    r = run(hdlamp, "batch", "run", plan, "--jobs", "2", "--out", out, ok=False)
    assert "0 run" in r.stderr and "10 already finished" in r.stderr, r.stderr


def wait_for(cond, timeout_s=60, what=""):
    t0 = time.monotonic()
    while not cond():
        if time.monotonic() - t0 > timeout_s:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.05)


def children(pid):
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as f:
            return [int(p) for p in f.read().split()]
    except FileNotFoundError:
        return []


def start_task(hdlamp, plan, out, index):
    """hdlamp batch run --index: the runner, once its task's child is up."""
    p = subprocess.Popen([hdlamp, "batch", "run", plan, "--index", str(index), "--out", out],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_for(lambda: children(p.pid), what=f"task {index}'s child")
    time.sleep(0.3)
    return p


def test_every_missing_result_is_an_error_with_its_reason(hdlamp, lab, tmp_path):
    root, base, _ = lab
    drives = tmp_path / "drives"
    drives.mkdir()
    for name in ("a", "b", "c", "d", "e", "f", "g", "gone"):
        shutil.copy(os.path.join(root, "drives", "low.log"), drives / f"{name}.log")
        shutil.copy(os.path.join(root, "drives", "low.json"), drives / f"{name}.json")
    spec = write_spec(str(tmp_path), dict(base))
    plan, out = str(tmp_path / "plan.jsonl"), str(tmp_path / "out")
    run(hdlamp, "batch", "plan", spec, "--out", plan)
    _, tasks = plan_tasks(plan)
    idx = {t["id"].split("/")[1]: t["index"] for t in tasks}
    os.unlink(drives / "gone.log")  # the plan names a log that is not there when it runs

    run(hdlamp, "batch", "run", plan, "--index", idx["a"], "--out", out)  # passes
    r = run(hdlamp, "batch", "run", plan, "--index", idx["gone"], "--out", out, ok=False)
    assert r.returncode == 2
    # a crash, and an OOM kill (SIGKILL) of the task's process
    for name, sig in (("b", signal.SIGSEGV), ("c", signal.SIGKILL)):
        p = start_task(hdlamp, plan, out, idx[name])
        os.kill(children(p.pid)[0], sig)
        assert p.wait(timeout=60) == 1
    # the scheduler's SIGTERM (scancel, a time limit): the runner dies of it, after its result
    p = start_task(hdlamp, plan, out, idx["d"])
    p.send_signal(signal.SIGTERM)
    assert p.wait(timeout=60) == -signal.SIGTERM
    # a lost node: the runner itself SIGKILLed, no result written
    p = start_task(hdlamp, plan, out, idx["e"])
    child = children(p.pid)[0]
    p.kill()
    p.wait()
    os.kill(child, signal.SIGKILL)
    # a half-written result, a result of another plan's task; g never runs
    run(hdlamp, "batch", "run", plan, "--index", idx["f"], "--out", out)
    path = os.path.join(out, str(idx["f"]), "result.json")
    text = open(path).read()
    open(path, "w").write(text[: len(text) // 2])
    res = result(out, idx["a"])
    res["id"] = "drive/someone-else"
    json.dump(res, open(os.path.join(out, str(idx["a"]), "result.json"), "w"))

    r = run(hdlamp, "batch", "merge", out, "--plan", plan, "--junit", tmp_path / "all.xml",
            "--json", tmp_path / "all.json", "--html", tmp_path / "all" / "index.html", ok=False)
    assert r.returncode == 3, r.stderr
    s = json.load(open(tmp_path / "all.json"))
    assert (s["tasks"], s["passed"], s["errors"], s["verdict"]) == (8, 0, 8, "failed")
    why = {e["id"].split("/")[1]: e["reason"] for e in s["errors_list"]}
    assert "of another task ('drive/someone-else')" in why["a"]
    assert "crashed: signal 11 (Segmentation fault)" in why["b"]
    assert "crashed: signal 9 (Killed): killed (out of memory" in why["c"]
    assert "stopped by SIGTERM (scancel" in why["d"]
    assert "no result: started on" in why["e"] and "never finished" in why["e"]
    assert "result.json unreadable (half written?)" in why["f"]
    assert "no result: the task never ran" in why["g"]
    assert "exit 2 (bad input)" in why["gone"] and "gone.log" in why["gone"] \
        and "No such file or directory" in why["gone"]
    cases = junit_cases(tmp_path / "all.xml")
    assert sorted(cases.values()) == ["error"] * 8
    assert "ERRORS" in open(tmp_path / "all" / "index.html").read()

    # run again: only what has no finished result (gone's bad input is final until re-planned)
    r = run(hdlamp, "batch", "run", plan, "--jobs", "2", "--out", out, ok=False)
    assert "7 run (0 failed, 0 errors), 1 already finished" in r.stderr, r.stderr
    r = run(hdlamp, "batch", "merge", out, "--plan", plan, "--json", tmp_path / "again.json",
            ok=False)
    s = json.load(open(tmp_path / "again.json"))
    assert (s["passed"], s["errors"]) == (7, 1) and r.returncode == 3
    assert s["errors_list"][0]["id"] == "drive/gone"


def test_run_refuses_bad_input(hdlamp, lab, tmp_path):
    root, _, spec = lab
    plan = str(tmp_path / "plan.jsonl")
    run(hdlamp, "batch", "plan", spec, "--out", plan)
    r = run(hdlamp, "batch", "run", plan, "--index", "10", "--out", tmp_path / "o", ok=False)
    assert r.returncode == 2 and "the plan has 10 tasks (0..9)" in r.stderr
    r = run(hdlamp, "batch", "run", plan, "--index", "env", "--out", tmp_path / "o", ok=False)
    assert r.returncode == 2 and "SLURM_ARRAY_TASK_ID" in r.stderr
    (tmp_path / "bad.jsonl").write_text('{"plan": "hdlamp batch plan", "version": 1, '
                                        '"tasks": 2}\n{"index": 0, "id": "x", "kind": "sil"\n')
    r = run(hdlamp, "batch", "run", tmp_path / "bad.jsonl", "--index", "0", "--out",
            tmp_path / "o", ok=False)
    assert r.returncode == 2 and f"{tmp_path}/bad.jsonl:2:" in r.stderr, r.stderr
    r = run(hdlamp, "batch", "merge", tmp_path / "o", "--plan", tmp_path / "bad.jsonl", ok=False)
    assert r.returncode == 2 and "bad.jsonl:2: expected task 0" in r.stderr, r.stderr
    r = run(hdlamp, "batch", "merge", tmp_path / "nowhere", ok=False)
    assert r.returncode == 2 and "nowhere/plan.jsonl" in r.stderr


def test_slurm_submission_lists_arrays_offsets_and_chunks(hdlamp, lab, tmp_path):
    """What hdlamp batch slurm submits (--dry-run: the sbatch commands, no cluster; the real
    cluster runs in test_batch_slurm.py): the array list with its limit, one array per
    --max-array-size - 1 indices with its HL_BATCH_OFFSET, chunks of tasks, and the merge job
    depending on every array; and a task's index from the environment as an array task gets it."""
    root, _, spec = lab
    plan = str(tmp_path / "plan.jsonl")
    run(hdlamp, "batch", "plan", spec, "--out", plan)
    out = str(tmp_path / "out")
    r = run(hdlamp, "batch", "slurm", plan, "--out", out, "--dry-run", "--max-parallel", "3",
            "--partition", "lamps", "--time", "10", "--mem", "2G", "--max-array-size", "4")
    lines = [line for line in r.stdout.splitlines() if line.startswith("sbatch")]
    assert "10 of 10 tasks to run: 0-9" in r.stdout
    assert [line.split()[3:7] for line in lines[:4]] == [
        ["--array=0-2%3", f"--output={out}/slurm/%A_%a.out", f"--export=ALL,HL_BATCH_OFFSET={o}",
         "--partition=lamps"] if o < 9 else
        ["--array=0%3", f"--output={out}/slurm/%A_%a.out", "--export=ALL,HL_BATCH_OFFSET=9",
         "--partition=lamps"] for o in (0, 3, 6, 9)]
    assert all("--time=10" in line and "--mem=2G" in line for line in lines[:4])
    assert "--dependency=afterany:ARRAY0:ARRAY3:ARRAY6:ARRAY9" in lines[4]
    script = open(f"{out}/slurm/array.sh").read()
    assert "'--index' 'env'" in script and "'--chunk'" not in script
    # chunks of 4: tasks 0-9 are elements 0-2; with tasks 5 and 6 finished, still 1 (4 and 7)
    r = run(hdlamp, "batch", "slurm", plan, "--out", out, "--dry-run", "--chunk", "4")
    assert "as array elements of 4 tasks each: 0-2" in r.stdout and "--array=0-2%2" in r.stdout
    assert "'--chunk' '4'" in open(f"{out}/slurm/array.sh").read()
    env = dict(os.environ, SLURM_ARRAY_TASK_ID="1", HL_BATCH_OFFSET="3")  # task 4
    r = subprocess.run([hdlamp, "batch", "run", plan, "--index", "env", "--out", out],
                       capture_output=True, text=True, env=env)
    assert r.returncode == 0 and "task 4: passed" in r.stderr, r.stderr
    for var in ("JOB_COMPLETION_INDEX", "AWS_BATCH_JOB_ARRAY_INDEX"):  # Kubernetes, AWS Batch
        env = {k: v for k, v in os.environ.items() if not k.startswith("SLURM_")}
        r = subprocess.run([hdlamp, "batch", "run", plan, "--index", "env", "--out", out],
                           capture_output=True, text=True, env=dict(env, **{var: "4"}))
        assert r.returncode == 0 and "task 4 (" in r.stderr and "already finished" in r.stderr
    for i in (5, 6):
        run(hdlamp, "batch", "run", plan, "--index", i, "--out", out, ok=False)
    r = run(hdlamp, "batch", "slurm", plan, "--out", out, "--dry-run", "--chunk", "4")
    assert "7 of 10 tasks to run: 0-3,7-9" in r.stdout
    assert "as array elements of 4 tasks each: 0-2" in r.stdout
    r = run(hdlamp, "batch", "slurm", plan, "--out", out, "--dry-run", "--chunk", "2")
    assert "as array elements of 2 tasks each: 0-1,3-4" in r.stdout, r.stdout
    # an element of chunks runs its tasks one after the other, skipping the finished
    r = run(hdlamp, "batch", "run", plan, "--index", "2", "--chunk", "3", "--out", out, ok=False)
    assert "task 6 (" in r.stderr and "already finished" in r.stderr and "task 7:" in r.stderr
    r = run(hdlamp, "batch", "run", plan, "--index", "4", "--chunk", "3", "--out", out, ok=False)
    assert r.returncode == 2 and "the plan has 10 tasks (chunks 0..3)" in r.stderr
