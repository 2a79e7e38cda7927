#!/usr/bin/env python3
"""Compare signals of two VCD files over time and report the first divergence.

    python3 scripts/vcdcompare.py RTL.vcd REF.vcd [--signals a,b,...]
        [--map REF_PREFIX=RTL_PREFIX ...] [--strict-x] [--period-ps P] [--max-report N]
        [--cycle [--rtl-edge0-ps T]] [--skip-missing]

Signals are matched by hierarchical name (scopes joined with '.'; a trailing bit range
such as [31:0] is ignored, so 'm_count' and 'm_count [31:0]' match). The default set is
every signal of the reference file; --signals takes reference names, full or as a unique
dotted suffix ('m_count', 'u_lut.phase_o'). --map rewrites a reference-name prefix into the
RTL's (repeatable, longest prefix wins), e.g. --map TOP.finequad_core=finequad_core for a
VCD whose root is the core itself.

Value-at-time semantics: for each signal, at every time at which either file records a
change, the values both files hold at that time (the last change at or before it) must be
equal, so waveforms that only differ in redundant re-dumps compare equal. Times are
converted through each file's $timescale. Values compare as integers of the bits; x/z
bits are shown as such. Bits that are x or z in the reference are don't-care (the
SystemVerilog ==? convention: sim/vcdref.py writes 'x' where the model does not define a
value); --strict-x makes them match only an identical x/z bit. An x/z bit in the RTL
never matches a 0/1 in the reference.

Per clock (--cycle, with --period-ps): the files are compared once per clock period, at
a quarter period after each rising edge (edge e of the reference at e * P, of the RTL at
T + e * P with --rtl-edge0-ps T): the value each holds there, whenever within the period
it changed. For traces of one design from benches that place their edges and input
changes differently, e.g. GHDL's VCD of the VHDL edition (sim/harness/harness.vhd: edge
e at e * P + P / 2, its inputs changed half a period earlier) against the model's or the
Verilator VCD (edge e at e * P, inputs changed with it). Times are then reported on the
reference's time line (edge e at e * P).

--skip-missing: reference signals the RTL VCD lacks are listed and left out instead of
being an error (another edition's internal signals, GHDL's VCD leaving out records and
arrays).

Exit status: 0 identical, 1 mismatch (first divergence: time, signal, RTL value, reference
value), 2 bad input (missing or unreadable file, signal not found, bad option).
Parsing uses vcdvcd.
"""
import argparse
import os
import re
import sys
from array import array
from decimal import Decimal

try:
    from vcdvcd import VCDVCD, StreamParserCallbacks
except ImportError:  # pragma: no cover
    sys.stderr.write("vcdcompare: error: the Python package 'vcdvcd' is not installed "
                     "(pip install vcdvcd, or use the project's .venv/bin/python)\n")
    sys.exit(2)

PROG = "vcdcompare"
_RANGE = re.compile(r"\[\s*-?\d+\s*:\s*-?\d+\s*\]$")
_FS = Decimal("1e-15")


class BadInput(Exception):
    """Bad input: exit status 2."""


def base_name(ref):
    """Reference name without a trailing bit range: 'a.b.x[31:0]' -> 'a.b.x'."""
    return _RANGE.sub("", ref).rstrip()


class Vcd:
    """One VCD file: header first (names, widths, timescale), value changes on demand."""

    def __init__(self, path, role):
        self.path, self.role = path, role
        if not os.path.isfile(path):
            raise BadInput(f"{role} VCD '{path}' does not exist or is not a file")
        if not os.access(path, os.R_OK):
            raise BadInput(f"{role} VCD '{path}' is not readable")
        if not self._has_enddefinitions():
            raise BadInput(f"{role} VCD '{path}' ends before $enddefinitions (a truncated "
                           "file, or not a VCD)")
        if self._ends_mid_line():
            raise BadInput(f"{role} VCD '{path}' ends in the middle of a line (a truncated "
                           "file)")
        hdr = self._parse(only_sigs=True)
        self.names = {}                       # base name -> full reference
        self.width = {}                       # full reference -> bits
        self.vtype = {}
        for ref in hdr.signals:
            sig = hdr.data[hdr.references_to_ids[ref]]
            self.names.setdefault(base_name(ref), ref)
            try:
                self.width[ref] = int(sig.size)
            except ValueError:
                raise BadInput(f"{path}: signal '{ref}' has a non-integer size '{sig.size}'")
            self.vtype[ref] = sig.var_type
        if not self.names:
            raise BadInput(f"{role} VCD '{path}' declares no signals (is it a VCD file?)")
        ts = hdr.timescale.get("timescale")
        self.ts_fs = None if ts is None else ts / _FS    # file time unit in fs (Decimal)
        self.unit = (f"{hdr.timescale['magnitude']} {hdr.timescale['unit']}"
                     if ts is not None else "(no $timescale)")
        self.uname = hdr.timescale.get("unit")           # 's' .. 'fs'
        self.ufs = (None if ts is None                   # one such unit in fs
                    else hdr.timescale["factor"] / _FS)
        self.tv = {}

    def _has_enddefinitions(self):
        """The header is complete (read in blocks up to the keyword: the header comes
        first, so a complete file is not read through)."""
        key, tail = b"$enddefinitions", b""
        with open(self.path, "rb") as f:
            while True:
                block = f.read(1 << 20)
                if not block:
                    return False
                if key in tail + block:
                    return True
                tail = block[-len(key):]

    def last_time(self):
        """The file's last timestamp (#t) in its own units, from its tail; None if the
        tail has none."""
        with open(self.path, "rb") as f:
            f.seek(0, os.SEEK_END)
            f.seek(max(0, f.tell() - (1 << 16)))
            for line in reversed(f.read().split(b"\n")):
                if line.startswith(b"#"):
                    try:
                        return int(line[1:].strip())
                    except ValueError:
                        return None
        return None

    def _ends_mid_line(self):
        with open(self.path, "rb") as f:
            f.seek(0, os.SEEK_END)
            if f.tell() == 0:
                return False
            f.seek(-1, os.SEEK_END)
            return f.read(1) != b"\n"

    def _parse(self, **kw):
        try:
            return VCDVCD(self.path, **kw)
        except (_Stop, BadInput):
            raise
        except (OSError, UnicodeDecodeError) as e:
            raise BadInput(f"cannot read {self.role} VCD '{self.path}': {e}")
        except Exception as e:   # vcdvcd raises plain exceptions on malformed input
            raise BadInput(f"cannot parse {self.role} VCD '{self.path}': "
                           f"{type(e).__name__}: {e}")

    def find(self, name):
        """Full reference of `name` (the full reference or its base name), or None."""
        if name in self.width:
            return name
        return self.names.get(base_name(name))

    def find_suffix(self, name):
        """Full references whose base name is `name` or ends with '.' + name."""
        b = base_name(name)
        hits = sorted({ref for base, ref in self.names.items()
                       if base == b or base.endswith("." + b)})
        return hits

    def normaliser(self, ref):
        """Function turning a vcdvcd value string of `ref` into a comparable value."""
        if self.vtype[ref] in ("real", "realtime", "shortreal"):
            return _norm_real
        w = self.width[ref]

        def norm(v):
            if len(v) > w:
                raise BadInput(f"{self.role} VCD '{self.path}': a value of {len(v)} bits for "
                               f"'{ref}', declared {w} bits wide")
            return _norm(v, w)
        return norm

    def load(self, refs, mult):
        """Store the value changes of refs in self.tv: {ref: (times, values)} in common
        time units (mult: this file's time -> common units, a factor or a function), the
        last change per time only. Collected through parser callbacks into compact arrays
        (repeated values shared), not vcdvcd's per-change tuples."""
        col = _Collect({r: self.normaliser(r) for r in refs}, mult)
        self._parse(signals=list(refs), store_tvs=False, callbacks=col)
        for ref in refs:
            self.tv[ref] = col.tv[col.ident[ref]]

    def stream(self, comparisons, mult, early=False):
        """Parse the whole file, feeding the value changes of the compared signals (this
        file's names: Comparison.rtl_name) to their Comparison objects; early: stop once
        the first divergence is settled. Returns the _Stream (tmax, stopped, limit)."""
        by_ref = {}
        for c in comparisons:
            by_ref.setdefault(c.rtl_name, []).append(c)
        cb = _Stream(by_ref, {r: self.normaliser(r) for r in by_ref}, mult, early)
        try:
            self._parse(signals=list(by_ref), store_tvs=False, callbacks=cb)
        except _Stop:
            pass
        cb.finish()
        return cb


def _last_known_time(ts, vs):
    """Time of the last change to a known value (not an x/z bit string), or None."""
    for k in range(len(ts) - 1, -1, -1):
        if not isinstance(vs[k], str):
            return int(ts[k])
    return None


def _norm(v, width):
    """VCD value string -> int if all bits known, else the bit string left-extended to the
    width (IEEE 1364 18.2.1: extend with 0 after 0/1, with x/z after x/z)."""
    v = v.lower()
    try:
        return int(v, 2)
    except ValueError:
        pass
    if any(c not in "01xz" for c in v):
        return v                               # not a bit string; compared as text
    if len(v) < width:
        v = ("0" if v[0] == "1" else v[0]) * (width - len(v)) + v
    return v


def _norm_real(v):
    try:
        return float(v)
    except ValueError:
        return v


def _bits(val, width):
    return val if isinstance(val, str) else format(val, f"0{width}b")


def match(rtl, ref, width, strict_x):
    """True if the RTL value satisfies the reference value."""
    if rtl == ref:
        return True
    if isinstance(ref, (int, float)) and isinstance(rtl, (int, float)):
        return False
    if isinstance(ref, float) or isinstance(rtl, float):
        return False
    if strict_x:
        return False
    a, b = _bits(rtl, width), _bits(ref, width)
    n = max(len(a), len(b))
    a = ("0" if a[0] == "1" else a[0]) * (n - len(a)) + a
    b = ("0" if b[0] == "1" else b[0]) * (n - len(b)) + b
    return all(rb in "xz" or ab == rb for ab, rb in zip(a, b))


def show(val, width):
    if val is None:
        return "x (no value yet)"
    if isinstance(val, float):
        return repr(val)
    if isinstance(val, int):
        if width == 1:
            return str(val)
        s = f"{val} (0x{val:0{(width + 3) // 4}x}"
        if width > 1 and val >> (width - 1):
            s += f", signed {val - (1 << width)}"
        return s + ")"
    if set(val) <= {"x"}:
        return "x"
    if set(val) <= {"z"}:
        return "z"
    return f"b{val}"


class Comparison:
    """One signal pair. The reference's changes are held in memory; the RTL's arrive in
    time order through rtl_change() (streamed from the parser), so the RTL file, usually
    the big one, is never stored. Both sides are compared at every time at which either
    records a change, with the value each holds at that time."""

    def __init__(self, ref_name, rtl_name, ref_tv, width, strict_x):
        self.ref_name, self.rtl_name = ref_name, rtl_name
        self.bt, self.bv = ref_tv               # reference change times and values
        self.j = 0
        self.width, self.strict_x = width, strict_x
        self.va = self.vb = None             # None: no value yet (x)
        self.first = None                    # (t, rtl value, ref value)
        self.bad = self.total = self.dc = 0

    def _check(self, t):
        self.total += 1
        va, vb = self.va, self.vb
        if va == vb and va is not None:
            return
        ra = "x" * self.width if va is None else va
        rb = "x" * self.width if vb is None else vb
        if ra == rb:
            return
        if match(ra, rb, self.width, self.strict_x):
            self.dc += 1
            return
        self.bad += 1
        if self.first is None:
            self.first = (t, va, vb)

    def rtl_change(self, t, v):
        """The RTL's value from time t on (the last change at t), times increasing."""
        bt, bv, j = self.bt, self.bv, self.j
        n = len(bt)
        while j < n and bt[j] < t:
            self.vb = bv[j]
            self.j = j = j + 1
            self._check(bt[j - 1])
        if j < n and bt[j] == t:
            self.vb = bv[j]
            self.j = j + 1
        self.va = v
        self._check(t)

    def finish(self, until=None):
        """Compare the reference's remaining changes (up to time `until`)."""
        bt, bv = self.bt, self.bv
        while self.j < len(bt) and (until is None or bt[self.j] <= until):
            self.vb = bv[self.j]
            self.j += 1
            self._check(bt[self.j - 1])


class _Collect(StreamParserCallbacks):
    """vcdvcd callbacks storing value changes per identifier code as (array of times,
    list of values)."""

    def __init__(self, norm_of_ref, mult):
        self.norm_of_ref, self.tmap = norm_of_ref, _tmap(mult)
        self.ident, self.norm, self.tv, self.cache = {}, {}, {}, {}

    def enddefinitions(self, vcd, signals, cur_sig_vals):
        for ref, norm in self.norm_of_ref.items():
            i = vcd.references_to_ids[ref]
            self.ident[ref] = i
            self.norm[i] = norm
            self.tv[i] = (array("q"), [])
            self.cache[i] = {}

    def value(self, vcd, time, value, identifier_code, cur_sig_vals):
        t = self.tmap(time)
        ts, vs = self.tv[identifier_code]
        cache = self.cache[identifier_code]
        v = cache.get(value)
        if v is None:
            v = self.norm[identifier_code](value)
            if len(cache) < 4096:            # share repeated values, bounded
                cache[value] = v
        if ts and ts[-1] == t:
            vs[-1] = v
        else:
            ts.append(t)
            vs.append(v)


def _tmap(mult):
    """A file's time -> common units: mult itself if a function, else time * mult."""
    if callable(mult):
        return mult
    return lambda t: t * mult


def _per_clock(m, period, edge0):
    """--cycle: a file's time (m common units each) -> the reference time of the clock
    sample it is seen at: edge e's sample lies at edge0 + e * period + period / 4 (in
    common units, Fractions), and a change at t is seen at the first sample at or after
    it, reported as the reference's edge time e * period."""
    from math import ceil
    off4, p4 = 4 * edge0 + period, 4 * period       # (in quarters: whole numbers mostly)
    if off4.denominator == 1 and period.denominator == 1:
        off4, p4, per = int(off4), int(p4), int(period)

        def tmap(t):                                 # e = ceil((4 t m - off4) / p4)
            return -((off4 - 4 * t * m) // p4) * per
        return tmap
    off = edge0 + period / 4

    def tmap_exact(t):
        return int(round(ceil((t * m - off) / period) * period))
    return tmap_exact


class _Stop(Exception):
    """Raised from the parser callbacks once the first divergence is settled."""


class _Stream(StreamParserCallbacks):
    """vcdvcd callbacks feeding the RTL's value changes to the comparisons; several
    changes of one signal at one time collapse to the last. With early=True, parsing
    stops as soon as the file has passed the earliest divergence found so far: by then
    every change at or before it has been compared, so it is the first divergence."""

    def __init__(self, by_ref, norm_of_ref, mult, early):
        self.by_ref, self.norm_of_ref, self.tmap = by_ref, norm_of_ref, _tmap(mult)
        self.early = early
        self.by_id, self.norm = {}, {}       # filled once the header is read
        self.pending = {}                    # id -> (t, normalised value)
        self.tmax = 0
        self.limit = None                    # earliest divergence so far
        self.stopped = False

    def enddefinitions(self, vcd, signals, cur_sig_vals):
        for ref, cs in self.by_ref.items():
            ident = vcd.references_to_ids[ref]
            self.by_id.setdefault(ident, []).extend(cs)
            self.norm[ident] = self.norm_of_ref[ref]

    def _feed(self, ident, p):
        for c in self.by_id[ident]:
            c.rtl_change(*p)
            if c.first is not None and (self.limit is None or c.first[0] < self.limit):
                self.limit = c.first[0]

    def time(self, vcd, time, cur_sig_vals):
        # called when a new timestamp starts, with the one that just ended
        if self.early and self.limit is not None and self.tmap(time) > self.limit:
            self.stopped = True
            raise _Stop()

    def value(self, vcd, time, value, identifier_code, cur_sig_vals):
        t = self.tmap(time)
        p = self.pending.get(identifier_code)
        if p is not None and p[0] != t:
            self._feed(identifier_code, p)
        self.pending[identifier_code] = (t, self.norm[identifier_code](value))
        if t > self.tmax:
            self.tmax = t

    def finish(self):
        until = self.limit if self.stopped else None
        for ident, p in self.pending.items():
            if until is None or p[0] <= until:
                self._feed(ident, p)
        for cs in self.by_id.values():
            for c in cs:
                c.finish(until)


def parse_args(argv):
    ap = argparse.ArgumentParser(
        prog="vcdcompare.py",
        description="Compare the signals of an RTL VCD with a reference VCD; exit 0 if "
                    "identical, 1 on mismatch, 2 on bad input.")
    ap.add_argument("rtl", metavar="RTL.vcd")
    ap.add_argument("ref", metavar="REF.vcd")
    ap.add_argument("--signals", help="comma-separated reference signal names (full or a "
                    "unique dotted suffix); default: every signal in REF.vcd")
    ap.add_argument("--map", action="append", default=[], metavar="REF_PREFIX=RTL_PREFIX",
                    help="rename a hierarchy prefix of reference names to the RTL's "
                         "(repeatable; longest prefix wins)")
    ap.add_argument("--strict-x", action="store_true",
                    help="x/z bits in the reference are not don't-care")
    ap.add_argument("--period-ps", type=float, metavar="P",
                    help="clock period in ps: also report times as clock edges")
    ap.add_argument("--max-report", type=int, default=10, metavar="N",
                    help="list up to N diverging signals (default 10)")
    ap.add_argument("--all", action="store_true",
                    help="read the whole RTL file even after a divergence, to list every "
                         "diverging signal with its count of mismatching change times "
                         "(default: stop once the first divergence is settled)")
    ap.add_argument("--cycle", action="store_true",
                    help="compare once per clock (needs --period-ps): the values a quarter "
                         "period after each rising edge, wherever in the period they changed")
    ap.add_argument("--rtl-edge0-ps", type=float, default=0.0, metavar="T",
                    help="with --cycle: the time of the RTL's first rising edge, edge 0 "
                         "(default 0; GHDL's VCD of sim/harness/harness.vhd: 13889)")
    ap.add_argument("--skip-missing", action="store_true",
                    help="list and leave out the reference signals the RTL VCD lacks "
                         "(default: an error)")
    ap.add_argument("-q", "--quiet", action="store_true", help="no output when identical")
    return ap.parse_args(argv)


def map_name(name, maps):
    best = None
    for src, dst in maps:
        if name == src or name.startswith(src + "."):
            if best is None or len(src) > len(best[0]):
                best = (src, dst)
    if best is None:
        return name
    src, dst = best
    rest = name[len(src):]
    return (dst + rest) if dst else rest.lstrip(".")


def main(argv=None):
    args = parse_args(argv)
    try:
        return run(args)
    except BadInput as e:
        sys.stderr.write(f"{PROG}: error: {e}\n")
        return 2


def run(args):
    maps = []
    for m in args.map:
        if "=" not in m:
            raise BadInput(f"--map '{m}': expected REF_PREFIX=RTL_PREFIX")
        src, dst = m.split("=", 1)
        maps.append((src.strip().rstrip("."), dst.strip().rstrip(".")))
    if args.max_report < 1:
        raise BadInput("--max-report must be >= 1")
    if args.cycle and args.period_ps is None:
        raise BadInput("--cycle needs --period-ps (the clock period)")
    if args.rtl_edge0_ps and not args.cycle:
        raise BadInput("--rtl-edge0-ps applies to --cycle only")
    if args.cycle and not 0 <= args.rtl_edge0_ps < 1e15:
        raise BadInput(f"--rtl-edge0-ps must be a time >= 0 in ps, got {args.rtl_edge0_ps}")
    if args.period_ps is not None and not 1e-3 <= args.period_ps <= 1e12:   # (not nan)
        raise BadInput(f"--period-ps must be 0.001..1e12 (a clock period in ps), got "
                       f"{args.period_ps}")
    rtl = Vcd(args.rtl, "RTL")
    ref = Vcd(args.ref, "reference")

    # ---- signal selection and matching -------------------------------------------------
    if args.signals:
        wanted = [s.strip() for s in args.signals.split(",") if s.strip()]
        if not wanted:
            raise BadInput("--signals is empty")
        ref_refs = []
        for s in wanted:
            r = ref.find(s)
            if r is None:
                hits = ref.find_suffix(s)
                if len(hits) > 1:
                    raise BadInput(f"signal '{s}' is ambiguous in reference VCD "
                                   f"'{ref.path}': {', '.join(hits)}")
                if not hits:
                    raise BadInput(f"signal '{s}' not found in reference VCD '{ref.path}'")
                r = hits[0]
            if r not in ref_refs:
                ref_refs.append(r)
    else:
        ref_refs = list(dict.fromkeys(ref.names.values()))
    pairs, missing = [], []
    for r in ref_refs:
        want = map_name(base_name(r), maps)
        q = rtl.find(want)
        if q is None and args.skip_missing:
            missing.append(want)
            continue
        if q is None:
            leaf = want.rsplit(".", 1)[-1]
            near = sorted(b for b in rtl.names if b.rsplit(".", 1)[-1] == leaf)[:5]
            hint = f"; signals with that leaf name: {', '.join(near)}" if near else ""
            hint += " (use --map REF_PREFIX=RTL_PREFIX if the hierarchy roots differ)"
            via = f" (reference '{r}' through --map)" if want != base_name(r) else ""
            raise BadInput(f"signal '{want}'{via} not found in RTL VCD '{rtl.path}'{hint}")
        if rtl.width[q] != ref.width[r]:
            sys.stderr.write(f"{PROG}: warning: width differs for {want}: RTL {rtl.width[q]} "
                             f"bits, reference {ref.width[r]} bits (compared as integers)\n")
        pairs.append((r, q))

    if missing:
        sys.stderr.write(f"{PROG}: note: {len(missing)} reference signal(s) not in the RTL VCD, "
                         f"not compared (--skip-missing): {', '.join(missing[:12])}"
                         + (" ..." if len(missing) > 12 else "") + "\n")
    if not pairs:
        raise BadInput(f"no reference signal of '{ref.path}' is in the RTL VCD "
                       f"'{rtl.path}' (--map REF_PREFIX=RTL_PREFIX if the hierarchy roots "
                       "differ)")

    # ---- time base -----------------------------------------------------------------------
    if rtl.ts_fs is None or ref.ts_fs is None:
        if not (rtl.ts_fs is None and ref.ts_fs is None):
            sys.stderr.write(f"{PROG}: warning: only one file has a $timescale; comparing "
                             "raw timestamps\n")
        m_rtl = m_ref = 1
        base_fs = None
    else:
        base = min(rtl.ts_fs, ref.ts_fs)
        if (rtl.ts_fs / base) % 1 or (ref.ts_fs / base) % 1:
            raise BadInput(f"timescales {rtl.unit} and {ref.unit} are not integer multiples")
        m_rtl, m_ref = int(rtl.ts_fs / base), int(ref.ts_fs / base)
        base_fs = base
    if args.cycle:
        if base_fs is None:
            raise BadInput("--cycle needs both files' $timescale")
        from fractions import Fraction
        period = Fraction(Decimal(str(args.period_ps)) * 1000 / base_fs)
        edge0 = Fraction(Decimal(str(args.rtl_edge0_ps)) * 1000 / base_fs)
        tm_rtl, tm_ref = (_per_clock(m_rtl, period, edge0),
                          _per_clock(m_ref, period, Fraction(0)))
        rtl_end_of = tm_rtl
    else:
        tm_rtl, tm_ref = m_rtl, m_ref
        rtl_end_of = (lambda t: t * m_rtl)
    ref.load({r for r, _ in pairs}, tm_ref)
    comps = [Comparison(r, q, ref.tv[r], max(rtl.width[q], ref.width[r]), args.strict_x)
             for r, q in pairs]
    st = rtl.stream(comps, tm_rtl, early=not args.all)
    tmax = max([st.tmax] + [int(ts[-1]) for ts, _ in ref.tv.values() if len(ts)])
    # the reference's last change to a known value (a change to x/z asks nothing of the
    # RTL, so a complete file may end before it)
    ref_known = max((t for t in (_last_known_time(ts, vs) for ts, vs in ref.tv.values())
                     if t is not None), default=None)
    rtl_end = rtl.last_time()
    if ref_known is not None and rtl_end is not None and rtl_end_of(rtl_end) < ref_known:
        raise BadInput(f"RTL VCD '{rtl.path}' ends at #{rtl_end}, before the "
                       "reference's last change ("
                       + (f"edge {ref_known / period:g}, per clock" if args.cycle
                          else f"#{ref_known // m_ref}")
                       + "): a truncated file, or a run that stopped early")

    def when(t):
        """Time t (in units of `base` fs, or raw ticks) as text in the RTL's time unit."""
        if base_fs is None:
            return f"t={t}"
        fs = Decimal(t) * base_fs
        u = fs / rtl.ufs
        s = f"t={u.normalize():f} {rtl.uname}"
        if args.period_ps:
            e, rem = divmod(float(fs / 1000), args.period_ps)
            s += f" (edge {int(e)}{'' if rem == 0 else f' + {rem:g} ps'})"
        return s

    # ---- report ----------------------------------------------------------------------------
    diverged = []
    for k, c in enumerate(comps):
        if c.first is not None:
            diverged.append((c.first[0], k, c.ref_name, c.rtl_name, c.width, c.first, c.bad))
    total = sum(c.total for c in comps)
    dc = sum(c.dc for c in comps)
    if not diverged:
        if not args.quiet:
            print(f"{PROG}: OK: {len(pairs)} signal(s) identical in '{args.rtl}' (RTL) and "
                  f"'{args.ref}' (reference) up to {when(tmax)}: {total} change times "
                  f"compared, {dc} against reference x/z (don't-care)")
        return 0
    diverged.sort()
    if st.stopped:      # later divergences were not all seen: keep the settled ones
        diverged = [d for d in diverged if d[0] == diverged[0][0]]
    t, _, r, q, w, (_, va, vb), bad = diverged[0]
    name = map_name(base_name(r), maps)
    print(f"{PROG}: MISMATCH: first divergence at {when(t)} in {name}")
    print(f"  RTL       {show(va, w)}   ({args.rtl}: {q})")
    print(f"  reference {show(vb, w)}   ({args.ref}: {r})")
    if st.stopped:
        print(f"  {len(diverged)} of {len(pairs)} signal(s) diverge at that time (stopped "
              f"reading there; --all lists every diverging signal):")
    else:
        print(f"  {len(diverged)} of {len(pairs)} signal(s) diverge; first divergence per "
              f"signal:")
    for t, _, r, q, w, (_, va, vb), bad in diverged[:args.max_report]:
        print(f"    {when(t)}  {map_name(base_name(r), maps)}: RTL {show(va, w)}, "
              f"reference {show(vb, w)}"
              + ("" if st.stopped else f"  [{bad} mismatching change time(s)]"))
    if len(diverged) > args.max_report:
        print(f"    ... {len(diverged) - args.max_report} more (--max-report)")
    return 1


if __name__ == "__main__":
    sys.exit(main())
