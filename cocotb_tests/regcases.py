"""Write cases for every writable register of finequad_core, from its description
(sim/model/regs.py, generated from rtl/regs/finequad.rdl): each field at its legal bounds
(the register's other fields at their reset values) must be taken; one past a bound, a bit
no field holds, and a write to a read-only word must be refused, changing nothing.

cases(build) -> [(register, word, taken)] for a core built with `build` (the OPT_
parameters that differ from 1): in a build where a register is constant, every write to
it is refused. The bus tests (test_axil_regs.py through AXI4-Lite, test_uart_axil.py
through the UART bridge) run these cases against the real core.
"""
from sim.model import regs


def _place(r, field, v):
    """The word with `field` = v and the register's other writable fields at reset, or
    None if v does not fit the field's bits."""
    f = r.fields[field]
    if f.signed:
        if not -(1 << (f.width - 1)) <= v < 1 << (f.width - 1):
            return None
    elif not 0 <= v < 1 << f.width:
        return None
    return regs.word(r.name, **{field: v})


def cases(build=None):
    out = []
    for name, r in regs.REGS.items():
        if not r.write:
            continue
        present = all((build or {}).get(o, 1) for o in r.requires)
        for f in r.fields.values():
            if not f.write or f.w1c:
                continue
            for v, legal in ((f.lo, True), (f.hi, True), (f.lo - 1, False),
                             (f.hi + 1, False)):
                w = _place(r, f.name, v)
                if w is None:
                    # beyond the field's bits: the raw value there sets bits outside the
                    # register's fields, or none at all (then there is no such word)
                    raw = (v << f.lsb) & 0xFFFFFFFF if v >= 0 else v & 0xFFFFFFFF
                    if raw & ~r.wmask & 0xFFFFFFFF:
                        out.append((name, raw, False))
                    continue
                assert (regs.illegal(name, w) is None) == legal, (name, f.name, v)
                out.append((name, w, legal and present))
        spare = ~r.wmask & 0xFFFFFFFF
        if spare:                                      # a bit no field holds
            out.append((name, r.reset | (spare & -spare), False))
    # read-only words, and a word the map does not use
    for name, r in regs.REGS.items():
        if not r.write and not any(x.index == r.index and x.write for x in regs.REGS.values()):
            out.append((name, 0, False))
    # (words above ADDR_TOP are the bus's to refuse: tested with the bus)
    used = {r.index for r in regs.REGS.values()}
    spare_word = next((i for i in range(regs.ADDR_TOP) if i not in used), None)
    if spare_word is not None:
        out.append((f"0x{spare_word:02x}", 0, False))
    return out


def index(name):
    return regs.REGS[name].index if name in regs.REGS else int(name, 16)


def readback(name, word):
    """What a read of the register shows after `word` was taken (None: nothing to
    compare: the register reads something else, e.g. the bundle in use or STATUS)."""
    r = regs.REGS.get(name)
    if r is None or not r.read or name in ("GAIN", "M1", "M2", "C1", "C12", "C2",
                                           "FAULT_STICKY"):
        return None
    return word & r.rmask
