#!/usr/bin/env python3
"""Write the $readmemh files of the RTL from sim/model (tables and estimator microcode).

    python3 scripts/gen_tables.py [--out rtl/tables] [--check]

--check compares instead of writing and exits 1 if a committed file is stale.
"""
import argparse
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from sim.model import program, tables  # noqa: E402

SIN_WIDTHS = (8, 10, 12, 16)


ROM_AW = 9   # rtl/rls_engine.v ROM_AW


def files() -> dict:
    if len(program.ROM) > (1 << ROM_AW):
        sys.exit(f"gen_tables: error: estimator ROM of {len(program.ROM)} words exceeds "
                 f"2**ROM_AW = {1 << ROM_AW} (rtl/rls_engine.v)")
    out = {}
    for kind in tables.KINDS:
        out[f"phase_{kind}.hex"] = tables.hexlines(tables.phase_table(kind), tables.PHT_W)
    out["recip.hex"] = tables.hexlines(tables.recip_table(), tables.RCP_W)
    for w in SIN_WIDTHS:
        out[f"sine_{w}.hex"] = tables.hexlines(tables.sine_table(w), w)
    out["seeds.hex"] = tables.hexlines(tables.seed_recip() + tables.seed_isqrt(), 16)
    rom = program.ROM + [0] * ((1 << ROM_AW) - len(program.ROM))
    out["rls_program.hex"] = tables.hexlines(rom, program.ROM_W)
    out["rls_regfile.hex"] = tables.hexlines(program.RF_INIT, 32)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(pathlib.Path(__file__).resolve().parents[1]
                                         / "rtl" / "tables"))
    ap.add_argument("--check", action="store_true")
    args = ap.parse_args()
    d = pathlib.Path(args.out)
    stale = []
    for name, text in files().items():
        p = d / name
        if args.check:
            if not p.exists() or p.read_text() != text:
                stale.append(name)
        else:
            d.mkdir(parents=True, exist_ok=True)
            p.write_text(text)
    if stale:
        sys.exit(f"stale tables in {d}: {', '.join(stale)} (run scripts/gen_tables.py)")
    print(f"{'checked' if args.check else 'wrote'} {len(files())} tables in {d}; "
          f"estimator ROM {len(program.ROM)} words, entries {program.ENTRY}")


if __name__ == "__main__":
    main()
