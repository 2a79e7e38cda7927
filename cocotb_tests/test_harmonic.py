"""harmonic (fine-phase assembly and adaptive compensation) against sim.model.harmonic,
bit for bit on every sample; and the block inside finequad_core against sim.model.core.

The block stimulus is a fine-phase stream (units of 1/8192 period) from a moving stage with
a periodic error and noise, in segments that open and close the learning gate: speeds
inside the window (16..512 units/sample) and outside it (standstill, creep, reversals,
overspeed), phase jumps that break the observer's lock, an error larger than the table's
range (updates that would leave s16 are not made), and bursts of samples on every clock
(a candidate's update is committed on the arrival of the 7th sample after it, on the
same edge as that sample's read). Strobes are back to back, every few clocks or with
random gaps; apply, learn and mu change at random edges (also while samples are in
flight) and the table is cleared at random edges, among them every edge around a
sample's arrival and edges during a running sweep.

Timing contract (rtl/harmonic.v): a sample arrives on the edge a where valid_i is high,
with its octant (oct2_i, neg_i); its harmonic bin bin_i = phase >> 7 is presented for
edge a + 1 and the phase table's value ph_i for edge a + 2 (the block assembles
phase = (2048 oct2 +- ph) mod 8192; the test splits each stream phase into such an
octant and ph); phase_o (uncorrected), phase_c_o (corrected) and valid_o are registered
on edge a + 2; apply_i is sampled on edge a + 1, learn_i and mu_i on edge a + 5; a clear
pulse sampled on edge w empties the table for the samples arriving on edges >= w, and
those arriving on edges w .. w + 64 are passed through uncorrected
(sim.model.harmonic.sweep_flags). valid_o must be high after exactly the edges a + 2;
idle inputs carry garbage.
"""
import random

import pytest

import fqtb


@pytest.mark.parametrize("pattern", ["directed", "gaps", "b2b"])
@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_harmonic(sim, pattern):
    n = {"icarus": 20000 if pattern == "directed" else 12000, "verilator": 60000}[sim]
    fqtb.run_block(sim, "harmonic", fqtb.sources("harmonic"), "test_harmonic",
                   extra_env=dict(PATTERN=pattern, SAMPLES=n), testcase="harmonic_stream")


# ---- stimulus (importable without a simulator) ----------------------------------------------
OUT_LAT = 2          # phase_o, phase_c_o registered on edge a + 2
BIN_AT = 1           # bin_i read on edge a + 1
PH_AT = 2            # ph_i used on edge a + 2
APPLY_AT = 1         # apply_i sampled on edge a + 1
LEARN_AT = 5         # learn_i, mu_i sampled on edge a + 5


def split(p):
    """A fine phase as the octant and the phase table give it: (oct2, neg, ph, bin) with
    phase = (2048 oct2 + (-ph if neg else ph)) mod 8192, 0 <= ph <= 1024."""
    oct2 = ((p + 1024) >> 11) & 3
    d = ((p - 2048 * oct2 + 4096) & 8191) - 4096
    return oct2, int(d < 0), abs(d), p >> 7


def phases(n, rng):
    """n fine-phase samples (u13, a list of ints) of a stage that ramps between speeds
    (also through zero and past the window), stands still, jumps (the observer loses
    track) and overspeeds; the error is a 1st and a 4th harmonic of the phase plus noise
    (sigma per segment; up to 50 units at low speed, so that samples hop back and forth
    between bins)."""
    import numpy as np
    nrng = np.random.default_rng(rng.randrange(1 << 30))
    h1, h4 = rng.uniform(2, 8), rng.uniform(8, 20)
    p1, p4 = rng.uniform(0, 6.3), rng.uniform(0, 6.3)
    x = rng.uniform(0, 8192)
    v = rng.choice([-1, 1]) * rng.uniform(30, 400)
    xs_all = []
    total = 0
    while total < n:
        kind = rng.choices(["cruise", "edge", "stop", "reverse", "jump", "fast",
                            "overspeed"], [60, 10, 8, 7, 5, 6, 4])[0]
        hold = rng.randint(200, 2000)
        # mostly gentle (observer lag below 200 units), sometimes hard (lag to 1300)
        acc = rng.uniform(0.0005, 0.006) if rng.random() < 0.8 else rng.uniform(0.01, 0.04)
        if kind == "cruise":
            tgt = float(np.clip(v + rng.uniform(-40, 40), -700, 700))
        elif kind == "edge":
            tgt = np.sign(v or 1) * (rng.choice([15.9, 16.0, 16.1]) if abs(v) < 250
                                     else rng.choice([511.5, 512.0, 512.5]))
        elif kind == "stop":
            tgt = rng.uniform(-2, 2)
        elif kind == "reverse":
            tgt = -v
        elif kind == "fast":
            tgt = np.sign(v or 1) * rng.uniform(600, 1500)
        else:
            tgt = v
        m = int(abs(tgt - v) / acc) + 1
        if m > 3000 or (acc > 0.006 and m > 400):     # no long spells of large lag
            m = 3000 if acc <= 0.006 else 400
            tgt = v + np.sign(tgt - v) * acc * m
        ramp = v + np.sign(tgt - v) * acc * np.arange(1, m + 1)
        ramp[-1] = tgt
        vel = np.concatenate([ramp, np.full(hold, tgt)])
        if kind == "overspeed":
            vel[:rng.randint(50, 400)] = np.sign(v or 1) * rng.uniform(2500, 4000)
        xs = x + np.cumsum(vel)
        if kind == "jump":
            j = rng.randrange(len(xs))
            xs[j:] += rng.choice([-1, 1]) * rng.uniform(300, 3000)
        x, v = float(xs[-1]), float(tgt)
        # large noise at low speed sends samples back and forth across bin edges
        sigma = rng.choice([0.5, 2.0, 5.0, 8.0] + ([30.0, 50.0] if abs(v) < 60 else []))
        err = (h1 * np.sin(2 * np.pi * xs / 8192 + p1) + h4 * np.sin(8 * np.pi * xs / 8192 + p4)
               + sigma * nrng.standard_normal(len(xs)))
        xs_all.append(np.round(xs + err).astype(np.int64) % 8192)
        total += len(xs)
    return np.concatenate(xs_all)[:n].tolist()


def directed(n):
    """A stage at 20 units/sample (six samples per bin) with a 4th-harmonic error of 200
    units (more than the table holds: the entries run into the s16 limits), mu 3..6,
    phase jumps (the observer loses track), learn and apply off spells, clear pulses on
    every edge from 2 before to 7 after a sample's arrival and during a sweep, and a
    spell of large noise (samples hop between bins). Strobes back to back, then every 2
    or 3 clocks."""
    import numpy as np
    k = np.arange(n)
    x = 100.0 + 20.0 * k
    for j in (n * 3 // 10, n * 7 // 10):
        x[j:] += 2500.0                               # jumps: the observer loses track
    # noise of 40 units in [0.56 n, 0.68 n): samples hop back and forth between bins
    noise = np.where((k >= n * 56 // 100) & (k < n * 68 // 100),
                     40.0 * np.random.default_rng(5).standard_normal(n), 0.0)
    ph = (np.round(x + 200.0 * np.sin(8 * np.pi * x / 8192) + noise) % 8192).astype(np.int64)
    gaps = np.where(k < n // 2, 1, np.where(k % 3 == 0, 3, 2))
    edges = (12 + np.concatenate([[0], np.cumsum(gaps[:-1])])).tolist()
    ctrl = {0: (1, 1, 3)}

    def at(frac, val, off=0):
        ctrl[edges[int(n * frac)] + off] = val

    at(0.40, (1, 1, 5), 3)        # mid-flight changes of mu
    at(0.45, (1, 0, 5), 1)        # learn off
    at(0.50, (0, 1, 4), 2)        # apply off, learning goes on
    at(0.55, (1, 1, 6), 4)
    at(0.85, (1, 1, 3), 5)
    at(0.90, (1, 1, 4))
    clears = []
    for i, off in enumerate(range(-2, 8)):
        kk = int(n * (0.32 + 0.025 * i))
        clears.append(edges[kk] + off)
    clears.append(clears[-1] + 30)                    # during the sweep
    return edges, ph.tolist(), ctrl, sorted(set(clears))


def schedule(pattern, n, seed):
    """(arrival edges, phases, control changes {edge: (apply, learn, mu)}, clear edges)."""
    if pattern == "directed":
        return directed(n)
    rng = random.Random(seed)
    ph = phases(n, rng)
    edges = []
    e = 12
    burst = 0
    for _ in range(n):
        edges.append(e)
        if pattern == "b2b":
            gap = 1 if rng.random() < 0.97 else rng.randint(2, 12)
        else:
            if burst:
                burst -= 1
                gap = 1
            else:
                r = rng.random()
                if r < 0.05:
                    burst = rng.randint(2, 20)
                    gap = 1
                else:
                    gap = rng.choice([2, 3, 4, 5, 7, 8, 9, 13, 20, 36, 60])
        e += gap
    last = edges[-1]
    # control changes: mostly apply = learn = 1, mu 3..6
    ctrl = {0: (1, 1, 4)}
    for _ in range(max(8, n // 400)):
        w = rng.randint(1, last)
        ctrl[w] = (int(rng.random() < 0.8), int(rng.random() < 0.85),
                   rng.choice([3, 3, 4, 4, 4, 5, 6]))
    clears = set()
    for _ in range(max(4, n // 2000)):
        k = rng.randrange(8, n)
        clears.add(edges[k] + rng.choice([-2, -1, 0, 0, 1, 1, 2, 3, 4, 5, 6, 7]))
    return edges, ph, ctrl, sorted(clears)


def model_inputs(edges, ctrl, clears):
    """Per-sample apply, learn, mu, clear and blocked flags as the RTL samples them."""
    import bisect
    import numpy as np
    from sim.model import harmonic as hm
    ce = sorted(ctrl)

    def at(e):
        return ctrl[ce[bisect.bisect_right(ce, e) - 1]]

    apply = np.array([at(a + APPLY_AT)[0] for a in edges], dtype=np.int64)
    learn = np.array([at(a + LEARN_AT)[1] for a in edges], dtype=np.int64)
    mu = np.array([at(a + LEARN_AT)[2] for a in edges], dtype=np.int64)
    clear, blocked = hm.sweep_flags(edges, clears)
    return apply, learn, mu, clear, blocked


def expected(pattern, n, seed):
    from sim.model import harmonic as hm
    edges, ph, ctrl, clears = schedule(pattern, n, seed)
    apply, learn, mu, clear, blocked = model_inputs(edges, ctrl, clears)
    h = hm.Harmonic()
    out = h.run(ph, apply=apply, learn=learn, mu=mu, clear=clear, blocked=blocked)
    return edges, ph, ctrl, clears, out, h


# ---- cocotb side -----------------------------------------------------------------------------
import cocotb  # noqa: E402


async def _watch(sig, log):
    from cocotb.triggers import ValueChange
    from cocotb.utils import get_sim_time
    while True:
        await ValueChange(sig)
        log.append((get_sim_time(unit="ps"), fqtb.uval(sig)))


@cocotb.test()
async def harmonic_stream(dut):
    pattern = fqtb.env_str("PATTERN")
    n = fqtb.env_int("SAMPLES")
    seed = {"directed": 0, "gaps": 11, "b2b": 12}[pattern]
    edges, ph, ctrl, clears, exp, h = expected(pattern, n, seed)
    log = dut._log
    log.info("%s: %d samples over %d edges, %d clears, model updates %d, table %s..%s",
             pattern, n, edges[-1], len(clears), h.learned, min(h.A), max(h.A))

    strobe = {e: k for k, e in enumerate(edges)}
    reads = {e + OUT_LAT: k for k, e in enumerate(edges)}
    clear_set = set(clears)
    slots = set()
    for e in list(strobe) + list(ctrl) + clears:
        slots.add(e - 1)
        slots.add(e)
    slots.update(reads)

    bench = fqtb.ClockedBench(dut)
    a0, l0, m0 = ctrl[0]
    dut.valid_i.value = 0
    dut.oct2_i.value = 0
    dut.neg_i.value = 0
    dut.bin_i.value = 0
    dut.ph_i.value = 0
    dut.apply_i.value = a0
    dut.learn_i.value = l0
    dut.mu_i.value = m0 - 3
    dut.clear_i.value = 0
    parts = [split(p) for p in ph]
    bins = {e + BIN_AT: k for k, e in enumerate(edges)}
    phs = {e + PH_AT: k for k, e in enumerate(edges)}
    slots.update(e - 1 for e in list(bins) + list(phs))
    slots = sorted(s for s in slots if s >= 0)
    await bench.start()
    vlog = []
    cocotb.start_soon(_watch(dut.valid_o, vlog))
    got = [None] * n
    junk = random.Random(seed + 1)
    for s in slots:
        await bench.goto(s)
        k = reads.get(s)
        if k is not None:
            got[k] = (fqtb.uval(dut.phase_o), fqtb.uval(dut.phase_c_o))
        nxt = s + 1
        k = strobe.get(nxt)
        if k is not None:
            dut.valid_i.value = 1
            dut.oct2_i.value, dut.neg_i.value = parts[k][0], parts[k][1]
        else:                                          # idle clocks carry garbage
            dut.valid_i.value = 0
            dut.oct2_i.value, dut.neg_i.value = junk.randrange(4), junk.randrange(2)
        k = bins.get(nxt)
        dut.bin_i.value = parts[k][3] if k is not None else junk.randrange(64)
        k = phs.get(nxt)
        dut.ph_i.value = parts[k][2] if k is not None else junk.randrange(4096)
        if nxt in ctrl:
            a, lr, m = ctrl[nxt]
            dut.apply_i.value = a
            dut.learn_i.value = lr
            dut.mu_i.value = m - 3
        dut.clear_i.value = int(nxt in clear_set)
    await bench.goto(bench.edge + 4)

    bad = [k for k in range(n) if got[k] != (ph[k], int(exp[k]))]
    if bad:
        lines = [f"sample {k} (arrival edge {edges[k]}, phase {ph[k]}): rtl (phase, "
                 f"corrected) {got[k]}, model {(ph[k], int(exp[k]))}" for k in bad[:12]]
        raise AssertionError(f"{len(bad)} of {n} samples differ, first:\n" + "\n".join(lines))
    assert h.learned > n // 40, f"only {h.learned} updates: the stimulus hardly learns"

    # valid_o high after exactly the edges a + 2
    high = set()
    rise = None
    for tm, v in vlog:
        e, r = divmod(int(tm - bench.t0), fqtb.PERIOD_PS)
        assert r == 0, f"valid_o changed between clock edges (t={tm} ps)"
        if v == 1 and rise is None:
            rise = e
        elif v == 0 and rise is not None:
            high.update(range(rise, e))
            rise = None
    assert rise is None
    want = {e + OUT_LAT for e in edges}
    assert high == want, f"valid_o edges differ: {sorted(high ^ want)[:8]}"
    nc = sum(1 for k in range(n) if int(exp[k]) != ph[k])
    log.info("%s: %d samples equal (%d corrected), %d updates", pattern, n, nc, h.learned)


# ==== the block in the core: finequad_core against sim.model.core.run ==========================
# A stage at 40 units/sample with a 1 % third harmonic; strobes back to back, then with
# random gaps. HARM (0x12) is written during the run: mu = 3, a clear, apply off, learn
# off, apply on again with mu = 5; the count of every sample and the HARM read-back must
# equal the model's. (The estimator calibrates meanwhile; the block sees whatever phase
# comes.)
CORE_SOURCES = fqtb.core_sources()
HARM_ADDR = 0x12


@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_core_harmonic(sim):
    n = {"icarus": 7000, "verilator": 40000}[sim]
    fqtb.run_block(sim, "finequad_core", CORE_SOURCES, "test_harmonic",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR), TABLE_EXACT=1),
                   extra_env=dict(SAMPLES=n), testcase="core_harmonic")


def harm_value(apply, learn, mu, clear=0):
    """HARM register word."""
    return apply | learn << 1 | (mu - 3) << 4 | clear << 8


def core_stimulus(n):
    """(u1, u2, strobe edges, HARM writes [(edge, value)])."""
    import numpy as np
    from sim import siggen
    rng = np.random.default_rng(21)
    x = siggen.constant_speed(n, 1e6, 40 / 8192 * 4000 * 1e6, x0=123.0)    # 40 units/sample
    sig = siggen.Signal(A1=0.5, A2=0.47, h3=0.01, noise=0.004)
    u1, u2, _ = siggen.encode(x, 4000.0, sig, seed=22)
    gaps = np.where(np.arange(n) < n // 3, 1,
                    rng.choice([1, 1, 1, 2, 3, 5, 8, 13, 21, 36], size=n))
    t = 16 + np.concatenate([[0], np.cumsum(gaps[:-1])])
    writes = [(int(t[int(n * 0.45)]) - 3, harm_value(1, 1, 3)),
              (int(t[int(n * 0.55)]) + 7, harm_value(1, 1, 3, clear=1)),
              (int(t[int(n * 0.70)]) + 11, harm_value(0, 1, 4)),
              (int(t[int(n * 0.80)]) + 15, harm_value(1, 0, 4)),
              (int(t[int(n * 0.90)]) + 12, harm_value(1, 1, 5))]
    return u1.astype(np.int64), u2.astype(np.int64), t.astype(np.int64), writes


def core_config(t, writes):
    """Config with the per-sample HARM fields the RTL samples (sim/model/core.py)."""
    import numpy as np
    from sim.model import core
    n = len(t)
    apply = np.ones(n, np.int64)
    learn = np.ones(n, np.int64)
    mu = np.full(n, 4, np.int64)
    clears = []
    for w, v in writes:
        # a write on edge w is seen on the edges after it: apply is sampled on edge
        # t + HARM_AT + APPLY_AT, learn and mu on t + HARM_AT + LEARN_AT
        a_new = t + core.HARM_AT + APPLY_AT > w
        l_new = t + core.HARM_AT + LEARN_AT > w
        apply[a_new] = v & 1
        learn[l_new] = (v >> 1) & 1
        mu[l_new] = ((v >> 4) & 3) + 3
        if v >> 8 & 1:
            clears.append(w)
    return core.Config(harm_apply=apply, harm_learn=learn, harm_mu=mu, harm_clears=clears)


@cocotb.test()
async def core_harmonic(dut):
    import numpy as np
    from sim.model import core
    n = fqtb.env_int("SAMPLES")
    u1, u2, t, writes = core_stimulus(n)
    res = core.run(u1, u2, core_config(t, writes), strobes=t, trace=True)
    h = res["harm"]
    log = dut._log
    log.info("core: %d samples, %d table updates, %d samples corrected", n, h.learned,
             int(np.sum(res["phase_c"] != res["phase"])))
    assert h.learned > n // 40
    lat = core.LATENCY
    strobe = {int(e): k for k, e in enumerate(t)}
    reads = {int(e) + lat: k for k, e in enumerate(t)}
    wr = dict(writes)
    slots = set(reads)
    for e in list(strobe) + list(wr):
        slots.update((e - 1, e))
    bench = fqtb.ClockedBench(dut)
    dut.rst.value = 0
    dut.s_valid.value = 0
    dut.s_u1.value = 0
    dut.s_u2.value = 0
    dut.reg_we.value = 0
    dut.reg_re.value = 0
    dut.reg_addr.value = 0
    dut.reg_wdata.value = 0
    await bench.start()
    got = np.zeros(n, dtype=np.int64)
    for s in sorted(slots):
        await bench.goto(s)
        k = reads.get(s)
        if k is not None:
            assert fqtb.uval(dut.m_valid) == 1, f"m_valid low for sample {k}"
            got[k] = fqtb.sval(dut.m_count)
        k = strobe.get(s + 1)
        dut.s_valid.value = int(k is not None)
        if k is not None:
            dut.s_u1.value = int(u1[k])
            dut.s_u2.value = int(u2[k])
        if s + 1 in wr:
            dut.reg_we.value = 1
            dut.reg_addr.value = HARM_ADDR
            dut.reg_wdata.value = wr[s + 1]
        else:
            dut.reg_we.value = 0
    bad = np.nonzero(got != res["count"])[0]
    if len(bad):
        k = int(bad[0])
        raise AssertionError(f"{len(bad)} of {n} counts differ, first sample {k} (strobe "
                             f"edge {int(t[k])}): rtl {int(got[k])}, model "
                             f"{int(res['count'][k])}, phase {int(res['phase'][k])}, "
                             f"phase_c {int(res['phase_c'][k])}")
    await bench.goto(bench.edge + 30)
    dut.reg_addr.value = HARM_ADDR                 # a registered read: reg_re for one edge
    dut.reg_re.value = 1
    await bench.step()
    dut.reg_re.value = 0
    rd = fqtb.uval(dut.reg_rdata)
    exp = writes[-1][1] & 0x33
    assert rd == exp, f"HARM read-back {rd:#x}, expected {exp:#x}"
    log.info("core: %d counts equal, HARM %#x", n, rd)
