"""Bit-true model of rtl/harmonic.v: adaptive compensation of the fine phase's periodic
error (harmonic distortion of the encoder signals, which no ellipse correction removes).

The block sits between the fine phase (lut phase_o, u13, 8192 units per period) and the
counter. A table A of 64 entries (s8.8 phase units, bin b = phase[12:7], 128 units each)
is applied to every sample and learned online, by LMS, from the error of a tracking
observer while the stage moves smoothly. Every sample k, in order:

  clear   (clear[k]) A = 0, R = -8192, a pending update is dropped.
  commit  on the 7th sample after a learning candidate j, j's update is written:
          A[b_j] = H_j and R += H_j - A_old (R = sum(A) - 8192).
  corr    corr = (A[b] - (R >> 6)) >> 8   (s10 units; round(A[b] - mean(A)), half up);
          0 for samples arriving while the RAM is swept after a clear (blocked[k]).
          pc = (phase - corr) mod 8192;  phase_c = pc if apply else phase. The correction
          is zero-mean over the table: it moves no position on average, and a learned
          constant cannot drift the count. The observer and the learning always use pc,
          so the table keeps learning while the correction is not shown.
  track   2nd-order observer of pc; P u13.5 (wraps with the period), V s13.13
          units/sample (wraps modulo one period per sample), C u11:
              E = wrap18(pc * 32 - P)                 s13.5 prediction error
              P = P + (V >> 8) + (E >> KA)            the next sample's prediction
              V = V + (E >> KA)                       (V's LSB is 2^-13 units/sample)
              C = 0 if |E| >= 1024 units else min(C + 1, 2047)
          gears from C before the update: C < 256: KA = 2 (P gain 1/4, V gain 2^-10 per
          sample per unit, pull-in: speeds to ~1000 units/sample are acquired within
          ~3000 samples), else KA = 7 (P gain 2^-7, V gain 2^-15: natural frequency
          2^-7.5 rad/sample, damping 0.71). The prediction uses the velocity before this
          sample's update, which keeps the RTL's recurrence two adders deep; with these
          gains the loop is the textbook one to within a sample's delay on the integral.
  mean    Y = E * 4 - M;  M = M + (Y >> 10)      running mean of E (s13.7, 1024 samples):
          the observer's lag under acceleration, which is not a function of the phase.
  learn   candidates: one sample in 8..15 (after a candidate, 7 + (lfsr & 7) samples are
          skipped; 8-bit Galois LFSR x^8 + x^6 + x^5 + x^4 + 1, seed 0xE1, stepped per
          candidate). A candidate learns if learn, not blocked, C == 2047, VMIN <= |V| >> 13
          < VMAX (|V| = V or ~V, one's complement; C and V before this sample's update)
          and -256 <= E >> 5 < 256:
              x = sat12((Y >> 2) - (R >> 7))    E minus its mean minus 4 x mean(A), 1/32
              H = A[b] + (x >> (mu - 3))         in 1/256 units: LMS step 2^-mu, mu 3..6
          and H is committed 7 samples later (not made if H would leave s16).
          The term in R anchors the table's common mode, which the correction ignores:
          without it rounding would random-walk the table into its limits, and what is
          left of the observer's lag after accelerations (M follows it with a delay) would
          shift it; with the gain 4 the shift is a quarter of the mean lag while learning.

Why one candidate in 8..15 samples: the correction of sample k must not depend on the
strobe pattern, and at one sample per clock the update of sample k - 1 cannot reach it
(its error needs k - 1's corrected phase, the observer, the mean: a long recurrence). With
candidates 8 or more samples apart, at most one update is in flight; it is committed on
the arrival of the 7th sample after it, whatever the clock gaps, and the learning view is
the table itself (no forwarding network, one block RAM, a few hundred LUTs: the device is
nearly full). The dither keeps the candidates from locking onto a few phases at speeds
where 8 samples are a whole fraction of a period. The price is learning from ~1/11.5 of
the samples: harmonic3 converges within ~20 000 samples of motion at mu = 4.

Why the speed window (VMIN = 16, VMAX = 512 units/sample): the LMS sees E, the observer's
error, i.e. the periodic error through the loop's sensitivity function
S(w) = -x^2 / (1 - x^2 + j sqrt(2) x), x = w / wn, wn = 2^-7.5 rad/sample. Its real part is
positive only for x > 1: below the observer's bandwidth the observer follows the error
and the update has the wrong sign. The slowest error component is the first harmonic of
the phase, w = 2 pi |v| / 8192: at |v| = 16 it is x = 2.2 (S's phase 39 deg, the LMS
converges; the 4th-harmonic error of a third signal harmonic is at x = 8.9, phase 9
deg). The upper end keeps the fourth harmonic of the phase at or below a quarter of the
sample rate (4 * 512 / 8192 = 1/4), far from Nyquist and from speeds where a harmonic
aliases onto the observer's bandwidth. Standstill, creep and reversals (|V| < 16) learn
nothing; the table keeps being applied. The lock gates (C, |E| < 256 units) keep the
observer's pull-in after power-up or an overspeed out of the table.

Clear: the RTL sweeps the RAM to zero in 64 clocks; sweep_flags() turns the clear edges
and the samples' arrival edges into the per-sample flags `clear` (the table is empty
from this sample on) and `blocked` (arrived during the sweep: not corrected, not
learned from). The observer and M keep running.

Formats: A, H s8.8 phase units (+-128 units = +-0.1 rad; 1/256 unit = 1.9 pm on a 4 um
scale); R s23; corr s10 units; E, P s13.5; V s13.13; M s13.7.
"""
import numpy as np

from .regs import SETTINGS

BINS_LOG2 = 6
BINS = 1 << BINS_LOG2
BIN_SHIFT = 13 - BINS_LOG2
D = 7              # a candidate's update is committed (applied) when sample k + D arrives
SKIP_MIN = 7       # candidates: one sample in 8..15 (after one, 7 + (lfsr & 7) skipped)
LFSR_SEED = 0xE1   # 8-bit Galois LFSR, x^8 + x^6 + x^5 + x^4 + 1
PF = 5             # fraction bits of P and E (phase units)
VF = 13            # fraction bits of V (units/sample)
GEARS = ((256, 2, 10), (None, 7, 15))  # (C below, KA, KB): P gain 2^-KA, V gain 2^-KB
C_MAX = 2047       # samples in track before learning (u11, saturating)
ELOST = 1024       # |E| >= ELOST units: the observer lost track (C = 0)
KM = 10            # running mean of E over 2^KM samples
MF = 2             # extra fraction bits of M
ANCHOR = BINS_LOG2 - 2   # x -= R >> ANCHOR: the table's mean times 4
VMIN = 16          # learning speed window, units/sample: VMIN <= |V| < VMAX
VMAX = 512
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

    def __init__(self):
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
        self.k = 0                   # samples seen
        self.learned = 0             # updates computed (for tests; the RTL counts them)

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
                                       "h", "R")}
        A, R, P, V, M, C = self.A, self.R, self.P, self.V, self.M, self.C
        skip, lfsr, cc, pend = self.skip, self.lfsr, self.cc, self.pend
        learned = self.learned
        (c0, ka0, kb0), (_, ka1, kb1) = GEARS
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
                A = [0] * BINS
                R = -8192
                pend = None
            # commit the last candidate's update on the arrival of the 7th sample after it
            if cc == 1 and pend is not None:
                eb, ev, eo = pend
                A[eb] = ev
                R += ev - eo
            cand = skip == 0
            if cand:
                skip = SKIP_MIN + (lfsr & 7)
                lfsr = lfsr_step(lfsr)
                cc = D
            else:
                skip -= 1
                if cc:
                    cc -= 1
            p = ph[i]
            b = p >> BIN_SHIFT
            corr = 0 if blk[i] else (A[b] - (R >> 6)) >> 8
            pc = (p - corr) & 8191
            # observer
            e = ((pc << PF) - P) & pmask
            if e >= phalf:
                e -= phalf << 1
            av = V if V >= 0 else ~V
            win = C == C_MAX and vlo <= av < vhi
            de = e >> (ka0 if C < c0 else ka1)
            P = (P + (V >> vsh) + de) & pmask
            V = ((V + de + vhalf) & vmask) - vhalf
            C = 0 if not lost_lo <= e < lost_hi else C + 1 if C < C_MAX else C_MAX
            y = (e << MF) - M
            M += y >> KM
            gate = False
            dlt = hn = 0
            if cand:
                pend = None
                if not blk[i] and lrn[i] and win and elo <= e < ehi:
                    x = (y >> MF) - (R >> (ANCHOR + 8 - PF))
                    x = dmax if x > dmax else dmin if x < dmin else x
                    dlt = x >> (mus[i] - (8 - PF))
                    hf = A[b]
                    hn = hf + dlt
                    if hmin <= hn <= hmax:       # an update that would leave s16 is not made
                        pend = (b, hn, hf)
                        gate = True
                        learned += 1
            out[i] = pc if apl[i] else p
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
        self.A, self.R, self.P, self.V, self.M, self.C = A, R, P, V, M, C
        self.skip, self.lfsr, self.cc, self.pend = skip, lfsr, cc, pend
        self.k += n
        self.learned = learned
        res = np.asarray(out, dtype=np.int64)
        if trace:
            return res, {k: np.asarray(v, dtype=np.int64) for k, v in tr.items()}
        return res


def run(phase, apply=1, learn=1, mu=MU_DEFAULT, clear=None, blocked=None, trace=False):
    """One stream from power-up (all state zero). Returns (phase_c, state), with trace
    (phase_c, state, internals). (With learn off from power-up the table stays empty and
    phase_c = phase: sim.model.finequad_core skips the call then.)"""
    h = Harmonic()
    r = h.run(phase, apply=apply, learn=learn, mu=mu, clear=clear, blocked=blocked,
              trace=trace)
    if trace:
        return r[0], h, r[1]
    return r, h
