"""Bit-true model of the sample-rate datapath, one function per RTL block.

All functions take and return numpy int64 arrays (one element per sample) and compute
exactly what the RTL computes. Formats (sI.F: I integer bits including the sign):

  u_raw   s1.15   ADC code, MSB-aligned to 16 bits             (rtl/correct.v)
  x       s4.15   u_raw * 2**g (exact)                          (rtl/correct.v)
  m       s1.15   offsets, normalised units                     (bundle)
  c       s4.12   correction coefficients c1, c12, c2           (bundle)
  d       s1.15   sat16(x - m)                                  (rtl/correct.v)
  u       s2.14   corrected signals (unit circle = 16384): the   (rtl/correct.v, Eq. 9)
                  fast path keeps |u| = (v ^ sign) >> 13 (u15,
                  saturated) and the sign of the products' sum v
  j       u11     octant-local table address: exact table       (rtl/octant.v, Table 2)
                  |small|/|large| in steps of 1/2048, paper table
                  |small| in steps of 1/2048 of the unit radius
  phase   u13     fine phase of the signal, 8192 per period     (rtl/harmonic.v)
  prod    u22     n * phase: pn = prod mod 8192, the n-th order (rtl/lut.v, Table 1)
                  phase; q = prod >> 11, the counter's fine count
  cosn/sinn s1.(SIN_W-1) n-th order sinusoids from the table    (rtl/lut.v)
  a, b    u1      pulses with hysteresis eps (u0.15)            (rtl/pulse.v, Eq. 12)
  count   s32     count of the n-th order                       (rtl/counter.v)
"""
import numpy as np

from .tables import ADDR_W, PH_W, RCP_AW, phase_table, recip_table, sine_table

I64 = np.int64


def _sat(v, w):
    return np.clip(v, -(1 << (w - 1)), (1 << (w - 1)) - 1)


def _rnd_shr(v, s):
    return (v + (1 << (s - 1))) >> s


CLIP_LEVEL = 32512   # CLIP register reset value: |u| >= 0.992 of full scale is clipped


def align(code, adc_w, clip_level=CLIP_LEVEL):
    """ADC code (adc_w bits, signed) -> s1.15 MSB-aligned, and the clip flag: the code
    is at or near an ADC rail, |u_aligned| >= clip_level (u16; |-32768| = 32768)."""
    code = np.asarray(code, dtype=I64)
    u = code << (16 - adc_w)
    return u, np.abs(u) >= clip_level


def correct(u1r, u2r, g, m1, m2, c1, c12, c2):
    """Input gain, offsets and Eq. 9 as three products (rtl/correct.v):
        x = u_raw * 2**g,  d = sat16(x - m),  v1 = c1 d1,  v2 = c12 d1 + c2 d2  (s6.27),
        |u| = (v ^ sign) >> 13 (s2.14 units: floor(|v| / 2**13) for v >= 0, of
        (|v| - 1) for v < 0; no carry after the sum), saturated to 32767.
    Returns a dict: ax, ay (u15), xn, yn (v < 0), u1c, u2c (+-|u|, for traces), nsat (x
    leaves s1.15), dsat (d saturated), rsat (|u| reached 32768), csat (either)."""
    g = np.asarray(g, dtype=I64)
    x1, x2 = np.asarray(u1r, dtype=I64) << g, np.asarray(u2r, dtype=I64) << g
    e1, e2 = x1 - m1, x2 - m2
    d1, d2 = _sat(e1, 16), _sat(e2, 16)
    v1 = d1 * c1
    v2 = d1 * c12 + d2 * c2
    q1 = (v1 ^ (v1 >> 63)) >> 13
    q2 = (v2 ^ (v2 >> 63)) >> 13
    ax, ay = np.minimum(q1, 32767), np.minimum(q2, 32767)
    xn, yn = (v1 < 0).astype(I64), (v2 < 0).astype(I64)
    nsat = (x1 != _sat(x1, 16)) | (x2 != _sat(x2, 16))
    dsat = (d1 != e1) | (d2 != e2)
    rsat = (q1 > 32767) | (q2 > 32767)
    return dict(ax=ax, ay=ay, xn=xn, yn=yn, u1c=np.where(xn == 1, -ax, ax),
                u2c=np.where(yn == 1, -ay, ay), nsat=nsat, dsat=dsat, rsat=rsat,
                csat=dsat | rsat)


_RECIP = np.array(recip_table(), dtype=I64)
RATIO_ROUND = 1 << 15     # rounds the address to 1/2048


def lzc15(v):
    """Leading zeros of a u15 value, 0..14 (14 for 0 and 1, as rtl/octant.v)."""
    v = np.asarray(v, dtype=I64)
    z = np.full(v.shape, 14, dtype=I64)
    for b in range(15):                             # the highest set bit is applied last
        z = np.where((v >> b) & 1, 14 - b, z)
    return z


def ratio_product(small, large):
    """The ratio product of rtl/octant.v (small <= large, both u15):

      zl  = lzc15(large)
      ln  = large << zl          u15 in [2**14, 2**15) (0 for large = 0), m = ln / 2**14
      sn  = (small << zl) >> 1   u14: t = 2 sn / ln
      r   = RECIP[ln[13:5]]      u0.14, ~ 1/m (9-bit bin below the leading 1)
      p   = sn * r = t * 2**27 (1 + O(2**-10))    u28"""
    zl = lzc15(large)
    ln = (large << zl) & 0x7FFF
    sn = ((small << zl) & 0x7FFF) >> 1
    r = _RECIP[(ln >> 5) & ((1 << RCP_AW) - 1)]
    return sn * r


def ratio(small, large):
    """Exact-table address j = min(2047, round(2048 small / large)) as rtl/octant.v forms
    it: j = min(2047, (p + 2**15) >> 16) of the ratio product p (ratio_product)."""
    return np.minimum((ratio_product(small, large) + RATIO_ROUND) >> 16, (1 << ADDR_W) - 1)


def octant(ax, ay, xn, yn, kind="exact"):
    """Table 2: octant from signs and magnitudes; address from the magnitudes: for the
    exact table the ratio small / large (the tangent of the octant-local angle, so both
    signals contribute), for the paper's table the smaller magnitude alone (Eq. 10).
    Ties |u1c| == |u2c| take the low octant.

    Returns (j, base, neg): phase = base + (neg ? -PH[j] : PH[j]) mod 8192."""
    ax, ay = np.asarray(ax, dtype=I64), np.asarray(ay, dtype=I64)
    xn, yn = np.asarray(xn, dtype=I64) != 0, np.asarray(yn, dtype=I64) != 0
    low = ay <= ax                                  # octants 0, 3, 4, 7: address from |u2c|
    small = np.where(low, ay, ax)
    base = np.where(low, np.where(xn, 4096, 0), np.where(yn, 6144, 2048))
    neg = np.where(low, xn != yn, xn == yn)
    if kind == "paper":
        j = np.minimum((small + 4) >> 3, (1 << ADDR_W) - 1)
    elif kind == "exact":
        j = ratio(small, np.where(low, ax, ay))
    else:
        raise ValueError(f"table kind must be 'exact' or 'paper', got {kind!r}")
    return j.astype(I64), base.astype(I64), neg.astype(I64)


def scale(ax, ay, kind="exact"):
    """The address's scale t (rtl/octant.v t_o, u12) from which rtl/harmonic.v finds the
    bin and which addresses the exact phase table of 4096 rows per sign
    (tables.phase_table_4k): exact
    min(4095, floor(p / 2**15)) of the ratio product (j = (t + 1) >> 1 clipped at 2047),
    paper 2 j."""
    ax, ay = np.asarray(ax, dtype=I64), np.asarray(ay, dtype=I64)
    low = ay <= ax
    small, large = np.where(low, ay, ax), np.where(low, ax, ay)
    if kind == "paper":
        return 2 * np.minimum((small + 4) >> 3, (1 << ADDR_W) - 1)
    if kind == "exact":
        return np.minimum(ratio_product(small, large) >> 15, 2 * (1 << ADDR_W) - 1)
    raise ValueError(f"table kind must be 'exact' or 'paper', got {kind!r}")


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
        """n-th order: prod = n * phase (u22); pn = prod mod 8192 and the sines."""
        prod = np.asarray(phase, dtype=I64) * np.asarray(n, dtype=I64)
        pn = prod & ((1 << PH_W) - 1)
        return prod, pn, self._sine((pn + 2048) & 8191), self._sine(pn)


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


def counter(phase, prod, n, count_w=32, state=None, hold=None):
    """Phase-mode count (rtl/counter.v): count = B + (prod >> 11), B = 4 n W stepping by
    -4 n / +4 n when the phase wraps backwards / forwards (raw = phase - phase_prev >=
    4096 / < -4096; phase_prev = 0 from reset), i.e. floor(4 n Phi / 8192) of the
    unwrapped phase Phi (starting at wrap13(phase_0)). Overspeed: |wrap13(raw)| >= 3072,
    never on the first sample from reset. n: scalar or per-sample array (sampled with the
    sample). hold (per sample, rtl/monitor.v): a held sample changes nothing: its count is
    the previous sample's (0 before any), phase_prev and B stay, no overspeed; the next
    sample steps from the last one counted. `state` (B, phase_prev, primed, count)
    continues a run.

    Returns (count, overspeed, state after the last sample)."""
    b0, ph0, primed, c0 = (0, 0, False, 0) if state is None else state
    phase = np.asarray(phase, dtype=I64)
    n = np.broadcast_to(np.asarray(n, dtype=I64), phase.shape)
    if hold is not None and np.any(hold):
        # count the accepted samples alone; a held sample repeats the count before it
        acc = np.nonzero(~np.asarray(hold, dtype=bool))[0]
        c_acc, o_acc, st = counter(phase[acc], np.asarray(prod, dtype=I64)[acc], n[acc],
                                   count_w, (b0, ph0, primed, c0))
        last = np.full(len(phase), -1, dtype=I64)
        last[acc] = np.arange(len(acc))
        last = np.maximum.accumulate(last)
        count = np.where(last >= 0, c_acc[np.maximum(last, 0)] if len(acc) else 0, c0)
        ovs = np.zeros(len(phase), dtype=bool)
        ovs[acc] = o_acc
        return count.astype(I64), ovs, st
    prev = np.concatenate([[ph0], phase[:-1]]).astype(I64)
    raw = phase - prev
    step = np.where(raw >= 4096, -1, np.where(raw < -4096, 1, 0))
    dph = ((raw + 4096) & 8191) - 4096
    ovs = np.abs(dph) >= 3072
    if not primed and len(phase):
        ovs[0] = False
    m = 1 << count_w
    bacc = b0 + np.cumsum(4 * n * step)
    count = ((bacc + (np.asarray(prod, dtype=I64) >> 11) + (m >> 1)) % m) - (m >> 1)
    if len(phase):
        state = (int(bacc[-1]), int(phase[-1]), True, int(count[-1]))
    elif state is None:
        state = (0, 0, False, 0)
    return count.astype(I64), ovs, state


def edge_steps(a, b, state=None):
    """The paper's x4 decoder of the Eq. 12 pulses (rtl/counter.v, edge mode): per sample
    the step +1 / -1 for a quadrant step 1 / 3 (mod 4), 0 otherwise; a step of 2 (both A
    and B changed) is illegal: 0, flagged unless it is the first sample from reset.
    Quadrant code (1,1) 0, (0,1) 1, (0,0) 2, (1,0) 3; quadrant 0 before the first sample.
    Returns (step, illegal, state)."""
    qd0, primed = (0, False) if state is None else state
    a, b = np.asarray(a, dtype=I64), np.asarray(b, dtype=I64)
    qd = np.where(a == 1, np.where(b == 1, 0, 3), np.where(b == 1, 1, 2)).astype(I64)
    dq = (qd - np.concatenate([[qd0], qd[:-1]])) & 3
    step = np.where(dq == 1, 1, np.where(dq == 3, -1, 0)).astype(I64)
    ill = dq == 2
    if not primed and len(a):
        ill[0] = False
    if len(a):
        state = (int(qd[-1]), True)
    elif state is None:
        state = (0, False)
    return step, ill, state
