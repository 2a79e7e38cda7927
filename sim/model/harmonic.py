"""Bit-true model of rtl/harmonic.v: adaptive compensation of the fine phase's periodic
error (harmonic distortion of the encoder signals, which no ellipse correction removes).

The block sits between the fine phase (lut phase_o, u13, 8192 units per period) and the
counter. A table A of 64 entries (s8.8 phase units, bin b = phase[12:7], 128 units each)
is learned online, by LMS, from the error of a tracking observer while the stage moves
smoothly, and applied to every sample once it is significant (sig, below). The observer
runs in gears g = 0..11: in gear g it sees the mean phase of blocks of D = 2**g samples
(a tick ends each block), so that it can be slower than the error at any speed (below).
Every sample k, in order:

  clear   (clear[k]) A = 0, R = -8192, N = 0, sig = 0, a pending update is dropped.
  sig     sig = (N - |R + 8192|) > (2**14 if sig else 2**15), N and R as after the
          commits of the samples <= k - 3 (|x| here: x or ~x, one's complement): whether
          the table is significant (shown, below).
  commit  on the 9th sample after a learning candidate j, j's update is written:
          A[b_j] = H_j, R += H_j - A_old (R = sum(A) - 8192) and N += |H_j| - |A_old|
          (N = sum(|A|), one's complement).
  gear    k is a tick if 2**g samples have arrived since the last one (every sample in
          gear 0). On a tick the gear may change by the observer's request as sample
          k - 6 found it (up: locked, |M| < 2 units and |V| < 16 units/tick; down:
          |V| >= 64 units/tick; back to 0: the lock is lost), if k - 6 arrived after the
          last gear change. (The RTL's observer is five edges behind the arrival: the
          request is read from a ring of the last samples'.)
  corr    corr = (A[b] - (R >> 6)) >> 8   (s10 units; round(A[b] - mean(A)), half up);
          0 for samples arriving while the RAM is swept after a clear (blocked[k]).
          pc = (phase - corr) mod 8192;  phase_c = pc if apply and sig else phase (with
          show = 0, rtl/harmonic.v SHOW, sig is taken as 1: every table is shown). The
          correction is zero-mean over the table: it moves no position on average, and a
          learned constant cannot drift the count. The observer and the learning always
          use pc, so the table keeps learning while the correction is not shown.
  block   the block's first sample is its base; S sums pc - base (wrapped, s24) over the
          block; on the tick the block's mean, moved to the tick (its last sample), is
              meas = 32 base + (32 S >> g) + ((V >> 1) - (V >> (g + 1))) >> 8    u13.5
          ((D - 1) / 2 samples of travel at V per block; meas = 32 pc in gear 0).
  track   on ticks, a 2nd-order observer of meas; P u13.5 (wraps with the period), V
          s13.13 units per tick (wraps), C u11 (ticks):
              E = wrap18(meas - P)                    s13.5 prediction error
              P = P + (W >> 8) + round(E / 2**KA)     the next tick's prediction
              V = V' + round(E / 2**KA)               (V's LSB is 2^-13 units/tick)
              C = 0 if |E| >= 1024 units else min(C + 1, 2047)
          where a gear change converts V for the next block: up V' = 2 V (the next mean
          is W = 1.5 V ahead), down V' = V / 2 (W = 0.75 V), back to 0: V' = W = 0;
          else V' = W = V. After a change C is at most 1791 (256 ticks to settle before
          learning or shifting up again). The loop's gears from C before the update:
          C < 256: KA = 2 (P gain 1/4, V gain 2^-10, pull-in: speeds to ~1000 units/tick
          are acquired within ~3000 ticks), else KA = 7 (P gain 2^-7, V gain 2^-15:
          natural frequency 2^-7.5 rad/tick, damping 0.71). The steps are rounded (half
          up), so E has no mean at constant speed (with noise: without any, the fine step's
          dead band leaves up to 2 units). The prediction uses the velocity
          before this tick's update, which keeps the RTL's recurrence two adders deep.
  mean    Y = E * 4096 - M;  M = M + round(Y / 1024)   running mean of E (s13.17, 1024
          ticks; fine enough that its rounding leaves a dead band of 2^-8 units only):
          the observer's lag under acceleration, which is not a function of the phase;
          0 after a gear change (the lag measured afresh in the new gear).
  learn   candidates: the first tick after 10..17 samples (after a candidate,
          9 + (lfsr & 7) samples are skipped; 8-bit Galois LFSR x^8 + x^6 + x^5 + x^4 + 1,
          seed 0xE1, stepped per candidate). A candidate learns if learn, not blocked,
          C == 2047, VMIN <= |V| >> 13 < VMAX (|V| = V or ~V, one's complement; C, V and
          M before this tick's update), -256 <= E >> 5 < 256, and in gears above 0 also
          |M| < 2 units and |E| < 64 units:
              x = sat12(X - (R >> 7))      X = E - M (Y >> 12) in gear 0, E above; 1/32
              H = A[b] + (x >> (mu - 3 + s + n))   in 1/256 units: LMS step
                                   2^-(mu + s + n), mu 3..6, s = 0 in gear 0, 1 in gears
                                   1..3, 2 from gear 4, n the number of 2048, 4096 and
                                   8192 that the updates made since a clear have
                                   reached (0..3)
          and H is committed 9 samples later (not made if H would leave s16).
          The term in R anchors the table's common mode, which the correction ignores:
          without it rounding would random-walk the table into its limits, and what is
          left of the observer's lag after accelerations (M follows it with a delay) would
          shift it; with the gain 4 the shift is a quarter of the mean lag while learning.

Why the step halves at 2048, 4096 and 8192 updates: the LMS's misadjustment (the
table's own noise) is proportional to its step. With 64 bins, 2048 updates are 32 per
bin, where the step 2^-5 (the default mu 3 in gears 1..3, n = 1) is the running mean's
1/32; halving it each time the count doubles keeps the step at the running mean's until
2^-7, the mean of a bin's last ~128 updates, which then keeps following slow changes. A
clear (HARM.harm_clear) starts fast again.

Why gear 0 learns with twice the step of gears 1..3: gear 0 is where fast moves learn,
and there the harmonic error is left whole until the table is significant (below), so
the first millimetres of a move weigh: harmonic3 (1 % third harmonic, 10 mm/s) is at
1.011 x the floor with 2^-3 and 1.0145 with 2^-4 (model, make bench-accuracy's
scoring). In gears 1..3 (2 to 7 mm/s at 1 MS/s) a larger step lets a noisy table reach
the significance: noise2's (2 % noise at 2 mm/s) did with the doubled step in every gear.

Why sig (the table is shown only once it is significant): a table learned from signals
without harmonics holds only its own noise, and adding that to the count costs accuracy
(0.2 to 0.6 % of the floor on the harmonic-free scenarios of the accuracy suite at 2 to
5 mm/s, where learning runs in gears 1 and 2 and the observer's error is correlated over
many bins). The noise is smooth across neighbouring bins there (lag-1 correlation up to
0.9), so a smoothness test does not tell it from a harmonic; its size does: on the
accuracy suite the tables learned from noise keep (N - |R + 8192|) / (64 * 256), a bound
of their mean absolute deviation, at most 1.7 units (noise2, 2 % noise, early on;
s_curve 1.3, standstill 1.0, 0.6 or less elsewhere), the ones learned from the
scenarios' mixes of 2nd, 3rd and 5th harmonics (0.2 to 2 % each) reach 7 to 13 units.
The table is shown from 2 units (2**15) and hidden again at 1 unit or below (a
hysteresis: the switch does not chatter). A periodic error whose mean deviation stays
under 2 units (about 1 nm RMS on a 4 um scale: a harmonic of about 0.25 % of the
fundamental) is then not corrected. The statistic uses the mean |R + 8192| as a bound
for the common mode (the correction ignores it), and one's complement magnitudes (an XOR
in the RTL). It lags by three samples, so that the RTL forms it in three registers
clocked by the arrivals.

Why one candidate in 10..17 samples: the correction of sample k must not depend on the
strobe pattern, and at one sample per clock the update of sample k - 1 cannot reach it
(its error needs k - 1's corrected phase, the block, the observer: a long recurrence).
With candidates 10 or more samples apart, at most one update is in flight; it is
committed on the arrival of the 9th sample after it, whatever the clock gaps, and the
learning view is the table itself (no forwarding network, one block RAM). The dither
keeps the candidates from locking onto a few phases at speeds where 10 samples are a
whole fraction of a period. In gears >= 4 (16 samples per tick) nearly every tick is a
candidate, and the step is halved again: those ticks are averages of 16 or more samples,
and there are many per period.

Why the speed window (VMIN = 16, VMAX = 512 units per tick) and the gears: the LMS sees
E, the observer's error, i.e. the periodic error through the loop's sensitivity function
S(w) = -x^2 / (1 - x^2 + j sqrt(2) x), x = w / wn, wn = 2^-7.5 rad/tick. Its real part is
positive only for x > 1: below the observer's bandwidth the observer follows the error
and the update has the wrong sign. The slowest error component is the first harmonic of
the phase, w = 2 pi |v| / 8192 per tick: at |v| = 16 units/tick it is x = 2.2 (S's
phase 39 deg, the LMS converges; the 4th-harmonic error of a third signal harmonic is at
x = 8.9, phase 9 deg). The upper end keeps the fourth harmonic of the phase at or below a
quarter of the tick rate, far from Nyquist. A fixed loop at the sample rate would learn
only from 16 units/sample (7.8 mm/s on a 4 um scale at 1 MS/s) up. The gears keep the
speed per tick in the window at any speed from 16 / 2**11 units/sample up (one period in
~10^6 samples): the loop is the same in ticks, the block means lower the noise by
sqrt(D), and from gear 1 on a block spans at most 64 units (half a bin), so the table's
32 harmonics are not blurred. Decimation was chosen over a loop whose gains shrink with
the speed (the same dynamics per sample would need V and P some 22 bits wider and
barrel shifters on the loop's recurrence) and over the phase unwrapped over a window
(a fit per window is a multiplier per sample).

Why the lag gates: in a gear g the loop's bandwidth is 2**g times lower, so an
acceleration a leaves a lag of a D^2 2^15 units (hundreds of units at 0.5 mm/s per
10 ms in gear 4), and unlike at high speed a lag transient falls on a few bins. In
gears above 0 the table learns only while the mean error |M| < 2 units (no acceleration
over the last ~1024 ticks) and |E| < 64 units (none starting now), from E itself (M,
slow to follow a lag, would add a bias where the lag ends). Standstill (|V| < 16 units
per tick in the top gear), servo dither (no steady travel: M and V) and reversals learn
nothing; the table keeps being applied (sim/tests/test_harmonic_model.py measures them).
The lock gates (C, |E| < 256 units) keep the observer's pull-in out of the table.

Clear: the RTL sweeps the RAM to zero in 64 clocks; sweep_flags() turns the clear edges
and the samples' arrival edges into the per-sample flags `clear` (the table is empty
from this sample on) and `blocked` (arrived during the sweep: not corrected, not
learned from). The observer and M keep running.

Formats: A, H s8.8 phase units (+-128 units = +-0.1 rad; 1/256 unit = 1.9 pm on a 4 um
scale); R s23; corr s10 units; E, P, meas s13.5; S s24 units; V s13.13 units per tick;
M s13.17.
"""
import numpy as np

from .regs import SETTINGS

BINS_LOG2 = 6
BINS = 1 << BINS_LOG2
BIN_SHIFT = 13 - BINS_LOG2
D = 9              # a candidate's update is committed (applied) when sample k + D arrives
SKIP_MIN = 9       # candidates: the first tick after 10..17 samples (after a candidate,
                   # 9 + (lfsr & 7) samples are skipped)
LFSR_SEED = 0xE1   # 8-bit Galois LFSR, x^8 + x^6 + x^5 + x^4 + 1
PF = 5             # fraction bits of P and E (phase units)
VF = 13            # fraction bits of V (units/tick)
GAINS = ((256, 2, 10), (None, 7, 15))  # (C below, KA, KB): P gain 2^-KA, V gain 2^-KB
C_MAX = 2047       # ticks in track before learning (u11, saturating)
ELOST = 1024       # |E| >= ELOST units: the observer lost track (C = 0)
KM = 10            # running mean of E over 2^KM ticks
MF = 12            # extra fraction bits of M (its step is rounded: a dead band of
                   # 2^(KM - 1 - MF - PF) units)
ANCHOR = BINS_LOG2 - 2   # x -= R >> ANCHOR: the table's mean times 4
VMIN = 16          # learning speed window, units per tick: VMIN <= |V| < VMAX
VMAX = 512
GMAX = 11          # gears 0..11: the observer sees one sample in 2**g (a tick)
VUP = 16           # |V| < VUP units/tick (locked): one gear up (half the tick rate)
VDOWN = 64         # |V| >= VDOWN units/tick: one gear down
GDELAY = 6         # a tick's gear decision uses the observer's state as the sample
                   # GDELAY before it found it, if that sample arrived after the last
                   # change
SETTLE = 256      # a gear change: C back to at most C_MAX - SETTLE (settling ticks)
MQ = 2 << (PF + MF)   # gears >= 1 learn (and shift up) only while |M| < 2 units
EQUIET = 64        # gears >= 1 learn only while |E| < EQUIET units
ANNEAL = 2048      # the step halves at ANNEAL, 2 ANNEAL and 4 ANNEAL updates since a
                   # clear (ANNEALS halvings)
ANNEALS = 3
SIG_ON = 1 << 15   # the table is shown once sum|A| - |sum A| exceeds SIG_ON (2 units mean)
SIG_HYST = 1       # and hidden again when it falls to SIG_ON >> SIG_HYST or below
SIG_LAG = 3        # sig uses the table as after the commits of the samples <= k - SIG_LAG
GSLOW = 4          # the step's shift s: 0 in gear 0, 1 below GSLOW, 2 from GSLOW (nearly
                   # every tick a candidate)
ELOCK = 256        # learning only while |E| < ELOCK units
H_W = 16           # table entry s8.8
D_W = 12           # update clamp s12
MU_MIN, MU_MAX = 3, 6   # the LMS step is 2^-mu, mu = MU_MIN + HARM.harm_mu
MU_DEFAULT = MU_MIN + SETTINGS["harm_mu"].reset
SWEEP = 64         # clocks of a clear (one RAM word per clock)

P_W = 13 + PF
V_W = 13 + VF


def lfsr_step(v):
    return (v >> 1) ^ (0xB8 if v & 1 else 0)


def sweep_flags(arrivals, clear_edges):
    """Per-sample (clear, blocked) flags for Harmonic.run from the samples' arrival edges
    (the edge on which rtl/harmonic.v's valid_i is high) and the edges w on which clear_i
    is high: the tables are empty from the first sample arriving on an edge >= w, and the
    samples arriving on edges w .. w + 64 (the RAM sweep) are neither corrected nor
    learned from."""
    a = np.asarray(arrivals, dtype=np.int64)
    clear = np.zeros(len(a), bool)
    blocked = np.zeros(len(a), bool)
    for w in clear_edges:
        k = int(np.searchsorted(a, w, side="left"))
        if k < len(a):
            clear[k] = True
        blocked |= (a >= w) & (a <= w + SWEEP)
    return clear, blocked


class Harmonic:
    """State of the block; `run` processes a stream of samples and keeps the state, so a
    recording can be fed in pieces (register changes between pieces)."""

    def __init__(self, gears=GMAX, show=SIG_ON):
        if not 0 <= gears <= GMAX:
            raise ValueError(f"gears must be 0..{GMAX}")
        if not 0 <= show < 1 << 21:
            raise ValueError("show must be 0..2**21 - 1")
        self.gears = gears
        self.show = show             # rtl/harmonic.v SHOW: sig's threshold, 0 always shown
        self.A = [0] * BINS          # the table (RAM)
        self.R = -8192               # sum of A - 8192
        self.P = 0
        self.V = 0
        self.M = 0
        self.C = 0
        self.skip = 0                # samples to pass before the next candidate
        self.lfsr = LFSR_SEED
        self.cc = 0                  # arrivals until the pending update is committed
        self.pend = None             # (bin, new, old) of the last candidate, or None
        self.g = 0                   # gear: the observer updates on one sample in 2**g
        self.t = 0                   # samples until the next tick (tick when 0)
        self.hold = GDELAY + 1       # samples since the last gear change (saturating)
        self.flags = [0] * GDELAY    # the observer's gear request after the last samples
        self.gb = 0                  # the gear of the current block (its 2**gb samples)
        self.base = 0                # the block's first corrected phase
        self.S = 0                   # sum of the block's phases minus base (wrapped)
        self.first = True            # the next sample starts a block
        self.k = 0                   # samples seen
        self.learned = 0             # updates computed (for tests; the RTL counts them)
        self.nup = 0                 # updates since the last clear (saturating at
                                     # ANNEAL << (ANNEALS - 1))
        self.N = 0                   # sum(|A|), one's complement magnitudes
        self.sig = False             # the table is significant: shown
        self.stat = [0] * (SIG_LAG - 1)   # N - |R + 8192| after the last samples

    def run(self, phase, apply=1, learn=1, mu=MU_DEFAULT, clear=None, blocked=None,
            trace=False):
        """phase: u13 array. apply, learn, mu: scalars or per-sample arrays (apply as the
        RTL samples it for the sample's correction, learn and mu for its update). clear,
        blocked: None or boolean arrays (sweep_flags). Returns phase_c (and with trace, a
        dict of per-sample internals)."""
        phase = np.asarray(phase, dtype=np.int64)
        n = len(phase)

        def per_sample(v):
            return np.broadcast_to(np.asarray(v, dtype=np.int64), (n,)).tolist()

        apl = per_sample(apply)
        lrn = per_sample(learn)
        mus = per_sample(mu)
        if n and not MU_MIN <= min(mus) <= max(mus) <= MU_MAX:
            raise ValueError(f"mu must be {MU_MIN}..{MU_MAX}")
        clr = [False] * n if clear is None else np.asarray(clear, bool).tolist()
        blk = [False] * n if blocked is None else np.asarray(blocked, bool).tolist()
        ph = phase.tolist()
        out = [0] * n
        tr = None
        if trace:
            tr = {k: [0] * n for k in ("corr", "E", "V", "M", "C", "cand", "gate", "d",
                                       "h", "R", "g", "tick", "conv", "P", "gb", "sig",
                                       "N")}
        A, R, P, V, M, C = self.A, self.R, self.P, self.V, self.M, self.C
        skip, lfsr, cc, pend = self.skip, self.lfsr, self.cc, self.pend
        g, t, hold, flags = self.g, self.t, self.hold, list(self.flags)
        gb, base, S, first = self.gb, self.base, self.S, self.first
        learned = self.learned
        nup = self.nup
        N, sig, stat = self.N, self.sig, list(self.stat)
        nsat = ANNEAL << (ANNEALS - 1)
        show = self.show
        (c0, ka0, kb0), (_, ka1, kb1) = GAINS
        assert ka0 == kb0 - (VF - PF) and ka1 == kb1 - (VF - PF)   # dV = dP = E >> KA
        vsh = VF - PF
        pmask = (1 << P_W) - 1
        phalf = 1 << (P_W - 1)
        vmask = (1 << V_W) - 1
        vhalf = 1 << (V_W - 1)
        hmax, hmin = (1 << (H_W - 1)) - 1, -(1 << (H_W - 1))
        dmax, dmin = (1 << (D_W - 1)) - 1, -(1 << (D_W - 1))
        vlo, vhi = VMIN << VF, VMAX << VF
        elo, ehi = -(ELOCK << PF), ELOCK << PF
        lost_lo, lost_hi = -(ELOST << PF), ELOST << PF
        for i in range(n):
            if clr[i]:
                nup = 0
                A = [0] * BINS
                R = -8192
                N = 0
                sig = False
                stat = [0] * (SIG_LAG - 1)
                pend = None
            # whether the table is shown (the commits of samples <= k - 3)
            sr = R + 8192
            stat.append(N - (sr if sr >= 0 else ~sr))
            st = stat.pop(0)
            sig = st > (show >> SIG_HYST if sig else show)
            # commit the last candidate's update on the arrival of the 9th sample after it
            if cc == 1 and pend is not None:
                eb, ev, eo = pend
                A[eb] = ev
                R += ev - eo
                N += (ev if ev >= 0 else ~ev) - (eo if eo >= 0 else ~eo)
            # the tick schedule and the gear (on the sample's arrival)
            tick = t == 0
            conv = 0                     # the observer's V on this tick: 0 as it is,
            if tick:                     # 1 doubled, 2 halved, 3 zeroed
                req = flags[0] if hold > GDELAY else 0
                if req == 3 and g:
                    g, conv = 0, 3
                elif req == 1 and g < self.gears:
                    g, conv = g + 1, 1
                elif req == 2 and g:
                    g, conv = g - 1, 2
                if conv:
                    hold = 0
                t = (1 << g) - 1
            else:
                t -= 1
            hold = hold + 1 if hold <= GDELAY else GDELAY + 1
            cand = skip == 0 and tick
            if cand:
                skip = SKIP_MIN + (lfsr & 7)
                lfsr = lfsr_step(lfsr)
                cc = D
            else:
                if skip:
                    skip -= 1
                if cc:
                    cc -= 1
            p = ph[i]
            b = p >> BIN_SHIFT
            corr = 0 if blk[i] else (A[b] - (R >> 6)) >> 8
            pc = (p - corr) & 8191
            # the block's mean phase; the observer (on ticks)
            if first:
                base, S = pc, 0
            dd = (pc - base) & 8191
            S += dd - 8192 if dd >= 4096 else dd
            first = tick
            # the block's mean moved to the tick (its last sample): + V (D - 1) / (2 D)
            ext = ((V >> 1) - (V >> (gb + 1))) >> vsh
            e = ((base << PF) + ((S << PF) >> gb) + ext - P) & pmask
            if e >= phalf:
                e -= phalf << 1
            av = V if V >= 0 else ~V
            # the gear request as this sample finds the observer (read GDELAY samples later)
            flags.append(3 if C == 0 else 1 if C == C_MAX and -MQ < M < MQ and av < VUP << VF
                         else 2 if av >= VDOWN << VF else 0)
            del flags[0]
            gate = False
            dlt = hn = 0
            y = 0
            gw = gb
            if tick:
                win = (C == C_MAX and vlo <= av < vhi
                       and (gb == 0 or -MQ < M < MQ and -(EQUIET << PF) <= e < EQUIET << PF))
                gw = gb
                # the next block's mean is (D + D') / 2 samples after this one's
                w = V
                if conv == 1:
                    w = V + (V >> 1)
                    V = ((2 * V + vhalf) & vmask) - vhalf
                elif conv == 2:
                    w = V - (V >> 2)
                    V >>= 1
                elif conv == 3:
                    w = V = 0
                gb = g
                ka = ka0 if C < c0 else ka1
                de = (e + (1 << (ka - 1))) >> ka         # rounded: no bias in E's mean
                P = (P + (w >> vsh) + de) & pmask
                V = ((V + de + vhalf) & vmask) - vhalf
                C = 0 if not lost_lo <= e < lost_hi else C + 1 if C < C_MAX else C_MAX
                if conv and C > C_MAX - SETTLE:
                    C = C_MAX - SETTLE
                y = (e << MF) - M
                M += (y + (1 << (KM - 1))) >> KM         # rounded: no bias
                if conv:
                    M = 0                        # a new gear: the lag measured afresh
            if cand:
                pend = None
                if not blk[i] and lrn[i] and win and elo <= e < ehi:
                    x = ((y >> MF) if gw == 0 else e) - (R >> (ANCHOR + 8 - PF))
                    x = dmax if x > dmax else dmin if x < dmin else x
                    gsh = 0 if gw == 0 else 1 if gw < GSLOW else 2
                    dlt = x >> (mus[i] - (8 - PF) + gsh
                                + sum(nup >= ANNEAL << s for s in range(ANNEALS)))
                    hf = A[b]
                    hn = hf + dlt
                    if hmin <= hn <= hmax:       # an update that would leave s16 is not made
                        pend = (b, hn, hf)
                        gate = True
                        learned += 1
                        nup = min(nup + 1, nsat)
            out[i] = pc if apl[i] and (sig or not show) else p
            if trace:
                tr["corr"][i] = corr
                tr["E"][i] = e
                tr["V"][i] = V
                tr["M"][i] = M
                tr["C"][i] = C
                tr["cand"][i] = cand
                tr["gate"][i] = gate
                tr["d"][i] = dlt
                tr["h"][i] = hn
                tr["R"][i] = R
                tr["g"][i] = g
                tr["gb"][i] = gw if tick else gb
                tr["tick"][i] = tick
                tr["conv"][i] = conv
                tr["P"][i] = P
                tr["sig"][i] = sig
                tr["N"][i] = N
        self.A, self.R, self.P, self.V, self.M, self.C = A, R, P, V, M, C
        self.skip, self.lfsr, self.cc, self.pend = skip, lfsr, cc, pend
        self.g, self.t, self.hold, self.flags = g, t, hold, flags
        self.gb, self.base, self.S, self.first = gb, base, S, first
        self.k += n
        self.learned = learned
        self.nup = nup
        self.N, self.sig, self.stat = N, sig, stat
        res = np.asarray(out, dtype=np.int64)
        if trace:
            return res, {k: np.asarray(v, dtype=np.int64) for k, v in tr.items()}
        return res


def run(phase, apply=1, learn=1, mu=MU_DEFAULT, clear=None, blocked=None, trace=False,
        gears=GMAX):
    """One stream from power-up (all state zero). Returns (phase_c, state), with trace
    (phase_c, state, internals). (With learn off from power-up the table stays empty and
    phase_c = phase: sim.model.finequad_core skips the call then.)"""
    h = Harmonic(gears)
    r = h.run(phase, apply=apply, learn=learn, mu=mu, clear=clear, blocked=blocked,
              trace=trace)
    if trace:
        return r[0], h, r[1]
    return r, h
