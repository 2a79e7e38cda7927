"""Adaptive harmonic compensation (sim/model/harmonic.py, rtl/harmonic.v) against ground
truth: the scenarios of sim/scenarios.py through the bit-true core model, and synthetic
fine-phase streams through the block's model alone.

The counter's error with the correction applied (the default) is compared with the same
recording's counter on the uncorrected phase (apply off: the counter of the raw fine
phase, which is what the core counts with HARM bit 0 clear): counter in phase
mode on the traced phase, with the product n * phase from Lut.nth and n,
COUNT_W of the run's Config, as core.Core counts; with nothing learned the two counts
are equal sample for sample.
"""
import time

import numpy as np
import pytest

from sim import metrics, scenarios, siggen
from sim.model import finequad_core as core
from sim.model import counter as counter_m, lut as lut_m
from sim.model import harmonic as hm

PITCH = scenarios.PITCH_NM
N_INTERP = core.Config().interp      # the runs below use the default n


def _run(name):
    sc = scenarios.by_name([name])[0]
    u1, u2, a = sc.codes()
    cfg = core.Config(ADC_W=sc.sig.adc_bits)
    return sc, a, core.run(u1, u2, cfg, trace=True), cfg


def _score(sc, a, count):
    return metrics.score(count, sc.x, siggen.angle_var(a, sc.sig), PITCH, N_INTERP,
                         sc.start(), a=a)[0]


def _count_off(r, cfg):
    """The core's phase-mode count of the uncorrected fine phase (what m_count is with HARM
    bit 0 clear): counter on r["phase"] with the product n * phase as rtl/lut.v
    forms it (Lut.nth), n and COUNT_W of the run's Config, as core.Core counts
    the corrected phase."""
    ph = np.asarray(r["phase"], dtype=np.int64)
    prod = lut_m.Lut(cfg.TABLE, cfg.SIN_W).nth(ph, cfg.interp)[0]
    return counter_m.counter(ph, prod, cfg.interp, cfg.COUNT_W)[0]


def phase_error(phase, a, lo, hi):
    """Fine-phase error against the true angle on samples [lo, hi), nm, its mean
    removed: (RMS, RMS of its periodic part). The periodic part is the error averaged in
    256 bins of the true phase (noise averages out, a function of the phase stays)."""
    a = np.asarray(a[lo:hi])
    e = ((np.asarray(phase[lo:hi]) - a * 8192 / (2 * np.pi) + 4096) % 8192) - 4096
    e_nm = (e - e.mean()) * PITCH / 8192
    b = ((a % (2 * np.pi)) / (2 * np.pi) * 256).astype(int) % 256
    cnt = np.bincount(b, minlength=256)
    m = np.bincount(b, weights=e_nm, minlength=256) / np.maximum(cnt, 1)
    return float(np.sqrt(np.mean(e_nm ** 2))), float(np.sqrt(np.sum(cnt * m ** 2) / cnt.sum()))


def moving(x, vmin_units=16):
    """Indices of samples where the true speed is at least vmin_units units/sample."""
    v = np.abs(np.diff(x)) / PITCH * 8192
    return np.nonzero(v >= vmin_units)[0]


@pytest.fixture(scope="module")
def harmonic3():
    return _run("harmonic3")


def test_harmonic3_counter_error_falls_to_the_floor(harmonic3):
    sc, a, r, cfg = harmonic3
    on = _score(sc, a, r["count"])
    off = _score(sc, a, _count_off(r, cfg))
    print(f"harmonic3 counter: apply on {on['rms_nm']:.2f} nm (ratio {on['ratio']:.3f}), "
          f"off {off['rms_nm']:.2f} nm (ratio {off['ratio']:.3f}), floor {on['floor_nm']:.2f}")
    assert off["ratio"] > 1.2                   # the 1 % harmonic is there
    assert on["ratio"] < 1.03                   # and gone (scored from the first move on)
    assert on["slips"] == 0
    assert r["harm"].learned > 10_000           # learning happened (speed gate open)


def test_harmonic3_fine_phase_periodic_error_below_1nm(harmonic3):
    """After convergence (the second move), the periodic part of the fine-phase error
    falls from the harmonic's ~4.7 nm RMS to below 1 nm; during the first move it
    converges within a few thousand samples."""
    sc, a, r, _ = harmonic3
    n = len(sc.x)
    mv = moving(sc.x)
    m1, m2 = mv[mv < n // 2], mv[mv > n // 2]
    rms_on, per_on = phase_error(r["phase_c"], a, m2[0], m2[-1])
    rms_off, per_off = phase_error(r["phase"], a, m2[0], m2[-1])
    _, per_conv = phase_error(r["phase_c"], a, m1[0] + 20_000, m1[-1])
    print(f"harmonic3 fine phase, 2nd move: apply on {rms_on:.2f} nm RMS (periodic "
          f"{per_on:.2f}), off {rms_off:.2f} nm (periodic {per_off:.2f}); 1st move after "
          f"20k samples: periodic {per_conv:.2f}")
    assert per_off > 4.0
    assert per_on < 1.0
    assert per_conv < 1.0
    assert rms_on < rms_off - 2.0


def test_harmonic3_correction_is_zero_mean(harmonic3):
    """No drift of the mean: the applied correction averages to zero over the table (to
    its rounding), and over the second move (uniform in phase) it moves the position by
    a negligible amount."""
    sc, a, r, _ = harmonic3
    h = r["harm"]
    corr = [(v - (h.R >> 6)) >> 8 for v in h.A]
    assert abs(np.mean(corr)) <= 0.5
    assert max(abs(v) for v in h.A) < 30000    # far from the s16 limits
    mv = moving(sc.x)
    m2 = mv[mv > len(sc.x) // 2]
    d = ((r["phase_c"] - r["phase"] + 4096) % 8192) - 4096
    assert abs(np.mean(d[m2[0]:m2[-1]])) * PITCH / 8192 < 0.3     # nm
    assert np.abs(d).max() > 8                 # while the correction itself is not small


def test_constant_no_harm():
    """A harmonic-free recording at 2 mm/s (4 units/sample: the observer in gear 2): the
    table learns noise only; the counter error is not larger than with apply off by more
    than 0.1 nm."""
    sc, a, r, cfg = _run("constant")
    on = _score(sc, a, r["count"])
    off = _score(sc, a, _count_off(r, cfg))
    print(f"constant: apply on {on['rms_nm']:.3f} nm, off {off['rms_nm']:.3f} nm")
    assert r["harm"].learned > 1000
    assert on["rms_nm"] < off["rms_nm"] + 0.1


def test_harmonic_free_at_learning_speed_no_harm():
    """The paper-like signals without harmonics at 10 mm/s (20 units/sample, inside the
    window): the table learns noise only; the counter error is not larger than with
    apply off by more than 0.1 nm."""
    n = 150_000
    x = siggen.constant_speed(n, scenarios.FS, 10 * scenarios.MM)
    sc = scenarios.Scenario("free10", "harmonic-free, 10 mm/s", x, siggen.Signal(), seed=31)
    u1, u2, a = sc.codes()
    cfg = core.Config()
    r = core.run(u1, u2, cfg, trace=True)
    on = _score(sc, a, r["count"])
    off = _score(sc, a, _count_off(r, cfg))
    print(f"harmonic-free 10 mm/s: apply on {on['rms_nm']:.3f} nm, off {off['rms_nm']:.3f} nm,"
          f" table spread {(max(r['harm'].A) - min(r['harm'].A)) / 256:.2f} units")
    assert r["harm"].learned > 5_000
    assert on["rms_nm"] < off["rms_nm"] + 0.1


# ---- the block's model on synthetic fine-phase streams -------------------------------------
def stream(v, n, h4=13.0, sigma=7.0, seed=0, x0=100.0):
    """Fine phase (u13) of a stage at v units/sample (scalar or per-sample array) with a
    4th-harmonic error h4 (units) and noise sigma (units); returns (phase, true x)."""
    rng = np.random.default_rng(seed)
    v = np.broadcast_to(np.asarray(v, float), (n,))
    x = x0 + np.concatenate([[0.0], np.cumsum(v[:-1])])
    ph = np.round(x + h4 * np.sin(8 * np.pi * x / 8192 + 0.3) + sigma * rng.standard_normal(n))
    return (ph.astype(np.int64) % 8192), x


def test_no_learning_at_standstill_from_dither_or_reversals():
    """Learn at 40 units/sample, stop (1 m/s^2 on a 4 um scale: 0.002 units/sample^2),
    then a long dwell with noise, servo dither around a point (amplitudes 100 to 2000
    units, periods 2000 to 200 000 samples) and sinusoidal reversals (|v| <= 10): the
    observer shifts through its gears, the table does not change, and it keeps being
    applied."""
    h = hm.Harmonic()
    v = np.concatenate([np.full(60_000, 40.0), np.linspace(40.0, 0.0, 20_000)])
    ph, x = stream(v, len(v))
    h.run(ph)
    assert h.learned > 4_000
    a0, r0, n0 = list(h.A), h.R, h.learned
    pos = x[-1]
    k = np.arange(200_000)
    runs = [("dwell", stream(0.0, 300_000, seed=1, x0=pos)[0]),
            ("reversals", stream(10.0 * np.cos(2 * np.pi * k / 20_000), len(k), seed=3,
                                 x0=pos)[0])]
    for amp, per in ((100, 2000), (500, 20_000), (1000, 200_000), (2000, 20_000)):
        v = np.diff(amp * np.sin(2 * np.pi * np.arange(len(k) + 1) / per))
        runs.append((f"dither {amp} units / {per} samples",
                     stream(v, len(k), seed=per + amp, x0=pos)[0]))
    gears = set()
    for name, s in runs:
        out, tr = h.run(s, trace=True)
        gears.update(np.unique(tr["g"]).tolist())
        assert h.learned == n0, name
        assert h.A == a0 and h.R == r0, name
        corr = (np.asarray(a0)[s >> 7] - (r0 >> 6)) >> 8
        assert np.array_equal(out, (s - corr) % 8192), name     # still applied
    assert max(gears) >= 9 and len(gears) > 6


def test_gears_zero_learns_only_from_16_units_per_sample():
    """Harmonic(gears=0) (rtl/harmonic.v GEARS = 0): the observer stays at the sample
    rate, so at 8 units/sample nothing is learned, and at 20 it is."""
    for v, learns in ((8.0, False), (20.0, True)):
        ph, _ = stream(v, 60_000, seed=7)
        h = hm.Harmonic(gears=0)
        _, tr = h.run(ph, trace=True)
        assert not tr["g"].any() and (h.learned > 1000) == learns, v
    with pytest.raises(ValueError, match="gears must be 0..11"):
        hm.Harmonic(gears=12)


@pytest.mark.parametrize("v, periods", [(0.05, 24), (0.4, 24), (3.0, 24), (-9.0, 80)])
def test_learns_at_slow_speed(v, periods):
    """At 0.05 to 9 units/sample (0.024 to 4.4 mm/s on a 4 um scale; 160 000 to 900
    samples per period) the observer takes a gear above 0 and the table learns a
    4th-harmonic error of 13 units (a 1 % third harmonic): after 24 periods (80 in gear 1,
    where a period has fewer candidates) it is below 20 % of what it was."""
    n = int(periods * 8192 / abs(v))
    ph, x = stream(v, n, seed=5)
    h = hm.Harmonic()
    out, tr = h.run(ph, trace=True)
    gate = tr["gate"].astype(bool)
    assert tr["gb"][gate].min() >= 1 and h.learned > 500
    tail = slice(n - n // 6, n)
    xt = x[tail]

    def per_part(p):
        e = ((p[tail] - xt + 4096) % 8192) - 4096
        e = e - e.mean()
        c = np.exp(-1j * 8 * np.pi * xt / 8192)
        return 2 * abs(np.mean(e * c))              # the 4th harmonic's amplitude
    before, after = per_part(ph), per_part(out)
    print(f"v {v}: {h.learned} updates, gears {sorted(set(tr['gb'][gate].tolist()))}, "
          f"4th harmonic {before:.1f} -> {after:.1f} units")
    assert before > 11 and after < 0.2 * before


def test_long_run_no_drift_no_saturation():
    """Two million samples over speeds across the window with accelerations (the
    observer lags): the table's common mode stays small and nothing saturates."""
    n = 2_000_000
    k = np.arange(n)
    v = 200.0 + 180.0 * np.sin(2 * np.pi * k / 400_000)          # 20 .. 380 units/sample
    ph, _ = stream(v, n, sigma=10.0, seed=4)
    h = hm.Harmonic()
    h.run(ph)
    mean_units = (h.R + 8192) / 64 / 256
    spread = (max(h.A) - min(h.A)) / 256
    print(f"long run: {h.learned} updates, table mean {mean_units:.2f} units, spread "
          f"{spread:.1f} units")
    assert h.learned > 120_000                 # one candidate in 10..17 samples
    assert abs(mean_units) < 8
    assert max(abs(v) for v in h.A) < 30000
    assert 24 < spread < 36                     # the +-13-unit harmonic (and noise)


@pytest.mark.parametrize("v", [4.0, 40.0, -150.0])
def test_table_of_noise_hidden(v):
    """No harmonic, noise 7 units (0.5 % of the signal): the table learns (its own noise)
    in gears 2 and 0, but it never becomes significant, so phase_c is the raw phase (the
    count is exactly what it would be without the block)."""
    ph, _ = stream(v, 300_000, h4=0.0, seed=9)
    h = hm.Harmonic()
    out, tr = h.run(ph, trace=True)
    st = h.N - abs(h.R + 8192)
    print(f"v {v}: {h.learned} updates, N - |S| = {st} ({st / 64 / 256:.2f} units)")
    assert h.learned > 10_000
    assert not tr["sig"].any() and np.array_equal(out, ph)


def test_table_shown_once_significant_hidden_below_half():
    """A 13-unit 4th-harmonic error at 40 units/sample: the table is shown once it is
    significant (within 10 000 samples of the start: 2047 to lock) and corrects the error; when the error
    goes away the table decays and is hidden again only once N - |R + 8192| has fallen
    to half of the threshold (the hysteresis)."""
    n1, n2 = 60_000, 400_000
    ph1, _ = stream(40.0, n1, seed=3)
    ph2, _ = stream(40.0, n2, h4=0.0, seed=4, x0=100.0 + 40.0 * n1)
    h = hm.Harmonic()
    out1, tr1 = h.run(ph1, trace=True)
    on = int(np.argmax(tr1["sig"]))
    assert tr1["sig"][-1] and 0 < on < 10_000, on
    assert np.array_equal(out1[:on], ph1[:on]) and not np.array_equal(out1[on:], ph1[on:])
    _, tr2 = h.run(ph2, trace=True)
    st = tr2["N"] - np.abs(tr2["R"] + 8192)          # N - |R + 8192| after each sample
    sig = tr2["sig"].astype(bool)
    off = int(np.argmin(sig))                          # the first hidden sample
    print(f"shown from sample {on}; hidden after {off} samples of no error, at "
          f"N - |S| = {st[off - 3]} (sig sees the samples <= k - 3)")
    half = hm.SIG_ON >> hm.SIG_HYST
    assert 10_000 < off and sig[:off].all() and not sig[off:].any()
    assert st[off - 3] <= half < st[off - 4]
    assert (st[:off - 3] <= hm.SIG_ON).sum() > 1000      # shown below the threshold


def test_learning_off_and_clear():
    h = hm.Harmonic()
    ph, _ = stream(40.0, 30_000)
    out = h.run(ph, learn=0)
    assert h.learned == 0 and np.array_equal(out, ph)
    h.run(ph)
    assert h.learned > 0 and any(h.A)
    clr = np.zeros(100, bool)
    clr[0] = True
    out = h.run(ph[:100], learn=0, clear=clr)
    assert not any(h.A) and h.R == -8192
    assert np.array_equal(out, ph[:100])


def test_apply_off_keeps_learning():
    """apply off: phase_c is the raw phase, the table still converges (it learns from the
    internally corrected phase), so switching apply on shows a converged correction."""
    ph, x = stream(40.0, 60_000)
    h_on, h_off = hm.Harmonic(), hm.Harmonic()
    h_on.run(ph)
    out = h_off.run(ph, apply=0)
    assert np.array_equal(out, ph)
    assert h_off.A == h_on.A


def test_observer_acquires_speeds_up_to_1000():
    """From power-up at any speed up to 1000 units/sample (twice the learning window)
    the observer pulls in (its wide gear) and holds track (C saturates)."""
    for v in (20.0, 300.0, 1000.0, -700.0):
        ph, _ = stream(v, 6000, sigma=5.0, seed=int(abs(v)))
        h = hm.Harmonic()
        _, tr = h.run(ph, learn=0, trace=True)
        assert tr["C"][-1] == hm.C_MAX, v
        assert abs(h.V / (1 << hm.VF) - v) < 0.5, v


def test_model_speed():
    ph, _ = stream(40.0, 300_000)
    h = hm.Harmonic()
    t0 = time.perf_counter()
    h.run(ph)
    rate = len(ph) / (time.perf_counter() - t0)
    print(f"harmonic model: {rate / 1e3:.0f}k samples/s")
    assert rate > 150e3          # ~500k/s unloaded; a margin for busy machines


def test_sweep_flags():
    """A clear sampled on edge w: the table is empty from the first sample arriving on an
    edge >= w; the samples arriving on edges w .. w + 64 are blocked."""
    arr = np.array([10, 99, 100, 101, 130, 164, 165, 300])
    clear, blocked = hm.sweep_flags(arr, [100])
    assert clear.tolist() == [0, 0, 1, 0, 0, 0, 0, 0]
    assert blocked.tolist() == [0, 0, 1, 1, 1, 1, 0, 0]
    h = hm.Harmonic(show=0)          # (every table shown: sig has its own tests)
    h.A[3] = 5000
    h.R = 5000 - 8192
    ph = np.full(len(arr), 3 << 7, np.int64)
    out = h.run(ph, learn=0, clear=clear, blocked=blocked)
    assert out[0] != ph[0] and out[1] != ph[1]           # corrected before the clear
    assert np.array_equal(out[2:], ph[2:])               # blocked, then an empty table
