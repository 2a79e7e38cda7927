"""Bit-true model of rtl/monitor.v: signal faults, the counter's hold and coast, the travel.

Beyond the paper. The monitor watches every sample and decides whether its fine phase can
be trusted (the counter counts it, the estimator may take it), and measures the travel
along the scale that gates the estimator's updates.

Per sample k (registers as the RTL has them; "stage H" is the clock between the edges
t + 6 and t + 7, when the sample's fine phase is registered and the counter decides):

  stuck channel  run_c(k) = how many consecutive samples up to k have channel c's code
                 equal to the previous sample's (0 if it changed at k), saturating at 255.
                 snap_c = the OTHER channel's corrected value (s2.14, signed) when channel
                 c's code last changed, and span_c the stuck span (below) of the sample
                 at that change. Channel c is stuck when run_c(k) >= STUCK_N
                 (STUCK_N > 0) and the other channel has since moved out of [-span_c,
                 span_c - 1]. Measured on the other channel, not on the phase: with one
                 channel frozen the phase can stand nearly still while the stage moves.
                 A working channel's code stays unchanged only near its peak, while the
                 signal's excursion there stays within one code step q: over the arc
                 |theta| <= sqrt(2 q / A), in which the other channel (calibrated radius
                 R = 16384) moves by up to 2 R sqrt(2 q / A). With the correction
                 coefficient c (s4.12, u_cal = d c >> 13, so A = 2^27 / c in d's units)
                 that is 4 sqrt(q c), at any speed: a slow scan only lingers longer on
                 the same arc. q = 2^(16 - ADC_W + code_step + g) (the aligned code step
                 after the input gain 2^g; MONITOR.code_step for a converter coarser
                 than the port). The span is 1.5 times that bound (noise on the other
                 channel, the code bin's position against the peak), rounded up by a
                 2-bit mantissa of |c| (stuck_span()), and never below STUCK_SPAN_MIN
                 (1/8 of the calibrated radius, 6 sigma of 2 % noise between two
                 samples), capped at 32767. At 60 % and 30 % of full scale: 16 and
                 14 bits 2048 and 2048, 12 bits 2048 and 2880, 10 bits 4064 and 5760,
                 8 bits 8128 and 11520 (half and 0.7 of the radius: a coarse converter
                 cannot tell a dead channel from a live one sooner). The other channel
                 moves by a span s (as a fraction of the radius) within at most
                 max over a of a + acos(cos a - s) of motion, with 1 - cos a < s (worst:
                 it starts just below its peak, rises by less than s, and must fall by
                 s from its start): 70 degrees for STUCK_SPAN_MIN, 150 for half the
                 radius (worst_motion()), then STUCK_N samples; typically far sooner.
                 Until then the count follows a distorted phase; a channel that works
                 again before the check fires leaves the count right while the stage
                 moved well under half a period meanwhile (with more the distorted
                 phase may have wound the other way: README, Limits). Standstill
                 with toggling codes is never flagged. Once detected, the channel stays
                 stuck until its code changes (stk_c). A sample whose bundle's (g, c1,
                 c2) differ from the previous sample's (a hand-over or a load: the
                 calibrated units change) takes new snapshots of both channels and
                 detects nothing. Offsets and c12 are not in that key: a change of them
                 alone moves the other channel by about c dm, a small fraction of the
                 span for a calibration's updates. A change of MONITOR.code_step takes
                 effect at each channel's next code change.
  radius         r = max(|u1c|, |u2c|) + min >> 2 + min >> 3 (alpha-max-plus-beta-min,
                 alpha = 1, beta = 3/8: within -2.8 % .. +6.8 % of the true radius; u16,
                 s2.14 units: the calibrated circle is 16384). Only while the bundle is a
                 calibration (`ref`: the estimator has handed over, or one was loaded
                 through the registers); before that the nominal radius is unknown.
                 loss = ref and r < LOSS;  over = ref and r > OVER.
  glitch         the phase off its line: e = wrap13(phase - pred), pred the line's
                 prediction (the last accepted phase plus the line's velocity v, or
                 where a coast has taken the line; pf below)
                 (s13.3): the first difference while (re-)anchoring (chk < 2), then a
                 running mean of the accepted steps, v += (8 d - v) >> 3 (not after a
                 coast, where d spans several samples), taken before the sample (so
                 pred is one add). A two-point line let one outlier under the threshold
                 (23 degrees off) set the velocity: the next samples failed the test,
                 the line coasted off at the outlier's speed and met the phase again only
                 by wrapping round, with a new bogus velocity, for 137 825 samples of a
                 soak run, until a rail came and was counted; with the running mean the
                 outlier moves v by 1/8 of its error and the next sample passes.
                 glitch = 0 < K < 12, the line anchored (chk == 2: two samples accepted
                 since the last re-anchoring hold; coasts keep it) and e
                 outside [-2^K, 2^K - 1] (K = GLITCH_K, default 10: 1/8 of a period; a
                 power of two, so the RTL tests bits instead of comparing). A real stage
                 cannot change its phase velocity by 1/8 of a period per sample within
                 one sample (that is 5e5 m/s^2 at 1 MS/s on a 4 um scale); noise is far
                 below (2 % noise: sigma(e) ~ 64 units).
                 The line is kept as pf (u13.3, pred = pf >> 3): an accepted sample sets
                 pf = 8 phase + v (8 phase + 8 d while re-anchoring), a coast adds v, so
                 a long coast keeps the velocity's fraction.
                 A sample held by the glitch test alone coasts: the line goes on through
                 it (pf <- pf + v; ph_a and v stay) and the test stays armed,
                 so a
                 burst of interference or a channel on a rail (a broken line reads full
                 scale, whatever the angle) is held for as long as it lasts, and the
                 first good sample is tested against the line. Were the line re-anchored
                 on the next samples, as after a loss, a rail read half a period away
                 would be counted and counted back with a sign chosen by the wrap: a
                 whole period lost (seen in the soak). grun counts the coasts since two
                 samples in a row were accepted (an accept right after a coast keeps it:
                 a wrong line meets the phase now and then while it coasts, and a count
                 cleared by every accept never reached its limit, found in review); at
                 COAST_MAX (16) the next glitch of an unclipped sample re-anchors the
                 line (held without a line, chk <- 0): a line still that far off is the
                 wrong line; clipped samples coast on.
  weak, dead     loss = ref and r < LOSS only keeps the sample from the estimator (its
                 amplitude is no longer a calibration's); dead = ref and r < FLOOR
                 (COAST.floor) holds it. Between the two the phase is still good: a
                 signal at 5 % of its amplitude with 0.5 % noise gives it to 0.1 rad, and
                 the glitch test still guards it. FLOOR must sit above the noise (6
                 sigma of the per-channel noise in the radius's units: pure noise then
                 passes it about once in 10^8 samples), else noise would be counted.
  hold           dead or stuck or glitch, or a clipped code (at or near an ADC rail,
                 rtl/correct.v) with the radius over-range: the sample's phase is not
                 trusted. The count shows the last trusted sample's (rtl/counter.v). A
                 clipped code alone still counts: a slightly
                 overdriven channel clips around its own peak, where the other channel
                 carries the angle, and holding every such sample would let the count lag
                 by the clipped arc while the stage moves; a channel stuck on a rail (a
                 broken line) reads far from its true value, which throws the radius out
                 of range. Over-range alone does not hold either (a strong signal still
                 has a good phase). Clipped samples are never estimated (excl).
  coast          a held sample while the line is known (chk == 2: two samples accepted in a
                 row since it was last lost), other than a glitch past COAST_MAX
                 unclipped: the counter follows the line (its last phase <- `line`, the
                 line's position at this sample, and its period count by the line's
                 wraps), so it catches up when the phase is trusted again; right while
                 the line stays within half a period of the stage. The line moves on
                 (pf += v). A coast through dead, stuck or clip with over-range sets rc:
                 the next accepted sample is not tested against the line (after a long
                 coast it may be off by up to the uncertainty) and takes the count there.
                 One stuck channel (stk of exactly one; latched after up to 70 degrees
                 of motion plus STUCK_N samples, during which the other channel's
                 distorted phase was accepted): on the latch's first sample the line
                 restarts from the channel's shadow line (sl_c: the line coasted at the
                 velocity sv_c since the channel's code last changed) with that
                 velocity, clear of the distorted samples. If that shadow line and the
                 line (which followed the distorted phase) have been a quarter period
                 or more apart on any sample since the change (parted: wrap16(sl_c -
                 pf) outside [-2^14, 2^14 - 1], in u13.3), the count may have followed
                 the distorted phase across a period boundary, which the restart cannot
                 repair: the travel is lost (unc <- 2^23). While the two stay within a
                 quarter period the restart's step is under half a period, so it takes
                 no wrong wrap. After that, while the signal
                 is not dead, each sign change of the working channel re-anchors it to
                 the crossing nearest the line (channel 2's zero crossings lie at phase 0
                 and 4096, channel 1's at 2048 and 6144: the nearest is right while the
                 line is within a quarter period, whatever the direction) and clears the
                 uncertainty. The working channel's sign is the corrected one, whose
                 zero crossing a stuck channel 1 shifts through c12 by a few hundredths
                 of a period at most.
  uncertainty    unc (u24, 2^-12 phase units): 0 on an accepted sample; each coasted
                 sample adds w and then w grows by coast_acc (COAST.coast_acc, the
                 machine's largest acceleration in 2^-12 units per sample^2: a coast of
                 k samples adds coast_acc k^2 / 2). w starts, on each accepted sample,
                 at (mdev + 1) / 8 units per sample, mdev the running mean of |8 d - v|
                 (gain 1/16; the velocity's error after the 1/8 running mean is about
                 0.26 sigma of the step, mean |8 d - v| / 8 about 0.83 sigma: about 3
                 sigma of the velocity, plus its 1/8-unit resolution). unc saturates at
                 2^23 (a quarter period): lost, and pos_valid falls (rtl/refmark.v).
                 A hold without a line sets it there at once.
  excl           hold, or loss, or over-range while it has lasted fewer than OVER_PERSIST
                 samples: the estimator does not take the sample. A persistent
                 over-range (the amplitude really grew) is let in again, so the estimator
                 can follow it (its jump detector fires and it re-fits; the next hand-over
                 moves the nominal radius, and the flag clears).
  accepted       not hold: ph_a <- phase, pf and v as above; chk <- min(chk + 1, 2);
                 grun <- 0 (if the sample before was accepted); unc <- 0;
                 S += ((U << 5) - S) >>> 5 (u20.5 smoothed travel, wraps; the difference
                 is taken as s25; U as it was before this sample: the two sums run side
                 by side in the RTL), U += wrap13(phase - ph_a) (u20 unwrapped phase,
                 wraps). Coasting (above): the line moves on, grun <- min(grun + 1,
                 COAST_MAX) on a glitch coast. Otherwise held (no line): chk <- 0,
                 grun <- 0, the line is lost (unc <- 2^23).
  shadow lines   per channel, every sample: a code change sets (sl_c, sv_c) to the line
                 and velocity after the sample and clears parted; otherwise sl_c += sv_c
                 and parted is kept, or set if sl_c and pf (both before the sample)
                 are a quarter period or more apart.
  over run       orun <- over ? min(orun + 1, OVER_PERSIST) : 0 (every sample).

The estimator gates its updates by S (rtl/estimator.v): the travel smoothed over 32
samples moves by less than 1/4 unit per sample at standstill even with 2 % noise, so
noise alone no longer passes the gate (the raw phase did, about one sample in 12), while
creep and motion pass it after every `gate` units of travel, at any speed.
All widths wrap or saturate as stated: nothing overflows (sim/formal/monitor.sby).

Without the checks (OPT_MONITOR = 0, rtl/monitor.v: a small device): loss, over, stuck
and glitch are never flagged, no sample is held, excl = clip, and every sample moves the
travel (U, S) as an accepted one does.
"""
import math
from dataclasses import dataclass

from .fixed import wrap
from .regs import SETTINGS

STUCK_SPAN_MIN = 2048    # s2.14: 1/8 of the calibrated radius, the least stuck span
STUCK_SPAN_MAX = 32767   # u15: the largest (the other channel never moves further)
# 16 x 6 sqrt((5 + m) / 4 x 2^o), rounded up, for o = E & 1 and m = the 2 bits below
# |c|'s leading one: the span's mantissa (stuck_span())
SPAN_K = tuple(math.ceil(16 * 6 * math.sqrt((5 + m) / 4 * 2 ** o))
               for o in (0, 1) for m in range(4))
OVER_PERSIST = 4095      # samples of over-range before it is let in to the estimator
COAST_MAX = 16           # glitches coasted in a row before an unclipped sample re-anchors
V_FRAC = 3               # fraction bits of the line's velocity v (s13.3) and its position
UNC_Q = 1 << 23          # a quarter period (2048 units) in 2^-12 units: the travel is lost
UNC_FRAC = 12            # fraction bits of the coast's uncertainty and its growth
PART_SH = 14             # a shadow line parted from the line: a quarter period (2^14 in
                         # u13.3) or more apart
MDEV_FRAC = 4            # fraction bits of the mean |8 d - v| (above the 1/8 units)
V_SH = 3                 # v follows the phase step with a time constant of 2^V_SH samples
S_FRAC = 5               # fraction bits of the smoothed travel S (time constant 32)
U_W = 20                 # unwrapped phase width (wraps)
S_W = U_W + S_FRAC


def wrap13(v):
    return ((v + 4096) & 8191) - 4096


def stuck_span(c, shift):
    """The stuck span (u15, s2.14 units) of a channel with correction coefficient c (s4.12)
    whose code step is 2^shift LSBs of the aligned, gained code d: an upper bound of
    6 sqrt(2^shift |c|) (1.5 times the other channel's excursion while a working channel's
    code stays unchanged at its peak), clamped to [STUCK_SPAN_MIN, STUCK_SPAN_MAX]. With
    |c| in [2^e (4 + m) / 4, 2^e (5 + m) / 4) and E = e + shift: SPAN_K[E & 1][m]
    2^(E >> 1) / 16, exact wherever it reaches STUCK_SPAN_MIN (E >> 1 >= 4: below, it is
    at most 192 x 8 / 16). rtl/monitor.v computes the same in three stages."""
    a = abs(int(c))
    if a == 0:
        return STUCK_SPAN_MIN
    e = a.bit_length() - 1
    m = ((a << 2) >> e) & 3
    big = e + shift
    t = (SPAN_K[(big & 1) * 4 + m] << (big >> 1)) >> 4
    return min(max(t, STUCK_SPAN_MIN), STUCK_SPAN_MAX)


def worst_motion(s):
    """The most motion (rad) in which the other channel of a dead one moves by s (a
    fraction of the radius) from the snapshot: max over a of a + acos(cos a - s), where
    the other channel starts a before its peak and rises by 1 - cos a < s."""
    a_max = math.acos(max(-1.0, 1.0 - s))
    return max(a + math.acos(max(-1.0, math.cos(a) - s))
               for a in (a_max * i / 4096 for i in range(4096)))


def _parted(x):
    """A shadow line x = sl - pf (u13.3, wraps) off the line by 2^PART_SH or more."""
    return not -(1 << PART_SH) <= wrap(x, 16) < (1 << PART_SH)


def radius(ax, ay):
    """alpha-max-plus-beta-min radius estimate of rtl/monitor.v (u16)."""
    mx, mn = (ax, ay) if ay <= ax else (ay, ax)
    return mx + (mn >> 2) + (mn >> 3)


@dataclass
class Flags:
    """One sample's verdict (Monitor.step()): the fault flags, whether the counter takes
    its phase (not hold), whether the estimator takes it (not excl), and for a held
    sample whether the count follows the line (coast: the counter's last phase becomes
    `line`, the line's position at this sample, u13) and whether the travel during the
    fault is lost (the coast's uncertainty reached a quarter period)."""
    loss: bool = False
    over: bool = False
    stuck: bool = False
    glitch: bool = False
    hold: bool = False
    excl: bool = False
    coast: bool = False
    line: int = 0
    lost: bool = False


@dataclass
class MonitorRegs:
    """Run-time settings of the monitor: the fields of RADIUS and MONITOR
    (rtl/regs/finequad.rdl), defaults their reset values."""
    loss: int = SETTINGS["loss"].reset       # radius (s2.14) below which the signal is lost
    over: int = SETTINGS["over"].reset       # radius above which it is over-range
    glitch_k: int = SETTINGS["glitch_k"].reset   # max |phase acceleration| 2^K (0: off)
    stuck_n: int = SETTINGS["stuck_n"].reset     # samples of an unchanged code (0: off)
    floor: int = SETTINGS["floor"].reset     # radius below which the phase is not trusted
    coast_acc: int = SETTINGS["coast_acc"].reset  # u0.12 the machine's |acceleration|


class Monitor:
    """State of rtl/monitor.v from reset; step() runs one sample."""

    def __init__(self, enabled=True):
        self.enabled = enabled    # OPT_MONITOR: the fault checks are built
        self.prev = (0, 0)        # the previous sample's aligned codes
        self.run = [0, 0]         # consecutive unchanged codes per channel
        self.snap = [0, 0]        # s2.14: the other channel when this one last changed
        self.span = [STUCK_SPAN_MIN] * 2   # u15: the sample's stuck span at that change
        self.bkey = (0, 0, 0)     # (g, c1, c2) of the previous sample's bundle
        self.stk = [False, False]  # channel detected stuck (until its code changes)
        self.ph_a = 0             # last accepted phase
        self.pf = 0               # u13.3 the line: the prediction of the next phase
        self.rc = False           # a coast through dead, stuck or a rail: the next
                                  # accepted sample is not tested against the line
        self.unc = 0              # u24 the coast's uncertainty, 2^-12 units (UNC_Q: lost)
        self.w = 0                # u26 its growth per coasted sample, 2^-12 units
        self.mdev = 0             # u20 mean |8 d - v| of accepted steps, 2^-7 units
        self.sl = [0, 0]          # u13.3 per channel: the line coasted since the channel's
        self.sv = [0, 0]          # code last changed, and the velocity it coasts with
        self.part = [False, False]    # the shadow line has parted from the line
        self.pstk = [False, False]    # the channels' stuck latches of the sample before
        self.psgn = (False, False)    # the signs (xn, yn) of the sample before
        self.v = 0                # s13.3 the line's velocity (smoothed phase step)
        self.chk = 0              # accepted samples in a row, 0..2
        self.grun = 0             # glitches coasted since two samples in a row were accepted
        self.acc = False          # the sample before was accepted
        self.u = 0                # u20 unwrapped phase of the accepted samples
        self.s = 0                # u20.5 smoothed travel
        self.orun = 0             # over-range samples in a row

    def travel(self):
        """Integer part of S (u20), what the estimator's gate compares."""
        return self.s >> S_FRAC

    def step(self, r1, r2, ax, ay, xn, yn, phase, ref, clip, regs: MonitorRegs,
             spans=(STUCK_SPAN_MIN, STUCK_SPAN_MIN), bkey=(0, 0, 0)):
        """One sample: aligned codes r1, r2 (s1.15), magnitudes ax, ay (u15) and signs
        xn, yn of the corrected signals, fine phase (u13, uncorrected), ref (the bundle
        is a calibration), clip (a code at or near a rail), the stuck spans of its bundle
        (stuck_span() of c1 and c2) and the bundle's (g, c1, c2). Returns a Flags."""
        if not self.enabled:
            self._travel(wrap13(phase - self.ph_a))
            self.ph_a = phase
            return Flags(excl=bool(clip))
        # stuck channel (codes compared with the previous sample's)
        other = (-ay if yn else ay, -ax if xn else ax)     # the other channel, signed
        stuck = False
        changed = (r1 != self.prev[0], r2 != self.prev[1])
        rebase = tuple(bkey) != self.bkey     # a new bundle: new units, new snapshots
        self.bkey = tuple(bkey)
        for c in (0, 1):
            self.run[c] = 0 if changed[c] else min(self.run[c] + 1, 255)
            x = other[c] - self.snap[c]
            far = (x >= self.span[c] or x < -self.span[c]) and not rebase
            det = bool(regs.stuck_n) and self.run[c] >= regs.stuck_n and far
            self.stk[c] = (self.stk[c] or det) and not changed[c]
            stuck = stuck or self.stk[c]
            if changed[c] or rebase:
                self.snap[c] = other[c]
                self.span[c] = spans[c]
        self.prev = (r1, r2)
        # radius
        r = radius(ax, ay)
        loss = bool(ref) and r < regs.loss
        dead = bool(ref) and r < regs.floor
        over = bool(ref) and r > regs.over
        # glitch: the phase against the line's prediction
        pred = self.pf >> V_FRAC
        e = wrap13(phase - pred)
        k = regs.glitch_k
        glitch = (0 < k < 12 and self.chk >= 2 and not self.rc
                  and not (-(1 << k) <= e < (1 << k)))
        early = dead or stuck or (bool(clip) and over)
        hold = early or glitch
        gcoast = glitch and not early and not (self.grun == COAST_MAX and not clip)
        coast = hold and self.chk == 2 and (early or gcoast)
        excl = hold or loss or bool(clip) or (over and self.orun < OVER_PERSIST)
        # registered at t + 7
        self.orun = min(self.orun + 1, OVER_PERSIST) if over else 0
        # one stuck channel: the working channel's zero crossings, and the line coasted
        # since the stuck one last changed
        one = self.stk[0] != self.stk[1]
        c_st = 0 if self.stk[0] else 1
        rise = one and not self.pstk[c_st]
        sgn = (xn, yn)
        anchor = coast and one and not dead and sgn[1 - c_st] != self.psgn[1 - c_st]
        self.pstk = list(self.stk)
        self.psgn = sgn
        pf0 = self.pf
        # the shadow lines against the line (both as after the sample before): parted
        # since the channel's code last changed
        part = [self.part[c] or _parted(self.sl[c] - self.pf) for c in (0, 1)]
        if not hold:
            # the growth of a coast from here: the velocity's spread, before this sample
            self.w = ((self.mdev >> MDEV_FRAC) + 1) << (UNC_FRAC - V_FRAC)
            d = wrap13(phase - self.ph_a)
            if self.chk < 2:              # (re-)anchoring: the first difference
                self.v = d << V_FRAC
                self.pf = ((phase << V_FRAC) + self.v) & 0xFFFF
            else:                         # the line's velocity before this sample
                self.pf = ((phase << V_FRAC) + self.v) & 0xFFFF
                if self.acc:              # (after a coast d spans several samples)
                    dv = (d << V_FRAC) - self.v
                    self.v += dv >> V_SH
                    self.mdev += ((abs(dv) << MDEV_FRAC) - self.mdev) >> 4
            self.ph_a = phase
            self.chk = min(self.chk + 1, 2)
            self.rc = False
            self._travel(d)
            if self.acc:                  # two in a row: the line holds
                self.grun = 0
            self.acc = True
            self.unc = 0
        elif coast:
            if rise:                      # the line as if it coasted since the change
                self.pf = (self.sl[c_st] + self.sv[c_st]) & 0xFFFF
                self.v = self.sv[c_st]
            elif anchor:                  # the crossing nearest the line
                cand = ((pred + 2048) & 4096) if c_st == 0 else ((pred & 4096) | 2048)
                self.pf = ((cand << V_FRAC) + self.v) & 0xFFFF
            else:
                self.pf = (self.pf + self.v) & 0xFFFF
            if rise and part[c_st]:       # the count may have followed the distorted
                self.unc = UNC_Q          # phase across a period boundary
            elif anchor and not rise:
                self.unc = 0
            else:
                self.unc = min(self.unc + self.w, UNC_Q)
            if self.w < UNC_Q:
                self.w += regs.coast_acc
            if early:
                self.rc = True
            else:
                self.grun = min(self.grun + 1, COAST_MAX)
            self.acc = False
        else:                             # no line to coast along: the travel is lost
            self.chk = 0
            self.grun = 0
            self.acc = False
            self.rc = False
            self.unc = UNC_Q
        for c in (0, 1):                  # the shadow lines (per channel)
            self.part[c] = part[c] and not changed[c]
            if changed[c]:
                self.sl[c], self.sv[c] = self.pf, self.v
            else:
                self.sl[c] = (self.sl[c] + self.sv[c]) & 0xFFFF
        return Flags(loss, over, stuck, glitch, hold, excl, coast, pf0 >> V_FRAC,
                     self.unc >= UNC_Q)

    def _travel(self, d):
        """An accepted sample's step d (s13) into U and S (S from U before the step)."""
        diff = ((self.u << S_FRAC) - self.s) & ((1 << S_W) - 1)
        if diff >> (S_W - 1):
            diff -= 1 << S_W
        self.s = (self.s + (diff >> S_FRAC)) & ((1 << S_W) - 1)
        self.u = (self.u + d) & ((1 << U_W) - 1)
