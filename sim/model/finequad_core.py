"""Bit-true model of rtl/finequad_core.v: the fast path, the signal monitor, the
estimator (sim/model/estimator.py) and the counter and A/B outputs, timed against the
sample stream. Clock-edge timing (the RTL implements exactly this; edges are numbered
from 0):

* Sample k is strobed (s_valid high) on edge t_k: correct.v registers x - m on t_k with
  the coefficient bundle as it stands before t_k (committed on edges < t_k), so a sample
  never mixes two bundles. Its fine phase is registered on t_k + PHASE_AT (6), its count
  on t_k + LATENCY (8); the paced A/B outputs and Z follow the count from t_k + 10.
* The estimator sees every sample on t_k and decides on t_k + 1 (sim/model/estimator.py
  gives its schedule); a hand-over commits a new bundle on an edge, and the samples
  strobed after that edge use it. A LOAD (CTRL.load) written on edge w replaces the
  bundle on w + BUNDLE_AT.
* The counter counts the fine phase after the harmonic compensation (sim/model/
  harmonic.py, rtl/harmonic.v; the block samples a sample's arrival on t_k + HARM_AT):
  a function of the samples alone, except the table clears (Config.harm_clears), which
  are timed in edges (a 64-clock RAM sweep).
* Edge mode (count_mode 1): the count of sample k is the x4 decoder's count of the Eq. 12
  pulses as of its output edge: the steps of the samples strobed on or before t_k - 3
  (the pulses come two edges after the phase-mode count).
* A/B pins: the paced outputs (sim/model/abgen.py) follow the count before the homing
  offset, which takes sample k's count on t_k + 8 and is registered again on t_k + 9 (the
  target from t_k + 10); the per-sample a, b and z are the pins after t_k + 8, as `make
  rtlsim` samples them. With ab_src = 1 the pins are the Eq. 12 pulses from t_k + 10
  (those of the last sample strobed on or before t_k - 2) and Z beside them.
* Reference marks (sim/model/refmark.py): sample k's reference input is taken on t_k + 9
  (window, crossing, Z armed), REF_COUNT, homed and pos_valid on t_k + 10 (the per-sample
  ref_count, homed, pos_valid are after t_k + 10); m_count = the count + the homing
  offset as it stands after t_k + 8.
"""
import bisect
from dataclasses import dataclass, field

import numpy as np

from . import abgen
from . import harmonic
from . import refmark
from . import regs
from .correct import align, correct
from .counter import counter, edge_steps
from .estimator import PHASE_AT, PHASE_STAGE, Estimator
from .lut import Lut
from .monitor import Monitor, MonitorRegs, stuck_span
from .octant import octant
from .pulse import pulse

# Pipeline timing of rtl/finequad_core.v: edges from a sample's strobe edge t to the edge
# that registers each result. The RTL declares the same numbers (localparams of
# finequad_core.v); the tests hold its behaviour to these, not to its source text.
CORR_AT = 2          # correct: |u1c|, |u2c|, signs, rsat
OCT_AT = 3           # octant: valid, oct2, neg (j and the bin follow, combinational, at 5)
HARM_AT = 4          # the edge on which the harmonic block samples the sample's arrival
ADDR_AT = 5          # phase and harmonic tables read (j, bin)
NTH_AT = 7           # n * phase; the period count B
LATENCY = 8          # counter: m_valid, m_count, m_fault
SIN_AT = 8           # sines of the n-th order
PULSE_AT = 9         # Eq. 12 pulses
AB_AT = 10           # paced A/B and Z (follow the count, registered again on t + 9)
REF_AT = 9           # reference window, crossing, Z armed (rtl/refmark.v)
LATCH_AT = 10        # REF_COUNT, homed, pos_valid, the homing offset
EDGE_AT = 10         # edge-mode count (x4 decoder of the pulses)
assert PHASE_AT == 6 and PHASE_STAGE == PHASE_AT + 2   # the fine phase (estimator.py)
ID = regs.ID_VALUE   # the ID register: "FQ" and the register map's version
FAULT_BITS = regs.FAULT_BITS   # m_fault's bits: the fields of FAULT_STICKY
FAULT_W = regs.FAULT_W
BUNDLE_AT = 1        # a LOAD (CTRL.load) written on edge w replaces the bundle on w + 1
_S = regs.SETTINGS   # the registers' fields (rtl/regs/finequad.rdl): names and reset values


@dataclass
class Config:
    """Build-time parameters (UPPER, as the RTL's) and run-time settings (lower: the
    registers' fields, by their names in rtl/regs/finequad.rdl, defaults their reset
    values), and the events a run is timed against (resets, harm_clears, loads)."""
    ADC_W: int = 16
    SIN_W: int = 10
    TABLE: str = "exact"
    COUNT_W: int = 32
    G_INIT: int = 0
    OPT_HARMONIC: int = 1    # 0: no harmonic compensation (rtl/phase.v), HARM reads 0
    OPT_MONITOR: int = 1     # 0: no fault checks (sim/model/monitor.py), RADIUS and
                             # MONITOR read 0
    OPT_JUMP: int = 1        # 0: no jump detector (as jump_off = 1), JUMPS reads 0
    OPT_DCODE: int = 1       # 0: no distance-coded marks (DCODE refused, as dc_spacing = 0)
    ENGINE_LANES: int = 1    # lanes of the RLS engine (1 or 2): its clocks per program
    interp: int = _S["interp"].reset
    count_mode: int = _S["count_mode"].reset
    eps: int = _S["eps"].reset
    lambda_k: int = _S["lambda_k"].reset
    kappa: int = _S["kappa"].reset
    period: int = _S["period"].reset
    jump_off: int = _S["jump_off"].reset
    jump_min: int = _S["jump_min"].reset
    settle: int = _S["settle"].reset
    gate: int = _S["gate"].reset
    div: int = 36            # clocks per sample when strobes are uniform
    resets: list = field(default_factory=list)   # sample indices of reset requests
                             # (CTRL.cov_reset; pending when the sample arrives)
    harm_apply: int = _S["harm_apply"].reset
    harm_learn: int = _S["harm_learn"].reset
    harm_mu: int = _S["harm_mu"].reset   # the LMS step is 2^-(3 + harm_mu) in gear 0
    harm_clears: list = field(default_factory=list)   # edges w of HARM writes with
                             # harm_clear: the samples strobed on edges t_k >= w + 1 -
                             # HARM_AT see an empty table; those strobed on w + 1 - HARM_AT
                             # .. w + 65 - HARM_AT are not corrected (the RAM is swept)
    # (harm_apply/learn/mu may also be per-sample arrays: the values the RTL samples on
    # edges t_k + HARM_AT + 1 (apply) and t_k + HARM_AT + 7 (learn, mu); a register
    # written on edge w is sampled on the edges after w)
    ab_sep: int = _S["ab_sep"].reset
    ab_src: int = _S["ab_src"].reset
    ab_bound: int = _S["ab_bound"].reset
    ref_q: int = _S["ref_q"].reset
    ref_filt: int = _S["ref_filt"].reset
    home_count: int = _S["home_count"].reset
    home_arm: bool = False   # REF.home written before the first sample: the first
                             # reference latched homes the count to home_count
    homes: list = field(default_factory=list)   # edges w of REF.home writes during the run
                             # (each arms homing for the latches on edges >= w + 2)
    dc_spacing: int = _S["dc_spacing"].reset   # distance-coded marks (sim/model/dcode.py)
    dc_coded: int = _S["dc_coded"].reset
    dc_confirm: int = _S["dc_confirm"].reset
    clip: int = _S["clip"].reset
    loss: int = _S["loss"].reset
    over: int = _S["over"].reset
    glitch_k: int = _S["glitch_k"].reset
    stuck_n: int = _S["stuck_n"].reset
    floor: int = _S["floor"].reset      # COAST: the radius below which the count coasts
    coast_acc: int = _S["coast_acc"].reset   # and the machine's largest acceleration
    code_step: int = _S["code_step"].reset   # the converter's code step, 2^code_step LSBs
    loads: list = field(default_factory=list)   # [(w, (g, m1, m2, c1, c12, c2))]: a
                             # LOAD (CTRL.load) written on edge w with that bundle staged
                             # in GAIN..C2; samples strobed on edges >= w + 2 use it
    tdm: tuple = None        # (axes, index, L, W): this axis of rtl/finequad_multi.v, whose
                             # engine programs start only in its window
                             # (sim/model/estimator.py); None: the axis's own engine

    def monitor_regs(self):
        return MonitorRegs(loss=self.loss, over=self.over, glitch_k=self.glitch_k,
                           stuck_n=self.stuck_n, floor=self.floor,
                           coast_acc=self.coast_acc)


# The registers of the coefficient bundle: writes stage a bundle for CTRL.load (Config.loads)
BUNDLE_REGS = ("GAIN", "M1", "M2", "C1", "C12", "C2")


def register_writes(cfg):
    """[(word index, word)]: the registers that hold cfg's settings (the Config fields
    named as the registers' fields, rtl/regs/finequad.rdl), CTRL last (its pulse fields
    0); the bundle's registers (BUNDLE_REGS) are not settings. Written before the first
    sample, they configure the RTL as cfg configures the model."""
    out = []
    for name, r in regs.REGS.items():
        if name in BUNDLE_REGS or name == "CTRL":
            continue
        sett = {f: getattr(cfg, f) for f, fd in r.fields.items()
                if fd.write and not fd.pulse and not fd.w1c}
        if sett:
            out.append((r.index, regs.word(name, **sett)))
    out.append((regs.CTRL, regs.word("CTRL", count_mode=cfg.count_mode)))
    return out


# Default bundle: the registers' reset values, a centred circle of radius 0.5
# (normalised): c1 = c2 = 2.0 in s4.12.
BUNDLE0 = (0, _S["m1"].reset, _S["m2"].reset, _S["c1"].reset, _S["c12"].reset,
           _S["c2"].reset)


def _front(u1r, u2r, bundle, lut):
    """Fast path up to the fine phase (gain, Eq. 9, Table 2, phase table); the bundle
    fields are scalars (one bundle for a block) or per-sample arrays."""
    g, m1, m2, c1, c12, c2 = bundle
    fr = correct(u1r, u2r, g, m1, m2, c1, c12, c2)
    j, base, neg = octant(fr["ax"], fr["ay"], fr["xn"], fr["yn"], lut.kind)
    phase = lut.phase(j, base, neg)
    fr.update(j=j, base=base, neg=neg, phase=phase, bin=phase >> 7)
    return fr


def strobe_edges(n, div, t0=32):
    return t0 + div * np.arange(n, dtype=np.int64)


class Core:
    """The core's state from power-up; `feed` runs the next samples and keeps the state,
    so a recording can be processed in pieces (closed-loop simulation: the controller
    reads the count after each piece). Feeding a recording in pieces gives exactly the
    result of one `run` over the whole (sim/tests/test_model.py checks it).

    Strobe edges continue from the last piece: by default `div` edges apart (the first
    sample on edge 32); given strobes must come after the last one. Config.resets are
    global sample indices; per-sample arrays in the harm_* fields are indexed globally
    too."""

    def __init__(self, cfg: Config = Config()):
        if cfg.count_mode not in (0, 1):
            raise ValueError(f"count_mode must be 0 or 1, got {cfg.count_mode!r}")
        self.cfg = cfg
        self.lut = Lut(cfg.TABLE, cfg.SIN_W)
        self.k0 = 0                   # samples fed so far
        self.t_last = None            # strobe edge of the last sample fed
        self.t_pieces = []            # strobe edges of the pieces fed (for the schedule)
        # bundle events: the edges on which the bundle registers change (sorted), what
        # each does (('init', b), ('commit', b), ('invalid',) an extraction that failed,
        # ('load', b) from the registers) and the state after it (bundle, uncal, hold,
        # loaded); a sample strobed on edge t uses the state of the last event before t
        self.ev_edge, self.ev_delta, self.ev_state = [-1], [("init", BUNDLE0)], \
            [(BUNDLE0, 1, 0, 0)]
        for w, b in sorted(cfg.loads, key=lambda x: x[0]):
            self._event(w + BUNDLE_AT, ("load", tuple(int(v) for v in b)))
        self.est = Estimator(cfg, self._event)
        self.mon = Monitor(enabled=bool(cfg.OPT_MONITOR))
        self.harm = harmonic.Harmonic()
        self.harm_used = False        # learning was on for some sample fed so far
        self.pulse_ab = (1, 1)        # Eq. 12 pulses after the last sample (reset: 1, 1)
        self.cnt_state = None         # the phase-mode counter after the last sample
        self.edge_state = None        # the x4 decoder after the last sample
        self.e_tail = []              # (t, E after it) of the last samples fed
        self.e_base = 0               # E before the samples in e_tail
        self.ill_count = 0            # illegal A/B steps
        self.ab = abgen.Follower(cfg.ab_sep, cfg.ab_bound, cfg.COUNT_W)
        self.rm = refmark.RefMark(cfg.COUNT_W, cfg.ref_q, cfg.ref_filt, cfg.home_count,
                                  cfg.home_arm, cfg.homes,
                                  cfg.dc_spacing if cfg.OPT_DCODE else 0, cfg.dc_coded,
                                  cfg.dc_confirm)

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

    def feed(self, u1_code, u2_code, strobes=None, trace=False, ref=None):
        """Run the next samples (ADC codes; ref: the reference input per sample, 0 or 1,
        None: 0); returns a dict of per-sample arrays for them (and, as a list since
        power-up, the jumps; the schedule: schedule_samples())."""
        cfg = self.cfg
        u1_code = np.asarray(u1_code, dtype=np.int64)
        u2_code = np.asarray(u2_code, dtype=np.int64)
        n = len(u1_code)
        ref = np.zeros(n, np.int64) if ref is None else np.asarray(ref, dtype=np.int64)
        if len(ref) != n or np.any((ref != 0) & (ref != 1)):
            raise ValueError("ref: one value per sample, each 0 or 1")
        t = self._strobes(n, strobes)
        u1r, clip1 = align(u1_code, cfg.ADC_W, cfg.clip)
        u2r, clip2 = align(u2_code, cfg.ADC_W, cfg.clip)
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
            # (the block's step exponent mu is 3 + HARM.harm_mu)
            mu = harmonic.MU_MIN + np.asarray(self._per_sample(cfg.harm_mu, n))
            phase_c = self.harm.run(phase, apply=self._per_sample(cfg.harm_apply, n),
                                    learn=learn, mu=mu if mu.ndim else int(mu),
                                    clear=clr, blocked=blk)
        else:
            phase_c = phase      # nothing learned from power-up: an empty table
        prod, pn, cosn, sinn = self.lut.nth(phase_c, cfg.interp)
        pa, pb = pulse(cosn, sinn, cfg.eps, cfg.SIN_W, *self.pulse_ab)
        count_ph, ovs, self.cnt_state = counter(phase_c, prod, cfg.interp, cfg.COUNT_W,
                                                state=self.cnt_state, hold=mon["hold"],
                                                coast=mon["coast"], line=mon["line"])
        # the x4 decoder of the pulses: E after each sample's pulses (edge t + EDGE_AT)
        steps, ill, self.edge_state = edge_steps(pa, pb, self.edge_state)
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
        # A/B pins and Z after each sample's output edge; the reference marks
        held = np.asarray(mon["hold"], bool) & (cfg.count_mode == 0)
        rmo = self.rm.run(t, count, np.asarray(prod, np.int64) >> 11, cfg.interp, held, ovs,
                          ref, cfg.count_mode, self.ab, pa, pb,
                          lost=np.asarray(mon["lost"], bool) & (cfg.count_mode == 0))
        a_pin, b_pin, ab_ovf, z_pin = rmo["a"], rmo["b"], rmo["ab_ovf"], rmo["z"]
        wrapm = 1 << cfg.COUNT_W
        count_raw = count
        count = ((count + rmo["off8"] + (wrapm >> 1)) % wrapm) - (wrapm >> 1)
        if cfg.ab_src:
            a_pin, b_pin, z_pin = rmo["ep_a"], rmo["ep_b"], rmo["ep_z"]
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
        est = self.est
        res = dict(jumps=list(est.jumps), count=count, a=a_pin, b=b_pin, fault=fault,
                   z=z_pin, ref_count=rmo["ref_count"], homed=rmo["homed"],
                   pos_valid=rmo["pos_valid"], abs_valid=rmo["abs_valid"],
                   abs_count=rmo["abs_count"],
                   ref_latches=self.rm.latches, ref_losses=self.rm.losses,
                   dc_errors=self.rm.dc.errors,
                   n_updates=est.n_updates, invalid_updates=est.n_invalid,
                   gain_held=est.n_gain_held,
                   sat=est.sat,           # the engine saturated a register (STATUS.sat)
                   illegal_count=self.ill_count)
        if trace:
            g, m1, m2, c1, c12, c2 = bund.T
            res.update({k: fr[k] for k in ("u1c", "u2c", "ax", "ay", "xn", "yn", "phase",
                                           "j", "base", "neg", "bin")})
            res.update(prod=prod, pn=pn, cosn=cosn, sinn=sinn, pa=pa, pb=pb, g=g, m1=m1,
                       m2=m2, c1=c1, c12=c12, c2=c2, phase_c=phase_c, harm=self.harm,
                       count_phase=count_ph, count_raw=count_raw, ill=ill, t=t,
                       travel=mon["travel"], ref_in=ref,
                       mon_hold=mon["hold"], mon_coast=mon["coast"], mon_lost=mon["lost"],
                       excl=mon["excl"], ref=mon["ref"],
                       loaded=flags[:, 2])
        return res

    def schedule_samples(self):
        """The estimator's programs since power-up as (kind, sample, g, commit): commit is
        the index of the first sample that sees the new coefficients (the number of
        samples fed so far if none has yet), None if the program did not commit."""
        t = np.concatenate(self.t_pieces) if self.t_pieces else np.zeros(0, np.int64)
        return [(kind, k, g, None if e is None else int(np.searchsorted(t, e, side="right")))
                for kind, k, g, e in self.est.sched]

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
        est = self.est
        out = {f: np.zeros(n, dtype=bool) for f in ("loss", "over", "stuck", "glitch",
                                                     "hold", "excl", "ref", "coast",
                                                     "lost")}
        out["line"] = np.zeros(n, dtype=np.int64)
        travel = np.zeros(n, dtype=np.int64)
        blk_lo = blk_hi = 0           # the fast path of samples [blk_lo, blk_hi) under one
        blk = None                    # bundle event (computed a block at a time)
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
                # the stuck spans of the bundle: the code step 2^sh of the gained code
                sh = 16 - cfg.ADC_W + cfg.code_step + int(bundle[0])
                blk = (fr["ax"].tolist(), fr["ay"].tolist(), fr["phase"].tolist(),
                       (not b_uncal) or b_loaded, fr["xn"].tolist(), fr["yn"].tolist(),
                       (stuck_span(bundle[3], sh), stuck_span(bundle[5], sh)),
                       (int(bundle[0]), int(bundle[3]), int(bundle[5])))
            j = k - blk_lo
            ph = blk[2][j]
            # ---- the monitor (every sample) ----
            s_prev = mon.travel()      # S after the previous sample (the gate's input)
            fl = mon.step(r1l[k], r2l[k], blk[0][j], blk[1][j], blk[4][j], blk[5][j], ph,
                          blk[3], clipl[k], mregs, blk[6], blk[7])
            for f in ("loss", "over", "stuck", "glitch", "hold", "excl", "coast", "line",
                      "lost"):
                out[f][k] = getattr(fl, f)
            excl = fl.excl
            out["ref"][k] = blk[3]
            travel[k] = mon.travel()
            # ---- the estimator: the held candidate's check on an edge <= t_k ----
            xdone = est.check_due(tk)
            if xdone is not None:
                # samples from the first one that sees the commit need their fast path
                blk_hi = min(blk_hi, int(np.searchsorted(t, xdone, side="right")))
            # ---- its arrival decision on t_k + 1 ----
            est.arrive(k0 + k, tk, r1l[k], r2l[k], amax[k], excl, s_prev)
        out["travel"] = travel
        return out


def run(u1_code, u2_code, cfg: Config = Config(), strobes=None, trace=False, ref=None):
    """Run the core on ADC codes (and the reference input: ref) from power-up; returns a
    dict of per-sample arrays, and the estimator's schedule (Core.schedule_samples)."""
    c = Core(cfg)
    res = c.feed(u1_code, u2_code, strobes=strobes, trace=trace, ref=ref)
    res["sched"] = c.schedule_samples()
    return res
