"""Floorplan of the fast path's DSP blocks on the iCE40 UP5K (a nextpnr-ice40 --pre-place
script: `nextpnr-ice40 --up5k ... --pre-place constraints/up5k_dsp.py`).

The UP5K has its eight SB_MAC16 blocks in two columns at the die's edges, four at x = 0
and four at x = 25 (rows 5, 10, 15, 23). The fast path uses four (rtl/correct.v: p1 =
d1 c1, p12 = d1 c12, p2 = d2 c2; rtl/octant.v: the ratio multiply psum), the engine the
other four (rtl/rls_engine.v: its partial products). Left to itself the placer puts the
fast path's four in one column but in any order, and it put p12 and p2, whose sum is the
path from the products into the magnitudes, 13 rows apart. This script locks the four in
the column at x = 25 with p12 and p2 next to each other (rows 10 and 15); the engine's four
take the other column. On the report's UP5K build (nextpnr-ice40 0.4, --freq 36, the same
netlist) seeds 1 to 5 went from 27.97, 28.56, 29.39, 28.27 and 28.66 MHz to 30.47, 30.20,
30.73, 30.47 and 29.74 MHz (median 28.56 -> 30.47; make report, scripts/README.md). Orders
tried on seeds 1 to 5: this one; p1, p12, p2, psum in rows 5, 10, 15, 23 (30.23, 30.81,
29.50, 30.69, 29.38: median 30.23); the fast path's four in the column at x = 0 in this
order and the engine's in the other in the order the placer chose (29.97, 30.12, 29.46,
29.68, 30.23: median 29.97).

Every block named here must be in the design exactly once: a renamed or missing block
stops nextpnr with the name that did not match, instead of a silent, unconstrained
placement.
"""

# the signal Yosys names the SB_MAC16 after, by its instance path in the flattened
# hierarchy (the cell's name before the "_SB_MAC16" suffix): a product register of
# rtl/correct.v, or the octant's rounding sum psum (a wire, rtl/octant.v, which Yosys
# folds into the block) -> the block's BEL
FLOORPLAN = {
    "u_octant.psum": "X25/Y5/mac16_0",
    "u_correct.p12": "X25/Y10/mac16_0",
    "u_correct.p2": "X25/Y15/mac16_0",
    "u_correct.p1": "X25/Y23/mac16_0",
}

# an SB_MAC16 in Yosys's netlist, and after nextpnr-ice40's packer
DSP_TYPES = ("SB_MAC16", "ICESTORM_DSP")


def register_of(cell_name):
    """'u_core.u_correct.p12_SB_MAC16_O_DSP' -> 'u_core.u_correct.p12'."""
    return cell_name.split("_SB_MAC16", 1)[0]


def floorplan(cells, plan=FLOORPLAN):
    """(name, cell) pairs of the design (cell.type: its type) -> {cell name: BEL} for every
    entry of the plan; ValueError naming the entries that match no DSP block or more than
    one, and listing the design's DSP blocks."""
    found = {key: [] for key in plan}
    dsps = []
    for name, cell in cells:
        if cell.type not in DSP_TYPES:
            continue
        dsps.append(name)
        reg = register_of(name)
        for key in plan:
            if reg == key or reg.endswith("." + key):
                found[key].append(name)
    bad = [f"{key}: {'no' if not names else len(names)} DSP blocks"
           + (f" ({', '.join(sorted(names))})" if names else "")
           for key, names in found.items() if len(names) != 1]
    if bad:
        raise ValueError("constraints/up5k_dsp.py: each entry must name exactly one DSP "
                         "block of the design: " + "; ".join(bad) + "; the design's DSP "
                         "blocks: " + (", ".join(sorted(dsps)) or "none"))
    return {names[0]: plan[key] for key, names in found.items()}


if "ctx" in globals():                  # run by nextpnr-ice40 --pre-place
    _cells = {_n: _c for _n, _c in ctx.cells}      # noqa: F821 (nextpnr's context)
    for _name, _bel in floorplan(_cells.items()).items():
        _cells[_name].setAttr("BEL", _bel)
