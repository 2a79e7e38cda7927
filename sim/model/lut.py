"""Bit-true model of rtl/lut.v: Table 1 through two block-RAM tables, the octant phase
table (phase u13, 8192 per signal period) and the quarter-wave sine table of the n-th
order sinusoids (prod = n * phase u22, pn = prod mod 8192; cos, sin s1.(SIN_W-1)).
"""
import numpy as np

from .tables import PH_W, phase_table, sine_table

I64 = np.int64


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
