"""Cells of a synthesised netlist (Yosys JSON): counts per module of the hierarchy
(hierarchy_breakdown, classify) and the iCE40 DSP blocks' stages without a register at
the block's pins, which nextpnr-ice40 does not time (ice40_dsp_modes)."""
import collections

from .common import ReportError


def module_base(name):
    """'$paramod$hash\\finequad_core' or '$paramod\\x\\P=1' -> the module's own name."""
    if name.startswith("$paramod"):
        parts = name.split("\\")
        if len(parts) >= 2:
            return parts[1]
    return name.lstrip("\\")


def classify(cell_type, cells):
    for k, types in cells.items():
        if k == "ff_prefix":
            continue
        if cell_type in types:
            return k
    if cell_type.startswith(cells["ff_prefix"]):
        return "ff"
    if cell_type == "$scopeinfo":
        return None
    return "other"


def flag(v):
    """A Yosys JSON attribute value ('00..01', '1', 1) as a bool."""
    s = str(v).strip()
    try:
        return int(s, 2) != 0 if s and set(s) <= {"0", "1"} else int(s) != 0
    except ValueError:
        return bool(s)


def ice40_dsp_modes(netlist):
    """Flattened iCE40 netlist -> one row per SB_MAC16: its name and the stages inside it
    that have no register at the block's pins. nextpnr-ice40 0.4 (and icetime) give every
    SB_MAC16 pin a fixed 0.1 ns clock-to-output or setup, whatever the configuration, so a
    path through such a stage is cut at the block's pins and the stage's delay is not in
    the reported Fmax. Stages (the SB_MAC16 model, Yosys's ice40/cells_sim.v): 'A in',
    'B in', 'C in', 'D in' for an input driven by a net (not a constant) and used without
    its register; 'O[31:16] out (...)', 'O[15:0] out (...)' for an output half that some
    cell or port reads and that leaves without a register, with what drives it: the
    multiplier, the sum of the registered 8x8 partial products ('product sum'), an 8x8
    product, the adder on its own inputs or the adder behind the multiplier
    ('multiplier+adder')."""
    rows = []
    for mod in netlist.get("modules", {}).values():
        cells = mod.get("cells", {})
        # every net bit something reads: a cell's input or the module's output ports
        read = {b for c in cells.values()
                for port, bits in c.get("connections", {}).items()
                if c.get("port_directions", {}).get(port, "input") == "input"
                for b in bits if isinstance(b, int)}
        read |= {b for pt in mod.get("ports", {}).values() if pt.get("direction") != "input"
                 for b in pt.get("bits", []) if isinstance(b, int)}
        for name, c in cells.items():
            if c.get("type") != "SB_MAC16":
                continue
            p, conn = c.get("parameters", {}), c.get("connections", {})

            def par(k):
                v = str(p.get(k, 0))
                try:
                    return int(v, 2) if v and set(v) <= {"0", "1"} else int(v)
                except ValueError:
                    raise ReportError(f"SB_MAC16 {name}: parameter {k} = {v!r} is not a "
                                      "number") from None

            def driven(port):               # any bit driven by a net, not a constant
                return any(isinstance(b, int) for b in conn.get(port, []))
            comb = [f"{port} in" for port in "ABCD"
                    if driven(port) and not par(f"{port}_REG")]
            # the four 8x8 partial products registered: what is left is the sum of them
            pp_reg = all(par(k) for k in ("TOP_8x8_MULT_REG", "BOT_8x8_MULT_REG",
                                          "PIPELINE_16x16_MULT_REG1"))
            o = conn.get("O", [])
            for half, lo, sel, mreg, lower in (
                    ("O[31:16]", 16, "TOPOUTPUT_SELECT", "TOP_8x8_MULT_REG",
                     "TOPADDSUB_LOWERINPUT"),
                    ("O[15:0]", 0, "BOTOUTPUT_SELECT", "BOT_8x8_MULT_REG",
                     "BOTADDSUB_LOWERINPUT")):
                if not any(b in read for b in o[lo:lo + 16]):
                    continue
                # select 1: the accumulator register; 2: the 8x8 product, registered by
                # its 8x8 register; 3: the 16x16 product, registered by REG2; 0: the
                # adder, whose lower input is the input register (0), the 8x8 (1) or the
                # 16x16 (2) product, or a sign extension (3)
                sv = par(sel)
                if sv == 1 or (sv == 3 and par("PIPELINE_16x16_MULT_REG2")) or \
                        (sv == 2 and par(mreg)):
                    continue
                if sv == 0:
                    what = "multiplier+adder" if par(lower) in (1, 2) else "adder"
                else:
                    what = "8x8 product" if sv == 2 else \
                        "product sum" if pp_reg else "multiplier"
                comb.append(f"{half} out ({what})")
            rows.append({"cell": name, "combinational": comb})
    return sorted(rows, key=lambda r: r["cell"])


def hierarchy_breakdown(netlist, cells):
    """Yosys JSON of an unflattened synthesis -> one row per instance (depth-first):
    instance path, module, own cell counts and counts including the submodules. Cell
    library modules (blackbox/whitebox: LUT4, TRELLIS_FF, ...) are leaves."""
    mods = netlist.get("modules")
    if not isinstance(mods, dict) or not mods:
        raise ReportError("netlist has no modules")

    def attr(m):
        return mods[m].get("attributes", {})

    def is_leaf(m):
        a = attr(m)
        return flag(a.get("blackbox", 0)) or flag(a.get("whitebox", 0))

    def name(m):
        return (attr(m).get("hdlname") or module_base(m)).lstrip("\\")

    tops = [m for m in mods if flag(attr(m).get("top", 0))]
    if len(tops) != 1:
        raise ReportError(f"netlist has {len(tops)} top modules, expected one")
    rows = []

    def walk(mod, path, depth):
        own = collections.Counter()
        kids = []
        for cname, c in sorted(mods[mod].get("cells", {}).items()):
            t = c["type"]
            if t in mods and not is_leaf(t):
                kids.append((cname, t))
            else:
                k = classify(name(t) if t in mods else module_base(t), cells)
                if k:
                    own[k] += 1
        row = {"instance": path, "module": name(mod), "depth": depth,
               "own": dict(own), "total": None}
        rows.append(row)
        total = collections.Counter(own)
        for cname, t in kids:
            total.update(walk(t, f"{path}.{cname}" if path else cname, depth + 1))
        row["total"] = dict(total)
        return total

    walk(tops[0], "", 0)
    rows[0]["instance"] = name(tops[0])
    return rows
