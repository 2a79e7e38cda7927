"""Bit-true model of rtl/octant.v: Table 2 (the octant from signs and magnitudes) and the
phase table's address j (u11): for the exact table |small|/|large| in steps of 1/2048
(a reciprocal table and one multiply), for the paper's table |small| in steps of 1/2048
of the unit radius (Eq. 10). numpy int64 arrays, one element per sample.
"""
import numpy as np

from .tables import ADDR_W, RCP_AW, recip_table

I64 = np.int64

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
