"""sim/closedloop.py: the slider's physics against independent answers, the PID, the gains,
and short closed-loop runs through the bit-true core."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from sim import closedloop as cl
from sim import siggen
from sim.model import finequad_core as core


def test_free_acceleration_matches_the_closed_form():
    # no Coulomb friction: m x'' = F - b x' from rest, x = (F/b)(t - tau (1 - exp(-t/tau)))
    s = cl.Slider(mass_kg=2.0, viscous_Ns_m=10.0, coulomb_N=0.0)
    t = np.linspace(0, 1e-3, 101)
    x, x_end, v_end = s.advance(0.0, 0.0, 3.0, t)
    tau = 0.2
    want = 3.0 / 10 * (t - tau * (1 - np.exp(-t / tau)))
    np.testing.assert_allclose(x, want, rtol=1e-12, atol=1e-18)
    assert x_end == pytest.approx(want[-1], rel=1e-12)
    assert v_end == pytest.approx(0.3 * (1 - np.exp(-1e-3 / tau)), rel=1e-12)


def test_stiction_holds_below_the_coulomb_force():
    s = cl.Slider(coulomb_N=1.0)
    x, x_end, v_end = s.advance(1e-3, 0.0, 0.999, np.linspace(0, 0.01, 50))
    assert np.all(x == 1e-3) and x_end == 1e-3 and v_end == 0.0
    x, _, v_end = s.advance(1e-3, 0.0, -1.001, np.linspace(0, 0.01, 50))
    assert np.all(np.diff(x) < 0) and v_end < 0


def test_coasting_to_a_stop_obeys_the_impulse_balance():
    # v0 > 0, no force: friction stops it at t* = tau ln(1 + v0 b / Fc); the impulse
    # m (0 - v0) = -b (x* - x0) - Fc t* gives x*; afterwards it stays (|F| = 0 <= Fc)
    m, b, fc, v0 = 2.0, 10.0, 1.0, 0.05
    s = cl.Slider(mass_kg=m, viscous_Ns_m=b, coulomb_N=fc)
    t_stop = m / b * np.log(1 + v0 * b / fc)
    x_stop = (m * v0 - fc * t_stop) / b
    t = np.linspace(0, 3 * t_stop, 301)
    x, x_end, v_end = s.advance(0.0, v0, 0.0, t)
    assert v_end == 0.0 and x_end == pytest.approx(x_stop, rel=1e-12)
    assert np.all(x[t >= t_stop] == pytest.approx(x_stop, rel=1e-12))
    assert np.all(np.diff(x[t < t_stop]) > 0)


def test_reversal_matches_a_numerical_integration():
    # moving forward against a force above the Coulomb level: it stops and comes back;
    # compare with scipy's RK45 on the same equations (sgn(v) flips once)
    m, b, fc = 2.0, 10.0, 1.0
    s = cl.Slider(mass_kg=m, viscous_Ns_m=b, coulomb_N=fc)
    f, v0 = -5.0, 0.02

    def rhs(_, y):
        return [y[1], (f - b * y[1] - fc * np.sign(y[1])) / m]

    t = np.linspace(0, 0.05, 501)
    ref = solve_ivp(rhs, (0, t[-1]), [0.0, v0], t_eval=t, rtol=1e-10, atol=1e-14,
                    max_step=1e-5)
    x, x_end, v_end = s.advance(0.0, v0, f, t)
    assert x.max() > 0 and x_end < 0 and v_end < 0        # it did reverse
    np.testing.assert_allclose(x, ref.y[0], atol=1e-9 * np.ptp(ref.y[0]) + 1e-12)
    assert v_end == pytest.approx(ref.y[1][-1], rel=1e-6)


def test_bad_parameters_are_rejected():
    with pytest.raises(ValueError, match="mass_kg must be > 0"):
        cl.Slider(mass_kg=0)
    with pytest.raises(ValueError, match="coulomb_N must be >= 0"):
        cl.Slider(coulomb_N=-1)
    with pytest.raises(ValueError, match="ascending"):
        cl.Slider().advance(0, 0, 0, [0.2, 0.1])
    with pytest.raises(ValueError, match="interp must be an integer 1..511"):
        cl.run(cl.Experiment(), 0)
    with pytest.raises(ValueError, match="samples_per_tick"):
        cl.Experiment(samples_per_tick=0)


def test_gains_place_a_triple_pole():
    s = cl.Slider()
    kp, ki, kd = cl.pid_gains(s, 50.0)
    roots = np.roots([s.mass_kg, s.viscous_Ns_m + kd, kp, ki])
    np.testing.assert_allclose(roots, -2 * np.pi * 50.0, rtol=1e-3)
    with pytest.raises(ValueError):
        cl.pid_gains(s, 0.01)            # Kd < 0: the viscous friction alone is more


def test_pid_terms_saturation_and_anti_windup():
    p = cl.Pid(kp=2.0, ki=100.0, kd=0.0, period_s=1e-3, d_cutoff_hz=100, limit=10.0)
    assert p.step(1.0) == pytest.approx(2.0)               # P only on the first step
    assert p.step(1.0) == pytest.approx(2.0 + 0.1)         # + Ki T e
    for _ in range(200):
        assert p.step(1.0) <= 10.0
    held = p.integ
    p.step(1.0)
    assert p.integ == held                                  # saturated: no windup
    p.step(-1.0)
    assert p.integ < held                                   # unwinds at once
    d = cl.Pid(kp=0.0, ki=0.0, kd=1.0, period_s=1e-3, d_cutoff_hz=1e9, limit=1e9)
    d.step(0.0)
    assert d.step(1e-3) == pytest.approx(1.0)              # de/dt with a wide filter


SHORT = dict(t_before=0.005, t_move=0.04, t_after=0.02, seed=3)


@pytest.fixture(scope="module")
def runs():
    exp = cl.Experiment(**SHORT)
    lit = core.Config(TABLE="paper", count_mode=1)
    quiet = cl.Experiment(**SHORT, sig=siggen.Signal(noise=0.001))
    return {"without": cl.run(exp, 1), "with": cl.run(exp, 100),
            "literal_quiet": cl.run(quiet, 100, lit)}


def test_the_controller_sees_the_true_position_to_the_resolution(runs):
    # the measurement the PID gets is the core's count: within half a count (plus the
    # interpolation error) of the truth, for the default design at both resolutions and
    # for the paper-literal design (edge counter, linear index: +-21 nm) with low noise
    for key, tol in (("without", 500 + 20), ("with", 5 + 20), ("literal_quiet", 5 + 40)):
        r = runs[key]
        e = r["meas_nm"] - r["true_nm"]
        assert np.max(np.abs(e)) < tol, (key, np.max(np.abs(e)))
    assert runs["without"]["resolution_nm"] == 1000 and runs["with"]["resolution_nm"] == 10


def test_interpolation_cuts_the_tracking_error(runs):
    w, i = runs["without"], runs["with"]
    assert i["rms_true_nm"] < w["rms_true_nm"] / 1.5
    # it tracks: the stage ends near the 7 um target with interpolation
    assert abs(i["err_true_nm"][-1]) < 100
    assert abs(i["true_nm"][-1] - i["true_nm"][0] - 7000) < 100
    assert np.max(np.abs(i["force_N"])) <= cl.Slider().force_limit_N
