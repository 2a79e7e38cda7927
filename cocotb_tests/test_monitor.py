"""monitor (signal faults, the counter's hold, the travel) against sim.model.monitor.

Timing (rtl/monitor.v; edges after a sample's strobe edge t in the core): ref_i is
sampled on t (presented before edge t, as the bundle flags are), valid0_i with raw1_i,
raw2_i and clip_i on t + 1, ax_i, ay_i, xn_i, yn_i on t + 3, pvalid_i with phase_i on t + 7; hold_o and excl_o
are combinational while pvalid_i is high (read in the slot before edge t + 7), loss_o,
over_o, stuck_o, glitch_o and travel_o change on t + 7. Off its edge every input carries
random garbage (the valid inputs low), so a block that samples an input on the wrong edge
fails; hold_o and excl_o must be low in every slot without a sample.

Stimulus: segments of a generated encoder (12-bit codes aligned to s1.15, the corrected
magnitudes with a radius of 1 +- noise in s2.14, the fine phase of the motion), back to
back or with idle gaps, each with its own register settings, changed only while no sample
is in flight (the model takes them per sample): motion at several speeds up to 0.45 of a
period per sample, standstill with toggling codes (no stuck flag: no travel), a channel
frozen while the stage moves (stuck), a channel on the rail (clip), occasional clipped
codes, the radius dropping below LOSS and rising above
OVER (also for longer than OVER_PERSIST samples, when over-range is let in to the
estimator again), single-sample phase glitches, contiguous dropouts below COAST.floor (the count coasts:
the stage speeding up meanwhile, so the line drifts off it; noisy steps, so the
velocity's spread alone loses the travel; a large coast_acc, so the acceleration bound
does), the checks off (0 thresholds), radius
checks disarmed (ref low), and an rst in the middle. sv_i strobes each sample's bundle
(g, c1, c2) and the code step (the stuck spans) on t, the bundle drawn per segment and
changed now and then inside one (a new bundle takes new snapshots). Every output of every sample equals
the model's (the coast and its line, lost); each fault kind, a coast and a lost travel
must have been raised. With OPT_MONITOR = 0 (Verilator, GHDL) the
same stimulus against Monitor(enabled=False): no flag and no hold, only clipped samples
excluded, the travel following every sample; the full model raises every flag there."""
import math
import random

import pytest

import fqtb


# GHDL (the VHDL edition) runs OPT_MONITOR=1 at SCALE=4 like Verilator, OPT_MONITOR=0 at
# SCALE=1 (the same plan with a quarter of the samples: GHDL is the slowest, CI's time)
@pytest.mark.parametrize("opt", [1, 0])
@pytest.mark.parametrize("sim", fqtb.simulators("monitor"))
def test_monitor(sim, opt):
    if not opt and sim == "icarus":
        pytest.skip("OPT_MONITOR=0 runs on Verilator and GHDL")
    scale = 1 if sim == "icarus" or (fqtb.is_vhdl(sim) and not opt) else 4
    fqtb.run_block(sim, "monitor", fqtb.sources("monitor"), "test_monitor",
                   parameters=dict(OPT_MONITOR=opt),
                   extra_env=dict(SCALE=scale, OPT_MONITOR=opt))


# ---- stimulus (importable without a simulator) -------------------------------------------
T_REF, T_RAW, T_MAG, T_PH = 0, 1, 3, 7      # edges sampling each input, after strobe t
ADC_SH = 4                                   # 12-bit codes aligned to 16 bits
ADC_W = 16                                   # the block's ADC_W (its default)


def motion(rng, kind, length, phi0, amp):
    """Per sample (r1, r2, ax, ay, xn, yn, phase, clip) of one segment."""
    out = []
    phi = phi0
    v = {"slow": 3.0, "creep": 0.05, "fast": 3600.0, "stand": 0.0,
         "stuck2_rebase": 10.0, "stuck1_fast": 450.0}.get(kind, 40.0)
    v *= rng.choice((1, -1))
    frozen = None
    for i in range(length):
        if kind == "mix":
            v = max(-3600.0, min(3600.0, v + rng.gauss(0, 30)))
        if kind == "dropout_accel" and i == length // 2:
            v *= 1.6                               # the stage speeds up while it is lost
        phi += v + (rng.gauss(0, 20 if kind == "dropout_noisy" else 2)
                    if kind != "creep" else 0.0)
        a = 2 * math.pi * phi / 8192
        noise = rng.gauss(0, 0.6) if kind == "stand" else rng.gauss(0, 0.3)
        r1 = int(round(amp * math.cos(a) + noise)) << ADC_SH
        r2 = int(round(amp * math.sin(a) + noise)) << ADC_SH
        rad = 1.0 + rng.gauss(0, 0.01)
        if kind == "loss" and length // 4 <= i < 3 * length // 4:
            rad = rng.uniform(0.02, 0.25)
        if kind.startswith("dropout") and length // 3 <= i < 2 * length // 3:
            rad = rng.uniform(0.02, 0.04)          # below floor throughout: a coast
        if kind in ("over", "over_long") and length // 8 <= i:
            rad = rng.uniform(1.45, 1.9)
        if kind.startswith("stuck") and i >= length // 5:
            frozen = frozen if frozen is not None else (r1, r2)
            r1, r2 = (frozen[0], r2) if kind.startswith("stuck1") else (r1, frozen[1])
        clip = rng.random() < 0.01
        if kind == "rail" and length // 3 <= i < 2 * length // 3:
            r1, clip = 2047 << ADC_SH, True
        ph = int(phi) % 8192
        if kind == "stuck1_fast":                  # the phase of the codes: distorted
            ph = int(math.atan2(r2, r1) * 8192 / (2 * math.pi)) % 8192
        if kind == "glitch" and rng.random() < 0.05:
            ph = (ph + rng.choice((1, -1)) * rng.randint(300, 4000)) % 8192
        ax = min(32767, int(round(abs(math.cos(a)) * rad * 16384)))
        ay = min(32767, int(round(abs(math.sin(a)) * rad * 16384)))
        out.append((r1, r2, ax, ay, int(math.cos(a) < 0), int(math.sin(a) < 0), ph,
                    int(clip)))
    return out, phi


def plan(scale):
    """(kind, length, ref, registers (loss, over, glitch_k, stuck_n, code_step, floor,
    coast_acc), before) segments; before: None, 'drain' or 'rst'."""
    d = (3277, 22118, 10, 8, 0, 2048, 16)
    return [
        ("slow", 300 * scale, 0, d, None),          # from power-up, radius checks off
        ("mix", 400 * scale, 1, d, "drain"),
        ("loss", 300 * scale, 1, d, None),
        ("stand", 400 * scale, 1, d, None),
        ("stuck1", 300 * scale, 1, d, None),
        ("slow", 100 * scale, 1, d, None),
        ("stuck2", 300 * scale, 1, (3277, 22118, 10, 3, 0, 2048, 16), "drain"),
        ("stuck1_wide", 300 * scale, 1, (3277, 22118, 10, 8, 8, 2048, 16), "drain"),  # span 8128
        ("stuck1_fast", 300 * scale, 1, d, "drain"),     # the shadow line parts: lost
        ("loss", 300 * scale, 1, (3277, 22118, 10, 8, 0, 4000, 4095), "drain"),  # lost soon
        ("loss", 200 * scale, 1, (3277, 22118, 10, 8, 0, 0, 0), "drain"),  # counted through
        ("dropout_accel", 300 * scale, 1, d, "drain"),       # the line drifts off the stage
        ("dropout_noisy", 400 * scale, 1, (3277, 22118, 10, 8, 0, 2048, 0), "drain"),
        ("dropout", 300 * scale, 1, (3277, 22118, 10, 8, 0, 2048, 4095), "drain"),
        ("stuck2_rebase", 300 * scale, 1, d, "drain"),   # a new bundle after the freeze
        ("glitch", 400 * scale, 1, d, None),
        ("rail", 300 * scale, 1, d, None),
        ("over", 300 * scale, 1, d, None),
        ("fast", 300 * scale, 1, d, None),
        ("over_long", 4500 + 200 * scale, 1, d, None),
        ("glitch", 300 * scale, 1, (0, 65535, 0, 0, 8, 0, 0), "drain"),  # every check off
        ("loss", 200 * scale, 0, d, "drain"),                       # disarmed
        ("creep", 300 * scale, 1, (8000, 20000, 8, 255, 4, 3000, 100), "rst"),
        ("glitch", 300 * scale, 1, (5000, 19000, 11, 1, 2, 2048, 16), "drain"),
        ("glitch", 200 * scale, 1, (5000, 19000, 12, 1, 6, 2048, 16), "drain"),  # K >= 12
        ("glitch", 200 * scale, 1, (5000, 19000, 1, 1, 8, 2048, 16), "drain"),
        ("mix", 300 * scale, 1, d, None),
    ]


# bundles (g, c1, c2) for the stuck spans: the reset one (span 2048), a calibrated 60 %
# signal, gains and coefficients up to the spans' cap, a zero and the most negative c
BUNDLE0 = (0, 8192, 8192)
BUNDLE_WIDE = (0, 6827, 6827)       # a 60 % signal: with code step 8 the span is 8128
BUNDLES = (BUNDLE0, (0, 6827, -7500), (1, 16384, 13000), (3, -32768, 0), (2, 30000, 20000),
           (0, 1, 3), (0, 100, 4096))


def build(scale, seed=5):
    """Samples in strobe order: dicts with t, the inputs, ref, regs; the rst edges."""
    rng = random.Random(seed)
    samples, resets = [], []
    t = 1
    phi = 0.0
    for si, (kind, length, ref, regs, before) in enumerate(plan(scale)):
        if samples and before is None and regs != samples[-1]["regs"]:
            before = "drain"                           # settings change: none in flight
        if before is not None and samples:
            t = samples[-1]["t"] + T_PH + 3            # drained
            if before == "rst":
                resets.append(t)
                t += 2
        amp = rng.choice((900, 1500, 2000))
        seg, phi = motion(rng, kind, length, phi, amp)
        # the bundle (g, c1, c2): the reset one where a channel freezes (its stuck flag
        # must rise; with code step 8 a wide span, or a new bundle 12 samples after the
        # freeze: a rebase), else drawn, and changed now and then inside the segment
        bundle = {"stuck1_wide": BUNDLE_WIDE}.get(kind, BUNDLE0) if kind.startswith("stuck") \
            else rng.choice(BUNDLES)
        for i, (r1, r2, ax, ay, xn, yn, ph, clip) in enumerate(seg):
            t += rng.choice((0, 0, 0, 0, 1, 2, 5))
            if not kind.startswith("stuck") and rng.random() < 0.01:
                bundle = rng.choice(BUNDLES)
            if kind == "stuck2_rebase" and i == length // 5 + 12:
                bundle = (0, 8300, 8100)
            samples.append(dict(t=t, seg=si, kind=kind, r1=r1, r2=r2, ax=ax, ay=ay,
                                xn=xn, yn=yn, phase=ph, clip=clip, ref=ref, regs=regs,
                                bundle=bundle))
            t += 1
    return samples, resets


def model(samples, resets, enabled=True, span=None, rebase=True, part=True):
    """Per sample (hold, excl, loss, over, stuck, glitch, travel, coast, line, lost) from
    sim.model.monitor,
    epoch by epoch (rst restarts the state); enabled: OPT_MONITOR. span (every span
    forced to it), rebase=False and part=False (a shadow line never parts from the line)
    are mutations: the stimulus must tell them apart."""
    from sim.model import monitor
    from sim.model.monitor import Monitor, MonitorRegs, stuck_span
    if not part:
        try:
            monitor.PART_SH, sh0 = 16, monitor.PART_SH
            return model(samples, resets, enabled, span, rebase)
        finally:
            monitor.PART_SH = sh0
    out = []
    mon = Monitor(enabled)
    ri = 0
    for x in samples:
        while ri < len(resets) and resets[ri] < x["t"] + T_RAW:
            mon = Monitor(enabled)
            ri += 1
        loss, over, glitch_k, stuck_n, code_step, floor, coast_acc = x["regs"]
        regs = MonitorRegs(loss=loss, over=over, glitch_k=glitch_k, stuck_n=stuck_n,
                           floor=floor, coast_acc=coast_acc)
        g, c1, c2 = x["bundle"]
        sh = 16 - ADC_W + code_step + g
        f = mon.step(x["r1"], x["r2"], x["ax"], x["ay"], x["xn"], x["yn"], x["phase"],
                     x["ref"], x["clip"], regs, (span, span) if span else
                     (stuck_span(c1, sh), stuck_span(c2, sh)),
                     x["bundle"] if rebase else (0, 0, 0))
        out.append((int(f.hold), int(f.excl), int(f.loss), int(f.over), int(f.stuck),
                    int(f.glitch), mon.travel(), int(f.coast), f.line, int(f.lost)))
    return out


@pytest.mark.parametrize("scale", [1, 4])
def test_stimulus_makes_spans_and_rebase_visible(scale):
    """The stimulus tells the stuck spans, the rebase and the parted shadow line apart:
    the model's outputs change when every span is 2048 (the old fixed span) or 32767,
    without the rebase, and when a shadow line never parts, so an RTL with such a bug
    fails test_monitor."""
    samples, resets = build(scale)
    want = model(samples, resets)
    for mutant in (dict(span=2048), dict(span=32767), dict(rebase=False), dict(part=False)):
        assert model(samples, resets, **mutant) != want, f"{mutant} changes no output"


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402

NAMES = ("hold", "excl", "loss", "over", "stuck", "glitch", "travel", "coast", "line",
         "lost")
RAISED = ("hold", "excl", "loss", "over", "stuck", "glitch", "coast", "lost")


@cocotb.test()
async def monitor_stream(dut):
    scale = fqtb.env_int("SCALE")
    opt = fqtb.env_int("OPT_MONITOR")
    samples, resets = build(scale)
    want = model(samples, resets, enabled=bool(opt))
    rng = random.Random(77)
    at = {off: {x["t"] + off: k for k, x in enumerate(samples)}
          for off in (T_REF, T_RAW, T_MAG, T_PH)}
    regs_at = {}                     # the registers of the sample in flight (held after)
    for x in samples:
        for e in range(x["t"], x["t"] + T_PH + 1):
            regs_at[e] = x["regs"]
    rst = set(resets)
    last = samples[-1]["t"] + T_PH + 3
    bench = fqtb.ClockedBench(dut)
    await bench.start()
    got = [None] * len(samples)
    bad = []
    regs = samples[0]["regs"]
    for e in range(last):
        # ---- inputs for edge e
        dut.rst.value = int(e in rst)
        regs = regs_at.get(e, regs)
        dut.loss_th_i.value, dut.over_th_i.value = regs[0], regs[1]
        dut.glitch_k_i.value, dut.stuck_n_i.value = regs[2], regs[3]
        dut.code_step_i.value = regs[4]
        dut.floor_th_i.value, dut.coast_acc_i.value = regs[5], regs[6]
        k = at[T_REF].get(e)
        dut.ref_i.value = samples[k]["ref"] if k is not None else rng.randint(0, 1)
        dut.sv_i.value = int(k is not None)
        g, c1, c2 = (samples[k]["bundle"] if k is not None else
                     (rng.randint(0, 3), rng.randint(-32768, 32767), rng.randint(-32768, 32767)))
        dut.g_i.value, dut.c1_i.value, dut.c2_i.value = g, c1, c2
        k = at[T_RAW].get(e)
        dut.valid0_i.value = int(k is not None)
        dut.raw1_i.value = samples[k]["r1"] if k is not None else rng.randint(-32768, 32767)
        dut.raw2_i.value = samples[k]["r2"] if k is not None else rng.randint(-32768, 32767)
        dut.clip_i.value = samples[k]["clip"] if k is not None else rng.randint(0, 1)
        k = at[T_MAG].get(e)
        dut.ax_i.value = samples[k]["ax"] if k is not None else rng.randint(0, 32767)
        dut.ay_i.value = samples[k]["ay"] if k is not None else rng.randint(0, 32767)
        dut.xn_i.value = samples[k]["xn"] if k is not None else rng.randint(0, 1)
        dut.yn_i.value = samples[k]["yn"] if k is not None else rng.randint(0, 1)
        k = at[T_PH].get(e)
        dut.pvalid_i.value = int(k is not None)
        dut.phase_i.value = samples[k]["phase"] if k is not None else rng.randint(0, 8191)
        await bench.settle()
        comb = (fqtb.uval(dut.hold_o), fqtb.uval(dut.excl_o))
        line = (fqtb.uval(dut.coast_o), fqtb.uval(dut.line_o))
        if k is None and comb + line[:1] != (0, 0, 0):
            bad.append(f"edge {e}: (hold_o, excl_o, coast_o) = {comb + line[:1]} without "
                       "a sample")
        await bench.step()
        # ---- outputs after edge e
        if k is not None:
            got[k] = comb + (fqtb.uval(dut.loss_o), fqtb.uval(dut.over_o),
                             fqtb.uval(dut.stuck_o), fqtb.uval(dut.glitch_o),
                             fqtb.uval(dut.travel_o)) + line + (fqtb.uval(dut.lost_o),)
    for k, (g, w) in enumerate(zip(got, want)):
        if g != w:
            x = samples[k]
            diff = ", ".join(f"{nm} rtl {a} model {b}" for nm, a, b in zip(NAMES, g, w)
                             if a != b)
            bad.append(f"sample {k} (segment {x['seg']} {x['kind']}, strobe {x['t']}, "
                       f"codes {x['r1']},{x['r2']}, mags {x['ax']},{x['ay']}, phase "
                       f"{x['phase']}, ref {x['ref']}, regs {x['regs']}): {diff}")
    assert not bad, f"{len(bad)} mismatches, first:\n" + "\n".join(bad[:12])
    full = want if opt else model(samples, resets)
    counts = {nm: sum(w[NAMES.index(nm)] for w in full) for nm in RAISED}
    for nm, c in counts.items():
        assert c > 0, f"no sample raised {nm}: the stimulus misses it"
    # over-range let in again once it lasted OVER_PERSIST samples
    assert any(w[3] and not w[1] for w in full), "persistent over-range never let in"
    if not opt:
        assert not any(any(w[i] for i in (0, 2, 3, 4, 5, 7, 8, 9)) for w in want)
        assert [w[1] for w in want] == [int(x["clip"]) for x in samples]
    dut._log.info("monitor: %d samples equal to the model; flags raised %s", len(samples),
                  counts)
