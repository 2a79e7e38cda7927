#!/usr/bin/env python3
"""Reproduce the paper's experiments in simulation (Ulu et al. 2014).

    python3 scripts/reproduce.py [--build build/reproduce] [--jobs 2] [--quick]

  --build  output folder (PNG figures, reproduce.json, reproduce.md)
  --jobs   worker processes for the independent runs (default 2)
  --quick  shortened experiments (a few seconds; for the tests, numbers not comparable)

Every number comes from the bit-true model of the core (sim/model/finequad_core.py; the RTL is
proved equal to it by sim/tests/test_rtlsim.py and the cocotb suite) fed with the seeded
encoder signals of sim/siggen.py: 4 um signal period, 1 MS/s, 16-bit ADC, the
paper-like imperfections of siggen.Signal (A1 0.60, A2 0.54 of full scale, offsets
3 % / -2 %, phase error 0.08 rad) and 0.5 % white noise unless a noise level is named.

Two designs run every experiment:
  default        the gateware as built (exact table, fine-phase counter)
  paper-literal  the gateware set as the paper prints the method: TABLE=paper (the linear
                 octant index of Table 2 / Eq. 11), CTRL count mode 1 (the x4 count of
                 the Eq. 12 pulses, eps = 0.05); the estimator is the gateware's
Fig. 11 also scores `sim/baselines.py paper_literal`, the whole method as printed in
float (RLS on every sample with forgetting and periodic resets).

Figures (build/reproduce/):
  fig02_measured.png     measured signals with their imperfections (time, Lissajous)
  fig03_parameters.png   A1, R, m1, m2, phi along a 120 mm travel with slow drifts and
                         three sudden changes: truth, the core's coefficient bundle (the
                         RTL's registers), the printed method in float
  fig04_corrected.png    corrected against measured signals
  fig05_interp_n25.png, fig09_interp_n50.png, fig10_interp_n100.png
                         corrected signals with the n-th order sinusoids, and the n-th
                         order phase error of both tables
  fig06_index.png        table index over one period (paper's table and exact)
  fig07_pulses.png       Eq. 12 pulses, n = 25, eps = 0.05
  fig11_validation.png   encoder against a 3 nm-resolution reference, n = 100 and 50
  fig12_tracking.png     closed-loop tracking of a 7 um S-curve (sim/closedloop.py)
  limits_speed.png       highest n against speed: Eq. 13 (edge counter), A/B outputs,
                         fine-phase counter, with measured points
  limits_noise.png       RMS error against n at several noise levels, both designs
reproduce.json holds every number (tracking_rms_nm_without / _with: default design);
reproduce.md the table beside the paper's numbers. Exit 1 if interpolation does not
cut the RMS tracking error of the default design by at least 2x.
"""
import argparse
import json
import os
import pathlib
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "scripts"))
from sim import baselines, closedloop, metrics, siggen  # noqa: E402
from sim.model import finequad_core as core  # noqa: E402
import limits  # noqa: E402

PITCH = 4000.0            # nm
FS = 1e6                  # samples/s
BITS = 16
FULL = 1 << (BITS - 1)
NOISE_STD = 0.005         # the suite's paper-like noise (siggen.Signal default)
VIB_RES = 3.0             # nm, the paper's vibrometer
DESIGNS = {"default": {}, "paper-literal": dict(TABLE="paper", count_mode=1)}
# Fig. 12's plant is our assumption (the paper gives none): the same run with other
# guides and gains shows how much of the improvement is the plant's
PLANTS = {"Coulomb friction 0.3 N": dict(coulomb_N=0.3),
          "Coulomb friction 3 N": dict(coulomb_N=3.0),
          "bandwidth 20 Hz": dict(bandwidth_hz=20.0),
          "bandwidth 100 Hz": dict(bandwidth_hz=100.0)}
PAPER = {"fig11_n50_rms_nm": 8.3, "fig11_n100_rms_nm": 7.2,
         "tracking_rms_nm_without": 312.14, "tracking_rms_nm_with": 121.53,
         "tracking_improvement": 312.14 / 121.53}


def cfg_for(design, interp, **kw):
    if design not in DESIGNS:
        raise ValueError(f"unknown design {design!r}; known: {', '.join(DESIGNS)}")
    return core.Config(interp=interp, **DESIGNS[design], **kw)


def homing_then(plan, x0=1e6):
    """Positions (nm): a 40 um jerk-limited homing move at 2 mm/s (the estimator
    calibrates on it), 5 ms at rest, then `plan` (siggen.moves steps). Returns (x, index
    of the first sample after the homing)."""
    home = siggen.moves(FS, [("move", 40_000.0, 2e6, 1e9, 1e11), ("dwell", 0.005)], x0=x0)
    rest = siggen.moves(FS, plan, x0=home[-1])
    return np.concatenate([home, rest]), len(home)


# ============================================================================ experiments
# Each task is a top-level function (run in a worker process) returning plain data.

def task_signals(quick):
    """Figs. 2, 4, 5, 6, 7, 9, 10: 2 mm/s (2000 samples per signal period), traced."""
    n_samples = 24_000 if quick else 40_000
    x = siggen.constant_speed(n_samples, FS, 2e6, x0=1e6)
    sig = siggen.Signal()
    u1, u2, a = siggen.encode(x, PITCH, sig, seed=21)
    w = slice(n_samples - 4000, n_samples)          # two periods, long after calibration
    out = dict(x=x[w], a=a[w], u1=u1[w] / FULL, u2=u2[w] / FULL,
               sig=siggen.describe(sig))
    for table in ("exact", "paper"):
        for n in (25, 50, 100):
            r = core.run(u1, u2, core.Config(TABLE=table, interp=n), trace=True)
            d = {k: np.asarray(r[k])[w] for k in ("u1c", "u2c", "phase", "j", "pn",
                                                   "cosn", "sinn", "pa", "pb", "g", "m1",
                                                   "m2", "c1", "c12", "c2")}
            out[f"{table}_{n}"] = d
    return out


def fig3_truth(x):
    """The signal parameters along the travel x (nm): slow drifts and three sudden
    changes (a scale joint at 40 mm, dirt at 70 mm, a readhead knock at 95 mm)."""
    mm = (x - x[0]) / 1e6
    L = max(float(mm[-1]), 1e-9)
    s = mm / L                                       # 0..1 along the travel
    A1 = 0.60 + 0.04 * np.sin(2 * np.pi * s * 1.5) - 0.06 * (s > 70 / 120)
    A2 = 0.54 + 0.03 * np.cos(2 * np.pi * s * 2.4)
    m1 = 0.03 - 0.02 * s + 0.03 * (s > 40 / 120)
    m2 = -0.02 + 0.01 * np.sin(2 * np.pi * s * 2)
    phi = 0.08 + 0.04 * s + 0.05 * (s > 95 / 120)
    return dict(A1=A1, A2=A2, m1=m1, m2=m2, phi=phi)


def bundle_params(r):
    """(A1, R, m1, m2, phi) in full-scale units from the coefficient bundle in use
    (rtl/README.md Q formats: c s4.12 and m s1.15 in units normalised by the input gain 2^g;
    c1 = 1/A1, c12 = sin(phi) / (A1 cos phi), c2 = R / (A1 cos phi))."""
    g = 2.0 ** np.asarray(r["g"], float)
    c1 = np.asarray(r["c1"], float) / 4096
    c12 = np.asarray(r["c12"], float) / 4096
    c2 = np.asarray(r["c2"], float) / 4096
    phi = np.arctan2(c12, c1)
    return dict(A1=1 / c1 / g, R=c2 * np.cos(phi) / c1, m1=np.asarray(r["m1"]) / FULL / g,
                m2=np.asarray(r["m2"]) / FULL / g, phi=phi)


def task_params(quick):
    """Fig. 3: a 120 mm jerk-limited travel at 200 mm/s (50 kHz signal)."""
    travel = 12e6 if quick else 120e6
    x = 1e6 + siggen.jerk_limited(travel, 200e6, 2e9, 1e11, FS)
    tr = fig3_truth(x)
    sig = siggen.Signal(A1=tr["A1"], A2=tr["A2"], m1=tr["m1"], m2=tr["m2"], phi=tr["phi"])
    u1, u2, a = siggen.encode(x, PITCH, sig, seed=31)
    r = core.run(u1, u2, core.Config(), trace=True)
    est = bundle_params(r)
    uncal = (r["fault"] >> core.FAULT_BITS["uncal"]) & 1
    lit = baselines.paper_literal(u1 / FULL, u2 / FULL, 100)["params"]
    var_a = siggen.angle_var(a, sig)
    cal = np.nonzero(uncal == 0)[0]
    s, err, _ = metrics.score(r["count"], x, var_a, PITCH, 100, int(cal[0]) + 2000, a=a)
    dec = max(1, len(x) // 4000)
    true = dict(tr, R=tr["A1"] / tr["A2"])
    keys = ("A1", "R", "m1", "m2", "phi")
    # RMS of estimate - truth where calibrated (after the first commit)
    k = uncal == 0
    rms = {p: float(np.sqrt(np.mean((est[p][k] - true[p][k]) ** 2))) for p in keys}
    return dict(x_mm=(x[::dec] - x[0]) / 1e6,
                true={p: true[p][::dec] for p in keys},
                est={p: np.where(uncal[::dec] == 0, est[p][::dec], np.nan) for p in keys},
                lit={p: lit[::dec, i] for i, p in enumerate(keys)},
                jumps_mm=[float((x[j] - x[0]) / 1e6) for j in r["jumps"]],
                est_rms=rms, count=s, samples=len(x), travel_mm=travel / 1e6,
                updates=int(r["n_updates"]))


def validation_record(noise, quick):
    """Fig. 11: homing, then +10 um and back in jerk-limited S-curves with dwells."""
    mv = ("move", 10_000.0, 4e5, 2e7, 2e9)
    plan = [mv, ("dwell", 0.02), ("move", -10_000.0, 4e5, 2e7, 2e9), ("dwell", 0.02)]
    if quick:
        plan = [mv, ("dwell", 0.005)]
    x, k0 = homing_then(plan)
    sig = siggen.Signal(noise=noise)
    u1, u2, a = siggen.encode(x, PITCH, sig, seed=41)
    return x, k0, sig, u1, u2, a


def task_validation(noise, interp, design, quick):
    """Fig. 11: RMS of (encoder - reference), the reference being the true position
    quantised to 3 nm, over the motion after the homing (means removed: both measure
    displacement from an arbitrary zero). design 'printed' is baselines.paper_literal."""
    x, k0, sig, u1, u2, a = validation_record(noise, quick)
    if design == "printed":
        count = baselines.paper_literal(u1 / FULL, u2 / FULL, interp)["count"]
        illegal = None
    else:
        r = core.run(u1, u2, cfg_for(design, interp))
        count, illegal = r["count"], int(r["illegal_count"])
    q = PITCH / (4 * interp)
    enc = count[k0:] * q
    vib = VIB_RES * np.round(x[k0:] / VIB_RES)
    d = (enc - vib) - np.mean(enc - vib)
    var_a = siggen.angle_var(a, sig)
    fl = metrics.floor_nm(var_a[k0:], PITCH, interp, a[k0:])[0]
    dec = 20
    return dict(noise=noise, interp=interp, design=design,
                rms_nm=float(np.sqrt(np.mean(d ** 2))), peak_nm=float(np.max(np.abs(d))),
                floor_nm=fl, floor_vs_ref_nm=float(np.hypot(fl, VIB_RES / np.sqrt(12))),
                illegal_steps=illegal, t=np.arange(len(d))[::dec] / FS,
                enc=(enc - np.mean(enc - vib))[::dec] - vib[0], vib=vib[::dec] - vib[0],
                diff=d[::dec])


def task_track(noise, interp, design, stratum, strata, quick, plant=None):
    """Fig. 12: one closed-loop run. The start position is the stratum's point inside
    a 1 um count cell of the plain x4 count (strata spread over the cell). plant: a
    PLANTS entry (slider fields and/or bandwidth_hz) instead of the default plant."""
    plant = dict(plant or {})
    bw = plant.pop("bandwidth_hz", closedloop.Experiment.bandwidth_hz)
    exp = closedloop.Experiment(sig=siggen.Signal(noise=noise),
                                slider=closedloop.Slider(**plant), bandwidth_hz=bw,
                                start_nm=1e6 + (stratum + 0.5) / strata * PITCH / 4,
                                seed=51 + stratum)
    if quick:
        exp = replace(exp, t_before=0.01, t_move=0.06, t_after=0.03)
    r = closedloop.run(exp, interp, cfg_for(design, interp))
    r.pop("x_nm")
    r.update(noise=noise, interp=interp, design=design, stratum=stratum)
    return r


def noise_record(noise, quick):
    """Limitations: homing, then 0.5 mm/s (8000 samples per period) for 30 ms."""
    x, k0 = homing_then([("dwell", 0.0)])
    n_run = 10_000 if quick else 30_000
    x = np.concatenate([x, x[-1] + 5e5 * np.arange(1, n_run + 1) / FS])
    sig = siggen.Signal(noise=noise)
    u1, u2, a = siggen.encode(x, PITCH, sig, seed=61)
    return x, k0, sig, u1, u2, a


def task_noise(noise, design, interps, quick):
    """RMS error against the truth for each n on one recording (one core run per n)."""
    x, k0, sig, u1, u2, a = noise_record(noise, quick)
    var_a = siggen.angle_var(a, sig)
    rows = []
    for n in interps:
        r = core.run(u1, u2, cfg_for(design, n))
        s, _, _ = metrics.score(r["count"], x, var_a, PITCH, n, k0, a=a)
        rows.append(dict(interp=n, rms_nm=s["rms_nm"], floor_nm=s["floor_nm"],
                         slips=s["slips"], illegal_steps=int(r["illegal_count"])))
    return dict(noise=noise, design=design, rows=rows)


def _speed_ok(kind, v, n, samples=20_000, noise=0.0005):
    """Does the core keep up at speed v (m/s) with factor n? kind: 'edge' (paper-literal
    x4 pulse counter: count increment over the second half against the truth), 'ab'
    (default design: A/B backlog overflow flag, fault bit 6, in the second half),
    'phase' (default design, fine-phase counter: count increment)."""
    x = siggen.constant_speed(samples, FS, v * 1e9, x0=1e6)
    u1, u2, _ = siggen.encode(x, PITCH, siggen.Signal(noise=noise), seed=71)
    cfg = cfg_for("paper-literal" if kind == "edge" else "default", n)
    r = core.run(u1, u2, cfg)
    h = samples // 2
    if kind == "ab":
        return not np.any((r["fault"][h:] >> core.FAULT_BITS["abovf"]) & 1)
    q = PITCH / (4 * n)
    err = (r["count"][-1] - r["count"][h]) * q - (x[-1] - x[h])
    return abs(err) <= max(2 * q, 40.0)


def task_speed(kind, v, quick):
    """Highest n in 1..INTERP's largest that keeps up at speed v (bisection; for 'phase' the result is
    just pass/fail at n = 100)."""
    samples = 8000 if quick else 20_000
    if kind == "phase":
        return dict(kind=kind, v=v, interp=100, ok=bool(_speed_ok(kind, v, 100, samples)))
    lo, hi = 0, limits.N_MAX            # lo passes (0: none yet), hi + 1 fails
    if _speed_ok(kind, v, hi, samples):
        return dict(kind=kind, v=v, n_max=hi, capped=True)
    hi -= 1
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if _speed_ok(kind, v, mid, samples):
            lo = mid
        else:
            hi = mid - 1
    return dict(kind=kind, v=v, n_max=lo, capped=False)


# ============================================================================ figures

def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({"figure.dpi": 110, "axes.grid": True, "grid.alpha": 0.3,
                         "font.size": 9})
    return plt


def fig02(d, path):
    plt = _plt()
    sig = d["sig"]
    pos = (d["x"] - d["x"][0]) / 1e3
    fig, ax = plt.subplots(1, 2, figsize=(11, 4), gridspec_kw=dict(width_ratios=[1.8, 1]))
    ax[0].plot(pos, d["u1"], lw=1, label="u1 measured")
    ax[0].plot(pos, d["u2"], lw=1, label="u2 measured")
    A = sig["A1"]
    ax[0].plot(pos, A * np.cos(d["a"]), "k--", lw=0.7, label="ideal A cos(a), A sin(a)")
    ax[0].plot(pos, A * np.sin(d["a"]), "k--", lw=0.7)
    ax[0].set_xlabel("position (um)")
    ax[0].set_ylabel("signal (fraction of ADC full scale)")
    ax[0].legend(loc="upper right", fontsize=7)
    ax[1].plot(d["u1"], d["u2"], ".", ms=1, label="measured")
    t = np.linspace(0, 2 * np.pi, 200)
    ax[1].plot(A * np.cos(t), A * np.sin(t), "k--", lw=0.7, label="ideal")
    ax[1].set_aspect("equal")
    ax[1].set_xlabel("u1 (full scale)")
    ax[1].set_ylabel("u2 (full scale)")
    ax[1].legend(loc="upper right", fontsize=7)
    fig.suptitle(f"Fig. 2: measured encoder signals with imperfections (A1 {sig['A1']}, "
                 f"A2 {sig['A2']}, m1 {sig['m1']}, m2 {sig['m2']}, phi {sig['phi']} rad, "
                 f"noise {sig['noise'] * 100:g} %; 4 um pitch, 1 MS/s)")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def fig04(d, path):
    plt = _plt()
    e = d["exact_100"]
    pos = (d["x"] - d["x"][0]) / 1e3
    c1, c2 = e["u1c"] / 16384, e["u2c"] / 16384
    A1 = d["sig"]["A1"]
    m1, m2 = d["sig"]["m1"], d["sig"]["m2"]
    fig, ax = plt.subplots(1, 2, figsize=(11, 4), gridspec_kw=dict(width_ratios=[1.8, 1]))
    ax[0].plot(pos, (d["u1"] - m1) / A1, lw=0.7, alpha=0.6, label="measured u1 (- m1, / A1)")
    ax[0].plot(pos, (d["u2"] - m2) / A1, lw=0.7, alpha=0.6, label="measured u2 (- m2, / A1)")
    ax[0].plot(pos, c1, lw=1, label="corrected u1c (core, Eq. 9)")
    ax[0].plot(pos, c2, lw=1, label="corrected u2c (core, Eq. 9)")
    ax[0].set_xlabel("position (um)")
    ax[0].set_ylabel("signal (unit circle = 1)")
    ax[0].legend(loc="upper right", fontsize=7)
    rad_m = np.hypot((d["u1"] - m1) / A1, (d["u2"] - m2) / A1)
    rad_c = np.hypot(c1, c2)
    ax[1].plot((d["u1"] - m1) / A1, (d["u2"] - m2) / A1, ".", ms=1,
               label=f"measured: radius {rad_m.min():.2f}..{rad_m.max():.2f}")
    ax[1].plot(c1, c2, ".", ms=1, label=f"corrected: radius {rad_c.min():.2f}..{rad_c.max():.2f}")
    ax[1].set_aspect("equal")
    ax[1].set_xlabel("u1")
    ax[1].set_ylabel("u2")
    ax[1].legend(loc="lower left", fontsize=7, markerscale=8)
    fig.suptitle("Fig. 4: corrected and measured encoder signals (bit-true core, after "
                 "calibration)")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def _phase_err_nm(d, table, n):
    """Fine-phase error (nm) against the true angle, mean removed. The n-th order phase
    is n times the fine phase (mod one period), so this error reaches the n-th order
    sinusoids and the count unchanged in nm, i.e. n times larger in n-th order degrees."""
    ph = d[f"{table}_{n}"]["phase"] * 2 * np.pi / 8192
    e = np.angle(np.exp(1j * (ph - d["a"])))
    e -= np.angle(np.mean(np.exp(1j * e)))
    return e / (2 * np.pi) * PITCH


def fig_interp(d, n, figno, path):
    plt = _plt()
    e = d[f"exact_{n}"]
    pos = (d["x"] - d["x"][0]) / 1e3
    # 12.5 periods of the n-th order sinusoid at every n (half a signal period at n = 25,
    # an eighth at n = 100), so that its samples stay visible
    span = 25000 // n
    k = slice(0, span)
    sc = 1 << 9                                            # SIN_W = 10: sign + u0.9
    q = PITCH / (4 * n)
    fig, ax = plt.subplots(2, 1, figsize=(11, 6), sharex=True,
                           gridspec_kw=dict(height_ratios=[1.6, 1]))
    ax[0].plot(pos[k], e["cosn"][k] / sc, lw=0.6, label=f"u1n = cos({n} a) (table)")
    ax[0].plot(pos[k], e["sinn"][k] / sc, lw=0.6, label=f"u2n = sin({n} a) (table)")
    ax[0].plot(pos[k], e["u1c"][k] / 16384, "k", lw=1.2, label="corrected u1c")
    ax[0].plot(pos[k], e["u2c"][k] / 16384, "k--", lw=1.2, label="corrected u2c")
    ax[0].set_ylabel("signal (unit amplitude)")
    ax[0].legend(loc="upper right", fontsize=7, ncol=2)
    for table, lab in (("paper", "paper's table (linear index)"), ("exact", "exact table")):
        err = _phase_err_nm(d, table, n) / q
        rms = np.sqrt(np.mean(err ** 2))
        ax[1].plot(pos[k], err[k], lw=0.6,
                   label=f"{lab}: RMS {rms:.2f} counts = {rms * q:.1f} nm = "
                         f"{rms / 4 * 360:.0f} deg of {n} a")
    ax[1].set_ylabel(f"phase error (counts of {q:g} nm)")
    ax[1].set_xlabel("position (um)")
    ax[1].legend(loc="upper right", fontsize=7)
    fig.suptitle(f"Fig. {figno}: interpolation for n = {n} ({span / 2000:g} of a signal "
                 f"period, 0.5 % noise; resolution pitch / 4n = {q:g} nm)")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def fig06(d, path):
    plt = _plt()
    pos = (d["x"] - d["x"][0]) / 1e3
    k = slice(0, 2000)
    true_idx = np.mod(d["a"], 2 * np.pi) / (2 * np.pi) * 8192
    fig, ax = plt.subplots(2, 1, figsize=(11, 6), sharex=True,
                           gridspec_kw=dict(height_ratios=[1.6, 1]))
    p, e = d["paper_25"], d["exact_25"]
    ax[0].plot(pos[k], p["phase"][k], lw=1, label="index, paper's table (0..8N, N = 1024)")
    ax[0].plot(pos[k], e["phase"][k], lw=1, ls="--", label="index, exact table")
    ax[0].plot(pos[k], e["u1c"][k] / 16384 * 8192, lw=0.8, label="corrected u1c x 8192")
    ax[0].plot(pos[k], e["u2c"][k] / 16384 * 8192, lw=0.8, label="corrected u2c x 8192")
    ax[0].set_ylabel("index / scaled signal")
    ax[0].legend(loc="lower right", fontsize=7)
    for lab, ph in (("paper's table", p["phase"]), ("exact table", e["phase"])):
        err = np.mod(ph - true_idx + 4096, 8192) - 4096
        err = err - np.mean(err)
        ax[1].plot(pos[k], err[k], lw=0.7,
                   label=f"{lab}: peak {np.max(np.abs(err)):.0f} rows "
                         f"({np.max(np.abs(err)) / 8192 * PITCH:.0f} nm)")
    ax[1].set_ylabel("index - true angle (rows)")
    ax[1].set_xlabel("position (um)")
    ax[1].legend(loc="upper right", fontsize=7)
    fig.suptitle("Fig. 6: table index over one signal period, n = 25 (the core's fine "
                 "phase, 8192 rows per period)")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def fig07(d, path):
    plt = _plt()
    e = d["exact_25"]
    pos = (d["x"] - d["x"][0]) / 1e3
    k = slice(0, 500)                                  # a quarter period: 6 n-th periods
    sc = 1 << 9
    fig, ax = plt.subplots(figsize=(11, 4))
    ax.plot(pos[k], e["cosn"][k] / sc, lw=0.6, color="C0", label="u1n = cos(25 a)")
    ax.plot(pos[k], e["sinn"][k] / sc, lw=0.6, color="C1", label="u2n = sin(25 a)")
    ax.step(pos[k], 0.4 * e["pa"][k], where="post", lw=1.4, color="C0", label="A x 0.4")
    ax.step(pos[k], 0.6 * e["pb"][k], where="post", lw=1.4, color="C1", label="B x 0.6")
    ax.plot(pos[k], e["u1c"][k] / 16384, "k", lw=1, label="corrected u1c")
    ax.plot(pos[k], e["u2c"][k] / 16384, "k--", lw=1, label="corrected u2c")
    for s in (0.05, -0.05):
        ax.axhline(s, color="gray", lw=0.5, ls=":")
    ax.set_xlabel("position (um)")
    ax.set_ylabel("signal / pulse")
    ax.legend(loc="upper right", fontsize=7, ncol=3)
    ax.set_title("Fig. 7: binary pulses A, B (Eq. 12) for n = 25, eps = 0.05 (dotted)")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def fig03(p, path):
    plt = _plt()
    labels = {"A1": "A1 (full scale)", "R": "R = A1/A2", "m1": "m1 (full scale)",
              "m2": "m2 (full scale)", "phi": "phi (rad)"}
    fig, ax = plt.subplots(5, 1, figsize=(11, 10), sharex=True)
    for i, k in enumerate(labels):
        ax[i].plot(p["x_mm"], p["lit"][k], lw=0.5, color="C2", alpha=0.6,
                   label="paper as printed (float RLS, every sample, resets)")
        ax[i].plot(p["x_mm"], p["est"][k], lw=1.2, color="C0",
                   label="core's coefficient bundle (RTL registers)")
        ax[i].plot(p["x_mm"], p["true"][k], "k--", lw=1, label="true")
        lo, hi = np.nanmin(p["true"][k]), np.nanmax(p["true"][k])
        pad = max(0.5 * (hi - lo), 0.01)
        ax[i].set_ylim(lo - pad, hi + pad)
        ax[i].set_ylabel(labels[k])
        for j in p["jumps_mm"]:
            ax[i].axvline(j, color="r", lw=0.5, ls=":")
    ax[0].legend(loc="upper right", fontsize=7, ncol=3)
    ax[-1].set_xlabel("position along the travel (mm)")
    fig.suptitle(f"Fig. 3: encoder signal parameters along a {p['travel_mm']:g} mm travel "
                 f"(200 mm/s); red dotted: jumps detected by the core")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def fig11(vals, path):
    plt = _plt()
    fig, ax = plt.subplots(2, 2, figsize=(11, 6), sharex=True,
                           gridspec_kw=dict(height_ratios=[1.6, 1]))
    for col, n in enumerate((100, 50)):
        v = vals[n]
        ax[0, col].plot(v["t"] * 1e3, v["vib"] / 1e3, "k", lw=1.5,
                        label="reference (3 nm resolution)")
        ax[0, col].plot(v["t"] * 1e3, v["enc"] / 1e3, "C1--", lw=1,
                        label=f"encoder, n = {n} (default design)")
        ax[0, col].set_ylabel("displacement (um)")
        ax[0, col].legend(loc="upper right", fontsize=7)
        ax[0, col].set_title(f"({'a' if n == 100 else 'b'}) n = {n}: resolution "
                             f"{PITCH / (4 * n):g} nm")
        ax[1, col].plot(v["t"] * 1e3, v["diff"], lw=0.5,
                        label=f"RMS {v['rms_nm']:.2f} nm (paper: "
                              f"{PAPER['fig11_n100_rms_nm' if n == 100 else 'fig11_n50_rms_nm']} nm)")
        ax[1, col].set_ylabel("encoder - reference (nm)")
        ax[1, col].set_xlabel("time (ms)")
        ax[1, col].legend(loc="upper right", fontsize=7)
    fig.suptitle("Fig. 11: validation against a 3 nm-resolution reference (0.5 % noise)")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def fig12(runs, summary, path):
    """runs: {(design, interp): run dict} of one stratum (the one plotted)."""
    plt = _plt()
    fig, ax = plt.subplots(3, 1, figsize=(11, 9), sharex=True,
                           gridspec_kw=dict(height_ratios=[1.4, 1, 0.8]))
    d0 = runs[("default", 1)]
    ax[0].plot(d0["t"], (d0["ref_nm"] - d0["ref_nm"][0]) / 1e3, "k", lw=1.5,
               label="reference (7 um S-curve)")
    style = {("default", 1): ("C3", "-", "without interpolation (x4, 1 um)"),
             ("default", 100): ("C0", "-", "with interpolation (n = 100, 10 nm)"),
             ("paper-literal", 100): ("C2", ":", "paper-literal design, n = 100")}
    for key, (c, ls, lab) in style.items():
        r = runs[key]
        if key[0] == "paper-literal":
            lab += f" ({r['illegal_steps']} illegal A/B steps: counts lost)"
        ax[0].plot(r["t"], (r["true_nm"] - r["ref_nm"][0]) / 1e3, color=c, ls=ls, lw=1,
                   label=lab + " (true position)")
        ax[1].plot(r["t"], r["err_true_nm"], color=c, ls=ls, lw=1,
                   label=f"{lab}: RMS {r['rms_true_nm']:.0f} nm (this run)")
        ax[2].plot(r["t"], r["force_N"], color=c, ls=ls, lw=0.5)
    ax[0].set_ylabel("position (um)")
    ax[0].legend(loc="lower right", fontsize=7)
    ax[1].set_ylabel("tracking error r - x (nm, clipped)")
    ax[1].legend(loc="upper right", fontsize=7)
    ax[1].set_ylim(-1500, 1500)
    ax[2].set_ylabel("motor force (N)")
    ax[2].set_xlabel("time (s)")
    fig.suptitle("Fig. 12: closed-loop tracking, PID at 10 kHz, 0.5 % noise; over "
                 f"{summary['strata']} start positions: without {summary['without']:.1f} nm, "
                 f"with {summary['with']:.1f} nm RMS ({summary['ratio']:.2f}x; paper "
                 "312.14 / 121.53 nm, 2.57x)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def fig_limits_speed(speed, path):
    plt = _plt()
    v = np.logspace(-4, np.log10(2.5), 300)
    L = limits.limits(PITCH / 1e3, FS, v=v)
    fig, ax = plt.subplots(figsize=(9, 5.5))
    ax.loglog(v, L["edge_counter_n_max"], "C2", label="x4 edge counter (paper): Eq. 13, "
              "N_n = 4, t_lp = 1 us")
    sep = limits.SETTINGS["ab_sep"].reset
    ax.loglog(v, L["ab_n_max"], "C1", label=f"A/B outputs: {sep} clocks per edge at 36 MHz "
              "(ABGEN.ab_sep's reset)")
    vc = L["counter_v_max"]
    nmax = limits.N_MAX
    ax.plot([v[0], vc, vc], [nmax, nmax, 0.5], "C0", lw=2,
            label=f"fine-phase counter: any n (1..{nmax}) below {vc:g} m/s (3/8 pitch fs)")
    ax.axvline(L["nyquist_v"], color="C0", ls=":", lw=1, label="Nyquist (pitch fs / 2)")
    for kind, c, m, lab in (("edge", "C2", "o", "measured: edge counter (paper-literal)"),
                            ("ab", "C1", "s", "measured: A/B outputs (no backlog overflow)")):
        pts = [s for s in speed if s["kind"] == kind]
        if pts:
            ax.plot([s["v"] for s in pts], [s["n_max"] for s in pts], m, color=c, ms=7,
                    mfc="none", mew=1.5, label=lab)
    ph = [s for s in speed if s["kind"] == "phase"]
    for s in ph:
        ax.plot(s["v"], 100, "o" if s["ok"] else "x", color="C0", ms=7,
                mfc="none" if s["ok"] else None, mew=1.5)
    if ph:
        ax.plot([], [], "o", color="C0", mfc="none", label="measured: fine-phase counter "
                "at n = 100 keeps count (o) / loses it (x)")
        ax.plot([], [], "x", color="C0")
    ax.set_ylim(0.8, 2000)
    ax.set_xlabel("speed (m/s)")
    ax.set_ylabel("highest interpolation factor n")
    ax.set_title("Limitations (Sec. 4): highest n against speed, 4 um pitch, 1 MS/s")
    ax.legend(loc="lower left", fontsize=7)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def fig_limits_noise(noise_rows, path):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(9, 5.5))
    levels = sorted({r["noise"] for r in noise_rows})
    for i, lev in enumerate(levels):
        for r in noise_rows:
            if r["noise"] != lev:
                continue
            n = [x["interp"] for x in r["rows"]]
            e = [x["rms_nm"] for x in r["rows"]]
            if r["design"] == "default":
                ax.loglog(n, e, "-o", color=f"C{i}", ms=3, label=f"noise {lev * 100:g} %: default")
                ax.loglog(n, [x["floor_nm"] for x in r["rows"]], ":", color=f"C{i}", lw=1)
            else:
                ax.loglog(n, e, "--x", color=f"C{i}", ms=4, label=f"noise {lev * 100:g} %: paper-literal")
    ax.plot([], [], "k:", label="floor (METHOD.md); the default design lies on it")
    ax.set_xlabel("interpolation factor n")
    ax.set_ylabel("RMS position error (nm)")
    ax.set_title("Limitations (Sec. 4): error against n at several noise levels "
                 "(0.5 mm/s, 4 um pitch, 1 MS/s)")
    ax.legend(loc="lower left", fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


# ============================================================================ report

def fmt(v, nd=2):
    return "-" if v is None else f"{v:.{nd}f}"


def markdown(res):
    v, t = res["validation"], res["tracking"]
    lines = ["| quantity | paper | paper-literal design | default design |",
             "|---|---:|---:|---:|"]
    for n, key in ((50, "fig11_n50_rms_nm"), (100, "fig11_n100_rms_nm")):
        for noise in res["noise_levels_validation"]:
            row = v[f"{noise}"][f"{n}"]
            lines.append(f"| Fig. 11 n = {n}: RMS vs 3 nm reference, noise {noise * 100:g} % "
                         f"(floor {row['default']['floor_vs_ref_nm']:.1f} nm) | "
                         f"{PAPER[key]} | {fmt(row['paper-literal']['rms_nm'])}"
                         f" (as printed, float: {fmt(row['printed']['rms_nm'])}) | "
                         f"{fmt(row['default']['rms_nm'])} |")
    for noise in res["noise_levels_tracking"]:
        tt = t[f"{noise}"]
        for lab, key, pk in (("without interpolation (x4, 1 um)", "without",
                              "tracking_rms_nm_without"),
                             ("with interpolation (n = 100, 10 nm)", "with",
                              "tracking_rms_nm_with")):
            lines.append(f"| Fig. 12 RMS tracking error {lab}, noise {noise * 100:g} % | "
                         f"{PAPER[pk]} | {fmt(tt['paper-literal'][key])} | "
                         f"{fmt(tt['default'][key])} |")
        lines.append(f"| Fig. 12 improvement (without / with), noise {noise * 100:g} % | "
                     f"{PAPER['tracking_improvement']:.2f}x | "
                     f"{fmt(tt['paper-literal']['ratio'])}x | {fmt(tt['default']['ratio'])}x |")
    std = t[f"{res['noise_std']}"]["default"]
    lines += ["", "Fig. 12 with other plants (default design, noise "
              f"{res['noise_std'] * 100:g} %; the paper gives no plant, so the "
              "improvement is the plant's as much as the encoder's):", "",
              "| plant | without (x4, 1 um) | with (n = 100) | improvement |",
              "|---|---:|---:|---:|",
              f"| as assumed (1 N Coulomb friction, 50 Hz) | {fmt(std['without'])} | "
              f"{fmt(std['with'])} | {fmt(std['ratio'])}x |"]
    for name, r in res["plant_sensitivity"].items():
        lines.append(f"| {name} | {fmt(r['without'])} | {fmt(r['with'])} | "
                     f"{fmt(r['ratio'])}x |")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build" / "reproduce"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--quick", action="store_true",
                    help="shortened experiments (tests); numbers not comparable")
    a = ap.parse_args(argv)
    if a.jobs < 1:
        print(f"reproduce: error: --jobs must be >= 1, got {a.jobs}", file=sys.stderr)
        return 2
    out = pathlib.Path(a.build)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.time()
    quick = a.quick
    strata = 1 if quick else 3
    val_noise = [NOISE_STD] if quick else [NOISE_STD, 0.01]
    trk_noise = [NOISE_STD] if quick else [0.001, NOISE_STD]
    noise_levels = [0.001, 0.01] if quick else [0.001, 0.005, 0.01, 0.02]
    interps = [1, 10, 100] if quick else [1, 3, 10, 30, 100, 300]
    # speeds off simple fractions of fs: at exactly 4 or 8 samples per signal period the
    # samples repeat 4 or 8 points of the ellipse and no fit can calibrate
    speeds = ({"edge": [0.107], "ab": [0.53], "phase": [0.97]} if quick else
              {"edge": [0.0043, 0.021, 0.107, 0.53], "ab": [0.021, 0.107, 0.53],
               "phase": [0.97, 1.37, 1.61, 1.83, 1.97]})
    load0 = os.getloadavg()
    with ProcessPoolExecutor(max_workers=a.jobs) as ex:
        # longest first, so that the two workers finish together
        f_track = {(noise, n, des, s): ex.submit(task_track, noise, n, des, s, strata, quick)
                   for noise in trk_noise for des in DESIGNS for n in (1, 100)
                   for s in range(strata)}
        plants = dict(list(PLANTS.items())[:1]) if quick else PLANTS
        f_plant = {(name, n, s): ex.submit(task_track, NOISE_STD, n, "default", s, strata,
                                           quick, plant)
                   for name, plant in plants.items() for n in (1, 100)
                   for s in range(strata)}
        f_params = ex.submit(task_params, quick)
        f_noise = [ex.submit(task_noise, lev, des, interps, quick)
                   for lev in noise_levels for des in DESIGNS]
        f_val = {(noise, n, des): ex.submit(task_validation, noise, n, des, quick)
                 for noise in val_noise for n in (50, 100)
                 for des in ("default", "paper-literal", "printed")}
        f_speed = [ex.submit(task_speed, kind, v, quick) for kind, vs in speeds.items()
                   for v in vs]
        f_sig = ex.submit(task_signals, quick)
        sigd = f_sig.result()
        fig02(sigd, out / "fig02_measured.png")
        fig04(sigd, out / "fig04_corrected.png")
        for n, no in ((25, 5), (50, 9), (100, 10)):
            fig_interp(sigd, n, no, out / f"fig{no:02d}_interp_n{n}.png")
        fig06(sigd, out / "fig06_index.png")
        fig07(sigd, out / "fig07_pulses.png")
        interp_err = {tab: float(np.sqrt(np.mean(_phase_err_nm(sigd, tab, 100) ** 2)))
                      for tab in ("exact", "paper")}
        params = f_params.result()
        fig03(params, out / "fig03_parameters.png")
        val = {k: f.result() for k, f in f_val.items()}
        fig11({n: val[(NOISE_STD, n, "default")] for n in (50, 100)},
              out / "fig11_validation.png")
        track = {k: f.result() for k, f in f_track.items()}
        plant_runs = {k: f.result() for k, f in f_plant.items()}
        noise_rows = [f.result() for f in f_noise]
        fig_limits_noise(noise_rows, out / "limits_noise.png")
        speed = [f.result() for f in f_speed]
        fig_limits_speed(speed, out / "limits_speed.png")

    def pooled(noise, n, des):
        rs = [track[(noise, n, des, s)] for s in range(strata)]
        return float(np.sqrt(np.mean([r["rms_true_nm"] ** 2 for r in rs]))), rs

    tracking = {}
    for noise in trk_noise:
        tracking[f"{noise}"] = {}
        for des in DESIGNS:
            w, rw = pooled(noise, 1, des)
            i, ri = pooled(noise, 100, des)
            tracking[f"{noise}"][des] = dict(
                without=w, **{"with": i}, ratio=w / i,
                without_meas=float(np.sqrt(np.mean([r["rms_meas_nm"] ** 2 for r in rw]))),
                with_meas=float(np.sqrt(np.mean([r["rms_meas_nm"] ** 2 for r in ri]))),
                per_start={"without": [r["rms_true_nm"] for r in rw],
                           "with": [r["rms_true_nm"] for r in ri]},
                peak_with=max(r["peak_true_nm"] for r in ri),
                illegal_steps_with=[r["illegal_steps"] for r in ri])
    std = tracking[f"{NOISE_STD}"]["default"]
    sensitivity = {}
    for name in plants:
        w, i = (float(np.sqrt(np.mean([plant_runs[(name, n, s)]["rms_true_nm"] ** 2
                                        for s in range(strata)]))) for n in (1, 100))
        sensitivity[name] = dict(without=w, **{"with": i}, ratio=w / i)
    fig12({(des, n): track[(NOISE_STD, n, des, 0)] for des in DESIGNS for n in (1, 100)},
          dict(strata=strata, without=std["without"], ratio=std["ratio"],
               **{"with": std["with"]}), out / "fig12_tracking.png")
    strip = ("t", "enc", "vib", "diff")
    validation = {f"{noise}": {f"{n}": {des: {k: v for k, v in val[(noise, n, des)].items()
                                               if k not in strip}
                                         for des in ("default", "paper-literal", "printed")}
                               for n in (50, 100)} for noise in val_noise}
    exp = closedloop.Experiment()
    kp, ki, kd = closedloop.pid_gains(exp.slider, exp.bandwidth_hz)
    seconds = time.time() - t0
    res = {
        "tracking_rms_nm_without": std["without"], "tracking_rms_nm_with": std["with"],
        "tracking_improvement": std["ratio"], "plant_sensitivity": sensitivity,
        "paper": PAPER, "quick": quick, "noise_std": NOISE_STD,
        "noise_levels_validation": val_noise, "noise_levels_tracking": trk_noise,
        "validation": validation, "tracking": tracking,
        "closed_loop": dict(slider=vars(exp.slider), bandwidth_hz=exp.bandwidth_hz,
                            d_cutoff_hz=exp.d_cutoff_hz, loop_hz=1 / exp.period_s,
                            kp_N_per_m=kp, ki_N_per_m_s=ki, kd_Ns_per_m=kd,
                            stroke_nm=exp.stroke_nm, t_before=exp.t_before,
                            t_move=exp.t_move, t_after=exp.t_after, start_positions=strata),
        "fig03": dict(est_rms=params["est_rms"], jumps_mm=params["jumps_mm"],
                      count=params["count"], samples=params["samples"],
                      updates=params["updates"], travel_mm=params["travel_mm"]),
        "fine_phase_err_rms_nm_2mm_s": interp_err,
        "limits_noise": noise_rows, "limits_speed": speed,
        "seconds": round(seconds, 1), "jobs": a.jobs,
        "loadavg_start": load0, "loadavg_end": os.getloadavg(),
    }
    md = ("Measured with `make reproduce` (bit-true model of the core; 4 um pitch, 1 MS/s, "
          f"16-bit ADC; Fig. 12: RMS over {strata} start positions inside a 1 um count "
          "cell, true position).\n\n" + markdown(res) + "\n")
    (out / "reproduce.md").write_text(md)
    (out / "reproduce.json").write_text(json.dumps(res, indent=1, default=float))
    print(md)
    print(f"reproduce: wrote {len(list(out.glob('*.png')))} figures, reproduce.json and "
          f"reproduce.md to {out} in {seconds:.0f} s ({a.jobs} jobs; load average "
          f"{load0[0]:.2f} at the start, {os.getloadavg()[0]:.2f} at the end)")
    if std["ratio"] < 2 and not quick:
        print(f"reproduce: error: interpolation cuts the RMS tracking error only "
              f"{std['ratio']:.2f}x (needs >= 2x)", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
