#!/usr/bin/env python3
"""Performance report: clock rate, sample rate, latency, area, simulation speed.

    python3 scripts/report.py [--build build/report] [--json build/report.json]
        [--md build/report.md] [--seeds 1,2,3,4,5] [--devices ice40_up5k,ecp5_25f]
        [--make-build build]

Writes build/report.json (per device the issue's keys, scripts/reporting/devices.py KEYS,
and context beside them) and build/report.md (tables); the work files, logs and
report_full.json (every run, path and cell count) go to the --build folder. Each device is
measured with its build of rtl/builds.toml ([up5k], [ecp5]): synthesis and place and
route of the build's top (rtl/boards/top_report.v), the probe's simulations of its
finequad_core against `make model PROFILE=<build>`, and `make rtlsim`'s speed. The method:
README.md, Performance report; the parts: scripts/reporting/.

Exit status: 0 when the report was written (targets met or not: the report says which),
1 when a measurement failed (a tool error, RTL != model, a latency that is not constant),
2 on bad arguments, a missing tool or an error in rtl/builds.toml.
"""
import argparse
import json
import os
import pathlib
import shutil
import subprocess
import sys
import time

from reporting import devices
from reporting.common import ROOT, ReportError, builds, die, rel, rtl_sources
from reporting.devices import DEVICES, check_entry, entry
from reporting import flow
from reporting.flow import device_flow, tool_versions
from reporting.markdown import markdown
from reporting.simulate import device_sim, measure_sim_speed, simulations


def measured_files():
    """What the report's numbers depend on: the design's sources and tables, the harnesses
    that measure it (the probe, `make rtlsim`'s harness) and the placement scripts."""
    files = sorted({f for d in DEVICES for f in rtl_sources(devices.top(d))})
    files += sorted(rel(p) for p in (ROOT / "rtl" / "tables").iterdir())
    files += sorted(rel(p) for p in (ROOT / "rtl").glob("*.vh"))        # included headers
    files += ["rtl/finequad_core.f", "rtl/builds.toml", "scripts/builds.mk",
              "sim/harness/probe.cpp", "sim/harness/harness.cpp", "sim/harness/input.h"]
    files += sorted({c["preplace"] for c in DEVICES.values() if c.get("preplace")})
    return files


def fingerprint():
    """SHA-256 over measured_files(): the report must measure one design."""
    import hashlib
    h = hashlib.sha256()
    for f in measured_files():
        h.update(f.encode() + b"\0" + (ROOT / f).read_bytes())
    return h.hexdigest()[:16]


def publish(entries, full):
    """The report's headline figures as a record (scripts/figures.py); its table links
    scripts/README.md relative to scripts/results/."""
    import figures
    head = {d: {"title": e["device"], "seeds": len(e["seeds"]), "fmax_mhz": e["fmax_mhz"],
                "luts": e["luts"], "lut_unit": e["lut_unit"].split(" (")[0],
                "luts_pct": e["percent"]["luts"], "rls_updates_msps": e["rls_updates_msps"]}
            for d, e in entries.items()}
    first = next(iter(entries.values()))
    head.update(latency_cycles=first["latency_cycles"],
                samples_per_clock=first["fast_path_samples_per_clock"],
                sim_samples_per_s=first["sim_samples_per_s"])
    figures.publish("report", "make report", head, markdown(full, "../README.md"))


def compare_editions(entries, path=None):
    """The resources and Fmax of this (VHDL) edition beside the Verilog edition's report."""
    if path is None:
        path = next((p for p in (ROOT / "build" / "report.json",
                                 ROOT / "scripts" / "results" / "report.json")
                     if p.is_file()), None)
    if path is None or not pathlib.Path(path).is_file():
        print("(no Verilog edition report to compare with: make report, or --compare)")
        return
    ver = json.loads(pathlib.Path(path).read_text())
    ver = ver.get("headline", ver)     # (scripts/results/: luts and Fmax only)
    print(f"\nVHDL edition beside the Verilog edition ({rel(pathlib.Path(path).resolve())}):")
    print("| device | | Verilog | VHDL | VHDL / Verilog |\n|---|---|---:|---:|---:|")
    for d, e in entries.items():
        v = ver.get(d, {})
        for k in ("luts", "ffs", "dsps", "brams", "fmax_mhz"):
            a, b = v.get(k), e.get(k)
            ratio = f"{b / a - 1:+.1%}" if isinstance(a, (int, float)) and a else "-"
            print(f"| {d} | {k} | {a if a is not None else '-'} | {b} | {ratio} |")


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
    ap.add_argument("--publish", action="store_true",
                    help="record the figures (scripts/results/report.*, README.md): make "
                         "report does; every device and the default seeds only")
    ap.add_argument("--edition", choices=["verilog", "vhdl"], default="verilog",
                    help="the edition synthesised: verilog (rtl/) or vhdl (rtl/vhdl/, "
                         "through ghdl --synth; its resources and Fmax are printed beside "
                         "the Verilog edition's of --compare); the simulations are the "
                         "Verilog edition's either way")
    ap.add_argument("--compare", metavar="REPORT.json",
                    help="with --edition vhdl: the Verilog edition's report.json to print "
                         "beside it (default: build/report.json if it exists, else "
                         "scripts/results/report.json)")
    a = ap.parse_args(argv)
    if a.edition != "verilog" and a.publish:
        die("--publish records the Verilog edition only (no --edition)")
    flow.EDITION = a.edition
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
    if a.publish and (sorted(devs) != sorted(DEVICES) or a.seeds != "1,2,3,4,5"):
        die("--publish records every device with the default seeds only")
    bdir = pathlib.Path(a.build).resolve()
    try:
        bdir.relative_to(ROOT)
    except ValueError:
        die(f"--build must lie inside the repository ({ROOT}): the YoWASP tools only see "
            "the working directory")
    for d in devs:
        for tool in (DEVICES[d]["yosys"][0], DEVICES[d]["nextpnr_tool"]):
            if not shutil.which(tool):
                die(f"{tool} not found (scripts/install.sh; the venv: pip install -r "
                    "scripts/requirements.txt)")
    bdir.mkdir(parents=True, exist_ok=True)
    sys.path.insert(0, str(ROOT))

    def log(msg):
        print(f"[{time.strftime('%H:%M:%S')}] {msg}", flush=True)

    t0 = time.perf_counter()
    try:
        fp0 = fingerprint()
        for d in devs:                         # the builds are readable before anything runs
            devices.synth_params(d), devices.probe_params(d), devices.nextpnr(d)
    except builds.BuildError as e:
        die(str(e))
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
        entries = {}
        for d, f in flows.items():
            e = entry(d, f["util"], f["ffs"], f["fits"], f["fmax"],
                      device_sim(sims, spd, d), DEVICES[d]["freq"],
                      seeds, f["variant"])
            check_entry(e)
            entries[d] = e
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
        "devices": {d: {**entries[d], "build": devices.build_of(d), "top": devices.top(d),
                        "params": devices.synth_params(d), "runs": flows[d]["runs"],
                        "breakdown": flows[d]["breakdown"], "dsp_modes": flows[d]["dsp_modes"],
                        "times": flows[d]["times"]}
                    for d in devs},
        "sim": sim,
    }
    out_json, out_md = pathlib.Path(a.json), pathlib.Path(a.md)
    for f in (out_json, out_md):
        f.parent.mkdir(parents=True, exist_ok=True)
    (bdir / "report_full.json").write_text(json.dumps(full, indent=1))
    out_json.write_text(json.dumps(entries, indent=1))
    md = markdown(full, os.path.relpath(ROOT / "scripts" / "README.md", out_md.parent.resolve()))
    out_md.write_text(md)
    print(md)
    if a.publish:
        publish(entries, full)
    for d, sl in sims.items():
        if not sl["fast_path"]["rtl_equals_model"]:
            die(f"RTL != model at DIV=1 on {d}'s build (sample "
                f"{sl['fast_path']['first_difference']}): see "
                f"{rel(bdir / f'fastpath_{d}')}", 1)
    if a.edition != "verilog":
        compare_editions(entries, a.compare)
    log(f"wrote {rel(out_json)}, {rel(out_md)} and "
        f"{rel(bdir / 'report_full.json')} in {full['wall_s'] / 60:.1f} min")


if __name__ == "__main__":
    main()
