"""Bit-true, clock-accurate model of rtl/abgen.v: paced A/B quadrature output.

pos (the count the A/B outputs represent) chases the target by one count per output
edge, with at least sep clocks between two edges. Per clock edge i (no rst), with
d = wrap(target[i] - pos, COUNT_W) and cnt = clocks since the last edge (1..255,
saturating; 255 after reset):

    step  = d != 0 and cnt >= sep[i]          (sep 0 acts as 1)
    pos  += sign(d) if step;  cnt = 1 if step else min(cnt + 1, 255)
    (a, b) = AB[pos % 4],  AB = (1,1), (0,1), (0,0), (1,0)   (counting up)
    backlog = sat(d', 16);  ovf = |d'| > bound[i-1];  sticky |= ovf

with d' the d of the edge before (0 after reset): backlog and ovf describe the distance
one edge before, before that edge's step (rtl/abgen.v registers d first). The returned
arrays hold the outputs after each edge (what the RTL shows half a clock later).
The state starts at reset (pos 0, A = B = 1, cnt 255, flags 0); `state` continues a run.
"""
from dataclasses import dataclass

import numpy as np

from .fixed import sat, wrap

AB = ((1, 1), (0, 1), (0, 0), (1, 0))   # (A, B) for pos mod 4; quadrant code {~B, A^B}
CNT_MAX = 255


@dataclass
class AbgenState:
    pos: int = 0
    cnt: int = CNT_MAX
    sticky: int = 0
    d: int = 0                # d of the last edge (its flags show on the next one)
    bound: int = 0            # bound of the last edge


def ab_of(pos: int):
    """(A, B) that represent `pos` (x4 quadrature, (1, 1) at pos = 0 mod 4)."""
    return AB[pos & 3]


def abgen(target, sep, bound, count_w=32, state=None):
    """Per-clock arrays target (signed count_w), sep (u8), bound (u16) -> dict of
    per-clock arrays a, b, pos, backlog, ovf, sticky (outputs after each edge).
    `state` (AbgenState) is updated in place when given."""
    n = len(target)
    target = np.broadcast_to(np.asarray(target, dtype=np.int64), (n,))
    sep = np.broadcast_to(np.asarray(sep, dtype=np.int64), (n,))
    bound = np.broadcast_to(np.asarray(bound, dtype=np.int64), (n,))
    st = state if state is not None else AbgenState()
    pos, cnt, sticky, dp, bp = st.pos, st.cnt, st.sticky, st.d, st.bound
    out_pos = np.empty(n, dtype=np.int64)
    out_bl = np.empty(n, dtype=np.int64)
    out_ovf = np.empty(n, dtype=np.int8)
    out_sticky = np.empty(n, dtype=np.int8)
    tl, sl, bl = target.tolist(), sep.tolist(), bound.tolist()
    for i in range(n):
        d = wrap(tl[i] - pos, count_w)
        ovf = 1 if abs(dp) > bp else 0
        sticky |= ovf
        out_bl[i] = sat(dp, 16)
        out_ovf[i] = ovf
        out_sticky[i] = sticky
        dp, bp = d, bl[i]
        if d != 0 and cnt >= sl[i]:
            pos = wrap(pos + (1 if d > 0 else -1), count_w)
            cnt = 1
        elif cnt < CNT_MAX:
            cnt += 1
        out_pos[i] = pos
    st.pos, st.cnt, st.sticky, st.d, st.bound = pos, cnt, sticky, dp, bp
    q = out_pos & 3
    a = np.array([1, 0, 0, 1], dtype=np.int8)[q]
    b = np.array([1, 1, 0, 0], dtype=np.int8)[q]
    return dict(a=a, b=b, pos=out_pos, backlog=out_bl, ovf=out_ovf, sticky=out_sticky)


def abgen_fast(target, sep, bound, count_w=32, state=None):
    """Same outputs as abgen(), faster on long runs: between changes of (target, sep) the
    motion is closed-form (a step every max(sep, 1) clocks once the timer allows, until
    pos meets the target), so the loop runs over those runs, not over clocks. ovf/backlog
    are vectorised from pos."""
    n = len(target)
    target = np.broadcast_to(np.asarray(target, dtype=np.int64), (n,))
    sep = np.broadcast_to(np.asarray(sep, dtype=np.int64), (n,))
    bound = np.broadcast_to(np.asarray(bound, dtype=np.int64), (n,))
    st = state if state is not None else AbgenState()
    pos, cnt = st.pos, st.cnt
    out_pos = np.empty(n, dtype=np.int64)
    pos_before = np.empty(n, dtype=np.int64)
    # run boundaries: where target or sep changes
    chg = np.flatnonzero((np.diff(target) != 0) | (np.diff(sep) != 0)) + 1
    starts = np.concatenate(([0], chg)).tolist() if n else []
    ends = np.concatenate((chg, [n])).tolist() if n else []
    tl, sl = target.tolist(), sep.tolist()
    for i0, i1 in zip(starts, ends):
        t, s = tl[i0], max(sl[i0], 1)
        L = i1 - i0
        d = wrap(t - pos, count_w)
        k = np.arange(L, dtype=np.int64)
        if d == 0:
            pos_before[i0:i1] = pos
            out_pos[i0:i1] = pos
            cnt = min(cnt + L, CNT_MAX)
            continue
        sg = 1 if d > 0 else -1
        first = max(0, s - cnt)            # clock offset of the first step
        # steps taken up to and including clock offset k: 0 before `first`, then one
        # every s clocks, at most |d|
        nst = np.where(k >= first, (k - first) // s + 1, 0)
        nst = np.minimum(nst, abs(d))
        out_pos[i0:i1] = pos + sg * nst
        pos_before[i0] = pos
        pos_before[i0 + 1:i1] = out_pos[i0:i1 - 1]
        total = int(nst[-1])
        if total == 0:
            cnt = min(cnt + L, CNT_MAX)
        else:
            last = first + (total - 1) * s   # offset of the last step
            cnt = min(L - last, CNT_MAX)
        pos = wrap(pos + sg * total, count_w)
    half = 1 << (count_w - 1)
    out_pos = ((out_pos + half) & ((1 << count_w) - 1)) - half
    dd = ((target - pos_before + half) & ((1 << count_w) - 1)) - half
    # the flags of edge i come from the d of edge i - 1
    ddp = np.concatenate(([st.d], dd[:-1])) if n else dd
    bdp = np.concatenate(([st.bound], bound[:-1])) if n else bound
    ovf = (np.abs(ddp) > bdp).astype(np.int8)
    sticky = (np.maximum.accumulate(ovf) | st.sticky).astype(np.int8) if n else ovf
    st.pos, st.cnt = pos, cnt
    st.sticky = int(sticky[-1]) if n else st.sticky
    if n:
        st.d, st.bound = int(dd[-1]), int(bound[-1])
    q = out_pos & 3
    a = np.array([1, 0, 0, 1], dtype=np.int8)[q]
    b = np.array([1, 1, 0, 0], dtype=np.int8)[q]
    return dict(a=a, b=b, pos=out_pos, backlog=np.clip(ddp, -32768, 32767),
                ovf=ovf, sticky=sticky)


def _run(pos, cnt, target, edges, sep, count_w):
    """(pos, cnt) after `edges` edges with a constant target (closed form)."""
    if edges <= 0:
        return pos, cnt
    s = max(sep, 1)
    d = wrap(target - pos, count_w)
    first = max(0, s - cnt)                 # offset of the first step in the run
    if d == 0 or edges <= first:
        return pos, min(cnt + edges, CNT_MAX)
    steps = min(abs(d), (edges - 1 - first) // s + 1)
    last = first + (steps - 1) * s          # offset of the last step
    return wrap(pos + (steps if d > 0 else -steps), count_w), min(edges - last, CNT_MAX)


def advance(st: AbgenState, target: int, edges: int, sep: int, bound: int, count_w=32):
    """Run `edges` clock edges of abgen() with a constant target and settings, in closed
    form (a step every max(sep, 1) edges once the timer allows, until pos meets the
    target); updates `st`. The overflow flag of an edge shows the distance of the edge
    before it, before that edge's step: over a run the distance is largest on its first
    edge."""
    if edges <= 0:
        return
    if abs(st.d) > st.bound:                # the edge before the run, shown on its first
        st.sticky = 1
    d0 = wrap(target - st.pos, count_w)
    if edges >= 2 and abs(d0) > bound:
        st.sticky = 1
    pos_last, cnt_last = _run(st.pos, st.cnt, target, edges - 1, sep, count_w)
    st.d, st.bound = wrap(target - pos_last, count_w), bound     # the run's last edge
    st.pos, st.cnt = _run(pos_last, cnt_last, target, 1, sep, count_w)


class Follower:
    """abgen following a register that takes a new value on given edges (the core's
    m_count): `sample(edge)` runs the block up to and including `edge` and returns
    (a, b, sticky) after it; `set(edge, value)` makes the target `value` from `edge` on.
    Edges must not go back."""

    def __init__(self, sep, bound, count_w=32):
        self.st = AbgenState()
        self.sep, self.bound, self.count_w = sep, bound, count_w
        self.edge = 0                       # the next edge to run
        self.target = 0

    def sample(self, edge):
        advance(self.st, self.target, edge + 1 - self.edge, self.sep, self.bound,
                self.count_w)
        self.edge = max(self.edge, edge + 1)
        a, b = ab_of(self.st.pos)
        return a, b, self.st.sticky

    def set(self, edge, value):
        advance(self.st, self.target, edge - self.edge, self.sep, self.bound, self.count_w)
        self.edge = max(self.edge, edge)
        self.target = value
