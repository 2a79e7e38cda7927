#!/usr/bin/env python3
"""Accuracy benchmark: the RTL and the baselines on the scenario suite, against the floor.

    python3 scripts/bench_accuracy.py [--build build/bench] [--only NAME ...] [--no-rtl]
        [--edition verilog|vhdl|vhdl-synth]

For every scenario of sim/scenarios.py: generate the recording, run the RTL through
`make rtlsim` (Verilator) and the bit-true model, check that they agree bit for bit, and
score, through the same metrics (sim/metrics.py), these methods:

  rtl        finequad, the gateware (the count register)
  float      the float twin of finequad: the same estimator schedule in double precision
             with atan2 and an ideal counter (sim/reference.py run_schedule); RTL / float
             is the loss of the fixed-point design (word lengths, tables, rounding)
  paper_table  the bit-true model with the paper's table (TABLE=paper: the linear octant
             index of Eq. 11) counting the fine phase, harmonic learning off: the table's
             own error
  paper      the paper's method as printed, in float (sim/baselines.py paper_literal: RLS
             on every sample with lambda 0.995, P = 1000 I reset every 1000 samples, the
             linear index, Eq. 12 pulses, an x4 edge counter; its illegal steps, where
             both pulses changed at once and a count was lost, are reported beside it)
  heydemann  offline ellipse fit on the whole record, then atan2
  raw        atan2 of the uncorrected signals

Prints the table, writes accuracy.json and accuracy.md into the build directory, and
exits 1 if the RTL differs from the model anywhere, if a scenario's RTL (or, with
--no-rtl, model) count is over --target times the floor or slips, or if on a scenario
whose parameters are constant (Scenario.drifts false) its RMS error is more than 2 %
over the offline fit's (both counts, so both carry the count's quantisation; with
harmonics the online count is the better one) (2 on bad arguments).

--edition vhdl (make bench-accuracy EDITION=vhdl): the RTL is the VHDL edition under
GHDL (make rtlsim EDITION=vhdl); vhdl-synth: GHDL's synthesised netlist of it under
Verilator. The table is the same (every figure comes from the count, which must equal
the model's bit for bit); the run also times Verilator's rtlsim on each recording and
reports both editions' samples per second (accuracy.json "rtlsim_speed"). A GHDL run is
kept beside its recording (rtl.csv, rtl.key: run_key) and used again, not re-run, while
its command, its recording, the VHDL edition, its bench and GHDL are the same: the model
and every score are computed afresh each time. --jobs N runs the GHDL runs of N scenarios
at once first (make bench-accuracy EDITION=vhdl JOBS=N). A whole run's table (the whole
suite at the default n and bounds) is compared with the published Verilog edition's
(scripts/results/bench_accuracy.md) and must be the same, byte for byte (else exit 1);
--publish with --edition vhdl records the run as bench_accuracy_vhdl, with the sha256 of
the Verilog table it was compared with (make bench-accuracy EDITION=vhdl does).
"""
import argparse
from dataclasses import replace
import hashlib
import json
import pathlib
import subprocess
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from sim import baselines, metrics, reference, scenarios, siggen  # noqa: E402
from sim.model import finequad_core as core  # noqa: E402
from sim.model import regs  # noqa: E402
from sim.run_model import write_codes, write_result  # noqa: E402
from reporting.common import make_env  # noqa: E402  (scripts/reporting)

METHODS = ("rtl", "float", "paper_table", "paper", "heydemann", "raw")
TARGET = 1.15
OFFLINE = 1.02     # constant parameters: the count's RMS at most 2 % over the offline fit's


def score(count, sc, a, var_a, interp):
    s, err, _ = metrics.score(count, sc.x, var_a, scenarios.PITCH_NM, interp, sc.start(),
                              a=a)
    ev = [0] + list(sc.events)
    conv = [metrics.convergence_periods(err, sc.x, scenarios.PITCH_NM, s["floor_nm"], e,
                                        window=200, end=nxt)
            for e, nxt in zip(ev, ev[1:] + [None])]
    s["convergence_periods"] = conv
    s["convergence_samples"] = [metrics.convergence_samples(err, s["floor_nm"], e, window=200,
                                                            end=nxt)
                                for e, nxt in zip(ev, ev[1:] + [None])]
    return s


EDITIONS = {"verilog": "RTL (Verilator)", "vhdl": "RTL (VHDL edition, GHDL)",
            "vhdl-synth": "RTL (VHDL edition, ghdl --synth netlist, Verilator)"}
# the figures record (scripts/figures.py) a complete run of each edition publishes
RECORDS = {"verilog": "bench_accuracy", "vhdl": "bench_accuracy_vhdl"}


def not_whole(args):
    """Why this run is not the whole suite through the RTL at the default n and bounds
    (the run a record publishes, and whose table is the Verilog edition's), or None."""
    why = [opt for opt, on in (("--only", args.only), ("--no-rtl", args.no_rtl),
                               ("--interp", args.interp != core.Config().interp),
                               ("--target", args.target != TARGET),
                               ("--offline", args.offline != OFFLINE)) if on]
    return ", ".join(why) or None


def rtl_cmd(inp, out, interp, adc_w, code_step=0, edition="verilog"):
    cmd = ["make", "--no-print-directory", "-C", str(ROOT), "rtlsim", f"IN={inp}",
           f"OUT={out}", f"INTERP={interp}", f"ADC_W={adc_w}", "TABLE=exact"]
    if code_step:
        cmd.append(f"SETTINGS=--code-step {code_step}")
    return cmd + [f"EDITION={edition}"]


def run_rtl(inp, out, interp, adc_w, code_step=0, edition="verilog"):
    """`make rtlsim` in the background; returns the process (.seconds(): its wall time,
    from its start to its end, whenever it is asked)."""
    import threading
    t0 = time.time()
    proc = subprocess.Popen(rtl_cmd(inp, out, interp, adc_w, code_step, edition),
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            env=make_env())
    end = []
    waiter = threading.Thread(target=lambda: (proc.wait(), end.append(time.time())),
                              daemon=True)
    waiter.start()
    proc.seconds = lambda: (waiter.join(), end[0] - t0)[1]
    return proc


_WARM = set()


def timed_rtl(inp, out, interp, adc_w, code_step=0, edition="verilog"):
    """`make rtlsim` in the foreground (its harness built first, so a build is not
    timed); returns its wall seconds."""
    cmd = rtl_cmd(inp, out, interp, adc_w, code_step, edition)
    if (adc_w, edition) not in _WARM:            # (builds the harness: not timed)
        subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                       env=make_env())
        _WARM.add((adc_w, edition))
    t = time.time()
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                       env=make_env())
    if p.returncode != 0:
        raise SystemExit(f"bench: error: make rtlsim ({edition}) failed on {inp}:\n{p.stderr}")
    return time.time() - t


# What a GHDL run's output depends on besides its recording and the command make runs:
# the edition's files, the bench and its front end (the stimulus, the settings' register
# writes), the tables, and GHDL itself.
RUN_INPUTS = ("sim/harness/harness.vhd", "sim/run_vhdl.py", "sim/run_model.py", "sim/ghdl.py",
              "sim/model/regs.py")


def run_key(d, cmd):
    """The fingerprint of a GHDL run (--edition vhdl) of d/in.csv: the command `cmd` has
    make run (`make -n`, its paths left out), the recording and RUN_INPUTS (bench_accuracy
    keeps the run's rtl.csv and reuses it while the key is the same: a run of the whole
    suite takes hours)."""
    from sim import ghdl
    h = hashlib.sha256()
    files = sorted(set(ghdl.vhdl_files()) | set(RUN_INPUTS)) + sorted(
        str(f.relative_to(ROOT)) for f in (ROOT / "rtl" / "tables").glob("*.hex"))
    dry = subprocess.run(cmd[:1] + ["-n"] + cmd[1:], capture_output=True, text=True,
                         env=make_env())
    run = [ln for ln in dry.stdout.splitlines() if "sim.run_vhdl" in ln]
    if dry.returncode != 0 or len(run) != 1:
        raise SystemExit(f"bench: error: make -n rtlsim gave no one sim.run_vhdl command:\n"
                         f"{dry.stdout}{dry.stderr}")
    inp, out = (c.split("=", 1)[1] for c in cmd if c.startswith(("IN=", "OUT=")))
    run = " ".join(run[0].replace(inp, "IN").replace(out, "OUT").replace(str(ROOT), ".")
                   .split())
    for part in (run, subprocess.run(["ghdl", "--version"], capture_output=True,
                                     text=True).stdout.split("\n")[0]):
        h.update(part.encode() + b"\0")
    for f in files:
        h.update(f.encode() + b"\0" + (ROOT / f).read_bytes() + b"\0")
    h.update((d / "in.csv").read_bytes())
    return h.hexdigest()


class Reused:
    """A finished run whose rtl.csv is still valid (run_key): it took `secs` seconds."""
    returncode = 0

    def __init__(self, secs):
        self.secs = secs

    def communicate(self):
        return "", ""

    def seconds(self):
        return self.secs


def kept_run(d, key):
    """The run kept in d (Reused) if its key is `key`, else None (and no key is left)."""
    kept = json.loads((d / "rtl.key").read_text()) if (d / "rtl.key").is_file() else {}
    if kept.get("key") == key and (d / "rtl.csv").is_file():
        return Reused(kept["seconds"])
    (d / "rtl.key").unlink(missing_ok=True)
    return None


def keep_run(d, key, seconds):
    (d / "rtl.key").write_text(json.dumps({"key": key, "seconds": round(seconds, 1)}) + "\n")


def ghdl_runs(suite, build, interp, jobs):
    """--jobs N with --edition vhdl: the GHDL runs the suite needs and has not kept, N at a
    time, the longest first, each kept for bench() to take (so a run's samples per second
    is its own, on one of N busy cores)."""
    todo = []
    for sc in suite:
        d = build / sc.name
        u1, _, _, bits, code_step = recording(sc, d)
        key = run_key(d, rtl_cmd(d / "in.csv", d / "rtl.csv", interp, bits, code_step, "vhdl"))
        if kept_run(d, key) is None:
            todo.append((len(u1), sc.name, d, key, bits, code_step))
    if not todo:
        return
    todo.sort(key=lambda t: -t[0])
    print(f"GHDL runs of {len(todo)} scenarios, {jobs} at a time: "
          + ", ".join(t[1] for t in todo), flush=True)
    # (one short run first: it analyses the edition, which runs started together would race
    # on in one work library)
    warm = build / "_analysis"
    warm.mkdir(parents=True, exist_ok=True)
    write_codes(warm / "in.csv", np.zeros(2, dtype=np.int64), np.zeros(2, dtype=np.int64))
    p = subprocess.run(rtl_cmd(warm / "in.csv", warm / "rtl.csv", interp, 16, 0, "vhdl"),
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                       env=make_env())
    if p.returncode != 0:
        raise SystemExit(f"bench: error: make rtlsim (vhdl) failed:\n{p.stderr}")
    running = []
    while todo or running:
        while todo and len(running) < jobs:
            n, name, d, key, bits, code_step = todo.pop(0)
            running.append((name, d, key, run_rtl(d / "in.csv", d / "rtl.csv", interp, bits,
                                                  code_step, "vhdl")))
        time.sleep(1)
        for name, d, key, proc in [r for r in running if r[3].poll() is not None]:
            running.remove((name, d, key, proc))
            _, err = proc.communicate()
            if proc.returncode != 0:
                raise SystemExit(f"bench: error: make rtlsim failed on {name}:\n{err}")
            keep_run(d, key, proc.seconds())
            print(f"{name}: GHDL run done in {proc.seconds():.0f} s", flush=True)


def recording(sc, d):
    """Scenario sc's recording written to d/in.csv: its codes u1, u2, the angle, the port's
    width and the converter's code step."""
    u1, u2, a = sc.codes()
    bits, code_step = sc.port()
    d.mkdir(parents=True, exist_ok=True)
    write_codes(d / "in.csv", u1, u2)
    return u1, u2, a, bits, code_step


def bench(sc, d, interp, rtl, edition="verilog"):
    u1, u2, a, bits, code_step = recording(sc, d)
    proc, key = None, None
    if rtl and edition == "vhdl":
        key = run_key(d, rtl_cmd(d / "in.csv", d / "rtl.csv", interp, bits, code_step, edition))
        proc = kept_run(d, key)
    if rtl and proc is None:
        proc = run_rtl(d / "in.csv", d / "rtl.csv", interp, bits, code_step, edition)
    t0 = time.time()
    cfg = core.Config(interp=interp, ADC_W=bits, code_step=code_step)
    res = core.run(u1, u2, cfg)
    write_result(d / "model.csv", res)
    t_model = time.time() - t0
    var_a = siggen.angle_var(a, sc.sig)
    full = 1 << (bits - 1)
    f1, f2 = u1 / full, u2 / full
    paper = baselines.paper_literal(f1, f2, interp)
    counts = {
        "float": reference.run_schedule(u1, u2, res["sched"], interp, cfg.lambda_k,
                                        cfg.kappa / 256, adc_w=bits)["count"],
        # the gateware with the paper's table (linear octant index, Eq. 11) counting the
        # fine phase: the table's own error, without the edge counter's lost counts (and
        # without the harmonic table, which would learn that error away)
        "paper_table": core.run(u1, u2, replace(cfg, TABLE="paper", harm_learn=0))["count"],
        "paper": paper["count"],
        "heydemann": baselines.heydemann(f1, f2, interp)[0],
        "raw": baselines.raw_atan2(f1, f2, interp),
    }
    row = {"scenario": sc.name, "title": sc.title, "samples": len(u1),
           "scored_from": sc.start(), "adc_bits": sc.sig.adc_bits, "adc_port_bits": bits,
           "signal": siggen.describe(sc.sig),
           "estimator_updates": res["n_updates"], "jumps_detected": len(res["jumps"]),
           "model_seconds": round(t_model, 1), "paper_illegal_steps": int(paper["illegal"]),
           "paper_invalid_samples": int(paper["invalid"]), "drifts": sc.drifts}
    if proc is not None:
        _, err = proc.communicate()
        t_rtl = proc.seconds()
        if proc.returncode != 0:
            raise SystemExit(f"bench: error: make rtlsim failed on {sc.name}:\n{err}")
        row["rtl_reused"] = isinstance(proc, Reused)
        if key and not row["rtl_reused"]:
            keep_run(d, key, t_rtl)
        rtl_bytes = (d / "rtl.csv").read_bytes()
        row["rtl_equals_model"] = rtl_bytes == (d / "model.csv").read_bytes()
        rows = np.loadtxt(d / "rtl.csv", delimiter=",", skiprows=1, dtype=np.int64, ndmin=2)
        counts["rtl"] = rows[:, 0]
        row["method_rtl"] = EDITIONS[edition]
        if edition != "verilog":
            # samples per second of this edition's run (beside the model's) and of
            # Verilator's on the same recording, alone
            t_ver = timed_rtl(d / "in.csv", d / "rtl_verilog.csv", interp, bits, code_step)
            row["rtlsim_speed"] = {edition: round(len(u1) / t_rtl),
                                   "verilog": round(len(u1) / t_ver)}
    else:
        row["rtl_equals_model"] = None
        counts["rtl"] = res["count"]
        row["method_rtl"] = "bit-true model (RTL not run)"
    for m in METHODS:
        row[m] = score(counts[m], sc, a, var_a, interp)
    row["fixed_point_loss"] = row["rtl"]["rms_nm"] / row["float"]["rms_nm"]
    row["rtl_over_offline"] = row["rtl"]["rms_nm"] / row["heydemann"]["rms_nm"]
    return row


def offline_gap(r, bound=OFFLINE):
    """The RTL's RMS over the offline fit's, and whether it is over `bound` (constant
    parameters only: an offline fit of a drifting record is not the bar)."""
    g = r["rtl_over_offline"]
    return g, (not r["drifts"]) and g > bound


def fmt_conv(c, k=None):
    """Periods of travel (and samples) from the start / after each jump."""
    per = "/".join("-" if v is None else f"{v:.1f}" for v in c)
    if k is None:
        return per
    return per + " (" + "/".join("-" if v is None else f"{v}" for v in k) + " samples)"


def table(rows, target=TARGET):
    head = ("| scenario | method | RMS nm | floor nm | ratio | peak nm | slips | "
            "convergence (periods) |")
    lines = [head, "|" + "---|" * 8]
    for r in rows:
        for m in METHODS:
            s = r[m]
            name = r["scenario"] if m == "rtl" else ""
            mark = ""
            if m == "rtl":
                ok = s["ratio"] <= target and s["slips"] == 0
                mark = " " + ("ok" if ok else "**over**")
            lines.append(f"| {name} | {m}{mark} | {s['rms_nm']:.2f} | {s['floor_nm']:.2f} | "
                         f"{s['ratio']:.3f} | {s['peak_nm']:.1f} | {s['slips']} | "
                         f"{fmt_conv(s['convergence_periods'], s['convergence_samples'])} |")
    return "\n".join(lines)


def summary_table(rows, offline=OFFLINE):
    """One row per scenario: the RTL in full, the other methods as ratios."""
    def r(s):
        return f"{s['ratio']:.3f}" + (f" ({s['slips']} slips)" if s["slips"] else "")

    def gap(x):
        g, bad = offline_gap(x, offline)
        return f"{g:.3f}" + (" (drifts)" if x["drifts"] else " **over**" if bad else "")
    lines = ["| scenario | RTL RMS nm | floor nm | ratio | peak nm | slips | convergence "
             "periods (samples) | float twin | paper table, fine-phase count | paper "
             "literal | Heydemann offline | RTL / offline (RMS; constant parameters: "
             f"at most {offline}) | raw atan2 |",
             "|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|"]
    for x in rows:
        s = x["rtl"]
        lines.append(f"| {x['scenario']} | {s['rms_nm']:.2f} | {s['floor_nm']:.2f} | "
                     f"{s['ratio']:.3f} | {s['peak_nm']:.1f} | {s['slips']} | "
                     f"{fmt_conv(s['convergence_periods'], s['convergence_samples'])} | "
                     f"{r(x['float'])} | {r(x['paper_table'])} | "
                     f"{x['paper']['ratio']:.3f} ({x['paper']['slips']} slips, "
                     f"{x['paper_illegal_steps']} illegal) | {r(x['heydemann'])} | "
                     f"{gap(x)} | {r(x['raw'])} |")
    return "\n".join(lines)


def loss_table(rows):
    """The fixed-point design against its float twin (same schedule, double precision)."""
    lines = ["| scenario | RTL ratio | float twin ratio | fixed-point loss (RMS) | "
             "estimator updates | jumps detected |", "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scenario']} | {r['rtl']['ratio']:.3f} | {r['float']['ratio']:.3f} | "
                     f"{(r['fixed_point_loss'] - 1) * 100:+.1f} % | {r['estimator_updates']} | "
                     f"{r['jumps_detected']} |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build" / "bench"))
    ap.add_argument("--only", nargs="*", help="scenario names (default: the whole suite)")
    ap.add_argument("--interp", type=int, default=core.Config().interp)
    ap.add_argument("--no-rtl", action="store_true", help="score the bit-true model only")
    ap.add_argument("--edition", choices=list(EDITIONS), default="verilog",
                    help="the RTL: verilog (Verilator, default), vhdl (the VHDL edition "
                         "under GHDL) or vhdl-synth (its ghdl --synth netlist, Verilator)")
    ap.add_argument("--jobs", type=int, default=1, metavar="N",
                    help="with --edition vhdl: GHDL runs of up to N scenarios at once "
                         "(default 1)")
    ap.add_argument("--target", type=float, default=TARGET,
                    help=f"the largest RMS / floor a scenario may have (default {TARGET})")
    ap.add_argument("--offline", type=float, default=OFFLINE,
                    help="the largest RMS / the offline fit's RMS a scenario with constant "
                         f"parameters may have (default {OFFLINE})")
    ap.add_argument("--publish", action="store_true",
                    help="record the figures (scripts/results/bench_accuracy.*, or "
                         "bench_accuracy_vhdl.* with --edition vhdl; README.md): make "
                         "bench-accuracy [EDITION=vhdl] does; the whole suite with the RTL "
                         "only")
    args = ap.parse_args()
    if args.publish and (not_whole(args) or args.edition not in RECORDS):
        print("bench: error: --publish records the whole suite through the RTL at the default "
              "n and bounds only (no --only, --no-rtl, --interp, --target or --offline; "
              f"--edition {' or '.join(RECORDS)}); got {not_whole(args) or args.edition}",
              file=sys.stderr)
        raise SystemExit(2)
    import figures
    try:
        verilog_table = figures.table(RECORDS["verilog"])
    except figures.FiguresError as e:
        print(f"bench: error: {e}", file=sys.stderr)
        raise SystemExit(2)
    if args.publish and args.edition != "verilog" and verilog_table is None:
        print(f"bench: error: --publish --edition {args.edition} records whether its table is "
              "the Verilog edition's, and none is published (scripts/results/"
              "bench_accuracy.md: make bench-accuracy first)", file=sys.stderr)
        raise SystemExit(2)
    for name in ("target", "offline"):
        if not getattr(args, name) > 0:                      # (and not nan)
            print(f"bench: error: --{name} must be a ratio > 0, got {getattr(args, name)}",
                  file=sys.stderr)
            raise SystemExit(2)
    fi = regs.SETTINGS["interp"]
    if not fi.lo <= args.interp <= fi.hi:
        print(f"bench: error: --interp must be {fi.lo}..{fi.hi} (INTERP.interp), got "
              f"{args.interp}", file=sys.stderr)
        raise SystemExit(2)
    try:
        suite = scenarios.by_name(args.only)
    except ValueError as e:
        print(f"bench: error: {e}", file=sys.stderr)
        raise SystemExit(2)
    if args.jobs < 1:
        print(f"bench: error: --jobs must be 1 or more, got {args.jobs}", file=sys.stderr)
        raise SystemExit(2)
    build = pathlib.Path(args.build)
    rows = []
    t0 = time.time()
    if args.jobs > 1 and args.edition == "vhdl" and not args.no_rtl:
        ghdl_runs(suite, build, args.interp, args.jobs)
    for sc in suite:
        r = bench(sc, build / sc.name, args.interp, not args.no_rtl, args.edition)
        rows.append(r)
        s = r["rtl"]
        eq = {True: "RTL == model", False: "RTL != MODEL", None: "model only"}[
            r["rtl_equals_model"]]
        sp = r.get("rtlsim_speed")
        print(f"{sc.name:16s} {s['rms_nm']:6.2f} nm RMS, floor {s['floor_nm']:5.2f} nm, "
              f"ratio {s['ratio']:.3f}, peak {s['peak_nm']:6.1f} nm, slips {s['slips']}, "
              f"float twin {r['float']['ratio']:.3f}; {eq}"
              + (f"; {args.edition} {sp[args.edition]} samples/s, Verilator {sp['verilog']}"
                 if sp else "") + (" (its GHDL run kept from before: rtl.key)"
                                   if r.get("rtl_reused") else ""), flush=True)
    md = (f"n = {args.interp}, 4 um pitch, 1 MS/s; ratio = RMS / floor; convergence = "
          f"signal periods of travel (and samples) from the start / after each jump "
          f"until every 200-sample window stays within 2x the floor ('-': never); "
          f"fixed-point loss = RTL RMS / float twin RMS - 1 on the same schedule\n\n"
          + summary_table(rows, args.offline) + "\n\n" + loss_table(rows) + "\n\n"
          + table(rows, args.target))
    print()
    print(md)
    (build / "accuracy.md").write_text(md + "\n")
    summary = {"interp": args.interp, "pitch_nm": scenarios.PITCH_NM, "fs_hz": scenarios.FS,
               "target_ratio": args.target, "seconds": round(time.time() - t0, 1),
               "scenarios": rows}
    (build / "accuracy.json").write_text(json.dumps(summary, indent=1))
    over = [r["scenario"] for r in rows
            if r["rtl"]["ratio"] > args.target or r["rtl"]["slips"]]
    loss = max((r["fixed_point_loss"] - 1) * 100 for r in rows)
    print(f"\nwrote {build / 'accuracy.json'} and {build / 'accuracy.md'} "
          f"({time.time() - t0:.0f} s); RTL over {args.target}x the floor or slipping: "
          f"{', '.join(over) if over else 'none'}; largest fixed-point loss {loss:+.2f} %")
    speeds = [r["rtlsim_speed"] for r in rows if r.get("rtlsim_speed")]
    if speeds:
        n = sum(r["samples"] for r in rows if r.get("rtlsim_speed"))
        tot = {e: n / sum(r["samples"] / r["rtlsim_speed"][e] for r in rows
                          if r.get("rtlsim_speed")) for e in (args.edition, "verilog")}
        summary["rtlsim_speed"] = {e: round(v) for e, v in tot.items()}
        (build / "accuracy.json").write_text(json.dumps(summary, indent=1))
        print(f"rtlsim samples per second over the suite (wall, whole make rtlsim runs): "
              f"{EDITIONS[args.edition]} {tot[args.edition]:.0f}, RTL (Verilator) "
              f"{tot['verilog']:.0f} ({tot['verilog'] / tot[args.edition]:.1f}x)")
    same = None
    if args.edition != "verilog":
        # the whole suite: this edition's table must be the Verilog edition's published
        # one, byte for byte (every figure comes from the count)
        if not_whole(args) or verilog_table is None:
            print("the table is not compared with the Verilog edition's ("
                  + (not_whole(args) or "none is published") + ")")
        else:
            same = verilog_table == md + "\n"
            print(f"the table is {figures.SAME_AS_VERILOG[same]} the Verilog edition's "
                  "(scripts/results/bench_accuracy.md)")
    bad = [r["scenario"] for r in rows if r["rtl_equals_model"] is False]
    gaps = [r["rtl_over_offline"] for r in rows if not r["drifts"]]
    behind = [r["scenario"] for r in rows if offline_gap(r, args.offline)[1]]
    if gaps:
        print(f"RTL / offline fit on constant parameters: {min(gaps):.3f} to "
              f"{max(gaps):.3f} (at most {args.offline}); over: "
              f"{', '.join(behind) if behind else 'none'}")
    if args.publish:
        ratios = [r["rtl"]["ratio"] for r in rows]
        head = dict(scenarios=len(rows), ratio_min=min(ratios), ratio_max=max(ratios),
                    slips=sum(r["rtl"]["slips"] for r in rows),
                    rtl_equal=sum(bool(r["rtl_equals_model"]) for r in rows),
                    offline_max=max(gaps), offline_over=len(behind))
        if args.edition == "verilog":
            figures.publish(RECORDS["verilog"], "make bench-accuracy", head, md)
        else:
            head.update(same_as_verilog=same,
                        verilog_table_sha256=figures.sha256(verilog_table))
            figures.publish(RECORDS[args.edition], f"make bench-accuracy EDITION={args.edition}",
                            head, f"{EDITIONS[args.edition]}; the table is "
                            f"{figures.SAME_AS_VERILOG[same]} the Verilog edition's "
                            "([bench_accuracy.md](bench_accuracy.md)).\n\n" + md)
    if bad:
        print(f"bench: error: RTL differs from the bit-true model on {', '.join(bad)}",
              file=sys.stderr)
    if over:
        print(f"bench: error: over {args.target}x the floor or slipping: {', '.join(over)}",
              file=sys.stderr)
    if behind:
        print(f"bench: error: over {args.offline}x the offline fit's RMS with constant "
              f"parameters: {', '.join(behind)}", file=sys.stderr)
    if same is False:
        print("bench: error: the table differs from the Verilog edition's published one "
              "(scripts/results/bench_accuracy.md): the model or the scoring changed since "
              "it was published, or an edition differs from the model", file=sys.stderr)
    if bad or over or behind or same is False:
        raise SystemExit(1)


if __name__ == "__main__":
    main()
