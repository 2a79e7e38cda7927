"""counter (phase mode and edge mode) against sim.model.counter / edge_steps with
the core's timing (sim.model.finequad_core), and against an independent reference computed here
from the test's own unwrapped phase.

Timing (rtl/counter.v; sim.model.finequad_core's *_AT constants, edges after the core's strobe
edge t of a sample): valid_i, hold_i, phase_i and n_i are sampled on t + PHASE_AT + 1,
prod_i =
n * phase on t + NTH_AT + 1 (rtl/lut.v registers it on t + NTH_AT), mode_i on
t + LATENCY; count_o, ovs_o and valid_o show the sample after edge t + LATENCY. The Eq. 12
pulses of a sample (pv_i, a_i, b_i) are sampled on t + EDGE_AT (rtl/pulse.v registers
them on t + PULSE_AT); ill_o and ill_count_o change on that edge. In edge mode count_o
of a sample is the x4 decoder's count E after the pulses sampled on edges
<= t + LATENCY - 1 (as sim.model.finequad_core.Core.feed). Off its edge every input carries random
garbage (valid_i and pv_i low), so a block that samples an input on the wrong edge fails.

Every output is compared on every edge, not only with valid_o: count_o holds its value
between samples (0 after rst), ovs_o, held_o and ill_o are low off their edges,
ill_count_o holds between pulses. held_o is high with valid_o for a held sample in phase
mode (the core's rule, sim.model.finequad_core: hold & count_mode == 0).

  * RTL == model: per epoch (power-up or rst to the next rst) counter on the
    samples that survive and edge_steps on the pulses, E and the illegal count
    (mod 2**16) as cumulative sums, the edge-mode count picked by the core's rule;
  * RTL == the reference of this file: phase mode 4 n W + floor(n f / 2048) for
    Phi = 8192 W + f, the period part accumulated with the n of each period step
    (= floor(4 n Phi / 8192) while n is constant), overspeed = |dPhi| >= 3072 (never on
    the first sample after rst); edge mode a transition-table x4 decoder (+1/-1 per
    single-channel step, 0 and flagged for a double step, the first pulse after rst never
    flagged);
  * while one n was used since rst: count == floor(4 n Phi / 8192) (+ the preload) wrapped,
    directly.

Held samples (hold_i, rtl/monitor.v's verdict that the phase is not trusted) carry a
garbage phase: in phase mode their count is the last one (0 after rst) and they never flag
overspeed. Without coast_i nothing moves: the next sample steps from the last phase taken
(the reference's Phi does not move for them; the step of the next trusted sample is the
motion over the whole outage, up to half a period); with coast_i the counter takes line_i
instead (the reference's Phi moves by the line's steps, B with it, the count shown does
not), and the next trusted sample steps from the line. Overspeed is armed by the first
trusted sample after rst, not by a coast. The edge mode ignores hold_i.

Stimulus: an unwrapped integer phase Phi (u13 units, 8192 per period) with steps in
[-4096, 4095]; phase_i = Phi mod 8192. After rst Phi starts in [-4096, 4095] (so it
equals wrap13 of the first phase), often at |Phi| >= 3072 (the first sample must not be
flagged). A/B are the n-th order quadrant of Phi (in "noise" segments often random).
Samples back to back or with 1 or 3 idle edges. Directed parts: the overspeed threshold
(steps +-3071, +-3072, 3073, 4095, -4096, ...), the phase step's wrap at +-4096 (a step
of 4095 or -4096 crosses 0 or not depending on the phase), per-sample random n and mode,
a start from power-up without rst (the registers' initial values), rst after the pipeline
drained and rst in the middle of a stream (samples registered on the rst edge or the edge
before it are lost, pulses sampled on the rst edge are lost, the pulses after it are
decoded from the reset state), the counter's wrap at COUNT_W in both directions in both
modes (B and E preloaded near the limits through the registers b_acc / e_acc: the only
hierarchical access, which rtl/vhdl/counter.vhd keeps for GHDL: it releases GHDL's VPI
force on the next edge; COUNT_W = 16 also wraps from 0), the x4 count through zero, and the edge mode's loss: the same motion of single and double
quadrant steps (n = 64, dPhi in {32, 64}) counts everything in phase mode and 2 less per
double step (flagged) in edge mode. A second test holds pv_i high with A and B both
toggling on every edge (a double step per edge) past 65536 illegal steps: ill_count_o
wraps at 16 bits, E does not move, the first pulse after rst is not flagged."""
import random

import pytest

import fqtb
from sim.model.finequad_core import EDGE_AT, LATENCY, NTH_AT, PHASE_AT, PULSE_AT

COUNT_WS = [32, 16]


@pytest.mark.parametrize("count_w", COUNT_WS, ids=[f"COUNT{w}" for w in COUNT_WS])
@pytest.mark.parametrize("sim", fqtb.simulators("counter"))
def test_counter(sim, count_w):
    fqtb.run_block(sim, "counter", fqtb.sources("counter"), "test_counter",
                   parameters=dict(COUNT_W=count_w))


# ---- timing: edges after the core's strobe edge t of a sample (sim/model/finequad_core.py) -------
T_PHASE = PHASE_AT + 1    # valid_i, phase_i, n_i sampled (registered upstream on PHASE_AT)
T_PROD = NTH_AT + 1       # prod_i sampled (rtl/lut.v registers n * phase on NTH_AT)
T_OUT = LATENCY           # mode_i sampled; count_o, ovs_o, valid_o registered
T_PULSE = EDGE_AT         # pv_i, a_i, b_i sampled (rtl/pulse.v registers them on PULSE_AT)
assert T_PROD == T_OUT and T_PULSE == PULSE_AT + 1 and T_PHASE < T_OUT < T_PULSE, \
    "the core's timing no longer matches the counter's structure (rtl/counter.v)"

# ---- reference and stimulus (independent of sim.model) ---------------------------------
AB = {0: (1, 1), 1: (0, 1), 2: (0, 0), 3: (1, 0)}   # n-th order quadrant -> (A, B)
# x4 decoder: (A, B) before -> after, +1 in the positive direction (quadrant + 1)
DECODE = {}
for _q in range(4):
    DECODE[(AB[_q], AB[(_q + 1) % 4])] = 1
    DECODE[(AB[_q], AB[(_q - 1) % 4])] = -1
    DECODE[(AB[_q], AB[_q])] = 0
THRESHOLD_STEPS = [3071, -3071, 3072, -3072, 3073, -3073, 4095, -4096, 4094, -4095, 0, 1,
                   -1, 2047, 2048, -2048, -2049, 3000, -3100, 4000, -4000]


def wrap_s(v, w):
    return ((v + (1 << (w - 1))) % (1 << w)) - (1 << (w - 1))


class PhaseRef:
    """Phase mode from the unwrapped phase; state since rst (b0: a preloaded B)."""

    def __init__(self, count_w, rng):
        self.w = count_w
        self.rng = rng
        self.reset()

    def reset(self, b0=0):
        self.phi = None          # unwrapped phase of the last sample (None: none since rst)
        self.primed = False      # a trusted sample since rst (overspeed is armed)
        self.last = 0            # the last count (count_o after rst: 0)
        self.b0 = b0
        self.b = b0              # 4 n W summed over the period steps of Phi (+ b0)
        self.w_prev = 0          # W = floor(Phi / 8192) of the last sample (0 before)
        self.pure_n = None       # the one n used since rst, else False

    def start_phi(self):
        """First sample after rst: often at |wrap13| >= 3072 (must not be flagged)."""
        r = self.rng
        if r.random() < 0.6:
            return r.choice([r.randint(3072, 4095), r.randint(-4096, -3072)])
        return r.randint(-4096, 4095)

    def sample(self, phi, n):
        """(count, ovs, direct) of a sample at unwrapped phase phi."""
        first = self.phi is None
        dphi = phi - (0 if first else self.phi)
        assert -4096 <= dphi <= 4095, dphi
        # count = 4 n W + floor(n f / 2048), Phi = 8192 W + f: the period part B keeps the
        # n of each period step (n is changed at standstill), floor(4 n Phi / 8192) while
        # n is constant
        w = phi // 8192
        self.b += 4 * n * (w - self.w_prev)
        self.w_prev = w
        count = self.b + (n * (phi % 8192)) // 2048
        ovs = abs(dphi) >= 3072 and self.primed
        self.primed = True
        self.pure_n = n if self.pure_n in (None, n) else False
        self.phi = phi
        direct = wrap_s(self.b0 + (4 * n * phi) // 8192, self.w) if self.pure_n else None
        self.last = wrap_s(count, self.w)
        return self.last, int(ovs), direct

    def held(self):
        """(count, ovs, direct) of a held sample: nothing moves."""
        return self.last, 0, None

    def coast(self, phi, n):
        """(count, ovs, direct) of a held sample that follows the line to phi: Phi and B
        move, the count shown does not."""
        dphi = phi - (0 if self.phi is None else self.phi)
        assert -4096 <= dphi <= 4095, dphi
        w = phi // 8192
        self.b += 4 * n * (w - self.w_prev)
        self.w_prev = w
        self.pure_n = n if self.pure_n in (None, n) else False
        self.phi = phi
        return self.last, 0, None


class Decoder:
    """The x4 decoder by its transition table; state since rst (e0: a preloaded E)."""

    def __init__(self, count_w):
        self.w = count_w
        self.reset()

    def reset(self, e0=0):
        self.ab = (1, 1)         # A/B before the first pulse after rst
        self.primed = False      # a pulse arrived since rst
        self.e = e0
        self.ills = 0

    def pulse(self, ab):
        """(illegal, illegal count, E) after one pulse."""
        step = DECODE.get((self.ab, ab))
        ill = step is None and self.primed
        self.e += step or 0
        self.ills = (self.ills + ill) & 0xFFFF
        self.ab = ab
        self.primed = True
        return int(ill), self.ills, wrap_s(self.e, self.w)


def mix_step(rng, n):
    r = rng.random()
    if r < 0.15:
        return 0                                   # standstill
    if r < 0.6:                                    # under one n-th order quadrant
        lim = max(1, 2047 // n)
        return rng.randint(-lim, lim)
    if r < 0.8:                                    # a few quadrants
        lim = max(1, 3 * 2048 // n)
        return rng.randint(-lim, lim)
    return rng.randint(-4096, 4095)                # anything up to half a period


def segment_steps(rng, kind, n, mode, length):
    """Per sample (phase step, n, mode, forced (A, B) or None, hold) of one segment; hold:
    False, True (a held sample: its step is ignored, the next trusted sample's step is the
    whole motion) or "coast" (held, the count follows the line: its step moves Phi)."""
    if kind == "hold":
        # outages of 1..6 samples between trusted samples, steps up to half a period;
        # some coast (each sample a line step), some not
        out = []
        while len(out) < length:
            if rng.random() < 0.3:
                if rng.random() < 0.5:
                    out += [(0, n, mode, None, True)] * rng.randint(1, 6)
                else:
                    out += [(mix_step(rng, n), n, mode, None, "coast")
                            for _ in range(rng.randint(1, 6))]
            out.append((mix_step(rng, n), n, mode, None, False))
        return out
    return [st + (False,) for st in _segment_steps(rng, kind, n, mode, length)]


def _segment_steps(rng, kind, n, mode, length):
    out = []
    if kind == "mix":
        out = [(mix_step(rng, n), n, mode, None) for _ in range(length)]
    elif kind == "noise":                          # A/B that disagree with the phase
        for _ in range(length):
            ab = (rng.randint(0, 1), rng.randint(0, 1)) if rng.random() < 0.4 else None
            out.append((mix_step(rng, n), n, mode, ab))
    elif kind == "fast":                           # every step size up to half a period
        out = [(rng.randint(-4096, 4095), n, mode, None) for _ in range(length)]
    elif kind == "threshold":
        steps = THRESHOLD_STEPS * 2
        rng.shuffle(steps)
        for s in steps:
            out += [(s, n, mode, None), (rng.randint(-20, 20), n, mode, None)]
    elif kind in ("wrap", "wrap_down"):            # fast, one direction
        sgn = 1 if kind == "wrap" else -1
        out = [(sgn * rng.randint(3500, 4095 if sgn > 0 else 4096), n, mode, None)
               for _ in range(length)]
    elif kind == "nmix":                           # n changes on every sample
        out = [(mix_step(rng, 100), rng.randint(1, 511), mode, None) for _ in range(length)]
    elif kind == "modemix":                        # mode changes on every sample
        out = [(rng.randint(-600, 600), n, rng.randint(0, 1), None) for _ in range(length)]
    elif kind in ("edge_up", "edge_down"):         # single quadrant steps in one direction
        sgn = 1 if kind == "edge_up" else -1
        # n = 100: 20.48 units per quadrant
        out = [(sgn * rng.choice((0, 10, 20)), n, mode, None) for _ in range(length)]
    elif kind == "loss":                           # n = 64: dPhi = 32 is one quadrant
        sgn = 1 if length > 0 else -1
        steps = [sgn * rng.choice((32, 32, 64)) for _ in range(abs(length))]
        out = [(s, n, m, None) for m in (0, 1) for s in steps]
    else:
        raise ValueError(kind)
    return out


def build(plan, count_w, rng):
    """The stimulus and the reference's expectations. plan entries: (kind, n, mode,
    length, before, check); before: None (continue), "drain" (rst once the pipeline is
    empty), "busy" (rst while samples and pulses are in flight) or ("preload", B, E)
    (drain, rst, then B and E deposited); check: what to verify on the segment's counts.
    Returns (samples, resets, preloads): samples are dicts in strobe order (t: the core's
    strobe edge), resets the rst edges, preloads {rst edge: (B, E)}."""
    raw, resets, preloads = [], [], {}
    t = 1 - T_PHASE           # the first sample's phase is sampled on edge 1
    for si, (kind, n, mode, length, before, _check) in enumerate(plan):
        steps = segment_steps(rng, kind, n, mode, length)
        ts = []
        for _ in steps:
            t += rng.choice((0, 0, 0, 1, 3))
            ts.append(t)
            t += 1
        if before == "busy":
            # rst near the phase edge of one of the first samples: the samples sampled on
            # the rst edge or the edge before are lost, the previous segment's last samples
            # and pulses are still in flight
            rst_at = ts[rng.randint(0, 4)] + T_PHASE + rng.randint(-3, 1)
            resets.append(max(rst_at, ts[0] + T_PHASE - 1))
        elif before is not None:
            # after the last pulse of what came before; the segment starts 1..3 edges later
            last = raw[-1][0] + T_PULSE if raw else 0
            rst_at = last + rng.randint(1, 2)
            shift = rst_at + rng.randint(1, 3) - (ts[0] + T_PHASE)
            ts = [x + shift for x in ts]
            t = ts[-1] + 1
            resets.append(rst_at)
            if isinstance(before, tuple):
                preloads[rst_at] = tuple(before[1:])
        raw += [(ts_, si, kind, i, st) for i, (ts_, st) in enumerate(zip(ts, steps))]
    assert all(b > a + T_PULSE for a, b in zip(resets, resets[1:]))

    ref = PhaseRef(count_w, rng)
    samples, ri = [], 0
    for ts_, si, kind, i, (step, n, mode, ab, hold) in raw:
        e_ph = ts_ + T_PHASE
        while ri < len(resets) and resets[ri] < e_ph:
            ref.reset(preloads.get(resets[ri], (0, 0))[0])
            ri += 1
        # lost: sampled on the rst edge or on the edge before it (its count is due on rst)
        lost = ri < len(resets) and resets[ri] in (e_ph, e_ph + 1)
        line = rng.randint(0, 8191)
        if lost:
            phi = rng.randint(0, 8191)
            cnt = ovs = direct = None
        elif hold == "coast":        # a garbage phase; the line moves Phi
            phi = ref.start_phi() if ref.phi is None else ref.phi + step
            cnt, ovs, direct = ref.coast(phi, n)
            line, phi = phi % 8192, rng.randint(0, 8191)
        elif hold:                   # a garbage phase; nothing moves
            phi = rng.randint(0, 8191)
            cnt, ovs, direct = ref.held()
        else:
            phi = ref.start_phi() if ref.phi is None else ref.phi + step
            cnt, ovs, direct = ref.sample(phi, n)
        ab = ab or AB[((phi * n) % 8192) >> 11]
        samples.append(dict(t=ts_, seg=si, kind=kind, idx=i, phase=phi % 8192, n=n,
                            mode=mode, a=ab[0], b=ab[1], lost=lost, count_ph=cnt, ovs=ovs,
                            direct=direct, hold=bool(hold), coast=hold == "coast",
                            line=line, phi=None if lost or hold else phi))
    return samples, resets, preloads


def assemble(length, resets, outs, pulses):
    """Per edge e the outputs after it, (valid_o, count_o, ovs_o, held_o, ill_o,
    ill_count_o), from the samples' outputs {edge: (count, ovs, held)} and the pulses'
    {edge: (ill, ill count)}: count_o holds between samples, ill_count_o between pulses,
    rst clears all."""
    rst = set(resets)
    count = illc = 0          # power-up values
    out = []
    for e in range(length):
        valid = ovs = held = ill = 0
        if e in rst:
            count = illc = 0
        else:
            if e in outs:
                valid = 1
                count, ovs, held = outs[e]
            if e in pulses:
                ill, illc = pulses[e]
        out.append((valid, count, ovs, held, ill, illc))
    return out


def epochs(samples, resets):
    """{epoch: (indices of the samples that survive, indices of the samples whose pulse
    survives)}; epoch -1 is power-up, epoch i starts with rst edge resets[i]."""
    import bisect
    ep = {}
    rst = set(resets)
    for k, x in enumerate(samples):
        if not x["lost"]:
            e = bisect.bisect_left(resets, x["t"] + T_PHASE) - 1
            ep.setdefault(e, ([], []))[0].append(k)
        p = x["t"] + T_PULSE
        if p not in rst:
            ep.setdefault(bisect.bisect_left(resets, p) - 1, ([], []))[1].append(k)
    return ep


def model_trace(samples, resets, preloads, count_w, length):
    """The expected outputs from sim.model.counter, epoch by epoch, with the core's
    timing for the edge-mode count (sim.model.finequad_core.Core.feed); held_o, which
    sim.model.counter does not give, by the core model's rule (hold & count_mode == 0)."""
    import numpy as np
    from sim.model import counter as counter_m

    outs, pulses = {}, {}
    m = 1 << count_w
    for ep, (ks, ps) in epochs(samples, resets).items():
        b0, e0 = preloads.get(resets[ep], (0, 0)) if ep >= 0 else (0, 0)
        t = np.array([samples[k]["t"] for k in ks], dtype=np.int64)
        ph = np.array([samples[k]["phase"] for k in ks], dtype=np.int64)
        n = np.array([samples[k]["n"] for k in ks], dtype=np.int64)
        hold = np.array([samples[k]["hold"] for k in ks], dtype=bool)
        coast = np.array([samples[k]["coast"] for k in ks], dtype=bool)
        line = np.array([samples[k]["line"] for k in ks], dtype=np.int64)
        cnt, ovs, _ = counter_m.counter(ph, ph * n, n, count_w,
                                        state=(b0, 0, False, 0) if b0 else None, hold=hold,
                                        coast=coast, line=line)
        tp = np.array([samples[k]["t"] for k in ps], dtype=np.int64)
        a = np.array([samples[k]["a"] for k in ps], dtype=np.int64)
        b = np.array([samples[k]["b"] for k in ps], dtype=np.int64)
        steps, ill, _ = counter_m.edge_steps(a, b)
        ecum = e0 + np.cumsum(steps)
        illc = np.cumsum(ill) & 0xFFFF
        for j, k in enumerate(ps):
            pulses[samples[k]["t"] + T_PULSE] = (int(ill[j]), int(illc[j]))
        # E as of the output edge t + LATENCY: the pulses of the samples strobed on or
        # before t + LATENCY - 1 - EDGE_AT (as Core.feed)
        jj = np.searchsorted(tp, t + LATENCY - 1 - EDGE_AT, side="right") - 1
        e_at = np.where(jj >= 0, ecum[np.maximum(jj, 0)] if len(ecum) else e0, e0)
        e_at = ((e_at + (m >> 1)) % m) - (m >> 1)
        for j, k in enumerate(ks):
            c = int(e_at[j]) if samples[k]["mode"] else int(cnt[j])
            outs[samples[k]["t"] + T_OUT] = (c, int(ovs[j]),
                                             int(hold[j] and not samples[k]["mode"]))
    return assemble(length, resets, outs, pulses)


def reference_trace(samples, resets, preloads, count_w, length):
    """The expected outputs from PhaseRef (computed with the stimulus) and Decoder, edge by
    edge."""
    dec = Decoder(count_w)
    by_out = {x["t"] + T_OUT: x for x in samples if not x["lost"]}
    by_pulse = {x["t"] + T_PULSE: x for x in samples}
    rst = set(resets)
    outs, pulses = {}, {}
    for e in range(length):
        if e in rst:
            dec.reset(preloads.get(e, (0, 0))[1])
            continue                 # a pulse sampled with rst is lost
        if e in by_out:              # E before this edge's pulse
            x = by_out[e]
            outs[e] = (wrap_s(dec.e, count_w) if x["mode"] else x["count_ph"], x["ovs"],
                       int(x["hold"] and not x["mode"]))
        if e in by_pulse:
            x = by_pulse[e]
            ill, ills, _ = dec.pulse((x["a"], x["b"]))
            pulses[e] = (ill, ills)
    return assemble(length, resets, outs, pulses)


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402

OUT_NAMES = ("valid_o", "count_o", "ovs_o", "held_o", "ill_o", "ill_count_o")


def make_plan(count_w, rng):
    top, bot = (1 << (count_w - 1)) - 1, -(1 << (count_w - 1))
    r = rng.randint
    plan = [
        # (kind, n, mode, length, before, check)
        ("mix", 100, 0, 400, None, None),               # from power-up (initial values)
        ("hold", 100, 0, 400, None, "hold"),
        ("hold", r(1, 511), 0, 300, "busy", "hold"),
        ("hold", 64, 1, 200, None, None),                # edge mode ignores hold_i
        ("threshold", 37, 0, 0, None, "threshold"),
        ("fast", r(1, 511), 0, 300, "drain", None),
        ("fast", r(1, 511), 0, 300, "busy", None),
        ("wrap", 511, 0, 150, None, "wraps" if count_w <= 16 else None),
        ("wrap_down", 511, 0, 300, None, "wraps" if count_w <= 16 else None),
        ("mix", r(1, 511), 0, 200, "busy", None),
        ("nmix", 0, 0, 300, None, None),
        ("noise", 7, 1, 300, "drain", None),
        ("mix", 100, 1, 400, "busy", None),
        ("loss", 64, 0, 200, "drain", "loss"),
        ("loss", 64, 0, -200, None, "loss"),
        ("modemix", 50, 0, 400, "drain", None),
        ("fast", 1, 0, 200, "busy", None),
        ("mix", 511, 1, 200, "drain", None),
        ("threshold", 511, 0, 0, "drain", "threshold"),
        # the counter's wrap at COUNT_W in both directions and both modes, from B and E
        # preloaded near the limits
        ("wrap", 511, 0, 100, ("preload", top - 20000, 0), "wraps"),
        ("wrap_down", 511, 0, 150, ("preload", bot + 20000, 0), "wraps"),
        ("edge_up", 100, 1, 400, ("preload", 0, top - 100), "wraps"),
        ("edge_down", 100, 1, 800, None, "wraps"),
    ]
    if count_w <= 16:
        plan += [("wrap", 511, 0, 200, "drain", "wraps"),
                 ("edge_up", 100, 1, 900, "drain", None),
                 ("edge_down", 100, 1, 1800, None, "zero"),
                 ("fast", 300, 0, 100, None, None)]
    for _ in range(3):
        plan.append(("fast", r(1, 511), 0, 150, rng.choice(("drain", "busy")), None))
        plan.append(("mix", r(1, 511), r(0, 1), 150, None, None))
    return plan


@cocotb.test()
async def counter_sequences(dut):
    """The plan of make_plan() edge by edge, every output on every edge against the model
    and the reference. Runs first: its first segment starts from power-up (the registers'
    initial values, no rst)."""
    count_w = len(dut.count_o)
    rng = random.Random(700 + count_w)
    plan = make_plan(count_w, rng)
    samples, resets, preloads = build(plan, count_w, rng)
    length = samples[-1]["t"] + T_PULSE + 4
    want_m = model_trace(samples, resets, preloads, count_w, length)
    want_r = reference_trace(samples, resets, preloads, count_w, length)

    def at(off, with_lost=True):
        return {x["t"] + off: x for x in samples if with_lost or not x["lost"]}

    ph_at, prod_at, mode_at, pulse_at = at(T_PHASE), at(T_PROD), at(T_OUT), at(T_PULSE)
    rst = set(resets)
    bench = fqtb.ClockedBench(dut)
    await bench.start()
    got = []
    mask = (1 << count_w) - 1
    for e in range(length):
        # ---- inputs for edge e (garbage unless due)
        if e - 1 in preloads:            # just after the rst edge: B and E preloaded
            b0, e0 = preloads[e - 1]
            dut.b_acc.value = b0 & mask
            dut.e_acc.value = e0 & mask
        dut.rst.value = int(e in rst)
        x = ph_at.get(e)
        dut.valid_i.value = int(x is not None)
        dut.hold_i.value = int(x["hold"]) if x else rng.randint(0, 1)
        dut.coast_i.value = int(x["coast"]) if x else rng.randint(0, 1)
        dut.line_i.value = x["line"] if x else rng.randint(0, 8191)
        dut.phase_i.value = x["phase"] if x else rng.randint(0, 8191)
        dut.n_i.value = x["n"] if x else rng.randint(0, 511)
        x = prod_at.get(e)
        dut.prod_i.value = x["phase"] * x["n"] if x else rng.randint(0, (1 << 22) - 1)
        x = mode_at.get(e)
        dut.mode_i.value = x["mode"] if x else rng.randint(0, 1)
        x = pulse_at.get(e)
        dut.pv_i.value = int(x is not None)
        dut.a_i.value = x["a"] if x else rng.randint(0, 1)
        dut.b_i.value = x["b"] if x else rng.randint(0, 1)
        await bench.step()
        # ---- outputs after edge e
        got.append((fqtb.uval(dut.valid_o), fqtb.sval(dut.count_o), fqtb.uval(dut.ovs_o),
                    fqtb.uval(dut.held_o), fqtb.uval(dut.ill_o), fqtb.uval(dut.ill_count_o)))

    # ---- compare every output on every edge
    out_at = at(T_OUT, with_lost=False)
    bad = []
    direct_checked = 0
    for e in range(length):
        x = out_at.get(e) or pulse_at.get(e)
        what = (f"edge {e}" + (" (rst)" if e in rst else "")
                + (f", segment {x['seg']} ({x['kind']}) sample {x['idx']} "
                   f"(phase,n,mode,a,b)={(x['phase'], x['n'], x['mode'], x['a'], x['b'])}"
                   if x else ""))
        for name, want in (("model", want_m[e]), ("reference", want_r[e])):
            if got[e] != want:
                diff = ", ".join(f"{o} rtl {g} {name} {w}"
                                 for o, g, w in zip(OUT_NAMES, got[e], want) if g != w)
                bad.append(f"{what}: {diff}")
        x = out_at.get(e)
        if x is not None and x["mode"] == 0 and x["direct"] is not None:
            direct_checked += 1
            if got[e][1] != x["direct"]:
                bad.append(f"{what}: count_o rtl {got[e][1]}, floor(4 n Phi / 8192) "
                           f"{x['direct']}")
    assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])

    # ---- what each segment must show (the stimulus reached its corner)
    lo, hi = -(1 << (count_w - 1)), (1 << (count_w - 1)) - 1
    n_out = sum(1 for x in samples if not x["lost"])
    n_lost = sum(1 for x in samples if x["lost"])
    for si, (kind, n, mode, length_, before, check) in enumerate(plan):
        seg = [x for x in samples if x["seg"] == si and not x["lost"]]
        c = [got[x["t"] + T_OUT][1] for x in seg]
        assert all(lo <= v <= hi for v in c)
        if check == "wraps":
            assert any(abs(y - x) > (1 << (count_w - 1)) for x, y in zip(c, c[1:])), \
                f"segment {si} ({kind}) did not wrap the counter"
        elif check == "zero":                        # the x4 count runs through zero
            assert min(c) < -200 and max(c) > 200, (min(c), max(c))
        elif check == "hold":                        # held samples kept their count
            held = [x for x in seg if x["hold"]]
            assert len(held) >= 20 and all(
                got[x["t"] + T_OUT][1:4] == (x["count_ph"], 0, 1)    # count, ovs, held
                for x in held), f"segment {si}: held samples"
        elif check == "threshold":
            o = [got[x["t"] + T_OUT][2] for x in seg]
            assert 0 < sum(o) < len(o), (si, sum(o))
        elif check == "loss":
            # the same steps, phase mode first (counted from the phase), edge mode second
            # (counted from the pulses): over each half the count moves by the motion,
            # less 2 per double step in edge mode (the pulses lag the phase by a few
            # samples, hence the margin)
            h = len(seg) // 2
            p = [x["phi"] for x in seg]
            sgn = 1 if length_ > 0 else -1
            d_ph = wrap_s(c[h - 1] - c[0], count_w)
            want = (p[h - 1] - p[0]) // 32
            d_ed = wrap_s(c[-1] - c[h], count_w)
            want_e = (p[-1] - p[h]) // 32
            doubles = sum(1 for u, v in zip(p[h:], p[h + 1:]) if abs(v - u) == 64)
            assert abs(d_ph - want) <= 1, (d_ph, want)
            assert doubles >= 20 and abs(d_ed - (want_e - 2 * sgn * doubles)) <= 6, \
                (d_ed, want_e, doubles)
            dut._log.info("loss%s: %d quadrants moved in edge mode, counted %d (%d double "
                          "steps); phase mode %d of %d", "+" if sgn > 0 else "-", want_e,
                          d_ed, doubles, d_ph, want)
    assert direct_checked > 1000 and n_lost >= 4
    dut._log.info("counter COUNT_W=%d: %d edges, %d samples (%d lost to rst), %d resets, "
                  "every output equal to model and reference; %d counts checked against "
                  "floor(4 n Phi / 8192)", count_w, length, n_out, n_lost, len(resets),
                  direct_checked)


@cocotb.test()
async def counter_ill_count_wraps(dut):
    """A double step on every edge past 65536 illegal steps: ill_count_o wraps at 16 bits
    (edge_steps, counted modulo 2**16), E does not move, the first pulse after
    rst is not flagged. A and B are driven by clocks (a simulator-speed run)."""
    import numpy as np
    from cocotb.clock import Clock
    from sim.model import counter as counter_m

    count_w = len(dut.count_o)
    n_edges = 65545
    bench = fqtb.ClockedBench(dut)
    dut.rst.value = 1
    dut.valid_i.value = 0
    dut.pv_i.value = 0
    dut.mode_i.value = 1
    dut.n_i.value = 5
    dut.phase_i.value = 100
    dut.prod_i.value = 500
    await bench.start()
    await bench.step()                              # rst on edge 0
    dut.rst.value = 0
    dut.valid_i.value = 1                           # a sample (standstill) on every edge
    dut.pv_i.value = 1                              # and a pulse: A, B both toggling,
    clocks = [Clock(s, 2 * fqtb.PERIOD_PS, unit="ps") for s in (dut.a_i, dut.b_i)]
    for c in clocks:                                # (1, 1) on edge 1, (0, 0) on edge 2 ...
        c.start(start_high=True)
    a = np.arange(n_edges) % 2 == 0                 # pulse k sampled on edge k + 1
    steps, ill, _ = counter_m.edge_steps(a.astype(np.int64), a.astype(np.int64))
    illc = np.cumsum(ill) & 0xFFFF
    ecum = np.cumsum(steps)
    checks = list(range(1, 20)) + list(range(65530, n_edges + 1))
    bad = []
    for e in checks:
        await bench.goto(e)
        k = e - 1
        # count_o of the sample on edge e - 1: E after the pulses on edges <= e - 1
        want = (int(e >= 2), wrap_s(int(ecum[k - 1]) if k >= 1 else 0, count_w), 0,
                int(ill[k]), int(illc[k]))
        got = (fqtb.uval(dut.valid_o), fqtb.sval(dut.count_o), fqtb.uval(dut.ovs_o),
               fqtb.uval(dut.ill_o), fqtb.uval(dut.ill_count_o))
        if got != want:
            bad.append(f"edge {e}: (valid, count, ovs, ill, ill_count) rtl {got}, "
                       f"model {want}")
    for c in clocks:
        c.stop()
    assert int(illc[65536]) == 0 and int(illc[65535]) == 65535   # the checks span the wrap
    assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])
