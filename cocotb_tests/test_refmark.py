"""Reference marks (rtl/refmark.v): homing over a mark, Z at the pins, the latch, pos_valid;
finequad_core against sim.model.finequad_core.run bit for bit, and independent checks of
the pins.

The recording (homing_recording()): an encoder (sim/siggen.py, PITCH units per signal
period, n = 25: 100 counts per period) calibrates on a move away from the mark, then
crosses a reference mark (a window of half a period around the mark's centre, from a
comparator whose threshold chatters, plus single-sample glitches away from the mark)
PASSES times, alternating direction, at peak speeds from creep (0.0002 period per sample)
to the paced pins' limit (div / ab_sep counts per sample), then dithers on the mark, rests
on it, moves off, loses the signal for 400 samples while creeping (amplitude x 0.03: the
count coasts, and with this noise its uncertainty passes a quarter period: pos_valid
falls) and crosses the mark once more. Homing is armed from the start (REF.home,
HOME = HOME_COUNT) and again (a REF.home write during the run) before that last pass. Three runs: 0.5 % noise with uniform strobes; 2 % noise with random
gaps between strobes (1 .. 30 clocks, bursts back to back); the Eq. 12 pulses on the pins
(ABGEN.ab_src = 1, 0.5 % noise, passes up to 0.4 counts per sample, as fast as the pulses
can follow), all on Verilator; Icarus runs the first on a shortened recording (LENGTH),
GHDL the second on the same shortened recording.

Checks:
* every sample: count, a, b, fault and z after t + 8, ref_count, homed and pos_valid after
  t + 10 equal the model's (sim/model/finequad_core.py timing);
* the model latched once per pass over the mark (counted from the true motion: the
  window's spans that cross the reference point), and every REF_COUNT after the first
  latch is HOME;
* the pins, decoded independently (an x4 decoder of m_a/m_b; m_z watched): Z high on at
  least one span per pass, every span exactly one count wide (no A/B edge while Z is
  high) and at the same decoded count every time;
* Z on every pass: a span rising between the pass's first sample and its last (plus the
  pins' lag);
* pos_valid falls at the loss (REF_STICKY.lost), stays 0 until the homing armed again
  latches on the last pass, and is 1 after it;
* REF_COUNT, REF_STATUS, REF_STICKY read back as the model ends.
"""
import dataclasses

import numpy as np
import pytest

import fqtb
from sim import siggen
from sim.model import finequad_core as core_model
from sim.model import regs

CORE_SOURCES = fqtb.core_sources()
PITCH = 20.0                 # position units per signal period
INTERP = 25                  # 100 counts per period
REF_Q = 37                   # the reference point: counts = 37 (mod 100)
HOME_COUNT = 1000
DIV = 36                     # clocks per sample (uniform run; the gaps run averages 15.5)
AB_SEP = 4                   # the pins' limit: DIV / AB_SEP = 9 counts per sample
PASSES = 20
MARK_AT = 20                 # the mark's signal period
WIDTH = 0.5 * PITCH          # the window
RUNS = {
    "n05": dict(noise=0.005, gaps=False),
    "n2_gaps": dict(noise=0.02, gaps=True),
    # the Eq. 12 pulses on the pins (ABGEN.ab_src = 1): they follow up to a quarter of an
    # n-th order period per sample (less with noise), so the passes peak at 0.4 counts per
    # sample
    "eq12": dict(noise=0.005, gaps=False, ab_src=1, vmax=0.004),
}
# the recording's length: Verilator the whole (32 000 samples), Icarus (some 30x slower) a
# short one: 6 passes, creep at 0.001 period per sample, shorter dither and rest; GHDL
# the short one too (10 553 samples)
LENGTH = {"verilator": dict(passes=PASSES, creep=0.0002, dwell=1.0),
          "icarus": dict(passes=6, creep=0.001, dwell=0.25),
          "ghdl": dict(passes=6, creep=0.001, dwell=0.25)}


def mark_centre():
    """The window's centre: half a count past the reference point (count REF_Q)."""
    return PITCH * (MARK_AT + (REF_Q + 0.5) / (4 * INTERP))


def _pass(x0, x1, v):
    """x0 -> x1 with a smooth (s-curve) move peaking at v units per sample."""
    n = max(8, int(np.ceil(2 * abs(x1 - x0) / v)))
    return siggen.s_curve(n, 1.0, x1 - x0, float(n), 0.0, x0)


def homing_recording(noise, passes=PASSES, creep=0.0002, dwell=1.0, vmax=None, seed=1):
    """(x, ref, events): the true position per sample, the reference input, and the
    sample ranges of the parts (dict)."""
    xc = mark_centre()
    half = 1.5 * PITCH                       # a pass runs from xc - half to xc + half
    parts, ev = [], {}

    def add(name, seg):
        start = sum(len(p) for p in parts)
        parts.append(np.asarray(seg, float))
        ev.setdefault(name, []).append((start, start + len(seg)))

    ncal = int(6000 * max(dwell, 0.5))
    add("calibrate", siggen.s_curve(ncal, 1.0, 12 * PITCH, ncal - 200.0, 100.0, 0.0))
    # peak speeds (periods per sample): by default up to the paced pins' limit (DIV /
    # AB_SEP counts per sample, less 5 %); every move is at most that fast
    if vmax is None:
        vmax = 0.95 * DIV / AB_SEP / (4 * INTERP)
    add("approach", _pass(12 * PITCH, xc - half, min(0.05, vmax) * PITCH))
    # two creep passes over 0.7 period at constant speed, then geometric up to vmax
    speeds = np.geomspace(min(0.002, vmax / 4), vmax, passes - 2)
    x = xc - half
    for i in range(passes):
        fwd = i % 2 == 0
        if i < 2:
            a, b = (xc - 0.35 * PITCH, xc + 0.35 * PITCH)
            add("to_creep", _pass(x, a if fwd else b, min(0.02, vmax) * PITCH))
            n = int(0.7 / creep)
            seg = np.linspace(a, b, n) if fwd else np.linspace(b, a, n)
            add("pass", seg)
            x = seg[-1]
        else:
            tgt = xc + half if fwd else xc - half
            if abs(x - tgt) < 1e-9:
                continue
            add("pass", _pass(x, tgt, speeds[i - 2] * PITCH))
            x = tgt
    # end the passes below the mark, then dither on it and rest there
    if x > xc:
        add("pass", _pass(x, xc - half, min(0.02, vmax) * PITCH))
    add("pass", _pass(xc - half, xc, min(0.01, vmax) * PITCH))     # the dither enters the window
    k = np.arange(int(2000 * dwell))
    add("dither", xc - 0.5 * PITCH / (4 * INTERP) + 0.03 * PITCH * np.sin(2 * np.pi * k / 200))
    add("rest", np.full(int(1000 * dwell), xc - 0.5 * PITCH / (4 * INTERP)))
    add("leave", _pass(xc - 0.5 * PITCH / (4 * INTERP), xc + 3 * PITCH, min(0.01, vmax) * PITCH))
    # creep during a signal loss (the count coasts until its uncertainty passes a quarter
    # period: pos_valid falls)
    add("loss", xc + 3 * PITCH + 0.0005 * PITCH * np.arange(600))
    add("final", _pass(xc + 3 * PITCH + 0.3 * PITCH, xc - half, min(0.02, vmax) * PITCH))
    x = np.concatenate(parts)
    lo, hi = ev["loss"][0]
    ref = siggen.reference(x, [xc], WIDTH, jitter=0.002 * PITCH, seed=seed)
    # single-sample glitches away from the mark (the filter takes them out)
    rng = np.random.default_rng(seed + 1)
    far = np.flatnonzero(np.abs(x - xc) > 2 * PITCH)
    ref[rng.choice(far, 20, replace=False)] ^= 1
    sig = siggen.Signal(noise=noise, dropout=((lo + 100, lo + 500, 0.03),))
    return x, ref, ev, sig


def expected_latches(x):
    """Spans of the noiseless window that cross the reference point (the count REF_Q
    boundary): one latch each."""
    xc = mark_centre()
    xr = xc - 0.5 * PITCH / (4 * INTERP)
    inside = np.abs(x - xc) <= WIDTH / 2
    edges = np.flatnonzero(np.diff(inside.astype(np.int8)))
    starts = [0] if inside[0] else []
    starts += [e + 1 for e in edges if inside[e + 1]]
    n = 0
    for s in starts:
        e = s
        while e < len(x) and inside[e]:
            e += 1
        seg = x[s:e]
        if seg.min() < xr <= seg.max():
            n += 1
    return n


def config(run):
    return core_model.Config(interp=INTERP, ab_sep=AB_SEP, ref_q=REF_Q, home_count=HOME_COUNT,
                             home_arm=True, div=DIV, ab_src=RUNS[run].get("ab_src", 0))


def recording(run, sim="verilator"):
    """(u1, u2, ref, t, x, ev) of a run, as long as the simulator runs it."""
    spec = RUNS[run]
    x, ref, ev, sig = homing_recording(spec["noise"], vmax=spec.get("vmax"), **LENGTH[fqtb.plan_sim(sim)])
    u1, u2, _ = siggen.encode(x, PITCH, sig, seed=7)
    n = len(x)
    if spec["gaps"]:
        rng = np.random.default_rng(3)
        gaps = rng.integers(1, 31, n)
        gaps[rng.random(n) < 0.2] = 1                 # bursts back to back
        t = 32 + np.concatenate([[0], np.cumsum(gaps[:-1])])
    else:
        t = core_model.strobe_edges(n, DIV)
    return u1, u2, ref, t, x, ev


def setup_writes(cfg):
    """The settings (register_writes), then REF with home = 1 (homing armed)."""
    w = core_model.register_writes(cfg)
    if cfg.home_arm:
        w.append((regs.REF, regs.word("REF", ref_q=cfg.ref_q, ref_filt=cfg.ref_filt,
                                      home=1)))
    return w


@pytest.mark.parametrize("run", list(RUNS))
# GHDL runs n2_gaps only (CI time: 21 s on the short recording, where n05 takes 40 s:
# some 15 clocks per sample against 36; the 2 % noise and the bursts where Icarus has
# n05's uniform strobes)
@pytest.mark.parametrize("sim", fqtb.simulators("finequad_core"))
def test_refmark(sim, run):
    if sim == "icarus" and run != "n05":
        pytest.skip(f"{run}: Verilator only (Icarus runs the 0.5 % run, shortened)")
    if fqtb.plan_sim(sim) == "ghdl" and run != "n2_gaps":
        pytest.skip(f"{run}: not on GHDL (GHDL runs n2_gaps, shortened)")
    fqtb.run_block(sim, "finequad_core", CORE_SOURCES, "test_refmark",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR), TABLE_EXACT=1),
                   extra_env=dict(RUN=run, SIM=sim), testcase="refmark_run")


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402

GRAY_UP = {(1, 1): 0, (0, 1): 1, (0, 0): 2, (1, 0): 3}


async def _watch(sig, log):
    from cocotb.triggers import ValueChange
    from cocotb.utils import get_sim_time
    while True:
        await ValueChange(sig)
        log.append((get_sim_time(unit="ps"), fqtb.uval(sig)))


def decode_z(logs, bench, start=0):
    """The pins decoded from their change logs: ([(edge Z rose, edge Z fell, decoded count
    at the rise, A/B edges while Z was high)], the edge of the first illegal A/B step or
    None); the decoder starts at (1, 1) = 0 and stops at an illegal step (both pins)
    after edge `start` (the Eq. 12 pulses jump from (1, 1) to the first sample's state)."""
    ev = []
    for ch in ("a", "b", "z"):
        for tm, v in logs[ch]:
            e, r = divmod(tm - bench.t0, fqtb.PERIOD_PS)
            assert r == 0, f"m_{ch} changed between clock edges (t={tm} ps)"
            ev.append((e, ch, v))
    ev.sort()
    ab, pos, z, spans, cur = (1, 1), 0, 0, [], None
    i = 0
    while i < len(ev):
        e = ev[i][0]
        chg = {}
        while i < len(ev) and ev[i][0] == e:
            chg[ev[i][1]] = ev[i][2]
            i += 1
        nxt = (chg.get("a", ab[0]), chg.get("b", ab[1]))
        if nxt != ab:
            step = (GRAY_UP[nxt] - GRAY_UP[ab]) % 4
            if step == 2 and e <= start:
                step = 0
            elif step == 2:
                return spans, e
            pos += {0: 0, 1: 1, 3: -1}[step]
            ab = nxt
            if cur is not None and "z" not in chg:
                cur[3] += 1
        if "z" in chg and chg["z"] != z:
            z = chg["z"]
            if z:
                cur = [e, None, pos, 0]
            else:
                cur[1] = e
                spans.append(tuple(cur))
                cur = None
    return spans, None


@cocotb.test()
async def refmark_run(dut):
    run = fqtb.env_str("RUN")
    sim = fqtb.env_str("SIM")
    u1, u2, ref, t, x, ev = recording(run, sim)
    n = len(u1)
    # homing armed again by a REF.home write before the last pass
    w_home = int(t[ev["final"][0][0]]) + 3
    cfg = dataclasses.replace(config(run), homes=[w_home])
    res = core_model.run(u1, u2, cfg, strobes=t, ref=ref)
    log = dut._log
    log.info("%s: %d samples, last strobe on edge %d, %d latches, %d Z samples", run, n,
             int(t[-1]), res["ref_latches"], int(res["z"].sum()))
    writes = dict(enumerate(setup_writes(cfg)))
    assert max(writes) < int(t[0])
    writes[w_home] = (regs.REF, regs.word("REF", ref_q=cfg.ref_q, ref_filt=cfg.ref_filt,
                                          home=1))
    got8 = np.zeros((n, 5), np.int64)
    got10 = np.zeros((n, 3), np.int64)
    bench = fqtb.ClockedBench(dut)
    for p in ("rst", "s_valid", "s_u1", "s_u2", "s_ref", "reg_we", "reg_re", "reg_addr",
              "reg_wdata"):
        getattr(dut, p).value = 0
    await bench.start()
    logs = {"a": [], "b": [], "z": []}
    for ch in logs:
        cocotb.start_soon(_watch(getattr(dut, f"m_{ch}"), logs[ch]))
    await bench.run_samples(t, u1, u2, ref, writes, {
        core_model.LATENCY: (lambda: (fqtb.sval(dut.m_count), fqtb.uval(dut.m_a),
                                      fqtb.uval(dut.m_b), fqtb.uval(dut.m_fault),
                                      fqtb.uval(dut.m_z)), got8),
        core_model.LATCH_AT: (lambda: (fqtb.sval(dut.m_ref_count), fqtb.uval(dut.m_homed),
                                       fqtb.uval(dut.m_pos_valid)), got10)})

    # ---- RTL == model, every sample ----------------------------------------------------------
    exp8 = np.stack([res["count"], res["a"], res["b"], res["fault"], res["z"]], axis=1)
    exp10 = np.stack([res["ref_count"], res["homed"], res["pos_valid"]], axis=1)
    for name, got, exp, cols in (("t + 8", got8, exp8, "count,a,b,fault,z"),
                                 ("t + 10", got10, exp10, "ref_count,homed,pos_valid")):
        diff = np.nonzero((got != exp).any(axis=1))[0]
        assert not len(diff), (
            f"{run}: {len(diff)} of {n} samples differ after {name} ({cols}), first: " +
            "; ".join(f"sample {k} (edge {int(t[k])}, ref {int(ref[k])}): rtl "
                      f"{tuple(int(v) for v in got[k])}, model {tuple(int(v) for v in exp[k])}"
                      for k in diff[:8]))

    # ---- the latch: once per pass, HOME every time ---------------------------------------------
    want = expected_latches(x)
    assert want >= LENGTH[fqtb.plan_sim(sim)]["passes"], want
    assert res["ref_latches"] == want, (f"{run}: {res['ref_latches']} latches, the motion "
                                        f"crossed the reference point in {want} passes")
    rc = np.asarray(res["ref_count"])
    first = int(np.argmax(res["homed"]))
    assert res["homed"][first] == 1 and np.all(rc[:first] == 0) and \
        np.all(rc[first:] == HOME_COUNT), f"{run}: REF_COUNT other than {HOME_COUNT}"

    # ---- the pins, decoded: Z one count wide, at one count --------------------------------------
    await bench.goto(bench.edge + 20 * AB_SEP * 100)
    spans, illegal = decode_z(logs, bench, start=int(t[0]) + core_model.AB_AT)
    if cfg.ab_src:
        # the pulses skip states in the signal loss: the passes before it are decoded
        lost_at = int(t[ev["loss"][0][0]])
        assert illegal is None or illegal >= lost_at, \
            f"{run}: the pulses made an illegal step on edge {illegal}, before the loss"
        want_spans = want - 1
    else:
        assert illegal is None, f"{run}: A and B both changed on edge {illegal}"
        want_spans = want
    assert len(spans) >= want_spans, f"{run}: {len(spans)} Z spans for {want} passes"
    rises = np.array([sp[0] for sp in spans])
    for s0, s1 in ev["pass"]:
        e0, e1 = int(t[s0]), int(t[min(s1, n - 1)]) + 20 * AB_SEP * 10
        assert np.any((rises >= e0) & (rises <= e1)), \
            f"{run}: no Z in the pass over samples {s0}..{s1}"
    wide = [s for s in spans if s[3]]
    assert not wide, f"{run}: Z high over A/B edges: {wide[:5]}"
    at = sorted({s[2] for s in spans})
    assert len(at) == 1, f"{run}: Z at decoded counts {at[:10]}"

    # ---- pos_valid: lost in the signal loss, back with the next pass ----------------------------
    lo, hi = ev["loss"][0]
    f0 = ev["final"][0][0]
    pv = np.asarray(res["pos_valid"])
    assert pv[lo - 1] == 1 and pv[hi - 1] == 0 and pv[f0:f0 + 10].max() == 0 and \
        pv[-1] == 1, (f"{run}: pos_valid {pv[lo - 1]} before the loss, {pv[hi - 1]} after "
                      f"it, {pv[f0:f0 + 10].max()} as the last pass starts, {pv[-1]} at the end")
    assert res["ref_losses"] == 1

    # ---- registers after the run ---------------------------------------------------------------
    bad = []
    for name, want_v in (
            ("REF_COUNT", HOME_COUNT & 0xFFFFFFFF),
            ("REF_STATUS", regs.word_read("REF_STATUS", win=0, homed=1, pos_valid=1,
                                          home_armed=0)),
            ("REF_STICKY", regs.word_read("REF_STICKY", latched=1, lost=1)),
            ("HOME", HOME_COUNT),
            ("REF", regs.word_read("REF", ref_q=REF_Q, ref_filt=cfg.ref_filt))):
        v = await bench.reg_read(regs.REGS[name].index)
        if v != want_v:
            bad.append(f"{name}: rtl {v:#x}, expected {want_v:#x}")
    assert not bad, f"{run}: " + "; ".join(bad)
    zc = sorted(at)[0]
    log.info("%s: %d samples equal; %d latches (REF_COUNT %d), %d Z spans, all one count wide "
             "at decoded count %d; pos_valid lost in the signal loss and back", run, n,
             res["ref_latches"], HOME_COUNT, len(spans), zc)
