"""Baseline interpolators for the accuracy benchmark (float, not bit-true).

Every function takes the encoder signals u1, u2 as float arrays in full-scale units
(ADC code / 2**(bits-1)), signal model (METHOD.md)

    u1 = A1 cos(a) + m1,    u2 = A2 sin(a - phi) + m2,

and returns, one per sample, an int64 x4 count of the n-th order sinusoid (resolution
pitch / (4 n), n = `interp`) that counts UP for increasing angle a (counter-clockwise motion
of (u1, u2)). The zero of the count is arbitrary (metrics remove the mean), but there are no
arbitrary jumps: for an ideal interpolator count = floor(unwrapped_angle * 2 n / pi) + const.
So the baselines go through exactly the same metrics as the gateware's bit-true model.

    raw_atan2      no correction at all (how much the distortion alone costs)
    heydemann      offline least-squares ellipse fit of the whole record (Heydemann 1981),
                   Eq. 8 / Eq. 9 of Ulu et al. 2014, then atan2 (the best an ellipse
                   correction can do with hindsight)
    paper_literal  the method of Ulu et al. 2014 as printed (errata of METHOD.md applied):
                   float RLS with forgetting and resets, Eq. 8, Eq. 9, the linear octant
                   index of Table 2, Table 1, hysteresis pulses (Eq. 12) and an x4 pulse
                   counter that loses counts at high speed (Eq. 13)
"""
import numpy as np

from sim import reference

_S45 = np.sin(np.pi / 4)
# initial guess of paper_literal: A1 = 0.5, R = 1, m1 = m2 = 0, phi = 0 (a circle of radius
# 0.5), i.e. theta = (1/A1^2, 1/A1^2, 0, 0, 0) by Eq. 4
_P0 = (0.5, 1.0, 0.0, 0.0, 0.0)
_THETA0 = (4.0, 4.0, 0.0, 0.0, 0.0)


# ---------------------------------------------------------------------------- helpers

def _signals(u1, u2):
    """Validate and convert the inputs: 1-D, same non-zero length, finite."""
    u1 = np.asarray(u1, dtype=float)
    u2 = np.asarray(u2, dtype=float)
    if u1.ndim != 1 or u2.ndim != 1:
        raise ValueError(f"u1 and u2 must be 1-D arrays (got shapes {u1.shape} and {u2.shape})")
    if len(u1) != len(u2):
        raise ValueError(f"u1 and u2 must have the same length (got {len(u1)} and {len(u2)})")
    if len(u1) == 0:
        raise ValueError("u1 and u2 are empty")
    if not (np.all(np.isfinite(u1)) and np.all(np.isfinite(u2))):
        raise ValueError("u1 and u2 must be finite (no NaN or inf samples)")
    return u1, u2


def _positive_int(value, name):
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) \
            or value < 1:
        raise ValueError(f"{name} must be a positive integer (got {value!r})")
    return int(value)


def _quantise(angle, interp):
    """x4 count of the n-th order sinusoid from an angle in rad: floor(angle * 2 n / pi)."""
    return np.floor(angle * (2.0 * interp / np.pi)).astype(np.int64)


def _atan2_count(c1, c2, interp):
    """Angle of the (corrected) signals by atan2, unwrapped, quantised."""
    return _quantise(np.unwrap(np.arctan2(c2, c1)), interp)


def extract_many(theta):
    """Eq. 8 for many theta at once (rows of an (n, 5) array), the vectorised twin of
    reference.extract. Returns (params (n, 5) with columns A1, R, m1, m2, phi, valid (n,)
    bool); rows that are not an ellipse (reference.extract would return None) are NaN and
    not valid."""
    th = np.asarray(theta, dtype=float)
    t1, t2, t3, t4, t5 = th.T
    with np.errstate(all="ignore"):
        den = 4 * t1 * t2 - t3 * t3
        ok = (t1 > 0) & (t2 > 0) & (den > 0)
        m1 = (2 * t2 * t4 - t5 * t3) / (t3 * t3 - 4 * t1 * t2)
        m2 = (2 * t1 * t5 - t4 * t3) / (t3 * t3 - 4 * t1 * t2)
        a1sq = 4 * t2 * (1 + t1 * m1 ** 2 + t2 * m2 ** 2 + t3 * m1 * m2) / den
        ok &= a1sq > 0
        p = np.column_stack([np.sqrt(a1sq), np.sqrt(t2 / t1), m1, m2,
                             np.arcsin(t3 / np.sqrt(4 * t1 * t2))])
    ok &= np.all(np.isfinite(p), axis=1)
    p[~ok] = np.nan
    return p, ok


def _forward_fill(state, first):
    """Replace the -1 entries of an int array by the last entry >= 0 before them; leading
    -1 become `first`. Vectorised form of a sequential 'keep the last decisive value'."""
    n = len(state)
    pos = np.where(state >= 0, np.arange(n), -1)
    np.maximum.accumulate(pos, out=pos)
    return np.where(pos >= 0, state[np.maximum(pos, 0)], first)


# ---------------------------------------------------------------------------- baselines

def raw_atan2(u1, u2, interp):
    """No correction at all: atan2(u2, u1) of the raw signals, unwrapped and quantised to
    the x4 count of the n-th order (floor(angle * 2 n / pi)).

    This is the ideal interpolation step of the paper (the angle of Eq. 1) applied without
    the ellipse correction of Eq. 9, so offsets, amplitude mismatch and phase error show up
    in full."""
    u1, u2 = _signals(u1, u2)
    interp = _positive_int(interp, "interp")
    return _atan2_count(u1, u2, interp)


def heydemann(u1, u2, interp, mask=None):
    """Offline ellipse fit on the whole record (Heydemann, Appl. Opt. 20(19), 1981), then
    the correction of Ulu et al. 2014.

    Least squares (np.linalg.lstsq) of Eq. 3,
        theta1 u1^2 + theta2 u2^2 + theta3 u1 u2 + theta4 u1 + theta5 u2 = 1,
    over the samples selected by `mask` (boolean, default all; exclude clipped or dropout
    samples with it), parameters (A1, R, m1, m2, phi) by Eq. 8 (reference.extract),
    correction of every sample by Eq. 9 (reference.correct), then atan2, unwrap and the x4
    count floor(angle * 2 n / pi).

    Returns (count, params) with params = (A1, R, m1, m2, phi) as floats. Raises
    ValueError if the inputs are bad, the fit is rank deficient (the samples do not span
    enough of the circle) or theta is not an ellipse."""
    u1, u2 = _signals(u1, u2)
    interp = _positive_int(interp, "interp")
    if mask is None:
        sel = np.ones(len(u1), bool)
    else:
        sel = np.asarray(mask)
        if sel.dtype != bool or sel.shape != u1.shape:
            raise ValueError(f"mask must be a boolean array of the signals' shape {u1.shape} "
                             f"(got dtype {sel.dtype}, shape {sel.shape})")
    x1, x2 = u1[sel], u2[sel]
    if len(x1) < 5:
        raise ValueError(f"heydemann: need at least 5 samples to fit the ellipse "
                         f"(got {len(x1)})")
    phi = np.column_stack([x1 * x1, x2 * x2, x1 * x2, x1, x2])
    theta, _, rank, _ = np.linalg.lstsq(phi, np.ones(len(x1)), rcond=None)
    if rank < 5:
        raise ValueError(f"heydemann: the least-squares fit is rank deficient (rank {rank} "
                         f"of 5); the samples do not cover enough of an ellipse")
    p = reference.extract(theta)
    if p is None or not np.all(np.isfinite(p)):
        raise ValueError(f"heydemann: the fitted conic is not an ellipse (theta = "
                         f"{np.array2string(theta, precision=4)}; need theta1 > 0, "
                         f"theta2 > 0, 4 theta1 theta2 > theta3^2 and A1^2 > 0)")
    p = tuple(float(v) for v in p)
    c1, c2 = reference.correct(u1, u2, p)
    return _atan2_count(c1, c2, interp), p


def _rls_thetas(u1, u2, lam, kappa, reset_every, theta0=_THETA0):
    """Eq. 7 (Eqs. 5-7: RLS with exponential forgetting lambda, given directly) on every
    sample, P reset to kappa*I after every `reset_every` updates (0 or None: never).
    Returns theta after each sample's update, shape (n, 5).

    Same arithmetic as reference.Rls.update (h = P phi, K = h / (lambda + phi' h),
    theta += K (1 - phi' theta), P = (P - K h') / lambda), written out on scalars with P
    kept symmetric by construction (upper triangle only); about 5x faster than numpy on
    5-vectors (~4 us per sample)."""
    il = 1.0 / lam
    z = 0.0
    fresh = (kappa, z, z, z, z, kappa, z, z, z, kappa, z, z, kappa, z, kappa)
    p00, p01, p02, p03, p04, p11, p12, p13, p14, p22, p23, p24, p33, p34, p44 = fresh
    t0, t1, t2, t3, t4 = (float(t) for t in theta0)
    reset_every = int(reset_every or 0)
    out = []
    ap = out.append
    k = 0
    for f0, f1, f2, f3, f4 in zip((u1 * u1).tolist(), (u2 * u2).tolist(),
                                  (u1 * u2).tolist(), u1.tolist(), u2.tolist()):
        h0 = p00 * f0 + p01 * f1 + p02 * f2 + p03 * f3 + p04 * f4
        h1 = p01 * f0 + p11 * f1 + p12 * f2 + p13 * f3 + p14 * f4
        h2 = p02 * f0 + p12 * f1 + p22 * f2 + p23 * f3 + p24 * f4
        h3 = p03 * f0 + p13 * f1 + p23 * f2 + p33 * f3 + p34 * f4
        h4 = p04 * f0 + p14 * f1 + p24 * f2 + p34 * f3 + p44 * f4
        den = lam + h0 * f0 + h1 * f1 + h2 * f2 + h3 * f3 + h4 * f4
        e = (1.0 - (t0 * f0 + t1 * f1 + t2 * f2 + t3 * f3 + t4 * f4)) / den
        t0 += h0 * e
        t1 += h1 * e
        t2 += h2 * e
        t3 += h3 * e
        t4 += h4 * e
        ap((t0, t1, t2, t3, t4))
        k += 1
        if reset_every and k % reset_every == 0:
            p00, p01, p02, p03, p04, p11, p12, p13, p14, p22, p23, p24, p33, p34, p44 = fresh
            continue
        g0 = h0 / den * il
        g1 = h1 / den * il
        g2 = h2 / den * il
        g3 = h3 / den * il
        g4 = h4 / den * il
        p00 = p00 * il - h0 * g0
        p01 = p01 * il - h0 * g1
        p02 = p02 * il - h0 * g2
        p03 = p03 * il - h0 * g3
        p04 = p04 * il - h0 * g4
        p11 = p11 * il - h1 * g1
        p12 = p12 * il - h1 * g2
        p13 = p13 * il - h1 * g3
        p14 = p14 * il - h1 * g4
        p22 = p22 * il - h2 * g2
        p23 = p23 * il - h2 * g3
        p24 = p24 * il - h2 * g4
        p33 = p33 * il - h3 * g3
        p34 = p34 * il - h3 * g4
        p44 = p44 * il - h4 * g4
    return np.array(out, dtype=float).reshape(-1, 5)


def linear_index(c1, c2, N):
    """Table 2 with the paper's linear index (Eq. 11), rule of METHOD.md: the octant from
    signs and magnitudes, the index inside it linear in the smaller-magnitude corrected
    signal divided by sin(pi/4), times N; 8N rows per period, rounded to the nearest row.

        |u2c| <= |u1c|, u1c >= 0:  i =      u2c / sin(pi/4) * N     a in (-pi/4, pi/4]
        |u1c| <  |u2c|, u2c >  0:  i = 2N - u1c / sin(pi/4) * N     a in (pi/4, 3pi/4]
        |u2c| <= |u1c|, u1c <  0:  i = 4N - u2c / sin(pi/4) * N     a in (3pi/4, 5pi/4]
        |u1c| <  |u2c|, u2c <  0:  i = 6N + u1c / sin(pi/4) * N     a in (5pi/4, 7pi/4]

    (the comparison of the two magnitudes equals the printed comparison with sin(pi/4) on
    the unit circle and is what the gateware does). Returns i mod 8N as int64. The linear
    index treats sin(a) as proportional to a inside an octant: angle error up to 0.033 rad."""
    c1 = np.asarray(c1, dtype=float)
    c2 = np.asarray(c2, dtype=float)
    low = np.abs(c2) <= np.abs(c1)
    i = np.where(low, np.where(c1 >= 0, c2 / _S45 * N, 4 * N - c2 / _S45 * N),
                 np.where(c2 > 0, 2 * N - c1 / _S45 * N, 6 * N + c1 / _S45 * N))
    # corrected signals are finite but may be huge with absurd parameters: keep the cast safe
    i = np.clip(np.nan_to_num(i), -2.0 ** 52, 2.0 ** 52)
    return np.mod(np.rint(i).astype(np.int64), 8 * N)


def pulses(x, eps):
    """Eq. 12 with hysteresis: 1 where x >= eps, 0 where x <= -eps, otherwise the previous
    value (before the first decisive sample: x[0] >= 0). Vectorised forward fill."""
    x = np.asarray(x, dtype=float)
    state = np.where(x >= eps, 1, np.where(x <= -eps, 0, -1)).astype(np.int8)
    return _forward_fill(state, np.int8(x[0] >= 0)).astype(np.int8)


# quadrant of the n-th order sinusoid from (A, B): A = [cos >= 0], B = [sin >= 0];
# increasing phase runs (1,1) -> (0,1) -> (0,0) -> (1,0), i.e. quadrant 0, 1, 2, 3
_QUADRANT = np.array([2, 1, 3, 0], dtype=np.int64)          # indexed by 2 A + B
_STEP = np.array([0, 1, 0, -1], dtype=np.int64)             # by quadrant difference mod 4


def decode_x4(a, b):
    """x4 quadrature decoder: +1 / -1 per single edge of A or B (up for increasing phase
    of the n-th order), nothing when both change in the same sample (an illegal transition:
    the counter cannot tell the direction and loses the counts). Returns (count int64 per
    sample, starting at the first sample's quadrant, number of illegal transitions)."""
    q = _QUADRANT[2 * np.asarray(a, dtype=np.int64) + np.asarray(b, dtype=np.int64)]
    d = np.mod(np.diff(q), 4)
    count = np.empty(len(q), dtype=np.int64)
    count[0] = q[0]
    count[1:] = q[0] + np.cumsum(_STEP[d])
    return count, int(np.count_nonzero(d == 2))


def paper_literal(u1, u2, interp, lam=0.995, kappa=1000.0, reset_every=1000, N=1000,
                  eps=0.05):
    """The method of Ulu et al. 2014 as printed, errata of METHOD.md applied.

    - Eqs. 5-7: float RLS with exponential forgetting `lam` (given directly, not the
      gateware's 1/(1 + 2**-k)) updated on EVERY sample, P = kappa*I at the start and reset
      to it after every `reset_every` samples (0 or None: never); theta starts at the
      initial guess A1 = 0.5, R = 1, m1 = m2 = 0, phi = 0 (theta = (4, 4, 0, 0, 0)).
    - Eq. 8 for the parameters after each sample. Where theta is not an ellipse (early on,
      before the samples span enough of the circle, or after a windup), the literal method
      takes square roots of negative numbers and produces NaN; here the last valid
      parameters are kept instead (the initial guess until the first valid one).
    - Eq. 9 correction of the sample with the parameters in force after its own update.
    - Table 2 with the LINEAR index (Eq. 11, `linear_index`): N rows per octant.
    - Table 1: rows cos(n a_i), sin(n a_i), a_i = i pi / (4N), 8N rows per period.
    - Eq. 12: pulses A, B from cos_n, sin_n with hysteresis eps.
    - x4 decoder of A/B (`decode_x4`): +-1 per single edge; when A and B change in the same
      sample nothing is counted and `illegal` is incremented: this is how the pulse counter
      loses counts once the n-th order moves more than a quarter period per sample (Eq. 13).

    Returns dict(count=int64 per sample (up for increasing angle), illegal=number of steps
    where both pulses changed at once, invalid=number of samples whose theta was not an
    ellipse, params=(n, 5) parameters in force (A1, R, m1, m2, phi)).
    The RLS is a Python loop (~4 us per sample); everything after it is vectorised."""
    u1, u2 = _signals(u1, u2)
    interp = _positive_int(interp, "interp")
    N = _positive_int(N, "N")
    if not 0.0 < lam <= 1.0:
        raise ValueError(f"lam must be in (0, 1] (got {lam!r})")
    if not kappa > 0:
        raise ValueError(f"kappa must be positive (got {kappa!r})")
    if reset_every is not None and reset_every != 0:
        reset_every = _positive_int(reset_every, "reset_every")
    if not eps >= 0:
        raise ValueError(f"eps must be >= 0 (got {eps!r})")

    theta = _rls_thetas(u1, u2, float(lam), float(kappa), reset_every)
    p, ok = extract_many(theta)
    n = len(u1)
    last = np.where(ok, np.arange(n), -1)
    np.maximum.accumulate(last, out=last)
    params = np.where((last >= 0)[:, None], p[np.maximum(last, 0)], np.array(_P0))
    with np.errstate(all="ignore"):
        c1, c2 = reference.correct(u1, u2, params.T)

    i = linear_index(c1, c2, N)
    # Table 1: one table of 8N sines serves every n, row i -> (n i) mod 8N
    sine = np.sin(2 * np.pi * np.arange(8 * N) / (8 * N))
    j = np.mod(interp * i, 8 * N)
    cos_n = sine[np.mod(j + 2 * N, 8 * N)]
    sin_n = sine[j]
    count, illegal = decode_x4(pulses(cos_n, eps), pulses(sin_n, eps))
    return dict(count=count, illegal=illegal, invalid=int(n - np.count_nonzero(ok)),
                params=params)
