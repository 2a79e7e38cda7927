"""octant (Table 2) against sim.model.fastpath.octant, both table kinds, bit for bit.

Timing (rtl/octant.v; sim.model.core CORR_AT, OCT_AT, ADDR_AT): the magnitudes and signs
presented for edge E (= t + CORR_AT + 1 in the core) give valid_o, oct2_o and neg_o after
edge E + (OCT_AT - CORR_AT - 1), and j_o and bin_o (combinational, read by the block RAMs
on edge t + ADDR_AT) after edge E + (ADDR_AT - CORR_AT - 2). oct2_o is the model's base
phase / 2048, neg_o its neg, j_o its j (exact: round(2048 |small| / |large|) through the
reciprocal table and the multiply; paper: the small magnitude), bin_o the harmonic bin
phase >> 7 of the phase the table gives (Lut.phase). Directed: special magnitudes and
their pairs, every normalising shift at the reciprocal table's extremes, diagonal ties,
and for every harmonic bin threshold the ratios just below, at and above it (both signs,
both halves of an octant); then seeded random magnitudes (any, near the unit circle, near
the octant borders); back to back, then with idle clocks (garbage inputs)."""
import random

import pytest

import fqtb


@pytest.mark.parametrize("exact", [1, 0], ids=["EXACT1", "EXACT0"])
@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_octant(sim, exact):
    fqtb.run_block(sim, "octant", fqtb.sources("octant"), "test_octant",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR), TABLE_EXACT=exact),
                   extra_env=dict(TABLE_EXACT=exact))


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402

def directed():
    v = []
    # every pair of special values: zeros, signs, the j rounding steps ((s + 4) >> 3),
    # the j clip at 2047, the saturated magnitude 32767
    sp = [0, 1, 2, 3, 4, 5, 11, 12, 13, 11585, 11586, 16370, 16371, 16372, 16379, 16380,
          16383, 16384, 16385, 20000, 32766, 32767]
    vals = sorted({s for x in sp for s in (x, -x)})
    for x in vals:
        for y in vals:
            v.append((x, y))
    # the reciprocal table's extremes: |large| at and around powers of two (m ~ 1 and ~ 2,
    # every normalising shift), small = large, large - 1, half, tiny
    for e in range(15):
        for lg in {(1 << e) - 1, 1 << e, (1 << e) + 1}:
            if 0 < lg <= 32767:
                for sm in {lg, lg - 1, lg // 2, 1, 0}:
                    v += [(lg, sm), (-sm, lg), (-lg, -sm), (sm, -lg)]
    # diagonal ties |x| == |y| and their neighbours, in all four quadrants
    for a in [1, 2, 7, 100, 4096, 11585, 16383, 16384, 32767]:
        for d in (-1, 0, 1):
            for sx in (1, -1):
                for sy in (1, -1):
                    b = a + d
                    if b <= 32767:
                        v.append((sx * a, sy * b))
                        v.append((sx * b, sy * a))
    return v


def threshold_vectors(exact):
    """Ratios around every harmonic bin threshold T (j >= T), at several |large|."""
    from sim.model import tables
    kind = "exact" if exact else "paper"
    v = []
    for thr in tables.bin_thresholds(kind):
        for t in thr:
            if t >= tables.ROWS:
                continue
            for lg in (16384, 12000, 23170, 32767):
                if exact:
                    c = t * lg / 2048
                else:
                    c, lg = t * 8, max(lg, t * 8 + 8)
                for sm in {int(c) + d for d in range(-6, 7)}:
                    if 0 <= sm <= lg <= 32767:
                        for sx in (1, -1):
                            for sy in (1, -1):
                                v += [(sx * lg, sy * sm), (sx * sm, sy * lg)]
    return v


def random_vectors(rng, n):
    import math
    v = []
    for _ in range(n):
        r = rng.random()
        if r < 0.4:
            v.append((rng.randint(-32767, 32767), rng.randint(-32767, 32767)))
        elif r < 0.8:   # on and around the unit circle (16384), any angle
            a = rng.uniform(-math.pi, math.pi)
            rad = rng.uniform(0.5, 1.5) * 16384
            v.append((round(rad * math.cos(a)), round(rad * math.sin(a))))
        else:           # near the octant borders: near-diagonal, near an axis
            m = rng.randint(0, 32767)
            d = rng.randint(-3, 3)
            o = min(32767, max(0, m + d))
            sx, sy = rng.choice((1, -1)), rng.choice((1, -1))
            v.append((sx * m, sy * o) if rng.random() < 0.5 else (sx * m, sy * rng.randint(0, 9)))
    return v


def magnitudes(vec):
    """Signed corrected values -> (ax, ay, xn, yn) as rtl/correct.v delivers them."""
    return [(min(abs(x), 32767), min(abs(y), 32767), int(x < 0), int(y < 0)) for x, y in vec]


@cocotb.test()
async def octant_all(dut):
    import numpy as np
    from sim.model import core
    from sim.model import fastpath as fp

    exact = fqtb.env_int("TABLE_EXACT")
    kind = "exact" if exact else "paper"
    rng = random.Random(303 + exact)
    vec = magnitudes(directed() + threshold_vectors(exact) + random_vectors(rng, 6000))
    a = np.array(vec, dtype=np.int64)
    j, base, neg = fp.octant(a[:, 0], a[:, 1], a[:, 2], a[:, 3], kind)
    phase = fp.Lut(kind).phase(j, base, neg)
    assert set((base & 2047).tolist()) == {0}
    exp1 = list(zip((base >> 11).tolist(), neg.tolist()))
    exp2 = list(zip(j.tolist(), (phase >> 7).tolist()))
    d1 = core.OCT_AT - core.CORR_AT - 1          # valid, oct2, neg: after edge E + d1
    d2 = core.ADDR_AT - core.CORR_AT - 2         # j, bin: after edge E + d2

    bench = fqtb.ClockedBench(dut)
    await bench.start()
    bad = []
    # back to back, then a second pass with idle clocks in between
    gaps = [0] * len(vec) + [rng.choice((0, 1, 2)) for _ in vec]
    order = list(range(len(vec))) * 2
    edges, e = [], 0
    for gp in gaps:
        e += gp
        edges.append(e)
        e += 1
    by_edge = dict(zip(edges, order))
    at1 = {e + d1: i for e, i in by_edge.items()}
    at2 = {e + d2: i for e, i in by_edge.items()}
    for e in range(-1, edges[-1] + d2 + 2):
        if e >= 0:
            valid = fqtb.uval(dut.valid_o)
            if (valid == 1) != (e in at1):
                bad.append(f"valid_o={valid} after edge {e}")
            if e in at1:
                i = at1[e]
                got = (fqtb.uval(dut.oct2_o), fqtb.uval(dut.neg_o))
                if got != exp1[i]:
                    bad.append(f"(ax,ay,xn,yn)={vec[i]}: (oct2,neg)={got}, model {exp1[i]}")
            if e in at2:
                i = at2[e]
                got = (fqtb.uval(dut.j_o), fqtb.uval(dut.bin_o))
                if got != exp2[i]:
                    bad.append(f"(ax,ay,xn,yn)={vec[i]}: (j,bin)={got}, model {exp2[i]}")
        if e + 1 in by_edge:
            x = vec[by_edge[e + 1]]
            dut.valid_i.value = 1
        else:
            x = (rng.randint(0, 32767), rng.randint(0, 32767), rng.randint(0, 1),
                 rng.randint(0, 1))
            dut.valid_i.value = 0
        dut.ax_i.value, dut.ay_i.value, dut.xn_i.value, dut.yn_i.value = x
        await bench.step()
    assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])
    dut._log.info("octant (%s table): %d samples equal, %d distinct bins", kind, len(vec),
                  len(set(b for _, b in exp2)))
