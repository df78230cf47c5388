"""A real single-node Slurm cluster for integration tests, started and stopped by the test itself
(no systemd, nothing from /etc/munge or /etc/slurm): munged with a fresh key, slurmctld and
slurmd in the foreground with a slurm.conf generated for this machine.

    with SlurmCluster(workdir) as c:
        job = c.sbatch(["--array=0-5%2", "job.sh"])
        states = c.wait_jobs([job], timeout_s=60)  # {"12_0": "COMPLETED", ...}

Clients run with c.env (SLURM_CONF names the generated slurm.conf, which also names the munge
socket), e.g. subprocess.run(["squeue"], env=c.env).

Final states: there is no accounting database (no slurmdbd, no sacct), and slurmctld forgets
a finished job after MinJobAge. So slurm.conf sets JobCompType=jobcomp/filetxt: slurmctld
appends one line per finished job (each array task its own line) to c.jobcomp_path, and
wait_jobs and job_states read the states from there.

The node is shared: the partition has OverSubscribe=FORCE:4, so even a 2-core machine has room
for 4 jobs per core at once; a limit such as --array=...%2 is then what bounds how many tasks
run together, not the core count.
"""
import ctypes
import os
import pwd
import shlex
import shutil
import signal
import socket
import subprocess
import tempfile
import time

import pytest

# munged and the slurm daemons live in /usr/sbin, which is not on a normal user's PATH.
SEARCH_PATH = os.pathsep.join([os.environ.get("PATH", ""), "/usr/sbin", "/sbin"])
DAEMONS = ("munged", "slurmctld", "slurmd")
CLIENTS = ("sbatch", "squeue", "sinfo", "scancel", "scontrol")
PARTITION = "batch"
SLOTS_PER_CORE = 4  # OverSubscribe=FORCE:4
PR_SET_CHILD_SUBREAPER = 36  # <linux/prctl.h>
# What the daemons fork and leave to init: slurmd a slurmstepd per job, slurmctld its
# slurmscriptd (orphaned only when slurmctld is killed).
HELPERS = ("slurmstepd", "slurmscriptd")


def missing_tools():
    """The names of the programs the cluster needs that are not installed."""
    return [t for t in DAEMONS + CLIENTS if not shutil.which(t, path=SEARCH_PATH)]


def require_tools():
    """Fails the test (CI=true) or skips it when a program of the cluster is missing."""
    missing = missing_tools()
    if not missing:
        return
    msg = (f"missing {', '.join(missing)}: "
           "tools/setup installs munge, slurmctld, slurmd and slurm-client")
    if os.environ.get("CI") == "true":
        pytest.fail(msg)
    pytest.skip(msg)


def free_port():
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("", 0))
        return s.getsockname()[1]


def node_config():
    """slurmd -C's view of this machine: {"NodeName": "vm", "CPUs": "2", ...}."""
    out = subprocess.run([shutil.which("slurmd", path=SEARCH_PATH), "-C"], capture_output=True,
                         text=True, check=True).stdout
    line = next(l for l in out.splitlines() if l.startswith("NodeName="))
    return dict(kv.split("=", 1) for kv in line.split())


def tail(path, lines=30):
    try:
        with open(path, errors="replace") as f:
            return "".join(f.readlines()[-lines:])
    except OSError as e:
        return f"({e.strerror})"


def conf_value(v):
    """A slurm.conf value: one holding a space (a path) in double quotes, which slurm.conf's
    parser takes as one value."""
    v = str(v)
    return f'"{v}"' if any(c.isspace() for c in v) else v


def parse_record(line):
    """One line of key=value pairs (jobcomp/filetxt, scontrol --oneliner) as a dict. Values
    never hold spaces in what we read (job names are ours)."""
    return dict(kv.split("=", 1) for kv in line.split() if "=" in kv)


class SlurmCluster:
    """The cluster in workdir (its files in workdir/slurm). One at a time per process: start
    makes the process the subreaper of its descendants until stop."""

    def __init__(self, workdir):
        self.workdir = os.path.abspath(str(workdir))
        self.procs = {}  # name -> Popen, in start order
        self.user = pwd.getpwuid(os.getuid()).pw_name
        self.tools = {t: shutil.which(t, path=SEARCH_PATH) for t in DAEMONS + CLIENTS}
        self.state_dir = None
        self.short_dir = None
        self.node = None
        self.conf_path = None
        self.jobcomp_path = None
        self.env = None

    def __enter__(self):
        self.start()
        return self

    def __exit__(self, *exc):
        self.stop()

    def path(self, name):
        return os.path.join(self.state_dir, name)

    def start(self, timeout_s=60):
        missing = [t for t, p in self.tools.items() if not p]
        if missing:
            raise RuntimeError(f"missing {', '.join(missing)} (tools/setup installs them)")
        os.makedirs(self.workdir, exist_ok=True)
        self.state_dir = os.path.join(self.workdir, "slurm")
        # A unix socket's path has at most 107 bytes (munged's socket lives here), and
        # slurm.conf's quoted values cannot hold a '"' (conf_value): a workdir that would break
        # either keeps the cluster's own files in a short directory of the system's instead.
        if len(self.state_dir) > 80 or any(c in self.state_dir for c in '"#\n'):
            self.short_dir = tempfile.mkdtemp(prefix="hl-slurm-")
            self.state_dir = self.short_dir
        else:
            os.makedirs(self.state_dir)
        # slurmd daemonizes slurmstepd, one per job: made our children when orphaned, they can
        # be waited for (and stopped) here, even where init does not reap (a container's).
        set_subreaper(True)
        try:
            self.start_munged()
            self.write_conf()
            self.env = {k: v for k, v in os.environ.items()
                        if not k.startswith(("SLURM_", "SBATCH_", "SQUEUE_", "SINFO_", "SALLOC_",
                                             "SRUN_", "SCANCEL_"))}
            self.env["SLURM_CONF"] = self.conf_path
            # -D: in the foreground, our child; -c: no state or locks from an earlier run.
            self.spawn("slurmctld", [self.tools["slurmctld"], "-D", "-c", "-f", self.conf_path])
            self.spawn("slurmd", [self.tools["slurmd"], "-D", "-c", "-f", self.conf_path,
                                  "-N", self.node["NodeName"]])
            self.wait_idle(timeout_s)
        except BaseException:
            self.stop()
            raise

    def spawn(self, name, argv):
        out = open(self.path(f"{name}.out"), "wb")
        self.procs[name] = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=out,
                                            stderr=subprocess.STDOUT, env=self.env,
                                            cwd=self.state_dir, start_new_session=True)
        out.close()

    def start_munged(self):
        key = self.path("munge.key")
        fd = os.open(key, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o400)
        with os.fdopen(fd, "wb") as f:
            f.write(os.urandom(1024))
        self.munge_socket = self.path("munge.socket")
        # --force: munged refuses a socket directory that is not executable by all (pytest's
        # temporary directories are 0700); every client here runs as the same user. In the
        # foreground munged logs to stderr (munged.out).
        self.spawn("munged", [self.tools["munged"], "--foreground", "--force",
                              f"--key-file={key}", f"--socket={self.munge_socket}",
                              f"--pid-file={self.path('munged.pid')}",
                              f"--seed-file={self.path('munged.seed')}"])
        deadline = time.monotonic() + 10
        while not os.path.exists(self.munge_socket):
            if self.procs["munged"].poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"munged did not start:\n{tail(self.path('munged.out'))}")
            time.sleep(0.05)

    def write_conf(self):
        self.node = node_config()
        n = self.node
        self.conf_path = self.path("slurm.conf")
        self.jobcomp_path = self.path("jobcomp.txt")
        open(self.path("plugstack.conf"), "w").close()
        host = n["NodeName"]
        conf = {
            "ClusterName": "hdlamp-test",
            # The node's address is given so that nothing depends on how the host name resolves.
            "SlurmctldHost": f"{host}(127.0.0.1)",
            "SlurmctldPort": free_port(),
            "SlurmdPort": free_port(),
            "SlurmUser": self.user,
            "SlurmdUser": self.user,
            "AuthType": "auth/munge",
            "CredType": "cred/munge",
            "AuthInfo": f"socket={self.munge_socket}",
            "StateSaveLocation": self.path("ctld"),
            "SlurmdSpoolDir": self.path("spool"),
            "SlurmctldPidFile": self.path("slurmctld.pid"),
            "SlurmdPidFile": self.path("slurmd.pid"),
            "SlurmctldLogFile": self.path("slurmctld.log"),
            "SlurmdLogFile": self.path("slurmd.log"),
            "SlurmctldDebug": "info",
            "SlurmdDebug": "info",
            "PlugStackConfig": self.path("plugstack.conf"),
            "MailProg": "/bin/true",
            # No cgroups: they are not there in every container or VM a test runs in.
            "ProctrackType": "proctrack/linuxproc",
            "TaskPlugin": "task/none",
            "JobAcctGatherType": "jobacct_gather/none",
            "AccountingStorageType": "accounting_storage/none",
            "JobCompType": "jobcomp/filetxt",
            "JobCompLoc": self.jobcomp_path,
            "MpiDefault": "none",
            "SwitchType": "switch/none",
            "SelectType": "select/cons_tres",
            "SelectTypeParameters": "CR_Core",
            "MaxArraySize": 10001,
            "MaxJobCount": 100000,  # an array's tasks count as jobs once they start
            # Scheduling within a second or two instead of the defaults' minute.
            "SchedulerType": "sched/backfill",
            "SchedulerParameters": "sched_interval=1,bf_interval=1,sched_min_interval=0",
            "MessageTimeout": 5,
            "KillWait": 5,
            "SlurmdTimeout": 30,
            "SlurmctldTimeout": 30,
            "InactiveLimit": 0,
            "MinJobAge": 300,  # s a finished job stays known to scontrol (jobcomp keeps it)
            "ReturnToService": 2,
        }
        node = " ".join(f"{k}={n[k]}" for k in ("NodeName", "CPUs", "Boards", "SocketsPerBoard",
                                                 "CoresPerSocket", "ThreadsPerCore",
                                                 "RealMemory") if k in n)
        lines = [f"{k}={conf_value(v)}" for k, v in conf.items()]
        lines.append(f"{node} NodeAddr=127.0.0.1 State=UNKNOWN")
        lines.append(f"PartitionName={PARTITION} Nodes={host} Default=YES MaxTime=INFINITE "
                     f"State=UP OverSubscribe=FORCE:{SLOTS_PER_CORE}")
        for d in ("ctld", "spool"):
            os.makedirs(self.path(d))
        with open(self.conf_path, "w") as f:
            f.write("# generated by tests/it/slurm_cluster.py\n" + "\n".join(lines) + "\n")

    def logs(self):
        """The tails of the daemons' logs, for an error message."""
        parts = []
        for name in ("munged.out", "slurmctld.log", "slurmctld.out", "slurmd.log", "slurmd.out"):
            parts.append(f"--- {name}\n{tail(self.path(name))}")
        return "\n".join(parts)

    def run(self, tool, *args, ok=True, timeout_s=30):
        """A Slurm client (sbatch, squeue, ...) against this cluster: its CompletedProcess."""
        r = subprocess.run([self.tools.get(tool) or tool, *map(str, args)], capture_output=True,
                           text=True, env=self.env, timeout=timeout_s)
        if ok and r.returncode != 0:
            raise AssertionError(f"{tool} {shlex.join(map(str, args))} exited {r.returncode}: "
                                 f"{r.stderr}")
        return r

    def wait_idle(self, timeout_s):
        deadline = time.monotonic() + timeout_s
        state = ""
        while time.monotonic() < deadline:
            for name, p in self.procs.items():
                if p.poll() is not None:
                    raise RuntimeError(f"{name} exited {p.returncode}\n{self.logs()}")
            r = self.run("sinfo", "-h", "-n", self.node["NodeName"], "-o", "%T", ok=False)
            state = r.stdout.strip() or r.stderr.strip()
            if state == "idle":
                return
            time.sleep(0.2)
        why = self.run("scontrol", "show", "node", ok=False)
        raise RuntimeError(f"node {self.node['NodeName']} not idle after {timeout_s} s "
                           f"(sinfo: {state!r})\n{why.stdout}{why.stderr}\n{self.logs()}")

    def sbatch(self, args):
        """Submits a job (args as for sbatch); its job id (of an array: the array's)."""
        r = self.run("sbatch", "--parsable", *args)
        return r.stdout.strip().split(";")[0]

    def scancel(self, spec):
        """Cancels a job, an array, or an array's task ("12_3")."""
        self.run("scancel", spec)

    def pending(self, job_ids):
        """The jobs of job_ids (or tasks of those arrays) slurmctld still has pending or
        running."""
        self.reap()
        r = self.run("squeue", "-h", "-o", "%F %A %i")
        ids = set(map(str, job_ids))
        return [l.split()[2] for l in r.stdout.splitlines() if ids & set(l.split()[:2])]

    def job_states(self, job_ids):
        """The finished jobs of job_ids from the jobcomp file: {"12": "COMPLETED",
        "12_3": "CANCELLED", ...}, an array's tasks keyed as JOBID_TASK."""
        ids = set(map(str, job_ids))
        states = {}
        try:
            with open(self.jobcomp_path) as f:
                lines = f.readlines()
        except FileNotFoundError:
            return states
        for line in lines:
            rec = parse_record(line)
            array = rec.get("ArrayJobId", "0")
            if array not in ("0", "") and array in ids:
                states[f"{array}_{rec['ArrayTaskId']}"] = rec["JobState"]
            elif rec.get("JobId") in ids:
                states[rec["JobId"]] = rec["JobState"]
        return states

    def wait_jobs(self, job_ids, timeout_s=60):
        """Waits until none of job_ids (nor a task of those arrays) is pending or running any
        more; their final states as job_states gives them."""
        deadline = time.monotonic() + timeout_s
        while True:
            left = self.pending(job_ids)
            if not left:
                return self.job_states(job_ids)
            if time.monotonic() > deadline:
                raise AssertionError(f"jobs still queued after {timeout_s} s: {left}\n"
                                     f"{self.run('squeue', ok=False).stdout}")
            time.sleep(0.2)

    def stop(self):
        """Cancels what still runs and stops slurmd, slurmctld and munged; no process of the
        cluster (nor a job's) is left."""
        if "slurmctld" in self.procs and self.procs["slurmctld"].poll() is None:
            r = self.run("scancel", "--user", self.user, ok=False)
            deadline = time.monotonic() + 15
            while r.returncode == 0 and time.monotonic() < deadline:
                r = self.run("squeue", "-h", ok=False)
                if r.returncode != 0 or not r.stdout.strip():
                    break
                time.sleep(0.2)
        for name in ("slurmd", "slurmctld", "munged"):
            p = self.procs.pop(name, None)
            if p is None:
                continue
            if p.poll() is None:
                p.terminate()
                try:
                    p.wait(10)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait()
        self.reap(self.kill_strays())
        set_subreaper(False)
        if self.short_dir:
            shutil.rmtree(self.short_dir, ignore_errors=True)
            self.short_dir = None

    def kill_strays(self):
        """Kills what is left of the cluster: slurmstepd and the jobs it started are not our
        children (slurmd daemonizes them), but they inherit SLURM_CONF from slurmd and from the
        submitting environment, so they are found by it (as is any process a test started with
        .env). Waits until they are dead; their pids."""
        if not self.conf_path:
            return set()
        mark = b"\0SLURM_CONF=" + self.conf_path.encode() + b"\0"
        killed = set()
        for pid in proc_pids():
            try:
                with open(f"/proc/{pid}/environ", "rb") as f:
                    env = b"\0" + f.read() + b"\0"
                if mark in env:
                    os.kill(pid, signal.SIGKILL)
                    killed.add(pid)
            except (OSError, ProcessLookupError):
                pass
        # Once all of them are dead, the children of those that were parents have become ours.
        deadline = time.monotonic() + 10
        while any(alive(pid) for pid in killed) and time.monotonic() < deadline:
            time.sleep(0.05)
        return killed

    def reap(self, pids=()):
        """Waits for our exited children among pids and the daemons' exited helpers: while the
        cluster runs this process is their subreaper (see start)."""
        for pid, ppid, comm, state in proc_stats():
            if ppid == os.getpid() and state == "Z" and (pid in pids or comm in HELPERS):
                try:
                    os.waitpid(pid, 0)
                except ChildProcessError:
                    pass


def proc_pids():
    return [int(p) for p in os.listdir("/proc") if p.isdigit() and int(p) != os.getpid()]


def alive(pid):
    """Whether process pid runs (exists and is no zombie)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            stat = f.read()
    except OSError:
        return False
    return stat[stat.rindex(")") + 2] not in "ZX"


def proc_stats():
    """(pid, parent pid, command name, state) of every process."""
    for pid in proc_pids():
        try:
            with open(f"/proc/{pid}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        comm = stat[stat.index("(") + 1:stat.rindex(")")]
        state, ppid = stat[stat.rindex(")") + 2:].split()[:2]
        yield pid, int(ppid), comm, state


def set_subreaper(on):
    """Makes this process (on) or init (off) the parent of orphaned descendants."""
    libc = ctypes.CDLL(None, use_errno=True)
    if libc.prctl(PR_SET_CHILD_SUBREAPER, int(on), 0, 0, 0) != 0:
        raise OSError(ctypes.get_errno(), "prctl(PR_SET_CHILD_SUBREAPER)")
