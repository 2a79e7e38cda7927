"""The VHDL edition's rtlsim (sim/run_vhdl.py + sim/harness/harness.vhd, `make rtlsim
EDITION=vhdl`): its front end's stimulus file and errors (no core needed), vcdcompare's
per-clock mode that compares GHDL's traces, and, once rtl/vhdl/finequad_core.vhd exists,
`make rtlsim EDITION=vhdl` and `EDITION=vhdl-synth` against `make model`."""
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest

from sim import run_vhdl, siggen
from sim.run_model import COLUMNS, write_codes

ROOT = pathlib.Path(__file__).resolve().parents[2]
CORE_VHD = ROOT / "rtl" / "vhdl" / "finequad_core.vhd"


def _run(tmp_path, *args, module="sim.run_vhdl"):
    return subprocess.run([sys.executable, "-m", module, "--out", str(tmp_path / "out.csv"),
                           *map(str, args)], cwd=ROOT, capture_output=True, text=True,
                          timeout=60)


def test_stim_file(tmp_path):
    """The bench's stimulus (sim/harness/harness.vhd's header): the run's parameters,
    the register writes with their words in hex, the reads, the samples (ref 0 without
    the column)."""
    p = tmp_path / "stim.txt"
    run_vhdl.write_stim(p, 36, [(1, 7), (0x1d, 0x80000001)], [0x11], np.array([5, -3]),
                        np.array([-32768, 32767]), None)
    assert p.read_text() == "36 2 1\n1 00000007\n29 80000001\n17\n5 -32768 0\n-3 32767 0\n"
    run_vhdl.write_stim(p, 1, [], [], np.array([1]), np.array([2]), np.array([1]))
    assert p.read_text() == "1 0 0\n1 2 1\n"


@pytest.mark.parametrize("csv,msg", [
    ("u1,u2\n1,2\nx,3\n", "{in}:3: u1: not a decimal integer: 'x'"),
    ("u1,u2\n1,40000\n", "{in}:2: u2: code 40000 out of the signed 16-bit range "
                         "[-32768, 32767]"),
    ("u1,u2,ref\n1,2,2\n", "{in}:2: ref: must be 0 or 1, got '2'"),
    ("u1,u2,ref\n1,2\n", "{in}:2: expected three values 'u1,u2,ref', got '1,2'"),
    ("u1;u2\n", "{in}:1: header is 'u1;u2', expected 'u1,u2' or 'u1,u2,ref'"),
    ("u1,u2\n", "{in}: no samples after the header"),
])
def test_bad_input_is_named(tmp_path, csv, msg):
    """A bad recording stops before GHDL runs, with the harness's message (the model's
    reader: the same words after the tool's name), naming the file, line and field."""
    inp = tmp_path / "in.csv"
    inp.write_text(csv)
    p = _run(tmp_path, "--in", inp, "--build", tmp_path / "work")
    want = msg.format(**{"in": inp})
    assert p.returncode == 2 and p.stderr == f"rtlsim: error: {want}\n", p.stderr
    m = _run(tmp_path, "--in", inp, module="sim.run_model")
    assert m.returncode == 2 and m.stderr == f"model: error: {want}\n", m.stderr
    assert not (tmp_path / "work").exists()


@pytest.mark.parametrize("args,msg", [
    (["--interp", "0"], "--interp: 0 is outside 1..511 (INTERP.interp)"),
    (["--div", "0"], "--div: 0 is outside 1..4096"),
    (["--div", "x"], "--div: not a decimal integer: 'x'"),
    (["-g", "ADC_W=11"], "-g ADC_W: 11 is outside 12..16"),
    (["-g", "ENGINE_LANES=3"], "-g ENGINE_LANES: 3 is outside 1..2"),
    (["-g", "COUNT_W=16"], "-g 'COUNT_W=16': expected NAME=VALUE with NAME one of ADC_W"),
    (["-g", "OPT_JUMP"], "-g 'OPT_JUMP': expected NAME=VALUE"),
    (["--extra", "/nonexistent/x.vhd"], "--extra '/nonexistent/x.vhd': no such file"),
])
def test_bad_option_is_named(tmp_path, args, msg):
    inp = tmp_path / "in.csv"
    inp.write_text("u1,u2\n1,2\n")
    p = _run(tmp_path, "--in", inp, "--build", tmp_path / "work", *args)
    assert p.returncode == 2 and p.stderr.startswith(f"rtlsim: error: {msg}"), p.stderr
    assert p.stderr.count("\n") == 1


@pytest.mark.skipif(CORE_VHD.is_file(), reason="the edition has its finequad_core")
def test_no_core_is_named(tmp_path):
    inp = tmp_path / "in.csv"
    inp.write_text("u1,u2\n1,2\n")
    p = _run(tmp_path, "--in", inp, "--build", tmp_path / "work")
    assert p.returncode == 2 and p.stderr.startswith(
        "rtlsim: error: the VHDL edition has no entity finequad_core yet"), p.stderr


def test_adc_w_sets_the_code_range(tmp_path):
    inp = tmp_path / "in.csv"
    inp.write_text("u1,u2\n1,2\n2048,0\n")
    p = _run(tmp_path, "--in", inp, "--build", tmp_path / "work", "-g", "ADC_W=12")
    assert p.returncode == 2 and p.stderr == (
        f"rtlsim: error: {inp}:3: u1: code 2048 out of the signed 12-bit range "
        "[-2048, 2047]\n"), p.stderr


# ---- vcdcompare --cycle: GHDL's bench places edge e at e * P + P / 2 ------------------------
def _vcd(path, scope, changes):
    """A VCD (1 ps) of clk and a 4-bit q under `scope`; changes: [(t, clk, q)]."""
    text = (f"$timescale 1ps $end\n$scope module {scope} $end\n$var wire 1 ! clk $end\n"
            "$var wire 4 \" q [3:0] $end\n$upscope $end\n$enddefinitions $end\n")
    for t, clk, q in changes:
        text += f"#{t}\n{clk}!\nb{q:b} \"\n"
    path.write_text(text)


def _trace(edge0, qs, period=1000):
    """clk rising at edge0 + e * period, q taking qs[e] at that edge."""
    out = [(0, 0, 0)]
    for e, q in enumerate(qs):
        out += [(edge0 + e * period, 1, q), (edge0 + e * period + period // 2, 0, q)]
    return out if edge0 else [(t, c, q) for t, c, q in out[1:]]


def _cmp(a, b, *args):
    return subprocess.run([sys.executable, "scripts/vcdcompare.py", str(a), str(b),
                           "--period-ps", "1000", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=60)


def test_vcdcompare_cycle(tmp_path):
    """Per clock, a trace whose edges lie half a period later compares equal; a value that
    differs is reported at its edge (the reference's time line), and signals the RTL
    lacks are skipped by name with --skip-missing."""
    qs = [1, 2, 3, 3, 5, 6]
    ref, ghdl, bad = tmp_path / "ref.vcd", tmp_path / "ghdl.vcd", tmp_path / "bad.vcd"
    _vcd(ref, "TOP", _trace(0, qs))
    _vcd(ghdl, "harness", _trace(500, qs))
    _vcd(bad, "harness", _trace(500, qs[:4] + [7, 6]))
    m = ["--map", "TOP=harness"]
    assert _cmp(ghdl, ref, *m).returncode == 1            # change times differ
    p = _cmp(ghdl, ref, *m, "--cycle", "--rtl-edge0-ps", "500")
    assert p.returncode == 0, p.stdout + p.stderr
    p = _cmp(bad, ref, *m, "--cycle", "--rtl-edge0-ps", "500")
    assert p.returncode == 1 and "first divergence at t=4000 ps (edge 4) in harness.q" \
        in p.stdout, p.stdout
    assert _cmp(ghdl, ref, "--cycle", "--rtl-edge0-ps", "500").returncode == 2
    p = _cmp(ghdl, ref, "--map", "TOP.q=harness.q", "--cycle", "--rtl-edge0-ps", "500",
             "--skip-missing")
    assert p.returncode == 0 and "1 reference signal(s) not in the RTL VCD" in p.stderr \
        and "TOP.clk" in p.stderr, p.stderr
    p = _cmp(ghdl, ref, "--rtl-edge0-ps", "500")
    assert p.returncode == 2 and "--rtl-edge0-ps applies to --cycle only" in p.stderr


# ---- the VHDL edition against the model ------------------------------------------------------
needs_core = pytest.mark.skipif(
    not CORE_VHD.is_file(),
    reason="rtl/vhdl/finequad_core.vhd does not exist yet (issue 29: the VHDL core)")
needs_ghdl = pytest.mark.skipif(shutil.which("ghdl") is None, reason="ghdl not installed")


def _make(tmp_path, target, knobs, tag):
    out = tmp_path / f"{tag}.csv"
    subprocess.run(["make", "-s", "-C", str(ROOT), target, f"IN={tmp_path / 'in.csv'}",
                    f"OUT={out}"] + [f"{k}={v}" for k, v in knobs.items()], check=True,
                   timeout=1800)
    assert out.read_text().split("\n", 1)[0] == ",".join(COLUMNS)
    return np.loadtxt(out, delimiter=",", skiprows=1, dtype=np.int64, ndmin=2)


def _recording(tmp_path, n, seed, ref_every=0):
    x = siggen.s_curve(n, 1e6, 60e3, 0.03, t_start=0.003)
    sig = siggen.Signal(A1=0.4, A2=0.37, m1=0.01, m2=-0.008, noise=0.004, adc_bits=16)
    u1, u2, _ = siggen.encode(x, 4000.0, sig, seed=seed)
    ref = None
    if ref_every:
        ref = np.zeros(n, dtype=np.int64)
        ref[ref_every::ref_every] = 1
    write_codes(tmp_path / "in.csv", u1, u2, ref)


@needs_core
@needs_ghdl
# (the netlist on one case only: its Verilator build costs a minute or two of CI)
@pytest.mark.parametrize("edition,knobs,ref_every", [
    ("vhdl", dict(INTERP=100, DIV=36), 0),
    ("vhdl", dict(INTERP=7, DIV=3, SETTINGS="--home"), 997),
    ("vhdl-synth", dict(INTERP=100, DIV=36), 0),
])
def test_vhdl_rtlsim_equals_model(tmp_path, edition, knobs, ref_every):
    """`make rtlsim EDITION=vhdl` (GHDL) and `EDITION=vhdl-synth` (GHDL's netlist under
    Verilator) give the file `make model` gives, on a short recording (at DIV=36 the
    estimator calibrates within it), with and without a reference input and homing."""
    n = 6000
    _recording(tmp_path, n, seed=3, ref_every=ref_every)
    r = _make(tmp_path, "rtlsim", dict(knobs, EDITION=edition), edition)
    m = _make(tmp_path, "model", knobs, "model")
    assert r.shape == (n, len(COLUMNS))
    diff = np.nonzero((r != m).any(axis=1))[0]
    assert len(diff) == 0, f"first difference at sample {diff[0]}: rtl {r[diff[0]]} " \
        f"model {m[diff[0]]}"
