#!/usr/bin/env python3
"""Print resource use and Fmax from a nextpnr --report JSON (iCE40 UP5K by default).

    python3 scripts/pnr_report.py report.json [nextpnr.log] [--json out.json]
"""
import argparse
import json
import sys

CELLS = {"LUTs": "ICESTORM_LC", "DSPs": "ICESTORM_DSP", "BRAMs": "ICESTORM_RAM",
         "PLLs": "ICESTORM_PLL", "IOs": "SB_IO",
         # ECP5 (nextpnr-ecp5): LUT4s, flip-flops, 18x18 multipliers, 18 kbit RAMs
         "LUT4s": "TRELLIS_COMB", "FFs": "TRELLIS_FF", "MULT18X18D": "MULT18X18D",
         "DP16KD": "DP16KD", "EHXPLLL": "EHXPLLL", "ECP5 IOs": "TRELLIS_IO"}


def parse(report_path):
    try:
        rep = json.load(open(report_path))
    except (OSError, json.JSONDecodeError) as e:
        sys.exit(f"pnr_report: error: cannot read {report_path}: {e}")
    util = rep.get("utilization", {})
    res = {}
    for name, cell in CELLS.items():
        if cell in util:
            res[name] = (util[cell]["used"], util[cell]["available"])
    fmax = {k: v["achieved"] for k, v in rep.get("fmax", {}).items()}
    return res, fmax


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("report")
    ap.add_argument("log", nargs="?")
    ap.add_argument("--target-mhz", type=float, default=None)
    ap.add_argument("--bitstream")
    ap.add_argument("--json")
    ap.add_argument("--require", action="store_true",
                    help="exit 1 if a clock misses --target-mhz")
    a = ap.parse_args()
    res, fmax = parse(a.report)
    print("| resource | used | available | % |")
    print("|---|---:|---:|---:|")
    for k, (u, av) in res.items():
        print(f"| {k} | {u} | {av} | {100.0 * u / av:.1f} |")
    for clk, f in fmax.items():
        tgt = f" (target {a.target_mhz:g} MHz: {'met' if f >= a.target_mhz else 'NOT met'})" \
            if a.target_mhz else ""
        print(f"Fmax {clk}: {f:.2f} MHz{tgt}")
    if a.bitstream:
        print(f"bitstream: {a.bitstream}")
    if a.json:
        json.dump({"resources": res, "fmax_mhz": fmax}, open(a.json, "w"), indent=1)
    if a.require and a.target_mhz and any(f < a.target_mhz for f in fmax.values()):
        sys.exit(f"pnr_report: error: timing not met at {a.target_mhz:g} MHz")


if __name__ == "__main__":
    main()
