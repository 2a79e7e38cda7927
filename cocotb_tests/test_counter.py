"""counter (x4 up/down counter resolved by the fine phase) against sim.model.fastpath.counter.

Latency 3: a sample on edge e is on the outputs after edge e + 2; n_i is used on edge
e + 1. Inputs are random A/B/phase sequences: legal quadrature steps, double transitions
(both channels at once), big phase jumps (whole n-th order periods), A/B that disagree
with the phase, standstill; idle clocks with garbage inputs; changes of n; rst. COUNT_W=16
runs far enough to wrap the counter in both directions."""
import random

import pytest

import fqtb

COUNT_WS = [32, 16]


@pytest.mark.parametrize("count_w", COUNT_WS, ids=[f"COUNT{w}" for w in COUNT_WS])
@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_counter(sim, count_w):
    fqtb.run_block(sim, "counter", fqtb.sources("counter"), "test_counter",
                   parameters=dict(COUNT_W=count_w))


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402

AB = {0: (1, 1), 1: (0, 1), 2: (0, 0), 3: (1, 0)}   # quadrant -> (A, B)


def segment(rng, n_len, n, phase0, kind):
    """(a, b, phase) samples; the fundamental phase moves, A/B follow the n-th order
    quadrant (mostly)."""
    out = []
    ph = phase0
    for _ in range(n_len):
        if kind == "wrap":                  # fast, one direction: wraps COUNT_W=16
            step = rng.randint(3500, 4000)
        elif kind == "wrap_down":
            step = -rng.randint(3500, 4000)
        else:
            r = rng.random()
            if r < 0.15:
                step = 0                    # standstill
            elif r < 0.75:                  # legal: under one n-th order quadrant
                lim = max(1, 2047 // n)
                step = rng.randint(-lim, lim)
            elif r < 0.9:                   # up to a few quadrants
                lim = max(1, 3 * 2048 // n)
                step = rng.randint(-lim, lim)
            else:                           # big jumps, up to half a period
                step = rng.randint(-4095, 4095)
        ph = (ph + step) & 8191
        q = ((ph * n) & 8191) >> 11
        a, b = AB[q]
        if kind == "noise" and rng.random() < 0.3:   # A/B that disagree with the phase
            a, b = rng.randint(0, 1), rng.randint(0, 1)
        out.append((a, b, ph))
    return out, ph


@cocotb.test()
async def counter_sequences(dut):
    import numpy as np
    from sim.model import fastpath as fp

    count_w = len(dut.count_o)
    rng = random.Random(600 + count_w)
    plan = [(100, "mix", 800), (1, "mix", 300), (511, "mix", 500), (7, "noise", 400),
            (256, "mix", 300), (511, "wrap", 150), (511, "wrap_down", 300),
            (100, "noise", 300), (rng.randint(2, 510), "mix", 400), (3, "mix", 200)]
    resets = {4, 8}           # rst before these segments

    bench = fqtb.ClockedBench(dut)
    dut.rst.value = 1
    dut.valid_i.value = 0
    await bench.start()
    await bench.step()
    dut.rst.value = 0
    # the model runs on the samples since the last reset; state carries across segments
    hist_a, hist_b, hist_ph, hist_n = [], [], [], []
    bad = []
    ph = rng.randint(0, 8191)
    total = 0
    for si, (n, kind, length) in enumerate(plan):
        if si in resets:
            dut.rst.value = 1
            await bench.step()
            dut.rst.value = 0
            if (fqtb.sval(dut.count_o), fqtb.uval(dut.illegal_count_o),
                    fqtb.uval(dut.valid_o)) != (0, 0, 0):
                bad.append("counter not cleared by rst")
            hist_a, hist_b, hist_ph, hist_n = [], [], [], []
        seg, ph = segment(rng, length, n, ph, kind)
        dut.n_i.value = n
        start = len(hist_a)
        for a, b, p in seg:
            hist_a.append(a)
            hist_b.append(b)
            hist_ph.append(p)
            hist_n.append(n)
        cnt, ill, ill_cnt, _ = fp.counter(np.array(hist_a), np.array(hist_b),
                                          np.array(hist_ph, dtype=np.int64),
                                          np.array(hist_n, dtype=np.int64), count_w)
        # drive: samples with idle gaps; outputs checked 2 edges after each sample
        edges, e = [], bench.edge + 1
        for _ in seg:
            e += rng.choice((0, 0, 0, 1, 3))
            edges.append(e)
            e += 1
        by_edge = {x: i for i, x in enumerate(edges)}
        out_at = {x + 2: i for i, x in enumerate(edges)}
        for e in range(bench.edge, edges[-1] + 4):
            if e in out_at:
                i = out_at[e]
                k = start + i
                got = (fqtb.uval(dut.valid_o), fqtb.sval(dut.count_o), fqtb.uval(dut.a_o),
                       fqtb.uval(dut.b_o), fqtb.uval(dut.illegal_o),
                       fqtb.uval(dut.illegal_count_o))
                exp = (1, int(cnt[k]), hist_a[k], hist_b[k], int(ill[k]), int(ill_cnt[k]))
                total += 1
                if got != exp:
                    bad.append(f"segment {si} (n={n}, {kind}) sample {i} (a,b,phase)="
                               f"{seg[i]}: (valid,count,a,b,illegal,ill_count)={got}, "
                               f"model {exp}")
            elif e > edges[0] and fqtb.uval(dut.valid_o):
                bad.append(f"valid_o high after edge {e}, no sample due")
            if e + 1 in by_edge:
                a, b, p = seg[by_edge[e + 1]]
                dut.valid_i.value = 1
            else:
                a, b, p = rng.randint(0, 1), rng.randint(0, 1), rng.randint(0, 8191)
                dut.valid_i.value = 0
            dut.a_i.value = a
            dut.b_i.value = b
            dut.phase_i.value = p
            await bench.step()
        assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])
        if kind.startswith("wrap"):
            lo, hi = -(1 << (count_w - 1)), (1 << (count_w - 1)) - 1
            c = [int(x) for x in cnt[start:]]
            wrapped = any(abs(y - x) > (1 << (count_w - 1)) for x, y in zip(c, c[1:]))
            if count_w <= 16:
                assert wrapped, "the wrap segment did not wrap the counter"
            assert all(lo <= x <= hi for x in c)
    dut._log.info("counter COUNT_W=%d: %d samples equal", count_w, total)
