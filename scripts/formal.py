#!/usr/bin/env python3
"""Formal proofs of finequad's RTL (`make formal`), without SymbiYosys.

Drives the flow SymbiYosys would: Yosys reads a wrapper (sim/formal/*.v: the block under
proof plus its assertions, assumptions and ghost state) with `read_verilog -formal`,
flattens it, writes SMT-LIB2, and yosys-smtbmc checks it with z3:

  bmc    bounded model check from the initial values (`reg x = 0`, initial blocks),
         assumptions at every step, `--presat` (fails if the assumptions contradict each
         other, which would make every assertion vacuous)
  ind    k-induction (`-i`): from an arbitrary state, DEPTH steps in which the assertions
         hold imply the next. Together with a `bmc` of at least the same depth this is an
         unbounded proof.
  cover  every `cover` statement is reached within DEPTH steps from the initial values
         (non-vacuity: the properties are about behaviour that really occurs)

Probes: a wrapper may declare `(* fv_probe = "u_dut.reg_name" *) wire [..] p_x;` to read
an internal register of the block (Yosys 0.23 has neither hierarchical references nor
`bind`); the wire is connected after `flatten` with `connect -set`, so a renamed register
fails the proof loudly. Blackboxes: a proof can read other RTL files as `-lib`
(interfaces only) and cut their instances (`cutpoint`: outputs become free inputs).

Every proof is listed in PROOFS below. Prints PASS/FAIL per check (proof, mode, depth,
seconds), keeps logs, and on a failure the solver's message and a counterexample VCD
(build/formal/<proof>/<mode>.vcd). Exit status 0 all passed, 1 a check failed, 2 tools
missing or bad arguments.

  scripts/formal.py [-j JOBS] [--rtl DIR] [--wrappers DIR] [--build DIR] [--json FILE] [PROOF ...]
"""
import argparse
import concurrent.futures
import dataclasses
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]


@dataclasses.dataclass(frozen=True)
class Proof:
    name: str
    top: str                     # wrapper module
    wrapper: str                 # file in the wrappers folder (sim/formal)
    rtl: tuple                   # RTL files read in full (rtl folder)
    checks: tuple                # ((mode, depth), ...), mode bmc / ind / cover
    params: tuple = ()           # ((name, value), ...) set on the wrapper (chparam)
    lib: tuple = ()              # RTL files read as blackboxes ("*": every other rtl/*.v)
    cut: str = ""                # Yosys selection of blackbox instances to cut
    note: str = ""               # one line: what is proved


# The proofs. Depths: bmc covers at least the induction depth (the base case of the
# induction); the induction depth is the smallest that succeeds, plus margin.
PROOFS = [
    Proof("counter_steps", "fv_counter_steps", "counter_steps.v", ("counter.v",),
          (("bmc", 12), ("ind", 4), ("cover", 10)),
          note="counter, both modes, any n and mode per sample: step <= 2n (phase), "
               "+-1/0 per quadrature rule (edge), flags, illegal count, no step without "
               "a sample"),
    Proof("counter_phase", "fv_counter_phase", "counter_phase.v", ("counter.v",),
          (("bmc", 4), ("ind", 1), ("cover", 8)),
          note="counter, phase mode, constant n: count == floor(4 n Phi / 8192) mod 2^16 "
               "of the unwrapped phase Phi (ghost), for all time"),
    Proof("pulse_w10", "fv_pulse", "pulse.v", ("pulse.v",),
          (("bmc", 8), ("ind", 2), ("cover", 6)), params=(("SIN_W", 10),),
          note="pulse (SIN_W 10): Eq. 12 with hysteresis, hold without a valid sample"),
    Proof("pulse_w8", "fv_pulse", "pulse.v", ("pulse.v",),
          (("bmc", 8), ("ind", 2)), params=(("SIN_W", 8),),
          note="pulse (SIN_W 8)"),
    Proof("pulse_w12", "fv_pulse", "pulse.v", ("pulse.v",),
          (("bmc", 8), ("ind", 2)), params=(("SIN_W", 12),),
          note="pulse (SIN_W 12)"),
    Proof("pulse_w16", "fv_pulse", "pulse.v", ("pulse.v",),
          (("bmc", 8), ("ind", 2)), params=(("SIN_W", 16),),
          note="pulse (SIN_W 16)"),
    Proof("core_sticky", "fv_core_sticky", "core_sticky.v", ("finequad_core.v",),
          (("bmc", 8), ("ind", 2), ("cover", 6)), lib=("*",), cut="c:u_core.u_*",
          note="finequad_core's sticky fault register (FAULT_STICKY, W1C) and its "
               "read-back; every submodule cut"),
]

MODES = ("bmc", "ind", "cover")
PROBE_RE = re.compile(r'\(\*\s*fv_probe\s*=\s*"([^"]+)"\s*\*\)\s*wire\s+(?:signed\s+)?'
                      r'(?:\[[^\]]*\]\s*)?(\w+)')


def tools():
    """Paths of yosys, yosys-smtbmc, z3, or exit 2 naming what is missing."""
    found = {t: shutil.which(t) for t in ("yosys", "yosys-smtbmc", "z3")}
    missing = [t for t, p in found.items() if not p]
    if missing:
        sys.stderr.write("formal: error: %s not found on PATH; the formal proofs need Yosys "
                         "(with yosys-smtbmc) and z3: run scripts/install.sh (Debian: "
                         "apt-get install yosys z3)\n" % ", ".join(missing))
        sys.exit(2)
    return found


def yosys_script(p, rtl_dir, wrap_dir, smt2):
    wrapper = wrap_dir / p.wrapper
    probes = PROBE_RE.findall(wrapper.read_text())
    lines = []
    full = [rtl_dir / f for f in p.rtl]
    if p.lib:
        libs = sorted(f for f in rtl_dir.glob("*.v") if f.name not in p.rtl) \
            if p.lib == ("*",) else [rtl_dir / f for f in p.lib]
        for f in libs:
            lines.append("read_verilog -lib %s" % f)
    for f in full + [wrapper]:
        lines.append("read_verilog -formal %s" % f)
    for k, v in p.params:
        lines.append("chparam -set %s %s %s" % (k, v, p.top))
    lines.append("hierarchy -check -top %s" % p.top)
    lines.append("proc")
    lines.append("flatten")
    if p.cut:
        lines.append("cutpoint %s/%s" % (p.top, p.cut))
    for target, wire in probes:
        lines.append("connect -set %s %s" % (wire, target))
    lines += ["prep -top %s" % p.top, "async2sync", "dffunmap",
              "write_smt2 -wires %s" % smt2]
    return "\n".join(lines) + "\n"


def tail_msgs(text, n=12):
    """The solver's message: assertion failures and the status, else the last lines."""
    keep = [ln for ln in text.splitlines()
            if re.search(r"failed|Assert|Unreached|cover|Status|ERROR|error", ln)]
    return "\n".join((keep or text.splitlines())[-n:])


def build_model(p, rtl_dir, wrap_dir, build, tool):
    """Yosys: wrapper + RTL -> build/formal/<proof>/model.smt2. Returns (smt2, secs, error)."""
    out = build / p.name
    out.mkdir(parents=True, exist_ok=True)
    smt2 = out / "model.smt2"
    if smt2.exists():
        smt2.unlink()
    ys = out / "model.ys"
    ys.write_text(yosys_script(p, rtl_dir, wrap_dir, smt2))
    t0 = time.monotonic()
    y = subprocess.run([tool["yosys"], "-q", "-l", str(out / "yosys.log"), "-s", str(ys)],
                       capture_output=True, text=True)
    secs = time.monotonic() - t0
    if y.returncode != 0 or not smt2.exists():
        return smt2, secs, "yosys: " + (tail_msgs(y.stdout + y.stderr)
                                        or "failed, see %s" % (out / "yosys.log"))
    return smt2, secs, ""


def run_check(p, mode, depth, smt2, tool):
    """One yosys-smtbmc run. Returns (ok, secs, message)."""
    out = smt2.parent
    cmd = [tool["yosys-smtbmc"], "-s", "z3", "-t", str(depth)]
    cmd += {"bmc": ["--presat"], "ind": ["-i"], "cover": ["-c"]}[mode]
    vcd = out / ("%s.vcd" % mode)
    if vcd.exists():
        vcd.unlink()
    if mode != "cover":
        cmd += ["--dump-vcd", str(vcd)]          # written only for a counterexample
    cmd.append(str(smt2))
    t = time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True)
    secs = time.monotonic() - t
    (out / ("%s.log" % mode)).write_text(r.stdout)
    ok = r.returncode == 0 and "Status: PASSED" in r.stdout
    msg = ""
    if not ok:
        msg = tail_msgs(r.stdout) or r.stderr.strip()[-2000:]
        if vcd.exists():
            msg += "\ncounterexample: %s" % (vcd.relative_to(ROOT)
                                             if vcd.is_relative_to(ROOT) else vcd)
    return ok, secs, msg


def main(argv=None):
    ap = argparse.ArgumentParser(description="formal proofs of the finequad RTL "
                                 "(Yosys + yosys-smtbmc + z3)")
    ap.add_argument("proofs", nargs="*", help="proof names (default: all)")
    ap.add_argument("-j", "--jobs", type=int, default=2, help="parallel checks (default 2)")
    ap.add_argument("--rtl", default=str(ROOT / "rtl"), help="RTL folder (default rtl/)")
    ap.add_argument("--wrappers", default=str(ROOT / "sim" / "formal"),
                    help="wrapper folder (default sim/formal/)")
    ap.add_argument("--build", default=str(ROOT / "build" / "formal"),
                    help="work folder (default build/formal/)")
    ap.add_argument("--json", help="also write the results to this JSON file")
    ap.add_argument("--list", action="store_true", help="list the proofs and exit")
    a = ap.parse_args(argv)
    if a.list:
        for p in PROOFS:
            print("%-14s %-26s %s" % (p.name, " ".join("%s:%d" % c for c in p.checks), p.note))
        return 0
    names = {p.name: p for p in PROOFS}
    bad = [n for n in a.proofs if n not in names]
    if bad or a.jobs < 1:
        sys.stderr.write("formal: error: %s\n" % ("unknown proof(s) %s; known: %s"
                         % (", ".join(bad), ", ".join(names)) if bad else "--jobs must be >= 1"))
        return 2
    rtl_dir, wrap_dir = pathlib.Path(a.rtl).resolve(), pathlib.Path(a.wrappers).resolve()
    for d in (rtl_dir, wrap_dir):
        if not d.is_dir():
            sys.stderr.write("formal: error: folder '%s' not found\n" % d)
            return 2
    tool = tools()
    build = pathlib.Path(a.build).resolve()
    todo = [names[n] for n in a.proofs] if a.proofs else PROOFS
    t0 = time.monotonic()
    word = {"bmc": "bounded", "ind": "k-induction", "cover": "cover"}
    results = []

    def report(r):
        results.append(r)
        print("%s %-14s %-11s depth %2d %6.1f s" % ("PASS" if r["ok"] else "FAIL", r["proof"],
              word[r["mode"]], r["depth"], r["seconds"]), flush=True)
        if not r["ok"]:
            print("    " + r["message"].replace("\n", "\n    "), flush=True)

    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as ex:
        models = list(ex.map(lambda p: build_model(p, rtl_dir, wrap_dir, build, tool), todo))
        futs = []
        for p, (smt2, ty, err) in zip(todo, models):
            for mode, depth in p.checks:
                if err:
                    futs.append((p, mode, depth, None, (False, ty, err)))
                else:
                    futs.append((p, mode, depth,
                                 ex.submit(run_check, p, mode, depth, smt2, tool), None))
        for p, mode, depth, fut, res in futs:
            ok, secs, msg = fut.result() if fut else res
            report(dict(proof=p.name, mode=mode, depth=depth, ok=ok,
                        seconds=round(secs, 2), message=msg))
    fails = [r for r in results if not r["ok"]]
    print("formal: %d check(s), %d failed, %.1f s" % (len(results), len(fails),
                                                       time.monotonic() - t0))
    if a.json:
        pathlib.Path(a.json).write_text(json.dumps(results, indent=1) + "\n")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
