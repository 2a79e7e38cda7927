"""scripts/vcdcompare.py on small VCDs written with pyvcd (no simulator needed), and
sim/vcdref.py on a short model run.

    .venv/bin/python -m pytest cocotb_tests/test_vcdcompare.py
"""
import os
import subprocess
import sys

import numpy as np
from vcd import VCDWriter
from vcdvcd import VCDVCD

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, "scripts", "vcdcompare.py")
SCOPE = "TOP.finequad_core"


def write_vcd(path, changes, timescale="1 ps", scope=SCOPE, widths=None):
    """changes: [(time, name, value)] in time order; widths: {name: bits} (default
    m_valid/m_a 1 bit, m_count 32 bits)."""
    widths = widths or {"m_valid": 1, "m_count": 32, "m_a": 1}
    with open(path, "w") as f:
        w = VCDWriter(f, timescale=timescale, date="")
        v = {n: w.register_var(scope, n, "wire", size=b,
                               bit_index=(b - 1, 0) if b > 1 else None)
             for n, b in widths.items()}
        for t, n, val in changes:
            w.change(v[n], t, val)
        w.close()
    return str(path)


BASE = [(0, "m_valid", 0), (0, "m_count", 0), (0, "m_a", 1),
        (100, "m_valid", 1), (100, "m_count", 5),
        (110, "m_valid", 0),
        (200, "m_valid", 1), (200, "m_count", 7), (200, "m_a", 0),
        (210, "m_valid", 0)]


def run(*args):
    p = subprocess.run([sys.executable, SCRIPT, *map(str, args)], capture_output=True,
                       text=True, cwd=ROOT)
    return p.returncode, p.stdout, p.stderr


def changed(changes, t, name, value):
    return [(tt, n, value if (tt, n) == (t, name) else v) for tt, n, v in changes]


def test_identical(tmp_path):
    a = write_vcd(tmp_path / "rtl.vcd", BASE)
    b = write_vcd(tmp_path / "ref.vcd", BASE)
    rc, out, err = run(a, b)
    assert rc == 0, out + err
    assert "OK: 3 signal(s) identical" in out


def test_changed_value_names_time_and_signal(tmp_path):
    a = write_vcd(tmp_path / "rtl.vcd", BASE)
    b = write_vcd(tmp_path / "ref.vcd", changed(BASE, 200, "m_count", 8))
    rc, out, err = run(a, b)
    assert rc == 1, out + err
    first = out.splitlines()[0]
    assert "first divergence at t=200 ps" in first
    assert "TOP.finequad_core.m_count" in first
    assert "RTL       7 (0x00000007)" in out
    assert "reference 8 (0x00000008)" in out


def test_earliest_divergence_wins(tmp_path):
    rtl = changed(changed(BASE, 200, "m_count", 9), 100, "m_valid", 0)
    a = write_vcd(tmp_path / "rtl.vcd", rtl)
    b = write_vcd(tmp_path / "ref.vcd", BASE)
    rc, out, _ = run(a, b, "--period-ps", 50)
    assert rc == 1
    assert out.splitlines()[0].endswith("at t=100 ps (edge 2) in TOP.finequad_core.m_valid")
    assert "1 of 3 signal(s) diverge at that time (stopped reading there" in out
    rc, out, _ = run(a, b, "--all")
    assert rc == 1
    assert "first divergence at t=100 ps in TOP.finequad_core.m_valid" in out
    assert "2 of 3 signal(s) diverge; first divergence per signal:" in out
    assert "t=200 ps  TOP.finequad_core.m_count: RTL 9 (0x00000009), reference 7" in out


def test_divergence_at_a_time_only_one_file_changes(tmp_path):
    # the reference changes at 150, where the RTL records no change at all
    ref = sorted(BASE + [(150, "m_count", 6)], key=lambda c: c[0])
    a = write_vcd(tmp_path / "rtl.vcd", BASE)
    b = write_vcd(tmp_path / "ref.vcd", ref)
    rc, out, _ = run(a, b)
    assert rc == 1
    assert "first divergence at t=150 ps in TOP.finequad_core.m_count" in out
    assert "RTL       5 " in out and "reference 6 " in out
    assert "[1 mismatching change time(s)]" in out


def test_missing_signal_is_bad_input(tmp_path):
    a = write_vcd(tmp_path / "rtl.vcd", [c for c in BASE if c[1] != "m_a"],
                  widths={"m_valid": 1, "m_count": 32})
    b = write_vcd(tmp_path / "ref.vcd", BASE)
    rc, out, err = run(a, b)
    assert rc == 2
    assert "TOP.finequad_core.m_a" in err and "rtl.vcd" in err and "not found" in err
    # and a --signals name the reference lacks
    rc, _, err = run(b, b, "--signals", "m_count,nosuch")
    assert rc == 2
    assert "'nosuch' not found in reference VCD" in err and "ref.vcd" in err


def test_missing_file_is_bad_input(tmp_path):
    b = write_vcd(tmp_path / "ref.vcd", BASE)
    rc, _, err = run(tmp_path / "nope.vcd", b)
    assert rc == 2
    assert "RTL VCD" in err and "nope.vcd" in err
    (tmp_path / "junk.vcd").write_text("not a vcd\n")
    rc, _, err = run(tmp_path / "junk.vcd", b)
    assert rc == 2 and "junk.vcd" in err


def test_truncated_files_are_bad_input(tmp_path):
    """A VCD cut short is an error (exit 2) that says so, not an OK on what was read nor a
    design mismatch: cut inside the header (either file), cut between lines before the
    reference's last change, cut inside a line."""
    b = write_vcd(tmp_path / "ref.vcd", BASE)
    full = open(write_vcd(tmp_path / "rtl.vcd", BASE)).read()
    head = full[:full.index("$enddefinitions")]
    (tmp_path / "hdr.vcd").write_text(head)
    rc, out, err = run(tmp_path / "hdr.vcd", b, "--signals", "m_count")
    assert rc == 2 and "ends before $enddefinitions" in err and "hdr.vcd" in err, out + err
    rc, out, err = run(b, tmp_path / "hdr.vcd")
    assert rc == 2 and "reference VCD" in err and "ends before $enddefinitions" in err, err
    lines = full.splitlines(keepends=True)
    cut = next(k for k, ln in enumerate(lines) if ln.startswith("#200"))
    (tmp_path / "lines.vcd").write_text("".join(lines[:cut]))
    rc, out, err = run(tmp_path / "lines.vcd", b)
    assert rc == 2 and "ends at #110, before the reference's last change (#210)" in err, \
        out + err
    (tmp_path / "mid.vcd").write_text(full[:full.index("#200") + 2])
    rc, out, err = run(tmp_path / "mid.vcd", b)
    assert rc == 2 and "middle of a line" in err, out + err
    rc, out, err = run(tmp_path / "rtl.vcd", tmp_path / "mid.vcd")      # the reference too
    assert rc == 2 and "reference VCD" in err and "middle of a line" in err, out + err
    # a complete file that ends before a reference change to x (nothing to compare
    # there) is not truncated
    bx = write_vcd(tmp_path / "ref_x.vcd", BASE + [(300, "m_count", "x")])
    rc, out, err = run(tmp_path / "rtl.vcd", bx)
    assert rc == 0 and "OK" in out, out + err


def test_signal_subset(tmp_path):
    a = write_vcd(tmp_path / "rtl.vcd", changed(BASE, 200, "m_a", 1))
    b = write_vcd(tmp_path / "ref.vcd", BASE)
    assert run(a, b)[0] == 1
    rc, out, _ = run(a, b, "--signals", "m_valid,TOP.finequad_core.m_count")
    assert rc == 0 and "OK: 2 signal(s)" in out


def test_redundant_dumps_and_ranges(tmp_path):
    """A Verilator-style file (name [31:0], full-width vectors, values re-dumped at every
    time step) equals a minimal one: value-at-time semantics."""
    b = write_vcd(tmp_path / "ref.vcd", BASE)
    lines = ["$timescale 1ps $end", " $scope module TOP $end",
             "  $scope module finequad_core $end",
             "   $var wire 1 # m_valid $end", "   $var wire 32 $ m_count [31:0] $end",
             "   $var wire 1 % m_a $end", "  $upscope $end", " $upscope $end",
             "$enddefinitions $end"]
    val = {"m_valid": 0, "m_count": 0, "m_a": 1}
    ident = {"m_valid": "#", "m_count": "$", "m_a": "%"}
    times = sorted({0, 50, 100, 105, 110, 200, 210, 300})
    for t in times:
        for tt, n, v in BASE:
            if tt == t:
                val[n] = v
        lines.append(f"#{t}")
        for n in ("m_valid", "m_count", "m_a"):       # everything, changed or not
            v = val[n]
            lines.append(f"b{v:032b} {ident[n]}" if n == "m_count" else f"{v}{ident[n]}")
    (tmp_path / "rtl.vcd").write_text("\n".join(lines) + "\n")
    rc, out, err = run(tmp_path / "rtl.vcd", b)
    assert rc == 0, out + err


def test_reference_x_is_dont_care(tmp_path):
    ref = changed(BASE, 0, "m_count", "x")
    a = write_vcd(tmp_path / "rtl.vcd", BASE)
    b = write_vcd(tmp_path / "ref.vcd", ref)
    rc, out, _ = run(a, b)
    assert rc == 0 and "against reference x/z (don't-care)" in out
    rc, out, _ = run(a, b, "--strict-x")
    assert rc == 1
    assert "t=0 ps in TOP.finequad_core.m_count" in out and "reference x " in out
    # x in the RTL never matches a known reference value
    rc, out, _ = run(b, a)
    assert rc == 1 and "RTL       x " in out


def test_prefix_map(tmp_path):
    a = write_vcd(tmp_path / "rtl.vcd", BASE, scope="finequad_core")
    b = write_vcd(tmp_path / "ref.vcd", BASE)
    rc, _, err = run(a, b)
    assert rc == 2 and "--map" in err
    rc, out, _ = run(a, b, "--map", "TOP.finequad_core=finequad_core")
    assert rc == 0, out


def test_timescales_are_converted(tmp_path):
    a = write_vcd(tmp_path / "rtl.vcd", [(t * 1000, n, v) for t, n, v in BASE])
    b = write_vcd(tmp_path / "ref.vcd", BASE, timescale="1 ns")
    rc, out, err = run(a, b)
    assert rc == 0, out + err
    b2 = write_vcd(tmp_path / "ref2.vcd", changed(BASE, 200, "m_a", 1), timescale="1 ns")
    rc, out, _ = run(a, b2)
    assert rc == 1 and "first divergence at t=200000 ps" in out


def test_vcdref_timing_and_names(tmp_path):
    """sim/vcdref.py on a short model run: Verilator names/widths, m_valid one cycle at
    t_k + LATENCY, x outside the sample windows, and a clean self-comparison."""
    from sim import vcdref
    from sim.model import finequad_core as core

    n = 12
    ang = 2 * np.pi * 0.013 * np.arange(n)
    u1 = np.round(12000 * np.cos(ang)).astype(np.int64)
    u2 = np.round(12000 * np.sin(ang)).astype(np.int64)
    cfg = core.Config(div=5)
    res = core.run(u1, u2, cfg, trace=True)
    path = str(tmp_path / "ref.vcd")
    names = vcdref.write(path, res, cfg)
    assert f"{SCOPE}.m_count" in names and f"{SCOPE}.{vcdref.HARM}.phase_o" in names
    v = VCDVCD(path)
    assert f"{SCOPE}.m_count[31:0]" in v.signals and f"{SCOPE}.m_valid" in v.signals
    for name in ("u_lut.sin_mag_o[8:0]", "u_lut.cos_neg_o", "u_abgen.pos_o[31:0]",
                 "u_abgen.backlog_o[15:0]", "u_abgen.ovf_sticky_o", "u_correct.clip_o"):
        assert f"{SCOPE}.{name}" in v.signals, name
    tm = vcdref.rtl_timing()
    P, L = vcdref.PERIOD_PS, tm["LATENCY"]
    rise = [t for t, x in v[f"{SCOPE}.m_valid"].tv if x == "1"]
    assert rise == [(vcdref.T0 + 5 * k + L) * P for k in range(n)]
    # div=5: one-cycle windows with gaps; phase_o is x in the gaps
    ph = v[f"{SCOPE}.{vcdref.HARM}.phase_o[12:0]"].tv
    assert ph[0] == (0, "x")
    t_ph = vcdref.T0 + tm["PHASE_AT"]
    assert ph[1] == (t_ph * P, format(int(res["phase"][0]), "b"))
    assert ph[2] == ((t_ph + 1) * P, "x")
    rc, out, err = run(path, path)
    assert rc == 0, out + err
    # one cycle more latency on the ports: caught at sample 0's m_valid
    late = dict(tm, LATENCY=L + 1)
    path2 = str(tmp_path / "late.vcd")
    vcdref.write(path2, res, cfg, timing=late)
    rc, out, _ = run(path2, path, "--period-ps", P)
    assert rc == 1
    assert out.splitlines()[0].endswith(
        f"first divergence at t={(vcdref.T0 + L) * P} ps (edge {vcdref.T0 + L}) in {SCOPE}.m_valid")
