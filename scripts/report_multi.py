#!/usr/bin/env python3
"""Multi-axis resource report: rtl/finequad_multi.v for 1, 2 and 4 axes on the
iCE40 UP5K and the ECP5 LFE5U-25F.

    python3 scripts/report_multi.py [--build build/report_multi] [--axes 1,2,4]
        [--devices ice40_up5k,ecp5_25f] [--seed 1] [--json F] [--md F]

The same flow and tools as scripts/report.py (its parts, scripts/reporting/): each
device's multi-axis build of rtl/builds.toml ([up5k_multi], [ecp5_multi]: the design
rtl/boards/top_report_multi.v, finequad_multi with every port kept, inputs from a scan
chain, outputs XOR-reduced into registers; the core parameters of the device's report
build; TDM_W; the axis counts, --axes by default) is linted with Verilator, synthesised
(iCE40: Debian Yosys `synth_ice40 -dsp`; ECP5: YoWASP Yosys `synth_ecp5`), then nextpnr
--pack-only (the resources; where nextpnr cannot even pack it, the synthesis cell counts
alone) and, where it fits, place and route with one seed (--freq 36 / 100 MHz as
report.py): Fmax. The synthesis cell counts are given in every case (LUT4, carry, FF, DSP,
block RAM cells of the flattened netlist).

Per-axis estimator update rate: measured on the bit-true model (sim/model/finequad_core.py, which
the RTL equals: cocotb_tests/test_finequad_multi.py) with a sample on every clock at a
constant speed where every sample passes the gate (one update per window round with
AXES > 1: TDM_L per axis), as updates per clock, then per second at Fmax and at 36 MHz.

Exit status 0 when the report was written, 1 when a step failed, 2 on bad arguments or an
error in rtl/builds.toml."""
import argparse
import collections
import json
import os
import pathlib
import subprocess
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from reporting import devices as rdev  # noqa: E402
from reporting.common import INCLUDE_FLAGS, ROOT, ReportError, builds, die, rel, run, \
    verilator  # noqa: E402
from reporting.devices import DEVICES, fits  # noqa: E402
from reporting.flow import ice40_ffs_from_log, pnr, tool_versions  # noqa: E402
from reporting.netlist import classify, flag, module_base  # noqa: E402
from reporting.timing import summarise_path  # noqa: E402


def multi_build(dev):
    """The name of device dev's multi-axis build (rtl/builds.toml)."""
    return DEVICES[dev]["multi"]


def top(dev):
    return builds.build(multi_build(dev))["top"]


def tdm_w(dev):
    """The build's window TDM_W: its own or its top's default."""
    return builds.resolved(multi_build(dev))["TDM_W"]


def sources(top):
    """The top's file, rtl/finequad_multi.v, rtl/finequad_core.f's files."""
    return [rel(builds.module_source(top)[0]), "rtl/finequad_multi.v"] + builds.sources(
        "rtl/finequad_core.f")


def lint(top, params):
    vroot, vbin = verilator()
    cmd = [vbin, "--lint-only", "-Wall", "-Wno-PROCASSINIT", *INCLUDE_FLAGS,
           "--top-module", top] + [f"-G{k}={v}" for k, v in params.items()]
    p = subprocess.run(cmd + sources(top), cwd=ROOT, capture_output=True, text=True,
                       env=dict(os.environ, VERILATOR_ROOT=vroot))
    if p.returncode != 0:
        raise ReportError(f"{top} does not lint clean ({params}):\n" +
                          "\n".join(ln for ln in p.stderr.splitlines() if ln.startswith("%"))[:2000])


def synth(dev, params, out_json, log):
    cfg = DEVICES[dev]
    t = top(dev)
    lint(t, params)
    chp = " ".join(f"-set {k} {v}" for k, v in params.items())
    script = (f"read_verilog {' '.join(INCLUDE_FLAGS)} {' '.join(sources(t))}; "
              f"chparam {chp} {t}; "
              f"{cfg['synth']} -top {t} -json {rel(out_json)}")
    _, dt = run(cfg["yosys"] + ["-q", "-l", rel(log), "-p", script], log, f"{dev} synthesis")
    return dt


def cell_counts(netlist, dev):
    """Cells of the flattened top by kind (lut4, carry, ff, dsp, bram, lutram, mux)."""
    cells = DEVICES[dev]["cells"]
    tops = [m for m, v in netlist["modules"].items()
            if flag(v.get("attributes", {}).get("top", 0))]
    c = collections.Counter()
    for cell in netlist["modules"][tops[0]]["cells"].values():
        k = classify(module_base(cell["type"]), cells)
        if k:
            c[k] += 1
    return dict(c)


def model_config(params):
    """The model's build fields (sim/model/finequad_core.py Config) of a build's parameters
    (the same names as the RTL's)."""
    fields = ("ENGINE_LANES", "OPT_HARMONIC", "OPT_MONITOR", "OPT_JUMP")   # same names
    return {k: int(v) for k, v in params.items() if k in fields}


def update_rate(axes, build, tdm_w, n=12000):
    """Estimator updates per clock of one axis, a sample on every clock, constant speed
    of 96 phase units per sample (every sample passes the 64-unit gate), model with the
    device's build (model_config(): its engine lanes set the window L) and window
    TDM_W."""
    import numpy as np
    from sim.model import finequad_core as core
    from sim.model import estimator
    x = np.arange(n) * (96 / 8192)                 # periods
    a = 2 * np.pi * x
    u1 = np.round(0.6 * 32767 * np.cos(a)).astype(np.int64)
    u2 = np.round(0.6 * 32767 * np.sin(a)).astype(np.int64)
    t = 16 + np.arange(n)
    lanes = build.get("ENGINE_LANES", 1)
    tdm = None if axes == 1 else (axes, 0, estimator.tdm_period(tdm_w, lanes), tdm_w)
    c = core.Core(core.Config(tdm=tdm, **build))
    c.feed(u1, u2, strobes=t)
    ups = [e for k, e in c.est.decided if k == "update"]
    ups = ups[len(ups) // 4:]                       # after the start-up
    return (len(ups) - 1) / (ups[-1] - ups[0])


def flow(dev, axes, bdir, seed, log):
    cfg = DEVICES[dev]
    d = bdir / dev / f"axes{axes}"
    d.mkdir(parents=True, exist_ok=True)
    bparams = builds.build(multi_build(dev))["params"]
    params = {"AXES": axes, **bparams}
    log(f"{dev} AXES={axes}: synthesis ({multi_build(dev)})")
    t_syn = synth(dev, params, d / "top.json", d / "yosys.log")
    cells = cell_counts(json.loads((d / "top.json").read_text()), dev)
    from sim.model import estimator
    build = model_config(bparams)
    out = {"device": dev, "axes": axes, "build": multi_build(dev), "params": params,
           "synth_cells": cells, "synth_s": round(t_syn, 1),
           "tdm_l": estimator.tdm_period(tdm_w(dev), build.get("ENGINE_LANES", 1)),
           "updates_per_clock": update_rate(axes, build, tdm_w(dev))}
    util, _, _, text, _, err = pnr(dev, d / "top.json", d)
    if err:
        log(f"{dev} AXES={axes}: nextpnr --pack-only failed: {err}")
        out.update(pack_error=err, fits=False)
        return out
    out["util"] = {k: list(util[c]) for k, c in cfg["util"].items()}
    if "ffs" not in cfg["util"]:
        out["util"]["ffs"] = [ice40_ffs_from_log(text), util[cfg["util"]["luts"]][1]]
    out["fits"] = fits(util, dev)
    if out["fits"]:
        log(f"{dev} AXES={axes}: place and route, seed {seed}")
        _, f, crit, _, dt, perr = pnr(dev, d / "top.json", d, seed, cfg["freq"])
        out.update(seed=seed, pnr_s=round(dt, 1), pnr_error=perr,
                   fmax_mhz=None if f is None else round(f, 2),
                   critical_path=summarise_path(crit) if crit else None)
        log(f"{dev} AXES={axes}: " + (perr or f"{f:.2f} MHz"))
    return out


def markdown(rep):
    L = ["| device | axes | window L (clocks) | LUTs | FFs | DSPs | BRAMs | fits | Fmax (seed "
         f"{rep['seed']}) | updates/s per axis at Fmax (at 36 MHz) | synthesis cells "
         "(LUT4 / carry / FF / DSP / BRAM) |", "|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---|"]
    for r in rep["runs"]:
        u = r.get("util", {})

        def cell(k):
            if k not in u:
                return "-"
            used, avail = u[k]
            return f"{used} / {avail} ({100 * used / avail:.1f} %)"
        c = r["synth_cells"]
        f = r.get("fmax_mhz")
        upc = r["updates_per_clock"]
        rate = (f"{upc * f * 1e6 / 1e3:.1f} k ({upc * 36e6 / 1e3:.1f} k)" if f
                else f"- ({upc * 36e6 / 1e3:.1f} k)")
        fits = "yes" if r.get("fits") else ("no (pack failed)" if "pack_error" in r else "no")
        L.append(f"| {r['device']} | {r['axes']} | {r['tdm_l'] if r['axes'] > 1 else '-'} | "
                 f"{cell('luts')} | {cell('ffs')} | {cell('dsps')} | {cell('brams')} | {fits} | "
                 f"{f if f else '-'} | {rate} | {c.get('lut4', 0)} / {c.get('carry', 0)} / "
                 f"{c.get('ff', 0)} / {c.get('dsp', 0)} / {c.get('bram', 0)} |")
    return "\n".join(L) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build/report_multi")
    ap.add_argument("--axes", default=None,
                    help="axis counts, e.g. 1,2,4 (default: each build's axes, rtl/builds.toml)")
    ap.add_argument("--devices", default="ice40_up5k,ecp5_25f")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--json", default=None)
    ap.add_argument("--md", default=None)
    a = ap.parse_args(argv)
    axes = None
    if a.axes is not None:
        try:
            axes = [int(x) for x in a.axes.split(",")]
        except ValueError:
            die(f"--axes: a comma-separated list of integers, got {a.axes!r}")
        if any(n < 1 for n in axes):
            die(f"--axes: every count must be >= 1 (rtl/finequad_multi.v AXES), got {a.axes!r}")
    devs = a.devices.split(",")
    for dv in devs:
        if dv not in DEVICES:
            die(f"--devices: unknown device {dv!r} (known: {', '.join(DEVICES)})")
    try:
        sweep = {dv: axes or builds.build(multi_build(dv))["axes"] for dv in devs}
        for dv in devs:
            rdev.nextpnr(dv), tdm_w(dv)
    except (builds.BuildError, KeyError) as e:
        die(f"rtl/builds.toml: {e}" if isinstance(e, KeyError) else str(e))
    bdir = (ROOT / a.build).resolve() if not pathlib.Path(a.build).is_absolute() \
        else pathlib.Path(a.build)
    bdir.mkdir(parents=True, exist_ok=True)
    t0 = time.time()

    def log(msg):
        print(f"[{time.time() - t0:6.0f} s] {msg}", flush=True)

    rep = {"seed": a.seed, "tdm_w": {dv: tdm_w(dv) for dv in devs}, "tools": tool_versions(),
           "runs": []}
    try:
        for dv in devs:
            for n in sweep[dv]:
                rep["runs"].append(flow(dv, n, bdir, a.seed, log))
    except ReportError as e:
        print(f"report_multi: error: {e}", file=sys.stderr)
        return 1
    js = pathlib.Path(a.json) if a.json else bdir / "report_multi.json"
    md = pathlib.Path(a.md) if a.md else bdir / "report_multi.md"
    js.write_text(json.dumps(rep, indent=1))
    md.write_text(markdown(rep))
    print(md.read_text())
    log(f"wrote {js} and {md}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
