"""Reference marks in the model (sim/model/refmark.py, rtl/refmark.v's rules): the latch at
every speed and in both directions, the glitch filter, homing, pos_valid, and what takes
no reference. The RTL is held to the model by cocotb_tests/test_refmark.py."""
import dataclasses

import numpy as np

from sim import siggen
from sim.model import finequad_core as core

PITCH = 20.0
N = 25                        # 100 counts per signal period
REF_Q = 61
CAL = 6000                    # samples of the calibrating move


def centre():
    return PITCH * (20 + (REF_Q + 0.5) / (4 * N))


LEAD = CAL + 2000             # samples before x (run())


def edge_of(i):
    """The strobe edge of x's sample i in run() (the model's uniform strobes)."""
    return int(core.strobe_edges(LEAD + i + 1, core.Config().div)[-1])


def run(x, ref=None, noise=0.005, seed=0, dropout=None, **cfg):
    """The model on positions x (after a calibrating move from 0 to 12 periods, whose
    samples are dropped from the result), the reference input of a mark at centre();
    dropout: (first, stop, level) over x's samples."""
    cal = siggen.s_curve(CAL, 1.0, 12 * PITCH, CAL - 200.0, 100.0, 0.0)
    lead = np.linspace(12 * PITCH, x[0], LEAD - CAL)
    xx = np.concatenate([cal, lead, x])
    if ref is None:
        ref = siggen.reference(xx, [centre()], 0.5 * PITCH, seed=seed)
    else:
        ref = np.concatenate([np.zeros(len(xx) - len(x), np.int64), ref])
    drop = () if dropout is None else ((dropout[0] + LEAD, dropout[1] + LEAD, dropout[2]),)
    u1, u2, _ = siggen.encode(xx, PITCH, siggen.Signal(noise=noise, dropout=drop), seed=seed)
    c = dict(interp=N, ref_q=REF_Q)
    c.update(cfg)
    res = core.run(u1, u2, core.Config(**c), ref=ref)
    k = LEAD
    return {key: (v[k:] if isinstance(v, np.ndarray) and len(v) == len(xx) else v)
            for key, v in res.items()}


def passes(speeds, half=1.5):
    """Back and forth over the mark, one smooth move (s-curve, its peak speed over the
    mark) per speed (periods per sample), alternating direction, starting below it; the
    faster passes run longer (the signal monitor flags a glitch at accelerations of some
    0.02 periods per sample squared)."""
    xc = centre()
    parts, x = [], xc - half * PITCH
    for i, v in enumerate(speeds):
        h = max(half, 30 * v)
        tgt = xc + h * PITCH if i % 2 == 0 else xc - h * PITCH
        n = int(np.ceil(2 * abs(tgt - x) / (v * PITCH)))
        parts.append(siggen.s_curve(n + 1, 1.0, tgt - x, float(n), 0.0, x)[1:])
        parts.append(np.full(50, tgt))
        x = tgt
    return np.concatenate([np.full(100, xc - half * PITCH)] + parts)


def test_one_latch_per_pass_same_count_at_every_speed():
    """Constant-speed passes, both directions: one latch per pass, all at the same count,
    which is = ref_q (mod 4 n). The sample that crosses the reference point must lie in
    the window, whose half is a quarter period here, and the filter opens it only after
    ref_filt + 1 samples inside: the stage must move less than w / 2 / max(1, ref_filt)
    per sample (w the window). Without the filter from 0.0005 to 0.22 periods per
    sample, with ref_filt = 2 up to 0.1."""
    for filt, top in ((0, 0.22), (2, 0.1)):
        speeds = np.geomspace(0.0005, top, 16)
        r = run(passes(speeds), ref_filt=filt)
        assert r["ref_latches"] == len(speeds), (filt, r["ref_latches"])
        rc = sorted(set(r["ref_count"].tolist()) - {0})
        assert len(rc) == 1 and rc[0] % (4 * N) == REF_Q, rc
        assert r["homed"][-1] == 1 and not r["pos_valid"].any()    # (no homing)
    # past that speed the filtered window misses the reference point
    r = run(passes([0.3, 0.3]), ref_filt=2)
    assert r["ref_latches"] == 0


def test_dither_and_rest_on_the_mark_latch_once():
    """A stage dithering across the reference point inside the window, then at rest on
    it with 2 % noise: one latch; Z comes and goes with the pins at the one count."""
    xr = centre() - 0.5 * PITCH / (4 * N)
    k = np.arange(6000)
    x = np.concatenate([np.linspace(xr - 1.5 * PITCH, xr - 0.1 * PITCH, 1500),
                        xr - 0.1 * PITCH * np.cos(2 * np.pi * k / 300) * (k < 3000)
                        + 0 * k])
    x[1500 + 3000:] = xr
    r = run(x, noise=0.02)
    assert r["ref_latches"] == 1
    z = r["z"]
    rises = int(np.sum((z[1:] == 1) & (z[:-1] == 0)))
    assert rises >= 10, rises


def test_glitch_filter():
    """The window opens once the input has been 1 on ref_filt + 1 consecutive samples: a
    pulse of that length ending on the sample that crosses the reference point latches
    there, one sample shorter opens nothing."""
    xc = centre()
    x = np.linspace(xc - PITCH, xc + PITCH, 2001)       # 0.001 period per sample
    wide = run(x, ref=np.ones(len(x), np.int64), ref_filt=0)
    k = int(np.argmax(wide["homed"]))                    # the first crossing
    assert wide["ref_latches"] == 1 and k > 20
    for filt in (0, 2, 7, 15):
        for length, latched in ((filt + 1, 1), (filt, 0)):
            ref = np.zeros(len(x), np.int64)
            ref[k + 1 - length:k + 1] = 1
            r = run(x, ref=ref, ref_filt=filt)
            assert r["ref_latches"] == latched, (filt, length, r["ref_latches"])
            if latched:
                assert int(np.argmax(r["homed"])) == k


def test_homing_sets_the_count_not_the_pins():
    """With homing armed, the count reads HOME at the reference and moves with the stage
    as before (the offset HOME - x from then on); the A/B pins and Z are those of the run
    without homing; REF_COUNT = HOME at every latch."""
    x = passes([0.01, 0.02, 0.05])
    plain = run(x)
    homed = run(x, home_arm=True, home_count=-123456)
    x0 = sorted(set(plain["ref_count"].tolist()) - {0})[0]
    k = int(np.argmax(homed["homed"]))
    for key in ("a", "b", "z", "homed"):
        assert np.array_equal(plain[key], homed[key]), key
    assert not plain["pos_valid"].any() and homed["pos_valid"][k:].all()
    assert np.all(homed["ref_count"][k:] == -123456)
    off = homed["count"][k + 3:] - plain["count"][k + 3:]
    assert np.all(off == -123456 - x0), set(off.tolist())


def test_no_reference_outside_the_period_in_edge_mode_or_overspeed():
    """ref_q >= 4 n is never reached; the edge-mode count is not B + q (no reference,
    pos_valid stays 0); a pass at 0.4 periods per sample (overspeed) takes none."""
    x = passes([0.01, 0.02])
    r = run(x, ref_q=4 * N)
    assert r["ref_latches"] == 0 and not r["z"].any() and not r["homed"].any()
    r = run(x, count_mode=1)
    assert r["ref_latches"] == 0 and not r["pos_valid"].any()
    xc = centre()
    fast = np.arange(xc - 3 * PITCH, xc + 3 * PITCH, 0.4 * PITCH)
    r = run(np.concatenate([np.full(200, fast[0]), fast, np.full(200, fast[-1])]))
    assert r["ref_latches"] == 0


def test_pos_valid_set_by_homing_cleared_by_a_lost_coast_or_overspeed():
    """pos_valid: 1 from the homing latch; a signal loss of 600 samples at rest away from
    the mark (the count coasts; with 0.5 % noise its uncertainty passes a quarter period
    after some 280 samples) clears it (REF_STICKY.lost) and a later pass does not set it
    again; a new REF.home write before the next pass does. An overspeed step clears it
    too."""
    x = passes([0.02, 0.02])
    xr = x[-1]
    rest = np.full(3000, xr)
    again = passes([0.02, 0.02])
    xx = np.concatenate([x, rest, again])
    lo = len(x) + 1000
    plain = run(xx, home_arm=True, dropout=(lo, lo + 600, 0.02))
    mon_hold = plain["fault"] >> core.FAULT_BITS["loss"] & 1
    assert mon_hold[lo:lo + 600].any() and not mon_hold[:lo].any()
    pv = plain["pos_valid"]
    assert pv[lo - 1] == 1 and pv[lo + 600:].max() == 0 and plain["ref_losses"] == 1
    assert plain["ref_latches"] == 4
    rearmed = run(xx, home_arm=True, dropout=(lo, lo + 600, 0.02),
                  homes=[edge_of(len(x) + 2000)])
    assert rearmed["pos_valid"][-1] == 1 and rearmed["pos_valid"][lo + 600] == 0
    assert set(rearmed["ref_count"][len(x):].tolist()) <= {0, core.Config().home_count}
    # a smooth move peaking at 0.42 period per sample: overspeed flags, no hold
    fast = siggen.s_curve(400, 1.0, 80 * PITCH, 380.0, 10.0, xr)
    r = run(np.concatenate([x, np.full(100, xr), fast]), home_arm=True)
    ovs = r["fault"] >> core.FAULT_BITS["ovs"] & 1
    held = r["fault"] & sum(1 << core.FAULT_BITS[b] for b in ("loss", "stuck", "glitch"))
    assert ovs.any() and not held.any()
    assert r["pos_valid"][len(x) + 99] == 1 and r["pos_valid"][-1] == 0
    assert r["ref_losses"] == 1


def test_feed_in_pieces_equals_one_run():
    """The reference state carries across Core.feed pieces (as the rest of the core), also
    with samples on consecutive edges (a piece's last results show after the next begins)."""
    x = passes([0.003, 0.05, 0.2, 0.01])
    xx = np.concatenate([siggen.s_curve(CAL, 1.0, 12 * PITCH, CAL - 200.0, 100.0, 0.0),
                         np.linspace(12 * PITCH, x[0], 2000), x])
    ref = siggen.reference(xx, [centre()], 0.5 * PITCH, jitter=0.01 * PITCH, seed=2)
    u1, u2, _ = siggen.encode(xx, PITCH, siggen.Signal(noise=0.01), seed=2)
    cfg = core.Config(interp=N, ref_q=REF_Q, home_arm=True, home_count=77, div=1)
    whole = core.run(u1, u2, cfg, ref=ref)
    c = core.Core(dataclasses.replace(cfg))
    k = int(np.argmax(whole["homed"]))                  # cut right after the homing latch
    cuts = np.unique(np.concatenate([
        np.random.default_rng(1).choice(np.arange(1, len(xx)), 30, replace=False),
        [k + 1, k + 2, k + 3]]))
    parts = [c.feed(u1[a:b], u2[a:b], ref=ref[a:b])
             for a, b in zip([0, *cuts], [*cuts, len(xx)])]
    for key in ("count", "a", "b", "z", "ref_count", "homed", "pos_valid"):
        assert np.array_equal(whole[key], np.concatenate([p[key] for p in parts])), key
    assert whole["ref_latches"] == 4
