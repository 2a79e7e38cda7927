"""Bit-true model of the sample-rate datapath, one function per RTL block.

All functions take and return numpy int64 arrays (one element per sample) and compute
exactly what the RTL computes. Formats (sI.F: I integer bits including the sign):

  u_raw   s1.15   ADC code, MSB-aligned to 16 bits             (rtl/normalize.v)
  u_n     s1.15   u_raw * 2**g, saturated                       (rtl/normalize.v)
  m       s1.15   offsets, normalised units                     (bundle)
  c       s4.12   correction coefficients c1, c12, c2           (bundle)
  d       s1.15   u_n - m, saturated                            (rtl/correct.v)
  uc      s2.14   corrected signals u1c, u2c (unit circle = 1)  (rtl/correct.v, Eq. 9)
  j       u11     octant-local table address                    (rtl/octant.v, Table 2)
  phase   u13     fine phase of the signal, 8192 per period     (rtl/lut.v)
  pn      u13     n * phase mod 8192: phase of the n-th order   (rtl/lut.v, Table 1)
  cosn/sinn s1.(SIN_W-1) n-th order sinusoids from the table    (rtl/lut.v)
  a, b    u1      pulses with hysteresis eps (u0.15)            (rtl/pulse.v, Eq. 12)
  count   s32     x4 up/down counter                            (rtl/counter.v)
"""
import numpy as np

from .tables import ADDR_W, PH_W, phase_table, sine_table

I64 = np.int64


def _sat(v, w):
    return np.clip(v, -(1 << (w - 1)), (1 << (w - 1)) - 1)


def _rnd_shr(v, s):
    return (v + (1 << (s - 1))) >> s


def align(code, adc_w):
    """ADC code (adc_w bits, signed) -> s1.15 MSB-aligned; clip flag at the rails."""
    code = np.asarray(code, dtype=I64)
    clip = (code >= (1 << (adc_w - 1)) - 1) | (code <= -(1 << (adc_w - 1)))
    return code << (16 - adc_w), clip


def normalize(u_raw, g):
    """u_n = sat16(u_raw << g); returns (u_n, saturated)."""
    v = np.asarray(u_raw, dtype=I64) << np.asarray(g, dtype=I64)
    s = _sat(v, 16)
    return s, s != v


def correct(u1n, u2n, m1, m2, c1, c12, c2):
    """Eq. 9 as three products: u1c = c1 d1, u2c = c12 d1 + c2 d2 (s2.14)."""
    d1r, d2r = u1n - m1, u2n - m2
    d1, d2 = _sat(d1r, 16), _sat(d2r, 16)
    p1 = d1 * c1                                   # s5.27
    p2 = d1 * c12 + d2 * c2                        # s6.27
    u1r, u2r = _rnd_shr(p1, 13), _rnd_shr(p2, 13)
    u1c, u2c = _sat(u1r, 16), _sat(u2r, 16)
    flag = (d1 != d1r) | (d2 != d2r) | (u1c != u1r) | (u2c != u2r)
    return u1c, u2c, flag


def octant(u1c, u2c):
    """Table 2: octant from signs and magnitudes, address from the smaller magnitude.

    Returns (j, base, neg): phase = base + (neg ? -PH[j] : PH[j]) mod 8192."""
    x, y = u1c, u2c
    ax = np.minimum(np.abs(x), 32767)
    ay = np.minimum(np.abs(y), 32767)
    low = ay <= ax                                  # octants 0, 3, 4, 7: address from |u2c|
    small = np.where(low, ay, ax)
    xn, yn = x < 0, y < 0
    base = np.where(low, np.where(xn, 4096, 0), np.where(yn, 6144, 2048))
    neg = np.where(low, xn != yn, xn == yn)
    j = np.minimum((small + 4) >> 3, (1 << ADDR_W) - 1)
    return j.astype(I64), base.astype(I64), neg.astype(I64)


class Lut:
    """Table 1 through two block-RAM tables: octant phase, then quarter-wave sine."""

    def __init__(self, kind="exact", sin_w=10):
        self.ph = np.array(phase_table(kind), dtype=I64)
        self.sin = np.array(sine_table(sin_w), dtype=I64)
        self.sin_w = sin_w

    def phase(self, j, base, neg):
        p = self.ph[j]
        return (base + np.where(neg == 1, -p, p)) & ((1 << PH_W) - 1)

    def _sine(self, p):
        q, k = p >> 11, p & 2047
        mag = self.sin[np.where(q & 1, 2047 - k, k)]
        return np.where(q >= 2, -mag, mag)

    def nth(self, phase, n):
        pn = (phase * np.asarray(n, dtype=I64)) & ((1 << PH_W) - 1)
        return pn, self._sine((pn + 2048) & 8191), self._sine(pn)


def pulse(cosn, sinn, eps, sin_w, a0=1, b0=1):
    """Eq. 12 with hysteresis: 1 if >= eps, 0 if <= -eps, else the previous value."""
    sh = 16 - sin_w

    def hyst(v, init):
        v = v << sh
        dec = np.where(v >= eps, 1, np.where(v <= -eps, 0, -1))
        idx = np.where(dec >= 0, np.arange(len(v)), -1)
        idx = np.maximum.accumulate(idx)
        return np.where(idx >= 0, dec[np.maximum(idx, 0)], init).astype(I64)

    return hyst(cosn, a0), hyst(sinn, b0)


QUAD = {(1, 1): 0, (0, 1): 1, (0, 0): 2, (1, 0): 3}


def counter(a, b, phase, n, count_w=32):
    """x4 up/down counter of the A/B edges (up when the phase increases).

    A/B only show the quadrant of the n-th order phase modulo 4, so a step of two
    quadrants (both channels at once) is ambiguous and a step of four is invisible. The
    exact n-th order step D = n * wrap13(phase - phase_prev) (u13 units of the fundamental,
    unambiguous up to a fundamental step of half a period) resolves both: with dq the A/B
    quadrant step in {-1, 0, 1, 2},

        increment = dq + 4 * k,   k = (D - 2048 dq + 4096) >> 13   (nearest multiple of 4)

    A sample with dq = 2 or k != 0 is flagged 'illegal' (and counted). The first sample
    only primes the state. Returns (count, illegal, illegal_count, D)."""
    qd = np.where(a == 1, np.where(b == 1, 0, 3), np.where(b == 1, 1, 2)).astype(I64)
    dq = np.zeros_like(qd)
    dq[1:] = (qd[1:] - qd[:-1]) & 3
    dq = np.where(dq == 3, -1, dq)
    dph = np.zeros_like(phase)
    dph[1:] = ((phase[1:] - phase[:-1] + 4096) & 8191) - 4096
    d = dph * np.asarray(n, dtype=I64)
    k = (d - 2048 * dq + 4096) >> 13
    k[0] = 0
    step = dq + 4 * k
    illegal = (dq == 2) | (k != 0)
    cnt = np.cumsum(step)
    m = (1 << count_w)
    cnt = ((cnt + (m >> 1)) % m) - (m >> 1)
    return cnt.astype(I64), illegal, np.cumsum(illegal).astype(I64), d
