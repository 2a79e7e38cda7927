"""Distance-coded reference marks in the model (sim/model/dcode.py, rtl/dcode.v's rules):
the decode of every pair of neighbouring marks on a 1000 / 1001 scale in both directions,
no position from a missing mark, none wrong from an extra one with dc_confirm, and the
absolute position right after two marks from start points along the scale, through the
whole core. The RTL is held to the model by cocotb_tests/test_dcode.py."""
import numpy as np
import pytest

from sim import siggen
from sim.model import dcode
from sim.model import finequad_core as core
from sim.model import refmark

A, B = 1000, 1001
LAYOUT = siggen.distance_coded(A, B, 40 * A)


def test_layout():
    """Fixed marks every A, coded marks A / 2 + (j + 1) after fixed mark j; every distance
    between neighbours occurs once."""
    assert LAYOUT[:6] == [0, 501, 1000, 1502, 2000, 2503]
    d = np.diff(LAYOUT)
    assert len(set(d.tolist())) == len(d) and d.min() > 0 and d.max() < A


def test_every_neighbour_pair_both_directions():
    for i in range(len(LAYOUT) - 1):
        p, q = LAYOUT[i], LAYOUT[i + 1]
        assert dcode.decode(q - p, True, A, B) == (True, q, p)
        assert dcode.decode(q - p, False, A, B) == (True, p, q)


def test_a_missing_mark_gives_no_position():
    """Marks two or more apart (the ones between missed) are never a valid distance."""
    for i in range(len(LAYOUT)):
        for j in range(i + 2, min(i + 5, len(LAYOUT))):
            for fwd in (True, False):
                assert not dcode.decode(LAYOUT[j] - LAYOUT[i], fwd, A, B)[0]


def test_invalid_layouts_decode_nothing():
    for a, b in ((0, 1), (999, 1000), (1000, 1000), (1000, 990)):
        assert not any(dcode.decode(m, f, a, b)[0] for m in range(1, 1200) for f in (0, 1))


def chain(marks, confirm, per_period=40):
    """The decoder (rtl/dcode.v's events) over a stage crossing `marks` (signal periods,
    in the order crossed, each at a reference point), one period per `per_period` edges:
    [(edge, abs_valid, ABS_COUNT / 4 n, the mark)] after each mark's decode."""
    rm = refmark.RefMark()
    dc = dcode.DCode(32, A, B, confirm, n=1)
    e, pos, out = 0, marks[0], []
    for k, m in enumerate(marks):
        if k == 0:
            e += per_period
            dc.edge(e, 0, True, 4 * pos, False)
        step = 1 if m > pos else -1
        while pos != m:
            e += per_period
            dc.finish(e - 1, rm)
            pos += step
            dc.edge(e, step, pos == m, 4 * pos, False)
        dc.finish(e + dcode.DC_LAT, rm)
        out.append((e, dc.abs_valid, dc.abs_count // 4, m))
    return out


@pytest.mark.parametrize("confirm", [0, 1])
def test_two_or_three_marks_in_one_direction(confirm):
    """From every mark of the layout, in both directions: abs_valid after the second mark
    (dc_confirm = 0) or the third (1), at the position of the mark last crossed."""
    for j in range(0, len(LAYOUT) - 3):
        for marks in (LAYOUT[j:j + 3], LAYOUT[j:j + 3][::-1]):
            out = chain(marks, confirm)
            assert out[0][1] == 0
            assert out[1][1] == (0 if confirm else 1)
            assert out[2][1] == 1
            for _, v, pos, m in out:
                assert not v or pos == m


@pytest.mark.parametrize("confirm", [0, 1])
def test_an_extra_mark(confirm):
    """A spurious mark (at a reference point where the scale has none) among real marks
    crossed in one direction: with dc_confirm = 1 never a wrong position; with 0 a wrong
    one only while the spurious mark is the last one crossed."""
    rng = np.random.default_rng(1)
    real = set(LAYOUT)
    wrong_seen = 0
    for _ in range(300):
        j = int(rng.integers(0, len(LAYOUT) - 5))
        marks = LAYOUT[j:j + 5]
        i = int(rng.integers(0, 4))
        lo, hi = marks[i], marks[i + 1]
        if hi - lo < 2:
            continue
        marks = marks[:i + 1] + [int(rng.integers(lo + 1, hi))] + marks[i + 1:]
        if rng.random() < 0.5:
            marks = marks[::-1]
        for _, v, pos, m in chain(marks, confirm):
            if v and pos != m:
                assert not confirm and m not in real, (marks, pos, m)
                wrong_seen += 1
    if not confirm:
        assert wrong_seen, "no spurious mark gave a plausible distance (the test is weak)"


def test_homing_armed_while_abs_valid():
    """REF.home written while abs_valid is already 1: the next decode homes (the count
    becomes HOME + the absolute count there)."""
    marks = LAYOUT[3:8]
    rm = refmark.RefMark(home_count=77)
    dc = dcode.DCode(32, A, B, 0, n=1, home=77)
    e, pos = 40, marks[0]
    dc.edge(e, 0, True, 4 * pos, False)
    for k, m in enumerate(marks[1:]):
        if k == 2:
            assert dc.abs_valid == 1 and not rm.pos_valid
            rm.home_armed = True
        step = 1
        while pos != m:
            e += 40
            dc.finish(e - 1, rm)
            pos += step
            dc.edge(e, step, pos == m, 4 * pos, False)
        dc.finish(e + dcode.DC_LAT, rm)
    assert rm.pos_valid == 1 and not rm.home_armed
    # homed at the first decode after the write (mark 3000: x = 4 * 3000 with n = 1, its
    # absolute count the same): off = HOME - x + ABS, REF_COUNT = HOME + ABS
    assert rm.off == 77 and rm.ref_count == 77 + 4 * marks[3]


def test_a_missing_mark_in_a_chain():
    """A mark missed inside a run of marks clears abs_valid (never a position from the
    distance across it); the next two neighbours give it again."""
    marks = LAYOUT[3:6] + LAYOUT[7:10]
    out = chain(marks, 0)
    assert [v for _, v, _, _ in out] == [0, 1, 1, 0, 1, 1]
    assert all(pos == m for _, v, pos, m in out if v)


# ---- through the whole core ------------------------------------------------------------------
PITCH = 20.0
N = 25
REF_Q = 61
CAL = 6000


def run_core(x0, x1, marks, confirm=0):
    """The model on a calibrating move of 5 periods from an integer period 6 below x0, a
    move to x0, then x0 -> x1 at up to 0.1 period per sample (positions in periods from
    the first fixed mark, which lies 10 periods from the encoder's zero); returns (the
    result from x0 on, the raw count at the first fixed mark's reference point)."""
    p0 = 10
    xs = np.floor(x0) - 6
    cent = [PITCH * (p0 + s + (REF_Q + 0.5) / (4 * N)) for s in marks]
    cal = siggen.s_curve(CAL, 1.0, 5 * PITCH, CAL - 200.0, 100.0, (p0 + xs) * PITCH)
    a, b = (p0 + x0) * PITCH, (p0 + x1) * PITCH
    lead = siggen.s_curve(200, 1.0, a - cal[-1], 200.0, 0.0, cal[-1])
    n = int(2 * abs(b - a) / (0.1 * PITCH)) + 8
    x = np.concatenate([cal, lead, siggen.s_curve(n, 1.0, b - a, float(n), 0.0, a)])
    ref = siggen.reference(x, cent, 0.5 * PITCH)
    ref[:CAL + 200] = 0                              # no mark before x0
    u1, u2, _ = siggen.encode(x, PITCH, siggen.Signal(noise=0.005), seed=3)
    cfg = core.Config(interp=N, ref_q=REF_Q, dc_spacing=A, dc_coded=B, dc_confirm=confirm,
                      home_arm=True, home_count=0)
    res = core.run(u1, u2, cfg, ref=ref, trace=True)
    c0 = 4 * N * (0 - int(xs)) + REF_Q
    return {k: v[CAL + 200:] for k, v in res.items()
            if isinstance(v, np.ndarray) and len(v) == len(x)}, c0


# start points: five chosen (the first marks, both directions, far along) and five at
# random along 17 000 periods, each moving 1 600 periods one way
_RNG = np.random.default_rng(11)
STARTS = [(120.0, 1700.0), (3400.5, 1900.0), (2650.0, 3900.0), (7999.0, 6900.0),
          (15003.0, 16600.0)] + [
    (float(s), float(s + d)) for s, d in zip(_RNG.uniform(1700, 15300, 5).round(2),
                                             _RNG.choice([-1600, 1600], 5))]


@pytest.mark.parametrize("x0,x1", STARTS)
def test_homed_after_two_marks_through_the_core(x0, x1):
    """Homing armed (HOME = 0): the count is set at the decode after the second mark
    crossed, to the absolute count (the raw count less the first fixed mark's), and
    ABS_COUNT is the second mark's absolute count."""
    marks = [s for s in LAYOUT if s <= 17000]
    res, c0 = run_core(x0, x1, marks)
    lat = np.flatnonzero(np.diff(res["ref_count"]) != 0) + 1
    pv = np.flatnonzero(res["pos_valid"])
    assert len(lat) >= 2 and len(pv), (lat, len(pv))
    raw = res["count_raw"]
    # the second latch's decode homes: pos_valid from the sample after it
    second = lat[1]
    assert pv[0] == second + 1, (pv[0], lat)
    k = pv[0]
    assert res["abs_valid"][k] == 1
    assert res["count"][k:].tolist() == (raw[k:] - c0).tolist()
    crossed = res["ref_count"][second] - c0          # the second mark's absolute count
    assert crossed % (4 * N) == 0 and crossed // (4 * N) in marks
    assert res["abs_count"][k] == crossed
