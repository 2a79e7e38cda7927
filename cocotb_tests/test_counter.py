"""counter (phase mode and edge mode) against sim.model.fastpath.counter and against an
independent reference computed here from the test's own unwrapped phase.

Latency 3: a sample on edge e (valid_i, a_i, b_i, phase_i, mode_i) is on the outputs after
edge e + 2; n_i is used on edge e + 1. The bench drives n_i with the sample's n only on
edge e + 1 and mode_i only on edge e; every other edge gets random garbage on every input
(valid_i low), so a block that samples them on the wrong edge fails.

The stimulus is an unwrapped integer phase Phi (u13 units, 8192 per period) with steps in
[-4096, 4095]; phase_i = Phi mod 8192. After rst Phi starts in [-4096, 4095] (so it equals
wrap13 of the first phase). A/B are the n-th order quadrant of Phi (sometimes noise, or
driven directly). For every sample three things are checked:
  * RTL == model (count, flag, flag count, valid, A/B pass-through), bit for bit;
  * RTL == the reference of this file: an accumulator S = sum of 4 n dPhi (phase mode) or
    8192 * (+1/-1 per single-channel A/B step, 0 for a double step) (edge mode) from the
    test's own dPhi and a transition-table quadrature decoder, count = floor(S / 8192)
    wrapped to COUNT_W; flag = |dPhi| >= 3072 (phase) or both A and B changed (edge),
    never on the first sample after rst;
  * while only phase mode and one n were used since rst: count == floor(4 n Phi / 8192)
    wrapped, directly.
Directed parts: overspeed threshold steps (+-3071, +-3072, 4095, -4096, ...), first samples
after rst at |wrap13| >= 3072 (not flagged), wrap of the counter in both directions in
phase mode and (COUNT_W=16) in edge mode, per-sample random n and mode, and the edge mode's
loss: the same motion of single and double quadrant steps (n = 64, dPhi in {32, 64}) in
phase mode counts everything, in edge mode it counts 2 less per double step, each flagged."""
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


def wrap_s(v, w):
    return ((v + (1 << (w - 1))) % (1 << w)) - (1 << (w - 1))


class Reference:
    """Generates samples and computes what the counter must output, from the unwrapped
    phase; state since the last rst."""

    def __init__(self, count_w, rng):
        self.w = count_w
        self.rng = rng
        self.reset()

    def reset(self):
        self.phi = None          # unwrapped phase of the last sample (None: none since rst)
        self.ab = (1, 1)         # A/B before the first sample: rtl/pulse.v's reset state
        self.s = 0               # accumulator, unbounded
        self.flags = 0
        self.pure_n = None       # the one n used since rst in phase mode only, else False

    def count(self):
        return wrap_s(self.s >> 13, self.w)

    def quadrant(self, phi, n):
        return ((phi * n) % 8192) >> 11

    def sample(self, phi, n, mode, ab=None):
        """One sample at unwrapped phase phi (step from the last one in [-4096, 4095]);
        A/B from the n-th order quadrant unless given."""
        first = self.phi is None
        dphi = phi - (0 if first else self.phi)
        if first:
            assert -4096 <= phi <= 4095
        assert -4096 <= dphi <= 4095, dphi
        if ab is None:
            ab = AB[self.quadrant(phi, n)]
        if mode == 0:
            self.s += 4 * n * dphi
            flag = abs(dphi) >= 3072
        else:
            step = DECODE.get((self.ab, ab))
            flag = step is None            # both channels changed: lost
            self.s += (step or 0) << 13
        flag = flag and not first
        self.flags += flag
        if mode == 0 and self.pure_n in (None, n):
            self.pure_n = n
        else:
            self.pure_n = False
        self.phi = phi
        self.ab = ab
        direct = None
        if self.pure_n:
            direct = wrap_s((4 * n * phi) // 8192, self.w)
        return dict(a=ab[0], b=ab[1], phase=phi % 8192, n=n, mode=mode,
                    count=self.count(), flag=int(flag), flags=self.flags, direct=direct)

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
            if ref.phi is None and mode == 1:
                ab = (0, 0)             # first sample after rst: a double step, not flagged
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
            m = rng.randint(0, 1)
            lim = max(1, 2 * 2048 // n) if m else 4095
            add(rng.randint(-lim, lim), mode_=m)
    elif kind == "to_wrap":
        # phase mode at n = 511 up to just below the top of the counter (COUNT_W <= 16)
        top = (1 << (ref.w - 1)) - 1
        target = ref.s // 8192 + (top - 25 - ref.count()) % (1 << ref.w)
        while ref.s // 8192 < target - 2:
            need = (target - 1) * 8192 - ref.s          # S units
            add(max(1, min(4000, need // (4 * n))))
    elif kind in ("edge_up", "edge_down"):         # single quadrant steps, drive A/B
        sgn = 1 if kind == "edge_up" else -1
        q = {v: k for k, v in AB.items()}[ref.ab]
        for _ in range(length):
            if rng.random() < 0.8:
                q = (q + sgn) % 4
            add(0, ab=AB[q])
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
        ("loss", 64, 0, 200, False),
        ("loss", 64, 0, -200, False),
        ("modemix", 50, 0, 400, False),
        ("fast", 1, 0, 200, False),
        ("mix", 511, 1, 200, True),
        ("threshold", 511, 0, 0, True),
    ]
    if count_w <= 16:
        plan += [("to_wrap", 511, 0, 0, False), ("edge_up", 100, 1, 80, False),
                 ("edge_down", 100, 1, 80, False), ("fast", 300, 0, 100, False)]
    for _ in range(3):
        plan.append(("fast", rng.randint(1, 511), 0, 150, True))
        plan.append(("mix", rng.randint(1, 511), rng.randint(0, 1), 150, False))

    bench = fqtb.ClockedBench(dut)
    dut.rst.value = 1
    dut.valid_i.value = 0
    dut.mode_i.value = 0
    dut.n_i.value = 1
    await bench.start()
    await bench.step()
    dut.rst.value = 0
    hist = []               # samples since the last rst (the model runs on them)
    bad = []
    total = 0
    direct_checked = 0
    segs = []
    for si, (kind, n, mode, length, rst) in enumerate(plan):
        if rst:
            dut.rst.value = 1
            await bench.step()
            dut.rst.value = 0
            if (fqtb.sval(dut.count_o), fqtb.uval(dut.illegal_count_o),
                    fqtb.uval(dut.valid_o), fqtb.uval(dut.illegal_o)) != (0, 0, 0, 0):
                bad.append(f"segment {si}: counter not cleared by rst")
            hist = []
            ref.reset()
        if kind == "loss":
            steps = loss_steps(rng, abs(length), 1 if length > 0 else -1)
            seg = []
            for m in (0, 1):
                for s in steps:
                    seg.append(ref.sample(ref.phi + s, n, m))
            kind = f"loss{'+' if length > 0 else '-'}"
        else:
            seg = segment(ref, kind, n, mode, length)
        start = len(hist)
        hist += seg
        cnt, flg, fcnt, _, _ = fp.counter(
            np.array([x["a"] for x in hist]), np.array([x["b"] for x in hist]),
            np.array([x["phase"] for x in hist], dtype=np.int64),
            np.array([x["n"] for x in hist], dtype=np.int64), count_w,
            np.array([x["mode"] for x in hist], dtype=np.int64))
        # drive: samples with idle gaps; outputs checked 2 edges after each sample
        edges, e = [], bench.edge + 1
        for _ in seg:
            e += rng.choice((0, 0, 0, 1, 3))
            edges.append(e)
            e += 1
        by_edge = {x: i for i, x in enumerate(edges)}
        n_at = {x + 1: seg[i]["n"] for i, x in enumerate(edges)}
        out_at = {x + 2: i for i, x in enumerate(edges)}
        got_seg = []
        for e in range(bench.edge, edges[-1] + 4):
            if e in out_at:
                i = out_at[e]
                x, k = seg[i], start + i
                got = (fqtb.uval(dut.valid_o), fqtb.sval(dut.count_o), fqtb.uval(dut.a_o),
                       fqtb.uval(dut.b_o), fqtb.uval(dut.illegal_o),
                       fqtb.uval(dut.illegal_count_o))
                got_seg.append(got)
                mod = (1, int(cnt[k]), x["a"], x["b"], int(flg[k]), int(fcnt[k]))
                want = (1, x["count"], x["a"], x["b"], x["flag"], x["flags"])
                total += 1
                what = (f"segment {si} ({kind}) sample {i} (a,b,phase,n,mode)="
                        f"{(x['a'], x['b'], x['phase'], x['n'], x['mode'])}: "
                        f"(valid,count,a,b,flag,flag_count) rtl {got}")
                if got != mod:
                    bad.append(f"{what}, model {mod}")
                if got != want:
                    bad.append(f"{what}, reference {want}")
                if x["direct"] is not None:
                    direct_checked += 1
                    if got[1] != x["direct"]:
                        bad.append(f"{what}, floor(4 n Phi / 8192) = {x['direct']}")
            elif e > edges[0] and fqtb.uval(dut.valid_o):
                bad.append(f"valid_o high after edge {e}, no sample due")
            if e + 1 in by_edge:
                x = seg[by_edge[e + 1]]
                dut.valid_i.value = 1
                a, b, p, m = x["a"], x["b"], x["phase"], x["mode"]
            else:
                dut.valid_i.value = 0
                a, b, p, m = (rng.randint(0, 1), rng.randint(0, 1), rng.randint(0, 8191),
                              rng.randint(0, 1))
            dut.a_i.value = a
            dut.b_i.value = b
            dut.phase_i.value = p
            dut.mode_i.value = m
            dut.n_i.value = n_at.get(e + 1, rng.randint(0, 511))
            await bench.step()
        assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])
        segs.append((si, kind, seg, got_seg))

        c = [g[1] for g in got_seg]
        lo, hi = -(1 << (count_w - 1)), (1 << (count_w - 1)) - 1
        assert all(lo <= v <= hi for v in c)
        wrapped = any(abs(y - x) > (1 << (count_w - 1)) for x, y in zip(c, c[1:]))
        if kind.startswith("wrap") and count_w <= 16:
            assert wrapped, f"segment {si} ({kind}) did not wrap the counter"
        if kind.startswith("edge_") and count_w <= 16:
            assert wrapped, f"segment {si} ({kind}) did not wrap the counter in edge mode"
        if kind == "threshold":
            assert 0 < sum(g[4] for g in got_seg) < len(seg)
        if kind.startswith("loss"):
            # the same steps, phase mode first, edge mode second
            h = len(seg) // 2
            prev = segs[-2][3][-1][1] if len(segs) > 1 else 0
            d_ph = wrap_s(c[h - 1] - prev, count_w)
            d_ed = wrap_s(c[-1] - c[h - 1], count_w)
            fl_ph = sum(g[4] for g in got_seg[:h])
            fl_ed = sum(g[4] for g in got_seg[h:])
            doubles = sum(1 for s in steps if abs(s) == 64)
            sgn = 1 if steps[0] > 0 else -1
            want_ph = sum(steps) // 32
            assert fl_ph == 0 and d_ph == want_ph, (d_ph, want_ph, fl_ph)
            assert fl_ed == doubles > 0, (fl_ed, doubles)
            assert d_ed == want_ph - 2 * sgn * doubles, (d_ed, want_ph, doubles)
            dut._log.info("%s: %d quadrants moved, phase mode counted %d, edge mode %d "
                          "(%d double steps flagged, %d counts lost)", kind, want_ph, d_ph,
                          d_ed, fl_ed, abs(d_ph - d_ed))
    assert direct_checked > 1000
    dut._log.info("counter COUNT_W=%d: %d samples equal (model and reference), %d checked "
                  "against floor(4 n Phi / 8192)", count_w, total, direct_checked)
