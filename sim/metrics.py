"""Accuracy against ground truth and against the physical floor (METHOD.md).

The floor of a record is what an ideal interpolator achieves on it: an unbiased angle with
the per-sample Cramer-Rao variance (siggen.angle_var: noise plus ADC quantisation), then
the same counter quantisation q = pitch / (4 n) as the gateware (count = floor(4 n a / 2
pi)), its mean over the record removed like ours. Where the positions spread over many
counts this is METHOD.md's sqrt(noise_rms^2 + q^2 / 12); at a standstill (or a speed that
is a whole number of counts per sample) the quantisation error is not uniform and the
exact expectation is used instead: with noise well below q, a dwell is off by its fixed
rounding error, for every interpolator.
"""
import numpy as np
from scipy.special import ndtr


def quantised_moments(z, s, span=7):
    """Mean and second moment of floor(z + s N(0, 1)) - z, per sample."""
    z = np.asarray(z, float)
    s = np.maximum(np.asarray(s, float), 1e-12)
    k0 = np.floor(z)
    m1 = np.zeros_like(z)
    m2 = np.zeros_like(z)
    kmax = int(np.ceil(span * float(np.max(s)))) + 1
    for j in range(-kmax, kmax + 1):
        k = k0 + j
        p = ndtr((k + 1 - z) / s) - ndtr((k - z) / s)
        m1 += p * (k - z)
        m2 += p * (k - z) ** 2
    return m1, m2


def floor_nm(var_a, pitch_nm, interp, a=None):
    """(floor, noise part, q) in nm from per-sample angle variances (rad^2); with the true
    angles `a` the exact quantised floor, else METHOD.md's formula."""
    var_a = np.asarray(var_a, float)
    noise_rms = pitch_nm / (2 * np.pi) * np.sqrt(np.mean(var_a))
    q = pitch_nm / (4 * interp)
    if a is None:
        return float(np.sqrt(noise_rms ** 2 + q ** 2 / 12)), float(noise_rms), q
    c = 2 * interp / np.pi                       # counts per rad
    m1, m2 = quantised_moments(np.asarray(a) * c, np.sqrt(var_a) * c)
    var = np.mean(m2) - np.mean(m1) ** 2
    return float(q * np.sqrt(var)), float(noise_rms), q


def position_error_nm(count, x_nm, interp, pitch_nm, keep):
    """Counter position minus truth on every sample, with the arbitrary zero of the
    counter removed (the mean over the samples `keep`, an index array or mask)."""
    q = pitch_nm / (4 * interp)
    e = np.asarray(count) * q - (np.asarray(x_nm) - x_nm[0])
    return e - np.mean(e[keep])


def summary(err_nm, floor, pitch_nm):
    """RMS, peak, ratio to the floor, and slips (samples off by more than pitch/8)."""
    rms = float(np.sqrt(np.mean(err_nm ** 2)))
    return dict(rms_nm=rms, peak_nm=float(np.max(np.abs(err_nm))), floor_nm=floor,
                ratio=rms / floor, slips=int(np.sum(np.abs(err_nm) > pitch_nm / 8)))


def score(count, x_nm, var_a, pitch_nm, interp, start, mask=None, a=None):
    """summary() of the counter against the truth from sample `start` on (and where `mask`
    is true, e.g. outside a dropout), against the floor of the same samples (the exact
    quantised floor if the true angles `a` are given). Returns the
    summary, the error of every sample (scored or not) and the mask of scored samples."""
    keep = np.zeros(len(x_nm), bool)
    keep[start:] = True
    if mask is not None:
        keep &= mask
    keep &= np.isfinite(var_a)
    if not keep.any():
        raise ValueError(f"score: no samples to score from sample {start} on")
    fl, noise, q = floor_nm(np.asarray(var_a)[keep], pitch_nm, interp,
                            None if a is None else np.asarray(a)[keep])
    err = position_error_nm(count, x_nm, interp, pitch_nm, keep)
    out = summary(err[keep], fl, pitch_nm)
    out.update(floor_noise_nm=noise, q_nm=q, scored_samples=int(keep.sum()))
    return out, err, keep


def convergence_samples(err_nm, floor, event, window=1000, bound=2.0, end=None):
    """Samples from sample `event` to the start of the first window after which every
    window of `window` samples up to `end` (default: the end of the record) has an RMS
    error within `bound` x floor. None if it never settles."""
    e = err_nm[event:end]
    nw = len(e) // window
    if nw == 0:
        return None
    rms = np.sqrt(np.mean(e[:nw * window].reshape(nw, window) ** 2, axis=1))
    bad = rms > bound * floor
    if not bad.any():
        return 0
    if bad[-1]:
        return None
    return (int(np.nonzero(bad)[0][-1]) + 1) * window


def convergence_periods(err_nm, x_nm, pitch_nm, floor, event, window=1000, bound=2.0,
                        end=None):
    """convergence_samples() as travel, in signal periods. None if it never settles."""
    k = convergence_samples(err_nm, floor, event, window, bound, end)
    if k is None:
        return None
    travel = np.sum(np.abs(np.diff(np.asarray(x_nm)[event:event + k + 1])))
    return float(travel / pitch_nm)
