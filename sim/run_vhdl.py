#!/usr/bin/env python3
"""`make rtlsim EDITION=vhdl`: the VHDL edition's finequad_core under GHDL, with the
contract of the Verilator harness (sim/harness/harness.cpp).

    python3 -m sim.run_vhdl --in in.csv --out out.csv [--div D] [--<setting> N ...]
        [--home] [--vcd out.vcd] [--dump-regs] [-g NAME=VALUE ...] [--build DIR]
        [--extra FILE.vhd ...]

The input CSV ('u1,u2' or 'u1,u2,ref'), the settings (--interp, --eps, ... --home) and
the output CSV ('count,a,b,fault,z,ref_count,homed,pos_valid', one row per sample) are
the harness's, with its timing and error messages ('rtlsim: error: ...', exit status 2):
the input is read, the options checked and the settings turned into register writes by
the code the model uses (sim/run_model.py read_codes, bounded, setting_options,
register_writes), so there is one source of each rule. This front end writes them into
a plain stimulus file that the VHDL bench sim/harness/harness.vhd reads (its header
says the format); the bench writes the output CSV itself.

-g NAME=VALUE: finequad_core's generics as the bench takes them (the knobs of make
rtlsim: TABLE_EXACT, ADC_W, ENGINE_LANES, OPT_...); ADC_W also sets the input's code
range. --build: GHDL's work library (the edition of rtl/vhdl/sources.f and the bench,
analysed again when a file changed); --extra: further VHDL files analysed after those
(e.g. a stand-in finequad_core while the edition has none). GHDL's back end: the
fastest installed unless GHDL_BACKEND is set (as cocotb_tests/fqtb.py setup_paths).
--vcd: GHDL's VCD of the whole bench (edge e at e * 27778 + 13889 ps: the bench's
header says why; scripts/vcdcompare.py --rtl-edge0-ps 13889 compares it).
"""
import argparse
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

from sim import ghdl, run_model
from sim.model import regs

ROOT = pathlib.Path(__file__).resolve().parents[1]
BENCH = ROOT / "sim" / "harness" / "harness.vhd"
TABLE_DIR = str(ROOT / "rtl" / "tables") + "/"
T0 = 32                     # the first strobe's edge (harness.cpp T0)
PERIOD_PS = 27778           # harness.cpp PERIOD_PS
# the bench's generics that are finequad_core's (harness.vhd), with their legal values
GENERICS = {"ADC_W": range(12, 17), "TABLE_EXACT": (0, 1), "ENGINE_LANES": (1, 2),
            **{k: (0, 1) for k in ("OPT_DISTRAM", "OPT_PHASE_4K", "OPT_PULSE_ADDR",
                                   "OPT_HARMONIC", "OPT_NTH_DSP", "OPT_TUNABLE",
                                   "OPT_MONITOR", "OPT_JUMP", "OPT_DCODE")}}
# --dump-regs: the counters and status harness.cpp reads back, in its order
DUMP_REGS = ("UPDATES", "JUMPS", "ILLEGAL", "FAULT_STICKY", "STATUS", "COUNT", "GAIN")


def die(msg):
    run_model.die(msg)


def vhdl_sources(extra=()):
    """The edition's files in GHDL's analysis order (rtl/vhdl/sources.f), the extra
    files, then the bench."""
    return ([ROOT / f for f in ghdl.vhdl_files()] + [pathlib.Path(f).resolve() for f in extra]
            + [BENCH])


def ghdl_env():
    """The environment for `ghdl`: GHDL_BACKEND the fastest back end installed, unless
    set (cocotb_tests/fqtb.py setup_paths picks it alike)."""
    env = dict(os.environ)
    if shutil.which("ghdl") is None:
        die("ghdl not found (scripts/install.sh installs ghdl-llvm)")
    backend = ghdl.fastest_backend()
    if backend:
        env.setdefault("GHDL_BACKEND", backend)
    return env


def parse_generic(text):
    """'NAME=VALUE' of -g: a generic of GENERICS and one of its values."""
    name, eq, value = text.partition("=")
    if not eq or name not in GENERICS:
        die(f"-g '{text}': expected NAME=VALUE with NAME one of {', '.join(GENERICS)}")
    legal = GENERICS[name]
    v = run_model.bounded(value, f"-g {name}", min(legal), max(legal))
    if v not in legal:
        die(f"-g {name}: {v} is not one of {', '.join(map(str, legal))}")
    return name, v


def write_stim(path, div, writes, reads, u1, u2, ref):
    """The bench's stimulus file (sim/harness/harness.vhd): 'div n_writes n_reads', the
    writes 'index word' (word in 8 hex digits), the reads 'index', the samples 'u1 u2 ref'."""
    with open(path, "w") as f:
        f.write(f"{div} {len(writes)} {len(reads)}\n")
        f.writelines(f"{i} {w:08x}\n" for i, w in writes)
        f.writelines(f"{i}\n" for i in reads)
        if ref is None:
            f.writelines(f"{a} {b} 0\n" for a, b in zip(u1.tolist(), u2.tolist()))
        else:
            f.writelines(f"{a} {b} {r}\n" for a, b, r in zip(u1.tolist(), u2.tolist(),
                                                               ref.tolist()))


def analyse(build, files, env):
    """GHDL's analysis of `files` into the work library `build`, again only when the list,
    a file's time stamp or the back end changed (the stamp file says which)."""
    build.mkdir(parents=True, exist_ok=True)
    stamp = build / "analysed"
    want = "\n".join([env.get("GHDL_BACKEND", "")] +
                     [f"{f} {f.stat().st_mtime_ns}" for f in files]) + "\n"
    if stamp.is_file() and stamp.read_text() == want:
        return
    for cf in build.glob("*.cf"):
        cf.unlink()
    stamp.unlink(missing_ok=True)
    r = subprocess.run(["ghdl", "-a", "--std=08", f"--workdir={build}"] + [str(f) for f in files],
                       cwd=build, env=env, capture_output=True, text=True)
    if r.returncode != 0:
        die(f"GHDL's analysis of the VHDL edition failed:\n{r.stderr.strip()}")
    stamp.write_text(want)


def main(argv=None):
    run_model.PROG = "rtlsim"           # the harness's name in every message
    ap = argparse.ArgumentParser(prog="rtlsim (VHDL edition, GHDL)",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--in", dest="inp", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--div", default="36", metavar="D",
                    help=f"clocks per sample, 1..{run_model.DIV_MAX} (default 36)")
    ap.add_argument("--vcd", help="GHDL's VCD of the run")
    ap.add_argument("--dump-regs", action="store_true",
                    help="after the last sample, 'regs: NAME=value ...' on stderr")
    ap.add_argument("--home", action="store_true",
                    help="arm homing from the start (REF.home written after the settings)")
    ap.add_argument("-g", dest="generics", action="append", default=[], metavar="NAME=VALUE",
                    help="a generic of finequad_core: " + ", ".join(GENERICS))
    ap.add_argument("--build", default=str(ROOT / "build" / "rtlsim_vhdl"),
                    help="GHDL's work library (default build/rtlsim_vhdl)")
    ap.add_argument("--extra", action="append", default=[], metavar="FILE.vhd",
                    help="a VHDL file analysed after rtl/vhdl/sources.f's")
    opts = run_model.setting_options()
    for o, f in opts.items():
        ap.add_argument(o, dest="set_" + f.name, metavar="N",
                        help=f"{f.reg}.{f.name}, {f.lo}..{f.hi} (reset {f.reset})")
    args = ap.parse_args(argv)

    generics = dict(parse_generic(g) for g in args.generics)
    adc_w = generics.get("ADC_W", 16)
    settings = {}
    for o, f in opts.items():
        text = getattr(args, "set_" + f.name)
        if text is not None:
            settings[f.name] = run_model.bounded(text, o, f.lo, f.hi, f"{f.reg}.{f.name}")
    div = run_model.bounded(args.div, "--div", 1, run_model.DIV_MAX)
    writes = [(regs.REGS[r].index, w) for r, w in run_model.register_writes(settings, args.home)]
    if T0 < len(writes) + 1:
        die("internal: the register writes run into the first strobe")
    reads = [regs.REGS[r].index for r in DUMP_REGS] if args.dump_regs else []
    for extra in args.extra:
        if not os.path.isfile(extra):
            die(f"--extra '{extra}': no such file")
    files = vhdl_sources(args.extra)
    for f in files:
        if not f.is_file():
            die(f"{f}: no such file (rtl/vhdl/sources.f lists it)")
    # the outputs can be written: before the run (the harness opens them first too)
    for what, path in (("the VCD ", args.vcd), ("", args.out)):
        if path is None:
            continue
        try:
            with open(path, "w"):
                pass
        except OSError as e:
            die(f"cannot write {what}'{path}': {e.strerror}")
    u1, u2, ref = run_model.read_codes(args.inp, adc_w)
    if not any(re.search(r"^\s*entity\s+finequad_core\s+is\b", f.read_text(errors="replace"),
                         re.I | re.M) for f in files):
        die("the VHDL edition has no entity finequad_core yet (rtl/vhdl/finequad_core.vhd, "
            "listed in rtl/vhdl/sources.f; or give a stand-in with --extra, make's VHDL_EXTRA=)")

    env = ghdl_env()
    build = pathlib.Path(args.build).resolve()
    analyse(build, files, env)
    with tempfile.TemporaryDirectory(dir=build, prefix="run_") as tmp:
        stim, status = pathlib.Path(tmp) / "stim.txt", pathlib.Path(tmp) / "status.txt"
        write_stim(stim, div, writes, reads, u1, u2, ref)
        out = os.path.abspath(args.out)
        # (the generics as run options: the mcode back end takes them there only, the
        # compiling ones there too)
        cmd = (["ghdl", "--elab-run", "--std=08", f"--workdir={build}", "harness",
                f"-gSTIM={stim}", f"-gOUT_CSV={out}", f"-gOUT_STATUS={status}",
                f"-gTABLE_DIR={TABLE_DIR}"]
               + [f"-g{k}={v}" for k, v in generics.items()]
               + ["--ieee-asserts=disable-at-0"]
               + ([f"--vcd={os.path.abspath(args.vcd)}"] if args.vcd else []))
        # (in a folder of its own: a compiling back end writes the executable there)
        r = subprocess.run(cmd, cwd=tmp, env=env, capture_output=True, text=True)
        lines = status.read_text().split("\n") if status.is_file() else []
        refused = [ln.split()[1] for ln in lines if ln.startswith("refused ")]
        if refused:
            index, word = writes[int(refused[0])]
            name = next(n for n, g in regs.REGS.items() if g.index == index and g.write)
            os.remove(out)
            die(f"the core refused the write of {name} = 0x{word:08x}: this build keeps "
                "the register constant (rtl/regs/finequad.rdl requires; e.g. OPT_TUNABLE=0)")
        if r.returncode != 0:
            die(f"GHDL's run of the bench failed (exit status {r.returncode}):\n"
                f"{(r.stderr or r.stdout).strip()}")
        if args.dump_regs:
            vals = [int(ln.split()[1], 16) for ln in lines if ln.startswith("rdata ")]
            if len(vals) != len(DUMP_REGS):
                die(f"internal: {len(vals)} registers read back, expected {len(DUMP_REGS)}")
            print("regs: " + " ".join(f"{n}={v}" for n, v in zip(DUMP_REGS, vals)),
                  file=sys.stderr)


if __name__ == "__main__":
    main()
