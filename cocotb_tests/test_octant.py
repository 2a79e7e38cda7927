"""octant (Table 2 and the address's scale) against sim.model.octant and scale,
both table kinds, bit for bit: every output of every sample, and valid_o on every edge.

Timing (rtl/octant.v header; sim.model.finequad_core CORR_AT, OCT_AT, ADDR_AT): the magnitudes and
signs presented for edge E (= t + CORR_AT + 1 in the core, the edge after correct
registers them), with zl_i = lzc15(ax | ay) (rtl/correct.v forms it beside them), give
valid_o, oct2_o and neg_o after edge E + (OCT_AT - CORR_AT - 1), and j_o and t_o
(combinational, read by the block RAMs on edge t + ADDR_AT) after edge
E + (ADDR_AT - CORR_AT - 2). Expected values: oct2_o = the model's base / 2048, neg_o its
neg, j_o its j (exact: round(2048 |small| / |large|) through the reciprocal table and the
multiply, clipped at 2047; paper: min(2047, (|small| + 4) >> 3)), t_o its scale
(scale: exact min(4095, floor(p / 2**15)) of the ratio product, so that j =
(t + 1) >> 1 clipped; paper 2 j): the address of the 4096-row phase table and the input of
the harmonic bin (rtl/hbin.v, tested exhaustively over t in test_hbin.py).

Vectors (ax, ay, xn, yn), u15 magnitudes and signs as rtl/correct.v delivers them:
  - directed: every pair of special signed values (zero, +-1, the paper address's rounding
    steps (s + 4) >> 3, its clip at 2047, 16384, the saturated 32767); |large| at and
    around every power of two (every normalising shift, both ends of the reciprocal
    table) with small = large, large - 1, large / 2, 1, 0; diagonal ties |x| = |y| and
    their neighbours (ties take the low octant) in all quadrants; "negative zeros" (a
    zero magnitude with its sign bit set: correct gives |u| = 0, sign 1 for sums in
    [-8192, -1]) with every sign combination;
  - every harmonic bin threshold T of both sets (floor for neg = 0, ceil for neg = 1),
    so that t_o is right on both sides of every threshold rtl/hbin.v compares it with:
    for |large| from 128 to 32767 (normalising shifts 0 to 7 at both ends of the
    reciprocal table, the unit circle, the rail, a few random; paper: three |large|) the
    last |small| with j < T and the first with j >= T (found with the model), each in two
    octants with neg = 0 and two with neg = 1; the test checks that j = T - 1 and j = T
    are both reached with both values of neg before it runs;
  - a sweep of t_o's whole scale (rtl/octant.v's t = floor(p / 2**15):
    every t from 0 to 4095 and the clip, exact table; every j, paper table), once with
    neg = 0 and once with neg = 1, the octant drawn at random;
  - seeded random: any magnitudes and signs, on and around the unit circle (16384), near
    the octant borders (near-diagonal, near an axis);
fed back to back, then a random subset of them again with 0, 1 or 2 idle clocks between
strobes, where the inputs hold random garbage with valid_i low."""
import random

import pytest

import fqtb


@pytest.mark.parametrize("exact", [1, 0], ids=["EXACT1", "EXACT0"])
@pytest.mark.parametrize("sim", fqtb.simulators("octant"))
def test_octant(sim, exact):
    fqtb.run_block(sim, "octant", fqtb.sources("octant"), "test_octant",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR), TABLE_EXACT=exact),
                   extra_env=dict(TABLE_EXACT=exact))


# (not on GHDL's netlist: the bench reads the VHDL's instance by its name, and synthesis
# leaves MULT18X18D a black box)
@pytest.mark.parametrize("sim", [s for s in fqtb.simulators("octant")
                                 if s not in ("verilator", "ghdl-synth")])
def test_octant_mult18(sim):
    """OPT_ECP5_MULT = 1 as synthesis sees it (the MULT18X18D instance, whose operand
    registers are the DSP block's), with a behavioural stand-in of the primitive: the
    instance's wiring (the operands' and the used product bits' order) gives the same
    outputs as the inferred form, on the same vectors (exact table). Icarus compiles
    rtl/octant.v with SYNTHESIS defined and cocotb_tests/sim_mult18x18d.v; GHDL runs
    rtl/vhdl/octant.vhd, which instantiates the primitive whenever OPT_ECP5_MULT = 1, with
    cocotb_tests/sim_mult18x18d.vhd. (A clock enable of 1 instead of v1 would pass too: rcp
    and sn only change with a sample.)"""
    vhdl = fqtb.is_vhdl(sim)
    fqtb.run_block(sim, "octant",
                   fqtb.sources("octant")
                   + [fqtb.HERE / ("sim_mult18x18d.vhd" if vhdl else "sim_mult18x18d.v")],
                   "test_octant",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR), TABLE_EXACT=1,
                                   OPT_ECP5_MULT=1),
                   extra_env=dict(TABLE_EXACT=1, MULT18=1), tag="mult18",
                   extra_build_args=() if vhdl else ("-DSYNTHESIS",))


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402

UMAX = 32767        # u15 magnitudes (correct saturates |u| to 32767)
N_RANDOM = 5000     # seeded random vectors
N_GAPPED = 5000     # vectors of the second pass, with idle clocks


def magnitudes(vec):
    """Signed corrected values -> (ax, ay, xn, yn) as rtl/correct.v delivers them."""
    return [(min(abs(x), UMAX), min(abs(y), UMAX), int(x < 0), int(y < 0)) for x, y in vec]


def octants(lg, sm):
    """(ax, ay, xn, yn) of |large| = lg, |small| = sm in all eight octants (both signs of
    both axes, small on either axis); lg > sm puts four of them in the low octants."""
    return [(a, b, xn, yn) for a, b in ((lg, sm), (sm, lg)) for xn in (0, 1) for yn in (0, 1)]


def directed():
    v = []
    # every pair of special values: zeros, signs, the paper address's rounding steps
    # ((s + 4) >> 3), its clip at 2047, 16384, the saturated magnitude 32767
    sp = [0, 1, 2, 3, 4, 5, 11, 12, 13, 11585, 11586, 16370, 16371, 16372, 16379, 16380,
          16383, 16384, 16385, 20000, 32766, 32767]
    vals = sorted({s for x in sp for s in (x, -x)})
    v += magnitudes([(x, y) for x in vals for y in vals])
    # the reciprocal table's extremes: |large| at and around powers of two (m ~ 1 and ~ 2,
    # every normalising shift), small = large, large - 1, half, tiny
    for e in range(16):
        for lg in sorted({(1 << e) - 1, 1 << e, (1 << e) + 1}):
            if 0 < lg <= UMAX:
                for sm in sorted({lg, lg - 1, lg // 2, 1, 0}):
                    v += octants(lg, sm)
    # diagonal ties |x| == |y| and their neighbours, in all four quadrants
    for a in [1, 2, 7, 100, 4096, 11585, 16383, 16384, 32767]:
        for d in (-1, 0, 1):
            b = a + d
            if b <= UMAX:
                v += octants(a, b) + octants(b, a)
    # negative zeros: a zero magnitude with its sign bit set
    for ax, ay in [(0, 0), (0, 1), (1, 0), (0, 16384), (16384, 0), (0, UMAX), (UMAX, 0)]:
        v += [(ax, ay, xn, yn) for xn in (0, 1) for yn in (0, 1)]
    return v


def larges(rng):
    """|large| for the threshold search: every normalising shift at both ends of the
    reciprocal table (m ~ 1 and m ~ 2), the unit circle, the rail, a few at random."""
    out = {16384, 11585, 12000, 23170, UMAX}
    for e in range(7, 15):
        out |= {1 << e, (1 << e) + 1, (2 << e) - 1}
    out |= {rng.randint(128, UMAX) for _ in range(4)}
    return sorted(out)


def threshold_vectors(kind, rng):
    """For every bin threshold T (j >= T) and every |large| of larges(): the last |small|
    with j < T and the first with j >= T, by the model's j, each in two octants with
    neg = 0 and two with neg = 1."""
    import numpy as np
    from sim.model import octant as octant_m
    from sim.model import tables

    thr = sorted({t for s in tables.bin_thresholds(kind) for t in s if t < tables.ROWS})
    # the paper's j does not depend on |large|: a few suffice
    lgs = larges(rng) if kind == "exact" else [16384, 23170, UMAX]
    v = []
    for lg in lgs:
        sm = np.arange(lg + 1, dtype=np.int64)
        j, _, _ = octant_m.octant(np.full_like(sm, lg), sm, 0 * sm, 0 * sm, kind)
        for t in thr:
            first = int(np.searchsorted(j, t))     # j is non-decreasing in |small|
            if 0 < first <= lg:
                for s in (first - 1, first):
                    # two octants with neg = 0 and two with neg = 1, drawn at random
                    o = octants(lg, s)
                    negs = [int(xn ^ yn ^ (ax < ay)) for ax, ay, xn, yn in o]
                    for nv in (0, 1):
                        v += rng.sample([x for x, n in zip(o, negs) if n == nv], 2)
    return v


def sweep_vectors(exact, rng):
    """Every value of the address's scale t (rtl/octant.v: exact t = floor(p / 2**15),
    p = sn * RECIP[ln[13:5]], here with |large| = 32767: ln = 32767, sn = |small| >> 1;
    paper t = 2 j) and the exact table's clip, each once with neg = 0 and once with
    neg = 1 in a random octant. Returns (vectors, t of each)."""
    from sim.model import tables

    v, ts = [], []
    if exact:
        r = tables.recip_table()[UMAX >> 5 & 511]
        sn = 0
        for t in range(4096):
            while (sn * r) >> 15 < t:
                sn += 1
            v.append(2 * sn)
            ts.append(t)
        v.append(UMAX - 1)                          # sn = 16383: p >= 2**27, clipped
        ts.append(4096)
    else:
        v = [8 * j for j in range(2048)]           # j = (8 j + 4) >> 3
        ts = [2 * j for j in range(2048)]
    out, tout = [], []
    for sm, t in zip(v, ts):
        for neg in (0, 1):
            low = rng.random() < 0.5
            xn = rng.randint(0, 1)
            yn = xn ^ neg if low else xn ^ neg ^ 1  # low: neg = xn ^ yn; high: !(xn ^ yn)
            out.append((UMAX, sm, xn, yn) if low else (sm, UMAX, xn, yn))
            tout.append(t)
    return out, tout


def random_vectors(rng, n):
    import math
    v = []
    for _ in range(n):
        r = rng.random()
        if r < 0.4:
            v += magnitudes([(rng.randint(-32768, 32767), rng.randint(-32768, 32767))])
        elif r < 0.8:   # on and around the unit circle (16384), any angle
            a = rng.uniform(-math.pi, math.pi)
            rad = rng.uniform(0.5, 1.5) * 16384
            v += magnitudes([(round(rad * math.cos(a)), round(rad * math.sin(a)))])
        else:           # near the octant borders: near-diagonal, near an axis
            m = rng.randint(0, UMAX)
            o = min(UMAX, max(0, m + rng.randint(-3, 3))) if rng.random() < 0.5 \
                else rng.randint(0, 9)
            xn, yn = rng.randint(0, 1), rng.randint(0, 1)
            v.append((m, o, xn, yn) if rng.random() < 0.5 else (o, m, xn, yn))
    return v


def check_threshold_coverage(kind, j, neg):
    """Both sides of every bin threshold, with neg = 0 and with neg = 1 (else the vectors
    do not test what they claim)."""
    from sim.model import tables
    miss = []
    for t in sorted({t for s in tables.bin_thresholds(kind) for t in s if t < tables.ROWS}):
        for nv in (0, 1):
            got = {int(x) for x, n in zip(j, neg) if n == nv and x in (t - 1, t)}
            if got != {t - 1, t}:
                miss.append((t, nv, sorted(got)))
    assert not miss, f"thresholds not straddled (T, neg, j seen): {miss}"


@cocotb.test()
async def octant_all(dut):
    import numpy as np
    from sim.model import finequad_core as core
    from sim.model import lut as lut_m, octant as octant_m

    exact = fqtb.env_int("TABLE_EXACT")
    if fqtb.env_int("MULT18", 0):
        # the primitive's branch was elaborated (not the inferred form)
        assert dut.g_mult18.u_mult is not None
    kind = "exact" if exact else "paper"
    rng = random.Random(303 + exact)
    sweep, sweep_t = sweep_vectors(exact, rng)
    head = directed() + threshold_vectors(kind, rng)
    vec = head + sweep + random_vectors(rng, N_RANDOM)
    assert all(0 <= ax <= UMAX and 0 <= ay <= UMAX and xn in (0, 1) and yn in (0, 1)
               for ax, ay, xn, yn in vec)
    a = np.array(vec, dtype=np.int64)
    j, base, neg = octant_m.octant(a[:, 0], a[:, 1], a[:, 2], a[:, 3], kind)
    phase = lut_m.Lut(kind).phase(j, base, neg)
    assert set((base & 2047).tolist()) == {0}
    check_threshold_coverage(kind, j, neg)
    # the sweep's t (worked out here from rtl/octant.v's formats) agrees with the model's
    # j = (t + 1) >> 1 (clipped), so it does span the bin logic's whole scale
    js = j[len(head):len(head) + len(sweep)]
    assert js.tolist() == [min(2047, (t + 1) >> 1) if exact else t >> 1 for t in sweep_t]
    assert len(set(sweep_t)) == (4097 if exact else 2048)
    t = octant_m.scale(a[:, 0], a[:, 1], kind)
    # the sweep's t is the model's too
    assert t[len(head):len(head) + len(sweep)].tolist() == [min(4095, x) for x in sweep_t]
    exp1 = list(zip((base >> 11).tolist(), neg.tolist()))
    exp2 = list(zip(j.tolist(), t.tolist()))
    d1 = core.OCT_AT - core.CORR_AT - 1          # valid, oct2, neg: after edge E + d1
    d2 = core.ADDR_AT - core.CORR_AT - 2         # j, t: after edge E + d2

    # back to back, then a random subset with idle clocks in between
    order = list(range(len(vec))) + rng.sample(range(len(vec)), N_GAPPED)
    gaps = [0] * len(vec) + [rng.choice((0, 1, 1, 2)) for _ in range(N_GAPPED)]
    edges, e = [], 0
    for gp in gaps:
        e += gp
        edges.append(e)
        e += 1
    by_edge = dict(zip(edges, order))
    at1 = {e + d1: i for e, i in by_edge.items()}
    at2 = {e + d2: i for e, i in by_edge.items()}

    bench = fqtb.ClockedBench(dut)
    await bench.start()
    bad, checked = [], 0
    for e in range(-1, edges[-1] + max(d1, d2) + 3):
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
                got = (fqtb.uval(dut.j_o), fqtb.uval(dut.t_o))
                checked += 1
                if got != exp2[i]:
                    bad.append(f"(ax,ay,xn,yn)={vec[i]}: (j,t)={got}, model {exp2[i]}")
        if e + 1 in by_edge:
            x = vec[by_edge[e + 1]]
            dut.valid_i.value = 1
        else:
            x = (rng.randint(0, UMAX), rng.randint(0, UMAX), rng.randint(0, 1),
                 rng.randint(0, 1))
            dut.valid_i.value = 0
        dut.ax_i.value, dut.ay_i.value, dut.xn_i.value, dut.yn_i.value = x
        dut.zl_i.value = int(octant_m.lzc15(x[0] | x[1]))
        await bench.step()
        if len(bad) > 50:
            break
    assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])
    assert checked == len(order)
    dut._log.info("octant (%s table): %d samples (%d distinct) equal, %d distinct t, "
                  "%d distinct bins", kind, len(order), len(set(vec)),
                  len(set(x for _, x in exp2)), len(set((phase >> 7).tolist())))
