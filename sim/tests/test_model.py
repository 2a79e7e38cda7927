"""The bit-true model against the float reference (tolerances live only here)."""
import pathlib
import sys

import numpy as np
import pytest

from sim import metrics, reference, siggen
from sim.model import program
from sim.model.rls_engine import RlsEngine

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))       # scripts/demo.py (its recording)


@pytest.mark.parametrize("amp", [0.1, 0.3, 0.6, 0.95])
def test_estimator_matches_float_reference(amp):
    """Same samples, same RLS (lambda = 1/(1 + 2**-k), the same trace bound): the extracted
    parameters agree, and the trace of P the engine reports is the float one's."""
    sig = siggen.Signal(A1=amp, A2=amp * 0.9, m1=0.02 * amp, m2=-0.01 * amp, phi=0.1,
                        noise=0.005)
    rng = np.random.default_rng(3)
    x = np.cumsum(rng.uniform(20, 200, 3000))          # nm, irregular progress
    u1, u2, _ = siggen.encode(x, 4000.0, sig, seed=4)
    g = max(c for c in range(4) if (max(np.abs(u1).max(), np.abs(u2).max()) * 2 ** c) < 2 ** 14
            ) if amp < 0.5 else 0
    est = RlsEngine()
    est.run("reset", kappa=64 << 8, dg=0)
    bound = (5 * (64 << 8)) >> 4              # the trace bound, as sim.model.finequad_core applies it
    ref = reference.Rls(lambda_k=8, kappa=64.0)
    for a, b in zip(u1, u2):
        a, b = int(a) << g, int(b) << g
        ok = est.run("update", x1=a, x2=b, lambda_k=8, freeze=int(est.out[6] >= bound))
        ref.update(a / 32768, b / 32768)
    assert ok
    assert est.run("extract")
    a1, r, m1, m2, phi = reference.extract(ref.theta)
    m1q, m2q, c1, c12, c2 = est.out[:5]
    s = 2.0 ** -g
    assert m1q / 32768 == pytest.approx(m1, abs=2e-4)        # normalised units
    assert m2q / 32768 == pytest.approx(m2, abs=2e-4)
    assert c1 / 4096 == pytest.approx(1 / a1, rel=2e-3)
    assert c12 / 4096 == pytest.approx(np.sin(phi) / (a1 * np.cos(phi)), abs=2e-3)
    assert c2 / 4096 == pytest.approx(r / (a1 * np.cos(phi)), rel=2e-3)
    # and the float reference found the true ellipse (in normalised units)
    assert a1 * s == pytest.approx(sig.A1, rel=0.01)
    assert est.out[6] / 16 == pytest.approx(np.trace(ref.P), rel=0.05, abs=0.1)


def assert_near_floor(r, x, a, sig, start, pitch=4000.0, interp=100, limit=1.3):
    s, _, _ = metrics.score(r["count"], x, siggen.angle_var(a, sig), pitch, interp, start)
    assert s["slips"] == 0, s
    assert s["ratio"] < limit, s


def test_program_is_hazard_free():
    """Every register read as operand A comes HAZARD_A slots after the write it depends on
    (the engine forwards to A), as operand B HAZARD_B slots after it; a dz is read after
    the NORM that writes it."""
    for name, entry in program.ENTRY.items():
        last_write = {}
        k = 0
        while True:
            f = program.decode(program.ROM[entry + k])
            if f["op"] == program.OP_END:
                break
            if f["op"] != program.OP_NOP:
                reads = [(f["a"], program.HAZARD_A)]
                if f["op"] == program.OP_MAC:
                    reads.append((f["b"], program.HAZARD_B))
                for r, hz in reads:
                    if r < 64 and r in last_write:
                        assert k - last_write[r] >= hz, (name, k, r)
                if f["wb"] and not f["out"]:
                    last_write[f["dst"]] = k
            k += 1


@pytest.mark.parametrize("amp,bits", [(0.1, 12), (0.1, 16), (0.95, 12), (0.95, 16)])
def test_core_works_from_10_to_95_percent_of_full_scale(amp, bits):
    """The whole core (bit-true model, proved equal to the RTL elsewhere) stays near the
    floor of METHOD.md with no slips, at the ends of the amplitude range."""
    from sim.model import finequad_core as core
    n = 250000
    x = siggen.s_curve(n, 1e6, 0.25e6, 0.1, t_start=0.01)
    x += siggen.s_curve(n, 1e6, -0.15e6, 0.08, t_start=0.14)
    sig = siggen.Signal(A1=amp * 0.97, A2=amp * 0.9, m1=0.03 * amp, m2=-0.02 * amp,
                        adc_bits=bits)
    u1, u2, a = siggen.encode(x, 4000.0, sig, seed=7)
    r = core.run(u1, u2, core.Config(ADC_W=bits))
    cal = np.nonzero(((r["fault"] >> core.FAULT_BITS["uncal"]) & 1) == 0)[0]
    assert len(cal), "never calibrated"
    assert_near_floor(r, x, a, sig, int(cal[0]) + 20000)


@pytest.mark.parametrize("bits", [12, 16])
def test_first_hand_over_waits_for_the_input_gain(bits):
    """At 10 % of full scale the warm-up's gain check raises the gain to 4; a theta fitted
    before it, at gain 1, needs coefficients near 10 (beyond s4.12), and its bundle mapped
    the signal to a radius near 0.27. It is not handed over: from the first hand-over on,
    the paper's table, whose index assumes the unit radius, counts without a slip within
    its linearisation error (the demo's recording, scripts/demo.py --amp 0.1)."""
    import demo
    from sim.model import finequad_core as core
    x, u1, u2, a, sig = demo.recording(0.5, 1, 0.1, bits)
    r = core.run(u1, u2, core.Config(TABLE="paper", ADC_W=bits), trace=True)
    cal = np.nonzero(((r["fault"] >> core.FAULT_BITS["uncal"]) & 1) == 0)[0]
    assert len(cal), "never calibrated"
    assert r["g"][cal[0]] == 2, "the first hand-over is at gain 4"
    assert_near_floor(r, x, a, sig, int(cal[0]), limit=3.5)


@pytest.mark.parametrize("div,f_over_fs", [(1, 1 / 128), (1, 3 / 128), (3, 3 / 128),
                                           (36, 1 / 14), (36, 3 / 56)])
def test_constant_speed_where_signal_and_update_rates_alias(div, f_over_fs):
    """Speeds where the signal period divides the update period (128 clocks): at a sample
    per clock and fs / 128 every update decided at the end of the last would see the same
    phase. The dither (estimator.dither: the candidate is strobed a random 0..DSPAN clocks
    after the decision) spreads the updates over the circle, and the fit is handed over
    (with the dither counted in samples, 0..15, the first three never handed over: the
    count stayed on the default coefficients, 1.3 to 1.4 times the floor)."""
    from sim.model import finequad_core as core
    n = 120000
    x = siggen.constant_speed(n, 1e6, f_over_fs * 1e6 * 4000.0)
    u1, u2, a = siggen.encode(x, 4000.0, siggen.Signal(), seed=3)
    r = core.run(u1, u2, core.Config(div=div))
    assert [k for _, k, _, c in r["sched"] if c is not None], "never handed over"
    assert_near_floor(r, x, a, siggen.Signal(), 30000)


def test_dither_covers_the_span_and_no_more():
    """dither(): every value 0..DSPAN occurs over the LFSR's period and none above: a
    candidate strobed at any of them is checked by the edge the UPDATE ends (one axis)
    or the axis's next window opens (a shared engine)."""
    from sim.model import estimator
    spans = []
    for lanes in (1, 2):
        cyc = estimator.CYCLES_BY_LANES[lanes]
        spans.append(estimator.dither_span(cyc))
        assert spans[-1] == cyc["update"] + estimator.START_DELAY - estimator.PHASE_STAGE
        for axes in (2, 4):
            ln = estimator.tdm_period(64, lanes)
            spans.append(estimator.dither_span(cyc, axes * ln))
            assert spans[-1] == axes * ln - estimator.PHASE_STAGE
    assert spans[0] == 120 and spans[3] == 79
    for span in spans + [1, 2, 64, 32767]:
        v, seen = estimator.LFSR_SEED, set()
        for _ in range(65535):
            seen.add(estimator.dither(v, span))
            v = estimator.lfsr_step(v)
        assert v == estimator.LFSR_SEED and seen == set(range(span + 1)), span
    with pytest.raises(ValueError, match="dither span 32768"):
        estimator.dither_span({"update": 0}, 32768 + estimator.PHASE_STAGE)


def test_shared_engine_axis_calibrates_where_its_update_period_aliases():
    """Two axes on one engine (rtl/finequad_multi.v): an axis decides its UPDATE in its
    window, one every 2 L = 518 clocks, so its dither must span that period: at a signal
    period of 518 clocks (36 clocks per sample) a dither over one UPDATE (120 clocks)
    saw a fixed arc and never handed over."""
    from sim.model import estimator
    from sim.model import finequad_core as core
    ln = estimator.tdm_period(64)
    n, div = 30000, 36
    x = siggen.constant_speed(n, 1e6, div / (2 * ln) * 1e6 * 4000.0)
    u1, u2, a = siggen.encode(x, 4000.0, siggen.Signal(), seed=3)
    r = core.run(u1, u2, core.Config(div=div, tdm=(2, 0, ln, 64)))
    assert [k for _, k, _, c in r["sched"] if c is not None], "never handed over"
    assert_near_floor(r, x, a, siggen.Signal(), 15000)


def test_servo_dither_over_a_short_arc_does_not_corrupt_the_correction():
    """Holding position with +-600 nm of dither (+-54 degrees of a 4 um period) for 0.35 s:
    the updates see only a short arc, the fit drifts, and it must not be applied (only
    updates covering all eight octants since the last hand-over are)."""
    from sim.model import finequad_core as core
    fs, n = 1e6, 500000
    t = np.arange(n) / fs
    x = siggen.s_curve(n, fs, 0.2e6, 0.1, t_start=0.01)
    x = x + np.where(t > 0.12, 600 * np.sin(2 * np.pi * 50 * (t - 0.12)), 0)
    u1, u2, a = siggen.encode(x, 4000.0, siggen.Signal(), seed=5)
    r = core.run(u1, u2, core.Config())
    # the move hands fits over (the scan sees them); the dither none (a fit of its arc
    # would be handed over about 1400 times without the eight-octant rule)
    commits = [k for _, k, _, c in r["sched"] if c is not None]
    assert commits and min(commits) < 110000, "no hand-over during the move"
    assert not [k for k in commits if k >= 120000], "a fit of the dither's arc was handed over"
    assert_near_floor(r, x, a, siggen.Signal(), 400000)


def _run_scenario(name, **cfg):
    from sim import scenarios
    from sim.model import finequad_core as core
    sc = scenarios.by_name([name])[0]
    u1, u2, a = sc.codes()
    r = core.run(u1, u2, core.Config(ADC_W=sc.sig.adc_bits, **cfg))
    s, err, _ = metrics.score(r["count"], sc.x, siggen.angle_var(a, sc.sig), 4000.0, 100,
                              sc.start(), a=a)
    return sc, r, s, err


def test_sudden_jump_is_detected_and_the_fit_reconverges_within_a_period_or_so():
    sc, r, s, err = _run_scenario("drift_jump")
    (k,) = sc.events
    assert len(r["jumps"]) == 1 and k <= r["jumps"][0] < k + 200, r["jumps"]
    conv = metrics.convergence_periods(err, sc.x, 4000.0, s["floor_nm"], k, window=200)
    assert conv is not None and conv <= 1.5
    # without the detector the forgetting alone takes many periods
    _, r0, s0, err0 = _run_scenario("drift_jump", jump_off=1)
    assert r0["jumps"] == []
    conv0 = metrics.convergence_periods(err0, sc.x, 4000.0, s0["floor_nm"], k, window=200)
    assert conv0 is None or conv0 > 4 * conv


@pytest.mark.parametrize("name", ["constant", "noise2", "reversals"])
def test_no_false_jumps(name):
    _, r, _, _ = _run_scenario(name)
    assert r["jumps"] == []


def test_residual_is_written_early_enough_for_the_pipelined_jump_detector():
    """rtl/estimator.v registers |e| -> means -> trigger over three edges and uses the
    trigger on the UPDATE's END: OUT E must be written at least three slots before END."""
    entry = program.ENTRY["update"]
    k = 0
    e_slot = None
    while True:
        f = program.decode(program.ROM[entry + k])
        if f["op"] == program.OP_END:
            break
        if f["wb"] and f["out"] and f["dst"] == program.OUTS["E"]:
            e_slot = k
        k += 1
    assert e_slot is not None and k - e_slot >= 3 + 1


def test_feeding_in_pieces_equals_one_run():
    """core.Core.feed keeps the whole state: a recording fed in pieces of random lengths
    (with a reset request and harmonic learning in it) gives exactly the per-sample
    results and the estimator schedule of one run over the whole."""
    from sim.model import finequad_core as core
    n = 60000
    x = siggen.s_curve(n, 1e6, 0.12e6, 0.05, t_start=0.005)
    u1, u2, _ = siggen.encode(x, 4000.0, siggen.Signal(h3=0.01), seed=11)
    cfg = core.Config(resets=[31000], harm_clears=[32 + 36 * 45000])
    whole = core.run(u1, u2, cfg)
    c = core.Core(cfg)
    rng = np.random.default_rng(5)
    cuts = np.sort(rng.choice(np.arange(1, n), 40, replace=False))
    parts = [c.feed(u1[a:b], u2[a:b]) for a, b in zip([0, *cuts], [*cuts, n])]
    for key in ("count", "a", "b", "fault"):
        assert np.array_equal(np.concatenate([p[key] for p in parts]), whole[key]), key
    assert c.schedule_samples() == whole["sched"]
    assert parts[-1]["jumps"] == whole["jumps"]
    assert parts[-1]["n_updates"] == whole["n_updates"]
    assert any(kind == "reset" and k >= 31000 for kind, k, _, _ in whole["sched"])


def test_recording_csv_round_trip_and_output_columns(tmp_path):
    """The CSV contract of `make model` (sim/run_model.py, as the harness's): write_codes
    and read_codes round-trip 'u1,u2' (ref None: every sample's ref 0) and 'u1,u2,ref';
    the output has the harness's columns, each the result key of that name, and the
    model's run with a column of zeros equals the one without the column."""
    from sim import run_model
    from sim.model import finequad_core as core
    u1 = np.array([1000, -2000, 30000, -32768], np.int64)
    u2 = np.array([-5, 7, 0, 32767], np.int64)
    ref = np.array([0, 1, 1, 0], np.int64)
    run_model.write_codes(tmp_path / "a.csv", u1, u2)
    run_model.write_codes(tmp_path / "b.csv", u1, u2, ref)
    assert (tmp_path / "b.csv").read_text().splitlines()[:2] == ["u1,u2,ref", "1000,-5,0"]
    a1, a2, ar = run_model.read_codes(str(tmp_path / "a.csv"))
    b1, b2, br = run_model.read_codes(str(tmp_path / "b.csv"))
    assert ar is None and br.dtype == np.int64 and np.array_equal(br, ref)
    assert all(np.array_equal(x, y) for x, y in ((a1, u1), (a2, u2), (b1, u1), (b2, u2)))
    with pytest.raises(ValueError):
        run_model.write_codes(tmp_path / "c.csv", u1, u2, ref[:3])
    assert run_model.COLUMNS == ("count", "a", "b", "fault", "z", "ref_count", "homed",
                                 "pos_valid")
    res = core.run(u1, u2, core.Config(), ref=ref)
    run_model.write_result(tmp_path / "out.csv", res)
    rows = (tmp_path / "out.csv").read_text().splitlines()
    assert rows[0] == ",".join(run_model.COLUMNS) and len(rows) == len(u1) + 1
    assert rows[1] == ",".join(str(int(res[c][0])) for c in run_model.COLUMNS)
    zero = core.run(u1, u2, core.Config(), ref=np.zeros(4, np.int64))
    none = core.run(u1, u2, core.Config())
    assert all(np.array_equal(zero[c], none[c]) for c in run_model.COLUMNS)
