"""Fine phase of the exact table (rtl/octant.v ratio address + rtl/lut.v atan rows) through
the bit-true model (sim.model.octant, Lut.phase), against atan2.

Requirement: for every corrected pair (u1c, u2c) with radius 0.3 .. 1.9 (s2.14), the fine
phase equals round(atan2(u2c, u1c) * 8192 / (2 pi)) mod 8192 within +-1 (u13 units).

Why it holds (error budget of the address, in t = |small| / |large|): the reciprocal
table's bin (9 bits below the leading 1) gives a relative error of t below 2**-10 / m,
its u0.14 rounding 2**-14, the truncated carry-save product about 2**-15 of t, and the
rounding of j to 1/2048 half a row. The phase error is K (dt) / (1 + t**2), K = 8192 /
(2 pi): at most 0.82 units at t = 1 (m = 1), so the table value is within 0.5 + 0.82 of
the true angle and the reference within 0.5, an integer difference of at most 1. Measured
below: at most 1.34 units from the exact angle (0.5 of it the output rounding)."""
import math

import numpy as np

from sim.model import lut as lut_m, octant as octant_m
from sim.model import tables

K = 8192 / (2 * math.pi)
R0, R1 = int(0.3 * 16384), int(1.9 * 16384)


def _octant(x, y, kind):
    """octant of signed corrected values (magnitudes saturated to u15, signs)."""
    x, y = np.asarray(x, dtype=np.int64), np.asarray(y, dtype=np.int64)
    return octant_m.octant(np.minimum(np.abs(x), 32767), np.minimum(np.abs(y), 32767),
                     (x < 0).astype(np.int64), (y < 0).astype(np.int64), kind)


def _check(x, y, lut):
    j, base, neg = _octant(x, y, "exact")
    ph = lut.phase(j, base, neg)
    th = np.arctan2(y, x) * K
    ref = np.round(th).astype(np.int64) % 8192
    d = ((ph - ref + 4096) & 8191) - 4096
    e = ((ph - th + 4096) % 8192) - 4096
    return d, e


def _ring(xs, ys, r0, r1):
    X, Y = np.meshgrid(xs, ys)
    X, Y = X.ravel(), Y.ravel()
    rr = X.astype(float) ** 2 + Y.astype(float) ** 2
    m = (rr >= float(r0) ** 2) & (rr <= float(r1) ** 2)
    return X[m].astype(np.int64), Y[m].astype(np.int64)


def test_exact_phase_within_one_of_atan2_dense_grid():
    """The whole plane on a grid of 11 LSB (about 25 million points, every octant)."""
    lut = lut_m.Lut("exact")
    xs = np.arange(-R1, R1 + 1, 11)
    worst, n = 0.0, 0
    for i in range(0, len(xs), 400):
        x, y = _ring(xs[i:i + 400], xs, R0, R1)
        d, e = _check(x, y, lut)
        bad = np.nonzero(np.abs(d) > 1)[0]
        assert len(bad) == 0, f"u1c={x[bad[0]]} u2c={y[bad[0]]}: off by {d[bad[0]]}"
        worst = max(worst, float(np.abs(e).max()))
        n += len(x)
    assert n > 20_000_000
    assert worst < 1.4


def test_exact_phase_every_pair_where_the_reciprocal_is_worst():
    """Exhaustive in one octant (the others are mirrors, checked by the grid) for every
    |large| within 48 LSB of a power of two (m ~ 1 and m ~ 2, the largest and smallest
    reciprocal error) and for every 97th |large|: every |small| <= |large| in the ring."""
    lut = lut_m.Lut("exact")
    ls = set(range(int(R0 / math.sqrt(2)) - 1, R1 + 1, 97))
    for p in (12, 13, 14):
        ls |= set(range((1 << p) - 48, (1 << p) + 48))
    n = 0
    for lg in sorted(ls):
        s = np.arange(0, lg + 1, dtype=np.int64)
        rr = s.astype(float) ** 2 + float(lg) ** 2
        s = s[(rr >= R0 * R0) & (rr <= R1 * R1)]
        if not len(s):
            continue
        for x, y in ((np.full_like(s, lg), s), (-s, np.full_like(s, -lg))):
            d, _ = _check(x, y, lut)
            bad = np.nonzero(np.abs(d) > 1)[0]
            assert len(bad) == 0, f"u1c={x[bad[0]]} u2c={y[bad[0]]}: off by {d[bad[0]]}"
        n += len(s)
    assert n > 5_000_000


def test_exact_phase_small_amplitudes():
    """Before the estimator has converged |large| may be far from 1: the ratio does not
    depend on the scale (full normalisation), so +-1 holds down to a radius of 0.02."""
    lut = lut_m.Lut("exact")
    xs = np.arange(-R0, R0 + 1, 3)
    x, y = _ring(xs, xs, int(0.02 * 16384), R0)
    d, _ = _check(x, y, lut)
    assert np.abs(d).max() <= 1


def test_reciprocal_table():
    r = np.array(tables.recip_table(), dtype=float)
    assert len(r) == 512
    assert r.min() >= 1 << 13 and r.max() < 1 << 14       # u0.14, bit 13 always set
    i = np.arange(512)
    for m in (1 + i / 512, 1 + (i + 1) / 512):           # both ends of every bin
        rel = np.abs(r / 16384 * m - 1)
        assert rel.max() < 2 ** -10 * 1.02


def test_ratio_address_edges():
    """j for small = large is 2046 or 2047 (t = 1 within the reciprocal's 2**-10, clipped;
    PH 1023 or 1024 for an exact 1024), 0 for a zero small magnitude, and the clip at
    2047 holds for every |large|."""
    lg = np.arange(1, 32768, dtype=np.int64)
    j, _, _ = _octant(lg, lg, "exact")
    assert j.min() >= 2046 and j.max() == 2047
    assert np.array(tables.phase_table("exact"))[[2046, 2047]].tolist() == [1023, 1024]
    j0, _, _ = _octant(lg, np.zeros_like(lg), "exact")
    assert (j0 == 0).all()
    j00, base, _ = _octant(np.array([0]), np.array([0]), "exact")
    assert j00[0] == 0 and base[0] == 0


def test_paper_address_unchanged():
    """TABLE_EXACT = 0 keeps the paper's address: the small magnitude in steps of 1/2048."""
    rng = np.random.default_rng(5)
    x = rng.integers(-32768, 32768, 100000)
    y = rng.integers(-32768, 32768, 100000)
    j, _, _ = _octant(x, y, "paper")
    ax, ay = np.minimum(np.abs(x), 32767), np.minimum(np.abs(y), 32767)
    assert (j == np.minimum((np.minimum(ax, ay) + 4) >> 3, 2047)).all()


def test_exact_phase_noise_is_that_of_atan2():
    """With white noise on both channels the table's phase noise is that of float atan2
    (the Cramer-Rao bound sigma/A), not that of asin of the small signal (1.27 x the
    variance averaged over an octant)."""
    rng = np.random.default_rng(7)
    n, sig = 400000, 0.01
    a = rng.uniform(0, 2 * np.pi, n)
    x = np.round(16384 * (np.cos(a) + sig * rng.standard_normal(n))).astype(np.int64)
    y = np.round(16384 * (np.sin(a) + sig * rng.standard_normal(n))).astype(np.int64)
    lut = lut_m.Lut("exact")
    ph = lut.phase(*_octant(x, y, "exact")) * (2 * np.pi / 8192)

    def rms(p):
        return np.sqrt(np.mean(np.angle(np.exp(1j * (p - a))) ** 2))

    ratio = rms(ph) / rms(np.arctan2(y, x))
    small = np.minimum(np.abs(x), np.abs(y)) / 16384.0
    asin_only = np.arcsin(np.minimum(small, 1.0))        # the small signal alone
    low = np.abs(y) <= np.abs(x)
    base = np.where(low, np.where(x < 0, np.pi, 0.0), np.where(y < 0, 1.5 * np.pi, 0.5 * np.pi))
    neg = np.where(low, (x < 0) != (y < 0), (x < 0) == (y < 0))
    ph_asin = base + np.where(neg, -asin_only, asin_only)
    assert ratio < 1.02, ratio
    assert rms(ph_asin) / rms(np.arctan2(y, x)) > 1.08
