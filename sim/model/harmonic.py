"""Bit-true model of rtl/harmonic.v: adaptive compensation of the fine phase's periodic
error (harmonic distortion of the encoder signals, which no ellipse correction removes).

The block sits between the fine phase (lut phase_o, u13, 8192 units per period) and the
counter. Every sample k, in order:

  bin   b = phase[12:7]                          64 bins of 128 units over one period
  corr  pc = (phase - corr) mod 8192,            corr = (64 A[b] - R) >> 14
        with R = sum(A) - 8192, i.e. corr = round(A[b] - mean(A)) in phase units (round
        half up). A is the applied table; the correction is zero-mean over the table, so
        it moves no position on average and a learned constant cannot drift the count.
        phase_c = pc if apply is on, else phase (the observer and the learning always
        use pc, so the table keeps learning while the correction is not shown).
  track a 2nd-order observer of pc (state P: u13.8, wraps with the period;
        V: s13.16 units/sample, wraps modulo one period per sample; C: u11 samples
        since the observer last lost track):
            E = wrap21(pc * 256 - P)             s13.8 prediction error
            P = P + (V >> 8) + (E >> KA)         the next sample's prediction
            V = V + E * 2^(8 - KB)               (V's LSB is 2^-16 units/sample)
            C = 0 if |E| >= 1024 units (E >> 18 not in {0, -1}) else min(C + 1, 2047)
        with gear-shifted gains from C before the update: C < 64: KA = 2, KB = 5 (pull-in,
        natural frequency 0.18 rad/sample); C < 512: KA = 4, KB = 10; else KA = 7,
        KB = 15 (tracking: natural frequency 2^-7.5 rad/sample, damping 0.71). The gears
        acquire any speed up to about 2000 units/sample from any state within ~600
        samples (the tracking loop alone would slip cycles for good beyond ~150).
        The velocity used in the prediction is the one before this sample's update, which
        keeps the RTL's recurrence two adders deep; with KB = 15 the loop is the textbook
        one to within a sample's delay on the integral path.
  mean  Y = E * 256 - M;  M = M + (Y >> 10)       running mean of E (s13.16, 1024 samples):
        the observer's lag under acceleration, which is not a function of the phase
  learn x = (Y >> 8) - (R >> 4)                  E minus its mean, minus 4x the table's
        mean (less 2 units: R holds the rounding constant). The last term anchors the
        table's common mode, which the correction ignores: without it rounding noise
        would random-walk the table into saturation, and what is left of the observer's
        lag after accelerations (M follows it with a delay) would shift it; with the
        gain 4 that shift is a quarter of the mean lag seen while learning.
        g = learn and C == 2047 and VMIN <= |V| >> 16 < VMAX and -256 <= E >> 8 < 256
        (C, V before this sample's update; |V| = V or ~V, one's complement): learning
        only after 2047 samples in track (the last ~1500 of them in the tracking gear)
        if g:  d = sat12(rnd(x, mu));  H[b] = sat16(H[b] + d)     (LMS, s8.8 entries)
  delay the applied table A follows the learning table H with a delay of D = 7 samples:
        sample k's correction sees the updates of samples <= k - 7. (The RTL commits
        sample j's update to its table RAM when sample j + 7 arrives; the update of sample
        k - 1 cannot reach sample k's correction at one sample per clock.) The LMS does
        not care about a delay of 7 samples; the RTL needs no long combinational path.

Formats: H and A entries s8.8 phase units (+-128 units = +-0.1 rad, 1/256 unit = 1.9 pm
on a 4 um scale); R s23; corr s10 units; mu 0..15 (default 6).

Why the speed window (VMIN = 16, VMAX = 512 units/sample): the LMS sees E, the observer's
error, i.e. the harmonic error through the loop's sensitivity function
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

Clear (register bit): the tables become zero (R = -8192) for the samples from the first one
that reaches the block after the clear (see `Harmonic.run`'s `clear`); updates of earlier
samples still in flight are dropped. The observer and M keep running.
"""
import numpy as np

BINS_LOG2 = 6
BINS = 1 << BINS_LOG2
BIN_SHIFT = 13 - BINS_LOG2
D = 7              # samples between an update and the correction that sees it
PF = 8             # fraction bits of P and E (phase units)
VF = 16            # fraction bits of V (units/sample)
GEARS = ((64, 2, 5), (512, 4, 10), (None, 7, 15))   # (C below, KA, KB): P gain 2^-KA,
                                                    # V gain 2^-KB (units/sample per unit)
C_MAX = 2047       # samples in track before learning (u11, saturating)
ELOST = 1024       # |E| >= ELOST units: the observer lost track (C = 0)
KM = 10            # running mean of E over 2^KM samples
MF = 8             # extra fraction bits of M
ANCHOR = BINS_LOG2 - 2   # x -= R >> ANCHOR: the table's mean times 4
VMIN = 16          # learning speed window, units/sample: VMIN <= |V| < VMAX
VMAX = 512
ELOCK = 256        # learning only while |E| < ELOCK units
H_W = 16           # table entry s8.8
HF = 8
D_W = 12           # update clamp s12
MU_DEFAULT = 6

P_W = 13 + PF      # 21
V_W = 13 + VF      # 29


class Harmonic:
    """State of the block; `run` processes a stream of samples and keeps the state, so a
    recording can be fed in pieces (register changes between pieces)."""

    def __init__(self):
        self.A = [0] * BINS          # applied table
        self.H = [0] * BINS          # learning table (A plus the last D - 1 updates)
        self.R = -8192               # sum of A - 8192
        self.P = 0
        self.V = 0
        self.M = 0
        self.C = 0
        self.ring = [None] * D       # updates of the last D samples, by sample index % D
        self.k = 0                   # samples seen
        self.learned = 0             # updates applied to H (for tests)

    def clear(self):
        self.A = [0] * BINS
        self.H = [0] * BINS
        self.R = -8192
        self.ring = [None] * D

    def run(self, phase, apply=1, learn=1, mu=MU_DEFAULT, clear=None, trace=False):
        """phase: u13 array. apply, learn, mu: scalars or per-sample arrays (apply as the
        RTL samples it for the sample's correction, learn and mu for its update). clear:
        None or a boolean array, True at the samples before which the tables are cleared.
        Returns phase_c (and with trace, a dict of per-sample internals)."""
        phase = np.asarray(phase, dtype=np.int64)
        n = len(phase)

        def per_sample(v):
            a = np.broadcast_to(np.asarray(v, dtype=np.int64), (n,))
            return a.tolist()

        apl = per_sample(apply)
        lrn = per_sample(learn)
        mus = per_sample(mu)
        clr = [False] * n if clear is None else np.asarray(clear, bool).tolist()
        ph = phase.tolist()
        out = [0] * n
        tr = None
        if trace:
            tr = {k: [0] * n for k in ("corr", "E", "V", "M", "C", "gate", "d", "h", "R")}
        A, H, ring = self.A, self.H, self.ring
        R, P, V, M, C = self.R, self.P, self.V, self.M, self.C
        (c0, ka0, kb0), (c1, ka1, kb1), (_, ka2, kb2) = GEARS
        assert VF - PF == 8 and kb0 <= 8 <= kb1 <= kb2
        lost_lo, lost_hi = -(ELOST << PF), ELOST << PF
        k0 = self.k
        learned = self.learned
        pmask = (1 << P_W) - 1
        phalf = 1 << (P_W - 1)
        vmask = (1 << V_W) - 1
        vhalf = 1 << (V_W - 1)
        hmax, hmin = (1 << (H_W - 1)) - 1, -(1 << (H_W - 1))
        dmax, dmin = (1 << (D_W - 1)) - 1, -(1 << (D_W - 1))
        vlo, vhi = VMIN << VF, VMAX << VF
        elo, ehi = -(ELOCK << PF), ELOCK << PF
        for i in range(n):
            if clr[i]:
                A = [0] * BINS
                H = [0] * BINS
                R = -8192
                ring = [None] * D
            p = ph[i]
            b = p >> BIN_SHIFT
            slot = (k0 + i) % D
            ent = ring[slot]                 # the update of sample k - D: commit it
            if ent is not None:
                eb, ev, ed = ent
                A[eb] = ev
                R += ed
            corr = ((A[b] << 6) - R) >> 14
            pc = (p - corr) & 8191
            # observer
            e = ((pc << PF) - P) & pmask
            if e >= phalf:
                e -= phalf << 1
            av = V if V >= 0 else ~V
            win = C == C_MAX and vlo <= av < vhi
            if C < c0:
                dp, dv = e >> ka0, e << (8 - kb0)
            elif C < c1:
                dp, dv = e >> ka1, e >> (kb1 - 8)
            else:
                dp, dv = e >> ka2, e >> (kb2 - 8)
            P = (P + (V >> (VF - PF)) + dp) & pmask
            V = ((V + dv + vhalf) & vmask) - vhalf
            C = 0 if not lost_lo <= e < lost_hi else C + 1 if C < C_MAX else C_MAX
            y = (e << MF) - M
            M += y >> KM
            ent = None
            dlt = hn = 0
            if lrn[i] and win and elo <= e < ehi:
                x = (y >> MF) - (R >> ANCHOR)
                m = mus[i]
                dlt = (x + ((1 << m) >> 1)) >> m
                dlt = dmax if dlt > dmax else dmin if dlt < dmin else dlt
                hf = H[b]
                hn = hf + dlt
                hn = hmax if hn > hmax else hmin if hn < hmin else hn
                H[b] = hn
                ent = (b, hn, hn - hf)
                learned += 1
            ring[slot] = ent
            out[i] = pc if apl[i] else p
            if trace:
                tr["corr"][i] = corr
                tr["E"][i] = e
                tr["V"][i] = V
                tr["M"][i] = M
                tr["C"][i] = C
                tr["gate"][i] = ent is not None
                tr["d"][i] = dlt
                tr["h"][i] = hn
                tr["R"][i] = R
        self.A, self.H, self.ring = A, H, ring
        self.R, self.P, self.V, self.M, self.C = R, P, V, M, C
        self.k = k0 + n
        self.learned = learned
        res = np.asarray(out, dtype=np.int64)
        if trace:
            return res, {k: np.asarray(v, dtype=np.int64) for k, v in tr.items()}
        return res


def run(phase, apply=1, learn=1, mu=MU_DEFAULT, clear=None, trace=False):
    """One stream from power-up (all state zero). Returns (phase_c, state), with trace
    (phase_c, state, internals). (With learn off from power-up the tables stay empty and
    phase_c = phase: sim.model.core skips the call then.)"""
    h = Harmonic()
    r = h.run(phase, apply=apply, learn=learn, mu=mu, clear=clear, trace=trace)
    if trace:
        return r[0], h, r[1]
    return r, h
