"""Encoder signal generator with ground truth (METHOD.md signal model).

    u1 = A1 cos(a) + m1,   u2 = A2 sin(a - phi) + m2,   a = 2 pi x / pitch

plus white Gaussian noise (sigma as a fraction of full scale) and quantisation to signed
ADC codes (adc_bits, full scale = +-1, clipped at the rails). Everything is seeded.
"""
from dataclasses import dataclass, asdict

import numpy as np


@dataclass
class Signal:
    A1: float = 0.60       # amplitudes, fraction of ADC full scale
    A2: float = 0.54
    m1: float = 0.030      # offsets, fraction of full scale
    m2: float = -0.020
    phi: float = 0.08      # quadrature phase error, rad
    noise: float = 0.005   # white noise sigma per channel, fraction of A1
    adc_bits: int = 16


def constant_speed(n, fs, v, x0=0.0):
    return x0 + v * np.arange(n) / fs


def s_curve(n, fs, dist, t_move, t_start=0.0, x0=0.0):
    """Smooth point-to-point move of `dist` in `t_move` s (sinusoidal acceleration),
    starting at t_start; standstill before and after."""
    t = np.arange(n) / fs
    tau = np.clip((t - t_start) / t_move, 0.0, 1.0)
    return x0 + dist * (tau - np.sin(2 * np.pi * tau) / (2 * np.pi))


def encode(x, pitch, sig: Signal, seed=0):
    """Return (u1_code, u2_code, angle) for positions x (same unit as pitch)."""
    rng = np.random.default_rng(seed)
    a = 2 * np.pi * np.asarray(x) / pitch
    sigma = sig.noise * sig.A1
    u1 = sig.A1 * np.cos(a) + sig.m1 + sigma * rng.standard_normal(a.shape)
    u2 = sig.A2 * np.sin(a - sig.phi) + sig.m2 + sigma * rng.standard_normal(a.shape)
    full = 1 << (sig.adc_bits - 1)
    q1 = np.clip(np.round(u1 * full), -full, full - 1).astype(np.int64)
    q2 = np.clip(np.round(u2 * full), -full, full - 1).astype(np.int64)
    return q1, q2, a


def describe(sig: Signal) -> dict:
    return asdict(sig)
