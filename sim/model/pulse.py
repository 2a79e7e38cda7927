"""Bit-true model of rtl/pulse.v: the Eq. 12 pulses A, B (u1) of the n-th order sinusoids
with hysteresis EPS (u0.15).
"""
import numpy as np

I64 = np.int64


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
