"""The single-node Slurm cluster of slurm_cluster.py, as `hdlamp batch slurm` will use it: an
array with a limit on how many tasks run at once, a job that depends on the whole array, and one
task of the array cancelled while the others finish.

Each task records when it started and ended (date +%s.%N, written by the task itself), so what
is checked is the order of events, not how fast the scheduler is."""
import time

import pytest

from slurm_cluster import SlurmCluster, require_tools

TASK = """#!/bin/sh
# One task of the array, writing into the directory $1: its ids, its start and end; task 3
# sleeps until it is cancelled (the trap still records its end).
out=$1
t=$SLURM_ARRAY_TASK_ID
trap 'date +%s.%N > "$out/end_$t"; exit 143' TERM
echo "$SLURM_ARRAY_TASK_ID $SLURM_ARRAY_JOB_ID" > "$out/ids_$t"
date +%s.%N > "$out/start_$t"
if [ "$t" = "$2" ]; then sleep 300 & wait $!; else sleep "$3"; fi
date +%s.%N > "$out/end_$t"
touch "$out/done_$t"
"""

AFTER = """#!/bin/sh
date +%s.%N > "$1/after_start"
"""


@pytest.fixture(scope="module")
def slurm(tmp_path_factory):
    require_tools()
    with SlurmCluster(tmp_path_factory.mktemp("slurm")) as cluster:
        yield cluster


def script(path, text):
    path.write_text(text)
    path.chmod(0o755)
    return str(path)


def read_time(path):
    return float(path.read_text())


def most_at_once(intervals):
    """The largest number of (start, end) intervals that overlap; one ending as another starts
    does not count as overlapping."""
    events = sorted([(s, 1) for s, _ in intervals] + [(e, -1) for _, e in intervals])
    running = most = 0
    for _, step in events:
        running += step
        most = max(most, running)
    return most


def wait_for_file(path, timeout_s):
    deadline = time.monotonic() + timeout_s
    while not path.exists():
        assert time.monotonic() < deadline, f"{path} not written within {timeout_s} s"
        time.sleep(0.1)


def test_array_limit_dependency_and_cancel(slurm, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    task = script(tmp_path / "task.sh", TASK)
    array = slurm.sbatch(["--array=0-5%2", "-o", f"{out}/slurm-%A_%a.out", task, out, 3, 1])
    after = slurm.sbatch([f"--dependency=afterany:{array}", "-o", f"{out}/after.out",
                          script(tmp_path / "after.sh", AFTER), out])

    wait_for_file(out / "start_3", 60)
    slurm.scancel(f"{array}_3")
    states = slurm.wait_jobs([array, after], timeout_s=60)

    want = {f"{array}_{t}": "COMPLETED" for t in range(6)}
    want[f"{array}_3"] = "CANCELLED"
    want[after] = "COMPLETED"
    assert states == want
    for t in range(6):
        assert (out / f"ids_{t}").read_text() == f"{t} {array}\n"
        assert (out / f"done_{t}").exists() == (t != 3), t
    runs = [(read_time(out / f"start_{t}"), read_time(out / f"end_{t}")) for t in range(6)]
    assert most_at_once(runs) <= 2, runs
    assert read_time(out / "after_start") >= max(e for _, e in runs)


def test_without_a_limit_more_than_two_run_at_once(slurm, tmp_path):
    """What makes the %2 above a check of the limit: the node has room for more tasks than 2
    (OverSubscribe in slurm_cluster.py), so without the limit they run together."""
    out = tmp_path / "out"
    out.mkdir()
    task = script(tmp_path / "task.sh", TASK)
    array = slurm.sbatch(["--array=0-3", "-o", f"{out}/slurm-%A_%a.out", task, out, -1, 3])
    states = slurm.wait_jobs([array], timeout_s=60)

    assert states == {f"{array}_{t}": "COMPLETED" for t in range(4)}
    runs = [(read_time(out / f"start_{t}"), read_time(out / f"end_{t}")) for t in range(4)]
    assert most_at_once(runs) >= 3, runs
