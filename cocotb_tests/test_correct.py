"""correct: alignment, input gain, offsets and Eq. 9 against sim.model.align and
correct (bit for bit), for 16- and 12-bit ADC codes.

Timing (rtl/correct.v; sim.model.finequad_core.CORR_AT): a sample with its coefficient bundle
presented for edge e gives raw1_o, raw2_o, amax_o, clip_o, nsat_o, dsat_o, valid0_o after
edge e, and ax_o, ay_o, xn_o, yn_o, rsat_o, zl_o, valid_o after edge e + CORR_AT. Every output
of every sample is checked; the valid outputs must be high after exactly those edges.
Samples are streamed back to back (one per clock) and with idle gaps (the data inputs
carry garbage while valid_i is low).

Directed vectors: zero and full scale at every gain (the gain's saturation both ways),
the ADC rails, the clip level (codes one below, at and one above |u| = clip_i for
levels 0, 1, 16384, the reset value 32512, 32767, 32768 and 65535, both signs), saturation of d = x - m on each channel and just inside it, products
to the rails and just inside, the |u| = 2 (32768) saturation of the magnitudes, the carry
of the low 13 bits of p12 + p2 into v2 >> 13 (exactly 2**13 and one short of it, around
zero, both signs), the truncation of (v ^ sign) >> 13 at multiples of 2**13 +-1 for both
signs; then seeded random bundles, realistic (a calibration's range) and arbitrary.
Model values: align and correct; amax_o is max(|raw1|, |raw2|) capped at
32767, as sim.model.finequad_core computes the estimator's peak; zl_o = lzc15(ax | ay),
the octant's normalising shift."""
import random

import pytest

import fqtb


@pytest.mark.parametrize("adc_w", [16, 12], ids=["ADC16", "ADC12"])
@pytest.mark.parametrize("sim", fqtb.simulators("correct"))
def test_correct(sim, adc_w):
    fqtb.run_block(sim, "correct", fqtb.sources("correct"), "test_correct",
                   parameters=dict(ADC_W=adc_w), extra_env=dict(ADC_W=adc_w))


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402

S16 = (-32768, 32767)
BUNDLE0 = (0, 0, 0, 8192, 0, 8192)      # g, m1, m2, c1, c12, c2 (reset values)
CLIP0 = 32512                           # clip_i: the CLIP register's reset value


def directed(adc_w):
    """(u1, u2, g, m1, m2, c1, c12, c2) vectors for the corner cases; u in ADC codes."""
    sh = 16 - adc_w
    lo, hi = -(1 << (adc_w - 1)), (1 << (adc_w - 1)) - 1

    def code(v16):                       # an s1.15 value as the nearest ADC code
        return max(lo, min(hi, v16 >> sh))

    v = _directed_bundles(code, lo, hi, sh)
    # the clip level: |u_r| one step (of the ADC) below, at and above it, both signs
    for level in (0, 1, 16384, CLIP0, 32767, 32768, 65535):
        for d in (-1, 0, 1):
            u16 = min(32768, max(0, level + d * (1 << sh)))
            c = u16 >> sh
            for cu in {min(c, hi), -min(c, -lo)}:
                v.append((cu, 0, 0, *BUNDLE0[1:], level))
                v.append((0, cu, 0, *BUNDLE0[1:], level))
    return v


def _directed_bundles(code, lo, hi, sh):
    """The corner cases of the gain, offsets and products, at the reset clip level."""
    v = []
    full = [0, 1, -1, 32767, -32768, 32766, -32767, 16383, 16384, -16384, -16385, 8191,
            8192, -8193, 4095, 4096, -4097]
    # zero, full scale and the rails, saturation of u << g both ways, every gain
    for g in range(4):
        for u in full:
            c = code(u)
            v.append((c, -c if c != lo else hi, g, *BUNDLE0[1:]))
    # saturation of d = x - m (both ways, each channel), and just not saturating
    for un, m in [(32767, -1), (32767, -32768), (-32768, 1), (-32768, 32767), (32767, 0),
                  (-32768, 0), (32766, -1), (-32767, 1), (0, -32768), (-1, 32767)]:
        v.append((code(un), 0, 0, m, 0, 8192, 0, 8192))
        v.append((0, code(un), 0, 0, m, 8192, 0, 8192))
    # products p1 = d1 c1 and p12 + p2 to the rails and just inside
    for d1, c1 in [(-32768, -32768), (32767, 32767), (-32768, 32767), (32767, -32768),
                   (16384, 8192), (16384, 8191), (-16384, 8192), (-16384, 8193),
                   (12288, 10923), (-12288, 10923)]:
        v.append((code(d1), 0, 0, 0, 0, c1, 0, 8192))
    for d1, d2, c12, c2 in [(32767, 32767, 32767, 32767), (-32768, -32768, 32767, 32767),
                            (-32768, 32767, 32767, -32768), (16384, 16384, 4096, 4096),
                            (16384, 16384, 4096, 4095), (-16384, -16384, 4096, 4097),
                            (32767, -32768, 32767, 32767), (-32768, -32768, -32768, -32768)]:
        v.append((code(d1), code(d2), 0, 0, 0, 8192, c12, c2))
    # |u| = 2 (32768 in s2.14) and just below: v = d c = 2**28 - 1 .. 2**28 + 1 and negative
    for d, c in [(16384, 16384), (16384, 16383), (-16384, 16384), (-16384, 16383),
                 (32767, 8193), (-32768, 8192)]:
        v.append((code(d), code(d), 0, 0, 0, c, c, 0))
    # the carry of the low 13 bits of p12 + p2 into v2 >> 13 (formed by carry select):
    # d1, d2 from the offsets and c12 = c2 = 1, so v2 = d1 + d2, with the low parts summing
    # to exactly 2**13 (a carry, from the LSB up) or 2**13 - 1 (none), around v2 = 0 and
    # for both signs of each term
    for hi1 in (-2, -1, 0, 1):
        for hi2 in (-2, -1, 0, 1):
            for lo1 in (8191, 4096, 1):
                for lo2 in (8192 - lo1, 8191 - lo1):
                    v.append((0, 0, 0, -((hi1 << 13) + lo1), -((hi2 << 13) + lo2),
                              8192, 1, 1))
    # the truncation of (v ^ sign) >> 13: v = k 2**13 + e, e in -1, 0, 1 (c1 = 1: v1 = d1)
    for k in (-3, -2, -1, 0, 1, 2, 3):
        for e in (-1, 0, 1):
            p = (k << 13) + e
            if lo <= p >> sh and (p >> sh) <= hi and (p >> sh) << sh == p:
                v.append((p >> sh, p >> sh, 0, 0, 0, 1, 1, 0))
                v.append((p >> sh, -(p >> sh), 0, 0, 0, -1, 0, 1))
            # with an offset, every e is reachable for any ADC width
            v.append((0, 0, 0, -p, -p, 1, 0, 1))
    return [t + (CLIP0,) for t in v]


def random_vectors(rng, n, adc_w):
    lo, hi = -(1 << (adc_w - 1)), (1 << (adc_w - 1)) - 1
    v = []
    for _ in range(n):
        r = rng.random()
        if r < 0.5:     # realistic: amplitudes, offsets and coefficients of a calibration
            g = rng.randint(0, 3)
            a = rng.randint(hi >> 4, hi >> g)
            u1 = rng.randint(-a, a)
            u2 = rng.randint(-a, a)
            b = (g, rng.randint(-3000, 3000), rng.randint(-3000, 3000),
                 rng.randint(4096, 16384), rng.randint(-3000, 3000), rng.randint(4096, 16384))
        else:           # anything
            u1, u2 = rng.randint(lo, hi), rng.randint(lo, hi)
            b = (rng.randint(0, 3), rng.randint(*S16), rng.randint(*S16),
                 rng.randint(*S16), rng.randint(*S16), rng.randint(*S16))
        clip = CLIP0 if rng.random() < 0.5 else rng.randint(0, 65535)
        v.append((u1, u2, *b, clip))
    return v


def model(vec, adc_w):
    """Per sample: (outputs after edge e, outputs after edge e + CORR_AT)."""
    import numpy as np
    from sim.model import correct as correct_m, octant as octant_m

    a = np.array(vec, dtype=np.int64)
    u1, u2, g, m1, m2, c1, c12, c2, clip = a.T
    r1, k1 = correct_m.align(u1, adc_w, clip)
    r2, k2 = correct_m.align(u2, adc_w, clip)
    fr = correct_m.correct(r1, r2, g, m1, m2, c1, c12, c2)
    amax = np.minimum(np.maximum(np.abs(r1), np.abs(r2)), 32767)
    early = zip(r1, r2, amax, k1 | k2, fr["nsat"], fr["dsat"])
    late = zip(fr["ax"], fr["ay"], fr["xn"], fr["yn"], fr["rsat"],
               octant_m.lzc15(fr["ax"] | fr["ay"]))
    return ([tuple(int(x) for x in t) for t in early],
            [tuple(int(x) for x in t) for t in late])


PORTS_IN = ("u1_i", "u2_i", "g_i", "m1_i", "m2_i", "c1_i", "c12_i", "c2_i", "clip_i")


async def stream(dut, vec, gaps, rng, adc_w):
    """Present vec[i] for edge e_i (gaps[i] idle clocks before it); check every output."""
    from sim.model.finequad_core import CORR_AT

    bench = fqtb.ClockedBench(dut)
    await bench.start()
    early, late = model(vec, adc_w)
    edges, e = [], 0
    for gap in gaps:
        e += gap
        edges.append(e)
        e += 1
    by_edge = {e: i for i, e in enumerate(edges)}
    at0 = {e: i for i, e in enumerate(edges)}
    at2 = {e + CORR_AT: i for i, e in enumerate(edges)}
    last = edges[-1] + CORR_AT + 2
    bad = []
    seen = 0
    for e in range(-1, last + 1):
        # slot after edge e: outputs of edge e, then inputs for edge e + 1
        if e >= 0:
            v0, v2 = fqtb.uval(dut.valid0_o), fqtb.uval(dut.valid_o)
            if (v0 == 1) != (e in at0):
                bad.append(f"valid0_o={v0} after edge {e}")
            if (v2 == 1) != (e in at2):
                bad.append(f"valid_o={v2} after edge {e}")
            if e in at0:
                i = at0[e]
                got = (fqtb.sval(dut.raw1_o), fqtb.sval(dut.raw2_o), fqtb.uval(dut.amax_o),
                       fqtb.uval(dut.clip_o), fqtb.uval(dut.nsat_o), fqtb.uval(dut.dsat_o))
                if got != early[i]:
                    bad.append(f"sample {i} {vec[i]} edge t: (raw1,raw2,amax,clip,nsat,dsat)="
                               f"{got}, model {early[i]}")
            if e in at2:
                i = at2[e]
                got = (fqtb.uval(dut.ax_o), fqtb.uval(dut.ay_o), fqtb.uval(dut.xn_o),
                       fqtb.uval(dut.yn_o), fqtb.uval(dut.rsat_o), fqtb.uval(dut.zl_o))
                if got != late[i]:
                    bad.append(f"sample {i} {vec[i]} edge t+{CORR_AT}: (ax,ay,xn,yn,rsat,zl)="
                               f"{got}, model {late[i]}")
                seen += 1
        nxt = e + 1
        if nxt in by_edge:
            for p, x in zip(PORTS_IN, vec[by_edge[nxt]]):
                getattr(dut, p).value = x
            dut.valid_i.value = 1
        else:           # idle: garbage on the data inputs
            dut.valid_i.value = 0
            for p, x in zip(PORTS_IN, random_vectors(rng, 1, adc_w)[0]):
                getattr(dut, p).value = x
        await bench.step()
    assert seen == len(vec)
    assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])


@cocotb.test()
async def correct_back_to_back(dut):
    """Directed corners then seeded random vectors with random bundles, one per clock."""
    adc_w = fqtb.env_int("ADC_W")
    rng = random.Random(101)
    vec = directed(adc_w) + random_vectors(rng, 3000, adc_w)
    await stream(dut, vec, [0] * len(vec), rng, adc_w)


@cocotb.test()
async def correct_with_gaps(dut):
    """The same kinds of vectors with 0..3 idle clocks between samples."""
    adc_w = fqtb.env_int("ADC_W")
    rng = random.Random(202)
    vec = directed(adc_w) + random_vectors(rng, 1500, adc_w)
    rng.shuffle(vec)
    gaps = [rng.choice((0, 0, 1, 2, 3)) for _ in vec]
    await stream(dut, vec, gaps, rng, adc_w)
