"""The baseline interpolators of sim/baselines.py against the ground truth."""
import numpy as np
import pytest

from sim import baselines, reference

TRUE = (0.6, 0.6 / 0.5, 0.03, -0.02, 0.1)          # A1, R, m1, m2, phi of the distorted signal


def distorted(n, spp, direction=1, a0=0.3, A1=0.6, A2=0.5, m1=0.03, m2=-0.02, phi=0.1):
    """Noise-free distorted signals at constant speed, spp samples per signal period."""
    a = a0 + direction * 2 * np.pi * np.arange(n) / spp
    return A1 * np.cos(a) + m1, A2 * np.sin(a - phi) + m2, a


def truth_count(a, interp):
    return np.floor(a * 2 * interp / np.pi).astype(np.int64)


def centred(err):
    """Remove the arbitrary zero of the counter (a constant)."""
    return err - np.round(np.mean(err))


# ------------------------------------------------------------------------------ raw_atan2

@pytest.mark.parametrize("direction", [1, -1])
def test_raw_atan2_reproduces_floor_on_a_perfect_circle(direction):
    u1, u2, a = distorted(20000, 997.3, direction, A1=0.7, A2=0.7, m1=0.0, m2=0.0, phi=0.0)
    c = baselines.raw_atan2(u1, u2, 100)
    assert c.dtype == np.int64 and c.shape == a.shape
    e = c - truth_count(a, 100)
    assert e.min() == e.max()                   # exactly the truth up to a constant
    assert np.sign(c[-1] - c[0]) == direction


# ------------------------------------------------------------------------------ heydemann

def test_heydemann_recovers_a_strongly_distorted_ellipse():
    u1, u2, a = distorted(20000, 200)
    c, p = baselines.heydemann(u1, u2, 100)
    np.testing.assert_allclose(p, TRUE, rtol=0, atol=1e-9)
    e = c - truth_count(a, 100)
    assert e.max() - e.min() <= 1               # within one count of the truth
    # the distortion matters: without correction the count is off by many counts
    r = baselines.raw_atan2(u1, u2, 100)
    er = r - truth_count(a, 100)
    assert er.max() - er.min() > 10


def test_heydemann_mask_excludes_bad_samples():
    u1, u2, a = distorted(20000, 200)
    u1 = u1.copy()
    bad = np.zeros(len(u1), bool)
    bad[5000:5100] = True
    u1[bad] = 0.0                                # a dropout
    with pytest.raises(AssertionError):          # unmasked, the fit is spoilt
        np.testing.assert_allclose(baselines.heydemann(u1, u2, 100)[1], TRUE, atol=1e-6)
    _, p = baselines.heydemann(u1, u2, 100, mask=~bad)
    np.testing.assert_allclose(p, TRUE, rtol=0, atol=1e-9)


def test_heydemann_rejects_a_hyperbola():
    t = np.linspace(-2, 2, 500)
    u1, u2 = 0.5 * np.cosh(t), 0.5 * np.sinh(t)  # 4 u1^2 - 4 u2^2 = 1
    with pytest.raises(ValueError, match="not an ellipse"):
        baselines.heydemann(u1, u2, 100)


def test_heydemann_rejects_degenerate_and_bad_masks():
    t = np.linspace(0, 1, 100)
    with pytest.raises(ValueError, match="rank deficient"):
        baselines.heydemann(t, 2 * t, 100)       # a straight line
    u1, u2, _ = distorted(1000, 200)
    with pytest.raises(ValueError, match="at least 5"):
        baselines.heydemann(u1, u2, 100, mask=np.arange(1000) < 3)
    with pytest.raises(ValueError, match="boolean"):
        baselines.heydemann(u1, u2, 100, mask=np.ones(999, bool))


@pytest.mark.parametrize("fn", [baselines.raw_atan2, baselines.heydemann,
                                baselines.paper_literal])
def test_bad_input_raises(fn):
    u1, u2, _ = distorted(1000, 200)
    with pytest.raises(ValueError, match="same length"):
        fn(u1, u2[:-1], 100)
    with pytest.raises(ValueError, match="finite"):
        fn(np.where(np.arange(1000) == 7, np.nan, u1), u2, 100)
    with pytest.raises(ValueError, match="1-D"):
        fn(u1.reshape(10, 100), u2.reshape(10, 100), 100)
    with pytest.raises(ValueError, match="interp"):
        fn(u1, u2, 0)


# ------------------------------------------------------------------------------ pieces

def test_extract_many_matches_reference_extract():
    rng = np.random.default_rng(5)
    th = np.column_stack([rng.uniform(-1, 6, 4000), rng.uniform(-1, 6, 4000),
                          rng.uniform(-6, 6, 4000), rng.uniform(-3, 3, 4000),
                          rng.uniform(-3, 3, 4000)])
    p, ok = baselines.extract_many(th)
    n_ok = 0
    for row, q, v in zip(th, p, ok):
        r = reference.extract(row)
        assert (r is not None) == v
        if v:
            np.testing.assert_allclose(q, r, rtol=1e-12, atol=1e-12)
            n_ok += 1
    assert 100 < n_ok < len(th) - 100            # both kinds were exercised


def test_linear_index_octants_and_linearisation_error():
    N = 1000
    a = np.linspace(-np.pi, np.pi, 100001)
    i = baselines.linear_index(np.cos(a), np.sin(a), N)
    ideal = a * 4 * N / np.pi
    d = np.mod(i - ideal + 4 * N, 8 * N) - 4 * N   # index error, rows
    err = d * np.pi / (4 * N)                      # angle error, rad
    assert np.abs(err).max() == pytest.approx(0.033, abs=0.001)   # METHOD.md: 0.033 rad
    for k in range(8):                            # the same error in every octant
        octant = np.abs(a - (k - 4) * np.pi / 4 - np.pi / 8) < np.pi / 8
        assert np.abs(err[octant]).max() == pytest.approx(0.033, abs=0.001), k
    # rows continuous across the octant boundaries (no step larger than the slope allows)
    step = np.mod(np.diff(i) + 4 * N, 8 * N) - 4 * N
    assert step.min() >= 0 and step.max() <= 2


def test_pulses_hysteresis_and_decoder():
    x = np.array([0.0, 0.01, 0.2, 0.01, -0.01, -0.2, -0.01, 0.03, 0.06])
    np.testing.assert_array_equal(baselines.pulses(x, 0.05), [1, 1, 1, 1, 1, 0, 0, 0, 1])
    np.testing.assert_array_equal(baselines.pulses(-x, 0.05), [1, 1, 0, 0, 0, 1, 1, 1, 0])
    np.testing.assert_array_equal(baselines.pulses([-0.01, 0.01, 0.3], 0.05), [0, 0, 1])
    # quadrants 0, 1, 2, 3 for increasing phase: (1,1) (0,1) (0,0) (1,0)
    A = np.array([1, 0, 0, 1, 1, 1, 0, 0, 1, 0])
    B = np.array([1, 1, 0, 0, 1, 0, 0, 1, 1, 0])
    c, ill = baselines.decode_x4(A, B)
    np.testing.assert_array_equal(np.diff(c), [1, 1, 1, 1, -1, -1, -1, -1, 0])
    assert ill == 1                              # the last step changes A and B at once


def test_decoder_counts_floor_of_an_ideal_phase():
    b = 0.2 + np.cumsum(np.random.default_rng(2).uniform(-0.5, 1.0, 5000))   # < pi/2 steps
    c, ill = baselines.decode_x4(np.cos(b) >= 0, np.sin(b) >= 0)
    assert ill == 0
    e = c - np.floor(b * 2 / np.pi)
    assert e.min() == e.max()


# ------------------------------------------------------------------------------ paper_literal

@pytest.mark.parametrize("direction", [1, -1])
def test_paper_literal_tracks_within_its_linearisation_error(direction):
    """n = 100 at 1000 samples per signal period (the n-th order moves 1/10 period per
    sample): after convergence the count follows the truth within the linear index's
    error (0.033 rad = 2.1 counts peak, ~1.55 counts RMS) and counts with the motion."""
    n, start = 100, 1000
    u1, u2, a = distorted(20000, 1000, direction)
    r = baselines.paper_literal(u1, u2, n)
    c = r["count"]
    assert c.dtype == np.int64 and c.shape == a.shape
    assert r["invalid"] == 0
    np.testing.assert_allclose(r["params"][-1], TRUE, atol=1e-6)
    e = (c - a * 2 * n / np.pi)[start:]           # against the continuous truth
    e = e - e.mean()
    assert np.abs(e).max() <= 3.0
    assert np.sqrt(np.mean(e ** 2)) == pytest.approx(1.55, abs=0.25)   # METHOD: 15.7 nm
    assert np.ptp(e) > 4.0                        # the linearisation error is really there
    # direction: monotonic, and the net count equals the truth's
    steps = np.diff(c[start:])
    assert np.all(direction * steps >= 0)
    net_truth = truth_count(a, n)[-1] - truth_count(a, n)[start]
    assert abs((c[-1] - c[start]) - net_truth) <= 6
    assert abs(net_truth) > 1000
    # the same signal through the exact ellipse fit and atan2 is better than the paper
    h, _ = baselines.heydemann(u1, u2, n)
    eh = centred(h - truth_count(a, n))
    assert np.abs(eh).max() <= 1


def test_paper_literal_loses_counts_beyond_a_quarter_period_per_sample():
    """n = 100 at 50 samples per signal period: the n-th order moves 2 periods per sample
    (Eq. 13 limit exceeded); the pulse counter sees illegal transitions and loses counts,
    although the parameters are still found exactly."""
    n, start = 100, 1000
    u1, u2, a = distorted(20000, 50)
    r = baselines.paper_literal(u1, u2, n)
    assert r["illegal"] > 0
    np.testing.assert_allclose(r["params"][-1], TRUE, atol=1e-6)
    net_truth = truth_count(a, n)[-1] - truth_count(a, n)[start]
    assert abs((r["count"][-1] - r["count"][start]) - net_truth) > 0.5 * net_truth


def test_paper_literal_keeps_last_valid_parameters_on_a_short_arc():
    """Noisy creep over a short arc: theta is often not an ellipse (the literal method would
    produce NaN there); the last valid parameters are kept, and once the motion spans the
    circle the estimate converges."""
    rng = np.random.default_rng(1)
    a = np.concatenate([np.linspace(0, 0.3, 1500), 0.3 + 2 * np.pi * np.arange(1, 8001) / 1000])
    u1 = 0.6 * np.cos(a) + 0.03 + 0.003 * rng.standard_normal(len(a))
    u2 = 0.5 * np.sin(a - 0.1) - 0.02 + 0.003 * rng.standard_normal(len(a))
    r = baselines.paper_literal(u1, u2, 10)     # n = 10: the noise stays within eps
    assert r["invalid"] > 0
    assert np.all(np.isfinite(r["params"]))
    np.testing.assert_allclose(r["params"][-1], TRUE, atol=0.01)
    net = r["count"][-1] - r["count"][3000]
    net_truth = truth_count(a, 10)[-1] - truth_count(a, 10)[3000]
    assert net_truth > 100 and abs(net - net_truth) <= 2


class LiteralRls:
    """Eqs. 5-7 as printed, in numpy: regressor (u1^2, u2^2, u1 u2, u1, u2), lambda given
    directly, no trace bound (reference.Rls is the gateware's twin, which has both)."""

    def __init__(self, lam, kappa, theta0=(4.0, 4.0, 0.0, 0.0, 0.0)):
        self.lam, self.kappa = lam, kappa
        self.theta = np.array(theta0, dtype=float)
        self.reset()

    def reset(self):
        self.P = self.kappa * np.eye(5)

    def update(self, u1, u2):
        phi = np.array([u1 * u1, u2 * u2, u1 * u2, u1, u2])
        h = self.P @ phi
        k = h / (self.lam + phi @ h)
        self.theta = self.theta + k * (1.0 - phi @ self.theta)
        self.P = (self.P - np.outer(k, h)) / self.lam
        return self.theta


def test_paper_literal_rls_and_parameters_match_a_plain_loop():
    """The unrolled RLS and the vectorised Eq. 8 / keep-last-valid equal a straightforward
    per-sample loop over LiteralRls and reference.extract (noisy creep, so that invalid
    thetas occur)."""
    rng = np.random.default_rng(4)
    a = np.concatenate([np.linspace(0, 0.2, 800), 0.2 + 2 * np.pi * np.arange(1, 1201) / 300])
    u1 = 0.6 * np.cos(a) + 0.03 + 0.003 * rng.standard_normal(len(a))
    u2 = 0.5 * np.sin(a - 0.1) - 0.02 + 0.003 * rng.standard_normal(len(a))
    r = baselines.paper_literal(u1, u2, 10, lam=0.99, kappa=500.0, reset_every=700)
    rls = LiteralRls(0.99, 500.0)
    p = (0.5, 1.0, 0.0, 0.0, 0.0)
    want, invalid = [], 0
    for k in range(len(a)):
        q = reference.extract(rls.update(u1[k], u2[k]))
        if q is None:
            invalid += 1
        else:
            p = q
        if (k + 1) % 700 == 0:
            rls.reset()
        want.append(p)
    assert 0 < invalid == r["invalid"]
    np.testing.assert_allclose(r["params"], np.array(want), rtol=1e-6, atol=1e-9)


def test_paper_literal_rejects_bad_parameters():
    u1, u2, _ = distorted(1000, 200)
    for kw in (dict(lam=0.0), dict(lam=1.5), dict(kappa=-1.0), dict(N=0), dict(eps=-0.1),
               dict(reset_every=-5)):
        with pytest.raises(ValueError):
            baselines.paper_literal(u1, u2, 100, **kw)


# ------------------------------------------------------------- the float twin (reference)

def test_float_twin_follows_the_gateware_schedule_to_the_truth():
    """reference.run_schedule on the bit-true model's schedule: the same updates, resets
    and hand-overs in double precision. Its parameters end at the truth and its count is
    at the floor; with an empty schedule it keeps the default bundle (a circle of radius
    0.5 without offsets), far off on these signals."""
    from sim import metrics, siggen
    from sim.model import finequad_core as core
    sig = siggen.Signal(A1=0.6, A2=0.5, m1=0.03, m2=-0.02, phi=0.1, noise=0.002)
    x = siggen.moves(1e6, [("dwell", 0.002), ("move", 0.3e6, 20e6, 1e9, 1e11)])
    u1, u2, a = siggen.encode(x, 4000.0, sig, seed=5)
    r = core.run(u1, u2, core.Config())
    assert any(first is not None for kind, _, _, first in r["sched"] if kind == "update")
    f = reference.run_schedule(u1, u2, r["sched"], interp=100)
    a1, rr, m1, m2, phi = f["params"][-1]
    assert a1 == pytest.approx(0.6, abs=0.003) and rr == pytest.approx(1.2, abs=0.006)
    assert m1 == pytest.approx(0.03, abs=0.002) and m2 == pytest.approx(-0.02, abs=0.002)
    assert phi == pytest.approx(0.1, abs=0.005)
    start = len(x) // 2
    s, _, _ = metrics.score(f["count"], x, siggen.angle_var(a, sig), 4000.0, 100, start, a=a)
    assert s["slips"] == 0 and s["ratio"] < 1.1, s
    f0 = reference.run_schedule(u1, u2, [], interp=100)
    s0, _, _ = metrics.score(f0["count"], x, siggen.angle_var(a, sig), 4000.0, 100, start,
                             a=a)
    assert s0["ratio"] > 3, s0
