"""Bit-true model of rtl/counter.v: the phase-mode count (s COUNT_W, 4 n counts per signal
period) and the edge mode's x4 decoder of the Eq. 12 pulses.
"""
import numpy as np

I64 = np.int64

QUAD = {(1, 1): 0, (0, 1): 1, (0, 0): 2, (1, 0): 3}


def counter(phase, prod, n, count_w=32, state=None, hold=None, coast=None, line=None):
    """Phase-mode count (rtl/counter.v): count = B + (prod >> 11), B = 4 n W stepping by
    -4 n / +4 n when the phase wraps backwards / forwards (raw = phase - phase_prev >=
    4096 / < -4096; phase_prev = 0 from reset), i.e. floor(4 n Phi / 8192) of the
    unwrapped phase Phi (starting at wrap13(phase_0)). Overspeed: |wrap13(raw)| >= 3072,
    never on the first trusted sample from reset. n: scalar or per-sample array (sampled
    with the sample). hold (per sample, rtl/monitor.v): a held sample's count is the last
    trusted sample's (0 before any), and it never flags overspeed; a held sample with
    coast follows the monitor's line instead of its phase: phase_prev <- line (u13) and B
    steps by the line's wraps, so the next trusted sample steps from where the line has
    come; a held sample without coast changes nothing. `state` (B, phase_prev, primed,
    count) continues a run (primed: a trusted sample since reset).

    Returns (count, overspeed, state after the last sample)."""
    b0, ph0, primed, c0 = (0, 0, False, 0) if state is None else state
    phase = np.asarray(phase, dtype=I64)
    n = np.broadcast_to(np.asarray(n, dtype=I64), phase.shape)
    if hold is not None and np.any(hold):
        hold = np.asarray(hold, dtype=bool)
        coast = (np.zeros_like(hold) if coast is None else np.asarray(coast, bool)) & hold
        line = phase if line is None else np.asarray(line, dtype=I64)
        mv = np.nonzero(~hold | coast)[0]          # the samples that move B and phase_prev
        tr = ~hold[mv]                             # the trusted ones among them
        c_m, o_m, st = counter(np.where(coast, line, phase)[mv],
                               np.asarray(prod, dtype=I64)[mv], n[mv], count_w,
                               (b0, ph0, True, c0))
        seen = np.cumsum(tr) - tr > 0               # a trusted sample before this one
        ovs = np.zeros(len(phase), dtype=bool)
        ovs[mv] = o_m & tr & (seen | primed)
        last = np.full(len(phase), -1, dtype=I64)
        c_tr = c_m[tr]
        last[mv[tr]] = np.arange(len(c_tr))
        last = np.maximum.accumulate(last)
        count = np.where(last >= 0, c_tr[np.maximum(last, 0)] if len(c_tr) else 0, c0)
        st = (st[0], st[1], bool(primed or tr.any()), int(count[-1]))
        return count.astype(I64), ovs, st
    prev = np.concatenate([[ph0], phase[:-1]]).astype(I64)
    raw = phase - prev
    step = np.where(raw >= 4096, -1, np.where(raw < -4096, 1, 0))
    dph = ((raw + 4096) & 8191) - 4096
    ovs = np.abs(dph) >= 3072
    if not primed and len(phase):
        ovs[0] = False
    m = 1 << count_w
    bacc = b0 + np.cumsum(4 * n * step)
    count = ((bacc + (np.asarray(prod, dtype=I64) >> 11) + (m >> 1)) % m) - (m >> 1)
    if len(phase):
        state = (int(bacc[-1]), int(phase[-1]), True, int(count[-1]))
    elif state is None:
        state = (0, 0, False, 0)
    return count.astype(I64), ovs, state


def edge_steps(a, b, state=None):
    """The paper's x4 decoder of the Eq. 12 pulses (rtl/counter.v, edge mode): per sample
    the step +1 / -1 for a quadrant step 1 / 3 (mod 4), 0 otherwise; a step of 2 (both A
    and B changed) is illegal: 0, flagged unless it is the first sample from reset.
    Quadrant code (1,1) 0, (0,1) 1, (0,0) 2, (1,0) 3; quadrant 0 before the first sample.
    Returns (step, illegal, state)."""
    qd0, primed = (0, False) if state is None else state
    a, b = np.asarray(a, dtype=I64), np.asarray(b, dtype=I64)
    qd = np.where(a == 1, np.where(b == 1, 0, 3), np.where(b == 1, 1, 2)).astype(I64)
    dq = (qd - np.concatenate([[qd0], qd[:-1]])) & 3
    step = np.where(dq == 1, 1, np.where(dq == 3, -1, 0)).astype(I64)
    ill = dq == 2
    if not primed and len(a):
        ill[0] = False
    if len(a):
        state = (int(qd[-1]), True)
    elif state is None:
        state = (0, False)
    return step, ill, state
