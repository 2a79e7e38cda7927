"""harmonic (rtl/harmonic.v: fine-phase assembly and adaptive compensation) against
sim.model.harmonic, and the block inside finequad_core against sim.model.finequad_core: bit for
bit, every output, every sample.

Block (test_harmonic). Timing, from rtl/harmonic.v's header, with the offsets that the
core model has taken from sim.model.finequad_core (HARM_AT, ADDR_AT, PHASE_AT): a sample arrives on
the edge a on which valid_i is high (t + HARM_AT in the core), with oct2_i and neg_i;
t_i (the octant address's scale, from which rtl/hbin.v finds the bin) is presented for
edge a + BIN_AT (ADDR_AT - HARM_AT: the tables are read) and ph_i
for edge a + OUT_AT (PHASE_AT - HARM_AT), after which phase_o, phase_c_o and valid_o hold
the sample. apply_i is sampled on a + APPLY_AT (1), learn_i and mu_i on a + LEARN_AT (7)
(the header's numbers: sim.model has no names for them); a clear_i pulse on edge w
empties the table for the samples arriving on edges >= w and blocks (no correction, no
learning) those arriving on w .. w + SWEEP (harmonic.sweep_flags). oct2_i, neg_i, t_i
and ph_i carry a sample's values only on the edge they are read on and garbage on every
other edge; apply_i, learn_i and mu_i are levels (the core's registers).
The stimulus is a stream of angles (a moving stage with a periodic error and noise) made
into corrected signals on a circle and put through sim.model.octant and Lut
(front()), so that oct2 (base / 2048), neg, t (scale), ph (PH[j], ~PH[j] for
neg: rtl/lut.v ph_o) and the model's bin = phase >> 7 are what the core's octant and
phase table give (hbin(t) = bin: cocotb_tests/test_hbin.py). Both table memories: block
RAM (OPT_DISTRAM = 0, read on a + 1 with the same-edge collision undone) and distributed
RAM (OPT_DISTRAM = 1, read after a + 1 from copies written one edge late). Checked:
phase_o equals the model's fine phase (Lut.phase) and phase_c_o the output of
sim.model.harmonic.Harmonic.run, for every sample; valid_o is high after exactly the
edges a + OUT_AT; the model learns (more than one update per 40 samples).

  directed  one stream of some 33 000 samples, the same on every simulator (DIRECTED,
            directed_stim), with the 4th-harmonic error beyond the table's range:
            - the learning window: |V| held above it (540 units/sample: nothing is
              learned), just inside its upper edge (511.97: every candidate lands in one
              of 16 bins, whose entries reach the s16 limits and updates that would leave
              them are not made), ramps through 512 and through 16 (both signs);
            - the observer's gears: three velocity steps lose the lock (C back to 0, the
              wide gear, the narrow one from C = 256, learning again from C = 2047; the
              step is placed so that a candidate arrives with C = 2046);
            - register changes on exact edges at samples chosen from the model's state
              (Planner): apply off and on, for one edge and as a step, at a + APPLY_AT
              of samples whose correction is not 0; learn off and on, for one edge and as
              steps, and mu steps and one-edge pulses at a + LEARN_AT (or one edge later)
              of learning candidates whose update is not 0 (or changes with mu); each
              back to back, with gaps of 2 and 3 and with random gaps;
            - clears: on a sample's arrival edge and on the edge after it (gaps of 2 and
              3), with a learning candidate arriving on the last blocked edge w + SWEEP
              and on the first free one, a clear during a sweep, clears on every edge
              from 2 before a learning candidate's arrival to 1 after its commit (the
              update in flight is dropped) back to back and with random gaps, a clear
              inside a gap longer than the sweep; samples read the partly swept table
              meanwhile;
            - a spell of large noise (samples hop between bins).
            Every event but the clears around candidates changes the model's output when
            moved by one edge in the directions that matter for it (a step on a
            candidate's a + LEARN_AT tells early sampling from the model, one on
            a + LEARN_AT + 1 late sampling), so a block that samples any input one edge
            off cannot pass.
  gaps      seeded random stream (speed segments through and around the window,
            standstill, reversals, jumps, overspeed, noise up to 50 units), the paper's
            table (ph beyond 1024: phases past the octant's border), random gaps up to
            70 clocks with bursts back to back, random register changes and clears.
  b2b       the same with the exact table and strobes back to back (a few gaps).
  slow      slow motion (0.01 to 24 units/sample, standstill, dither, reversals, gentle
            accelerations to gear 0, jumps) with strobes back to back: the observer's
            gears, up and down and back to 0 on a lost lock, and learning in them
            (400 000 samples on Verilator; test_slow_stream_exercises_gears).

test_directed_sensitivity (no simulator): every placed event moved by one edge, and
each model constant of MUTATIONS changed (window edges 16 and 512 by one unit/sample,
the gear switch at C = 256 by one, the gears' gains, learning from C = 2047, the lock
and lost thresholds, the sweep length, the commit delay, the candidates, the mean, the
anchor, the entry and update limits, the gear shifts, the lag gates, the slow gears'
and the annealed step), changes the expected output of the directed stream or of a
random one.

Core (test_core_harmonic): finequad_core (TABLE_EXACT=1) against sim.model.finequad_core.run, a
stage at 40 units/sample with a 1 % third harmonic, strobes back to back, then random
gaps; n = 511 (written to 0x01 before the first sample) so that the count resolves 4
phase units. HARM (0x12) writes are placed like the block's events (Planner on the
core's fine phase, arrivals t + HARM_AT, a write on edge w reaching the block on edge
w + 1, the count's fine part as the observable): apply off and on (steps, one edge),
learn off and on, mu 6 and back at learning candidates, a clear with a learning
candidate on the last blocked edge, and the same in the gaps; on Verilator, 12 random
writes (clears among them) after the first CORE_PLAN samples. Checked: m_count, m_a,
m_b and m_fault of every sample after edge t + LATENCY equal the model's, m_valid is
high after exactly those edges, and HARM read through the registered port (reg_re
with reg_addr for edge e, reg_rdata after it) on the edge of every HARM write (the value
before it) and on the edge after (the value written, without the clear bit). s_u1, s_u2
and the register port carry garbage on idle edges. test_core_sensitivity (no
simulator): every placed write moved by one edge (the directions that matter) changes
sim.model.finequad_core's outputs.
"""
import bisect
import copy
import functools
import random

import numpy as np
import pytest

import fqtb
from sim.model import finequad_core as core_model
from sim.model import lut as lut_m, octant as octant_m
from sim.model import harmonic as hm
from sim.model import regs
from sim.model import tables

# ---- timing, in edges after a sample's arrival a (the edge on which valid_i is high) --------
# The core strobes sample k on edge t and the block sees its arrival on t + HARM_AT; the
# phase table and the harmonic table are read on t + ADDR_AT, the phases registered on
# t + PHASE_AT (sim/model/finequad_core.py).
ARRIVE_AT = core_model.HARM_AT
BIN_AT = core_model.ADDR_AT - ARRIVE_AT       # t_i read
OUT_AT = core_model.PHASE_AT - ARRIVE_AT      # ph_i used; phase_o, phase_c_o, valid_o after
# The block's register sampling, as rtl/harmonic.v's header states it (sim/model has no
# names for them; core.Config's harm_* text uses the same offsets).
APPLY_AT = 1                                  # apply_i
LEARN_AT = 7                                  # learn_i, mu_i

# table kind of each block stream; samples of the random streams per simulator (the
# directed stream is the same everywhere)
PATTERNS = {"directed": "exact", "gaps": "paper", "b2b": "exact", "slow": "exact",
            "long": "exact"}
SAMPLES = {"icarus": {"gaps": 6000, "b2b": 10000, "slow": 20000},
           "verilator": {"gaps": 40000, "b2b": 60000, "slow": 400000, "long": 340000}}
# GHDL (the VHDL edition) runs Icarus's streams but the slow one: some 30 s in all
SAMPLES["ghdl"] = {p: n for p, n in SAMPLES["icarus"].items() if p != "slow"}
# (the long stream, no clears, takes the step through all its halvings: Verilator only)
RUNS = [(s, p) for s in fqtb.simulators("harmonic") for p in PATTERNS
        if p == "directed" or p in SAMPLES[fqtb.plan_sim(s)]]


@pytest.mark.parametrize("distram", [0, 1], ids=["BRAM", "DISTRAM"])
@pytest.mark.parametrize("sim, pattern", RUNS)
def test_harmonic(sim, pattern, distram):
    n = SAMPLES[fqtb.plan_sim(sim)].get(pattern, 0)
    exact = int(PATTERNS[pattern] == "exact")
    fqtb.run_block(sim, "harmonic", fqtb.sources("harmonic", "hbin"), "test_harmonic",
                   parameters=dict(TABLE_EXACT=exact, OPT_DISTRAM=distram,
                                   SHOW=show_of(pattern)),
                   extra_env=dict(PATTERN=pattern, SAMPLES=n), testcase="harmonic_stream")


def show_of(pattern):
    """rtl/harmonic.v SHOW of a stream: the b2b and long streams use the default (sig:
    the table shown once significant, and hidden again); the directed, gaps and slow
    streams show every table, so that the correction and what is learned are seen at
    once (the directed stream's events are placed on that; on Icarus the gaps and slow
    streams are too short for a table to become significant)."""
    return hm.SIG_ON if pattern in ("b2b", "long") else 0


def test_sig_switches():
    """The streams the RTL runs with SHOW = 2**15 take sig both ways: the b2b stream
    (on both simulators) shows the table once significant and hides it again, by a
    clear and by a table that shrinks (the hysteresis); the long one shows it."""
    for sim in fqtb.SIMULATORS:
        st = stimulus("b2b", SAMPLES[fqtb.plan_sim(sim)]["b2b"])
        assert st.show == hm.SIG_ON
        _, tr, _ = run_model(st, trace=True)
        clear = model_inputs(st.edges, st.ctrl, st.clears)[3]
        sw = np.diff(tr["sig"].astype(np.int64))
        on, off = np.nonzero(sw == 1)[0] + 1, np.nonzero(sw == -1)[0] + 1
        print(f"b2b on {sim}: sig on at {on.tolist()}, off at {off.tolist()}")
        assert len(on) >= 1 and len(off) >= 1
        if sim == "verilator":
            assert len(on) >= 2 and any(not clear[k] for k in off), off
    _, tr, _ = run_model(stimulus("long", SAMPLES["verilator"]["long"]), trace=True)
    assert tr["sig"].any()


def test_slow_stream_exercises_gears():
    """The slow stream (the RTL runs it on Verilator) takes the observer through its
    gears: every kind of gear change (up, down, back to 0 on a lost lock), gears up to 4,
    and learning in gears above 0 with and without the step halved again (the other streams
    learn in gear 0; make bench-accuracy's creep scenarios take the core's RTL to gears 8
    and 11, sim/tests/test_rtlsim.py's slow scan to gear 5)."""
    st = stimulus("slow", SAMPLES["verilator"]["slow"])
    _, tr, _ = run_model(st, trace=True)
    conv = np.bincount(tr["conv"], minlength=4)
    learned = np.bincount(tr["gb"][tr["gate"].astype(bool)], minlength=hm.GMAX + 1)
    assert conv[1] >= 5 and conv[2] >= 1 and conv[3] >= 1, conv
    assert tr["g"].max() >= 4
    assert learned[1:hm.GSLOW].max() > 500 and learned[hm.GSLOW:].max() > 500, learned


# Model constants changed one at a time: the directed stream's expected output must change
# with each (an RTL that had the changed constant could not pass).
MUTATIONS = [
    ("VMIN", 15), ("VMIN", 17), ("VMAX", 511), ("VMAX", 513),       # learning window
    ("VMAX", 1024),
    ("GAINS", ((255, 2, 10), (None, 7, 15))),                         # gear switch at C = 256
    ("GAINS", ((257, 2, 10), (None, 7, 15))),
    ("GAINS", ((256, 3, 11), (None, 7, 15))),                         # the gears' gains
    ("GAINS", ((256, 2, 10), (None, 6, 14))),
    ("C_MAX", 2046),                                                  # learning from C = 2047
    ("ELOCK", 248), ("ELOCK", 264),                                   # lock gate |E| < 256
    ("ELOST", 992), ("ELOST", 1056),                                  # lock lost |E| >= 1024
    ("SWEEP", 63), ("SWEEP", 65),                                     # clear: blocked samples
    ("D", 8), ("D", 10),                                              # commit on sample k + 9
    ("SKIP_MIN", 8), ("SKIP_MIN", 10), ("LFSR_SEED", 0xE0),           # candidates
    ("KM", 9), ("KM", 11), ("ANCHOR", 3), ("ANCHOR", 5),              # mean of E, anchor
    ("H_W", 15), ("H_W", 17), ("D_W", 11),                            # entry and update limits
    ("VUP", 15), ("VUP", 17), ("VDOWN", 63), ("VDOWN", 65),           # gear shifts
    ("GDELAY", 5), ("GDELAY", 7), ("SETTLE", 255), ("SETTLE", 257),
    ("MQ", (2 << 7) - 1), ("MQ", (2 << 7) + 1),                       # |M| < 2 units
    ("EQUIET", 32), ("EQUIET", 128), ("GSLOW", 3), ("GSLOW", 5),      # learning in gears
    ("ANNEAL", 1024), ("ANNEAL", 2049), ("ANNEALS", 2), ("ANNEALS", 4),  # the step halves
    ("SIG_LAG", 2), ("SIG_LAG", 4), ("SIG_HYST", 0), ("SIG_HYST", 2),  # sig
]


def test_directed_sensitivity(monkeypatch):
    """The directed stream tells the exact edges apart (every placed event moved by one
    edge, in the directions that matter for it, see Planner, changes the model's output)
    and the streams the RTL runs tell the constants apart (every entry of MUTATIONS
    changes the output of the directed stream or of a random one)."""
    st = directed_stim()
    out = run_model(st)[0]
    same = []
    for name, k, items, shifts, end in st.events:
        # (the difference is in the samples before `end`: the model runs up to there)
        pre = Stim(st.edges[:end], {key: v[:end] for key, v in st.f.items()}, {}, [],
                   show=st.show)
        for sh in shifts:
            ctrl, clears = moved(st.ctrl, st.clears, items, sh)
            if np.array_equal(run_model(pre, ctrl, clears)[0], out[:end]):
                same.append(f"{name} (sample {k}) moved by {sh:+d} edge")
    # (a constant the directed stream cannot tell must change the output of one of the
    # random streams, which the RTL runs too)
    others = [stimulus(p, SAMPLES["verilator"][p]) for p in ("b2b", "slow", "long")]
    outs = [run_model(o)[0] for o in others]
    for name, val in MUTATIONS:
        with monkeypatch.context() as m:
            m.setattr(hm, name, val)
            if all(np.array_equal(run_model(x)[0], y)
                   for x, y in zip([st] + others, [out] + outs)):
                same.append(f"harmonic.{name} = {val}")
    assert not same, "the directed stream does not tell apart:\n" + "\n".join(same)


# ---- stimulus (importable without a simulator) ----------------------------------------------
def front(x, kind, rng, spread):
    """What the core's octant and phase table give for a stream of angles x (float, phase
    units): corrected signals on a circle of radius 16384 (1 +- spread) (s2.14, rounded)
    through sim.model.octant and Lut(kind). Returns int64 arrays oct2 (base
    phase / 2048), neg, t = the address's scale (scale), ph = the phase table's
    word (PH[j], its 12-bit complement for neg: rtl/lut.v ph_o), bin = phase >> 7 and
    phase (Lut.phase)."""
    a = 2 * np.pi * np.asarray(x, dtype=float) / tables.PH_PERIOD
    r = 16384.0 * (1.0 + spread * (2.0 * rng.random(len(a)) - 1.0))
    u1 = np.rint(r * np.cos(a)).astype(np.int64)
    u2 = np.rint(r * np.sin(a)).astype(np.int64)
    ax, ay = np.minimum(np.abs(u1), 32767), np.minimum(np.abs(u2), 32767)
    j, base, neg = octant_m.octant(ax, ay, u1 < 0, u2 < 0, kind)
    lut = lut_m.Lut(kind)
    phase = lut.phase(j, base, neg)
    return dict(oct2=base // (tables.PH_PERIOD // 4), neg=neg, t=octant_m.scale(ax, ay, kind),
                ph=lut.ph[j] ^ (neg * ((1 << tables.PHT_W) - 1)),
                bin=phase >> hm.BIN_SHIFT, phase=phase)


class Stim:
    """A block stream: arrival edges, front (oct2, neg, ph, bin, phase per sample), control
    {edge: (apply, learn, mu)} (the value from that edge on), clear edges, and the placed
    events (name, sample, items, shifts, end) of a directed stream (Planner.place)."""

    def __init__(self, edges, f, ctrl, clears, events=(), show=hm.SIG_ON):
        self.show = show             # rtl/harmonic.v SHOW
        self.edges = np.asarray(edges, dtype=np.int64)
        self.f = f
        self.ctrl = dict(ctrl)
        self.clears = sorted(clears)
        self.events = list(events)


def model_inputs(edges, ctrl, clears):
    """Per-sample apply, learn, mu, clear and blocked as the block samples them."""
    a = np.asarray(edges, dtype=np.int64)
    ce = np.array(sorted(ctrl), dtype=np.int64)
    cv = np.array([ctrl[e] for e in ce], dtype=np.int64)

    def at(e):
        return cv[np.searchsorted(ce, e, side="right") - 1]

    lm = at(a + LEARN_AT)
    clear, blocked = hm.sweep_flags(a, clears)
    return at(a + APPLY_AT)[:, 0], lm[:, 1], lm[:, 2], clear, blocked


def run_model(st, ctrl=None, clears=None, trace=False):
    """sim.model.harmonic on a stream: (phase_c, Harmonic) or with trace (phase_c, trace,
    Harmonic)."""
    apply, learn, mu, clear, blocked = model_inputs(
        st.edges, st.ctrl if ctrl is None else ctrl, st.clears if clears is None else clears)
    h = hm.Harmonic(show=st.show)
    r = h.run(st.f["phase"], apply=apply, learn=learn, mu=mu, clear=clear, blocked=blocked,
              trace=trace)
    return (*r, h) if trace else (r, h)


def moved(ctrl, clears, items, shift):
    """Control and clears with the event `items` moved by `shift` edges."""
    ctrl, clears = dict(ctrl), list(clears)
    for it in items:
        if it[0] == "ctrl":
            del ctrl[it[1]]
        else:
            clears.remove(it[1])
    for it in items:
        if it[0] == "ctrl":
            ctrl[it[1] + shift] = it[2]
        else:
            clears.append(it[1] + shift)
    return ctrl, sorted(clears)


class Planner:
    """Places register changes and clears on exact edges relative to samples chosen from
    the model's state. Events are placed in order of their samples; `place` takes the
    first sample k in [lo, hi) that meets `pre` (on the model's trace without the event)
    and `post` (on the trace with it) and where the event moved by each of `shifts` edges
    changes the observable (`score` of the model's output) of the samples before k +
    reach. Later events act only on edges after those samples' last sampling edge, so the
    difference stays in the finished stream. The model state is kept at the last
    sample that no event still to come can change, so a placement costs a few thousand
    samples of the model."""

    def __init__(self, edges, phase, ctrl0, score=None, show=hm.SIG_ON):
        self.a = np.asarray(edges, dtype=np.int64)
        self.phase = np.asarray(phase, dtype=np.int64)
        self.n = len(self.a)
        self.ctrl = {0: tuple(ctrl0)}
        self.clears = []
        self.events = []
        self.score = score or (lambda out: out)
        self.h = hm.Harmonic(show=show)   # rtl/harmonic.v SHOW
        self.pos = 0             # self.h has seen samples [0, pos)
        self.floor = 0           # the next event's edges must be >= this

    def _run(self, h, hi, trace, ctrl=None, clears=None):
        ap, le, mu, cl, bl = model_inputs(self.a, self.ctrl if ctrl is None else ctrl,
                                          self.clears if clears is None else clears)
        s = slice(self.pos, hi)
        return h.run(self.phase[s], apply=ap[s], learn=le[s], mu=mu[s], clear=cl[s],
                     blocked=bl[s], trace=trace)

    def peek(self, hi, ctrl=None, clears=None, trace=True):
        """The model on samples [pos, hi) (a copy of the state)."""
        return self._run(copy.deepcopy(self.h), hi, trace, ctrl, clears)

    def now(self, e):
        ce = sorted(self.ctrl)
        return self.ctrl[ce[bisect.bisect_right(ce, e) - 1]]

    def place(self, name, lo, hi, make, pre=None, post=None, shifts=(-1, 1), reach=60):
        """Returns the first sample after the event's reach (where the next may go)."""
        hi = min(hi, self.n - reach)
        start = bisect.bisect_left(self.a, self.floor - 200)
        if start > self.pos:
            self._run(self.h, start, False)
            self.pos = start
        _, tr = self.peek(hi)
        for k in range(max(lo, self.pos), hi):
            i = k - self.pos
            if pre is not None and not pre(tr, i):
                continue
            items = make(k)
            first = min(it[1] for it in items)
            if first - 1 < self.floor or any(first - 1 <= e <= first + 8 for e in self.ctrl):
                continue
            ctrl, clears = dict(self.ctrl), list(self.clears)
            for it in items:
                if it[0] == "ctrl":
                    ctrl[it[1]] = it[2]
                else:
                    clears.append(it[1])
            clears.sort()
            end = k + reach
            out, tr2 = self.peek(end, ctrl, clears)
            if post is not None and not post(tr, tr2, i):
                continue
            sc = self.score(out)
            if all(not np.array_equal(self.score(self.peek(end, *moved(ctrl, clears, items, sh),
                                                           trace=False)), sc)
                   for sh in shifts):
                self.ctrl, self.clears = ctrl, clears
                self.events.append((name, k, items, tuple(shifts), end))
                # the samples before `end` sample their inputs on edges < a[end] + LEARN_AT
                self.floor = int(self.a[end]) + LEARN_AT + 2
                return end
        raise RuntimeError(f"no sample in [{lo}, {hi}) takes the event '{name}'")

    # ---- events (make(k) -> items) ----------------------------------------------------------
    def pulse(self, field, val, at):
        """apply (field 0), learn (1) or mu (2) = val for the one edge a_k + at."""
        def make(k):
            e = int(self.a[k]) + at
            new = list(self.now(e))
            new[field] = val
            return [("ctrl", e, tuple(new)), ("ctrl", e + 1, self.now(e + 1))]
        return make

    def setting(self, field, val, at):
        """apply, learn or mu = val from edge a_k + at on."""
        def make(k):
            e = int(self.a[k]) + at
            new = list(self.now(e))
            new[field] = val
            return [("ctrl", e, tuple(new))]
        return make

    def clear(self, off):
        """A clear on edge a_k + off (off: an int, or a function of k)."""
        def make(k):
            return [("clear", int(self.a[k]) + (off(k) if callable(off) else off))]
        return make


# conditions on the model's trace (index i = sample - planner state)
def _corr(tr, i):
    return tr["corr"][i] != 0


def _learns(tr, i):
    return bool(tr["gate"][i]) and tr["d"][i] != 0


def _learns_after(tr, tr2, i):
    return _learns(tr2, i)


def _update_changed(tr, tr2, i):
    return bool(tr2["gate"][i]) and tr2["d"][i] != tr["d"][i]


def _gaps(mode, m, rng):
    if mode == "b2b":
        return np.ones(m, np.int64)
    if mode == "g23":
        return 2 + (np.arange(m) % 2)
    return rng.choice([1, 1, 1, 1, 2, 3, 4, 7, 13, 36, 70], size=m)   # 70: a whole sweep


# The directed stream: (name, samples, speed at its end in units/sample, linear from the
# previous end; strobe gaps). Lock is lost at "step" and "reverse" (velocity steps).
DIRECTED = [
    ("start", 1, -540.0, "b2b"),
    # pull-in (wide gear), lock, nothing learned: |V| above the window (a window decoded
    # from too few bits of |V| would learn here)
    ("over", 3200, -540.0, "b2b"),
    ("upper_step", 1, -511.97, "b2b"),    # velocity step: lock lost, the wide gear again
    # pull-in, lock, learning: just inside the window every candidate lands in one of 16
    # bins (10..17 samples of 512 units), whose entries reach the s16 limits
    ("upper", 9000, -511.97, "b2b"),
    ("up_ramp", 1200, -515.0, "b2b"),     # |V| through 512, the window's upper edge
    ("up_back", 1200, -506.0, "b2b"),     # (+ pad samples: see _lock_pad)
    ("step", 1, 20.0, "b2b"),             # velocity step: lock lost, the wide gear again
    ("relock", 3000, 20.0, "b2b"),        # apply changes while the lock returns
    ("pulses_b2b", 1200, 20.0, "b2b"),     # learn and mu changes at candidates
    ("pulses_g23", 1200, 20.0, "g23"),
    ("pulses_rand", 1200, 20.0, "rand"),
    ("low_down", 1300, 13.0, "b2b"),      # |V| through 16, the window's lower edge
    ("low_up", 1300, 20.0, "b2b"),
    ("reverse", 1, -20.0, "b2b"),         # reversal step: lock lost again
    ("relock2", 2200, -20.0, "b2b"),
    ("clear_g23", 400, -20.0, "g23"),     # a clear: the first sample that sees it
    ("nlow_down", 1100, -13.0, "b2b"),    # the lower edge, negative speed
    ("nlow_up", 1100, -20.0, "b2b"),
    ("clear_g23b", 300, -20.0, "g23"),    # a clear: the first sample that sees it
    ("clears_b2b", 2200, -20.0, "b2b"),   # clears around learning candidates
    ("clears_rand", 1200, -20.0, "rand"),
    ("noise", 800, -20.0, "b2b"),         # large noise: samples hop between bins
]
ERR_H4 = 150.0    # 4th-harmonic error, units: beyond the table's +-128 (entries hit s16)
ERR_H1 = 12.0


def directed_front(pad):
    """Edges, front and first sample of each segment of the directed stream, with `pad`
    samples at -506 units/sample before the velocity step (the samples before them do
    not depend on pad)."""
    rg, rn, rr = (np.random.default_rng(s) for s in (7, 8, 9))
    v, g, first = [], [], {}
    cur, k = DIRECTED[0][2], 0
    segs = list(DIRECTED)
    i = [x[0] for x in segs].index("step")
    segs.insert(i, ("pad", pad, segs[i - 1][2], "b2b"))
    for name, m, end, mode in segs:
        first[name] = k
        v.append(cur + (end - cur) * np.arange(1, m + 1) / max(m, 1))
        g.append(_gaps(mode, m, rg))
        cur, k = end, k + m
    first["end"] = k
    v, gaps = np.concatenate(v), np.concatenate(g)
    x = 300.0 + np.cumsum(v)
    th = 2 * np.pi * x / tables.PH_PERIOD
    noise = rn.standard_normal(k)
    noise[first["noise"]:] *= 40.0
    err = ERR_H4 * np.sin(4 * th + 0.7) + ERR_H1 * np.sin(th + 2.0) + noise
    edges = 12 + np.concatenate([[0], np.cumsum(gaps[:-1])])
    return edges, front(x + err, "exact", rr, 0.3), first


def _lock_pad():
    """Samples to add before the velocity step so that once the lock has returned after
    it, a learning candidate arrives with C one below C_MAX (learning from C = 2046
    would change its update: MUTATIONS)."""
    _, f, first = directed_front(0)
    p0 = first["pad"]
    h0 = hm.Harmonic(show=show_of("directed"))
    h0.run(f["phase"][:p0], learn=1, mu=3)
    for pad in range(200):
        _, f, first = directed_front(pad)
        m = first["pulses_b2b"]
        _, tr = copy.deepcopy(h0).run(f["phase"][p0:m], learn=1, mu=3, trace=True)
        C, V, E = tr["C"], tr["V"], tr["E"]
        i = next(i for i in range(first["relock"] - p0, m - p0) if C[i - 1] == hm.C_MAX - 1)
        av = V[i - 1] if V[i - 1] >= 0 else ~V[i - 1]
        if (tr["cand"][i] and hm.VMIN << hm.VF <= av < hm.VMAX << hm.VF
                and -(hm.ELOCK << hm.PF) <= E[i] < hm.ELOCK << hm.PF):
            return pad
    raise RuntimeError("no pad puts a candidate on C = C_MAX - 1")


@functools.lru_cache(maxsize=None)
def directed_stim():
    """The directed stream with its events (see the module text)."""
    edges, f, S = directed_front(_lock_pad())
    P = Planner(edges, f["phase"], (1, 1, 3), show=show_of("directed"))
    A, L, M = 0, 1, 2
    # apply: one-edge pulses and steps at samples whose correction is not 0, while the
    # lock returns (nothing is learned: the table is the one learned near -512)
    k = S["relock"] + 100
    k = P.place("apply off for one edge", k, k + 300, P.pulse(A, 0, APPLY_AT), pre=_corr)
    k = P.place("apply off", k, k + 300, P.setting(A, 0, APPLY_AT), pre=_corr)
    k = P.place("apply on for one edge", k, k + 300, P.pulse(A, 1, APPLY_AT), pre=_corr)
    k = P.place("apply on", k, k + 300, P.setting(A, 1, APPLY_AT), pre=_corr)
    # learn and mu at learning candidates whose update is not 0. A step on a + LEARN_AT
    # of a candidate tells a block that samples one edge early, a step on a + LEARN_AT +
    # 1 one that samples late (the samples next to a candidate do not learn).
    for seg in ("pulses_b2b", "pulses_g23", "pulses_rand"):
        k, hi = S[seg], S[seg] + 1200
        k = P.place(f"{seg}: apply off for one edge", k, hi, P.pulse(A, 0, APPLY_AT), pre=_corr)
        k = P.place(f"{seg}: learn off for one edge", k, hi, P.pulse(L, 0, LEARN_AT),
                    pre=_learns)
        k = P.place(f"{seg}: mu 6 for one edge", k, hi, P.pulse(M, 6, LEARN_AT), pre=_learns,
                    post=_update_changed)
        k = P.place(f"{seg}: learn off", k, hi, P.setting(L, 0, LEARN_AT), pre=_learns,
                    shifts=(1,))
        k = P.place(f"{seg}: learn on for one edge", k, hi, P.pulse(L, 1, LEARN_AT),
                    post=_learns_after)
        k = P.place(f"{seg}: learn on", k, hi, P.setting(L, 1, LEARN_AT + 1), shifts=(-1,))
        k = P.place(f"{seg}: mu 4", k, hi, P.setting(M, 4, LEARN_AT), pre=_learns,
                    post=_update_changed, shifts=(1,))
        k = P.place(f"{seg}: mu 3", k, hi, P.setting(M, 3, LEARN_AT + 1), pre=_learns,
                    shifts=(-1,))
    # clears: the first sample that sees the empty table (gaps of 2 and 3)
    P.place("clear on a", S["clear_g23"] + 50, S["nlow_down"], P.clear(0), pre=_corr,
            shifts=(1,), reach=100)
    P.place("clear on a + 1", S["clear_g23b"], S["clears_b2b"], P.clear(1), pre=_corr,
            shifts=(-1,), reach=100)
    # the end of the sweep (back to back): the last sample blocked, the first that learns;
    # a clear during a sweep restarts it
    k = S["clears_b2b"] + 20
    k = P.place("clear, a candidate arrives on w + SWEEP", k, k + 300,
                P.clear(-hm.SWEEP), pre=_learns, shifts=(-1,), reach=100)
    k = P.place("clear, a candidate arrives on w + SWEEP + 1", k, k + 300,
                P.clear(-hm.SWEEP - 1), post=_learns_after, shifts=(1,), reach=100)
    k = P.place("clear during a sweep", k + hm.SWEEP, k + 300,
                lambda k: [("clear", int(P.a[k]) - hm.SWEEP - 30),
                           ("clear", int(P.a[k]) - hm.SWEEP)],
                pre=_learns, shifts=(-1,), reach=100)
    # clears on every edge from 2 before a learning candidate's arrival to 1 after its
    # commit (the arrival of sample k + D): the update in flight is dropped
    for off in range(-2, hm.D + 2):
        k = P.place(f"clear on a + {off} of a candidate", k, S["clears_rand"],
                    P.clear(off), pre=_learns, shifts=(), reach=90)
    k = S["clears_rand"]
    hi = S["noise"]
    k = P.place("clear inside a gap longer than the sweep", k, hi, P.clear(1),
                pre=lambda tr, i: P.a[P.pos + i + 1] - P.a[P.pos + i] > hm.SWEEP + 1,
                shifts=(), reach=90)

    def commit(k, extra=0):
        return int(P.a[k + hm.D] - P.a[k]) + extra
    for name, off in (("a - 1", -1), ("a", 0), ("a + 1", 1), ("the commit",
                      commit), ("the commit + 1", lambda k: commit(k, 1))):
        k = P.place(f"clear on {name} of a candidate (random gaps)", k, hi, P.clear(off),
                    pre=_learns, shifts=(), reach=90)
    return Stim(edges, f, P.ctrl, P.clears, P.events, show=show_of("directed"))


def phases(n, rng):
    """n angles (float, phase units) of a stage that ramps between speeds (also through
    zero and past the window), stands still, jumps (the observer loses track) and
    overspeeds; the error is a 1st and a 4th harmonic of the phase plus noise (sigma per
    segment; up to 50 units at low speed, so that samples hop back and forth between
    bins)."""
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
        xs_all.append(xs + err)
        total += len(xs)
    return np.concatenate(xs_all)[:n]


def slow_phases(n, rng):
    """n angles (float, phase units) of slow motion, which the observer follows in its
    gears above 0: cruises between 0.01 and 24 units/sample (both directions) with gentle
    ramps, standstill, servo dither around a point, reversals, and now and then a burst
    of fast motion or a jump (down-shifts, a lost lock); the error is a 1st and a 4th
    harmonic of the phase plus noise (a small 1st harmonic: the
    observer follows it at the bottom of a gear, and V's ripple reads as acceleration)."""
    nrng = np.random.default_rng(rng.randrange(1 << 30))
    h1, h4 = rng.uniform(0.5, 2), rng.uniform(8, 20)
    p1, p4 = rng.uniform(0, 6.3), rng.uniform(0, 6.3)
    x, v = rng.uniform(0, 8192), 1.5
    # standstill, then cruises that the observer follows in gears 4 and 3
    vel = np.concatenate([np.zeros(2000), np.full(100000, 1.5), np.linspace(1.5, 3.0, 20000),
                          np.full(80000, 3.0)])
    v = 3.0
    xs = x + np.cumsum(vel)
    xs_all = [xs + h1 * np.sin(2 * np.pi * xs / 8192 + p1) + h4 * np.sin(8 * np.pi * xs / 8192 + p4)
              + 2.0 * nrng.standard_normal(len(xs))]
    x, total = float(xs[-1]), len(xs)
    while total < n:
        kind = rng.choices(["cruise", "stop", "dither", "reverse", "fast", "jump"],
                           [64, 6, 8, 6, 12, 4])[0]
        hold = rng.randint(20000, 80000)
        if kind == "cruise":
            # from the speed now by up to 8 times up or down (gear changes one at a time)
            tgt = float(np.clip(abs(v) * 2 ** rng.uniform(-3, 3), 0.01, 24)) if v else 1.0
            tgt *= np.sign(v) if v and rng.random() < 0.9 else rng.choice([-1, 1])
        elif kind in ("stop", "dither"):
            tgt = 0.0
        elif kind == "reverse":
            tgt = -v
        elif kind == "fast":      # up through the gears to gear 0, one shift at a time
            tgt, hold = np.sign(v or 1) * rng.uniform(20, 60), rng.randint(2000, 10000)
            v = np.sign(v or 1) * max(abs(v), 2.0)
        else:
            tgt = v
        acc = 10 ** rng.uniform(-6.5, -4)
        m = min(int(abs(tgt - v) / acc) + 1, 30000)
        ramp = v + (tgt - v) * np.arange(1, m + 1) / m
        if kind == "fast":
            # an acceleration the observer follows in every gear: v^2 / 2^18 per sample
            # (its lag a D^2 2^15 stays below 1024 units at 64 units per tick)
            sp, r = abs(v), []
            while sp < abs(tgt):
                sp += sp * sp / 2 ** 18
                r.append(sp)
            ramp = np.sign(tgt) * np.minimum(np.array(r), abs(tgt))
        vel = np.concatenate([ramp, np.full(hold, tgt)])
        xs = x + np.cumsum(vel)
        if kind == "dither":
            amp, per = rng.uniform(5, 300), rng.uniform(200, 20000)
            xs += amp * np.sin(2 * np.pi * np.arange(len(xs)) / per)
        if kind == "jump":
            xs[rng.randrange(len(xs)):] += rng.choice([-1, 1]) * rng.uniform(1500, 3000)
        x, v = float(xs[-1]), float(tgt)
        sigma = rng.choice([0.5, 2.0, 5.0])
        err = (h1 * np.sin(2 * np.pi * xs / 8192 + p1) + h4 * np.sin(8 * np.pi * xs / 8192 + p4)
               + sigma * nrng.standard_normal(len(xs)))
        xs_all.append(xs + err)
        total += len(xs)
    return np.concatenate(xs_all)[:n]


def random_stim(pattern, n, seed):
    """A seeded random stream: strobes back to back with a few gaps (b2b, slow, long) or
    random gaps with bursts back to back (gaps); random control changes and clears (rarer
    in the slow stream, whose gears take thousands of samples; the long stream has none
    and always learns)."""
    rng = random.Random(seed)
    x = slow_phases(n, rng) if pattern == "slow" else phases(n, rng)
    kind = PATTERNS[pattern]
    f = front(x, kind, np.random.default_rng(seed), 0.3 if kind == "exact" else 0.05)
    edges = []
    e = 12
    burst = 0
    for _ in range(n):
        edges.append(e)
        if pattern in ("b2b", "slow", "long"):
            gap = 1 if rng.random() < 0.97 else rng.randint(2, 12)
        elif burst:
            burst -= 1
            gap = 1
        elif rng.random() < 0.05:
            burst = rng.randint(2, 20)
            gap = 1
        else:
            gap = rng.choice([2, 3, 4, 5, 7, 8, 9, 13, 20, 36, 60, 70])
        e += gap
    last = edges[-1]
    # control changes: mostly apply = learn = 1, mu 3..6
    ctrl = {0: (1, 1, 4)}
    sparse = 40 if pattern == "slow" else 1
    for _ in range(max(8, n // (400 * sparse))):
        w = rng.randint(1, last)
        ctrl[w] = (int(rng.random() < 0.8), int(rng.random() < 0.85),
                   rng.choice([3, 3, 4, 4, 4, 5, 6]))
    if pattern == "long":
        ctrl = {w: (a, 1, m) for w, (a, _, m) in ctrl.items()}
    clears = set()
    for _ in range(0 if pattern == "long" else max(4, n // (2000 * sparse))):
        k = rng.randrange(8, n)
        clears.add(edges[k] + rng.choice([-2, -1, 0, 0, 1, 1, 2, 3, 4, 5, 6, 7]))
    return Stim(edges, f, ctrl, clears, show=show_of(pattern))


def stimulus(pattern, n):
    if pattern == "directed":
        return directed_stim()
    return random_stim(pattern, n, {"gaps": 11, "b2b": 12, "slow": 37, "long": 41}[pattern])


# ---- cocotb side -----------------------------------------------------------------------------
import cocotb  # noqa: E402


async def _watch(sig, log):
    from cocotb.triggers import ValueChange
    from cocotb.utils import get_sim_time
    while True:
        await ValueChange(sig)
        log.append((get_sim_time(unit="ps"), fqtb.uval(sig)))


class _Pins:
    """Writes DUT inputs, skipping writes of the value a pin already has."""

    def __init__(self, dut, **init):
        self.dut, self.last = dut, {}
        for name, v in init.items():
            self[name] = v

    def __setitem__(self, name, v):
        if self.last.get(name) != v:
            getattr(self.dut, name).value = v
            self.last[name] = v


def _high_edges(vlog, t0):
    """The edges after which a watched 1-bit signal was high."""
    high, rise = set(), None
    for tm, v in vlog:
        e, r = divmod(int(tm - t0), fqtb.PERIOD_PS)
        assert r == 0, f"a valid output changed between clock edges (t={tm} ps)"
        if v == 1 and rise is None:
            rise = e
        elif v == 0 and rise is not None:
            high.update(range(rise, e))
            rise = None
    assert rise is None, "a valid output is still high at the end"
    return high


@cocotb.test()
async def harmonic_stream(dut):
    pattern = fqtb.env_str("PATTERN")
    st = stimulus(pattern, fqtb.env_int("SAMPLES"))
    exp, h = run_model(st)
    n = len(st.edges)
    edges = st.edges.tolist()
    f = {key: v.tolist() for key, v in st.f.items()}
    log = dut._log
    log.info("%s: %d samples over %d edges, %d control changes, %d clears, %d placed "
             "events, model updates %d, table %s..%s", pattern, n, edges[-1], len(st.ctrl),
             len(st.clears), len(st.events), h.learned, min(h.A), max(h.A))

    strobe = {e: k for k, e in enumerate(edges)}
    bins = {e + BIN_AT: k for k, e in enumerate(edges)}
    phs = {e + OUT_AT: k for k, e in enumerate(edges)}
    reads = phs
    clear_set = set(st.clears)
    slots = set(reads)
    for e in list(strobe) + list(bins) + list(phs) + list(st.ctrl) + st.clears:
        slots.update((e - 1, e))            # set before the edge, garbage after it
    slots = sorted(s for s in slots if s >= 0)

    bench = fqtb.ClockedBench(dut)
    a0, l0, m0 = st.ctrl[0]
    pin = _Pins(dut, valid_i=0, oct2_i=0, neg_i=0, t_i=0, ph_i=0, apply_i=a0, learn_i=l0,
                mu_i=m0 - hm.MU_MIN, clear_i=0)
    await bench.start()
    vlog = []
    cocotb.start_soon(_watch(dut.valid_o, vlog))
    got = [None] * n
    junk = random.Random(len(edges))
    for s in slots:
        await bench.goto(s)
        k = reads.get(s)
        if k is not None:
            got[k] = (fqtb.uval(dut.phase_o), fqtb.uval(dut.phase_c_o))
        # inputs for edge s + 1: a sample's values on its edges, garbage on the others
        nxt = s + 1
        k = strobe.get(nxt)
        pin["valid_i"] = int(k is not None)
        pin["oct2_i"] = f["oct2"][k] if k is not None else junk.randrange(4)
        pin["neg_i"] = f["neg"][k] if k is not None else junk.randrange(2)
        k = bins.get(nxt)
        pin["t_i"] = f["t"][k] if k is not None else junk.randrange(4096)
        k = phs.get(nxt)
        pin["ph_i"] = f["ph"][k] if k is not None else junk.randrange(4096)
        if nxt in st.ctrl:
            a, lr, m = st.ctrl[nxt]
            pin["apply_i"], pin["learn_i"], pin["mu_i"] = a, lr, m - hm.MU_MIN
        pin["clear_i"] = int(nxt in clear_set)
    await bench.goto(bench.edge + 4)

    want = list(zip(f["phase"], exp.tolist()))
    bad = [k for k in range(n) if got[k] != want[k]]
    if bad:
        lines = [f"sample {k} (arrival edge {edges[k]}, oct2 {f['oct2'][k]}, neg "
                 f"{f['neg'][k]}, t {f['t'][k]}, ph {f['ph'][k]}, bin {f['bin'][k]}): rtl "
                 f"(phase, corrected)"
                 f" {got[k]}, model {want[k]}" for k in bad[:12]]
        raise AssertionError(f"{len(bad)} of {n} samples differ, first:\n" + "\n".join(lines))
    assert h.learned > n // (400 if pattern == "slow" else 40), \
        f"only {h.learned} updates: the stimulus hardly learns"
    high = _high_edges(vlog, bench.t0)
    want_v = {e + OUT_AT for e in edges}
    assert high == want_v, f"valid_o high after other edges: {sorted(high ^ want_v)[:8]}"
    nc = int(np.sum(exp != st.f["phase"]))
    log.info("%s: %d samples equal (%d corrected), %d updates", pattern, n, nc, h.learned)
    assert nc > 0, "no sample corrected: the correction is not seen"


# ==== the block in the core: finequad_core against sim.model.finequad_core.run ========================
CORE_SOURCES = fqtb.core_sources()
INTERP_ADDR = regs.INTERP
HARM_ADDR = regs.HARM
HARM_READ = regs.REGS["HARM"].rmask   # the bits HARM reads back
CORE_INTERP = 511          # n: the count resolves 8192 / (4 n) = 4 phase units
CORE_PLAN = 7000           # the placed writes lie in the first CORE_PLAN samples
# GHDL, as Icarus: the CORE_PLAN samples of the placed writes only (CI time)
CORE_SAMPLES = {"icarus": CORE_PLAN, "verilator": 40000, "ghdl": CORE_PLAN}
CORE_B2B = 4500            # strobes back to back before this sample, random gaps after


@pytest.mark.parametrize("sim", fqtb.simulators("finequad_core"))
def test_core_harmonic(sim):
    fqtb.run_block(sim, "finequad_core", CORE_SOURCES, "test_harmonic",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR), TABLE_EXACT=1),
                   extra_env=dict(SAMPLES=CORE_SAMPLES[sim]), testcase="core_harmonic")


def test_core_sensitivity():
    """Every placed HARM write moved by one edge (the directions that matter for it)
    changes sim.model.finequad_core's outputs (count, A/B, faults) of the first CORE_PLAN samples."""
    n = CORE_PLAN
    u1, u2, t, writes, events = core_plan(n)
    ref = core_outputs(u1, u2, t, writes)
    same = []
    for name, k, ws, shifts in events:
        for sh in shifts:
            mv = sorted((w + sh, a, d) if (w, a, d) in ws else (w, a, d) for w, a, d in writes)
            if np.array_equal(core_outputs(u1, u2, t, mv), ref):
                same.append(f"{name} (sample {k}) moved by {sh:+d} edge")
    assert not same, "the core stimulus does not tell apart:\n" + "\n".join(same)


def harm_word(apply, learn, mu, clear=0):
    """HARM register word (mu: the block's step exponent, 2^-mu)."""
    return regs.word("HARM", harm_apply=apply, harm_learn=learn, harm_mu=mu - hm.MU_MIN,
                     harm_clear=clear)


def core_stimulus(n):
    """(u1, u2, strobe edges): a stage at 40 units/sample with a 1 % third harmonic."""
    from sim import siggen
    rng = np.random.default_rng(21)
    x = siggen.constant_speed(n, 1e6, 40 / 8192 * 4000 * 1e6, x0=123.0)    # 40 units/sample
    sig = siggen.Signal(A1=0.5, A2=0.47, h3=0.01, noise=0.004)
    u1, u2, _ = siggen.encode(x, 4000.0, sig, seed=22)
    gaps = np.where(np.arange(n) < CORE_B2B, 1,
                    rng.choice([1, 1, 1, 2, 3, 5, 8, 13, 21, 36], size=n))
    t = 16 + np.concatenate([[0], np.cumsum(gaps[:-1])])
    return u1.astype(np.int64), u2.astype(np.int64), t.astype(np.int64)


def core_config(t, writes):
    """core.Config with the per-sample HARM fields the core samples: a write on edge w
    reaches the block on w + 1 (apply sampled on a + APPLY_AT, learn and mu on a +
    LEARN_AT, a = t + HARM_AT; a clear is high on w + 1)."""
    n = len(t)
    d = core_model.Config()                    # the values after reset
    apply = np.full(n, d.harm_apply, np.int64)
    learn = np.full(n, d.harm_learn, np.int64)
    mu = np.full(n, d.harm_mu, np.int64)
    clears = []
    for w, addr, v in writes:
        if addr != HARM_ADDR:
            continue
        a_new = t + ARRIVE_AT + APPLY_AT > w
        l_new = t + ARRIVE_AT + LEARN_AT > w
        apply[a_new] = regs.value("HARM", "harm_apply", v)
        learn[l_new] = regs.value("HARM", "harm_learn", v)
        mu[l_new] = regs.value("HARM", "harm_mu", v)
        if regs.value("HARM", "harm_clear", v):
            clears.append(w)
    return core_model.Config(interp=CORE_INTERP, harm_apply=apply, harm_learn=learn,
                             harm_mu=mu, harm_clears=clears)


def core_outputs(u1, u2, t, writes, trace=False):
    res = core_model.run(u1, u2, core_config(t, writes), strobes=t, trace=trace)
    out = np.stack([res["count"], res["a"], res["b"], res["fault"]], axis=1)
    return (out, res) if trace else out


@functools.lru_cache(maxsize=None)
def core_plan(n):
    """(u1, u2, t, writes [(edge, addr, data)], events): n and the edge of every setting
    written, 0x12 HARM writes placed at samples chosen from the model's state (Planner on
    the core's fine phase, arrivals t + HARM_AT, observable: the count's fine part
    n * phase_c >> 11), then, past CORE_PLAN, a few seeded random ones."""
    u1, u2, t = core_stimulus(n)
    m = min(n, CORE_PLAN)
    # the fine phase does not depend on HARM (the estimator sees the uncorrected phase)
    ph = core_model.run(u1[:m], u2[:m], core_model.Config(harm_learn=0), strobes=t[:m],
                        trace=True)["phase"]
    P = Planner(t[:m] + ARRIVE_AT, ph, (1, 1, 3), score=lambda out: (CORE_INTERP * out) >> 11)
    A, L, M = 0, 1, 2
    spots = []
    k = 2600                                # learning from about sample 2300 on
    for name, make, pre, post, shifts in (
            ("apply off", P.setting(A, 0, APPLY_AT), _corr, None, (-1, 1)),
            ("apply on", P.setting(A, 1, APPLY_AT), _corr, None, (-1, 1)),
            ("apply off for one edge", P.pulse(A, 0, APPLY_AT), _corr, None, (-1, 1)),
            ("learn off", P.setting(L, 0, LEARN_AT), _learns, None, (1,)),
            ("learn on", P.setting(L, 1, LEARN_AT + 1), None, None, (-1,)),
            ("mu 6", P.setting(M, 6, LEARN_AT), _learns, _update_changed, (1,)),
            ("mu 3", P.setting(M, 3, LEARN_AT + 1), _learns, None, (-1,)),
            ("clear, a candidate arrives on w + SWEEP", P.clear(-hm.SWEEP), _learns, None,
             (-1,)),
            ("gaps: apply off", P.setting(A, 0, APPLY_AT), _corr, None, (1,)),
            ("gaps: apply on", P.setting(A, 1, APPLY_AT), _corr, None, (1,)),
            ("gaps: learn off", P.setting(L, 0, LEARN_AT), _learns, None, (1,)),
            ("gaps: learn on", P.setting(L, 1, LEARN_AT + 1), None, None, (-1,)),
            ("gaps: clear on a", P.clear(0), _corr, None, (1,))):
        if name.startswith("gaps") and k < CORE_B2B:
            k = CORE_B2B
        k0 = len(P.events)
        k = P.place(name, k, m, make, pre=pre, post=post, shifts=shifts, reach=150)
        spots.append(P.events[k0])
    # block edges -> register writes (a write on edge w reaches the block on w + 1)
    writes = [(1, INTERP_ADDR, CORE_INTERP), (2, HARM_ADDR, harm_word(1, 1, 3))]
    events = []
    for name, k, items, shifts, _ in spots:
        ws = []
        for it in items:
            if it[0] == "ctrl":
                ws.append((it[1] - 1, HARM_ADDR, harm_word(*it[2])))
            else:
                ws.append((it[1] - 1, HARM_ADDR, harm_word(*P.now(it[1] - 1), clear=1)))
        writes += ws
        events.append((name, k, ws, shifts))
    if n > m:
        rng = random.Random(5)
        for e in sorted(rng.sample(range(int(t[m]), int(t[-1])), 12)):
            writes.append((e, HARM_ADDR, harm_word(int(rng.random() < 0.8), int(
                rng.random() < 0.8), rng.choice([3, 4, 5, 6]), int(rng.random() < 0.3))))
    return u1, u2, t, sorted(writes), events


# HARM after reset (the model's Config defaults)
HARM_RESET = regs.REGS["HARM"].reset


def harm_reads(writes):
    """{edge: value}: HARM read on every edge of a HARM write (the value before it) and
    on the edge after (the value it wrote): a registered read on edge e returns the
    registers as they were before e."""
    hw = [(w, v) for w, a, v in writes if a == HARM_ADDR]
    other = {w for w, a, v in writes if a != HARM_ADDR}
    out = {}
    for w, _ in hw:
        for e in (w, w + 1):
            if e not in other:
                prev = [v for x, v in hw if x < e]
                out[e] = (prev[-1] if prev else HARM_RESET) & HARM_READ
    return out


@cocotb.test()
async def core_harmonic(dut):
    n = fqtb.env_int("SAMPLES")
    u1, u2, t, writes, events = core_plan(n)
    exp, res = core_outputs(u1, u2, t, writes, trace=True)
    h = res["harm"]
    log = dut._log
    log.info("core: %d samples, %d register writes (%d placed events), %d table updates, "
             "%d samples corrected", n, len(writes), len(events), h.learned,
             int(np.sum(res["phase_c"] != res["phase"])))
    assert h.learned > n // 40, \
        f"only {h.learned} updates: the stimulus hardly learns"
    lat = core_model.LATENCY
    strobe = {int(e): k for k, e in enumerate(t)}
    outs = {int(e) + lat: k for k, e in enumerate(t)}
    wr = {w: (a, d) for w, a, d in writes}
    assert len(wr) == len(writes), "two writes on one edge"
    rd = harm_reads(writes)
    slots = set(outs)
    for e in list(strobe) + list(wr) + list(rd):
        slots.update((e - 1, e))
    bench = fqtb.ClockedBench(dut)
    pin = _Pins(dut, rst=0, s_valid=0, s_u1=0, s_u2=0, reg_we=0, reg_re=0, reg_addr=0,
                reg_wdata=0)
    await bench.start()
    vlog = []
    cocotb.start_soon(_watch(dut.m_valid, vlog))
    got = np.zeros((n, 4), dtype=np.int64)
    got_rd = {}
    junk = random.Random(n)
    amax = 1 << (len(dut.s_u1) - 1)
    for s in sorted(x for x in slots if x >= 0):
        await bench.goto(s)
        k = outs.get(s)
        if k is not None:
            got[k] = (fqtb.sval(dut.m_count), fqtb.uval(dut.m_a), fqtb.uval(dut.m_b),
                      fqtb.uval(dut.m_fault))
        if s in rd:
            got_rd[s] = fqtb.uval(dut.reg_rdata)
        # inputs for edge s + 1; garbage on the data inputs after a strobe or an access
        nxt = s + 1
        k = strobe.get(nxt)
        pin["s_valid"] = int(k is not None)
        if k is not None:
            pin["s_u1"], pin["s_u2"] = int(u1[k]), int(u2[k])
        elif s in strobe:
            pin["s_u1"], pin["s_u2"] = junk.randrange(-amax, amax), junk.randrange(-amax, amax)
        pin["reg_we"] = int(nxt in wr)
        pin["reg_re"] = int(nxt in rd)
        if nxt in wr:
            pin["reg_addr"], pin["reg_wdata"] = wr[nxt]
        elif nxt in rd:
            pin["reg_addr"] = HARM_ADDR
        elif s in wr or s in rd:
            pin["reg_addr"], pin["reg_wdata"] = junk.randrange(64), junk.randrange(1 << 32)
    await bench.goto(bench.edge + 4)

    bad = np.nonzero((got != exp).any(axis=1))[0]
    if len(bad):
        lines = [f"sample {k} (strobe edge {int(t[k])}): rtl (count, a, b, fault) "
                 f"{tuple(int(x) for x in got[k])}, model {tuple(int(x) for x in exp[k])}; "
                 f"phase {int(res['phase'][k])}, phase_c {int(res['phase_c'][k])}"
                 for k in bad[:12]]
        raise AssertionError(f"{len(bad)} of {n} samples differ, first:\n" + "\n".join(lines))
    high = _high_edges(vlog, bench.t0)
    want = {int(e) + lat for e in t}
    assert high == want, f"m_valid high after other edges: {sorted(high ^ want)[:8]}"
    bad_rd = {e: (got_rd[e], v) for e, v in rd.items() if got_rd[e] != v}
    assert not bad_rd, f"HARM reads (edge: (rtl, expected)) differ: {bad_rd}"
    log.info("core: %d samples equal, %d HARM reads equal", n, len(rd))
