"""correct: input gain and Eq. 9 against sim.model.fastpath.normalize + correct.

Latency 5 (rtl/correct.v): a sample (with its coefficient bundle) presented on edge e is on
the outputs after edge e + 4. Samples are streamed back to back (one per clock) and with idle gaps
(during which the data inputs carry garbage)."""
import random

import pytest

import fqtb


@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_correct(sim):
    fqtb.run_block(sim, "correct", fqtb.sources("correct", "sat_round"), "test_correct")


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402

LATENCY = 5
S16 = (-32768, 32767)
BUNDLE0 = (0, 0, 0, 8192, 0, 8192)      # g, m1, m2, c1, c12, c2 (reset values)


def directed():
    """(u1, u2, g, m1, m2, c1, c12, c2) vectors for the corner cases."""
    v = []
    full = [0, 1, -1, 32767, -32768, 16383, 16384, -16384, -16385, 8191, 8192, -8193,
            4095, 4096, -4097]
    # zero, full scale, saturation of u << g in both directions, every gain
    for g in range(4):
        for u in full:
            v.append((u, -u if u != -32768 else 32767, g, *BUNDLE0[1:]))
    # saturation of d = u_n - m (both ways, each channel), and just not saturating
    for un, m in [(32767, -1), (32767, -32768), (-32768, 1), (-32768, 32767), (32767, 0),
                  (-32768, 0), (32766, -1), (-32767, 1), (0, -32768), (-1, 32767)]:
        v.append((un, 0, 0, m, 0, 8192, 0, 8192))
        v.append((0, un, 0, 0, m, 8192, 0, 8192))
    # products: p1 = d1 c1 and p12 + p2 to the rails and just inside
    for d1, c1 in [(-32768, -32768), (32767, 32767), (-32768, 32767), (32767, -32768),
                   (16384, 8192), (16384, 8191), (-16384, 8192), (-16384, 8193),
                   (12288, 10923), (-12288, 10923)]:
        v.append((d1, 0, 0, 0, 0, c1, 0, 8192))
    for d1, d2, c12, c2 in [(32767, 32767, 32767, 32767), (-32768, -32768, 32767, 32767),
                            (-32768, 32767, 32767, -32768), (16384, 16384, 4096, 4096),
                            (16384, 16384, 4096, 4095), (-16384, -16384, 4096, 4097),
                            (32767, -32768, 32767, 32767), (-32768, -32768, -32768, -32768)]:
        v.append((d1, d2, 0, 0, 0, 8192, c12, c2))
    # rounding ties of the >> 13: d c = k 8192 + 4096 (+-1)
    for k in (-3, -2, -1, 0, 1, 2, 3):
        for e in (-1, 0, 1):
            p = k * 8192 + 4096 + e
            # p = d1 * c1 with c1 = 1 -> d1 = p
            if -32768 <= p <= 32767:
                v.append((p, p, 0, 0, 0, 1, 1, 0))
                v.append((p, -p, 0, 0, 0, -1, 0, 1))
    return v


def random_vectors(rng, n):
    v = []
    for _ in range(n):
        r = rng.random()
        if r < 0.5:     # realistic: amplitudes, offsets and coefficients of a calibration
            g = rng.randint(0, 3)
            a = rng.randint(2000, 32767 >> g)
            u1 = rng.randint(-a, a)
            u2 = rng.randint(-a, a)
            b = (g, rng.randint(-3000, 3000), rng.randint(-3000, 3000),
                 rng.randint(4096, 16384), rng.randint(-3000, 3000), rng.randint(4096, 16384))
        else:           # anything
            u1, u2 = rng.randint(*S16), rng.randint(*S16)
            b = (rng.randint(0, 3), rng.randint(*S16), rng.randint(*S16),
                 rng.randint(*S16), rng.randint(*S16), rng.randint(*S16))
        v.append((u1, u2, *b))
    return v


def model(vec):
    import numpy as np
    from sim.model import fastpath as fp

    a = np.array(vec, dtype=np.int64)
    u1, u2, g, m1, m2, c1, c12, c2 = a.T
    u1n, ns1 = fp.normalize(u1, g)
    u2n, ns2 = fp.normalize(u2, g)
    u1c, u2c, csat = fp.correct(u1n, u2n, m1, m2, c1, c12, c2)
    return [tuple(int(x) for x in t) for t in zip(u1c, u2c, ns1 | ns2, csat)]


PORTS_IN = ("u1_i", "u2_i", "g_i", "m1_i", "m2_i", "c1_i", "c12_i", "c2_i")


async def stream(dut, vec, gaps, rng):
    """Present vec[i] on edge e_i (gaps[i] idle clocks before it); check every output."""
    bench = fqtb.ClockedBench(dut)
    await bench.start()
    exp = model(vec)
    # edge of every sample
    edges, e = [], 0
    for gap in gaps:
        e += gap
        edges.append(e)
        e += 1
    by_edge = {e: i for i, e in enumerate(edges)}
    out_at = {e + LATENCY - 1: i for i, e in enumerate(edges)}
    last = edges[-1] + LATENCY + 2
    bad = []
    seen = 0
    for e in range(-1, last + 1):
        # slot after edge e: outputs of edge e, then inputs for edge e + 1
        if e >= 0:
            valid = fqtb.uval(dut.valid_o)
            if e in out_at:
                i = out_at[e]
                got = (fqtb.sval(dut.u1c_o), fqtb.sval(dut.u2c_o), fqtb.uval(dut.nsat_o),
                       fqtb.uval(dut.csat_o))
                if valid != 1 or got != exp[i]:
                    bad.append(f"sample {i} {vec[i]}: valid={valid} (u1c,u2c,nsat,csat)="
                               f"{got}, model {exp[i]}")
                seen += 1
            elif valid:
                bad.append(f"valid_o high after edge {e}, no sample due")
        nxt = e + 1
        if nxt in by_edge:
            for p, x in zip(PORTS_IN, vec[by_edge[nxt]]):
                getattr(dut, p).value = x
            dut.valid_i.value = 1
        else:           # idle: garbage on the data inputs
            dut.valid_i.value = 0
            for p, x in zip(PORTS_IN, random_vectors(rng, 1)[0]):
                getattr(dut, p).value = x
        await bench.step()
    assert seen == len(vec)
    assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])


@cocotb.test()
async def correct_back_to_back(dut):
    """Directed corners then seeded random vectors with random bundles, one per clock."""
    rng = random.Random(101)
    vec = directed() + random_vectors(rng, 3000)
    await stream(dut, vec, [0] * len(vec), rng)


@cocotb.test()
async def correct_with_gaps(dut):
    """The same kinds of vectors with 0..3 idle clocks between samples."""
    rng = random.Random(202)
    vec = directed() + random_vectors(rng, 1500)
    rng.shuffle(vec)
    gaps = [rng.choice((0, 0, 1, 2, 3)) for _ in vec]
    await stream(dut, vec, gaps, rng)
