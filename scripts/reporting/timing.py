"""Timing analysis of a routed design: nextpnr's critical path of a seed (summarise_path),
the endpoints that fail the target from its slack histogram (failing_endpoints), and a
static timing analysis of the SDF it writes (sdf_endpoints) grouped into path classes
(path_classes, over_target)."""
import re

from .common import ReportError

# pins that clock a cell (its timing checks' reference pins are added per cell)
CLOCK_PINS = ("CLK", "RCLK", "WCLK", "CLKA", "CLKB", "CLK0", "CLK1", "CLK2", "CLK3",
              "INPUT_CLK", "OUTPUT_CLK")


def failing_endpoints(text):
    """Endpoints with negative slack at the --freq target, from the last slack histogram
    of a nextpnr log, as (least, most): a bin's '*' stands for `unit` endpoints and a '+'
    for 1..unit-1, and the bin that holds slack 0 may hold failing ones or not. None if
    the log has no histogram."""
    hists = text.split("Slack histogram:")
    if len(hists) < 2:
        return None
    h = hists[-1]
    m = re.search(r"\* represents (\d+) endpoint", h)
    if not m:
        raise ReportError("slack histogram without its legend")
    unit = int(m.group(1))
    least = most = 0
    for lo, hi, bar in re.findall(r"\[\s*(-?\d+),\s*(-?\d+)\)\s*\|([*+ ]*)", h):
        lo, hi = int(lo), int(hi)
        stars, plus = bar.count("*"), "+" in bar
        if lo >= 0:
            continue
        n_min, n_max = stars * unit + plus, stars * unit + plus * (unit - 1)
        if hi <= 0:
            least += n_min
        most += n_max
    return least, most


# pins that clock a cell (its timing checks' reference pins are added per cell)


def sdf_endpoints(text):
    """Static timing of a routed design from the SDF nextpnr writes (--sdf), as nextpnr's
    own report (one clock, rising edges; of a delay's rise and fall triples, min:typ:max,
    the largest value): every pin with a setup check, its latest arrival plus the setup
    time (ns), and the cell its longest path starts from. Arcs: INTERCONNECT (routing) and
    IOPATH (through a cell); an IOPATH from a clock pin starts a path, unless a constant
    ($PACKER_GND/VCC) drives that pin (nextpnr gives an SB_MAC16 used without registers
    such arcs). Pins that no clocked arc reaches (constants, unregistered inputs) start
    nothing. Returns [(ns, end pin, start cell)], the longest first. An arc or check it
    cannot read, or a loop, is an error."""
    m = re.search(r"\(TIMESCALE\s+(\d+(?:\.\d*)?)\s*(fs|ps|ns|us)\s*\)", text)
    if not m:
        raise ReportError("SDF without a readable TIMESCALE (n fs|ps|ns|us)")
    unit = float(m.group(1)) * {"fs": 1e-6, "ps": 1e-3, "ns": 1.0, "us": 1e3}[m.group(2)]
    num = r"-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?"
    tri = rf"\(\s*(?:(?:{num})?:){{0,2}}({num})?\s*\)"      # (v) or (min:typ:max): max

    def delay(*vals):                                      # the largest of rise and fall
        vs = [float(v) for v in vals if v]
        if not vs:
            raise ReportError("SDF delay without a value")
        return max(vs) * unit

    def pin(ref, inst=None):
        ref = ref.replace("\\", "")
        return ref if inst is None else f"{inst}/{ref}"
    succ, npred, start, setup, drv = {}, {}, {}, {}, {}

    def arc(a, b, d):
        succ.setdefault(a, []).append((b, d))
        npred[b] = npred.get(b, 0) + 1
        npred.setdefault(a, 0)
    n_ic = 0
    for a, b, r, f in re.findall(rf"\(INTERCONNECT\s+(\S+)\s+(\S+)\s+{tri}\s*(?:{tri})?",
                                 text):
        arc(pin(a), pin(b), delay(r, f))
        drv[pin(b)] = pin(a)
        n_ic += 1
    const = re.compile(r"PACKER_(GND|VCC)")
    cells = re.split(r"\(CELL\s", text)[1:]
    n_io = n_ck = 0
    for chunk in cells:
        cm = re.match(r"\s*\(CELLTYPE\s+\"[^\"]*\"\)\s*\(INSTANCE\s*((?:[^)\\\n]|\\.)*)\)",
                      chunk)
        if not cm:
            raise ReportError("SDF cell without CELLTYPE and INSTANCE")
        inst = cm.group(1).strip().replace("\\", "")
        checks = re.findall(r"\((?:SETUPHOLD|SETUP)\s+(?:\((?:posedge|negedge)\s+)?([^\s()]+)"
                            rf"\)?\s+\((?:posedge|negedge)\s+([^\s()]+)\)\s+{tri}", chunk)
        n_ck += len(checks)
        clocks = set(CLOCK_PINS) | {ref for _, ref, _ in checks}
        for i, o, r, f in re.findall(r"\(IOPATH\s+(?:\((?:posedge|negedge)\s+)?([^\s()]+)"
                                     rf"\)?\s+([^\s()]+)\s+{tri}\s*(?:{tri})?", chunk):
            n_io += 1
            if i in clocks:
                src = drv.get(pin(i, inst))
                if src is None or const.search(src):
                    continue                  # a constant clocks it: nothing starts here
                k = pin(o, inst)
                start[k] = max(start.get(k, float("-inf")), delay(r, f))
                npred.setdefault(k, 0)
            else:
                arc(pin(i, inst), pin(o, inst), delay(r, f))
        for p_, _, v in checks:
            k = pin(p_, inst)
            setup[k] = max(setup.get(k, float("-inf")), delay(v))
    for what, n, total in (("INTERCONNECT", n_ic, text.count("(INTERCONNECT")),
                           ("IOPATH", n_io, text.count("(IOPATH")),
                           ("SETUP", n_ck, len(re.findall(r"\(SETUP(?:HOLD)?\s", text)))):
        if n != total:
            raise ReportError(f"SDF: read {n} of {total} {what} entries")
    # longest arrival in topological order (Kahn); -inf: no clocked start reaches the pin
    arr = {k: start.get(k, float("-inf")) for k in npred}
    origin = {k: k.rsplit("/", 1)[0] for k in start}
    todo = [k for k, n in npred.items() if n == 0]
    left = dict(npred)
    while todo:
        a = todo.pop()
        for b, d in succ.get(a, ()):
            if arr[a] + d > arr[b] and b not in start:
                arr[b] = arr[a] + d
                origin[b] = origin[a]
            left[b] -= 1
            if left[b] == 0:
                todo.append(b)
    if any(n > 0 for n in left.values()):
        raise ReportError("SDF timing graph has a combinational loop")
    ends = [(round(arr[k] + s, 3), k, origin[k]) for k, s in setup.items()
            if k in arr and arr[k] > float("-inf")]
    return sorted(ends, reverse=True)


def over_target(sdf, period_ns, instances=(), keep=20):
    """The path classes of a routed seed (its SDF) longer than the target period: the
    worst `keep` classes and the number of endpoints over it, or the error that stopped
    the analysis (the report goes on without it)."""
    try:
        ends = sdf_endpoints(sdf.read_text())
    except (OSError, ValueError, ReportError) as e:
        return {"error": str(e)}
    cls = path_classes(ends, period_ns, instances)
    return {"period_ns": round(period_ns, 3), "endpoints": sum(c["endpoints"] for c in cls),
            "worst_ns": ends[0][0] if ends else None, "classes": cls[:keep],
            "classes_total": len(cls)}


def signal_of(cell):
    """The signal a flattened cell is named after: its last name component that is not a
    number (a memory's block index, '0', '14$RAMW_BLOCK1') up to the suffixes synthesis
    and nextpnr append ('u_core.u_correct.zl_o_SB_DFFE_Q_3_D_LC' -> 'zl_o',
    'u_core.u_lut.ph_rom.0.1_RAM' -> 'ph_rom'); the whole component if nothing is left."""
    if cell.startswith("$"):
        return cell
    parts = [x for x in cell.split(".") if not re.match(r"\d+(_RAM|\$|$)", x)]
    last = parts[-1] if parts else cell
    base = re.split(r"_SB_|_TRELLIS|_DFF|_LUT4|_CCU2C|_PFUMX|_L6MUX|_DP16KD|_MULT18|"
                    r"_DSP$|_RAM$|_LC$|\$", last)[0]
    return base or last


def path_classes(ends, over_ns, instances=()):
    """Endpoints (sdf_endpoints, the longest first) whose arrival exceeds over_ns, grouped
    by the signal and instance their longest path starts from and the signal and instance
    it ends at: [{"worst_ns", "endpoints", "from", "to"}], the worst class first. An
    endpoint counts once, under its longest path's start."""
    classes = {}
    for ns, end, origin in ends:
        if ns <= over_ns:
            break
        cell = end.rsplit("/", 1)[0]
        key = tuple(f"{instance_of(c, instances) or 'top'}: {signal_of(c)}"
                    for c in (origin, cell))
        c = classes.setdefault(key, {"worst_ns": ns, "endpoints": 0, "from": key[0],
                                     "to": key[1]})
        c["endpoints"] += 1
    return sorted(classes.values(), key=lambda c: -c["worst_ns"])


def instance_of(cell, instances=()):
    """Instance path of a flattened cell name: the longest known instance prefix, else the
    leading components named like instances in this code (u_*, g_*); '' is the top."""
    best = ""
    for inst in instances:
        if cell.startswith(inst + ".") and len(inst) > len(best):
            best = inst
    if best:
        return best
    parts = []
    for p in cell.split(".")[:-1]:
        if not (p.startswith("u_") or p.startswith("g_")):
            break
        parts.append(p)
    return ".".join(parts)


def summarise_path(path, instances=()):
    """A nextpnr critical path (report JSON) -> total, logic and routing delay (ns), logic
    levels, start and end cell, and the instances it runs through in order with the delay
    spent in each (a routing hop counts for the instance of its sink)."""
    if not path:
        raise ReportError("empty critical path")
    total = logic = routing = 0.0
    levels = 0
    through = []
    for step in path:
        d = float(step["delay"])
        total += d
        if step["type"] == "routing":
            routing += d
            cell = step["to"]["cell"]
        else:
            logic += d
            cell = step["from"]["cell"]
            if step["type"] == "logic":
                levels += 1
        inst = ("(nextpnr cell)" if cell.startswith("$nextpnr")
                else instance_of(cell, instances) or "top_report")
        if through and through[-1][0] == inst:
            through[-1][1] += d
        else:
            through.append([inst, d])
    return {"steps": [[st["type"], round(float(st["delay"]), 3),
                       st["to"]["cell"] if st["type"] == "routing" else st["from"]["cell"]]
                      for st in path],
            "total_ns": round(total, 3), "logic_ns": round(logic, 3),
            "routing_ns": round(routing, 3), "logic_levels": levels,
            "from": path[0]["from"]["cell"], "to": path[-1]["to"]["cell"],
            "through": [[i, round(d, 3)] for i, d in through]}
