"""tests/vm/run itself, from the host: what goes in comes out, and failures are failures.

Each case boots the VM once (a few seconds under TCG), so the cases are few and each checks a lot.
"""

import os
import subprocess
import time

RUN = os.path.join(os.path.dirname(os.path.abspath(__file__)), "run")


def vm(*args, env=None, cwd=None, timeout=600):
    return subprocess.run([RUN, *args], capture_output=True, text=True, env=env, cwd=cwd,
                          timeout=timeout)


def test_output_status_environment_directory_and_results_come_back(tmp_path):
    env = dict(os.environ, HL_TEST_VALUE='a b "c" $d')
    script = ('echo "value:$HL_TEST_VALUE"; pwd; printf "%s|" "$@"; echo; '
              'echo "to stderr" >&2; echo result >"$HL_VM_OUT/r.txt"; '
              'ip -o link show vcan0 | grep -o "vcan0: <[^>]*UP[^>]*> mtu 16"; '
              'test "$HL_VM" = 1 || exit 99; exit 7')
    r = vm("--out", str(tmp_path / "out"), "--", "/bin/sh", "-c", script, "sh",
           "a b", "c'd", "", env=env, cwd=tmp_path)
    assert r.returncode == 7, r.stderr
    assert r.stdout == (f'value:a b "c" $d\n{tmp_path}\na b|c\'d||\n'
                        "vcan0: <NOARP,UP,LOWER_UP> mtu 16\n")
    assert r.stderr == "to stderr\n"
    assert (tmp_path / "out" / "r.txt").read_text() == "result\n"


def test_a_failing_command_fails_the_run():
    r = vm("false")
    assert r.returncode == 1
    assert r.stdout == "" and r.stderr == ""


def test_a_hung_command_times_out():
    t0 = time.monotonic()
    r = vm("--timeout", "25", "--", "sleep", "600")
    assert r.returncode == 124
    assert "vm: timed out after 25 s" in r.stderr
    # cut short, not run to its end (how much after the 25 s depends on the load)
    print(f"timed-out run took {time.monotonic() - t0:.0f} s")
    assert time.monotonic() - t0 < 600


def test_a_broken_vm_setup_is_not_a_success():
    # An empty gpio-sim line list makes the guest's set-up fail before the command runs.
    r = vm("--gpio-sim=", "--", "true")
    assert r.returncode == 125
    assert "hl-gpio-sim failed" in r.stderr
    assert "the VM stopped without reporting a status" in r.stderr


def test_bad_usage_boots_nothing():
    for args in ([], ["--"], ["--timeout", "soon", "--", "true"], ["--bogus", "true"]):
        r = vm(*args, timeout=10)
        assert r.returncode == 2, args
        assert "Usage" in r.stderr or "tests/vm/run [" in r.stderr, args
