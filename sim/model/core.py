"""Bit-true model of rtl/finequad_core.v: timing of the estimator against the sample stream.

Clock-edge timing (the RTL implements exactly this; edges are numbered from 0):

* Sample k is strobed (s_valid high) on edge t_k: correct.v registers x - m on t_k with
  the coefficient bundle as it stands before t_k (committed on edges < t_k), so a sample
  never mixes two bundles. Its fine phase is registered on t_k + PHASE_AT (6), its count
  on t_k + LATENCY (8); the paced A/B outputs follow the count from t_k + 9.
* The estimator keeps one candidate slot, so that the engine finds the next sample
  ready when it finishes a program (it runs back to back at a sample per clock). Every
  sample arrives at the estimator on t_k (the raw sample and max |u| registered), which
  decides on the edge after it (t_k + 1), seeing the state of edges <= t_k:
    - reset pending, the slot empty and no program running -> RESET program (P = kappa I,
                        theta rescaled to the new input gain g, chosen from the peak |u|
                        of the samples since the last reset, before this one); the peak
                        restarts. A pending reset takes no new candidate.
    - no reset pending, the slot empty, strobed at least r clocks after the last UPDATE's
                        decision (the dither, dither() below: r random in 0..DSPAN, a
                        point of the running UPDATE, or with a shared engine of the
                        axis's window period) -> the sample becomes the candidate,
                        whether or not a program is running.
  The candidate is checked on c = t_k + PHASE_STAGE, when its fine phase and the
  monitor's verdict are known (the first failing check drops it; the slot is empty
  for samples strobed on or after c):
        - the monitor does not trust the sample (sim/model/monitor.py: signal loss,
                        over-range, a stuck channel, a glitch, a clipped code) -> dropped
                        (no reset either)
        - x = u << g saturates -> dropped; a reset becomes pending
        - the travel S (the monitor's smoothed unwrapped phase, as of the sample before
                        the candidate) within `gate` of S at the last update -> dropped
                        (no new information: standstill, with noise, and creep do not
                        wind the estimator up)
        - otherwise the UPDATE program (Eqs. 5-8) is decided on D = max(c, the edge on
                        which the running program ends; an EXTRACT due at an update's end
                        goes first), and the slot is empty for samples strobed on or after
                        D. On D: the travel at the last update and the octant coverage
                        take the candidate's, the dither r is drawn; after WARMUP
                        updates from power-up the input gain is checked (from the peak
                        before the candidate) and a reset becomes pending only if it would
                        change; then after every period-th update since the last reset
                        (period 0: never, the default).
  A program decided on edge D starts on D + 1 and ends (END retires) on D + 1 +
  CYCLES[prog]; a RESET needs a sample strobed on or after that edge.
  Shared engine (Config.tdm = (axes, index, L, W), rtl/finequad_multi.v): the axes take
  turns on one engine in fixed windows, so an axis's decisions depend on its own samples
  and the edge number alone. Axis `index` may decide a RESET or an UPDATE only on an edge
  e with index L <= e mod (axes L) < index L + W (edges counted from power-up or the last
  rst, as the RTL's window counter): a RESET on the arrival decision t_k + 1 only if that
  edge is in the window (else the sample passes, the reset stays pending), an UPDATE on
  the first edge in the window at or after max(c, the running program's end) (the
  candidate waits in the slot until then, and the slot is empty for samples strobed on or
  after that edge); an EXTRACT is decided on its UPDATE's last edge as always. L >= W + 1 +
  CYCLES[update] + CYCLES[extract] (tdm_period) ends every program an axis starts before
  the next axis's window opens, so the engine is never contended. tdm None: every edge
  (one axis, rtl/finequad_core.v). At the end of an
  UPDATE, if theta was valid, at least `settle` updates have ended since the last reset,
  and the updates since the last commit and the last reset covered all eight octants (so
  the fit is constrained all round, not by a short arc) within one coverage window, and
  the update was not decided before the warm-up's gain check with a candidate whose peak
  asks for another input gain (gain_pending; rtl/estimator.v gain_pend), an EXTRACT is
  decided on that edge, and the new bundle {g, m1, m2, c1, c12, c2} is
  committed on its end. Coverage window: an update that finds COVER_WIN updates counted
  since the coverage last restarted restarts it (the octants seen so far are dropped,
  its own is kept, the count is 1). So the eight octants must come within COVER_WIN
  consecutive updates, about the RLS's memory (1 / (1 - lambda) = 257 at the default
  k = 8; the window is fixed, so at k >= 10 a longer memory can still hold an older arc,
  and at k <= 5 the window is longer than the memory): a
  servo dither on a short arc, hours of it, adds a few octants per window and never
  completes the set, and when a move begins after it the hand-over waits until the
  move alone has covered the circle, instead of extracting a fit that the dither's arc
  still dominates (the soak handed over m1 = 0.67 of full scale after 30 updates of a
  move that followed 0.5 s of dither and had inherited the dither's octants).
  Jump detector, also at the end of an UPDATE: with |e| the update's a-priori residual
  (OUT E, s3.13, saturated to 15 bits; u15.5 below), jf a fast (1/4) and jl a slow (1/64)
  running mean of |e|: if armed (a commit since power-up or the last jump) and
  jf_next > 4 jl + jump_min, a reset becomes pending, the octant coverage restarts, the
  detector disarms and jf = jl (no commit on this update); otherwise jf = jf_next and,
  while armed or uncalibrated, jl follows |e|. A commit arms it.
  A reset becomes pending on an edge (a dropped candidate: c; the warm-up or period
  check: D; a jump or an invalid update: the update's end) and acts on the decisions of
  samples strobed on or after it; a reset request through the registers is pending for
  the sample it is attributed to (Config.resets).
* The counter counts the fine phase after the harmonic compensation (sim/model/
  harmonic.py, rtl/harmonic.v; the block samples a sample's arrival on t_k + HARM_AT):
  a function of the samples alone, except the table clears (Config.harm_clears), which
  are timed in edges (a 64-clock RAM sweep).
* Edge mode (count_mode 1): the count of sample k is the x4 decoder's count of the Eq. 12
  pulses as of its output edge: the steps of the samples strobed on or before t_k - 3
  (the pulses come two edges after the phase-mode count).
* A/B pins: the paced outputs (sim/model/abgen.py) follow m_count, which takes sample
  k's count on t_k + 8 (the target from t_k + 9); the per-sample a, b are the pins after
  t_k + 8, as `make rtlsim` samples them. With ab_src = 1 the pins are the Eq. 12 pulses
  (of the previous sample at that edge).
"""
import bisect
from dataclasses import dataclass, field

import numpy as np

from . import abgen
from . import fastpath as fp
from . import harmonic
from .estimator import Estimator
from .monitor import Monitor, MonitorRegs

# Pipeline timing of rtl/finequad_core.v: edges from a sample's strobe edge t to the edge
# that registers each result. The RTL declares the same numbers (localparams of
# finequad_core.v); the tests hold its behaviour to these, not to its source text.
CORR_AT = 2          # correct: |u1c|, |u2c|, signs, rsat
OCT_AT = 3           # octant: valid, oct2, neg (j and the bin follow, combinational, at 5)
HARM_AT = 4          # the edge on which the harmonic block samples the sample's arrival
ADDR_AT = 5          # phase and harmonic tables read (j, bin)
PHASE_AT = 6         # fine phase (corrected and not)
NTH_AT = 7           # n * phase; the period count B
LATENCY = 8          # counter: m_valid, m_count, m_fault
SIN_AT = 8           # sines of the n-th order
PULSE_AT = 9         # Eq. 12 pulses
AB_AT = 9            # paced A/B (follows m_count)
EDGE_AT = 10         # edge-mode count (x4 decoder of the pulses)
RESET_STAGE = 1      # a RESET is decided on the edge after the arrival
PHASE_STAGE = PHASE_AT + 2   # an UPDATE is decided here (inputs registered one edge first)
START_DELAY = 1      # the engine starts on the edge after the decision (registered)
LFSR_SEED = 0xACE1   # dither of the estimator's sample choice (see below)
WARMUP = 64          # updates before the first automatic reset (picks the input gain)
COVER_WIN = 255      # updates within which a hand-over needs all eight octants (estimator.v)
G_MAX = 3            # input gain 2**g, g in 0..3 (amplitudes down to ~6 % of full scale)
ID = 0x46510004      # register 0x1f: "FQ" and the version (0.4), rtl/finequad_core.v
FAULT_BITS = {
    "clip": 0,       # an input code at or near an ADC rail (|u| >= CLIP): kept from the
                     # estimator (the counter holds only with "over" beside it)
    "nsat": 1,       # u << g leaves s1.15 in the fast path
    "csat": 2,       # offset removal or correction saturated
    "ovs": 3,        # overspeed: |phase step| >= 3/4 pi per sample
    "uncal": 4,      # no estimate handed over yet: default or loaded coefficients in use
    "hold": 5,       # the last estimate was invalid: last valid coefficients held
    "abovf": 6,      # the A/B backlog exceeded its bound (sticky until rst)
    "loss": 7,       # Lissajous radius below LOSS: counter held, not estimated
    "over": 8,       # radius above OVER: not estimated (while it is short), still counted
    "stuck": 9,      # a channel's code stopped changing while the stage moved: held
    "glitch": 10,    # the phase jumped off its straight-line prediction: held
}
FAULT_W = len(FAULT_BITS)
BUNDLE_AT = 1        # a LOAD (CTRL bit 1) written on edge w replaces the bundle on w + 1


@dataclass
class Config:
    """Build-time parameters (UPPER in the RTL) and run-time registers (lower)."""
    ADC_W: int = 16
    SIN_W: int = 10
    TABLE: str = "exact"
    COUNT_W: int = 32
    G_INIT: int = 0
    OPT_HARMONIC: int = 1    # 0: no harmonic compensation (rtl/phase.v), HARM reads 0
    OPT_MONITOR: int = 1     # 0: no fault checks (sim/model/monitor.py), RADIUS and
                             # MONITOR read 0
    OPT_JUMP: int = 1        # 0: no jump detector (as jump_on = 0), JUMPS reads 0
    ENGINE_LANES: int = 1    # lanes of the RLS engine (1 or 2): its clocks per program
    interp: int = 100        # n, 1..511
    count_mode: int = 0      # CTRL bit 3: counter mode, 0 phase (4 n phase, nothing
                             # lost below half a period per sample), 1 edge (x4 of A/B)
    eps: int = 1638          # u0.15 hysteresis (0.05)
    lam_k: int = 8           # lambda = 1/(1 + 2**-k), k in 1..23
    kappa: int = 64 << 8     # u8.8
    period: int = 0          # updates between covariance resets (0: never)
    jump_on: int = 1         # jump detector: a reset when the mean |e| of the last few
    jump_min: int = 41       # updates exceeds 4x its long-run mean + jump_min (s3.13)
    settle: int = 32         # updates after a reset before coefficients are applied
    gate: int = 64           # u13 phase progress needed between updates (1/128 period)
    div: int = 36            # clocks per sample when strobes are uniform
    resets: list = field(default_factory=list)   # sample indices of reset requests (the
                             # request is pending when the sample arrives)
    harm_apply: int = 1      # HARM (0x12) bit 0: apply the harmonic correction to the
                             # counter's phase (sim/model/harmonic.py)
    harm_learn: int = 1      # HARM bit 1: learn the table (speed-gated)
    harm_mu: int = 4         # LMS step 2^-mu, 3..6 (HARM [5:4] = mu - 3)
    harm_clears: list = field(default_factory=list)   # edges w of HARM writes with bit 8
                             # (clear): the samples strobed on edges t_k >= w + 1 - HARM_AT
                             # see an empty table; those strobed on w + 1 - HARM_AT ..
                             # w + 65 - HARM_AT are not corrected (the RAM is swept)
    # (harm_apply/learn/mu may also be per-sample arrays: the values the RTL samples on
    # edges t_k + HARM_AT + 1 (apply) and t_k + HARM_AT + 5 (learn, mu); a register
    # written on edge w is sampled on the edges after w)
    ab_sep: int = 4          # ABGEN [7:0]: minimum clocks between A/B edges (0 as 1)
    ab_src: int = 0          # ABGEN bit 8: the A/B pins show the Eq. 12 pulses
    ab_bound: int = 1024     # AB_BOUND: backlog (counts) above which the overflow flags
    clip: int = fp.CLIP_LEVEL   # CLIP: |u| (s1.15 aligned) at or above it is clipped
    loss: int = 3277         # RADIUS [15:0]: radius (s2.14) below it: signal lost (0.2)
    over: int = 22118        # RADIUS [31:16]: radius above it: over-range (1.35)
    glitch_k: int = 10       # MONITOR [3:0]: max |phase acceleration| 2^K (0: off)
    stuck_n: int = 8         # MONITOR [23:16]: unchanged codes before stuck (0: off)
    loads: list = field(default_factory=list)   # [(w, (g, m1, m2, c1, c12, c2))]: a
                             # LOAD (CTRL bit 1) written on edge w with that bundle staged
                             # in 0x0b..0x10; samples strobed on edges >= w + 2 use it
    tdm: tuple = None        # (axes, index, L, W): this axis of rtl/finequad_multi.v, whose
                             # engine programs start only in its window (module text);
                             # None: the engine is the axis's own (every edge)

    def monitor_regs(self):
        return MonitorRegs(loss=self.loss, over=self.over, glitch_k=self.glitch_k,
                           stuck_n=self.stuck_n)


# Default bundle: centred circle of radius 0.5 (normalised): c1 = c2 = 2.0 in s4.12.
BUNDLE0 = (0, 0, 0, 2 << 12, 0, 2 << 12)


def lfsr_step(v: int) -> int:
    """16-bit Galois LFSR (x^16 + x^14 + x^13 + x^11 + 1), as rtl/estimator.v."""
    return (v >> 1) ^ (0xB400 if v & 1 else 0)


def dither_span(cycles: dict, period: int = 0) -> int:
    """DSPAN: the latest clock after an UPDATE's decision D at which a strobed candidate
    is still checked by the edge the next UPDATE may be decided on: the end of this one
    (D + START_DELAY + CYCLES[update]), or with a shared engine (period: this axis's
    window period, Config.tdm axes * L) the same edge of its next window."""
    span = (period if period else cycles["update"] + START_DELAY) - PHASE_STAGE
    if not 1 <= span < 1 << 15:          # (15 bits of the 16-bit LFSR: every value occurs)
        raise ValueError(f"dither span {span} outside 1..32767 (rtl/estimator.v DSPAN)")
    return span


def dither(v: int, span: int) -> int:
    """The clocks r after an UPDATE's decision before a sample may become the next
    candidate, from the LFSR state v: the low N bits, N = bits of span (2**(N-1) <= span),
    minus 2**(N-1) where they exceed span, so r covers 0..span (rtl/estimator.v dith).
    The candidates' instants spread over the update period, so at a speed where the
    signal period divides it (fs / 128 at a sample per clock, 3 fs / 128 at one every 3
    clocks; a shared engine's axis period) the updates still see the whole circle; a
    dither counted in samples (0..15, before) left such speeds uncalibrated."""
    n = span.bit_length()
    r = v & ((1 << n) - 1)
    return r - (1 << (n - 1)) if r > span else r


def gsel(peak: int, g: int) -> int:
    if peak == 0:
        return g
    for cand in range(G_MAX, -1, -1):
        if (peak << cand) < (1 << 14):
            return cand
    return 0


def _front(u1r, u2r, bundle, lut):
    """Fast path up to the fine phase (gain, Eq. 9, Table 2, phase table); the bundle
    fields are scalars (one bundle for a block) or per-sample arrays."""
    g, m1, m2, c1, c12, c2 = bundle
    fr = fp.correct(u1r, u2r, g, m1, m2, c1, c12, c2)
    j, base, neg = fp.octant(fr["ax"], fr["ay"], fr["xn"], fr["yn"], lut.kind)
    phase = lut.phase(j, base, neg)
    fr.update(j=j, base=base, neg=neg, phase=phase, bin=phase >> 7)
    return fr


def tdm_period(w, lanes=1):
    """The window spacing L (clocks) of rtl/finequad_multi.v for windows of W edges: the
    latest UPDATE decided in a window (edge base + W - 1) and the EXTRACT chained to it
    end on base + W + 1 + CYCLES[update] + CYCLES[extract] (a program decided on D ends on
    D + START_DELAY + CYCLES), the first edge on which the next axis may decide."""
    from .estimator import CYCLES_BY_LANES
    c = CYCLES_BY_LANES[lanes]
    return w + 2 * START_DELAY - 1 + c["update"] + c["extract"]


def strobe_edges(n, div, t0=16):
    return t0 + div * np.arange(n, dtype=np.int64)


class Core:
    """The core's state from power-up; `feed` runs the next samples and keeps the state,
    so a recording can be processed in pieces (closed-loop simulation: the controller
    reads the count after each piece). Feeding a recording in pieces gives exactly the
    result of one `run` over the whole (sim/tests/test_model.py checks it).

    Strobe edges continue from the last piece: by default `div` edges apart (the first
    sample on edge 16); given strobes must come after the last one. Config.resets are
    global sample indices; per-sample arrays in the harm_* fields are indexed globally
    too."""

    def __init__(self, cfg: Config = Config()):
        if cfg.count_mode not in (0, 1):
            raise ValueError(f"count_mode must be 0 or 1, got {cfg.count_mode!r}")
        self.cfg = cfg
        self.est = Estimator(cfg.ENGINE_LANES)
        self.lut = fp.Lut(cfg.TABLE, cfg.SIN_W)
        self.k0 = 0                   # samples fed so far
        self.t_last = None            # strobe edge of the last sample fed
        self.t_pieces = []            # strobe edges of the pieces fed (for the schedule)
        self.g_eng = cfg.G_INIT
        self.peak = 0
        self.reset_pend = True
        self.first = True
        self.upd = 0
        self.settle = 0
        self.eng_end = -1             # the running program ends on this edge
        self.slot = None              # the candidate awaiting its check (a dict)
        self.slot_free = -1           # the slot is empty for samples strobed on edges >= this
        self.reset_at = -1            # a pending reset acts on samples strobed on >= this
        self.cand_from = -1           # dither: no candidate strobed before this edge
        self.cover = 0                # octants of the updates since the last commit
        self.cwin = 0                 # updates since the coverage last restarted
        self.lfsr = LFSR_SEED
        self.requests = set(cfg.resets)
        # bundle events: the edges on which the bundle registers change (sorted), what
        # each does (('init', b), ('commit', b), ('invalid',) an extraction that failed,
        # ('load', b) from the registers) and the state after it (bundle, uncal, hold,
        # loaded); a sample strobed on edge t uses the state of the last event before t
        self.ev_edge, self.ev_delta, self.ev_state = [-1], [("init", BUNDLE0)], \
            [(BUNDLE0, 1, 0, 0)]
        for w, b in sorted(cfg.loads, key=lambda x: x[0]):
            self._event(w + BUNDLE_AT, ("load", tuple(int(v) for v in b)))
        self.uncal = 1
        self.mon = Monitor(enabled=bool(cfg.OPT_MONITOR))
        self.s_last = 0               # the travel at the last update (estimator's gate)
        self.n_updates = 0
        self.n_invalid = 0          # updates that ended invalid (each resets P)
        self.n_gain_held = 0        # hand-overs held for the warm-up's gain check
        self.sched = []               # the estimator's programs, for the float reference
        self.decided = []             # (kind, edge on which each program was decided)
        self.jf = self.jl = 0         # jump detector: fast and slow mean |e|, u15.5
        self.armed = False            # a commit since power-up or the last jump
        self.freeze = 0               # trace bound: the next update does not forget
        self.jumps = []
        self.harm = harmonic.Harmonic()
        self.harm_used = False        # learning was on for some sample fed so far
        self.pulse_ab = (1, 1)        # Eq. 12 pulses after the last sample (reset: 1, 1)
        self.cnt_state = None         # the phase-mode counter after the last sample
        self.edge_state = None        # the x4 decoder after the last sample
        self.e_tail = []              # (t, E after it) of the last samples fed
        self.e_base = 0               # E before the samples in e_tail
        self.ill_count = 0            # illegal A/B steps
        self.ab = abgen.Follower(cfg.ab_sep, cfg.ab_bound, cfg.COUNT_W)
        self.tdm = None
        if cfg.tdm is not None:
            axes, index, ln, w = (int(v) for v in cfg.tdm)
            if not (axes >= 1 and 0 <= index < axes and 1 <= w and
                    ln >= tdm_period(w, cfg.ENGINE_LANES)):
                raise ValueError(f"tdm (axes, index, L, W) = {cfg.tdm!r}: need 0 <= index "
                                 f"< axes, W >= 1, L >= tdm_period(W) = "
                                 f"{tdm_period(max(w, 1), cfg.ENGINE_LANES)}")
            if axes > 1:
                self.tdm = (axes * ln, index * ln, w)   # period, window start, length
        self.dspan = dither_span(self.est.cycles, self.tdm[0] if self.tdm else 0)

    def _granted(self, e):
        """The first edge >= e on which this axis may decide a program (Config.tdm)."""
        if self.tdm is None:
            return e
        period, base, w = self.tdm
        r = (e - base) % period
        return e if r < w else e + period - r

    @staticmethod
    def _apply(state, delta):
        bundle, uncal, hold, loaded = state
        kind = delta[0]
        if kind == "commit":
            return delta[1], 0, 0, 0
        if kind == "invalid":
            return bundle, uncal, 1, loaded
        if kind == "load":
            return delta[1], uncal, hold, 1
        return delta[1], 1, 0, 0                     # init

    def _event(self, edge, delta):
        """Insert a bundle event (after the ones on the same edge: a hand-over on the edge
        of a LOAD wins) and resolve the states from it on; returns its index."""
        i = bisect.bisect_right(self.ev_edge, edge)
        self.ev_edge.insert(i, edge)
        self.ev_delta.insert(i, delta)
        self.ev_state.insert(i, None)
        for j in range(i, len(self.ev_edge)):
            self.ev_state[j] = self._apply(self.ev_state[j - 1], self.ev_delta[j])
        return i

    def _strobes(self, n, strobes):
        cfg = self.cfg
        if strobes is None:
            t = strobe_edges(n, cfg.div) + cfg.div * self.k0
        else:
            t = np.asarray(strobes, np.int64)
            if len(t) != n:
                raise ValueError(f"strobes: {len(t)} edges for {n} samples")
            if n and (np.any(np.diff(t) <= 0) or
                      (self.t_last is not None and t[0] <= self.t_last)):
                raise ValueError("strobes must be strictly increasing and come after "
                                 "the last sample fed")
        return t

    def _per_sample(self, v, n):
        """A Config field that is a scalar or a global per-sample array, for this piece."""
        if np.ndim(v) == 0:
            return v
        return np.asarray(v)[self.k0:self.k0 + n]

    def feed(self, u1_code, u2_code, strobes=None, trace=False):
        """Run the next samples (ADC codes); returns a dict of per-sample arrays for them
        (and, as a list since power-up, the jumps; the schedule: schedule_samples())."""
        cfg = self.cfg
        u1_code = np.asarray(u1_code, dtype=np.int64)
        u2_code = np.asarray(u2_code, dtype=np.int64)
        n = len(u1_code)
        t = self._strobes(n, strobes)
        u1r, clip1 = fp.align(u1_code, cfg.ADC_W, cfg.clip)
        u2r, clip2 = fp.align(u2_code, cfg.ADC_W, cfg.clip)
        clip = clip1 | clip2
        mon = self._schedule(u1r, u2r, t, clip)

        # ---- fast path, vectorised over samples ---------------------------------------
        # the bundle committed on edges < t (correct.v registers the sample on t)
        idx = np.searchsorted(np.asarray(self.ev_edge), t, side="left") - 1
        bund = np.asarray([self.ev_state[i][0] for i in idx], dtype=np.int64).reshape(-1, 6)
        flags = np.asarray([self.ev_state[i][1:4] for i in idx],
                           dtype=np.int64).reshape(-1, 3)    # uncal, hold, loaded
        fr = _front(u1r, u2r, bund.T, self.lut)
        phase = fr["phase"]
        # harmonic compensation between the fine phase and the counter (rtl/harmonic.v)
        learn = self._per_sample(cfg.harm_learn, n)
        self.harm_used = self.harm_used or (bool(np.any(learn)) and bool(cfg.OPT_HARMONIC))
        if self.harm_used:
            # arrivals on t + HARM_AT; a clear written on edge w is high on w + 1 (a clear
            # seen by an earlier piece is not repeated)
            seen = -1 if self.t_last is None else self.t_last + HARM_AT
            clr, blk = harmonic.sweep_flags(t + HARM_AT, [w + 1 for w in cfg.harm_clears
                                                          if w + 1 > seen])
            phase_c = self.harm.run(phase, apply=self._per_sample(cfg.harm_apply, n),
                                    learn=learn, mu=self._per_sample(cfg.harm_mu, n),
                                    clear=clr, blocked=blk)
        else:
            phase_c = phase      # nothing learned from power-up: an empty table
        prod, pn, cosn, sinn = self.lut.nth(phase_c, cfg.interp)
        pa, pb = fp.pulse(cosn, sinn, cfg.eps, cfg.SIN_W, *self.pulse_ab)
        count_ph, ovs, self.cnt_state = fp.counter(phase_c, prod, cfg.interp, cfg.COUNT_W,
                                                   state=self.cnt_state, hold=mon["hold"])
        # the x4 decoder of the pulses: E after each sample's pulses (edge t + EDGE_AT)
        steps, ill, self.edge_state = fp.edge_steps(pa, pb, self.edge_state)
        self.ill_count += int(ill.sum())
        tail_t = np.array([e[0] for e in self.e_tail] + list(t), dtype=np.int64)
        tail_e = np.array([e[1] for e in self.e_tail], dtype=np.int64)
        ecum = np.concatenate([tail_e, (tail_e[-1] if len(tail_e) else self.e_base)
                               + np.cumsum(steps)])
        if cfg.count_mode:
            # E as of the output edge t + LATENCY: samples strobed on or before t - 3
            j = np.searchsorted(tail_t, t + LATENCY - 1 - EDGE_AT, side="right") - 1
            wrapm = 1 << cfg.COUNT_W
            e_at = np.where(j >= 0, ecum[np.maximum(j, 0)], self.e_base)
            count = ((e_at + (wrapm >> 1)) % wrapm) - (wrapm >> 1)
        else:
            count = count_ph
        keep = min(3, len(tail_t))
        if keep:
            drop = len(tail_t) - keep
            self.e_base = int(ecum[drop - 1]) if drop > 0 else self.e_base
            self.e_tail = list(zip(tail_t[drop:].tolist(), ecum[drop:].tolist()))
        # A/B pins after each sample's output edge
        a_pin = np.empty(n, np.int64)
        b_pin = np.empty(n, np.int64)
        ab_ovf = np.empty(n, np.int64)
        prev_pulse = self.pulse_ab
        for k in range(n):
            e = int(t[k]) + LATENCY
            a_pin[k], b_pin[k], ab_ovf[k] = self.ab.sample(e)
            self.ab.set(e + 1, int(count[k]))
        if cfg.ab_src:
            a_pin = np.concatenate([[prev_pulse[0]], pa[:-1]]) if n else a_pin
            b_pin = np.concatenate([[prev_pulse[1]], pb[:-1]]) if n else b_pin
        if n:
            self.pulse_ab = (int(pa[-1]), int(pb[-1]))
        fault = (clip.astype(np.int64) << FAULT_BITS["clip"]
                 | fr["nsat"].astype(np.int64) << FAULT_BITS["nsat"]
                 | fr["csat"].astype(np.int64) << FAULT_BITS["csat"]
                 | ovs.astype(np.int64) << FAULT_BITS["ovs"]
                 | flags[:, 0] << FAULT_BITS["uncal"]
                 | flags[:, 1] << FAULT_BITS["hold"]
                 | ab_ovf << FAULT_BITS["abovf"])
        for name in ("loss", "over", "stuck", "glitch"):
            fault |= mon[name].astype(np.int64) << FAULT_BITS[name]
        self.k0 += n
        if n:
            self.t_last = int(t[-1])
            self.t_pieces.append(t)
            # the bundle events no later sample can see are dropped (the one in force
            # for the next sample stays), so pieces stay cheap however long the run
            keep = bisect.bisect_right(self.ev_edge, self.t_last) - 1
            if keep > 0:
                del self.ev_edge[:keep], self.ev_delta[:keep], self.ev_state[:keep]
        res = dict(jumps=list(self.jumps), count=count, a=a_pin, b=b_pin, fault=fault,
                   n_updates=self.n_updates, invalid_updates=self.n_invalid,
                   gain_held=self.n_gain_held,
                   sat=self.est.sat,      # the engine saturated a register (STATUS bit 2)
                   illegal_count=self.ill_count)
        if trace:
            g, m1, m2, c1, c12, c2 = bund.T
            res.update({k: fr[k] for k in ("u1c", "u2c", "ax", "ay", "xn", "yn", "phase",
                                           "j", "base", "neg", "bin")})
            res.update(prod=prod, pn=pn, cosn=cosn, sinn=sinn, pa=pa, pb=pb, g=g, m1=m1,
                       m2=m2, c1=c1, c12=c12, c2=c2, phase_c=phase_c, harm=self.harm,
                       count_phase=count_ph, ill=ill, t=t, travel=mon["travel"],
                       mon_hold=mon["hold"], excl=mon["excl"], ref=mon["ref"],
                       loaded=flags[:, 2])
        return res

    def schedule_samples(self):
        """The estimator's programs since power-up as (kind, sample, g, commit): commit is
        the index of the first sample that sees the new coefficients (the number of
        samples fed so far if none has yet), None if the program did not commit."""
        t = np.concatenate(self.t_pieces) if self.t_pieces else np.zeros(0, np.int64)
        return [(kind, k, g, None if e is None else int(np.searchsorted(t, e, side="right")))
                for kind, k, g, e in self.sched]

    def _schedule(self, u1r, u2r, t, clip):
        """The monitor on every sample and the estimator's decisions, in edge order (see the
        module text and sim/model/monitor.py). Returns the monitor's per-sample flags
        (loss, over, stuck, glitch, hold, excl; ref: the radius checks are armed;
        travel: S after the sample)."""
        cfg = self.cfg
        lut, mon = self.lut, self.mon
        mregs = cfg.monitor_regs()
        n = len(u1r)
        k0 = self.k0
        amax = np.minimum(np.maximum(np.abs(u1r), np.abs(u2r)), 32767).tolist()
        r1l, r2l, clipl = u1r.tolist(), u2r.tolist(), clip.tolist()
        tl = t.tolist()
        requests = self.requests
        out = {f: np.zeros(n, dtype=bool) for f in ("loss", "over", "stuck", "glitch",
                                                     "hold", "excl", "ref")}
        travel = np.zeros(n, dtype=np.int64)
        blk_lo = blk_hi = 0           # the fast path of samples [blk_lo, blk_hi) under one
        blk = None                    # bundle event (computed a block at a time)
        kappa = max(cfg.kappa, 1)                  # KAPPA = 0 is taken as 1/256
        for k in range(n):
            tk = tl[k]
            if k >= blk_hi:
                # the state in force for t_k, up to the first sample that sees the next event
                i = bisect.bisect_left(self.ev_edge, tk)
                bundle, b_uncal, _, b_loaded = self.ev_state[i - 1]
                blk_lo, blk_hi = k, min(n, k + 256)
                if i < len(self.ev_edge):
                    blk_hi = min(blk_hi, int(np.searchsorted(t, self.ev_edge[i],
                                                             side="right")))
                fr = _front(u1r[k:blk_hi], u2r[k:blk_hi], bundle, lut)
                blk = (fr["ax"].tolist(), fr["ay"].tolist(), fr["phase"].tolist(),
                       (not b_uncal) or b_loaded, fr["xn"].tolist(), fr["yn"].tolist())
            j = k - blk_lo
            ph = blk[2][j]
            # ---- the monitor (every sample) ----
            s_prev = mon.travel()      # S after the previous sample (the gate's input)
            loss, over, stuck, glitch, hold, excl = mon.step(
                r1l[k], r2l[k], blk[0][j], blk[1][j], blk[4][j], blk[5][j], ph, blk[3],
                clipl[k], mregs)
            out["loss"][k], out["over"][k], out["stuck"][k] = loss, over, stuck
            out["glitch"][k], out["hold"][k], out["excl"][k] = glitch, hold, excl
            out["ref"][k] = blk[3]
            travel[k] = mon.travel()
            # ---- the estimator: the held candidate's check on an edge <= t_k ----
            if self.slot is not None and self.slot["c"] <= tk:
                xdone = self._check(self.slot)
                self.slot = None
                if xdone is not None:
                    # samples from the first one that sees the commit need their fast path
                    blk_hi = min(blk_hi, int(np.searchsorted(t, xdone, side="right")))
            # ---- its arrival decision on t_k + 1 ----
            if k0 + k in requests:
                self._pend_reset(-1)   # pending for this sample's decision
            empty = self.slot is None and tk >= self.slot_free
            if self.reset_pend and tk >= self.reset_at:
                if empty and tk >= self.eng_end and \
                        self._granted(tk + RESET_STAGE) == tk + RESET_STAGE:
                    g_new = gsel(self.peak, self.g_eng)
                    self.est.run("reset", kappa=kappa, dg=g_new - self.g_eng)
                    self.freeze = int(self.est.out[6] >= (5 * kappa) >> 4)
                    self.sched.append(("reset", k0 + k, g_new, None))
                    self.decided.append(("reset", tk + RESET_STAGE))
                    self.g_eng = g_new
                    self.peak = 0
                    self.reset_pend = False
                    self.upd = 0
                    self.settle = 0
                    self.cover = 0    # a hand-over needs all octants since the reset, too
                    self.cwin = 0
                    self.eng_end = tk + RESET_STAGE + START_DELAY + self.est.cycles["reset"]
                    continue
            elif empty and tk >= self.cand_from:
                self.slot = dict(k=k0 + k, c=tk + PHASE_STAGE, x1=r1l[k] << self.g_eng,
                                 x2=r2l[k] << self.g_eng, peak=self.peak, excl=excl,
                                 s_prev=s_prev, oct=raw_octant(r1l[k], r2l[k]))
            self.peak = max(self.peak, amax[k])
        out["travel"] = travel
        return out

    def _check(self, cand):
        """The candidate's check on its edge c, and its UPDATE (with the END decisions:
        jump detector, EXTRACT) if it passes. Returns the commit edge of a hand-over it
        caused, else None."""
        cfg = self.cfg
        c = cand["c"]
        self.slot_free = c
        if cand["excl"]:
            return None               # not trusted (monitor; clipped samples too)
        x1, x2 = cand["x1"], cand["x2"]
        if not (-32768 <= x1 <= 32767 and -32768 <= x2 <= 32767):
            self._pend_reset(c)
            return None
        if abs(((cand["s_prev"] - self.s_last + (1 << 19)) & 0xFFFFF) - (1 << 19)) < cfg.gate:
            return None               # too little travel since the last update
        d = self._granted(max(c, self.eng_end))   # the UPDATE is decided on d
        self.slot_free = d
        self.decided.append(("update", d))
        self.s_last = cand["s_prev"]
        if self.cwin >= COVER_WIN:    # the window is full: coverage restarts here
            self.cover, self.cwin = 0, 0
        self.cover |= 1 << cand["oct"]
        self.cwin += 1
        self.cand_from, self.lfsr = d + dither(self.lfsr, self.dspan), lfsr_step(self.lfsr)
        lam_k = min(max(cfg.lam_k, 1), 23)
        kappa = max(cfg.kappa, 1)
        ok = self.est.run("update", x1=x1, x2=x2, lam_k=lam_k, freeze=self.freeze)
        self.freeze = int(self.est.out[6] >= (5 * kappa) >> 4)
        self.n_updates += 1
        self.upd += 1
        # before the warm-up's gain check, a theta fitted at a gain the peak does not want
        # is not handed over (at 10 % of full scale it would map the signal to a radius
        # near 0.27: the coefficients it needs at that gain exceed s4.12)
        gain_wrong = gsel(cand["peak"], self.g_eng) != self.g_eng
        gain_pending = self.first and gain_wrong
        if self.first and self.upd >= WARMUP:
            # the gain check after the warm-up: reset only if the input gain changes
            if gain_wrong:
                self._pend_reset(d)
            self.first = False
        elif not self.first and cfg.period and self.upd >= cfg.period:
            self._pend_reset(d)
        done = d + START_DELAY + self.est.cycles["update"]
        self.eng_end = done
        # jump detector on the a-priori residual |e| of this update (s3.13)
        eabs = min(abs(self.est.out[5]), 32767) << 5
        jf_next = self.jf + ((eabs - self.jf) >> 2)
        trig = self.armed and cfg.OPT_JUMP and cfg.jump_on and \
            jf_next > (self.jl << 2) + (cfg.jump_min << 5)
        if trig:
            self._pend_reset(done)
            self.armed = False
            self.cover = self.cwin = 0
            self.jf = self.jl
            self.jumps.append(cand["k"])
        else:
            self.jf = jf_next
            if self.armed or self.uncal:
                self.jl += (eabs - self.jl) >> 6
        if not ok:
            self.n_invalid += 1
            self._pend_reset(done)    # s' <= 0 (P no longer positive) or e saturated
        xdone = None
        handover = ok and self.settle >= cfg.settle and self.cover == 0xFF and not trig
        self.n_gain_held += int(handover and gain_pending)
        if handover and not gain_pending:
            # EXTRACT, decided on the update's last edge; it hands the new bundle over on
            # its own last edge if theta is an ellipse
            okx = self.est.run("extract")
            self.decided.append(("extract", done))
            xdone = done + START_DELAY + self.est.cycles["extract"]
            self.eng_end = xdone
            if okx:
                self._event(xdone, ("commit", (self.g_eng, *self.est.out[:5])))
                self.sched.append(("update", cand["k"], self.g_eng, xdone))
                self.uncal = 0
                self.cover = self.cwin = 0
                self.armed = True
            else:
                self._event(xdone, ("invalid",))
                self.sched.append(("update", cand["k"], self.g_eng, None))
        else:
            self.sched.append(("update", cand["k"], self.g_eng, None))
        self.settle = min(self.settle + 1, 1023)
        return xdone

    def _pend_reset(self, edge):
        """A reset becomes pending on `edge` (acting on samples strobed on or after it)."""
        if not self.reset_pend:
            self.reset_pend, self.reset_at = True, edge
        else:
            self.reset_at = min(self.reset_at, edge)


def raw_octant(u1, u2):
    """The estimator's coverage octant of a sample: the sector of its raw codes around the
    origin, (u2 < 0) << 2 | (u1 < 0) << 1 | (|u1| < |u2|). A loop of any ellipse that
    encloses the origin passes all eight whatever the bundle in use (the fine phase's
    octants depend on it: a wrong bundle, loaded or fitted, kept the phase in three
    octants and the estimator never handed over again)."""
    return (int(u2 < 0) << 2) | (int(u1 < 0) << 1) | int(abs(int(u1)) < abs(int(u2)))


def run(u1_code, u2_code, cfg: Config = Config(), strobes=None, trace=False):
    """Run the core on ADC codes from power-up; returns a dict of per-sample arrays, and
    the estimator's schedule (Core.schedule_samples)."""
    c = Core(cfg)
    res = c.feed(u1_code, u2_code, strobes=strobes, trace=trace)
    res["sched"] = c.schedule_samples()
    return res
