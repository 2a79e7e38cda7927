#!/usr/bin/env python3
"""Run the bit-true model on a CSV of ADC codes (same interface as `make rtlsim`).

    python3 -m sim.run_model --in in.csv --out out.csv [--table exact|paper] [--div D]
        [--adc-w W] [--engine-lanes L] [--opt-harmonic 0|1] [--opt-monitor 0|1]
        [--opt-jump 0|1] [--opt-dcode 0|1] [--opt-tunable 0|1] [--<setting> N ...] [--home] [--vcd ref.vcd]

The settings (--interp, --eps, --lambda-k, --count-mode, --ab-sep, --ref-q, ...) are the
register fields of rtl/regs/finequad.rdl, as the RTL harness takes them; those not given
keep their reset values. --home: homing armed from the start (the harness writes REF
with its pulse REF.home = 1 after the other settings).

Input: 'u1,u2' or 'u1,u2,ref' (ref: the reference comparator's output of the sample, 0
or 1; without the column 0), read by the harness's rules (read_codes). Output: one row
per sample, 'count,a,b,fault,z,ref_count,homed,pos_valid' (COLUMNS; sim/README.md has
their timing).
"""
import argparse
import os
import pathlib
import re
import sys

import numpy as np

from sim.model import finequad_core as core
from sim.model import regs


# the name that starts every error message (sim/run_vhdl.py, the VHDL edition's rtlsim,
# reads and checks through this module as "rtlsim", the harness's name)
PROG = "model"


def die(msg: str):
    """Report bad input the way the RTL harness does: one line on stderr, exit code 2."""
    print(f"{PROG}: error: {msg}", file=sys.stderr)
    raise SystemExit(2)


# a field as the harness's strtol takes it (sim/harness/input.h parse_field): C
# white space, an optional sign, decimal digits, nothing after them
_FIELD = re.compile(rb"[ \t\n\v\f\r]*[+-]?[0-9]+")
# the largest --div, the harnesses' (sim/harness/input.h DIV_MAX: its one source)
DIV_MAX = int(re.search(r"#define DIV_MAX (\d+)", (pathlib.Path(__file__).parent / "harness"
                                                     / "input.h").read_text()).group(1))
LONG_MIN, LONG_MAX = -(1 << 63), (1 << 63) - 1      # the harness's strtol range
# the output's columns, as the harness writes them (sim/harness/harness.cpp): each the
# key of core.run's result of that name
COLUMNS = ("count", "a", "b", "fault", "z", "ref_count", "homed", "pos_valid")
HEADERS = (b"u1,u2", b"u1,u2,ref")                  # the input's two forms


def shown(b: bytes) -> str:
    """Bytes as the harness shows them: printable ASCII as is, others as \\xNN."""
    return "".join(chr(c) if 0x20 <= c < 0x7f else f"\\x{c:02x}" for c in b)


def _trim(line: bytes) -> bytes:
    """The harness's line rule: trailing CR, space and LF and leading spaces do not count."""
    return line.rstrip(b"\r \n").lstrip(b" ")


def _int_field(fld: bytes):
    """A field as the harness's strtol takes it (C white space, a sign, decimal digits), or
    None if it is not one; a value beyond any code or ref stands in for one of more than
    20 digits (Python's default conversion limit lies beyond that)."""
    if not _FIELD.fullmatch(fld):
        return None
    digits = fld.lstrip(b" \t\n\v\f\r+-").lstrip(b"0")
    return int(fld) if len(digits) <= 20 else 1 << 70


def read_codes(path: str, adc_w: int = 16):
    """Read a `u1,u2` or `u1,u2,ref` CSV of signed ADC codes (and the reference input, 0
    or 1) by the rules of the RTL harness (sim/harness/input.h read_csv: the same files
    are accepted and the same errors named, with the file and line). Returns u1, u2 (int64
    arrays) and ref (an int64 array, or None without the column: every sample's ref 0)."""
    lo, hi = -(1 << (adc_w - 1)), (1 << (adc_w - 1)) - 1
    if not os.path.exists(path):
        die(f"cannot open input '{path}': no such file")
    if not os.path.isfile(path):
        die(f"input '{path}' is not a regular file")
    try:
        with open(path, "rb") as f:
            lines = f.read().split(b"\n")
    except OSError as e:
        die(f"cannot open input '{path}': {e.strerror}")
    if lines[-1] == b"":
        lines.pop()                              # the final newline ends the last line
    if not lines:
        die(f"{path}:1: empty file (expected header 'u1,u2' or 'u1,u2,ref')")
    header = _trim(lines[0])
    if header not in HEADERS:
        die(f"{path}:1: header is '{shown(header)}', expected 'u1,u2' or 'u1,u2,ref'")
    has_ref = header == b"u1,u2,ref"
    u1, u2, ref = [], [], []
    for ln, raw in enumerate(lines[1:], start=2):
        line = _trim(raw)
        if not line:
            continue
        fields = line.split(b",")
        if not has_ref and len(fields) != 2:
            die(f"{path}:{ln}: expected two values 'u1,u2', got '{shown(line)}'")
        if has_ref and len(fields) != 3:
            die(f"{path}:{ln}: expected three values 'u1,u2,ref', got '{shown(line)}'")
        vals = []
        for name, fld in zip(("u1", "u2"), fields):
            fld = _trim(fld)
            v = _int_field(fld)
            if v is None:
                die(f"{path}:{ln}: {name}: not a decimal integer: '{shown(fld)}'")
            if not lo <= v <= hi:
                die(f"{path}:{ln}: {name}: code {shown(fld)} out of the signed {adc_w}-bit "
                    f"range [{lo}, {hi}]")
            vals.append(v)
        if has_ref:
            fld = _trim(fields[2])
            v = _int_field(fld)
            if v is None:
                die(f"{path}:{ln}: ref: not a decimal integer: '{shown(fld)}'")
            if v not in (0, 1):
                die(f"{path}:{ln}: ref: must be 0 or 1, got '{shown(fld)}'")
            ref.append(v)
        a, b = vals
        u1.append(a)
        u2.append(b)
    if not u1:
        die(f"{path}: no samples after the header")
    return (np.array(u1, dtype=np.int64), np.array(u2, dtype=np.int64),
            np.array(ref, dtype=np.int64) if has_ref else None)


def write_codes(path, u1, u2, ref=None):
    """The input CSV: 'u1,u2', or with ref (0 or 1 per sample) 'u1,u2,ref'."""
    with open(path, "w") as f:
        if ref is None:
            f.write("u1,u2\n")
            f.writelines(f"{a},{b}\n" for a, b in zip(u1, u2))
        else:
            if len(ref) != len(u1):
                raise ValueError(f"write_codes: {len(ref)} ref values for {len(u1)} samples")
            f.write("u1,u2,ref\n")
            f.writelines(f"{a},{b},{int(r)}\n" for a, b, r in zip(u1, u2, ref))


def write_result(path, res):
    """The output CSV of core.run's result, as the harness writes it (COLUMNS)."""
    cols = [np.asarray(res[c], dtype=np.int64).tolist() for c in COLUMNS]
    with open(path, "w") as f:
        f.write(",".join(COLUMNS) + "\n")
        f.writelines(",".join(map(str, row)) + "\n" for row in zip(*cols))


def bounded(text, opt, lo, hi, what=""):
    """A whole-number option within lo..hi, named as the harness names it
    (sim/harness/input.h parse_bounded): 'OPT: not a decimal integer: ...' or 'OPT: V is
    outside lo..hi (what)'."""
    raw = text.encode(errors="surrogateescape")
    if not _FIELD.fullmatch(raw):
        die(f"{opt}: not a decimal integer: '{shown(raw)}'")
    digits = raw.lstrip(b" \t\n\v\f\r+-").lstrip(b"0")
    v = int(raw) if len(digits) <= 20 else None         # (no digits limit to trip over)
    if v is None or not lo <= v <= hi:
        shown_v = v if v is not None and LONG_MIN <= v <= LONG_MAX else shown(raw)
        die(f"{opt}: {shown_v} is outside {lo}..{hi}" + (f" ({what})" if what else ""))
    return v


def setting_options():
    """The core's settings as options, as the RTL harness takes them (sim/harness/input.h
    Settings): --<field> for each field a register write stores, '_' written '-', except
    the coefficient bundle's (GAIN..C2)."""
    return {"--" + f.name.replace("_", "-"): f for f in regs.SETTINGS.values()
            if f.reg not in core.BUNDLE_REGS}


def register_writes(settings, home=False):
    """[(register name, word)] the harness writes for the given settings
    (sim/harness/input.h Settings::writes): each register a given setting is in, its
    other fields at their reset values, in the settings' order; with home (--home) REF
    last, with REF.home = 1."""
    out = []
    for name, f in regs.SETTINGS.items():
        if name not in settings or any(r == f.reg for r, _ in out) or (home and f.reg == "REF"):
            continue
        out.append((f.reg, regs.word(f.reg, **{g.name: settings.get(g.name, g.reset)
                                               for g in regs.SETTINGS.values()
                                               if g.reg == f.reg})))
    if home:
        out.append(("REF", regs.word("REF", home=1, **{
            g.name: settings.get(g.name, g.reset) for g in regs.SETTINGS.values()
            if g.reg == "REF"})))
    return out


def refused_write(settings, build, home=False):
    """The harness's error line when the core of `build` refuses a register write the
    given settings make (register_writes), or None."""
    for reg, word in register_writes(settings, home):
        if regs.illegal(reg, word, build):
            return (f"the core refused the write of {reg} = 0x{word:08x}: this build keeps "
                    "the register constant (rtl/regs/finequad.rdl requires; e.g. OPT_TUNABLE=0)")
    return None


def main(argv=None):
    ap = argparse.ArgumentParser(description="bit-true model of finequad_core")
    ap.add_argument("--in", dest="inp", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--table", choices=["exact", "paper"], default="exact",
                    help="TABLE_EXACT: exact (1) or the paper's table (0)")
    ap.add_argument("--div", default="36", metavar="D",
                    help=f"clocks per sample, 1..{DIV_MAX} (default 36)")
    ap.add_argument("--adc-w", type=int, default=16, help="ADC_W, 12..16")
    ap.add_argument("--vcd", help="write the reference VCD of the core's outputs")
    ap.add_argument("--engine-lanes", type=int, choices=[1, 2], default=1,
                    help="ENGINE_LANES: lanes of the estimator's RLS engine (default 1)")
    ap.add_argument("--opt-harmonic", type=int, choices=[0, 1], default=1,
                    help="OPT_HARMONIC: 0 = a core built without the harmonic compensation")
    ap.add_argument("--opt-monitor", type=int, choices=[0, 1], default=1,
                    help="OPT_MONITOR: 0 = a core built without the signal monitor's checks")
    ap.add_argument("--opt-jump", type=int, choices=[0, 1], default=1,
                    help="OPT_JUMP: 0 = a core built without the estimator's jump detector")
    ap.add_argument("--opt-dcode", type=int, choices=[0, 1], default=1,
                    help="OPT_DCODE: 0 = a core built without distance-coded marks")
    ap.add_argument("--opt-tunable", type=int, choices=[0, 1], default=1,
                    help="OPT_TUNABLE: 0 = a core whose tuning registers are constant (their "
                         "settings are refused, as that core refuses the writes)")
    opts = setting_options()
    for o, f in opts.items():
        # (a string: the value is checked below, with the harness's message)
        ap.add_argument(o, dest="set_" + f.name, metavar="N",
                        help=f"{f.reg}.{f.name}, {f.lo}..{f.hi} (reset {f.reset})")
    ap.add_argument("--home", action="store_true",
                    help="arm homing from the start (REF.home written after the settings): "
                         "the first reference latched sets the count to HOME (--home-count)")
    args = ap.parse_args(argv)
    settings = {}
    for o, f in opts.items():
        text = getattr(args, "set_" + f.name)
        if text is not None:
            settings[f.name] = bounded(text, o, f.lo, f.hi, f"{f.reg}.{f.name}")
    refused = refused_write(settings, dict(
        OPT_TUNABLE=args.opt_tunable, OPT_HARMONIC=args.opt_harmonic,
        OPT_MONITOR=args.opt_monitor, OPT_JUMP=args.opt_jump, OPT_DCODE=args.opt_dcode),
        args.home)
    if refused:
        die(refused)
    div = bounded(args.div, "--div", 1, DIV_MAX)
    if not 12 <= args.adc_w <= 16:
        die(f"--adc-w must be 12..16, got {args.adc_w}")
    # the outputs can be written: before the run, not after it
    for what, path in (("", args.out), ("the VCD ", args.vcd)):
        if path is None:
            continue
        try:
            with open(path, "a"):
                pass
        except OSError as e:
            die(f"cannot write {what}'{path}': {e.strerror}")
    u1, u2, ref = read_codes(args.inp, args.adc_w)
    cfg = core.Config(TABLE=args.table, div=div, ADC_W=args.adc_w,
                      ENGINE_LANES=args.engine_lanes, OPT_HARMONIC=args.opt_harmonic,
                      OPT_MONITOR=args.opt_monitor, OPT_JUMP=args.opt_jump,
                      OPT_DCODE=args.opt_dcode,
                      home_arm=args.home, **settings)
    res = core.run(u1, u2, cfg, trace=bool(args.vcd), ref=ref)
    try:
        write_result(args.out, res)
    except OSError as e:
        die(f"cannot write '{args.out}': {e.strerror}")
    if args.vcd:
        from sim import vcdref
        try:
            vcdref.write(args.vcd, res, cfg)
        except OSError as e:
            die(f"cannot write the VCD '{args.vcd}': {e.strerror}")


if __name__ == "__main__":
    main()
