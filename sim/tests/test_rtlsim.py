"""`make rtlsim` (compiled Verilator harness) and `make model` give identical files."""
import pathlib
import subprocess

import numpy as np
import pytest

from sim import siggen
from sim.model import finequad_core as core
from sim.run_model import COLUMNS, write_codes

ROOT = pathlib.Path(__file__).resolve().parents[2]


# the ECP5 build (rtl/builds.toml [ecp5], make's PROFILE=ecp5)
ECP5 = dict(PROFILE="ecp5")
# the UP5K build (rtl/builds.toml [up5k]) with the signal monitor's fault checks and the
# jump detector: no harmonic compensation (rtl/phase.v), n * phase in logic, the tuning
# registers constant (the harness writes their reset values); the build itself, without
# those two, is test_lean_build_equals_model_through_faults's
UP5K = dict(PROFILE="up5k", OPT_MONITOR=1, OPT_JUMP=1)


def _make(tmp_path, target, knobs, tag=None):
    """`make target` (rtlsim or model) on tmp_path/in.csv with the knobs (NAME: value);
    its rows (COLUMNS: count, a, b, fault, z, ref_count, homed, pos_valid), written to
    tmp_path/<tag or target>.csv."""
    out = tmp_path / f"{tag or target}.csv"
    subprocess.run(["make", "-s", "-C", str(ROOT), target, f"IN={tmp_path / 'in.csv'}",
                    f"OUT={out}"] + [f"{k}={v}" for k, v in knobs.items()], check=True)
    assert out.read_text().split("\n", 1)[0] == ",".join(COLUMNS)
    return np.loadtxt(out, delimiter=",", skiprows=1, dtype=np.int64, ndmin=2)


@pytest.mark.parametrize("table,interp,seed,div,adc_w,count_mode,build",
                         [("exact", 100, 1, 36, 16, 0, {}), ("paper", 100, 2, 36, 16, 0, {}),
                          ("exact", 256, 3, 36, 16, 0, {}), ("exact", 7, 4, 36, 16, 0, {}),
                          ("exact", 100, 5, 1, 16, 0, {}), ("paper", 50, 6, 3, 16, 0, {}),
                          ("exact", 100, 8, 36, 12, 0, {}), ("exact", 100, 9, 36, 16, 1, {}),
                          ("exact", 100, 10, 1, 16, 0, ECP5), ("paper", 100, 11, 36, 16, 0, ECP5),
                          ("exact", 100, 14, 1, 16, 1, ECP5),
                          ("exact", 100, 12, 1, 16, 0, UP5K), ("exact", 100, 13, 36, 16, 0, UP5K)],
                         ids=lambda v: {id(ECP5): "ecp5", id(UP5K): "up5k"}.get(id(v)))
def test_rtlsim_equals_model(tmp_path, table, interp, seed, div, adc_w, count_mode, build):
    """div = 1: a sample on every clock (the fast path's rate); every edge offset of the
    estimator's hand-over relative to the samples occurs. count_mode 1: the counter in
    edge mode (CTRL bit 3, the paper's x4 decoder of A/B: the count follows the Eq. 12
    pulses). build: the ECP5 build's RTL (two engine lanes, the harmonic table in
    distributed RAM, the 4096-row phase table, Eq. 12 on the sine table's address side;
    one exact-table case in edge mode, a sample every clock) against the model with two
    lanes; or the UP5K build's with the monitor and the jump detector (OPT_HARMONIC = 0:
    rtl/phase.v assembles the phase; OPT_NTH_DSP = 0, OPT_TUNABLE = 0) against the model
    without the harmonic compensation (make model takes the same PROFILE and knobs)."""
    # long enough in clocks for the estimator to calibrate (a commit needs ~330 updates
    # of ~400 clocks) and to re-estimate many times afterwards
    n = max(40000, 240000 // div)
    fs = 1e6 * n / 40000
    x = siggen.s_curve(n, fs, 60e3, 0.03, t_start=0.003)
    x += siggen.s_curve(n, fs, -25e3, 0.005, t_start=0.034)
    amp = 0.1 if adc_w == 12 else 0.3 + 0.1 * (seed % 4)   # 12 bit: 10 % of full scale
    sig = siggen.Signal(A1=amp, A2=amp * 0.93, m1=0.03 * amp, m2=-0.02 * amp,
                        noise=0.004 * (seed % 5 + 1), adc_bits=adc_w)
    u1, u2, _ = siggen.encode(x, 4000.0, sig, seed=seed)
    write_codes(tmp_path / "in.csv", u1, u2)
    knobs = dict(INTERP=interp, TABLE=table, DIV=div, ADC_W=adc_w, COUNT_MODE=count_mode,
                 **build)
    r, m = _make(tmp_path, "rtlsim", knobs), _make(tmp_path, "model", knobs)
    assert r.shape == (n, len(COLUMNS))
    diff = np.nonzero((r != m).any(axis=1))[0]
    assert len(diff) == 0, f"first difference at sample {diff[0]}: rtl {r[diff[0]]} model {m[diff[0]]}"
    assert np.abs(np.diff(r[:, 0])).max() > 0      # the counter moved
    uncal = (r[:, 3] >> 4) & 1
    assert uncal[0] == 1 and uncal[-1] == 0        # the coefficients were handed over


# the UP5K report build (rtl/builds.toml [up5k]): OPT_MONITOR = 0 and OPT_JUMP = 0 beside
# the options of UP5K above
LEAN = dict(PROFILE="up5k")


@pytest.mark.parametrize("div", [1, 36])
def test_lean_build_equals_model_through_faults(tmp_path, div):
    """The UP5K report build (OPT_MONITOR = 0, OPT_JUMP = 0 besides the UP5K build's
    options) against the model with the same options, on a recording with what those
    options are about: a signal dropout, a burst of wrong codes, a channel on its rail and
    an amplitude step after the hand-over. The full model flags and holds there and its
    jump detector fires; the lean one must not (so the options change the behaviour,
    and the RTL must follow them)."""
    n = max(40000, 240000 // div)
    fs = 1e6 * n / 40000
    x = siggen.s_curve(n, fs, 60e3, 0.03, t_start=0.003)
    x += siggen.s_curve(n, fs, -25e3, 0.005, t_start=0.034)
    amp = siggen.jump(np.full(n, 0.4), int(0.7 * n), 0.25)
    sig = siggen.Signal(A1=amp, A2=amp * 0.93, m1=0.012, m2=-0.008, noise=0.004,
                        dropout=((int(0.6 * n), int(0.6 * n) + 40, 0.0),))
    u1, u2, _ = siggen.encode(x, 4000.0, sig, seed=21)
    k = int(0.8 * n)
    u1[k:k + 6], u2[k:k + 6] = -u1[k:k + 6], -u2[k:k + 6]      # half a period off
    u1[k + 500:k + 540] = 32767                                  # a broken line
    write_codes(tmp_path / "in.csv", u1, u2)
    r = _make(tmp_path, "rtlsim", dict(DIV=div, **LEAN))
    m = _make(tmp_path, "model", dict(DIV=div, **LEAN))
    full = _make(tmp_path, "model", dict(DIV=div, **UP5K), tag="model_full")
    diff = np.nonzero((r != m).any(axis=1))[0]
    assert len(diff) == 0, f"first difference at sample {diff[0]}: rtl {r[diff[0]]} model {m[diff[0]]}"
    uncal = (r[:, 3] >> 4) & 1
    assert uncal[0] == 1 and uncal[-1] == 0        # the coefficients were handed over
    held = sum(1 << core.FAULT_BITS[b] for b in ("loss", "over", "stuck", "glitch"))
    assert not (r[:, 3] & held).any()
    assert (full[:, 3] & held).any() and (full != m).any()
    # the amplitude step fires the jump detector, also without the monitor's checks, and
    # it changes the outputs there (so an RTL that kept it would differ)
    jump = core.run(u1, u2, core.Config(OPT_HARMONIC=0, OPT_MONITOR=0, div=div))
    assert jump["jumps"]
    assert (np.stack([jump[f] for f in COLUMNS], axis=1) != m).any()


@pytest.mark.parametrize("knob,value", [("MONITOR", "2"), ("JUMP", ""), ("LANES", "3"),
                                        ("HARMONIC", "0 1"), ("TABLE", "Paper"),
                                        ("ADC_W", "11")])
def test_build_knob_outside_its_values_is_refused(knob, value):
    """A knob that Verilator would truncate (and whose build would share the default's
    folder) stops make before anything runs, naming the knob and its values."""
    p = subprocess.run(["make", "-s", "-C", str(ROOT), "rtlsim", f"{knob}={value}"],
                       capture_output=True, text=True)
    assert p.returncode != 0
    assert f"{knob}='{value}': must be" in p.stderr, p.stderr


BAD_CSV = [
    ("u1,u2\n1,2\n3,40000\n", 3, "u2: code 40000 out of the signed 16-bit range"),
    ("u1,u2\n-32769,0\n", 2, "u1: code -32769 out of the signed 16-bit range"),
    ("u1,u2\n1,99999999999999999999999\n", 2, "u2: code 99999999999999999999999 out of"),
    ("u1,u2\n1,2\n0x10,5\n", 3, "not a decimal integer"),
    ("u1,u2\n1,2,3\n", 2, "expected two values"),
    ("a,b\n1,2\n", 1, "expected 'u1,u2'"),
    # the model reads by the harness's rules: what one refuses, the other does too
    ("u1, u2\n1,2\n", 1, "expected 'u1,u2'"),
    ("u1,u2\n1,2\n,\n", 3, "not a decimal integer"),
    ("u1,u2\n1\t,2\n", 2, "not a decimal integer"),
    ("u1,u2\n1_000,2\n", 2, "not a decimal integer"),
    ('u1,u2\n"1","2"\n', 2, "not a decimal integer"),
    ("u1,u2\n1,\xff\n", 2, "not a decimal integer"),
    ("u1,u2\n5\x00junk,2\n", 2, "u1: not a decimal integer: '5\\x00junk'"),
    ("u1\x01,u2\n1,2\n", 1, "header is 'u1\\x01,u2'"),
    ("u1,u2\n\t1 ,\t-2\n1,2,\x7f\n", 3, "got '1,2,\\x7f'"),
    # a field of more digits than Python converts by default (4300): the same error
    ("u1,u2\n1,2\n" + "7" * 5000 + ",3\n", 3, "u1: code 777777"),
    # the reference column: the header names it, every row has it, 0 or 1
    ("", 1, "empty file (expected header 'u1,u2' or 'u1,u2,ref')"),
    ("u1,u2,ref\n1,2,0\n3,4,2\n", 3, "ref: must be 0 or 1, got '2'"),
    ("u1,u2,ref\n1,2,-1\n", 2, "ref: must be 0 or 1, got '-1'"),
    ("u1,u2,ref\n1,2,99999999999999999999999\n", 2,
     "ref: must be 0 or 1, got '99999999999999999999999'"),
    ("u1,u2,ref\n1,2,x\n", 2, "ref: not a decimal integer: 'x'"),
    ("u1,u2,ref\n1,2,\n", 2, "ref: not a decimal integer: ''"),
    ("u1,u2,ref\n1,2,1\t\n", 2, "ref: not a decimal integer: '1\\x09'"),
    ("u1,u2,ref\n1,2,0x1\n", 2, "ref: not a decimal integer: '0x1'"),
    ("u1,u2,ref\n1,2,0\n3,4\n", 3, "expected three values 'u1,u2,ref', got '3,4'"),
    ("u1,u2,ref\n1,2,0,1\n", 2, "expected three values 'u1,u2,ref', got '1,2,0,1'"),
    ("u1,u2\n1,2,0\n", 2, "expected two values 'u1,u2', got '1,2,0'"),
    ("u1,u2,ref\n1,40000,1\n", 2, "u2: code 40000 out of the signed 16-bit range"),
    ("u1,u2,ref\nq,2,7\n", 2, "u1: not a decimal integer: 'q'"),
    ("u1,u2,REF\n1,2,0\n", 1, "header is 'u1,u2,REF', expected 'u1,u2' or 'u1,u2,ref'"),
    ("u1,u2, ref\n1,2,0\n", 1, "header is 'u1,u2, ref', expected"),
    ("u1,u2,ref,x\n1,2,0,0\n", 1, "header is 'u1,u2,ref,x', expected"),
    ("ref,u1,u2\n0,1,2\n", 1, "header is 'ref,u1,u2', expected"),
]


def _make_bad(target, csv, out):
    return subprocess.run(["make", "-s", "-C", str(ROOT), target, f"IN={csv}", f"OUT={out}"],
                          capture_output=True, text=True, errors="replace")


@pytest.mark.parametrize("text,line,reason", BAD_CSV)
def test_bad_input_is_rejected_alike_with_file_line_and_reason(tmp_path, text, line, reason):
    """The RTL harness and the model read by one set of rules (sim/harness/input.h,
    sim/run_model.py): each refuses the input with the file, line and reason, in the same
    error line but for the tool's name; both read the good lines among them alike
    (leading tabs, trailing spaces)."""
    bad = tmp_path / "bad.csv"
    bad.write_bytes(text.encode("latin-1"))
    msgs = []
    for tool in ("rtlsim", "model"):
        p = _make_bad(tool, bad, tmp_path / "o.csv")
        assert p.returncode != 0
        assert f"bad.csv:{line}" in p.stderr and reason in p.stderr, p.stderr
        err = [ln for ln in p.stderr.splitlines() if ln.startswith(f"{tool}: error: ")]
        assert len(err) == 1, (tool, p.stderr)
        msgs.append(err[0][len(tool) + 2:])
    assert msgs[0] == msgs[1]


def test_ref_column_is_read_alike_and_zero_without_it(tmp_path):
    """The reference column as both tools read it: the header 'u1,u2,ref' with the line
    rules of 'u1,u2' (blank lines, CR, spaces, a sign, leading zeros: one file of all of
    them); the same rows from the harness and the model. A column of zeros gives the
    rows of the file without the column; --home without a reference changes nothing."""
    (tmp_path / "in.csv").write_bytes(b"u1,u2,ref \r\n 100,200,\t+0 \r\n\n300,-400, 01\n"
                                      b"-500,600,-0\n700,800,1\n")
    r, m = _make(tmp_path, "rtlsim", {}), _make(tmp_path, "model", {})
    assert r.shape == (4, len(COLUMNS)) and (r == m).all(), (r, m)
    u1, u2 = np.array([100, 300, -500, 700]), np.array([200, -400, 600, 800])
    write_codes(tmp_path / "in.csv", u1, u2, np.zeros(4, np.int64))
    assert (tmp_path / "in.csv").read_text().startswith("u1,u2,ref\n100,200,0\n")
    zeros = _make(tmp_path, "rtlsim", {"SETTINGS": "--home"}, tag="zeros")
    write_codes(tmp_path / "in.csv", u1, u2)
    plain = _make(tmp_path, "rtlsim", {}, tag="plain")
    assert (zeros == plain).all()


@pytest.mark.parametrize("div,settings", [(36, "--ref-q 200"),
                                          (36, "--ref-q 200 --home --home-count -123456"),
                                          (1, "--ref-q 200 --ref-filt 0 --home --ab-sep 1"),
                                          (3, "--ref-q 200 --home --home-count 77 --ab-sep 2")])
def test_reference_marks_rtlsim_equals_model(tmp_path, div, settings):
    """The reference input (the 'ref' column) through marks passed forward and back, with
    a chattering comparator and single-sample glitches, a signal dropout between two
    marks long enough for the coast to lose the travel (pos_valid, set by homing, falls): the RTL's rows equal the model's in every column,
    with and without homing armed from the start (--home), also with a sample on every
    clock and every third (the harness's pending rows: ref_count, homed and pos_valid
    two edges after the count; the pins paced fast enough to reach the marks)."""
    n = 40000
    x = siggen.s_curve(n, 1e6, 60e3, 0.03, t_start=0.003)
    x += siggen.s_curve(n, 1e6, -25e3, 0.005, t_start=0.034)
    sig = siggen.Signal(A1=0.4, A2=0.37, m1=0.01, m2=-0.008, noise=0.004,
                        dropout=((20000, 21500, 0.0),))
    u1, u2, _ = siggen.encode(x, 4000.0, sig, seed=7)
    # the count within the period is 200 (of 400, INTERP 100) at the marks' centres
    ref = siggen.reference(x, [30000.0, 46000.0, 50000.0, 54000.0], 2500.0, jitter=30.0,
                           glitches=20, seed=4)
    write_codes(tmp_path / "in.csv", u1, u2, ref)
    knobs = {"DIV": div, "SETTINGS": settings}
    r, m = _make(tmp_path, "rtlsim", knobs), _make(tmp_path, "model", knobs)
    for i, c in enumerate(COLUMNS):
        d = np.nonzero(r[:, i] != m[:, i])[0]
        assert len(d) == 0, f"{c}: first difference at sample {d[0]}: rtl {r[d[0]]} model {m[d[0]]}"
    col = {c: r[:, i] for i, c in enumerate(COLUMNS)}
    assert col["z"].any() and col["homed"][-1] == 1           # Z seen, a reference latched
    assert len(np.unique(col["ref_count"])) >= 3               # latched on several passes
    fell = np.nonzero(np.diff(col["pos_valid"]) < 0)[0]
    if "--home " not in settings + " ":
        assert not col["pos_valid"].any()                    # set by homing alone
    else:
        assert len(fell), "pos_valid never fell: the case checks less than it says"
        home = int(settings.split("--home-count ")[1].split()[0]) if "--home-count" in settings else 0
        first = int(np.argmax(col["homed"]))
        assert col["ref_count"][first] == home


@pytest.mark.parametrize("div", [1, 36])
def test_ride_through_rtlsim_equals_model(tmp_path, div):
    """The faults the count rides through (rtl/monitor.v), in one homed run at 0.02
    periods per sample with 0.5 % noise and COAST.floor = 512: the signal at 5 % for two
    periods (counted), lost for two (coasted), channel 1 stuck for one and channel 2 for
    three (coasted, re-anchored at the other's zero crossings), then a long loss at creep
    speed (the coast's uncertainty passes a quarter period: pos_valid falls). The RTL's
    rows equal the model's in every column, also with a sample on every clock, and the
    RTL's count stays on the truth through the first four faults with pos_valid 1."""
    pitch, n4, v = 20.0, 100, 0.02
    cal = siggen.s_curve(6000, 1.0, 12 * pitch, 5800.0, 100.0, 0.0)
    ramp = siggen.s_curve(400, 1.0, 4 * pitch, 400.0, 0.0, 12 * pitch)   # to 0.02 / sample
    cruise = ramp[-1] + v * pitch * np.arange(1, 1801)
    creep = cruise[-1] + 0.002 * pitch * np.arange(1, 2001)
    x = np.concatenate([cal, ramp, cruise, creep])
    at = len(cal) + len(ramp)                     # the cruise's first sample
    f = {"dip": at + 300, "loss": at + 500, "stuck1": at + 800, "stuck2": at + 1100}
    sig = siggen.Signal(noise=0.005, dropout=((f["dip"], f["dip"] + 100, 0.05),
                                              (f["loss"], f["loss"] + 100, 0.0),
                                              (at + 1900, at + 3700, 0.0)))
    u1, u2, _ = siggen.encode(x, pitch, sig, seed=17)
    u1[f["stuck1"]:f["stuck1"] + 50] = u1[f["stuck1"]]
    u2[f["stuck2"]:f["stuck2"] + 150] = u2[f["stuck2"]]
    mark = 14.5 * pitch                           # crossed during the ramp: homing
    write_codes(tmp_path / "in.csv", u1, u2, siggen.reference(x, [mark], 0.5 * pitch))
    knobs = {"DIV": div, "INTERP": n4 // 4, "SETTINGS": "--floor 512 --ref-q 50 --home"}
    r, m = _make(tmp_path, "rtlsim", knobs), _make(tmp_path, "model", knobs)
    for i, c in enumerate(COLUMNS):
        d = np.nonzero(r[:, i] != m[:, i])[0]
        assert len(d) == 0, f"{c}: first difference at sample {d[0]}: rtl {r[d[0]]} model {m[d[0]]}"
    col = {c: r[:, i] for i, c in enumerate(COLUMNS)}
    fault = col["fault"]
    for name, k in (("loss", f["dip"]), ("loss", f["loss"]), ("stuck", f["stuck1"] + 20),
                    ("stuck", f["stuck2"] + 20)):
        assert (fault[k:k + 30] >> core.FAULT_BITS[name] & 1).any(), (name, k)
    homed = int(np.argmax(col["pos_valid"]))
    assert 0 < homed < at, "not homed before the faults"
    assert col["pos_valid"][homed:at + 1800].all(), "pos_valid fell while the count rode"
    # the count on the truth after homing, but while it stands during a coast (the dip's
    # samples are counted, so they are checked)
    check = np.zeros(len(x), bool)
    check[homed + 3:at + 1800] = True       # (a sample every clock: the offset two rows on)
    for k, ln in ((f["loss"], 100), (f["stuck1"], 50), (f["stuck2"], 150)):
        check[k:k + ln + 2] = False
    err = col["count"] - n4 * x / pitch
    err -= np.median(err[check])
    dip = np.zeros(len(x), bool)
    dip[f["dip"]:f["dip"] + 110] = True           # 5 % amplitude: sigma 0.1 rad, 1.6 counts
    worst = np.abs(err[check & ~dip]).max(), np.abs(err[check & dip]).max()
    assert worst[0] < 3 and worst[1] < 8, f"the count off the truth by {worst} counts"
    assert col["pos_valid"][-1] == 0                # the long loss lost the travel


BAD_OPTIONS = [
    # DIV bounded (a run clocks every edge: 4611686018427387904 ran until killed)
    ("DIV=4611686018427387904", "--div: 4611686018427387904 is outside 1..4096"),
    ("DIV=99999999999999999999", "--div: 99999999999999999999 is outside 1..4096"),
    ("DIV=0", "--div: 0 is outside 1..4096"),
    ("DIV=1e3", "--div: not a decimal integer: '1e3'"),
    # a setting outside its register field's legal values (rtl/regs/finequad.rdl)
    ("INTERP=512", "--interp: 512 is outside 1..511 (INTERP.interp)"),
    ("SETTINGS=--lambda-k 24", "--lambda-k: 24 is outside 1..23 (LAMBDA_K.lambda_k)"),
    ("SETTINGS=--ab-sep 0", "--ab-sep: 0 is outside 1..255 (ABGEN.ab_sep)"),
    ("SETTINGS=--gate 8192", "--gate: 8192 is outside 0..8191 (GATE.gate)"),
    ("SETTINGS=--eps x", "--eps: not a decimal integer: 'x'"),
]


@pytest.mark.parametrize("opt,reason", BAD_OPTIONS)
def test_bad_option_is_refused_alike(tmp_path, opt, reason):
    """A knob or setting out of its range: the harness and the model refuse it with the
    same one-line error, before anything runs (exit 2)."""
    good = tmp_path / "in.csv"
    good.write_text("u1,u2\n100,200\n")
    msgs = []
    for tool in ("rtlsim", "model"):
        p = subprocess.run(["make", "-s", "-C", str(ROOT), tool, f"IN={good}",
                            f"OUT={tmp_path / 'o.csv'}", opt], capture_output=True,
                           text=True, timeout=300)
        assert p.returncode != 0 and reason in p.stderr, (tool, p.stderr)
        err = [ln for ln in p.stderr.splitlines() if ln.startswith(f"{tool}: error: ")]
        assert len(err) == 1, (tool, p.stderr)
        msgs.append(err[0][len(tool) + 2:])
    assert msgs[0] == msgs[1]
    assert not (tmp_path / "o.csv").exists()


@pytest.mark.parametrize("opt", ["AB_SEP=30", "SETTINGS=--eps 1000"])
def test_constant_register_setting_is_refused_alike(tmp_path, opt):
    """A setting of a register the build keeps constant (the UP5K build, OPT_TUNABLE=0):
    the core refuses the write (reg_err), the harness stops with the register and word,
    the model names the same, and neither leaves an output."""
    good = tmp_path / "in.csv"
    good.write_text("u1,u2\n100,200\n")
    msgs = []
    for tool in ("rtlsim", "model"):
        p = subprocess.run(["make", "-s", "-C", str(ROOT), tool, "PROFILE=up5k", f"IN={good}",
                            f"OUT={tmp_path / 'o.csv'}", opt], capture_output=True,
                           text=True, timeout=600)
        err = [ln for ln in p.stderr.splitlines() if ln.startswith(f"{tool}: error: ")]
        assert p.returncode != 0 and len(err) == 1, (tool, p.stderr)
        assert "the core refused the write of " in err[0], (tool, err)
        msgs.append(err[0][len(tool) + 2:])
        assert not (tmp_path / "o.csv").exists(), tool
    assert msgs[0] == msgs[1]


@pytest.mark.parametrize("target", ["rtlsim", "model"])
def test_unwritable_output_fails_before_the_run(tmp_path, target):
    """OUT in a folder that does not exist: the error comes before the simulation (a
    recording of 300 000 samples takes the model tens of seconds; the error, well under
    a few)."""
    import time
    big = tmp_path / "in.csv"
    big.write_text("u1,u2\n" + "100,200\n" * 300_000)
    out = tmp_path / "no_such_folder" / "o.csv"
    t0 = time.monotonic()
    p = subprocess.run(["make", "-s", "-C", str(ROOT), target, f"IN={big}", f"OUT={out}"],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode != 0 and f"cannot write '{out}'" in p.stderr, p.stderr
    assert time.monotonic() - t0 < 8.0


@pytest.mark.parametrize("target", ["rtlsim", "model"])
def test_unreadable_input_and_unwritable_vcd_are_named(tmp_path, target):
    """A folder as the input, and a VCD path that cannot be written: a one-line error with
    the path (no crash, no silent success)."""
    p = subprocess.run(["make", "-s", "-C", str(ROOT), target, f"IN={tmp_path}",
                        f"OUT={tmp_path / 'o.csv'}"], capture_output=True, text=True)
    assert p.returncode != 0 and f"'{tmp_path}' is not a regular file" in p.stderr, p.stderr
    good = tmp_path / "in.csv"
    good.write_text("u1,u2\n100,200\n")
    vcd = tmp_path / "no_such_folder" / "x.vcd"
    p = subprocess.run(["make", "-s", "-C", str(ROOT), target, f"IN={good}",
                        f"OUT={tmp_path / 'o.csv'}", f"VCD={vcd}"], capture_output=True,
                       text=True)
    assert p.returncode != 0 and f"cannot write the VCD '{vcd}'" in p.stderr, p.stderr


@pytest.mark.parametrize("data,reason", [(b"", "stdin has no samples"),
                                         (b"\x01\x00\x02\x00\x03",
                                          "stdin ended in the middle of sample 1")])
def test_raw_stream_cut_or_empty_is_an_error(data, reason):
    """--raw (scripts/soak.py's stream): an empty stdin and one ending inside a sample's
    four bytes stop the harness with an error (they used to spin forever, or drop the
    bytes)."""
    harness = ROOT / "build/rtlsim_exact_adc16/Vfinequad_core"
    if not harness.exists():
        pytest.skip("make harnesses first")
    p = subprocess.run([str(harness), "--raw"], input=data, capture_output=True, timeout=60)
    assert p.returncode == 2 and reason in p.stderr.decode(), p.stderr


def test_hand_over_waits_for_the_input_gain_in_the_rtl(tmp_path):
    """At 10 % of full scale, moving at fs / 30 from the first sample (20 000 samples),
    the eight octants come before the warm-up's gain check: the model holds 32 hand-overs
    for it (rtl/estimator.v gain_pend); the RTL's outputs equal the model's through them."""
    table = "exact"
    x = siggen.constant_speed(20000, 1e6, 1e6 * 4000.0 / 30)
    sig = siggen.Signal(A1=0.1, A2=0.09, m1=0.005, m2=-0.0033)
    u1, u2, _ = siggen.encode(x, 4000.0, sig, seed=3)
    r = core.run(u1, u2, core.Config(TABLE=table))
    assert r["gain_held"] > 0, "no hand-over waited for the gain: the case checks nothing"
    write_codes(tmp_path / "in.csv", u1, u2)
    rtl = _make(tmp_path, "rtlsim", {"TABLE": table})
    model = _make(tmp_path, "model", {"TABLE": table})
    assert (rtl == model).all(), f"RTL differs from the model in {int((rtl != model).any(axis=1).sum())} rows"
    mine = np.stack([r[f] for f in COLUMNS], axis=1)
    assert (model == mine).all()


def test_make_vcdcompare_end_to_end(tmp_path):
    """`make vcdcompare` as the README gives it (the default build, every signal of
    sim/vcdref.py) on a recording long enough for a hand-over: the RTL's VCD equals the
    model's reference, so the reference follows the RTL's current pipeline."""
    n = 40000
    x = siggen.s_curve(n, 1e6, 60e3, 0.03, t_start=0.003)
    u1, u2, _ = siggen.encode(x, 4000.0, siggen.Signal(), seed=3)
    # the first 10 000 samples: the hand-over comes at sample 9050 (a traced run writes
    # some 24 MB of VCD per 1000 samples)
    write_codes(tmp_path / "in.csv", u1[:10000], u2[:10000])
    out = tmp_path / "cmp"
    p = subprocess.run(["make", "-s", "-C", str(ROOT), "vcdcompare", f"IN={tmp_path / 'in.csv'}",
                        "SAMPLES=", f"VCDCMP={out}"], capture_output=True, text=True)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    assert "vcdcompare: OK:" in p.stdout and "warning" not in p.stderr, p.stdout + p.stderr


def test_slow_scan_through_the_harmonic_gears_equals_model(tmp_path):
    """A slow scan with a 2 % third harmonic (2 units/sample, then a reversal at 0.5):
    the harmonic block's observer shifts up through its gears (to gear 5 at the end),
    learns on the way and stops at the reversal; the RTL's outputs equal the model's."""
    v = np.concatenate([np.zeros(10_000), np.linspace(0, 2.0, 20_000), np.full(90_000, 2.0),
                        np.linspace(2.0, -0.5, 20_000), np.full(100_000, -0.5)])
    x = np.cumsum(v) * 4000.0 / 8192
    sig = siggen.Signal(h3=0.02)
    u1, u2, _ = siggen.encode(x, 4000.0, sig, seed=6)
    r = core.run(u1, u2, core.Config(), trace=True)
    h = r["harm"]
    assert h.learned > 300 and h.g >= 4
    write_codes(tmp_path / "in.csv", u1, u2)
    rtl = _make(tmp_path, "rtlsim", {})
    model = _make(tmp_path, "model", {})
    assert (rtl == model).all(), f"RTL differs from the model in {int((rtl != model).any(axis=1).sum())} rows"


def test_coarse_adc_scan_equals_model(tmp_path):
    """An 8-bit converter on the 16-bit port (codes shifted left by 8), a slow scan with a
    reversal: with --code-step 8 the RTL's outputs equal the model's, and the model raises
    no stuck flag (without the code step it raises many: sim/tests/test_stuck.py)."""
    n = 40000
    x = siggen.s_curve(n, 1e6, 8e3, 0.02, t_start=0.002)
    x += siggen.s_curve(n, 1e6, -6e3, 0.015, t_start=0.024)
    sig = siggen.Signal(A1=0.5, A2=0.45, m1=0.01, m2=-0.01, noise=0.0005, adc_bits=8)
    u1, u2, _ = siggen.encode(x, 4000.0, sig, seed=5)
    u1, u2 = u1 << 8, u2 << 8
    r = core.run(u1, u2, core.Config(code_step=8))
    assert not ((r["fault"] >> core.FAULT_BITS["stuck"]) & 1).any()
    assert ((core.run(u1, u2, core.Config())["fault"] >> core.FAULT_BITS["stuck"]) & 1).any()
    write_codes(tmp_path / "in.csv", u1, u2)
    knobs = {"SETTINGS": "--code-step 8"}
    rtl = _make(tmp_path, "rtlsim", knobs)
    model = _make(tmp_path, "model", knobs)
    assert (rtl == model).all(), f"RTL differs from the model in {int((rtl != model).any(axis=1).sum())} rows"
    mine = np.stack([r[f] for f in COLUMNS], axis=1)
    assert (model == mine).all()
