"""The multi-axis window predicate of the bit-true model (sim/model/finequad_core.py Config.tdm,
rtl/finequad_multi.v; the RTL against it: cocotb_tests/test_finequad_multi.py).

* one axis (tdm None, or axes = 1) is the single core exactly;
* with axes > 1 every RESET and UPDATE of axis i is decided on an edge of its window,
  i L <= e mod (axes L) < i L + W, and every program it starts (an EXTRACT chained to its
  UPDATE included) ends by the edge the next axis's window opens: the shared engine is
  never contended;
* the windows change the schedule (fewer updates), the estimator still calibrates, and
  once calibrated the count stays within one count of the single core's (the fit
  differs by its updates, not in what it finds);
* tdm_period is the chain W + 1 + CYCLES[update] + CYCLES[extract] for both LANES, and a
  window spacing shorter than it is refused."""
import numpy as np
import pytest

from sim import siggen
from sim.model import finequad_core as core
from sim.model import estimator
from sim.model.rls_engine import CYCLES_BY_LANES

N, FS, PITCH = 20000, 1e6, 20.0


def recording(n=N, div=36, seed=1, sig=None, gaps=False):
    x = (siggen.s_curve(n, FS, 160 * n / 20000, 0.5 * n / FS, 0.05 * n / FS)
         + siggen.s_curve(n, FS, -120 * n / 20000, 0.25 * n / FS, 0.6 * n / FS))
    u1, u2, _ = siggen.encode(x, PITCH, sig or siggen.Signal(), seed=seed)
    if gaps:
        rng = np.random.default_rng(seed)
        t = 16 + np.concatenate([[0], np.cumsum(rng.integers(1, 61, n - 1))])
    else:
        t = 16 + div * np.arange(n)
    return u1, u2, t


def run(u1, u2, t, tdm, lanes=1, **kw):
    c = core.Core(core.Config(tdm=tdm, ENGINE_LANES=lanes, **kw))
    r = c.feed(u1, u2, strobes=t)
    return c, r


@pytest.mark.parametrize("lanes", [1, 2])
def test_tdm_period(lanes):
    c = CYCLES_BY_LANES[lanes]
    assert estimator.tdm_period(64, lanes) == 64 + 1 + c["update"] + c["extract"]
    assert estimator.tdm_period(64, 1) == 259              # the README's number
    with pytest.raises(ValueError):
        core.Core(core.Config(tdm=(2, 0, estimator.tdm_period(64, lanes) - 1, 64),
                              ENGINE_LANES=lanes))
    with pytest.raises(ValueError):
        core.Core(core.Config(tdm=(2, 2, estimator.tdm_period(64, lanes), 64)))


def test_one_axis_is_the_single_core():
    u1, u2, t = recording()
    _, ref = run(u1, u2, t, None)
    _, one = run(u1, u2, t, (1, 0, estimator.tdm_period(64), 64))
    for f in ("count", "a", "b", "fault"):
        assert (one[f] == ref[f]).all(), f
    assert one["n_updates"] == ref["n_updates"]


@pytest.mark.parametrize("axes,lanes,gaps", [(2, 1, False), (2, 2, True), (4, 1, False),
                                             (4, 1, True)])
def test_programs_start_in_the_window(axes, lanes, gaps):
    w = 64
    ln = estimator.tdm_period(w, lanes)
    period = axes * ln
    u1, u2, t = recording(gaps=gaps, seed=3)
    _, ref = run(u1, u2, t, None, lanes)
    cyc = CYCLES_BY_LANES[lanes]
    for i in range(axes):
        c, r = run(u1, u2, t, (axes, i, ln, w), lanes, period=3000)
        kinds = [k for k, _ in c.est.decided]
        assert kinds.count("update") > 300 and "extract" in kinds and "reset" in kinds
        last_end = None
        for kind, e in c.est.decided:
            off = (e - i * ln) % period
            if kind == "extract":
                assert e == last_end, (kind, e, last_end)   # chained on its UPDATE's end
            else:
                assert off < w, f"axis {i}: {kind} decided on edge {e}, {off} into the span"
            last_end = e + estimator.START_DELAY + cyc[kind]
            # it ends by the edge on which the next axis's window opens
            assert off + estimator.START_DELAY + cyc[kind] <= ln, (kind, e, off)
        uncal = (r["fault"] >> core.FAULT_BITS["uncal"]) & 1
        assert not uncal[-1], f"axis {i} never calibrated"
        # the schedule differs from the single core's, the count once calibrated does not
        assert r["n_updates"] < ref["n_updates"]
        cal = int(np.argmin(uncal)) + 2000
        assert np.abs(r["count"][cal:] - ref["count"][cal:]).max() <= 1


def test_window_period_shift():
    """An axis's results are a function of its own samples and the edge number modulo
    the window period: a shift of the strobes by axes L changes nothing."""
    w, axes = 64, 2
    ln = estimator.tdm_period(w)
    u1, u2, t = recording(seed=5, sig=siggen.Signal(A1=0.4, A2=0.45, phi=-0.1))
    _, a = run(u1, u2, t, (axes, 1, ln, w))
    _, b = run(u1, u2, t + axes * ln, (axes, 1, ln, w))
    for f in ("count", "a", "b", "fault"):
        assert (a[f] == b[f]).all(), f
