"""Bit-true model of rtl/estimator.v: which samples the RLS engine takes, covariance
resets, the input gain, the jump detector and the hand-over of a new coefficient bundle.
The engine itself (Eqs. 5-8) is sim/model/rls_engine.py. The schedule, and why it is so,
is told once, in sim/README.md ("The estimator"); this module is its executable form,
edge for edge (edges numbered from 0, sample k strobed on edge t_k):

* arrival decision on t_k + RESET_STAGE (arrive()): a RESET, or the sample into the
  empty candidate slot once the dither has elapsed;
* the candidate's check on t_k + PHASE_STAGE (check_due(), _check()): dropped, or an
  UPDATE decided on D = the first granted edge at or after max(check, the running
  program's end); a program decided on D starts on D + START_DELAY and ends on
  D + START_DELAY + CYCLES[program];
* the END decisions of an UPDATE (the jump detector, the hand-over's EXTRACT) on its last
  edge; a bundle is committed on the EXTRACT's last edge (on_bundle);
* a reset becomes pending on an edge (a dropped candidate: its check; the warm-up or
  PERIOD check: D; a jump or an invalid update: the update's end) and acts on samples
  strobed on or after it; CTRL.cov_reset is pending for the sample it is attributed to
  (Config.resets). With a shared engine (Config.tdm) an axis decides only in its window
  (_granted()).
"""
from .rls_engine import CYCLES_BY_LANES, RlsEngine

RESET_STAGE = 1      # a RESET is decided on the edge after the arrival
PHASE_AT = 6         # the candidate's fine phase is registered on t_k + PHASE_AT
PHASE_STAGE = PHASE_AT + 2   # an UPDATE is decided here (inputs registered one edge first)
START_DELAY = 1      # the engine starts on the edge after the decision (registered)
LFSR_SEED = 0xACE1   # dither of the sample choice
WARMUP = 64          # updates before the first automatic reset (picks the input gain)
COVER_WIN = 255      # updates within which a hand-over needs all eight octants
G_MAX = 3            # input gain 2**g, g in 0..3 (amplitudes down to ~6 % of full scale)
LAMBDA_K_MIN, LAMBDA_K_MAX = 1, 23   # LAMBDA_K is used clamped to this (rtl/estimator.v)


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
    clocks; a shared engine's axis period) the updates still see the whole circle."""
    n = span.bit_length()
    r = v & ((1 << n) - 1)
    return r - (1 << (n - 1)) if r > span else r


def gsel(peak: int, g: int) -> int:
    """The input gain for the peak |u| (s1.15) seen since the last reset: the largest g
    that keeps peak << g below half of full scale (g kept if no sample was seen)."""
    if peak == 0:
        return g
    for cand in range(G_MAX, -1, -1):
        if (peak << cand) < (1 << 14):
            return cand
    return 0


def raw_octant(u1, u2):
    """The estimator's coverage octant of a sample: the sector of its raw codes around the
    origin, (u2 < 0) << 2 | (u1 < 0) << 1 | (|u1| < |u2|). A loop of any ellipse that
    encloses the origin passes all eight whatever the bundle in use (the fine phase's
    octants depend on it: a wrong bundle kept the phase in three octants and the
    estimator would never hand over again)."""
    return (int(u2 < 0) << 2) | (int(u1 < 0) << 1) | int(abs(int(u1)) < abs(int(u2)))


def tdm_period(w, lanes=1):
    """The window spacing L (clocks) of rtl/finequad_multi.v for windows of W edges: the
    latest UPDATE decided in a window (edge base + W - 1) and the EXTRACT chained to it
    end on base + W + 1 + CYCLES[update] + CYCLES[extract] (a program decided on D ends on
    D + START_DELAY + CYCLES), the first edge on which the next axis may decide."""
    c = CYCLES_BY_LANES[lanes]
    return w + 2 * START_DELAY - 1 + c["update"] + c["extract"]


class Estimator:
    """rtl/estimator.v's state from power-up. cfg: the core's Config (the settings it
    reads: lambda_k, kappa, period, settle, gate, jump_off, jump_min, resets, G_INIT,
    ENGINE_LANES, OPT_JUMP, tdm). on_bundle(edge, delta) receives the bundle events it
    causes (('commit', bundle) or ('invalid',) on the edge the EXTRACT ends)."""

    def __init__(self, cfg, on_bundle):
        self.cfg = cfg
        self.on_bundle = on_bundle
        self.engine = RlsEngine(cfg.ENGINE_LANES)
        self.cycles = self.engine.cycles
        self.g_eng = cfg.G_INIT       # the input gain of the engine's theta
        self.peak = 0                 # max |u| since the last reset
        self.reset_pend = True
        self.first = True             # before the warm-up's gain check
        self.upd = 0                  # updates since the last reset
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
        self.uncal = 1
        self.s_last = 0               # the travel at the last update (the gate)
        self.n_updates = 0
        self.n_invalid = 0            # updates that ended invalid (each resets P)
        self.n_gain_held = 0          # hand-overs held for the warm-up's gain check
        self.sched = []               # the programs, for the float reference
        self.decided = []             # (kind, edge on which each program was decided)
        self.jf = self.jl = 0         # jump detector: fast and slow mean |e|, u15.5
        self.armed = False            # a commit since power-up or the last jump
        self.freeze = 0               # trace bound: the next update does not forget
        self.jumps = []
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
        self.dspan = dither_span(self.cycles, self.tdm[0] if self.tdm else 0)

    @property
    def sat(self):
        """The engine saturated a register since power-up (STATUS.sat)."""
        return self.engine.sat

    def _granted(self, e):
        """The first edge >= e on which this axis may decide a program (Config.tdm)."""
        if self.tdm is None:
            return e
        period, base, w = self.tdm
        r = (e - base) % period
        return e if r < w else e + period - r

    def _kappa(self):
        return max(self.cfg.kappa, 1)            # KAPPA = 0 is taken as 1/256

    def check_due(self, tk):
        """The held candidate's check, if it falls on an edge <= tk. Returns the commit
        edge of a hand-over it caused, else None."""
        if self.slot is not None and self.slot["c"] <= tk:
            cand, self.slot = self.slot, None
            return self._check(cand)
        return None

    def arrive(self, k, tk, r1, r2, amax, excl, s_prev):
        """Sample k (global index) arrives on edge tk (r1, r2: its codes aligned to s1.15,
        amax: min(max(|r1|, |r2|), 32767), excl: the monitor keeps it from the estimator,
        s_prev: the travel after the sample before): its arrival decision on tk + 1.
        Returns True if it started a RESET."""
        if k in self.requests:
            self._pend_reset(-1)      # pending for this sample's decision
        empty = self.slot is None and tk >= self.slot_free
        if self.reset_pend and tk >= self.reset_at:
            if empty and tk >= self.eng_end and \
                    self._granted(tk + RESET_STAGE) == tk + RESET_STAGE:
                kappa = self._kappa()
                g_new = gsel(self.peak, self.g_eng)
                self.engine.run("reset", kappa=kappa, dg=g_new - self.g_eng)
                self.freeze = int(self.engine.out[6] >= (5 * kappa) >> 4)
                self.sched.append(("reset", k, g_new, None))
                self.decided.append(("reset", tk + RESET_STAGE))
                self.g_eng = g_new
                self.peak = 0
                self.reset_pend = False
                self.upd = 0
                self.settle = 0
                self.cover = 0        # a hand-over needs all octants since the reset, too
                self.cwin = 0
                self.eng_end = tk + RESET_STAGE + START_DELAY + self.cycles["reset"]
                return True
        elif empty and tk >= self.cand_from:
            self.slot = dict(k=k, c=tk + PHASE_STAGE, x1=r1 << self.g_eng,
                             x2=r2 << self.g_eng, peak=self.peak, excl=excl,
                             s_prev=s_prev, oct=raw_octant(r1, r2))
        self.peak = max(self.peak, amax)
        return False

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
        lambda_k = min(max(cfg.lambda_k, LAMBDA_K_MIN), LAMBDA_K_MAX)
        kappa = self._kappa()
        ok = self.engine.run("update", x1=x1, x2=x2, lambda_k=lambda_k, freeze=self.freeze)
        self.freeze = int(self.engine.out[6] >= (5 * kappa) >> 4)
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
        done = d + START_DELAY + self.cycles["update"]
        self.eng_end = done
        # jump detector on the a-priori residual |e| of this update (s3.13)
        eabs = min(abs(self.engine.out[5]), 32767) << 5
        jf_next = self.jf + ((eabs - self.jf) >> 2)
        trig = self.armed and cfg.OPT_JUMP and not cfg.jump_off and \
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
            okx = self.engine.run("extract")
            self.decided.append(("extract", done))
            xdone = done + START_DELAY + self.cycles["extract"]
            self.eng_end = xdone
            if okx:
                self.on_bundle(xdone, ("commit", (self.g_eng, *self.engine.out[:5])))
                self.sched.append(("update", cand["k"], self.g_eng, xdone))
                self.uncal = 0
                self.cover = self.cwin = 0
                self.armed = True
            else:
                self.on_bundle(xdone, ("invalid",))
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
