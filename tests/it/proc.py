"""Running the project's programs from tests."""
import subprocess


def run(*args, ok=True):
    """Runs a command; its CompletedProcess (text). ok: fail the test on a non-zero exit."""
    r = subprocess.run([str(a) for a in args], capture_output=True, text=True)
    if ok and r.returncode != 0:
        raise AssertionError(f"{args} exited {r.returncode}: {r.stderr}")
    return r
