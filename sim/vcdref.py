"""Reference VCD of finequad_core written from the bit-true model (sim/model/core.py).

    from sim import vcdref
    vcdref.write("ref.vcd", core.run(u1, u2, cfg, trace=True), cfg)

The file uses the hierarchy, names and widths of the Verilator VCD that the harness
(sim/harness/harness.cpp) dumps, so that scripts/vcdcompare.py can match it signal by
signal with the RTL: scope TOP.finequad_core, vectors declared as name[msb:lsb], time
unit 1 ps, edge e (rising clk) at e * PERIOD_PS.

Timing (rtl/finequad_core.v and its blocks; the harness never asserts rst): sample k is
strobed on edge t_k = t0 + k * cfg.div and its results are registered on edge t_k + L,
where L is the stage latency below. The model computes values, not fast-path latencies,
so these come from the pipeline timing constants of sim/model/core.py (rtl_timing()), which
the RTL declares as localparams. A comparison therefore checks that the RTL's registers
follow those latencies and hold the model's values. All these signals change only on rising edges.

    CORR_AT                 correct outputs (gain, offsets, products, round)
    OCT_AT   = PHASE_AT - 2 octant outputs (lut: +1 phase table, +2 phase_o)
    PHASE_AT                lut phase_o
    PN_AT    = PHASE_AT + 2 lut pn_o and sines (+3 n * phase, +4 sine table)
    AB_AT                   pulse
    LATENCY                 counter, m_* ports

    signal                          L         kind
    s_valid                         0         valid       high for one cycle from edge t_k
    u_correct.valid_o               CORR_AT   valid
    u_correct.u1c_o, u2c_o          CORR_AT   window      s2.14 corrected signals
    u_octant.valid_o                OCT_AT    valid
    u_octant.j_o, oct2_o, neg_o     OCT_AT    window      Table 2 address, octant, sign
    u_lut.phase_valid_o             PHASE_AT  valid
    u_lut.phase_o                   PHASE_AT  window      u13 fine phase
    u_lut.valid_o                   PN_AT     valid
    u_lut.pn_o                      PN_AT     window      u13 n-th order phase
    u_pulse.valid_o                 AB_AT     valid
    u_pulse.a_o, b_o                AB_AT     hold        A/B pulses (only change on valid)
    u_counter.illegal_o             LATENCY   pulse       = m_fault[3] on the valid cycle
    u_counter.illegal_count_o       LATENCY   hold
    m_valid                         LATENCY   valid
    m_count, m_a, m_b               LATENCY   hold        held between valid cycles
    m_fault                         LATENCY   window

kinds:
  valid   1 for the cycle after edge t_k + L, 0 otherwise (exact).
  hold    takes sample k's value after edge t_k + L and keeps it (exact: the RTL only
          updates these registers on a valid sample).
  pulse   sample k's value for one cycle, 0 otherwise (exact: gated with valid in the RTL).
  window  sample k's value for the one cycle after edge t_k + L and 'x' in every other
          cycle. These registers are also clocked on idle cycles, where they hold the
          datapath's response to the harness's idle input (s_u1 = s_u2 = 0) under
          whatever coefficient bundle is current on that edge; m_fault is combinational
          from delay lines of flags (uncal/hold follow the estimator on every edge).
          The model only knows the values that belong to a sample, so the reference
          says 'x' (not modelled) there. scripts/vcdcompare.py treats x/z bits of the
          reference as don't-care (the SystemVerilog ==? convention) by default, so
          these signals are checked exactly on the cycles that carry a sample, and
          ignored in between.

Harness quirk reproduced: the harness dumps at time 0 before edge 0 and Verilator ignores
the second dump at time 0 (after edge 0), so a change on edge 0 first shows at
PERIOD_PS / 2. Only s_valid with t0 = 0 can be affected.
"""

import numpy as np
from vcd import VCDWriter

from sim.model import core

PERIOD_PS = 27778        # sim/harness/harness.cpp (36 MHz)
T0 = 16                  # edge of the first strobe in the harness
SCOPE = "TOP.finequad_core"
X = -1                   # value code for 'x' in the event arrays

def rtl_timing():
    """Edges from the strobe to each stage's result register (sim/model/core.py, which
    rtl/finequad_core.v declares as localparams and the tests hold it to)."""
    return {k: getattr(core, k) for k in ("CORR_AT", "OCT_AT", "PHASE_AT", "PN_AT", "AB_AT",
                                          "LATENCY")}


# name (relative to SCOPE), width (int, or the Config field giving it), kind, latency (a
# key of rtl_timing(), or 0), source: key of res, or a callable res -> array
SIGNALS = [
    ("s_valid", 1, "valid", 0, None),
    ("u_correct.valid_o", 1, "valid", "CORR_AT", None),
    ("u_correct.u1c_o", 16, "window", "CORR_AT", "u1c"),
    ("u_correct.u2c_o", 16, "window", "CORR_AT", "u2c"),
    ("u_octant.valid_o", 1, "valid", "OCT_AT", None),
    ("u_octant.j_o", 11, "window", "OCT_AT", "j"),
    ("u_octant.oct2_o", 2, "window", "OCT_AT", lambda r: np.asarray(r["base"]) >> 11),
    ("u_octant.neg_o", 1, "window", "OCT_AT", "neg"),
    ("u_lut.phase_valid_o", 1, "valid", "PHASE_AT", None),
    ("u_lut.phase_o", 13, "window", "PHASE_AT", "phase"),
    ("u_lut.valid_o", 1, "valid", "PN_AT", None),
    ("u_lut.pn_o", 13, "window", "PN_AT", "pn"),
    ("u_pulse.valid_o", 1, "valid", "AB_AT", None),
    ("u_pulse.a_o", 1, "hold", "AB_AT", "a"),
    ("u_pulse.b_o", 1, "hold", "AB_AT", "b"),
    ("u_counter.illegal_o", 1, "pulse", "LATENCY",
     lambda r: (np.asarray(r["fault"]) >> core.FAULT_BITS["illegal"]) & 1),
    ("u_counter.illegal_count_o", 32, "hold", "LATENCY", "illegal_count"),
    ("m_valid", 1, "valid", "LATENCY", None),
    ("m_count", "COUNT_W", "hold", "LATENCY", "count"),
    ("m_a", 1, "hold", "LATENCY", "a"),
    ("m_b", 1, "hold", "LATENCY", "b"),
    ("m_fault", 6, "window", "LATENCY", "fault"),
]
# initial (power-up) value of the 'hold' signals: rtl/pulse.v, rtl/counter.v
INIT = {"u_pulse.a_o": 1, "u_pulse.b_o": 1, "m_a": 1, "m_b": 1}


def _source(res, src):
    if src is None:
        return None
    if callable(src):
        return src(res)
    return res[src]


def _available(res, src):
    try:
        _source(res, src)
        return True
    except KeyError:
        return False


def _events(kind, on, vals, width):
    """(edges, values) of one signal; on: edges of the sample results (increasing)."""
    if kind == "hold":
        v = np.asarray(vals, dtype=np.int64) & ((1 << width) - 1)
        keep = np.ones(len(v), dtype=bool)
        keep[1:] = v[1:] != v[:-1]          # unchanged holds are not changes
        return on[keep], v[keep]
    if kind == "valid":
        v = np.ones(len(on), dtype=np.int64)
        off_v = 0
    else:
        v = np.asarray(vals, dtype=np.int64) & ((1 << width) - 1)
        off_v = 0 if kind == "pulse" else X
    off = on + 1
    off = off[~np.isin(off, on)]            # back-to-back samples: no gap between them
    e = np.concatenate([on, off])
    val = np.concatenate([v, np.full(len(off), off_v, dtype=np.int64)])
    order = np.argsort(e, kind="stable")
    return e[order], val[order]


def write(path, res, cfg, t0=T0, period_ps=PERIOD_PS, strobes=None, signals=None,
          timing=None):
    """Write the reference VCD of the core to `path`.

    res: sim.model.core.run(..., trace=True) (without trace, the signals needing a trace
    array -- u1c, phase, illegal_count, ... -- are left out); cfg: core.Config (div,
    COUNT_W); strobes: the strobe edges if not t0 + k * cfg.div; signals: restrict to these
    names (relative to TOP.finequad_core); timing: stage edges (keys of rtl_timing(), all
    of them) instead of those of sim/model/core.py. Returns the list of full
    signal names written."""
    tm = rtl_timing() if timing is None else dict(timing)
    need = set(rtl_timing())
    if set(tm) != need:
        raise KeyError(f"vcdref: timing needs exactly the keys {sorted(need)}, got {sorted(tm)}")
    n = len(res["count"])
    t = (np.asarray(strobes, dtype=np.int64) if strobes is not None
         else t0 + cfg.div * np.arange(n, dtype=np.int64))
    if len(t) != n:
        raise ValueError(f"vcdref: {len(t)} strobe edges for {n} samples")
    if n > 1 and np.any(np.diff(t) < 1):
        raise ValueError("vcdref: strobe edges must increase")
    chosen = []
    for name, width, kind, lat, src in SIGNALS:
        if signals is not None and name not in signals:
            continue
        if src is not None and not _available(res, src):
            continue
        chosen.append((name, getattr(cfg, width) if isinstance(width, str) else width,
                       kind, tm[lat] if isinstance(lat, str) else lat, src))
    if signals is not None:
        missing = set(signals) - {c[0] for c in chosen}
        if missing:
            raise KeyError(f"vcdref: cannot write {sorted(missing)} (unknown signal or "
                           f"res lacks its trace array: run the model with trace=True)")

    all_e, all_s, all_v = [], [], []
    for i, (name, width, kind, lat, src) in enumerate(chosen):
        e, v = _events(kind, t + lat, _source(res, src), width)
        all_e.append(e)
        all_s.append(np.full(len(e), i, dtype=np.int64))
        all_v.append(v)
    e = np.concatenate(all_e) if all_e else np.zeros(0, np.int64)
    s = np.concatenate(all_s) if all_s else np.zeros(0, np.int64)
    v = np.concatenate(all_v) if all_v else np.zeros(0, np.int64)
    order = np.lexsort((s, e))
    ts = e[order] * period_ps
    ts[e[order] == 0] = period_ps // 2      # see the module docstring (harness quirk)
    s, v = s[order], v[order]

    comment = ("finequad_core reference from the bit-true model (sim/vcdref.py); "
               f"strobes t0={int(t[0]) if n else t0} div={cfg.div}, edge e at e*{period_ps} ps; "
               f"result registers at strobe + {', '.join(f'{k}={e}' for k, e in tm.items())}; "
               "x = not modelled (value only defined on the cycle carrying a sample)")
    with open(path, "w") as f:
        w = VCDWriter(f, timescale="1 ps", date="", comment=comment,
                      version="finequad sim/vcdref.py")
        vars_ = []
        for name, width, kind, lat, src in chosen:
            parts = name.split(".")
            scope = ".".join([SCOPE] + parts[:-1])
            init = "x" if kind == "window" else INIT.get(name, 0)
            vars_.append(w.register_var(scope, parts[-1], "wire", size=width, init=init,
                                        bit_index=(width - 1, 0) if width > 1 else None))
        change = w.change
        for ti, si, vi in zip(ts.tolist(), s.tolist(), v.tolist()):
            change(vars_[si], ti, "x" if vi < 0 else vi)
        end = (int(t[-1]) + tm["LATENCY"] + 1) * period_ps if n else period_ps
        w.close(end)
    return [f"{SCOPE}.{c[0]}" for c in chosen]
