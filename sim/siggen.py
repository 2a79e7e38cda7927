"""Encoder signal generator with ground truth (METHOD.md signal model, plus harmonics).

Each channel carries the same periodic waveform f (the readhead sees one grating through
two windows a quarter period apart), with gain, offset and quadrature error:

    f(t) = cos t + h2 cos 2t + h3 cos 3t + h5 cos 5t
    u1 = A1 f(a) + m1,   u2 = A2 f(a - phi - pi/2) + m2,   a = 2 pi x / pitch

With h2 = h3 = h5 = 0 this is u2 = A2 sin(a - phi) + m2, the paper's model. A third harmonic h3
gives an angle error of about h3 rad at four times the signal frequency, which no ellipse
correction removes (METHOD.md, weaknesses). Then white Gaussian noise (sigma = noise x the
initial A1, the same on both channels), signal dropout, and quantisation to signed ADC
codes (adc_bits, full scale = +-1, clipped at the rails).

A1, A2, m1, m2 and phi are fractions of full scale (phi in rad) and may be constants or
per-sample arrays: `along` makes a slow drift along the travel, `jump` a sudden change.
Motion profiles return positions (same unit as the pitch) at the sample instants.
Everything is seeded; `encode` returns the true angle, and `angle_var` the per-sample
Cramer-Rao bound that the accuracy floor is built from. `reference` gives the reference
input of marks along the scale (the comparator's output).
"""
from dataclasses import dataclass, asdict

import numpy as np


@dataclass
class Signal:
    A1: object = 0.60      # amplitudes, fraction of ADC full scale (float or array)
    A2: object = 0.54
    m1: object = 0.030     # offsets, fraction of full scale
    m2: object = -0.020
    phi: object = 0.08     # quadrature phase error, rad
    h2: float = 0.0        # 2nd, 3rd and 5th harmonic, fraction of the fundamental
    h3: float = 0.0
    h5: float = 0.0
    noise: float = 0.005   # white noise sigma per channel, fraction of the initial A1
    adc_bits: int = 16
    dropout: tuple = ()    # ((first, stop, level), ...): samples [first, stop) have their
                           # amplitudes scaled by level (0 = cable unplugged, 0.3 = dirt)

    def sigma(self):
        """Noise standard deviation in full-scale units."""
        return self.noise * float(np.ravel(self.A1)[0])


# ---- motion profiles ------------------------------------------------------------------

def constant_speed(n, fs, v, x0=0.0):
    return x0 + v * np.arange(n) / fs


def s_curve(n, fs, dist, t_move, t_start=0.0, x0=0.0):
    """Smooth point-to-point move of `dist` in `t_move` s (sinusoidal acceleration),
    starting at t_start; standstill before and after."""
    t = np.arange(n) / fs
    tau = np.clip((t - t_start) / t_move, 0.0, 1.0)
    return x0 + dist * (tau - np.sin(2 * np.pi * tau) / (2 * np.pi))


def jerk_limited(dist, vmax, amax, jmax, fs):
    """Seven-segment jerk-limited move from 0 to `dist` (units of dist per s, s^2, s^3):
    positions at the sample instants, first 0, last exactly dist. The cruise speed is
    lowered when the move is too short to reach vmax."""
    if min(vmax, amax, jmax) <= 0:
        raise ValueError(f"jerk_limited: vmax, amax, jmax must be > 0, got "
                         f"{vmax}, {amax}, {jmax}")
    d = abs(dist)
    if d == 0:
        return np.zeros(1)

    def ramp(v):                      # jerk time, constant-acceleration time, ramp length
        tj = min(amax / jmax, np.sqrt(v / jmax))
        ta = max(v / (jmax * tj) - tj, 0.0)
        return tj, ta, v * (2 * tj + ta) / 2

    v = vmax
    if 2 * ramp(v)[2] > d:            # too short to cruise: bisect the peak speed
        lo, hi = 0.0, vmax
        for _ in range(100):
            v = (lo + hi) / 2
            lo, hi = (v, hi) if 2 * ramp(v)[2] < d else (lo, v)
        v = lo
    tj, ta, dr = ramp(v)
    tv = (d - 2 * dr) / v
    seg = np.cumsum([0, tj, ta, tj, tv, tj, ta, tj])
    jerk = [jmax, 0, -jmax, 0, -jmax, 0, jmax]
    t = np.arange(int(np.ceil(seg[-1] * fs)) + 1) / fs
    # exact integration of the piecewise-constant jerk, segment by segment
    x = np.zeros_like(t)
    p = vv = a = 0.0
    for i, j in enumerate(jerk):
        m = (t >= seg[i]) & (t < seg[i + 1]) if i < 6 else t >= seg[i]
        tau = np.minimum(t[m] - seg[i], seg[i + 1] - seg[i])
        x[m] = p + vv * tau + a * tau ** 2 / 2 + j * tau ** 3 / 6
        h = seg[i + 1] - seg[i]
        p, vv, a = p + vv * h + a * h ** 2 / 2 + j * h ** 3 / 6, vv + a * h + j * h ** 2 / 2, a + j * h
    x *= d / x[-1]                    # remove the integration's rounding at the end
    return np.sign(dist) * x


def moves(fs, plan, x0=0.0):
    """Concatenate ('dwell', seconds) and ('move', dist, vmax, amax, jmax) steps."""
    parts, x = [], x0
    for step in plan:
        if step[0] == "dwell":
            parts.append(np.full(int(round(step[1] * fs)), x))
        elif step[0] == "move":
            seg = x + jerk_limited(*step[1:], fs)
            parts.append(seg[1:])
            x = seg[-1]
        else:
            raise ValueError(f"moves: unknown step {step!r} (expected 'dwell' or 'move')")
    return np.concatenate(parts)


def reversals(n, fs, amplitude, freq, x0=0.0):
    """Sinusoidal back-and-forth: x0 + amplitude (1 - cos(2 pi freq t)), two reversals per
    cycle."""
    t = np.arange(n) / fs
    return x0 + amplitude * (1 - np.cos(2 * np.pi * freq * t))


# ---- reference marks ---------------------------------------------------------------------

def reference(x, marks, width, jitter=0.0, glitches=0, seed=0):
    """The reference input (rtl/refmark.v s_ref) at positions x: 1 while x lies within
    width / 2 of a mark's centre (marks: centres, same unit as x), as an external
    comparator gives it. jitter: the comparator's threshold noise as a position
    (Gaussian sigma per sample: the window's edges chatter); glitches: that many single
    samples inverted at random (interference). Returns int64 0/1 per sample."""
    rng = np.random.default_rng(seed)
    x = np.asarray(x, float)
    edge = x + (jitter * rng.standard_normal(x.shape) if jitter else 0.0)
    r = np.zeros(x.shape, np.int64)
    for m in np.atleast_1d(marks):
        r |= (np.abs(edge - m) <= width / 2).astype(np.int64)
    if glitches:
        at = rng.choice(len(x), glitches, replace=False)
        r[at] ^= 1
    return r


def distance_coded(spacing, coded, length):
    """The marks of a scale with distance-coded reference marks (rtl/dcode.v): fixed marks
    every `spacing` signal periods and a coded mark spacing / 2 + (j + 1) (coded - spacing)
    after fixed mark j; their positions in signal periods from the first fixed mark, in
    order, up to `length` periods (a coded mark only while it lies before the next fixed
    one)."""
    d = coded - spacing
    out, j = [], 0
    while j * spacing <= length:
        out.append(j * spacing)
        b = j * spacing + spacing // 2 + d * (j + 1)
        if b < (j + 1) * spacing and b <= length:
            out.append(b)
        j += 1
    return out


# ---- parameter profiles -----------------------------------------------------------------

def along(x, start, end):
    """A parameter drifting linearly along the travel: `start` at the lowest position
    reached, `end` at the highest."""
    x = np.asarray(x, float)
    span = np.ptp(x)
    return start + (end - start) * ((x - x.min()) / span if span else 0.0 * x)


def jump(value, at, step):
    """`value` (float or array) with `step` added from sample `at` on; the length is that
    of `value` if an array, else give an array."""
    v = np.array(value, dtype=float, copy=True)
    v[at:] += step
    return v


# ---- signals --------------------------------------------------------------------------

def _waves(a, sig, d=0):
    """Channel waveforms f(a) and f(a - phi - pi/2) (d = 0), or their derivatives in a
    (d = 1), written with s = a - phi so that without harmonics channel 2 is sin(s)."""
    s = a - sig.phi
    if d == 0:
        return (np.cos(a) + sig.h2 * np.cos(2 * a) + sig.h3 * np.cos(3 * a)
                + sig.h5 * np.cos(5 * a),
                np.sin(s) - sig.h2 * np.cos(2 * s) - sig.h3 * np.sin(3 * s)
                + sig.h5 * np.sin(5 * s))
    return (-np.sin(a) - 2 * sig.h2 * np.sin(2 * a) - 3 * sig.h3 * np.sin(3 * a)
            - 5 * sig.h5 * np.sin(5 * a),
            np.cos(s) + 2 * sig.h2 * np.sin(2 * s) - 3 * sig.h3 * np.cos(3 * s)
            + 5 * sig.h5 * np.cos(5 * s))


def _amplitudes(n, sig):
    A1 = np.broadcast_to(np.asarray(sig.A1, float), (n,)).copy()
    A2 = np.broadcast_to(np.asarray(sig.A2, float), (n,)).copy()
    for first, stop, level in sig.dropout:
        A1[first:stop] *= level
        A2[first:stop] *= level
    return A1, A2


def encode(x, pitch, sig: Signal, seed=0):
    """Return (u1_code, u2_code, angle) for positions x (same unit as pitch)."""
    rng = np.random.default_rng(seed)
    a = 2 * np.pi * np.asarray(x, float) / pitch
    A1, A2 = _amplitudes(len(a), sig)
    sigma = sig.sigma()
    w1, w2 = _waves(a, sig)
    u1 = A1 * w1 + sig.m1 + sigma * rng.standard_normal(a.shape)
    u2 = A2 * w2 + sig.m2 + sigma * rng.standard_normal(a.shape)
    full = 1 << (sig.adc_bits - 1)
    q1 = np.clip(np.round(u1 * full), -full, full - 1).astype(np.int64)
    q2 = np.clip(np.round(u2 * full), -full, full - 1).astype(np.int64)
    return q1, q2, a


def angle_var(a, sig: Signal):
    """Per-sample Cramer-Rao bound of the angle (rad^2): noise plus ADC quantisation
    (lsb^2/12) over the squared speed of the signal vector, |du/da|^2 (METHOD.md; the
    same formula with harmonics and per-sample parameters). Infinite where the signal
    has dropped out (no information)."""
    a = np.asarray(a, float)
    A1, A2 = _amplitudes(len(a), sig)
    lsb = 2.0 / (1 << sig.adc_bits)
    var_u = sig.sigma() ** 2 + lsb ** 2 / 12
    d1, d2 = _waves(a, sig, 1)
    g2 = (A1 * d1) ** 2 + (A2 * d2) ** 2
    with np.errstate(divide="ignore"):
        return np.where(g2 > 0, var_u / np.maximum(g2, 1e-300), np.inf)


def describe(sig: Signal) -> dict:
    """JSON-friendly description: arrays as their first, last, min and max value."""
    out = {}
    for k, v in asdict(sig).items():
        if np.ndim(v) and k != "dropout":
            v = np.asarray(v, float)
            out[k] = dict(first=float(v[0]), last=float(v[-1]), min=float(v.min()),
                          max=float(v.max()))
        else:
            out[k] = v if k != "dropout" else [list(map(float, d)) for d in v]
    return out
