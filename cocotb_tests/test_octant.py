"""octant (Table 2) against sim.model.fastpath.octant, both table kinds. Latency 3
(rtl/octant.v): inputs on edge e, outputs after edge e + 2 (j_o of the exact table is
combinational from registers of edge e + 2). oct2_o is the model's base phase / 2048, neg_o
its neg, j_o its j (exact: round(2048 |small| / |large|) through the reciprocal table and
the carry-save multiply; paper: the small magnitude)."""
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

LATENCY = 3


def directed():
    v = []
    # every pair of special values: zeros, signs, the j rounding steps ((s + 4) >> 3),
    # the j clip at 2047, the abs() overflow of -32768
    sp = [0, 1, 2, 3, 4, 5, 11, 12, 13, 11585, 11586, 16370, 16371, 16372, 16379, 16380,
          16383, 16384, 16385, 20000, 32766, 32767]
    vals = sorted({s for x in sp for s in (x, -x)} | {-32768})
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
    v += [(-32768, -32768), (-32768, 32767), (32767, -32768), (-32768, 0), (0, -32768)]
    return v


def random_vectors(rng, n):
    import math
    v = []
    for _ in range(n):
        r = rng.random()
        if r < 0.4:
            v.append((rng.randint(-32768, 32767), rng.randint(-32768, 32767)))
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


@cocotb.test()
async def octant_all(dut):
    import numpy as np
    from sim.model import fastpath as fp

    exact = fqtb.env_int("TABLE_EXACT")
    rng = random.Random(303 + exact)
    vec = directed() + random_vectors(rng, 6000)
    a = np.array(vec, dtype=np.int64)
    j, base, neg = fp.octant(a[:, 0], a[:, 1], "exact" if exact else "paper")
    exp = list(zip(j.tolist(), (base >> 11).tolist(), neg.tolist()))
    assert set((base & 2047).tolist()) == {0}

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
    out_at = {e + LATENCY - 1: i for e, i in by_edge.items()}
    for e in range(-1, edges[-1] + LATENCY + 2):
        if e >= 0:
            valid = fqtb.uval(dut.valid_o)
            if e in out_at:
                i = out_at[e]
                got = (fqtb.uval(dut.j_o), fqtb.uval(dut.oct2_o), fqtb.uval(dut.neg_o))
                if valid != 1 or got != exp[i]:
                    bad.append(f"u1c={vec[i][0]} u2c={vec[i][1]}: valid={valid} "
                               f"(j,oct2,neg)={got}, model {exp[i]}")
            elif valid:
                bad.append(f"valid_o high after edge {e}, no sample due")
        if e + 1 in by_edge:
            x, y = vec[by_edge[e + 1]]
            dut.valid_i.value = 1
        else:
            x, y = rng.randint(-32768, 32767), rng.randint(-32768, 32767)
            dut.valid_i.value = 0
        dut.u1c_i.value = x
        dut.u2c_i.value = y
        await bench.step()
    assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])
