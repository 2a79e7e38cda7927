"""Reference VCD of finequad_core written from the bit-true model (sim/model/finequad_core.py).

    from sim import vcdref
    vcdref.write("ref.vcd", core.run(u1, u2, cfg, trace=True), cfg)

The file uses the hierarchy, names and widths of the Verilator VCD that the harness
(sim/harness/harness.cpp) dumps, so that scripts/vcdcompare.py can match it signal by
signal with the RTL: scope TOP.finequad_core, vectors declared as name[msb:lsb], time
unit 1 ps, edge e (rising clk) at e * PERIOD_PS.

Timing (rtl/finequad_core.v and its blocks; the harness never asserts rst): sample k is
strobed on edge t_k = t0 + k * cfg.div and its results are registered on edge t_k + L,
where L is the stage latency below. The model computes values, not fast-path latencies,
so these come from the pipeline timing constants of sim/model/finequad_core.py (rtl_timing()), which
the RTL declares as localparams. A comparison therefore checks that the RTL's registers
follow those latencies and hold the model's values. All these signals change only on
rising edges.

    signal                              L             kind
    s_valid                             0             valid   high for one cycle from t_k
    s_ref                               0             pulse   the sample's reference input
    u_correct.valid0_o                  0             valid   the sample registered
    u_correct.clip_o, nsat_o            0             window  = m_fault[0], [1] of the sample
    u_correct.valid_o                   CORR_AT       valid
    u_correct.ax_o, ay_o, xn_o, yn_o    CORR_AT       window  |u1c|, |u2c| (s2.14), signs
    u_octant.valid_o                    OCT_AT        valid
    u_octant.oct2_o, neg_o              OCT_AT        window  octant (base / 2048), sign
    u_octant.j_o                        ADDR_AT - 1   window  table address (combinational,
                                                              read on edge t_k + ADDR_AT)
    g_harm.u_harmonic.u_bin2.bin_o      ADDR_AT       window  harmonic bin (combinational
                                                              from the registers of that
                                                              edge, rtl/harmonic.v)
    g_harm.u_harmonic.valid_o           PHASE_AT      valid
    g_harm.u_harmonic.phase_o           PHASE_AT      window  u13 fine phase
    g_harm.u_harmonic.phase_c_o         PHASE_AT      window  u13 corrected fine phase
    u_lut.nth_valid_o                   NTH_AT        valid
    u_lut.prod_o                        NTH_AT        window  u22 n * phase
    u_lut.valid_o                       SIN_AT        valid
    u_lut.pn_o                          SIN_AT        window  u13 n-th order phase
    u_lut.sin_mag_o, cos_mag_o          SIN_AT        window  u(SIN_W-1) |sin|, |cos| of pn
    u_lut.sin_neg_o, cos_neg_o          SIN_AT        window  their signs (pn, pn + 2048
                                                              in the lower half circle)
    u_pulse.valid_o                     PULSE_AT      valid
    u_pulse.a_o, b_o                    PULSE_AT      hold    Eq. 12 pulses
    u_counter.ill_o                     EDGE_AT       pulse   illegal pulse step (x4)
    u_counter.ill_count_o               EDGE_AT       hold    u16 count of those
    u_counter.ovs_o                     LATENCY       pulse   = m_fault[3] on the sample
    m_valid                             LATENCY       valid
    m_count                             LATENCY       hold    (and on the edge the homing
                                                              offset changes, LATCH_AT of
                                                              the latching sample)
    m_fault                             LATENCY       window
    m_z                                 LATENCY       window  Z as the count appears (the
                                                              model gives Z there only)
    m_ref_count, m_homed, m_pos_valid   LATCH_AT      hold    REF_COUNT, REF_STATUS bits
    u_abgen.a_o, b_o                    every edge    edges   paced A/B (sim/model/abgen.py
                                                              run edge by edge on the count
                                                              before the homing offset,
                                                              from t_k + AB_AT)
    u_abgen.pos_o                       every edge    edges   s(COUNT_W) count they represent
    u_abgen.backlog_o, ovf_o,           every edge    edges   s16 distance, overflow, sticky
      ovf_sticky_o                                            overflow (m_fault[6])
    m_a, m_b                            every edge    edges   the A/B pins: u_abgen.a_o, b_o,
                                                              with ab_src = 1 the pulses

kinds:
  valid   1 for the cycle after edge t_k + L, 0 otherwise (exact).
  hold    takes sample k's value after edge t_k + L and keeps it (exact: the RTL only
          updates these registers on a valid sample).
  pulse   sample k's value for one cycle, 0 otherwise (exact: gated with valid in the RTL).
  edges   the value after every edge (exact).
  count   m_count: hold, and with homing the offset's change on its edge (exact; 'x'
          from there if no later sample shows the new offset).
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

The harness's first dump is the state after edge 0, at time 0 (the power-up values are
the ones declared here).
"""

import numpy as np
from vcd import VCDWriter

from sim.model import abgen
from sim.model import finequad_core as core

PERIOD_PS = 27778        # sim/harness/harness.cpp (36 MHz)
T0 = 32                  # edge of the first strobe in the harness
SCOPE = "TOP.finequad_core"
X = -1                   # value code for 'x' in the event arrays

TIMING_KEYS = ("CORR_AT", "OCT_AT", "ADDR_AT", "PHASE_AT", "NTH_AT", "SIN_AT", "PULSE_AT",
               "EDGE_AT", "LATENCY", "AB_AT", "LATCH_AT")


def rtl_timing():
    """Edges from the strobe to each stage's result register (sim/model/finequad_core.py, which
    rtl/finequad_core.v declares as localparams and the tests hold it to)."""
    return {k: getattr(core, k) for k in TIMING_KEYS}


def _ill_count(r):
    return np.cumsum(np.asarray(r["ill"], dtype=np.int64)) & 0xFFFF


def _bit(name):
    return lambda r: (np.asarray(r["fault"]) >> core.FAULT_BITS[name]) & 1


def _sin_neg(r):
    return np.asarray(r["pn"]) >> 12


def _cos_neg(r):
    return ((np.asarray(r["pn"]) + 2048) & 8191) >> 12


def _mag(key):
    return lambda r: np.abs(np.asarray(r[key]))


HARM = "g_harm.u_harmonic"
# name (relative to SCOPE), width (int, the Config field giving it, or (field, offset)),
# kind, latency (a key of rtl_timing(), (key, offset), or 0), source: key of res, or a
# callable res -> array ('edges' signals are computed from res["count"], _edge_values())
SIGNALS = [
    ("s_valid", 1, "valid", 0, None),
    ("s_ref", 1, "pulse", 0, "ref_in"),
    ("u_correct.valid0_o", 1, "valid", 0, None),
    ("u_correct.clip_o", 1, "window", 0, _bit("clip")),
    ("u_correct.nsat_o", 1, "window", 0, _bit("nsat")),
    ("u_correct.valid_o", 1, "valid", "CORR_AT", None),
    ("u_correct.ax_o", 15, "window", "CORR_AT", "ax"),
    ("u_correct.ay_o", 15, "window", "CORR_AT", "ay"),
    ("u_correct.xn_o", 1, "window", "CORR_AT", "xn"),
    ("u_correct.yn_o", 1, "window", "CORR_AT", "yn"),
    ("u_octant.valid_o", 1, "valid", "OCT_AT", None),
    ("u_octant.oct2_o", 2, "window", "OCT_AT", lambda r: np.asarray(r["base"]) >> 11),
    ("u_octant.neg_o", 1, "window", "OCT_AT", "neg"),
    ("u_octant.j_o", 11, "window", ("ADDR_AT", -1), "j"),
    (f"{HARM}.u_bin2.bin_o", 6, "window", "ADDR_AT", "bin"),
    (f"{HARM}.valid_o", 1, "valid", "PHASE_AT", None),
    (f"{HARM}.phase_o", 13, "window", "PHASE_AT", "phase"),
    (f"{HARM}.phase_c_o", 13, "window", "PHASE_AT", "phase_c"),
    ("u_lut.nth_valid_o", 1, "valid", "NTH_AT", None),
    ("u_lut.prod_o", 22, "window", "NTH_AT", "prod"),
    ("u_lut.valid_o", 1, "valid", "SIN_AT", None),
    ("u_lut.pn_o", 13, "window", "SIN_AT", "pn"),
    ("u_lut.sin_mag_o", ("SIN_W", -1), "window", "SIN_AT", _mag("sinn")),
    ("u_lut.sin_neg_o", 1, "window", "SIN_AT", _sin_neg),
    ("u_lut.cos_mag_o", ("SIN_W", -1), "window", "SIN_AT", _mag("cosn")),
    ("u_lut.cos_neg_o", 1, "window", "SIN_AT", _cos_neg),
    ("u_pulse.valid_o", 1, "valid", "PULSE_AT", None),
    ("u_pulse.a_o", 1, "hold", "PULSE_AT", "pa"),
    ("u_pulse.b_o", 1, "hold", "PULSE_AT", "pb"),
    ("u_counter.ill_o", 1, "pulse", "EDGE_AT", "ill"),
    ("u_counter.ill_count_o", 16, "hold", "EDGE_AT", _ill_count),
    ("u_counter.ovs_o", 1, "pulse", "LATENCY", _bit("ovs")),
    ("m_valid", 1, "valid", "LATENCY", None),
    ("m_count", "COUNT_W", "count", "LATENCY", "count"),
    ("m_fault", core.FAULT_W, "window", "LATENCY", "fault"),
    ("m_z", 1, "window", "LATENCY", "z"),
    ("m_ref_count", "COUNT_W", "hold", "LATCH_AT", "ref_count"),
    ("m_homed", 1, "hold", "LATCH_AT", "homed"),
    ("m_pos_valid", 1, "hold", "LATCH_AT", "pos_valid"),
    ("u_abgen.a_o", 1, "edges", 0, "count"),
    ("u_abgen.b_o", 1, "edges", 0, "count"),
    ("u_abgen.pos_o", "COUNT_W", "edges", 0, "count"),
    ("u_abgen.backlog_o", 16, "edges", 0, "count"),
    ("u_abgen.ovf_o", 1, "edges", 0, "count"),
    ("u_abgen.ovf_sticky_o", 1, "edges", 0, "count"),
    ("m_a", 1, "edges", 0, "a"),
    ("m_b", 1, "edges", 0, "b"),
]
# initial (power-up) value of the 'hold' and 'edges' signals: rtl/pulse.v, rtl/abgen.v
INIT = {"u_pulse.a_o": 1, "u_pulse.b_o": 1, "m_a": 1, "m_b": 1, "u_abgen.a_o": 1,
        "u_abgen.b_o": 1}


def _count_raw(res):
    """The counter's count before the homing offset (m_count = it + the offset)."""
    return np.asarray(res.get("count_raw", res["count"]), dtype=np.int64)


def _abgen(res, cfg, t, tm, end):
    """rtl/abgen.v's outputs after every edge 0 .. end (sim/model/abgen.py run edge by
    edge): its target is the count before the homing offset (rtl/refmark.v target_o),
    sample k's from edge t_k + AB_AT on (the pins step on that edge)."""
    count = _count_raw(res)
    idx = np.searchsorted(t + tm["AB_AT"], np.arange(end + 1), side="right") - 1
    target = np.where(idx >= 0, count[np.maximum(idx, 0)], 0)
    return abgen.abgen(target, cfg.ab_sep, cfg.ab_bound, cfg.COUNT_W)


def _count_events(res, cfg, t, tm, width):
    """(edges, values) of m_count = the counter's count + the homing offset: sample k's
    count after t_k + LATENCY (res["count"], with the offset as it stands then), and, where
    homing (cfg.home_arm) latches, the new offset from the latch's edge (t_k + LATCH_AT of
    the first sample with homed = 1) on: the count registered then plus that offset, which
    the samples whose count comes on or after that edge show; 'x' if none does (the
    latch in the last samples)."""
    count = np.asarray(res["count"], dtype=np.int64)
    on = t + tm["LATENCY"]
    e, v = on.copy(), count.copy()
    homed = np.asarray(res.get("homed", np.zeros(len(count))), dtype=np.int64)
    if getattr(cfg, "home_arm", False) and homed.any():
        k = int(np.argmax(homed))
        el = int(t[k]) + tm["LATCH_AT"]
        raw = _count_raw(res)
        j = int(np.searchsorted(on, el, side="right")) - 1     # the count standing then
        after = np.nonzero(on >= el)[0]
        if len(after):
            off = int(count[after[0]] - raw[after[0]])
            val = (int(raw[j]) + off) & ((1 << width) - 1)
        else:
            val = X
        e = np.concatenate([e, [el]])
        v = np.concatenate([v & ((1 << width) - 1), [val]])
        order = np.argsort(e, kind="stable")
        e, v = e[order], v[order]
        last = np.ones(len(e), dtype=bool)
        last[:-1] = e[1:] != e[:-1]                 # one value per edge: the later one
        e, v = e[last], v[last]
    else:
        v = v & ((1 << width) - 1)
    keep = np.ones(len(v), dtype=bool)
    keep[1:] = v[1:] != v[:-1]
    return e[keep], v[keep]


def _edge_values(name, res, cfg, t, tm, end, ab):
    """(edges, values) of an 'edges' signal: the A/B pins are the paced outputs, or with
    ab_src = 1 the Eq. 12 pulses (the hold of u_pulse.a_o / b_o)."""
    if name in ("m_a", "m_b") and cfg.ab_src:
        return t + tm["PULSE_AT"], np.asarray(res["pa" if name == "m_a" else "pb"])
    key = {"m_a": "a", "m_b": "b", "u_abgen.a_o": "a", "u_abgen.b_o": "b",
           "u_abgen.pos_o": "pos", "u_abgen.backlog_o": "backlog", "u_abgen.ovf_o": "ovf",
           "u_abgen.ovf_sticky_o": "sticky"}[name]
    return np.arange(end + 1), np.asarray(ab[key], dtype=np.int64)


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
    if kind in ("hold", "edges"):
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

    res: sim.model.finequad_core.run(..., trace=True) (without trace, the signals needing a trace
    array -- u1c, phase, illegal_count, ... -- are left out); cfg: core.Config (div,
    COUNT_W); strobes: the strobe edges if not t0 + k * cfg.div; signals: restrict to these
    names (relative to TOP.finequad_core); timing: stage edges (keys of rtl_timing(), all
    of them) instead of those of sim/model/finequad_core.py. Returns the list of full
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
    end = (int(t[-1]) + max(tm.values()) + 2) if n else 1   # after the last change

    def lat_of(lat):
        if isinstance(lat, tuple):
            return tm[lat[0]] + lat[1]
        return tm[lat] if isinstance(lat, str) else lat

    chosen = []
    for name, width, kind, lat, src in SIGNALS:
        if signals is not None and name not in signals:
            continue
        if src is not None and not _available(res, src):
            continue
        if isinstance(width, tuple):
            width = getattr(cfg, width[0]) + width[1]
        elif isinstance(width, str):
            width = getattr(cfg, width)
        chosen.append((name, width, kind, lat_of(lat), src))
    if signals is not None:
        missing = set(signals) - {c[0] for c in chosen}
        if missing:
            raise KeyError(f"vcdref: cannot write {sorted(missing)} (unknown signal or "
                           f"res lacks its trace array: run the model with trace=True)")

    ab = None
    all_e, all_s, all_v = [], [], []
    for i, (name, width, kind, lat, src) in enumerate(chosen):
        if kind == "edges":
            if ab is None:
                ab = _abgen(res, cfg, t, tm, end)
            on, vals = _edge_values(name, res, cfg, t, tm, end, ab)
            # changes against the power-up value (edge -1 stands for it, then dropped)
            e, v = _events("hold", np.concatenate([[-1], on]),
                           np.concatenate([[INIT.get(name, 0)], vals]), width)
            e, v = e[1:], v[1:]
        elif kind == "count":
            e, v = _count_events(res, cfg, t, tm, width)
        else:
            e, v = _events(kind, t + lat, _source(res, src), width)
        all_e.append(e)
        all_s.append(np.full(len(e), i, dtype=np.int64))
        all_v.append(v)
    e = np.concatenate(all_e) if all_e else np.zeros(0, np.int64)
    s = np.concatenate(all_s) if all_s else np.zeros(0, np.int64)
    v = np.concatenate(all_v) if all_v else np.zeros(0, np.int64)
    order = np.lexsort((s, e))
    ts = e[order] * period_ps
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
        w.close(end * period_ps)
    return [f"{SCOPE}.{c[0]}" for c in chosen]
