"""The man pages know what the binaries know: every option of `hdlampd --help`, of `hdlamp --help`
and of each `hdlamp COMMAND [SUBCOMMAND] --help`, and every key `hdlampd --print-config` prints
(daemon/core/config.c's table), is documented in docs/man/*.scd — each option in the block of its own
command, each key in its own section — and in the pages built into $HL_BUILD_DIR/docs/man/."""
import os
import re
import shutil
import subprocess

import pytest

SRC = os.environ.get("HL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BUILD = os.environ.get("HL_BUILD_DIR", "")
OPTION = re.compile(r"(?<![\w-])--[a-z][a-z0-9-]*")
BOLD = re.compile(r"\*([^*\n]+)\*")


def scd(name):
    with open(os.path.join(SRC, "docs", "man", name + ".scd"), encoding="utf-8") as f:
        return f.read()


def built(name):
    path = os.path.join(BUILD, "docs", "man", name)
    if not BUILD or not os.path.exists(path):
        pytest.fail(f"{path} is missing: build the target 'man' (docs/CMakeLists.txt)")
    with open(path, encoding="utf-8") as f:
        return f.read()


def sections(text):
    """scdoc '# HEADING' -> the text under it."""
    out, name = {}, None
    for line in text.splitlines():
        if line.startswith("# "):
            name = line[2:].strip()
            out[name] = []
        elif name:
            out[name].append(line)
    return {k: "\n".join(v) for k, v in out.items()}


def bold_options(text):
    """Options written in bold (*--opt*, or inside a bold span like *hdlamp model --sources*)."""
    return {o for span in BOLD.findall(text) for o in OPTION.findall(span)}


def roff_bold_options(roff):
    roff = roff.replace("\\&", "").replace("\\-", "-")
    return {o for span in re.findall(r"\\fB(.*?)\\f[RP]", roff) for o in OPTION.findall(span)}


def run_help(argv):
    r = subprocess.run(argv + ["--help"], capture_output=True, text=True, timeout=30)
    assert r.returncode == 0, f"{' '.join(argv)} --help: exit {r.returncode}: {r.stderr}"
    return r.stdout + r.stderr


def help_by_command(text, default):
    """Splits a help text into {command path: options}. A usage line 'hdlamp lid export FILE
    --source N' gives its options to 'lid export' (continuation lines to the same path); the
    rest of the text gives its options to `default`."""
    out, path = {}, None
    for line in text.splitlines():
        m = re.match(r"\s*(?:usage:\s*)?hdlamp((?:\s+[a-z][a-z0-9]*)+)(.*)$", line)
        if m and (line.lstrip().startswith("usage:") or path is not None):
            path = " ".join(m.group(1).split())
            rest = m.group(2)
        elif path is not None and line.startswith(" ") and line.strip().startswith(("[", "--")):
            rest = line
        else:
            path, rest = None, line
        out.setdefault(path or default, set()).update(OPTION.findall(rest))
    return out


def command_blocks(page):
    """hdlamp.1.scd's COMMANDS section -> {command path: text of its block(s)}."""
    blocks, name = {}, None
    for line in sections(page)["COMMANDS"].splitlines():
        m = re.match(r"\*([a-z][a-z0-9 ]*?)\*", line)
        if m:
            name = m.group(1).strip()
        if name:
            blocks[name] = blocks.get(name, "") + line + "\n"
    return blocks


@pytest.fixture(scope="module")
def hdlampd():
    path = os.path.join(BUILD, "daemon", "hdlampd")
    if not BUILD or not os.access(path, os.X_OK):
        pytest.fail("HL_BUILD_DIR must be the build tree with daemon/hdlampd (run through ctest)")
    return path


def test_hdlampd_options_in_man8(hdlampd):
    options = set(OPTION.findall(run_help([hdlampd]))) | {"--help"}
    assert len(options) >= 14, options
    page = scd("hdlampd.8")
    documented = bold_options(sections(page)["OPTIONS"])
    missing = sorted(options - documented)
    assert not missing, f"hdlampd options not in docs/man/hdlampd.8.scd OPTIONS: {missing}"
    missing = sorted(options - roff_bold_options(built("hdlampd.8")))
    assert not missing, f"hdlampd options not in the built hdlampd.8: {missing}"


def test_hdlamp_commands_and_options_in_man1(hdlamp):
    top = run_help([hdlamp])
    commands = re.findall(r"^  ([a-z]+)\s", top.split("commands:", 1)[1], re.M)
    assert {"model", "lid", "dbc", "scenario", "render"} <= set(commands), commands
    page = scd("hdlamp.1")
    blocks = command_blocks(page)
    roff = roff_bold_options(built("hdlamp.1"))
    assert "--help" in bold_options(sections(page)["OPTIONS"]), "hdlamp(1) lacks --help"

    wanted = {}  # command path -> options its --help names
    for cmd in commands:
        text = run_help([hdlamp, cmd])
        for path, opts in help_by_command(text, cmd).items():
            wanted.setdefault(path, set()).update(opts)
        # subcommands whose own --help says more ('hdlamp lid import --help')
        for sub in sorted({p for p in help_by_command(text, cmd) if p != cmd}):
            sub_text = run_help([hdlamp] + sub.split())
            if sub_text != text:
                for path, opts in help_by_command(sub_text, sub).items():
                    wanted.setdefault(path, set()).update(opts)
    assert "lid export" in wanted and "--step" in wanted["lid export"], wanted.keys()

    problems = []
    for path, opts in sorted(wanted.items()):
        opts = opts - {"--help"}
        # a group ('hdlamp dbc') is described by its subcommands' blocks together
        text = blocks.get(path) or "".join(v for k, v in blocks.items() if k.startswith(path + " "))
        if not text:
            problems.append(f"no block for 'hdlamp {path}' in COMMANDS")
            continue
        for o in sorted(opts - bold_options(text)):
            problems.append(f"hdlamp {path}: {o} not in its block")
        for o in sorted(opts - roff):
            problems.append(f"hdlamp {path}: {o} not in the built hdlamp.1")
    assert not problems, "docs/man/hdlamp.1.scd:\n" + "\n".join(problems)


def test_config_keys_in_man5(hdlampd):
    r = subprocess.run([hdlampd, "--print-config"], capture_output=True, text=True, timeout=30)
    assert r.returncode == 0, r.stderr
    keys, section = [], None
    for line in r.stdout.splitlines():
        if m := re.match(r"\[(\w+)\]$", line):
            section = m.group(1)
        elif m := re.match(r"(\w+) =", line):
            keys.append((section, m.group(1)))
    assert len(keys) >= 30, keys
    page = sections(scd("hdlampd.conf.5"))
    roff = built("hdlampd.conf.5").replace("\\&", "")
    problems = []
    for section, key in keys:
        text = page.get(f"SECTION [{section}]")
        if text is None:
            problems.append(f"no section [{section}]")
        elif key not in {b.strip() for b in BOLD.findall(text)}:
            problems.append(f"{section}.{key} not in SECTION [{section}]")
        if f"\\fB{key}\\fR" not in roff:
            problems.append(f"{section}.{key} not in the built hdlampd.conf.5")
    assert not problems, "docs/man/hdlampd.conf.5.scd:\n" + "\n".join(problems)


@pytest.mark.parametrize("page", ["hdlampd.8", "hdlampd.conf.5", "hdlamp.1"])
def test_man_renders(page):
    built(page)
    if not shutil.which("man"):
        pytest.skip("no man(1)")
    path = os.path.join(BUILD, "docs", "man", page)
    r = subprocess.run(["man", "-l", path], capture_output=True, text=True, timeout=60,
                       env=dict(os.environ, MANWIDTH="100", MANPAGER="cat", PAGER="cat"))
    assert r.returncode == 0, r.stderr
    assert "NAME" in r.stdout and "SEE ALSO" in r.stdout
    assert not r.stderr.strip(), r.stderr
