"""Accuracy against ground truth and against the physical floor (METHOD.md)."""
import numpy as np


def floor_nm(a, sig, pitch_nm, interp):
    """Per-sample Cramer-Rao bound of the angle (noise plus ADC quantisation), as position,
    combined with the counter quantisation q = pitch / (4 n)."""
    lsb = 2.0 / (1 << sig.adc_bits)                 # full scale +-1
    var_u = (sig.noise * sig.A1) ** 2 + lsb ** 2 / 12
    den = sig.A1 ** 2 * np.sin(a) ** 2 + sig.A2 ** 2 * np.cos(a - sig.phi) ** 2
    noise_rms = pitch_nm / (2 * np.pi) * np.sqrt(np.mean(var_u / den))
    q = pitch_nm / (4 * interp)
    return float(np.sqrt(noise_rms ** 2 + q ** 2 / 12)), float(noise_rms), q


def position_error_nm(count, x_nm, interp, pitch_nm, settle):
    """Counter position minus truth after `settle` samples, with the arbitrary zero of the
    counter removed (the mean over the scored window)."""
    q = pitch_nm / (4 * interp)
    e = count[settle:] * q - (x_nm[settle:] - x_nm[0])
    return e - np.mean(e)


def summary(err_nm, floor, pitch_nm):
    """RMS, peak, ratio to the floor, and slips (samples off by more than pitch/8)."""
    rms = float(np.sqrt(np.mean(err_nm ** 2)))
    return dict(rms_nm=rms, peak_nm=float(np.max(np.abs(err_nm))), floor_nm=floor,
                ratio=rms / floor, slips=int(np.sum(np.abs(err_nm) > pitch_nm / 8)))


def score(count, x_nm, a, sig, pitch_nm, interp, start):
    """summary() of the counter against the truth from sample `start` on, against the floor
    of the same samples."""
    fl, noise, q = floor_nm(a[start:], sig, pitch_nm, interp)
    err = position_error_nm(count, x_nm, interp, pitch_nm, start)
    out = summary(err, fl, pitch_nm)
    out.update(floor_noise_nm=noise, q_nm=q)
    return out, err
