"""A top of the VHDL edition as a Verilog netlist for Yosys, nextpnr's flows and Verilator:
GHDL's analysis of rtl/vhdl/sources.f (and the top's file if it is not listed), `ghdl
--synth --std=08 --out=verilog` (GHDL 2.0) with the generics given, and the repairs below.
`make bitstream EDITION=vhdl`, `make report EDITION=vhdl` (scripts/reporting/flow.py) and
`make rtlsim EDITION=vhdl-synth` all take their netlist from here.

    ghdl_netlist.py --top TOP --out NET.v --work DIR [--extra F.vhd ...] [-g NAME=VALUE ...]

TABLE_DIR is set to rtl/tables/ unless given: the tables are read by the synthesis and
become the ROMs' contents. GHDL's messages go to NET.log beside NET.v.

The VHDL edition instantiates the vendor primitives (SB_PLL40_PAD, EHXPLLL, MULT18X18D) as
components, which GHDL leaves as black boxes. Its Verilog then has these faults:
- an empty module for each black box (a component no entity is bound to), whose
  parameters have no defaults ("Parameter defaults can only be omitted in SystemVerilog
  mode"); it would also hide Yosys's own cell of that name. Removed.
- a string generic of an instance written as the bits of its ASCII text
  (`.FEEDBACK_PATH(48'b0101...)` for "SIMPLE"), where nextpnr reads a string. The
  generics declared `string` in the component declarations of VHDL_FILE... are written
  back as strings.
- a port of the top that is a vector of one bit (top_ulx3s's `btn : std_logic_vector(1
  downto 1)`, the Verilog's `[1:1] btn`) written as a scalar, so the constraints' `btn[1]`
  finds no port. Declared with its range again.
Anything else that does not match what this expects stops with the file and line.

And one fault of every netlist: a non-zero constant wider than 32 bits (the initial or
reset value of a wide record, e.g. finequad_core's settings) is written as a quoted
string of its bits, "0101...", which Verilog reads as ASCII text (8 bits a character), so
the register powers up and resets to garbage. Each becomes the sized literal it spells,
N'b0101... (GHDL writes no string of its own otherwise: generics are sized literals).
And a signed product (`// smul`) is written as Verilog's unsigned `*` of its operands
sign-extended to the product's width: the same bits, but Yosys cannot narrow an unsigned
multiplier whose high bits are sign copies, so a 16x16 signed product became a 32x32 one
(three SB_MAC16 instead of one: the iCE40 build took 18 of the UP5K's 8). Each is written
as `$signed(a) * $signed(b)`, the same bits modulo the width, which Yosys narrows to the
operands' real widths as it does the Verilog edition's.
And a memory's address (VHDL's ascending index on GHDL's descending memory) is written as
`assign a = N'b11...1 - i;`, which Yosys keeps as an N-bit subtractor (a carry chain per
memory port: three 11-bit ones in lut) where it is `~i`: written so when `a` is N bits.
And GHDL's Verilog writer drops the VHDL's attributes of a memory: the Yosys attributes
ram_style and no_rw_check that the Verilog edition sets (a 4-word delay line in block RAM,
no read-during-write logic where the design never reads a word as it writes it) are
declared on the VHDL signal (`attribute ram_style of late_mem : signal is "block"`,
`attribute no_rw_check of rf_mem : signal is true`) and written back onto the netlist's
memory of that name (GHDL's `reg [w] <prefix>_<name>[n] ; // memory`) in the modules of
the entity whose file declares them.
And GHDL names registers and expressions nN_q, nN_o and writes each VHDL signal as an
alias of one. With --signal-names (make report EDITION=vhdl) the nets take the signals'
names (named_nets), so Yosys's cells and nextpnr's paths carry the names the Verilog
edition's do (constraints/up5k_dsp.py finds the UP5K's DSP blocks by them). Not by
default: the same logic under other names comes out of Yosys's ABC differently (the
iCEBreaker's top: 23 more SB_LUT4, 5300 logic cells for its 5280, where GHDL's names
fit in 5271).
rtl/vhdl/README.md lists these with the constructs the VHDL avoids.
"""
import argparse
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from sim import ghdl  # noqa: E402  (the edition's analysis order, rtl/vhdl/sources.f)

COMPONENT = re.compile(r"^\s*component\s+(\w+)\s+is(.*?)end\s+component", re.I | re.M | re.S)
STRING_GENERIC = re.compile(r"^\s*(\w+)\s*:\s*string\b", re.I | re.M)


def string_generics(vhdl_files):
    """{primitive: {generic names of type string}} from the component declarations."""
    out = {}
    for f in vhdl_files:
        text = re.sub(r"--[^\n]*", "", Path(f).read_text())
        for name, body in COMPONENT.findall(text):
            out.setdefault(name, set()).update(STRING_GENERIC.findall(body))
    return out


def ascii_of(width: int, bits: str, where: str) -> str:
    if width != len(bits) or width % 8:
        sys.exit(f"ghdl_netlist: {where}: {width}'b{bits} is not a whole number of characters")
    text = bytes(int(bits[i:i + 8], 2) for i in range(0, width, 8)).decode("ascii")
    if not text.isprintable() or '"' in text:
        sys.exit(f"ghdl_netlist: {where}: {width}'b{bits} is not a printable string")
    return text


WIDE_CONST = re.compile(r'"([01xzXZ]+)"')


def wide_constants(netlist: str) -> str:
    """Each quoted string of bits as the sized literal it spells."""
    return WIDE_CONST.sub(lambda m: f"{len(m.group(1))}'b{m.group(1)}", netlist)


SMUL = re.compile(r"^(\s*assign \w+ = )(\S+) \* (\S+); // smul$", re.M)


def signed_products(netlist: str, path: str) -> str:
    """Each signed product as a product of signed operands."""
    text, n = SMUL.subn(r"\1$signed(\2) * $signed(\3); // smul", netlist)
    if n != netlist.count("// smul"):
        sys.exit(f"ghdl_netlist: {path}: a signed product (// smul) not of the form "
                 "`assign n = a * b; // smul`")
    return text


MEM_ATTRS = ("ram_style", "no_rw_check")
MEM_ATTR = re.compile(r"^\s*attribute\s+(\w+)\s+of\s+(\w+)\s*:\s*signal\s+is\s+"
                      r"(\"[^\"]*\"|true)\s*;", re.I | re.M)
ENTITY = re.compile(r"^\s*entity\s+(\w+)\s+is\b", re.I | re.M)
MEMORY = re.compile(r"^(\s*)reg (\[\d+:\d+\] )?(\w+)\[\d+:\d+\] ; // memory$")


def memory_attributes(vhdl_files) -> dict:
    """{entity: [(signal, Verilog attribute)]} of the memory attributes the files declare."""
    attrs = {}
    for f in vhdl_files:
        text = re.sub(r"--[^\n]*", "", Path(f).read_text())
        found = [(sig.lower(), f'{a.lower()} = {v}' if v.startswith('"') else a.lower())
                 for a, sig, v in MEM_ATTR.findall(text) if a.lower() in MEM_ATTRS]
        for e in ENTITY.findall(text):
            attrs[e.lower()] = found
    return attrs


def memory_attrs(netlist: str, attrs: dict) -> str:
    out, ents = [], []
    for ln in netlist.split("\n"):
        m = re.match(r"module (\w+)\s*$", ln)
        if m:
            name = m.group(1).lower()
            # (the longest entity name that names the module: `lut` before `lut_x`)
            es = [e for e in attrs if name == e or name.startswith(e + "_")]
            ents = attrs[max(es, key=len)] if es else []
        m = MEMORY.match(ln)
        if m:
            mem = m.group(3).lower()
            hit = [a for sig, a in ents if mem == sig or mem.endswith("_" + sig)]
            if hit:
                ln = f"{m.group(1)}(* {', '.join(hit)} *) {ln.lstrip()}"
        out.append(ln)
    return "\n".join(out)


ONES_MINUS = re.compile(r"^(\s*assign (\w+) = )(\d+)'b(1+) - (\w+);$", re.M)
WIRE_W = re.compile(r"^\s*(?:wire|reg) \[(\d+):0\] (\w+);$", re.M)


def ones_minus(netlist: str) -> str:
    """Each `a = N'b1..1 - i` with a of N bits as `a = ~i` (the same bits)."""
    width = {m.group(2): int(m.group(1)) + 1 for m in WIRE_W.finditer(netlist)}

    def sub(m):
        n = int(m.group(3))
        if n != len(m.group(4)) or width.get(m.group(2)) != n:
            return m.group(0)
        return f"{m.group(1)}~{m.group(5)};"
    return ONES_MINUS.sub(sub, netlist)


ALIAS = re.compile(r"^  assign (\w+) = (n\d+_[a-z]+); // \(signal\)\n"
                   r"|^  always @\*\n    (\w+) = (n\d+_[a-z]+); // \(isignal\)\n"
                   r"  initial\n    \3 <= [^;\n]+;\n", re.M)


def named_nets(netlist: str) -> str:
    """Each VHDL signal under its own name. GHDL names a register or an expression nN_q,
    nN_o and gives the signal as an alias of it (`assign p1 = nN_q; // (signal)`, or
    `always @* p1 = nN_q; // (isignal)` with its initial value); Yosys then names the cells
    after nN_q (u_correct.n4095_q_SB_MAC16_O where the Verilog edition has u_correct.p1:
    constraints/up5k_dsp.py places blocks by those names, and timing paths read better).
    Where a module has one alias of a net, the net takes the signal's name: its uses
    renamed, the signal's declaration and alias removed (the same bits: an alias)."""
    out = []
    for mod in re.split(r"(?<=\nendmodule\n)", netlist):
        aliases = [(m.group(1) or m.group(3), m.group(2) or m.group(4), m.group(0))
                   for m in ALIAS.finditer(mod)]
        count = {}
        for _, net, _ in aliases:
            count[net] = count.get(net, 0) + 1
        for name, net, text in aliases:
            decl = re.compile(rf"^  (?:wire|reg) (?:\[\d+:\d+\] )?{name};\n", re.M)
            if count[net] != 1 or len(decl.findall(mod)) != 1:
                continue
            mod = decl.sub("", mod.replace(text, "", 1), 1)
            mod = re.sub(rf"\b{net}\b", name, mod)
        out.append(mod)
    return "".join(out)


def fix(netlist: str, prims: dict, path: str) -> str:
    # (first, while GHDL's own text has no string: the string generics come after)
    lines = ones_minus(signed_products(wide_constants(netlist), path)).split("\n")
    out, i = [], 0
    inst = None                     # the primitive whose instance's parameters follow
    while i < len(lines):
        ln = lines[i]
        m = re.match(r"module (\w+)\s*$", ln)
        if m and m.group(1) in prims:
            # the black box: its header and ports, then endmodule, no statement
            j = i
            while j < len(lines) and lines[j].strip() != "endmodule":
                j += 1
            if j == len(lines):
                sys.exit(f"ghdl_netlist: {path}:{i + 1}: module {m.group(1)} has no endmodule")
            body = "\n".join(lines[i:j])
            if not re.search(r"\b(assign|always|reg|wire|initial)\b", body):
                i = j + 1
                continue
            # (a component bound to an entity of the edition, e.g. top_report's core:
            # a real module, kept)
        m = re.match(r"\s*(\w+) #\($", ln)
        if m:
            inst = m.group(1) if m.group(1) in prims else None
        elif inst:
            p = re.match(r"(\s*\.(\w+)\()(\d+)'b([01]+)(\)\)?,?)$", ln)
            if p and p.group(2) in prims[inst]:
                text = ascii_of(int(p.group(3)), p.group(4), f"{path}:{i + 1}")
                ln = f'{p.group(1)}"{text}"{p.group(5)}'
            if ln.rstrip().endswith("))"):
                inst = None
        out.append(ln)
        i += 1
    return "\n".join(out)


def sources(top, extra=()):
    """rtl/vhdl/sources.f's files, the extra ones, and rtl/vhdl/<top>.vhd if not listed."""
    files = ghdl.vhdl_files() + [str(f) for f in extra]
    vtop = f"rtl/vhdl/{top}.vhd"
    if vtop not in files and (ROOT / vtop).is_file():
        files.append(vtop)
    return files


def declares_generic(files, top, name):
    """The entity `top` (in one of `files`) has the generic `name` (a block's cocotb run
    takes a top without TABLE_DIR)."""
    ent = re.compile(rf"^\s*entity\s+{top}\s+is\b(.*?)\bport\b", re.I | re.M | re.S)
    for f in files:
        m = ent.search(re.sub(r"--[^\n]*", "", (ROOT / f).read_text()))
        if m:
            return re.search(rf"\b{name}\s*:", m.group(1), re.I) is not None
    return True


def one_bit_vectors(files, top):
    """{port: index} of the entity `top`'s ports declared std_logic_vector(i downto i)."""
    ent = re.compile(rf"^\s*entity\s+{top}\s+is\b(.*?)^\s*end\b", re.I | re.M | re.S)
    for f in files:
        m = ent.search(re.sub(r"--[^\n]*", "", (ROOT / f).read_text()))
        if m:
            return {n: int(i) for n, i, j in re.findall(
                r"(\w+)\s*:\s*(?:in|out|inout)\s+std_logic_vector\s*\(\s*(\d+)\s+downto\s+"
                r"(\d+)\s*\)", m.group(1), re.I) if i == j}
    return {}


def ranged_ports(netlist: str, top: str, ports: dict) -> str:
    """The scalar declarations of `ports` in module `top`'s header with their range."""
    if not ports:
        return netlist
    head = re.search(rf"^module {top}\b.*?\);", netlist, re.M | re.S)
    if head is None:
        sys.exit(f"ghdl_netlist: no module {top} in GHDL's netlist")
    text = head.group(0)
    for name, i in ports.items():
        text, n = re.subn(rf"\b(input|output|inout)(\s+){name}\b", rf"\1 [{i}:{i}]\2{name}", text)
        if n != 1:
            sys.exit(f"ghdl_netlist: module {top}: port {name} not found as a scalar")
    return netlist[:head.start()] + text + netlist[head.end():]


def netlist(top, out, work, generics=(), extra=(), signal_names=False):
    """Write the repaired netlist of `top` to `out` (GHDL's messages to out.log); stops with
    GHDL's message when GHDL fails."""
    out, work = Path(out), Path(work)
    files = sources(top, extra)
    work.mkdir(parents=True, exist_ok=True)
    log = out.with_suffix(".log")
    gen = [f"-g{g}" for g in generics]
    if not any(g.startswith("TABLE_DIR=") for g in generics) and \
            declares_generic(files, top, "TABLE_DIR"):
        gen.insert(0, f"-gTABLE_DIR={ROOT / 'rtl' / 'tables'}/")
    with open(log, "w") as lf:
        # (one step, the files before -e: GHDL analyses them in memory for the synthesis;
        # a separate `ghdl -a` would have the LLVM back end compile every file, 5 s here)
        for cmd in (["ghdl", "--synth", "--std=08", f"--workdir={work}", "--out=verilog"]
                    + gen + files + ["-e", top],):
            lf.write(" ".join(map(str, cmd)) + "\n")
            lf.flush()
            with open(out.with_suffix(".tmp"), "w") as f:
                r = subprocess.run(cmd, cwd=ROOT, stdout=f, stderr=lf)
            if r.returncode != 0:
                sys.exit(f"ghdl_netlist: {cmd[0]} {cmd[1]} of {top} failed (exit status "
                         f"{r.returncode}):\n{log.read_text()[-3000:]}")
    text = out.with_suffix(".tmp").read_text()
    out.with_suffix(".tmp").unlink()
    text = fix(text, string_generics(ROOT / f for f in files), str(out))
    text = memory_attrs(text, memory_attributes(ROOT / f for f in files))
    if signal_names:
        text = named_nets(text)
    out.write_text(ranged_ports(text, top, one_bit_vectors(files, top)))


def main(argv=None):
    ap = argparse.ArgumentParser(prog="ghdl_netlist.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("--top", required=True)
    ap.add_argument("--out", required=True, help="the Verilog netlist")
    ap.add_argument("--work", required=True, help="GHDL's work library")
    ap.add_argument("--extra", action="append", default=[], help="a VHDL file more")
    ap.add_argument("-g", action="append", default=[], metavar="NAME=VALUE",
                    help="a generic of the top")
    ap.add_argument("--signal-names", action="store_true",
                    help="each VHDL signal's net under its name (named_nets)")
    args = ap.parse_args(argv)
    for g in args.g:
        if not re.fullmatch(r"\w+=\S+", g):
            sys.exit(f"ghdl_netlist: error: -g {g!r}: expected NAME=VALUE")
    netlist(args.top, args.out, args.work, args.g, args.extra, args.signal_names)


if __name__ == "__main__":
    main()
