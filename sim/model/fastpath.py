"""Bit-true model of the sample-rate datapath, one function per RTL block.

All functions take and return numpy int64 arrays (one element per sample) and compute
exactly what the RTL computes. Formats (sI.F: I integer bits including the sign):

  u_raw   s1.15   ADC code, MSB-aligned to 16 bits             (rtl/normalize.v)
  u_n     s1.15   u_raw * 2**g, saturated                       (rtl/normalize.v)
  m       s1.15   offsets, normalised units                     (bundle)
  c       s4.12   correction coefficients c1, c12, c2           (bundle)
  d       s1.15   u_n - m, saturated                            (rtl/correct.v)
  uc      s2.14   corrected signals u1c, u2c (unit circle = 1)  (rtl/correct.v, Eq. 9)
  j       u11     octant-local table address: exact table       (rtl/octant.v, Table 2)
                  |small|/|large| in steps of 1/2048, paper table
                  |small| in steps of 1/2048 of the unit radius
  phase   u13     fine phase of the signal, 8192 per period     (rtl/lut.v)
  pn      u13     n * phase mod 8192: phase of the n-th order   (rtl/lut.v, Table 1)
  cosn/sinn s1.(SIN_W-1) n-th order sinusoids from the table    (rtl/lut.v)
  a, b    u1      pulses with hysteresis eps (u0.15)            (rtl/pulse.v, Eq. 12)
  count   s32     count of the n-th order (phase or x4 A/B)     (rtl/counter.v)
"""
import numpy as np

from .tables import ADDR_W, PH_W, RCP_AW, phase_table, recip_table, sine_table

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


_RECIP = np.array(recip_table(), dtype=I64)
RATIO_ROUND = 1 << 15     # rounds the address to 1/2048


def lzc15(v):
    """Leading zeros of a u15 value, 0..14 (14 for 0 and 1, as rtl/octant.v)."""
    v = np.asarray(v, dtype=I64)
    z = np.full(v.shape, 14, dtype=I64)
    for b in range(15):                             # the highest set bit is applied last
        z = np.where((v >> b) & 1, 14 - b, z)
    return z


def ratio(small, large, zl):
    """Exact-table address j = min(2047, round(2048 small / large)) as rtl/octant.v forms
    it (small <= large, both u15; zl = the leading zeros of large's one's complement
    magnitude, lzc15(large) or, when the signal is -2**p, lzc15(large) + 1):

      ln  = large << zl          u16 in [2**14, 2**15], m = ln / 2**14 in [1, 2]
      sn  = min(2**14 - 1, (small << zl) >> 1)     u14: t = 2 sn / ln
      r   = RECIP[ln >= 2**15 ? 511 : ln[13:5]]    u0.14, ~ 1/m (9-bit bin below the
                                                   leading 1; m = 2 takes the last bin)
      p   = sn * r = t * 2**27 (1 + O(2**-10))    u28 (p < 2**28 for every input)
      j   = min(2047, (p + 2**15) >> 16)           u11"""
    ln = (large << zl) & 0xFFFF
    sn = np.minimum(((small << zl) & 0xFFFF) >> 1, (1 << 14) - 1)
    r = _RECIP[np.where(ln >> 15, (1 << RCP_AW) - 1, (ln >> 5) & ((1 << RCP_AW) - 1))]
    p = sn * r + RATIO_ROUND
    return np.minimum(p >> 16, (1 << ADDR_W) - 1)


def octant(u1c, u2c, kind="exact"):
    """Table 2: octant from signs and magnitudes; address from the magnitudes: for the
    exact table the ratio small / large (the tangent of the octant-local angle, so both
    signals contribute), for the paper's table the smaller magnitude alone (Eq. 10).

    Returns (j, base, neg): phase = base + (neg ? -PH[j] : PH[j]) mod 8192."""
    x, y = np.asarray(u1c, dtype=I64), np.asarray(u2c, dtype=I64)
    ax = np.minimum(np.abs(x), 32767)
    ay = np.minimum(np.abs(y), 32767)
    low = ay <= ax                                  # octants 0, 3, 4, 7: address from |u2c|
    small = np.where(low, ay, ax)
    xn, yn = x < 0, y < 0
    base = np.where(low, np.where(xn, 4096, 0), np.where(yn, 6144, 2048))
    neg = np.where(low, xn != yn, xn == yn)
    if kind == "paper":
        j = np.minimum((small + 4) >> 3, (1 << ADDR_W) - 1)
    elif kind == "exact":
        zx = lzc15(np.where(xn, ~x, x) & 0x7FFF)    # one's complement magnitudes
        zy = lzc15(np.where(yn, ~y, y) & 0x7FFF)
        j = ratio(small, np.where(low, ax, ay), np.where(low, zx, zy))
    else:
        raise ValueError(f"table kind must be 'exact' or 'paper', got {kind!r}")
    return j.astype(I64), base.astype(I64), neg.astype(I64)


class Lut:
    """Table 1 through two block-RAM tables: octant phase, then quarter-wave sine."""

    def __init__(self, kind="exact", sin_w=10):
        self.kind = kind
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


def counter(a, b, phase, n, count_w=32, mode=0, state=None):
    """Position count of the n-th order (up when the phase increases), two modes.

    Both modes add to one accumulator S, s(count_w + 13), wrapping; count = S >> 13
    (floor). Every sample updates phase_prev and the A/B quadrant in both modes; the
    state before the first sample is phase_prev = 0, quadrant 0 (A = B = 1).

    mode 0, phase: S += 4 * D, D = n * dph, dph = wrap13(phase - phase_prev) in
      [-4096, 4095]. S = 4 n Phi for the unwrapped phase Phi (starting at
      wrap13(phase_0)): count = floor(4 n Phi / 8192), nothing lost while |dph| < 4096.
      Flag (overspeed): |dph| >= 3072.
    mode 1, edge (the paper's x4 counter of A/B): S += 8192 * e, e = +1 / -1 for a
      quadrant step dq = 1 / 3 (mod 4), 0 otherwise; dq = 2 (both channels changed) is
      not counted and flagged.

    The first sample after reset is never flagged. n and mode are scalars or per-sample
    arrays. `state` (S, phase_prev, quadrant_prev, flag count, primed) continues a run
    (None: from reset). Returns (count, flag, flag_count, S, state after the last
    sample)."""
    s0, ph0, qd0, fc0, primed = (0, 0, 0, 0, False) if state is None else state
    a = np.asarray(a, dtype=I64)
    b = np.asarray(b, dtype=I64)
    phase = np.asarray(phase, dtype=I64)
    qd = np.where(a == 1, np.where(b == 1, 0, 3), np.where(b == 1, 1, 2)).astype(I64)
    qd_prev = np.concatenate([[qd0], qd[:-1]]).astype(I64)
    dq = (qd - qd_prev) & 3
    ph_prev = np.concatenate([[ph0], phase[:-1]]).astype(I64)
    dph = ((phase - ph_prev + 4096) & 8191) - 4096
    d = dph * np.asarray(n, dtype=I64)
    edge = np.broadcast_to(np.asarray(mode, dtype=I64) != 0, phase.shape)
    e = np.where(dq == 1, 1, np.where(dq == 3, -1, 0))
    inc = np.where(edge, e << 13, 4 * d)
    flag = np.where(edge, dq == 2, np.abs(dph) >= 3072)
    if not primed:
        flag[:1] = False
    sw = count_w + 13
    m = 1 << sw
    s = ((s0 + np.cumsum(inc) + (m >> 1)) % m) - (m >> 1)
    fcnt = (fc0 + np.cumsum(flag)).astype(I64)
    if len(phase):
        state = (int(s[-1]), int(phase[-1]), int(qd[-1]), int(fcnt[-1]), True)
    elif state is None:
        state = (0, 0, 0, 0, False)
    return (s >> 13).astype(I64), flag, fcnt, s.astype(I64), state
