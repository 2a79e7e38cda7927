"""Bit-true model of rtl/correct.v: ADC alignment, input gain, offsets and Eq. 9.

Formats (sI.F: I integer bits including the sign), numpy int64 arrays, one element per
sample:

  u_raw   s1.15   ADC code, MSB-aligned to 16 bits
  x       s4.15   u_raw * 2**g (exact)
  m       s1.15   offsets, normalised units (the bundle's m1, m2)
  c       s4.12   correction coefficients c1, c12, c2 (the bundle)
  d       s1.15   sat16(x - m)
  u       s2.14   corrected signals (unit circle = 16384): the fast path keeps
                  |u| = (v ^ sign) >> 13 (u15, saturated) and the sign of the products'
                  sum v
"""
import numpy as np

from .regs import SETTINGS

I64 = np.int64


def _sat(v, w):
    return np.clip(v, -(1 << (w - 1)), (1 << (w - 1)) - 1)


def _rnd_shr(v, s):
    return (v + (1 << (s - 1))) >> s


CLIP_LEVEL = SETTINGS["clip"].reset   # CLIP's reset: |u| >= 0.992 of full scale is clipped


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
