"""Bit-true model of rtl/rls_engine.v: the microcoded RLS engine (Eqs. 5-8) that
rtl/estimator.v drives.

It executes the ROM image of sim/model/program.py for the engine's LANES (1 or 2). For
speed each program is translated once into straight-line Python (one statement per
instruction, a slot's lanes one after the other: the scheduler keeps them independent);
the semantics are those listed in program.py and implemented by rtl/rls_engine.v:

  acc   64-bit two's complement, one per lane (wrapped when written back, which equals
        wrapping on every add); rounding add and shift in 65 bits; register write
        saturates to 32 bits, OUT write to 16 bits.

Every LANES computes the same numbers (the programs differ only in their schedule and in
bit-identical rewrites: sim/tests/test_model.py holds them equal); only the clocks per
program (CYCLES_BY_LANES) differ.
"""
from . import program as prog
from .fixed import clz32

ACC_W = 64
_M64 = (1 << ACC_W) - 1
_H64 = 1 << (ACC_W - 1)

# The instruction in slot k of a program started on edge S writes its result on edge
# S + k + PIPE (rtl/rls_engine.v: fetch, read, operands, multiply, product, accumulate,
# shift, round, write); END in slot k ends the program (busy clears, commit) on edge
# S + k + PIPE.
PIPE = prog.PIPE


def program_cycles(entry: str, lanes: int = 1) -> int:
    """Clock edges from start to END retirement (commit) for a program."""
    im = prog.IMAGES[lanes]
    start = im.entry[entry]
    k = 0
    while prog.decode(im.rom[start + k])["op"] != prog.OP_END:
        k += 1
    return k + PIPE


def _compile(entry: str, lanes: int):
    im = prog.IMAGES[lanes]
    lines = ["def run(rf, out, acc, X1, X2, ONEL, KAPPA, GS1, GS2):",
             "    dz = [0, 0]; invalid = 0; sat = 0"]
    lines += [f"    acc{k} = acc[{k}]" for k in range(lanes)]
    spec = {v: k for k, v in prog.SPECIALS.items()}
    zero = im.regs["ZERO"]
    pc = im.entry[entry]

    def opnd(r):
        return spec[r] if r >= 64 else f"rf[{r}]"
    done = False
    while not done:
        word = im.rom[pc]
        pc += 1
        for lane, f in enumerate(prog.decode_word(word, lanes)):
            op = f["op"]
            acc = f"acc{lane}"
            if op == prog.OP_END:
                done = True
                continue
            a = opnd(f["a"])
            if op == prog.OP_NOP:
                continue
            if op == prog.OP_CHK:
                lines.append(f"    if {a} <= 0: invalid = 1")
                continue
            if op in (prog.OP_NORMR, prog.OP_NORMS):
                even = " & ~1" if op == prog.OP_NORMS else ""
                lines.append(f"    v = {a}")
                lines.append(f"    if v <= 0: invalid = 1; dz[{f['z']}] = 0")
                lines.append(f"    else: dz[{f['z']}] = (clz32(v) - 1){even}")
                continue
            if op == prog.OP_MAC:
                term = f"{a} * {opnd(f['b'])}"
                sign = "-" if f["neg"] else "+"
                if f["clr"]:
                    lines.append(f"    {acc} = {'-' if f['neg'] else ''}{term}")
                elif not (f["a"] == zero and f["b"] == zero):
                    lines.append(f"    {acc} = {acc} {sign} {term}")
            elif op == prog.OP_SEEDR:
                lines.append(f"    {acc} = SEEDR[(({a} << dz[{f['z']}]) >> 23) & 127]")
            elif op == prog.OP_SEEDS:
                lines.append(f"    {acc} = SEEDS[(({a} << dz[{f['z']}]) >> 24) & 127]")
            if f["wb"]:
                z = f["z"]
                dyn = {prog.DYN_NONE: "0", prog.DYN_DZ: f"dz[{z}]",
                       prog.DYN_DZ2: f"(dz[{z}] >> 1)"}[f["dyn"]]
                lines.append(f"    s = {f['sh']} - {dyn}")
                lines.append("    s = 0 if s < 0 else 63 if s > 63 else s")
                lines.append(f"    w = (({acc} + {_H64}) & {_M64}) - {_H64}")
                lines.append("    r = (w + (1 << (s - 1))) >> s if s else w")
                if f["out"]:
                    lines.append("    if r > 32767: r = 32767; invalid = 1")
                    lines.append("    elif r < -32768: r = -32768; invalid = 1")
                    lines.append(f"    out[{f['dst']}] = r")
                else:
                    lines.append("    if r > 2147483647: r = 2147483647; sat = 1")
                    lines.append("    elif r < -2147483648: r = -2147483648; sat = 1")
                    lines.append(f"    rf[{f['dst']}] = r")
    lines += [f"    acc[{k}] = acc{k}" for k in range(lanes)]
    lines.append("    return invalid, sat")
    from .tables import seed_recip, seed_isqrt
    ns = {"clz32": clz32, "SEEDR": [v << 15 for v in seed_recip()],
          "SEEDS": [v << 15 for v in seed_isqrt()]}
    exec("\n".join(lines), ns)
    return ns["run"]


_RUN = {L: {name: _compile(name, L) for name in prog.ENTRY} for L in prog.LANES_ALL}
CYCLES_BY_LANES = {L: {name: program_cycles(name, L) for name in prog.ENTRY}
                   for L in prog.LANES_ALL}
CYCLES = CYCLES_BY_LANES[1]


class RlsEngine:
    """State of the engine: register file, accumulators, OUT registers, flags. lanes: the
    engine's LANES (rtl/rls_engine.v), which chooses the ROM image and the clocks per
    program (self.cycles)."""

    def __init__(self, lanes: int = 1):
        if lanes not in prog.LANES_ALL:
            raise ValueError(f"lanes must be one of {prog.LANES_ALL}, got {lanes!r}")
        self.lanes = lanes
        self.cycles = CYCLES_BY_LANES[lanes]
        self.regs = prog.IMAGES[lanes].regs      # persistent name -> register number
        self.rf = list(prog.IMAGES[lanes].rf_init)
        self.out = [0] * len(prog.OUTS)
        self.acc = [0] * lanes
        self.invalid = 0
        self.sat = 0

    def run(self, entry: str, x1=0, x2=0, lambda_k=8, freeze=0, kappa=0, dg=0):
        """Run one program. x1, x2: s1.15 normalised sample (u << g); lambda_k: lambda =
        1/(1 + 2**-k); freeze: no forgetting (the trace bound); kappa: u8.8 (the
        engine's input); dg: input gain change (RESET). Returns True if the program
        ended valid."""
        onel = (1 << 23) + (0 if freeze else 1 << (23 - lambda_k))
        self.invalid, sat = _RUN[self.lanes][entry](
            self.rf, self.out, self.acc, x1 << 15, x2 << 15, onel, kappa << 15,
            1 << (24 - dg), 1 << (24 - 2 * dg))
        self.sat |= sat
        return not self.invalid

    def reg(self, name: str) -> int:
        """A persistent register by name (theta, P, constants)."""
        return self.rf[self.regs[name]]

    def theta(self):
        """theta in the paper's form (s9.23 integers; the register holds theta3 / 2)."""
        t = [self.reg(n) for n in prog.THETA]
        t[2] *= 2
        return t
