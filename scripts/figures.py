#!/usr/bin/env python3
"""The headline figures: written by the commands that measure them, never typed.

    python3 scripts/figures.py [--check]          (make test runs --check)

A measuring command (`make bench-accuracy`, `make bench-accuracy EDITION=vhdl`, `make demo`,
`make report`) calls publish() when its run is complete: scripts/results/<name>.json gets
the headline numbers with the date and the command, scripts/results/<name>.md the
command's full table under a line naming both, and README.md's block between the markers
BEGIN and END (HTML comments) is rendered again from every record. --check fails when
that block differs from the rendering of the committed records (an edit by hand, a
record without its README), or when a record is stale: the VHDL edition's accuracy record
was compared with a Verilog table other than the one committed (stale()).
"""
import argparse
import datetime
import hashlib
import json
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
RESULTS = ROOT / "scripts" / "results"
README = ROOT / "README.md"
BEGIN = "<!-- figures:begin (scripts/figures.py writes this block; do not edit) -->"
END = "<!-- figures:end -->"
# the records, in table order; each renders its rows
ORDER = ("bench_accuracy", "bench_accuracy_vhdl", "demo", "report")


class FiguresError(Exception):
    """A record or the README is not as this script needs it; the message says where."""


# the VHDL edition's record says whether its accuracy table is the Verilog edition's
SAME_AS_VERILOG = {True: "identical to", False: "NOT the same as"}


def table(name, results=RESULTS):
    """The full table of record `name` as publish() wrote it (without the line naming its
    command and date), or None if there is no such record."""
    p = results / f"{name}.md"
    if not p.is_file():
        return None
    head, sep, body = p.read_text().partition("\n\n")
    if not (sep and head.startswith("Measured with `")):
        raise FiguresError(f"{p}: not a table publish() wrote (its first line is not "
                           "'Measured with `<command>` on <date>.')")
    return body


def sha256(text):
    return hashlib.sha256(text.encode()).hexdigest()


def stale(results=RESULTS):
    """What a committed record claims about another that no longer holds: the VHDL
    edition's accuracy record names (sha256) the Verilog table it was compared with."""
    out = []
    for rec, _ in records(results):
        want = rec["headline"].get("verilog_table_sha256")
        if want is None:
            continue
        t = table("bench_accuracy", results)
        if t is None or sha256(t) != want:
            out.append(f"{rec['name']}.json was compared with a Verilog accuracy table that "
                       "is no longer scripts/results/bench_accuracy.md: run `"
                       f"{rec['command']}` again")
    return out


def publish(name, command, headline, table_md, results=RESULTS, readme=README):
    """Record a complete run of `command` (its headline numbers, a dict, and its full
    Markdown table) and render README.md's block again."""
    if name not in ORDER:
        raise FiguresError(f"unknown record '{name}' (one of {', '.join(ORDER)})")
    results.mkdir(parents=True, exist_ok=True)
    date = datetime.datetime.now(datetime.timezone.utc).date().isoformat()
    rec = {"name": name, "command": command, "date": date, "headline": headline}
    (results / f"{name}.json").write_text(json.dumps(rec, indent=1) + "\n")
    (results / f"{name}.md").write_text(f"Measured with `{command}` on {date}.\n\n"
                                        + table_md.rstrip() + "\n")
    write_readme(results, readme)
    return rec


def _rows_bench(h):
    return [("Accuracy: RMS error / the physical floor (METHOD.md), "
             f"{h['scenarios']} scenarios", f"{h['ratio_min']:.3f} to {h['ratio_max']:.3f}; "
             f"{h['slips']} slips; RTL == model on {h['rtl_equal']} of {h['scenarios']}"
             + (f"; constant parameters: at most {h['offline_max']:.3f} x the offline fit's "
                "RMS" if "offline_max" in h else ""))]


def _rows_bench_vhdl(h):
    return [("Accuracy through the VHDL edition (rtl/vhdl/, GHDL), "
             f"{h['scenarios']} scenarios", f"VHDL == model on {h['rtl_equal']} of "
             f"{h['scenarios']}; {h['ratio_min']:.3f} to {h['ratio_max']:.3f} x the floor; "
             f"{h['slips']} slips; table {SAME_AS_VERILOG[h['same_as_verilog']]} the "
             "Verilog edition's")]


def _rows_demo(h):
    return [("Demo recording (4 um pitch, n = 100, 1 MS/s, 0.5 % noise): counter error",
             f"{h['rms_nm']:.2f} nm RMS = {h['ratio']:.3f} x the floor; RTL == model: "
             f"{'yes' if h['rtl_equals_model'] else 'NO'}")]


def _rows_report(h):
    rows = []
    for dev in ("ice40_up5k", "ecp5_25f"):
        d = h.get(dev)
        if d:
            rows.append((f"{d['title']}: Fmax (median of {d['seeds']} seeds), logic, "
                         "estimator updates",
                         f"{d['fmax_mhz']:.2f} MHz, {d['luts']} {d['lut_unit']} "
                         f"({d['luts_pct']:.1f} %), {d['rls_updates_msps']:.3f} M/s"))
    if h.get("latency_cycles") is not None:
        rows.append(("Latency, sample to count and A/B; samples per clock",
                     f"{h['latency_cycles']} clocks; {h['samples_per_clock']:g}"))
    if h.get("sim_samples_per_s") is not None:
        rows.append(("Simulation speed (make rtlsim, Verilator)",
                     f"{h['sim_samples_per_s'] / 1e3:.0f} k samples per CPU second"))
    return rows


ROWS = {"bench_accuracy": _rows_bench, "bench_accuracy_vhdl": _rows_bench_vhdl,
        "demo": _rows_demo, "report": _rows_report}


def records(results=RESULTS):
    out = []
    for name in ORDER:
        p = results / f"{name}.json"
        if not p.is_file():
            continue
        try:
            rec = json.loads(p.read_text())
            rows = ROWS[name](rec["headline"])
            out.append((rec, rows))
        except (ValueError, KeyError, TypeError) as e:
            raise FiguresError(f"{p}: not a record of {name} ({type(e).__name__}: {e})") \
                from None
    return out


def render(results=RESULTS):
    lines = [BEGIN, "", "| figure | value | command | measured |", "|---|---|---|---|"]
    for rec, rows in records(results):
        for what, value in rows:
            lines.append(f"| {what} | {value} | `{rec['command']}` "
                         f"([table](scripts/results/{rec['name']}.md)) | {rec['date']} |")
    lines += ["", END]
    return "\n".join(lines)


def _split(text, where):
    if text.count(BEGIN) != 1 or text.count(END) != 1 or text.index(BEGIN) > text.index(END):
        raise FiguresError(f"{where}: expected one block from '{BEGIN}' to '{END}'")
    a = text.index(BEGIN)
    b = text.index(END) + len(END)
    return text[:a], text[a:b], text[b:]


def write_readme(results=RESULTS, readme=README):
    head, _, tail = _split(readme.read_text(), readme)
    readme.write_text(head + render(results) + tail)


def check(results=RESULTS, readme=README):
    """README.md's block is the rendering of the records, and no record is stale."""
    _, block, _ = _split(readme.read_text(), readme)
    return block == render(results) and not stale(results)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--check", action="store_true",
                    help="exit 1 if README.md's figures block is not the records' rendering")
    a = ap.parse_args(argv)
    try:
        if a.check:
            if not check():
                for why in stale() or ["README.md's figures block differs from "
                                       "scripts/results/*.json (run python3 "
                                       "scripts/figures.py)"]:
                    print(f"figures: error: {why}", file=sys.stderr)
                return 1
            print(f"checked README.md's figures block against {len(records())} records")
        else:
            write_readme()
            print(f"wrote README.md's figures block from {len(records())} records")
    except FiguresError as e:
        print(f"figures: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
