"""Signal generator, scenario suite and metrics: the yardsticks of the accuracy benchmark."""
import numpy as np
import pytest

from sim import metrics, scenarios, siggen

FS = 1e6


def test_jerk_limited_move_respects_its_limits_and_lands_exactly():
    vmax, amax, jmax = 20e6, 1e9, 1e11            # nm/s, nm/s^2, nm/s^3
    x = siggen.jerk_limited(1e6, vmax, amax, jmax, FS)
    assert x[0] == 0 and x[-1] == pytest.approx(1e6, abs=1e-6)
    v = np.diff(x) * FS
    a = np.diff(v) * FS
    j = np.diff(a) * FS
    assert v.max() <= vmax * 1.001 and v.min() >= -1e-6
    assert np.abs(a).max() <= amax * 1.001
    assert np.abs(j).max() <= jmax * 1.01
    assert v.max() >= vmax * 0.999                # long enough to cruise
    # a short move lowers the peak speed instead of overshooting
    xs = siggen.jerk_limited(-1000.0, vmax, amax, jmax, FS)
    assert xs[-1] == pytest.approx(-1000.0) and np.all(np.diff(xs) <= 1e-9)


def test_moves_dwell_and_reversals():
    x = siggen.moves(FS, [("dwell", 0.01), ("move", 4000.0, 1e6, 1e9, 1e11),
                          ("dwell", 0.005)])
    assert np.all(x[:10000] == 0) and np.all(x[-5000:] == pytest.approx(4000.0))
    with pytest.raises(ValueError, match="unknown step"):
        siggen.moves(FS, [("wait", 1.0)])
    r = siggen.reversals(100000, FS, 1000.0, 20.0)
    assert r.min() == pytest.approx(0.0) and r.max() == pytest.approx(2000.0, rel=1e-6)


def test_parameter_profiles():
    x = np.linspace(-5.0, 15.0, 11)
    p = siggen.along(x, 0.6, 0.5)
    assert p[0] == pytest.approx(0.6) and p[-1] == pytest.approx(0.5)
    q = siggen.jump(p, 4, 0.1)
    assert np.allclose(q[:4], p[:4]) and np.allclose(q[4:], p[4:] + 0.1)


def test_signal_model_without_harmonics_is_the_papers():
    sig = siggen.Signal(noise=0.0, adc_bits=16)
    x = np.linspace(0, 8000.0, 5000)
    u1, u2, a = siggen.encode(x, 4000.0, sig)
    full = 1 << 15
    assert np.abs(u1 / full - (sig.A1 * np.cos(a) + sig.m1)).max() < 1 / full
    assert np.abs(u2 / full - (sig.A2 * np.sin(a - sig.phi) + sig.m2)).max() < 1 / full


def test_third_harmonic_gives_a_fourfold_angle_error_of_h3():
    sig = siggen.Signal(A1=0.6, A2=0.6, m1=0, m2=0, phi=0, h3=0.01, noise=0.0)
    a = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    u1, u2, _ = siggen.encode(a * 4000.0 / (2 * np.pi), 4000.0, sig)
    err = np.angle(np.exp(1j * (np.arctan2(u2, u1) - a)))
    assert np.abs(err).max() == pytest.approx(0.01, rel=0.02)
    spec = np.abs(np.fft.rfft(err))
    assert np.argmax(spec) == 4


@pytest.mark.parametrize("h, err", [(dict(h2=0.01), {1: 0.00707, 3: 0.00707}),
                                    (dict(h5=0.01), {4: 0.01})])
def test_second_and_fifth_harmonics_give_their_angle_errors(h, err):
    """The angle error of the waveform's harmonics (the same waveform in both channels a
    quarter period apart): a 2nd harmonic h gives h / sqrt(2) rad at once and three times
    the signal frequency, a 5th (like the 3rd) h rad at four times; the derivative that
    the floor uses (angle_var) is the waveform's own."""
    sig = siggen.Signal(A1=0.6, A2=0.6, m1=0, m2=0, phi=0, noise=0.0, **h)
    a = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    u1, u2, _ = siggen.encode(a * 4000.0 / (2 * np.pi), 4000.0, sig)
    e = np.angle(np.exp(1j * (np.arctan2(u2, u1) - a)))
    spec = np.abs(np.fft.rfft(e)) * 2 / len(a)
    top = sorted(np.argsort(spec)[-len(err):].tolist())
    assert top == sorted(err)
    assert spec[top] == pytest.approx([err[k] for k in top], rel=0.05)
    d = 1e-6
    w0 = np.array(siggen._waves(a, sig))
    num = (np.array(siggen._waves(a + d, sig)) - w0) / d
    assert np.allclose(num, siggen._waves(a, sig, 1), atol=1e-5)


def test_angle_variance_is_methods_bound():
    sig = siggen.Signal()
    a = np.linspace(0, 2 * np.pi, 1000)
    lsb = 2.0 / (1 << sig.adc_bits)
    expect = ((sig.noise * sig.A1) ** 2 + lsb ** 2 / 12) / (
        sig.A1 ** 2 * np.sin(a) ** 2 + sig.A2 ** 2 * np.cos(a - sig.phi) ** 2)
    assert np.allclose(siggen.angle_var(a, sig), expect)
    # an 8-bit ADC without noise: the quantisation term alone (lsb^2 / 12)
    sig8 = siggen.Signal(noise=0.0, adc_bits=8, A1=0.5, A2=0.5, phi=0.0)
    assert np.allclose(siggen.angle_var(a, sig8), (2.0 / 256) ** 2 / 12 / 0.25)
    drop = siggen.Signal(dropout=((10, 20, 0.0),))
    v = siggen.angle_var(a, drop)
    assert np.all(np.isinf(v[10:20])) and np.all(np.isfinite(v[:10]))


def test_quantised_floor():
    """Spread positions: METHOD.md's sqrt(noise^2 + q^2/12); a dwell with little noise:
    its fixed rounding error, which no interpolator avoids."""
    rng = np.random.default_rng(1)
    pitch, n = 4000.0, 100
    a = rng.uniform(0, 200 * np.pi, 200000)
    var_a = np.full_like(a, (0.005) ** 2)
    exact = metrics.floor_nm(var_a, pitch, n, a=a)[0]
    method = metrics.floor_nm(var_a, pitch, n)[0]
    assert exact == pytest.approx(method, rel=0.01)
    # two dwells, noise far below q: each keeps its own rounding error
    c = 2 * n / np.pi
    a_dwell = np.concatenate([np.full(1000, 10.5 / c), np.full(1000, 20.9 / c)])
    tiny = np.full(2000, 1e-12)
    fl = metrics.floor_nm(tiny, pitch, n, a=a_dwell)[0]
    q = pitch / (4 * n)
    assert fl == pytest.approx(0.2 * q, rel=1e-3)  # errors -0.5 q, -0.9 q: 0.2 q about the mean


def test_score_and_convergence():
    pitch, n = 4000.0, 100
    x = siggen.constant_speed(20000, FS, 2e6)      # 10 periods
    a = 2 * np.pi * x / pitch
    count = np.floor(a * 2 * n / np.pi).astype(np.int64)
    count[:3000] += 7                              # start-up error of 70 nm
    var_a = np.full_like(a, 1e-6)
    s, err, keep = metrics.score(count, x, var_a, pitch, n, 5000, a=a)
    assert keep.sum() == 15000 and s["slips"] == 0 and s["ratio"] < 1.05
    c = metrics.convergence_periods(err, x, pitch, s["floor_nm"], 0, window=500)
    assert c == pytest.approx(1.5)                # 3000 samples at 2000 per period
    assert metrics.convergence_samples(err, s["floor_nm"], 0, window=500) == 3000
    # a tighter bound: the start-up error must be gone, and a bound below the RMS of
    # every window never settles (the bound is what decides, not a constant)
    assert metrics.convergence_samples(err, s["floor_nm"], 0, window=500, bound=0.01) is None
    bad = count.copy()
    bad[12000:] += 150                             # 1.5 um: slips, never settles
    s2, err2, _ = metrics.score(bad, x, var_a, pitch, n, 5000, a=a)
    assert s2["slips"] > 0
    assert metrics.convergence_periods(err2, x, pitch, s2["floor_nm"], 0) is None
    with pytest.raises(ValueError, match="no samples"):
        metrics.score(count, x, var_a, pitch, n, 20000)


def test_suite_is_complete_and_reproducible():
    sc = scenarios.suite()
    names = [s.name for s in sc]
    assert len(names) >= 10 and len(set(names)) == len(names)
    by = {s.name: s for s in sc}
    # 1 s of standstill between moves
    v = np.diff(by["standstill"].x)
    still = np.concatenate([[0], np.flatnonzero(v != 0), [len(v)]])
    assert np.diff(still).max() >= 1e6
    # creep: >= 100 000 samples per signal period, scored after the first period
    cr = by["creep"]
    assert scenarios.PITCH_NM / np.diff(cr.x).max() >= 1e5 * (1 - 1e-9)
    assert cr.start() == pytest.approx(1e5, abs=2)
    # and at 10^6 samples per signal period
    cr = by["creep1m"]
    assert scenarios.PITCH_NM / np.diff(cr.x).max() >= 1e6 * (1 - 1e-9)
    assert cr.start() == pytest.approx(1e6, abs=2)
    # high speed around 0.3 fs; 12-bit ADC near full scale; 2 % noise; 1 % 3rd harmonic
    assert np.diff(by["highspeed"].x).max() / scenarios.PITCH_NM == pytest.approx(0.3, abs=0.02)
    assert by["adc12_fullscale"].sig.adc_bits == 12 and by["adc12_fullscale"].sig.A1 >= 0.9
    assert by["noise2"].sig.noise == 0.02 and by["harmonic3"].sig.h3 == 0.01
    assert by["drift_jump"].events
    # slow scans with 2nd, 3rd and 5th harmonics (0.2 to 2 %), a rotary scale at low speed
    for name, mm_s in (("slow05", 0.5), ("slow2", 2), ("slow5", 5), ("rotary", 0.5),
                       ("magnetic12", 4.0)):
        sg = by[name].sig
        assert np.diff(by[name].x).max() * scenarios.FS / 1e6 == pytest.approx(mm_s, rel=1e-3)
        assert min(sg.h2, sg.h3, sg.h5) >= 0.002 and max(sg.h2, sg.h3, sg.h5) <= 0.02
    assert np.ptp(by["rotary"].sig.A1) > 0.01          # run-out over 0.3 revolution
    assert by["magnetic12"].sig.adc_bits == 12 and not by["magnetic12"].drifts
    assert by["rotary"].drifts and by["drift_jump"].drifts
    u1, u2, _ = by["constant"].codes()
    w1, w2, _ = by["constant"].codes()
    assert np.array_equal(u1, w1) and np.array_equal(u2, w2)
    with pytest.raises(ValueError, match="unknown scenario"):
        scenarios.by_name(["nope"])
