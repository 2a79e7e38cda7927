#!/usr/bin/env python3
"""Run the bit-true model on a CSV of ADC codes (same interface as `make rtlsim`).

    python3 -m sim.run_model --in in.csv --out out.csv [--interp N] [--table exact|paper]
        [--div D] [--adc-w W] [--count-mode M] [--ab-sep S] [--ab-src 0|1]
        [--ab-bound B] [--vcd ref.vcd]
"""
import argparse
import os
import re
import sys

import numpy as np

from sim.model import core


def die(msg: str):
    """Report bad input the way the RTL harness does: one line on stderr, exit code 2."""
    print(f"model: error: {msg}", file=sys.stderr)
    raise SystemExit(2)


# a field as the harness's strtol takes it (sim/harness/input.h parse_field): C
# white space, an optional sign, decimal digits, nothing after them
_FIELD = re.compile(rb"[ \t\n\v\f\r]*[+-]?[0-9]+")


def _trim(line: bytes) -> bytes:
    """The harness's line rule: trailing CR, space and LF and leading spaces do not count."""
    return line.rstrip(b"\r \n").lstrip(b" ")


def read_codes(path: str, adc_w: int = 16):
    """Read a `u1,u2` CSV of signed ADC codes by the rules of the RTL harness
    (sim/harness/input.h read_csv: the same files are accepted and the same errors
    named, with the file and line)."""
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
        die(f"{path}:1: empty file (expected header 'u1,u2')")
    # bytes as the harness shows them: printable ASCII as is, others as \xNN
    show = lambda b: "".join(chr(c) if 0x20 <= c < 0x7f else f"\\x{c:02x}"   # noqa: E731
                             for c in b)
    if _trim(lines[0]) != b"u1,u2":
        die(f"{path}:1: header is '{show(_trim(lines[0]))}', expected 'u1,u2'")
    u1, u2 = [], []
    for ln, raw in enumerate(lines[1:], start=2):
        line = _trim(raw)
        if not line:
            continue
        fields = line.split(b",")
        if len(fields) != 2:
            die(f"{path}:{ln}: expected two values 'u1,u2', got '{show(line)}'")
        vals = []
        for name, fld in zip(("u1", "u2"), fields):
            fld = _trim(fld)
            if not _FIELD.fullmatch(fld):
                die(f"{path}:{ln}: {name}: not a decimal integer: '{show(fld)}'")
            v = int(fld)
            if not lo <= v <= hi:
                die(f"{path}:{ln}: {name}: code {show(fld)} out of the signed {adc_w}-bit "
                    f"range [{lo}, {hi}]")
            vals.append(v)
        a, b = vals
        u1.append(a)
        u2.append(b)
    if not u1:
        die(f"{path}: no samples after the header")
    return np.array(u1, dtype=np.int64), np.array(u2, dtype=np.int64)


def write_codes(path, u1, u2):
    with open(path, "w") as f:
        f.write("u1,u2\n")
        f.writelines(f"{a},{b}\n" for a, b in zip(u1, u2))


def write_result(path, res):
    with open(path, "w") as f:
        f.write("count,a,b,fault\n")
        f.writelines(f"{c},{a},{b},{x}\n" for c, a, b, x in
                     zip(res["count"], res["a"], res["b"], res["fault"]))


def main(argv=None):
    ap = argparse.ArgumentParser(description="bit-true model of finequad_core")
    ap.add_argument("--in", dest="inp", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--interp", type=int, default=100)
    ap.add_argument("--table", choices=["exact", "paper"], default="exact")
    ap.add_argument("--div", type=int, default=36, help="clocks per sample (default 36)")
    ap.add_argument("--adc-w", type=int, default=16, help="ADC word width, 12..16")
    ap.add_argument("--count-mode", type=int, default=0,
                    help="counter mode (CTRL bit 3): 0 phase (default), 1 edge (x4 of A/B)")
    ap.add_argument("--ab-sep", type=int, default=4,
                    help="ABGEN: minimum clocks between A/B edges, 0..255 (default 4)")
    ap.add_argument("--ab-src", type=int, default=0,
                    help="ABGEN bit 8: 1 = the A/B pins show the Eq. 12 pulses")
    ap.add_argument("--ab-bound", type=int, default=1024,
                    help="AB_BOUND: A/B backlog bound in counts, 0..65535 (default 1024)")
    ap.add_argument("--vcd", help="write the reference VCD of the core's outputs")
    ap.add_argument("--lanes", type=int, choices=[1, 2], default=1,
                    help="lanes of the estimator's RLS engine (ENGINE_LANES; default 1)")
    ap.add_argument("--harmonic", type=int, choices=[0, 1], default=1,
                    help="OPT_HARMONIC: 0 = a core built without the harmonic compensation")
    ap.add_argument("--monitor", type=int, choices=[0, 1], default=1,
                    help="OPT_MONITOR: 0 = a core built without the signal monitor's checks")
    ap.add_argument("--jump", type=int, choices=[0, 1], default=1,
                    help="OPT_JUMP: 0 = a core built without the estimator's jump detector")
    args = ap.parse_args(argv)
    if not 1 <= args.interp <= 511:
        die(f"--interp must be 1..511, got {args.interp}")
    if not 12 <= args.adc_w <= 16:
        die(f"--adc-w must be 12..16, got {args.adc_w}")
    if args.count_mode not in (0, 1):
        die(f"--count-mode must be 0 or 1, got {args.count_mode}")
    if not 0 <= args.ab_sep <= 255:
        die(f"--ab-sep must be 0..255 (clocks), got {args.ab_sep}")
    if args.ab_src not in (0, 1):
        die(f"--ab-src must be 0 or 1, got {args.ab_src}")
    if not 0 <= args.ab_bound <= 65535:
        die(f"--ab-bound must be 0..65535 (counts), got {args.ab_bound}")
    u1, u2 = read_codes(args.inp, args.adc_w)
    if args.div < 1:
        die(f"--div must be >= 1, got {args.div}")
    cfg = core.Config(TABLE=args.table, interp=args.interp, div=args.div, ADC_W=args.adc_w,
                      count_mode=args.count_mode, ab_sep=args.ab_sep, ab_src=args.ab_src,
                      ab_bound=args.ab_bound, ENGINE_LANES=args.lanes,
                      OPT_HARMONIC=args.harmonic, OPT_MONITOR=args.monitor,
                      OPT_JUMP=args.jump)
    res = core.run(u1, u2, cfg, trace=bool(args.vcd))
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
