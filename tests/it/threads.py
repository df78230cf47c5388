"""The scheduling of each thread of a process, from /proc (shared with the VM tests)."""
import os

POLICY = {0: "TS", 1: "FF", 2: "RR", 3: "B", 5: "IDL", 6: "DLN"}  # ps -o cls names


def thread_policies(pid):
    """{tid: (comm, policy, rt_priority)} of every thread of pid, policy as ps -o cls shows it
    (TS = SCHED_OTHER, FF = SCHED_FIFO), from /proc/PID/task/TID/stat (fields 40 and 41)."""
    out = {}
    for tid in os.listdir(f"/proc/{pid}/task"):
        try:
            with open(f"/proc/{pid}/task/{tid}/stat") as f:
                stat = f.read()
        except FileNotFoundError:
            continue  # the thread ended meanwhile
        comm = stat[stat.index("(") + 1:stat.rindex(")")]
        rest = stat[stat.rindex(")") + 2:].split()  # rest[0] is field 3
        out[int(tid)] = (comm, POLICY.get(int(rest[38]), rest[38]), int(rest[37]))
    return out


def fifo_priority(name, priority):
    """The SCHED_FIFO priority sched.realtime_priority = priority gives a thread of hdlampd's,
    0 for SCHED_OTHER: priority for the CAN thread, the render thread and the render thread's
    helpers, one step below (at least 1) for the frame stream thread, 0 for the others."""
    if not priority:
        return 0
    if name in ("hl-can", "hl-render") or name.startswith("hl-render-"):
        return priority
    if name == "hl-stream":
        return max(priority - 1, 1)
    return 0


def check_policies(pid, priority, stream=True):
    """The CAN, render and render helper threads at SCHED_FIFO priority, the stream thread
    one below (priority 0: all TS), every other thread at SCHED_OTHER. Returns the threads for
    printing."""
    ts = thread_policies(pid)
    names = sorted(comm for comm, _, _ in ts.values())
    assert names.count("hl-can") == 1 and names.count("hl-render") == 1, names
    assert names.count("hl-stream") == (1 if stream else 0), names
    for comm, policy, prio in ts.values():
        p = fifo_priority(comm, priority)
        want = ("FF", p) if p else ("TS", 0)
        assert (policy, prio) == want, (comm, policy, prio, sorted(ts.values()))
    return sorted(ts.values())
