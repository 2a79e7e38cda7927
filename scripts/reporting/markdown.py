"""build/report.md: the report as tables with short labels. How each number is measured,
and what the timing model leaves out, is scripts/README.md's (`make report`), linked."""
from .common import median
from .devices import DEVICES, targets_of

SECTION = "#make-report"


def verdict(ok):
    return "met" if ok else "**missed**"


def fmt_counts(c, keys):
    return " | ".join(str(c.get(k, 0)) for k in keys)


def kv(d):
    """A parameter dict as `K=V K=V`, or `(defaults)`."""
    return " ".join(f"{k}={v}" for k, v in d.items()) or "(defaults)"


def table(head, rows, right=()):
    """A Markdown table: head (labels), rows (lists of cells); columns in `right` aligned
    right."""
    out = ["| " + " | ".join(head) + " |",
           "|" + "|".join("---:" if i in right else "---" for i in range(len(head))) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return out + [""]


def markdown(rep, readme="../scripts/README.md"):
    """The report's Markdown; readme: scripts/README.md relative to the file written."""
    devs = [d for d in DEVICES if d in rep["devices"]]
    E = [rep["devices"][d] for d in devs]
    sims = rep["sim"]["builds"]
    L = ["# finequad performance report", "",
         f"Method, and what each number leaves out: [scripts/README.md, `make report`]"
         f"({readme}{SECTION}).", ""]
    L += table(["run", ""], [
        ["command", f"`{rep['command']}`"],
        ["wall clock", f"{rep['wall_s'] / 60:.1f} min"],
        ["date", rep["date"]],
        ["commit", rep["commit"]],
        ["sources (SHA-256, 16 digits)", rep["sources_sha256"]],
    ] + [[f"tool: {k}", v] for k, v in rep["tools"].items()])
    for d, sl in sims.items():
        fp = sl["fast_path"]
        if not fp["rtl_equals_model"]:
            L += [f"**RTL != model** at DIV=1, build of {d}, from sample "
                  f"{fp['first_difference']}: the simulated numbers below are the RTL's.", ""]

    def fmax_cell(e):
        if e["fits"]:
            return f"{e['fmax_mhz']:.2f}"
        v = e.get("placed_variant") or {}
        why = v.get("why", "the full core does not fit")
        if not v.get("seeds_placed"):
            return f"0 ({why}; no reduced variant placed)"
        return f"0 ({why}; reduced variant {v['variant']}: {v['fmax_mhz']:.2f})"

    def seeds_cell(e):
        runs = e["runs"] if e["fits"] else (e.get("placed_variant") or {}).get("runs", [])
        ok = [str(r["seed"]) for r in runs if not r["error"]]
        routed = "" if len(ok) == len(runs) else f" (routed: {', '.join(ok) or 'none'})"
        pre = f"; --pre-place {e['preplace']}" if e.get("preplace") else ""
        return f"{', '.join(map(str, e['seeds']))}{routed}; {e['freq_target_mhz']:g} MHz{pre}"

    rows = [("`fmax_mhz` (median of the routed seeds)", fmax_cell),
            ("nextpnr seeds, --freq, placement script", seeds_cell),
            ("`fast_path_samples_per_clock`", lambda e: f"{e['fast_path_samples_per_clock']:g}"),
            ("`max_sample_rate_msps`", lambda e: f"{e['max_sample_rate_msps']:.2f}"),
            ("`rls_updates_msps`", lambda e: f"{e['rls_updates_msps']:.4f}"),
            ("`latency_cycles` (to m_count)", lambda e: f"{e['latency_cycles']}"),
            ("`luts`", lambda e: f"{e['luts']} ({e['percent']['luts']} %)"),
            ("LUT unit", lambda e: e["lut_unit"]),
            ("`ffs`", lambda e: f"{e['ffs']} ({e['percent']['ffs']} %)"),
            ("`dsps`", lambda e: f"{e['dsps']} ({e['percent']['dsps']} %)"),
            ("`brams`", lambda e: f"{e['brams']} ({e['percent']['brams']} %)"),
            ("`sim_samples_per_s` (per CPU s; wall)",
             lambda e: f"{e['sim_samples_per_s']:.0f} ({e.get('sim_samples_per_wall_s') or 0:.0f})")]
    L += table([""] + [e["device"] for e in E], [[name] + [f(e) for e in E] for name, f in rows],
               right=range(1, len(E) + 1))

    L += ["## Targets", ""]
    L += table(["device", "quantity", "target", "measured", ""],
               [[e["device"], q, t, m, verdict(ok)] for d, e in zip(devs, E)
                for q, t, m, ok in targets_of(d, e)])

    variants = [(e, e["placed_variant"]) for e in E if e.get("placed_variant")]
    if variants:
        def util_text(u):
            return ", ".join(f"{k} {a[0]}/{a[1]} ({100 * a[0] / a[1]:.1f} %)"
                             for k, a in u.items())
        L += ["## Reduced variants (the full core did not place)", ""]
        rows = []
        for e, v in variants:
            for t in v.get("not_placed", []) + [v]:
                placed = t is v and v.get("seeds_placed")
                rows.append([e["device"], t["variant"], t["design"], util_text(t["util"]),
                             "yes" if t["fits"] else "no",
                             f"{v['fmax_mhz']:.2f} ({', '.join(str(r['fmax_mhz']) for r in v['runs'])})"
                             if placed else "-"])
        L += table(["device", "variant", "design", "resources", "fits", "Fmax median (seeds)"],
                   rows)

    L += ["## Builds", "", "The builds of rtl/builds.toml each device is measured with; the "
          "simulations run the build's finequad_core (the probe) against `make model`.", ""]
    L += table(["device", "build", "synthesised", "probe (finequad_core)", "model"],
               [[rep["devices"][d]["device"], rep["devices"][d].get("build", "?"),
                 f"{rep['devices'][d].get('top', 'top_report')} "
                 f"{kv(rep['devices'][d].get('params', {}))}",
                 kv(sims[d]["probe_params"]), f"`make model {kv(sims[d]['model_args'])}`"]
                for d in devs if d in sims])

    L += ["## Latency (clocks from the strobe edge)", ""]
    rows = []
    for d, S in sims.items():
        lat = S["latency"]
        pulses = (f"{lat['ab_pulses_min']} .. {lat['ab_pulses']} ({lat['ab_pulses_trials']})"
                  if "ab_pulses" in lat else "(ABGEN constant)")
        rows.append([d, lat["trials"], lat["valid"], lat["count"],
                     f"{lat['ab_paced_min']} .. {lat['ab_paced']} ({lat['ab_paced_trials']})",
                     pulses])
    L += table(["build of", "samples", "m_valid", "m_count",
                "paced A/B pins (samples where they changed)", "Eq. 12 pulses (samples)"],
               rows, right=(1, 2, 3))

    L += ["## Samples per clock (a sample on every clock)", ""]
    L += table(["build of", "samples", "results", "on consecutive clocks", "longest gap",
                "RTL == `make model DIV=1`"],
               [[d, S["fast_path"]["samples"], S["fast_path"]["results"],
                 S["fast_path"]["edges"], S["fast_path"]["max_gap"],
                 "yes" if S["fast_path"]["rtl_equals_model"] else "**NO**"]
                for d, S in sims.items()], right=(1, 2, 3, 4))

    L += ["## Estimator updates (a sample on every clock, constant speed)", ""]
    L += table(["build of", "speed (1/8192 period per sample)", "clocks", "updates",
                "clocks/update", "UPDATE busy", "EXTRACT busy", "RESET busy",
                "idle (decision, dither)", "extracts", "gate blocks", "jumps"],
               [[d, f"{u['units_per_sample']:g}", u["clocks"], u["updates"],
                 u["clocks_per_update"], u["busy_per_update"]["update"],
                 u["busy_per_update"]["extract"], u["busy_per_update"]["reset"],
                 u["idle_per_update"], u["extracts"], u["gate_blocks"], u["jumps"]]
                for d, S in sims.items() for u in S["updates"]], right=range(1, 12))

    spd = rep["sim"]["sim_speed"]
    L += ["## Simulation speed (`make rtlsim`, the demo recording)", ""]
    L += table(["DIV", "samples", "clocks", "CPU s (runs)", "wall s (runs)",
                "samples per CPU s (fastest)", "per wall s (fastest; median)",
                "load average after"],
               [[spd["div"], spd["samples"], spd["clocks"], ", ".join(map(str, spd["cpu_s"])),
                 ", ".join(map(str, spd["wall_s"])), spd["samples_per_s"],
                 f"{spd['samples_per_wall_s']}; {spd['samples_per_wall_s_median']}",
                 ", ".join(map(str, spd["load_average"]))]], right=(0, 1, 2, 5))

    L += ["## Critical paths", ""]
    for d, e in zip(devs, E):
        runs = rep["devices"][d]["runs"] if e["fits"] else e["placed_variant"]["runs"]
        label = "full core" if e["fits"] else "reduced variant"
        L += [f"**{e['device']}** ({label}), the worst register-to-register path of each "
              "seed:", ""]
        rows = []
        for r in runs:
            cp = r["critical_path"]
            if r["error"] or not cp:
                rows.append([r["seed"], f"failed: {r['error']}"] + [""] * 7)
                continue
            fe = r.get("failing_endpoints")
            fe = "?" if not fe else (f"{fe[0]}" if fe[0] == fe[1] else f"{fe[0]}-{fe[1]}")
            rows.append([r["seed"], r["fmax_mhz"], fe, cp["total_ns"],
                         f"{cp['logic_ns']} / {cp['routing_ns']}", cp["logic_levels"],
                         f"`{cp['from']}`", f"`{cp['to']}`",
                         " -> ".join(f"{i} {dl:.1f}" for i, dl in cp["through"])])
        L += table(["seed", "Fmax MHz", "endpoints failing --freq", "path ns",
                    "logic / routing ns", "LUT/carry steps", "from", "to",
                    "through (ns per instance)"], rows, right=(0, 1, 3, 5))
        placed = [r for r in runs if not r["error"] and r["critical_path"]]
        if not placed:
            continue
        w = min(placed, key=lambda r: r["fmax_mhz"])
        L += [f"Steps of the slowest seed's path, seed {w['seed']} (routing listed with its "
              "sink):", ""]
        L += table(["step", "ns", "cell"],
                   [[k, dl, f"`{c}`"] for k, dl, c in w["critical_path"]["steps"]], right=(1,))
        mf = median([r["fmax_mhz"] for r in placed])
        med = min(placed, key=lambda r: abs(r["fmax_mhz"] - mf))
        ot = med.get("over_target")
        if ot and "error" in ot:
            L += [f"Path classes over the target period, seed {med['seed']}: not analysed "
                  f"({ot['error']}).", ""]
        elif ot:
            shown = (f"; the worst {len(ot['classes'])}" if ot["classes_total"] >
                     len(ot["classes"]) else "")
            L += [f"Path classes over the target period ({ot['period_ns']} ns), seed "
                  f"{med['seed']} (the median): {ot['endpoints']} endpoints in "
                  f"{ot['classes_total']} classes{shown}" + (":" if ot["classes"] else "."),
                  ""]
            if ot["classes"]:
                L += table(["worst ns", "endpoints", "from", "to"],
                           [[c["worst_ns"], c["endpoints"], f"`{c['from']}`", f"`{c['to']}`"]
                            for c in ot["classes"]], right=(0, 1))

    for d, e in zip(devs, E):
        modes = rep["devices"][d].get("dsp_modes")
        if not modes:
            continue
        comb = [m for m in modes if m["combinational"]]
        L += [f"## {e['device']}: DSP blocks with a stage nextpnr does not time", "",
              f"{len(comb)} of {len(modes)} SB_MAC16 (the netlist's parameters); on paths "
              "through them the Fmax is an upper bound "
              f"([scripts/README.md]({readme}{SECTION})).", ""]
        L += table(["SB_MAC16", "stages without a register at the block's pins"],
                   [[f"`{m['cell']}`", ", ".join(m["combinational"]) or "none"] for m in modes])

    L += ["## Cells per module", "",
          "Synthesis without flattening, the report build's parameters; 'incl.' counts the "
          "submodules.", ""]
    for d, e in zip(devs, E):
        rows = rep["devices"][d]["breakdown"]
        cells = DEVICES[d]["cells"]
        keys = ["lut4", "carry", "ff", "dsp", "bram"] + (["lutram", "mux"] if "mux" in cells
                                                       else [])
        tot = rows[0]["total"].get("lut4", 0) or 1
        L += [f"**{e['device']}**:", ""]
        L += table(["instance", "module"] + keys + [f"incl. {k}" for k in keys[:3]]
                   + ["% of LUT4"],
                   [[("&nbsp;" * 2 * r["depth"]) + (r["instance"].split(".")[-1] if r["depth"]
                                                    else r["instance"]),
                     r["module"], fmt_counts(r["own"], keys), fmt_counts(r["total"], keys[:3]),
                     f"{100 * r['total'].get('lut4', 0) / tot:.1f}"] for r in rows],
                   right=range(2, len(keys) + 6))
    L += ["## Times (s)", ""]
    L += table(["part", "s"],
               [[f"{d}: {k}", v] for d in devs for k, v in rep["devices"][d]["times"].items()]
               + [["simulations", rep["sim"]["seconds"]]]
               + [[f"probe build, {d}", sl["probe_build_s"]] for d, sl in sims.items()],
               right=(1,))
    return "\n".join(L).rstrip() + "\n"
