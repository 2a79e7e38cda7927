"""counter (phase mode and edge mode) against sim.model.fastpath.counter / edge_steps and
against an independent reference computed here from the test's own unwrapped phase.

Timing (rtl/counter.v, in the core e = t + PHASE_AT): a sample is presented for edge E
(valid_i, phase_i and n_i high/valid before E), its product prod_i = n * phase for edge
E + 1 (rtl/lut.v registers it one edge later), mode_i for edge E + 1; count_o, ovs_o and
valid_o show the sample after edge E + 1. The Eq. 12 pulses of a sample are presented
for edge E + 3 (pv_i, a_i, b_i; t + 9 in the core); the x4 decoder's count E, ill_o and
ill_count_o change on that edge. In edge mode count_o of a sample is E as of edge E (the
pulses presented for edges <= E). On every other edge the inputs carry random garbage
(valid_i, pv_i low), so a block that samples them on the wrong edge fails.

The stimulus is an unwrapped integer phase Phi (u13 units, 8192 per period) with steps in
[-4096, 4095]; phase_i = Phi mod 8192. After rst Phi starts in [-4096, 4095] (so it equals
wrap13 of the first phase). A/B are the n-th order quadrant of Phi (sometimes noise).
For every sample:
  * RTL == model (count, overspeed, valid) bit for bit; for every pulse ill_o and
    ill_count_o == fastpath.edge_steps;
  * RTL == the reference of this file: phase mode 4 n W + floor(n f / 2048) for
    Phi = 8192 W + f, the period part accumulated with the n of each period step
    (= floor(4 n Phi / 8192) while n is constant), overspeed =
    |dPhi| >= 3072 (never on the first sample after rst); edge mode a transition-table
    x4 decoder (+1/-1 per single-channel step, 0 and flagged for a double step, the first
    pulse after rst never flagged);
  * while one n was used since rst: count == floor(4 n Phi / 8192) wrapped, directly.
Directed parts: overspeed threshold steps (+-3071, +-3072, 4095, -4096, ...), first samples
after rst at |wrap13| >= 3072 (not flagged), wraps of the counter in both directions at
COUNT_W = 16 (phase mode), the x4 count up and down through zero (edge mode), per-sample
random n and mode, rst in the middle, and
the edge mode's loss: the same motion of single and double quadrant steps (n = 64, dPhi
in {32, 64}) counts everything in phase mode and 2 less per double step (flagged) in edge
mode."""
import random

import pytest

import fqtb

COUNT_WS = [32, 16]


@pytest.mark.parametrize("count_w", COUNT_WS, ids=[f"COUNT{w}" for w in COUNT_WS])
@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_counter(sim, count_w):
    fqtb.run_block(sim, "counter", fqtb.sources("counter"), "test_counter",
                   parameters=dict(COUNT_W=count_w))


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
PULSE_DELAY = 3           # pulses of a sample: edge E + 3 (t + 9 in the core)


def wrap_s(v, w):
    return ((v + (1 << (w - 1))) % (1 << w)) - (1 << (w - 1))


class Reference:
    """Generates samples and computes what the counter must output; state since rst."""

    def __init__(self, count_w, rng):
        self.w = count_w
        self.rng = rng
        self.reset()

    def reset(self):
        self.phi = None          # unwrapped phase of the last sample (None: none since rst)
        self.ab = (1, 1)         # the decoder's A/B before the first pulse after rst
        self.primed = False      # a pulse arrived since rst
        self.b = 0               # phase mode: 4 n W summed over the period steps of Phi
        self.w_prev = 0          # W = floor(Phi / 8192) of the last sample (0 before)
        self.e = 0               # edge mode: the x4 count
        self.ills = 0
        self.pure_n = None       # the one n used since rst, else False

    def quadrant(self, phi, n):
        return ((phi * n) % 8192) >> 11

    def sample(self, phi, n, mode, ab=None):
        """One sample at unwrapped phase phi (step from the last one in [-4096, 4095]);
        A/B from the n-th order quadrant unless given."""
        first = self.phi is None
        dphi = phi - (0 if first else self.phi)
        assert -4096 <= dphi <= 4095, dphi
        if ab is None:
            ab = AB[self.quadrant(phi, n)]
        # count = 4 n W + floor(n f / 2048), Phi = 8192 W + f: the period part B keeps the
        # n of each period step (n is changed at standstill), floor(4 n Phi / 8192) while
        # n is constant
        w = phi // 8192
        self.b += 4 * n * (w - self.w_prev)
        self.w_prev = w
        count = self.b + (n * (phi % 8192)) // 2048
        ovs = abs(dphi) >= 3072 and not first
        self.pure_n = n if self.pure_n in (None, n) else False
        self.phi = phi
        direct = wrap_s((4 * n * phi) // 8192, self.w) if self.pure_n else None
        return dict(a=ab[0], b=ab[1], phase=phi % 8192, n=n, mode=mode,
                    count_ph=wrap_s(count, self.w), ovs=int(ovs), direct=direct)

    def pulse(self, ab):
        """The decoder on one pulse: (illegal, illegal count, E) after it."""
        step = DECODE.get((self.ab, ab))
        ill = step is None and self.primed
        self.e += step or 0
        self.ills = (self.ills + ill) & 0xFFFF
        self.ab = ab
        self.primed = True
        return int(ill), self.ills, wrap_s(self.e, self.w)

    def start_phi(self):
        """First sample after rst: often at |wrap13| >= 3072 (must not be flagged)."""
        r = self.rng
        if r.random() < 0.6:
            return r.choice([r.randint(3072, 4095), r.randint(-4096, -3072)])
        return r.randint(-4096, 4095)


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


def segment(ref, kind, n, mode, length):
    """Samples of one segment (list of dicts from Reference.sample)."""
    rng = ref.rng
    out = []

    def add(step, n_=n, mode_=mode, ab=None):
        phi = ref.start_phi() if ref.phi is None else ref.phi + step
        out.append(ref.sample(phi, n_, mode_, ab))

    if kind == "mix":
        for _ in range(length):
            add(mix_step(rng, n))
    elif kind == "noise":                          # A/B that disagree with the phase
        for _ in range(length):
            ab = (rng.randint(0, 1), rng.randint(0, 1)) if rng.random() < 0.4 else None
            add(mix_step(rng, n), ab=ab)
    elif kind == "fast":                           # every step size up to half a period
        for _ in range(length):
            add(rng.randint(-4096, 4095))
    elif kind == "threshold":
        steps = THRESHOLD_STEPS * 2
        rng.shuffle(steps)
        for s in steps:
            add(s)
            add(rng.randint(-20, 20))
    elif kind in ("wrap", "wrap_down"):            # fast, one direction
        sgn = 1 if kind == "wrap" else -1
        for _ in range(length):
            add(sgn * rng.randint(3500, 4095 if sgn > 0 else 4096))
    elif kind == "nmix":                           # n changes on every sample
        for _ in range(length):
            add(mix_step(rng, 100), n_=rng.randint(1, 511))
    elif kind == "modemix":                        # mode changes on every sample
        for _ in range(length):
            add(rng.randint(-600, 600), mode_=rng.randint(0, 1))
    elif kind in ("edge_up", "edge_down"):         # single quadrant steps in one direction
        sgn = 1 if kind == "edge_up" else -1
        for _ in range(length):
            add(sgn * rng.choice((0, 10, 20)))     # n = 100: 20.48 units per quadrant
    else:
        raise ValueError(kind)
    return out


def loss_steps(rng, length, sgn):
    """n = 64: dPhi = 32 is one n-th order quadrant, 64 two."""
    return [sgn * rng.choice((32, 32, 64)) for _ in range(length)]


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402


@cocotb.test()
async def counter_sequences(dut):
    import numpy as np
    from sim.model import fastpath as fp

    count_w = len(dut.count_o)
    rng = random.Random(700 + count_w)
    ref = Reference(count_w, rng)
    # (kind, n, mode, length, rst before); "loss" = the same steps in phase then edge mode
    plan = [
        ("mix", 100, 0, 400, True),
        ("threshold", 37, 0, 0, False),
        ("fast", rng.randint(1, 511), 0, 300, True),
        ("fast", rng.randint(1, 511), 0, 300, True),
        ("wrap", 511, 0, 150, False),
        ("wrap_down", 511, 0, 300, False),
        ("mix", rng.randint(1, 511), 0, 200, True),
        ("nmix", 0, 0, 300, False),
        ("noise", 7, 1, 300, True),
        ("mix", 100, 1, 400, False),
        ("loss", 64, 0, 200, True),
        ("loss", 64, 0, -200, False),
        ("modemix", 50, 0, 400, False),
        ("fast", 1, 0, 200, False),
        ("mix", 511, 1, 200, True),
        ("threshold", 511, 0, 0, True),
    ]
    if count_w <= 16:
        plan += [("wrap", 511, 0, 200, True), ("edge_up", 100, 1, 900, True),
                 ("edge_down", 100, 1, 1800, False), ("fast", 300, 0, 100, False)]
    for _ in range(3):
        plan.append(("fast", rng.randint(1, 511), 0, 150, True))
        plan.append(("mix", rng.randint(1, 511), rng.randint(0, 1), 150, False))

    bench = fqtb.ClockedBench(dut)
    dut.rst.value = 1
    dut.valid_i.value = 0
    dut.pv_i.value = 0
    dut.mode_i.value = 0
    dut.n_i.value = 1
    await bench.start()
    await bench.step()
    dut.rst.value = 0
    hist = []               # samples since the last rst (the model runs on them)
    bad = []
    total = pulses = direct_checked = 0
    segs = []
    for si, (kind, n, mode, length, rst) in enumerate(plan):
        if rst:
            await bench.step(PULSE_DELAY + 2)          # let the last pulses land first
            dut.rst.value = 1
            await bench.step()
            dut.rst.value = 0
            if (fqtb.sval(dut.count_o), fqtb.uval(dut.ill_count_o),
                    fqtb.uval(dut.valid_o), fqtb.uval(dut.ill_o)) != (0, 0, 0, 0):
                bad.append(f"segment {si}: counter not cleared by rst")
            hist = []
            ref.reset()
        if kind == "loss":
            steps = loss_steps(rng, abs(length), 1 if length > 0 else -1)
            seg = []
            for m in (0, 1):
                for s in steps:
                    seg.append(ref.sample(ref.phi + s if ref.phi is not None else 0, n, m))
            kind = f"loss{'+' if length > 0 else '-'}"
        else:
            seg = segment(ref, kind, n, mode, length)
        start = len(hist)
        hist += seg
        ph = np.array([x["phase"] for x in hist], dtype=np.int64)
        nn = np.array([x["n"] for x in hist], dtype=np.int64)
        cnt_m, ovs_m, _ = fp.counter(ph, ph * nn, nn, count_w)
        _, ill_m, _ = fp.edge_steps(np.array([x["a"] for x in hist]),
                                    np.array([x["b"] for x in hist]))
        # schedule: sample i for edge E_i; count after E_i + 1; pulses for edge E_i + 3
        edges, e = [], bench.edge + 1
        for _ in seg:
            e += rng.choice((0, 0, 0, 1, 3))
            edges.append(e)
            e += 1
        by_edge = {x: i for i, x in enumerate(edges)}
        prod_at = {x + 1: i for i, x in enumerate(edges)}
        out_at = {x + 1: i for i, x in enumerate(edges)}
        pulse_at = {x + PULSE_DELAY: i for i, x in enumerate(edges)}
        e_after = {}                                  # E after each pulse edge
        ill_exp = {}
        got_seg = []
        e_now = wrap_s(ref.e, count_w) if start == 0 else None
        for e in range(bench.edge, edges[-1] + PULSE_DELAY + 2):
            # ---- outputs after edge e
            if e in pulse_at:
                i = pulse_at[e]
                x, k = seg[i], start + i
                ill, ills, e_cnt = ref.pulse((x["a"], x["b"]))
                e_after[e] = e_cnt
                pulses += 1
                got = (fqtb.uval(dut.ill_o), fqtb.uval(dut.ill_count_o))
                if got != (ill, ills) or int(ill_m[k]) != ill:
                    bad.append(f"segment {si} ({kind}) pulse of sample {i} (a,b)="
                               f"{(x['a'], x['b'])}: (ill, ill_count) rtl {got}, reference "
                               f"{(ill, ills)}, model ill {int(ill_m[k])}")
            elif e > bench.edge and fqtb.uval(dut.ill_o):
                bad.append(f"ill_o high after edge {e}, no pulse due")
            if e in out_at:
                i = out_at[e]
                x, k = seg[i], start + i
                # E as of edge e - 1 (pulses for edges <= E_i)
                past = [p for p in e_after if p <= e - 1]
                e_cnt = e_after[max(past)] if past else e_now
                got = (fqtb.uval(dut.valid_o), fqtb.sval(dut.count_o), fqtb.uval(dut.ovs_o))
                got_seg.append(got)
                want = (1, x["count_ph"] if x["mode"] == 0 else e_cnt, x["ovs"])
                mod = (1, int(cnt_m[k]) if x["mode"] == 0 else e_cnt, int(ovs_m[k]))
                total += 1
                what = (f"segment {si} ({kind}) sample {i} (phase,n,mode)="
                        f"{(x['phase'], x['n'], x['mode'])}: (valid,count,ovs) rtl {got}")
                if want[1] is None:
                    pass                               # E before this segment's first pulse
                elif got != want:
                    bad.append(f"{what}, reference {want}")
                if x["mode"] == 0 and got != mod:
                    bad.append(f"{what}, model {mod}")
                if x["direct"] is not None and x["mode"] == 0:
                    direct_checked += 1
                    if got[1] != x["direct"]:
                        bad.append(f"{what}, floor(4 n Phi / 8192) = {x['direct']}")
            elif e > bench.edge and fqtb.uval(dut.valid_o):
                bad.append(f"valid_o high after edge {e}, no sample due")
            # ---- inputs for edge e + 1 (garbage unless due)
            nxt = e + 1
            if nxt in by_edge:
                x = seg[by_edge[nxt]]
                dut.valid_i.value = 1
                dut.phase_i.value = x["phase"]
                dut.n_i.value = x["n"]
            else:
                dut.valid_i.value = 0
                dut.phase_i.value = rng.randint(0, 8191)
                dut.n_i.value = rng.randint(0, 511)
            if nxt in prod_at:
                x = seg[prod_at[nxt]]
                dut.prod_i.value = x["phase"] * x["n"]
                dut.mode_i.value = x["mode"]
            else:
                dut.prod_i.value = rng.randint(0, (1 << 22) - 1)
                dut.mode_i.value = rng.randint(0, 1)
            if nxt in pulse_at:
                x = seg[pulse_at[nxt]]
                dut.pv_i.value = 1
                dut.a_i.value, dut.b_i.value = x["a"], x["b"]
            else:
                dut.pv_i.value = 0
                dut.a_i.value, dut.b_i.value = rng.randint(0, 1), rng.randint(0, 1)
            await bench.step()
        assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])
        segs.append((si, kind, seg, got_seg))

        c = [g[1] for g in got_seg]
        lo, hi = -(1 << (count_w - 1)), (1 << (count_w - 1)) - 1
        assert all(lo <= v <= hi for v in c)
        wrapped = any(abs(y - x) > (1 << (count_w - 1)) for x, y in zip(c, c[1:]))
        if kind.startswith("wrap") and count_w <= 16:
            assert wrapped, f"segment {si} ({kind}) did not wrap the counter"
        if kind == "edge_down":                   # the x4 count runs through zero
            assert min(c) < -200 and max(c) > 200, (min(c), max(c))
        if kind == "threshold":
            assert 0 < sum(g[2] for g in got_seg) < len(seg)
        if kind.startswith("loss"):
            # the same steps, phase mode first (counted from the phase), edge mode second
            # (counted from the pulses): over each half the count moves by the motion,
            # less 2 per double step in edge mode
            h = len(seg) // 2
            doubles = sum(1 for s in steps if abs(s) == 64)
            sgn = 1 if steps[0] > 0 else -1
            want = sum(steps) // 32
            d_ph = wrap_s(c[h - 1] - c[0], count_w) + steps[0] // 32
            d_ed = wrap_s(c[-1] - c[h], count_w)
            assert abs(d_ph - want) <= 1, (d_ph, want)
            assert abs(d_ed - (want - 2 * sgn * doubles)) <= 3, (d_ed, want, doubles)
            assert doubles > 0
            dut._log.info("%s: %d quadrants moved, phase mode counted %d, edge mode %d "
                          "(%d double steps)", kind, want, d_ph, d_ed, doubles)
    assert direct_checked > 1000 and pulses == total
    dut._log.info("counter COUNT_W=%d: %d samples and pulses equal (model and reference), "
                  "%d checked against floor(4 n Phi / 8192)", count_w, total, direct_checked)
