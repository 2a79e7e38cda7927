"""abgen (paced A/B quadrature output) against sim.model.abgen, plus independent checks.

Per clock, bit-exact: a_o, b_o, pos_o, backlog_o, ovf_o, ovf_sticky_o equal the model
(sim/model/abgen.py abgen(); its run-based variant abgen_fast() is checked against it on
the same stream). Independently of the model, in this file:
  * an x4 decoder counting a_o/b_o (reset with rst) reads pos_o on every clock and the
    final target after every hold of the target (settle markers);
  * no clock where A and B both change (outside rst);
  * no two edges closer than sep clocks (sep of the later edge, 0 as 1);
  * no pacing lost: when the decoder is off the target and sep clocks have passed since
    the last edge, an edge happens (the backlog is paid at the maximum allowed rate);
  * ovf_o == |target_i - pos| > bound_i of the edge before (pos the decoder count before
    that edge; 0 on the first edge after rst), backlog_o == that difference saturated to
    s16, ovf_sticky_o == OR of ovf_o since rst;
  * z_o == z_en_i and (the decoder count after the edge == z_at_i), with z_en_i and
    z_at_i as driven before the edge (0 after rst): Z marks its count only, armed. z_at_i
    moves to a count near the pins' every 97 clocks (z_en_i low in a fifth of them), and
    the stream must enter Z from above and from below.
Streams: slow moves, jumps of thousands of counts, reversals mid-backlog, sep changes
(0, 1, 2..7, 255), bounds small enough that ovf toggles, rst in the middle of a backlog,
backlog saturation, a modular (short-way) difference at COUNT_W = 18.

Against the counters the pins are meant for (abgen_counters): moves faster than the pins
(the backlog paid at the pacing's maximum rate) with reversals, the pins timed at the
36 MHz of a core clock and read by sim.counters.FilteringCounter, a model of an
integrating input filter and x4 counter written from the description of LinuxCNC's Mesa
hostmot2 encoder with its driver's default filter (a level must hold 15 samples of a
25 MHz clock), at five sampling phases: with ABGEN.ab_sep at its reset value
(rtl/regs/finequad.rdl) it must end on the target with no quadrature error; with the
earlier default of 4 clocks it must not (the counter loses counts, silently)."""
import random

import pytest

import fqtb

COUNT_WS = [32, 18]


@pytest.mark.parametrize("count_w", COUNT_WS, ids=[f"CW{w}" for w in COUNT_WS])
@pytest.mark.parametrize("sim", fqtb.simulators("abgen"))
def test_abgen(sim, count_w):
    fqtb.run_block(sim, "abgen", fqtb.sources("abgen"), "test_abgen",
                   parameters=dict(COUNT_W=count_w), testcase="abgen_streams")


@pytest.mark.parametrize("sim", fqtb.simulators("abgen"))
def test_abgen_counters(sim):
    fqtb.run_block(sim, "abgen", fqtb.sources("abgen"), "test_abgen",
                   parameters=dict(COUNT_W=32), testcase="abgen_counters")


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402


def wrapw(v, w):
    v &= (1 << w) - 1
    return v - (1 << w) if v >> (w - 1) else v


class Stream:
    """Per-clock inputs (rst, target, sep, bound) built chunk by chunk, with the model's
    outputs computed as it grows (the model state tells how long a hold must be)."""

    def __init__(self, cw):
        from sim.model.abgen import AbgenState
        self.cw = cw
        self.rst, self.target, self.sep, self.bound = [], [], [], []
        self.exp = {k: [] for k in ("a", "b", "pos", "backlog", "ovf", "sticky")}
        self.settle = set()          # clocks at which the decoder must read the target
        self.st = AbgenState()
        self.t = 0                   # current target
        self.s = 1
        self.bd = 100

    def _model(self, tg, sp, bd):
        from sim.model.abgen import abgen
        r = abgen(tg, sp, bd, count_w=self.cw, state=self.st)
        for k in self.exp:
            self.exp[k].extend(int(x) for x in r[k])

    def add(self, targets, sep=None, bound=None):
        """Clocks with these targets (sep/bound: one value or one per clock)."""
        n = len(targets)
        sp = sep if isinstance(sep, list) else [self.s if sep is None else sep] * n
        bd = bound if isinstance(bound, list) else [self.bd if bound is None else bound] * n
        tg = [wrapw(t, self.cw) for t in targets]
        self.rst += [0] * n
        self.target += tg
        self.sep += sp
        self.bound += bd
        self._model(tg, sp, bd)
        if n:
            self.t, self.s, self.bd = tg[-1], sp[-1], bd[-1]

    def reset(self):
        from sim.model.abgen import AbgenState
        self.rst.append(1)
        self.target.append(wrapw(self.t + 12345, self.cw))   # ignored on the rst edge
        self.sep.append(self.s)
        self.bound.append(self.bd)
        for k, v in dict(a=1, b=1, pos=0, backlog=0, ovf=0, sticky=0).items():
            self.exp[k].append(v)
        self.st = AbgenState()
        self.t = 0

    def hold(self, extra=3):
        """Hold the target until pos must have reached it; mark the last clock."""
        d = abs(wrapw(self.t - self.st.pos, self.cw))
        n = d * max(self.s, 1) + max(self.s, 1) + extra
        self.add([self.t] * n)
        self.settle.add(len(self.rst) - 1)

    def __len__(self):
        return len(self.rst)


def build_stream(cw, seed):
    rng = random.Random(seed)
    S = Stream(cw)
    S.reset()
    # A: slow ramp up and down, sep 1, bound 2 (ovf toggles while the target runs ahead)
    S.s, S.bd = 1, 2
    S.add([i // 3 for i in range(1, 200)])
    S.add([S.t - i // 2 for i in range(1, 300)])
    S.hold()
    # B: jump of thousands, reversal mid-backlog, sep 1; bound 1000
    S.bd = 1000
    S.add([S.t + 2500] * 1200)
    S.add([S.t - 4000] * 10)
    S.hold()
    # C: sep changes during a backlog: 7, 2, 0, 255, 3
    S.add([S.t + 300] * 200, sep=7)
    S.add([S.t] * 100, sep=2)
    S.add([S.t] * 100, sep=0)
    S.add([S.t] * 600, sep=255)
    S.add([S.t] * 10, sep=3)
    S.hold()
    # C2: idle for more than 255 clocks (the timer saturates, never wraps), then a move
    # with sep 200 must start on the next edge
    S.add([S.t] * 300)
    S.add([S.t + 3] * 10, sep=200)
    S.hold()
    # D: target moves every clock by -3..3 (faster than sep 2 allows), bound 10
    S.s, S.bd = 2, 10
    x = S.t
    tg = []
    for _ in range(600):
        x += rng.randint(-3, 3)
        tg.append(x)
    S.add(tg)
    S.hold()
    # E: rst in the middle of a backlog, then a move from 0
    S.s = 1
    S.add([S.t + 500] * 100)
    S.reset()
    S.add([-7] * 5)
    S.add([5] * 20, sep=4)
    S.hold()
    # F: backlog saturation (|d| > 32767) for a few clocks, then back near pos; bound 65535
    S.s, S.bd = 1, 65535
    S.add([S.t + 40000] * 4 + [S.t - 40000] * 4 + [S.t + 30] * 40)
    S.add([S.t - 65536] * 3, bound=65534)
    S.add([S.t + 20] * 3, bound=0)
    S.hold()
    if cw < 20:
        # G: the modular difference goes the short way: a target 3/4 of the range ahead
        # is followed backwards (d wraps negative)
        S.add([S.t + (3 << (cw - 2))] * 300)
        S.add([S.t + 25] * 200)
        S.add([S.st.pos + 40] * 100)
        S.hold()
    # R: random segments
    for seg in range(14):
        S.s = rng.choice((0, 1, 1, 2, 3, 5, 9))
        S.bd = rng.choice((0, 1, 3, 20, 700, 5000, 65535))
        kind = rng.random()
        n = rng.randint(100, 500)
        tg, sp, bd = [], [], []
        x = S.t
        for _ in range(n):
            r = rng.random()
            if kind < 0.3:                 # slow wander
                if r < 0.3:
                    x += rng.choice((-1, 1))
            elif kind < 0.6:               # occasional jumps of up to thousands
                if r < 0.01:
                    x += rng.randint(-3000, 3000)
                elif r < 0.2:
                    x += rng.randint(-4, 4)
            else:                          # fast noisy moves with reversals
                x += rng.randint(-6, 6)
            tg.append(x)
            sp.append(rng.choice((S.s, S.s, S.s, rng.randint(0, 12))) if rng.random() < 0.05
                      else S.s)
            bd.append(S.bd if rng.random() < 0.9 else rng.randint(0, 50))
        S.add(tg, sep=sp, bound=bd)
        if rng.random() < 0.15:
            S.reset()
        if rng.random() < 0.6 or seg == 13:
            # keep holds affordable
            if abs(wrapw(S.t - S.st.pos, cw)) * max(S.s, 1) > 6000:
                S.s = 1
            S.hold()
    return S


@cocotb.test()
async def abgen_streams(dut):
    import numpy as np
    from sim.model.abgen import abgen_fast, AbgenState

    cw = len(dut.pos_o)
    S = build_stream(cw, seed=700 + cw)
    n = len(S)
    dut._log.info("abgen COUNT_W=%d: %d clocks, %d settle points", cw, n, len(S.settle))

    # the run-based model variant on the same stream (split at the rst clocks)
    cuts = [i for i in range(n) if S.rst[i]] + [n]
    for c0, c1 in zip(cuts[:-1], cuts[1:]):
        r = abgen_fast(S.target[c0 + 1:c1], S.sep[c0 + 1:c1], S.bound[c0 + 1:c1],
                       count_w=cw, state=AbgenState())
        for k in S.exp:
            assert np.array_equal(r[k], np.array(S.exp[k][c0 + 1:c1])), \
                f"abgen_fast differs from abgen in {k} (clocks {c0 + 1}..{c1})"

    # independent x4 decoder: (A, B) -> quadrant, up = +1 along (1,1),(0,1),(0,0),(1,0)
    quad = {(1, 1): 0, (0, 1): 1, (0, 0): 2, (1, 0): 3}

    bench = fqtb.ClockedBench(dut)
    dut.rst.value = 1
    dut.target_i.value = 0
    dut.sep_i.value = 1
    dut.bound_i.value = 0
    await bench.start()
    bad = []
    names = ("a", "b", "pos", "backlog", "ovf", "sticky")
    ports = (dut.a_o, dut.b_o, dut.pos_o, dut.backlog_o, dut.ovf_o, dut.ovf_sticky_o)
    signed = (False, False, True, True, False, False)
    prev_ab = None
    dec = 0
    last_edge = None
    sticky = 0
    n_edges = 0
    prev_diff, prev_bound = 0, 0          # the edge before (its flags show on this one)
    zrng = random.Random(900 + cw)
    z_en, z_at = 0, 0
    dut.z_en_i.value, dut.z_at_i.value = z_en, z_at
    z_entries = {1: 0, -1: 0}             # Z entered moving up / down
    for i in range(n):
        if i % 97 == 0:                   # Z moves to a count near the pins
            z_en = int(zrng.random() < 0.8)
            z_at = wrapw(dec + zrng.randint(-3, 3), cw)
        dut.rst.value = S.rst[i]
        dut.target_i.value = S.target[i] & ((1 << cw) - 1)
        dut.sep_i.value = S.sep[i]
        dut.bound_i.value = S.bound[i]
        dut.z_en_i.value = z_en
        dut.z_at_i.value = z_at & ((1 << cw) - 1)
        await bench.step()
        z = fqtb.uval(dut.z_o)
        got = [fqtb.sval(p) if sg else fqtb.uval(p) for p, sg in zip(ports, signed)]
        exp = [S.exp[k][i] for k in names]
        if got != exp:
            bad.append(f"clock {i}: {dict(zip(names, got))} model {dict(zip(names, exp))}"
                       f" (target {S.target[i]} sep {S.sep[i]} bound {S.bound[i]})")
        a, b, pos, backlog, ovf, stk = got
        if S.rst[i]:
            prev_ab, dec, last_edge, sticky = (a, b), 0, None, 0
            prev_diff, prev_bound = 0, 0
            if (a, b) != (1, 1) or pos != 0 or z != 0:
                bad.append(f"clock {i}: after rst a={a} b={b} pos={pos} z={z}")
            continue
        # ---- independent checks
        dec_before = dec
        diff = wrapw(S.target[i] - dec_before, cw)     # target - pos on this edge
        if ovf != int(abs(prev_diff) > prev_bound):
            bad.append(f"clock {i}: ovf_o={ovf}, the edge before: |target - pos| = "
                       f"{abs(prev_diff)} vs bound {prev_bound}")
        if backlog != max(-32768, min(32767, prev_diff)):
            bad.append(f"clock {i}: backlog_o={backlog}, the edge before: target - pos = "
                       f"{prev_diff}")
        prev_diff, prev_bound = diff, S.bound[i]
        sticky |= ovf
        if stk != sticky:
            bad.append(f"clock {i}: ovf_sticky_o={stk}, OR of ovf_o = {sticky}")
        ta, tb = a != prev_ab[0], b != prev_ab[1]
        since = None if last_edge is None else i - last_edge
        sep_eff = max(S.sep[i], 1)
        if ta and tb:
            bad.append(f"clock {i}: A and B both changed {prev_ab} -> {(a, b)}")
        elif ta or tb:
            n_edges += 1
            step = (quad[(a, b)] - quad[prev_ab]) % 4
            dec = wrapw(dec + (1 if step == 1 else -1), cw)
            if since is not None and since < sep_eff:
                bad.append(f"clock {i}: edge {since} clocks after the last, sep {sep_eff}")
            if (1 if step == 1 else -1) != (1 if diff > 0 else -1):
                bad.append(f"clock {i}: edge away from the target (diff {diff})")
            last_edge = i
        elif diff != 0 and (since is None or since >= sep_eff):
            bad.append(f"clock {i}: no edge, target - pos = {diff}, {since} clocks since "
                       f"the last edge, sep {sep_eff}")
        prev_ab = (a, b)
        if dec != pos:
            bad.append(f"clock {i}: decoder reads {dec}, pos_o {pos}")
        if z != int(z_en and dec == z_at):
            bad.append(f"clock {i}: z_o={z}, z_en_i={z_en}, decoder {dec}, z_at_i {z_at}")
        if z and dec != dec_before:
            z_entries[1 if wrapw(dec - dec_before, cw) > 0 else -1] += 1
        if i in S.settle and dec != S.target[i]:
            bad.append(f"clock {i}: settled decoder {dec} != target {S.target[i]}")
        if len(bad) > 40:
            break
    assert not bad, f"{len(bad)} failures:\n" + "\n".join(bad[:30])
    assert min(z_entries.values()) >= 5, f"Z entered (up, down) {z_entries}: too few"
    dut._log.info("abgen COUNT_W=%d: %d clocks equal, %d edges, %d settle points met, Z "
                  "entered %d times up and %d down", cw, n, n_edges, len(S.settle),
                  z_entries[1], z_entries[-1])


async def _pins(dut, bench, moves, sep):
    """Run abgen from rst with ABGEN.ab_sep = sep through `moves` (targets, each held
    until the pins have reached it and a little longer); the pins after every clock."""
    dut.rst.value = 1
    dut.target_i.value = 0
    dut.sep_i.value = sep
    dut.bound_i.value = 0xFFFF
    await bench.step()
    dut.rst.value = 0
    a, b = [], []
    for target in moves:
        dut.target_i.value = target & 0xFFFFFFFF
        idle = 0
        while idle < 4 * sep + 64:
            await bench.step()
            a.append(fqtb.uval(dut.a_o))
            b.append(fqtb.uval(dut.b_o))
            idle = idle + 1 if fqtb.sval(dut.pos_o) == target else 0
    return a, b


@cocotb.test()
async def abgen_counters(dut):
    from sim import counters
    from sim.model import regs

    fclk = 36e6                          # the pins' clock (the harness's 27.778 ns)
    hm2 = next(c for c in counters.COUNTERS if c.name.startswith("Mesa") and c.filter_ns == 600)
    depth = round(hm2.filter_ns / hm2.sample_ns)
    moves = [0, 300, 120, 420, -50, 260]   # jumps: the pins run at their maximum rate
    bench = fqtb.ClockedBench(dut)
    dut.rst.value = 1
    await bench.start()
    default = regs.SETTINGS["ab_sep"].reset
    results = {}
    for sep in (default, 4):
        a, b = await _pins(dut, bench, moves, sep)
        times = [k * 1e9 / fclk for k in range(len(a))]
        runs = []
        for phase in (0.0, 7.0, 13.0, 21.0, 33.0):
            c = counters.FilteringCounter(depth, hm2.sample_ns, phase_ns=phase)
            c.run(times, a, b)
            runs.append((c.count, c.errors))
        results[sep] = runs
        dut._log.info("ab_sep %d (%.0f ns at 36 MHz): %s counts seen (target %d), "
                      "quadrature errors %s", sep, sep * 1e9 / fclk,
                      [r[0] for r in runs], moves[-1], [r[1] for r in runs])
    assert default * 1e9 / fclk >= hm2.min_sep_ns, "the default is faster than the filter"
    assert all(r == (moves[-1], 0) for r in results[default]), results[default]
    # the old default: counts lost without a quadrature error (the test can tell)
    assert all(r[0] != moves[-1] for r in results[4]), results[4]
    assert all(r[1] == 0 for r in results[4]), results[4]
