"""Microcode of the estimator engine: RLS update (Eqs. 5-7) and CORDIC-free extraction (Eq. 8).

The engine (rtl/rls_engine.v) is a small fixed-point machine with one pipelined 32x32
multiplier, a 64-bit accumulator and a 64 x 32-bit register file in block RAM. This file
writes its three programs in a readable assembly, schedules them for the pipeline (no
hazards, NOPs where needed) and encodes the ROM image. The bit-true model
(sim/model/estimator.py) executes exactly the same ROM image, so RTL and model can only
differ if the machine differs, which the block tests check.

Every register holds a 32-bit signed fixed-point number; its format is given where it is
allocated below as sI.F (I integer bits including sign, F fraction bits, I + F = 32).

Instruction semantics (one per slot, in program order):

  MAC   acc = (clr ? 0 : acc) + (neg ? -1 : 1) * A * B      (64-bit wrap)
        if wb:  res = rnd_shr(acc, clamp(sh - dyn_amount, 0, 63))
                out ? OUT[dst] = sat16(res) (invalid if it saturates)
                    : RF[dst] = sat32(res)  (sticky 'sat' if it saturates)
  SEEDR/SEEDS  acc = seed table[A bits] ; write back as MAC (sh = 0)
  NORMR dz[z] = clz32(A) - 1          (A <= 0: invalid, dz[z] = 0)
  NORMS dz[z] = the same, rounded down to even (for inverse square roots)
  CHK   invalid |= (A <= 0)
  END   the program ends

  A is a register or the special X1 / X2; B is a register or a special input (sample,
  settings). dyn_amount: 0, dz[z], or dz[z]/2, with the dz[z] of the last NORM writing
  slot z before the instruction (two slots, so two normalisations can overlap).

Programs:
  reset    P = kappa I; theta rescaled to a new input gain (exact shifts)
  reset    also OUT TR = 5 kappa
  update   one RLS step on a sample; OUT E (a-priori residual, for the jump detector),
           OUT TR (trace of the new P, for the trace bound); invalid when s' = 1 + phi' hl
           is not positive (P no longer positive definite) or E or TR saturates (the
           estimator then resets P)
  extract  theta -> the correction bundle m1, m2, c1, c12, c2 (OUT); invalid when theta
           is not an ellipse or a coefficient does not fit its format
"""
import dataclasses
from dataclasses import dataclass, field

# ---- opcodes and fields (rtl/rls_engine.v decodes the same) -----------------------------
OP_NOP, OP_MAC, OP_NORMR, OP_NORMS, OP_SEEDR, OP_SEEDS, OP_CHK, OP_END = range(8)
DYN_NONE, DYN_DZ, DYN_DZ2 = range(3)
ROM_W = 36                     # instruction word width
RF_DEPTH = 64                  # register file depth
HAZARD_A = 6                   # a register written by the instruction in slot p may be
HAZARD_B = 8                   # read as operand A by the instruction in slot p + HAZARD_A
                               # or later (rtl/rls_engine.v forwards results 6 and 7 slots
                               # old to A), as operand B from slot p + HAZARD_B on; the
                               # scheduler swaps a product's operands where that helps

# Special inputs (index >= 64), latched by the engine at program start or taken from the
# estimator's stable registers. A may be X1 or X2; B may be any of them.
SPECIALS = {
    "X1": 64,     # s2.30  normalised sample u1 * 2**g (Eq. 5 regressor source)
    "X2": 65,     # s2.30  normalised sample u2 * 2**g
    "ONEL": 66,   # s9.23  1 + 2**-k = 1/lambda (forgetting), or 1 while the trace bound
                  #        holds the forgetting off
    "KAPPA": 67,  # s9.23  kappa (covariance reset value)
    "GS1": 68,    # s8.24  2**-dg   (theta4,5 rescale when the input gain changes by dg)
    "GS2": 69,    # s8.24  2**-2dg  (theta1,2,3 rescale)
}
A_SPECIALS = ("X1", "X2")
OUTS = {"M1": 0, "M2": 1, "C1": 2, "C12": 3, "C2": 4,
        "E": 5,           # the update's a-priori residual 1 - phi' theta, s3.13
        "TR": 6}          # trace of P (after the program), s12.4

# Formats (fraction bits) used by the programs.
F_TH = 23     # theta, P, e, h, K: s9.23
F_X = 30      # x, phi, NR mantissas: s2.30 (values within [-2, 2))
F_S = 20      # s = lambda' + phi' h: s12.20
F_D = 19      # D/4, numerators: s13.19
F_Y = 11      # Y = 2 theta2 (2 D4 - X): s21.11 (up to 4 theta2 D4 ~ 2**20)
F_V = 28      # invsqrt results, 1/D: s4.28
F_M = 30      # offsets m1, m2: s2.30
F_OUT_M = 15  # fast-path offsets: s1.15 (16 bit)
F_OUT_C = 12  # fast-path coefficients c1, c12, c2: s4.12 (16 bit)
F_OUT_E = 13  # residual for the jump detector: s3.13 (16 bit; |e| >= 4 saturates: invalid)
F_OUT_TR = 4  # trace of P: s12.4 (16 bit; kappa <= 256 keeps it below 2048 after a reset)

# Constants (register file initial values; never written).
CONSTS = {
    "ZERO": 0,
    "ONE30": 1 << 30,          # 1.0 in s2.30
    "ONE29": 1 << 29,          # 1.0 in s3.29
    "ONE23": 1 << 23,          # 1.0 in s9.23
    "HALF30": 1 << 29,         # 0.5 in s2.30
    "C38": 3 << 27,            # 0.375 in s2.30
}
# Initial theta: a centred circle of radius 0.5 (normalised units): theta = [4, 4, 0, 0, 0]
# (theta3 is held halved: the regressor's third element is 2 u1 u2).
THETA_INIT = [4 << F_TH, 4 << F_TH, 0, 0, 0]


@dataclass
class Instr:
    op: int
    a: str = "ZERO"
    b: str = "ZERO"
    dst: str = "ZERO"
    clr: int = 0
    neg: int = 0
    wb: int = 0
    out: int = 0
    dyn: int = DYN_NONE
    sh: int = 0
    z: int = 0                 # dz slot of a NORM, or read by dyn

    def reads(self):
        if self.op in (OP_NOP, OP_END):
            return set()
        r = {self.a}
        if self.op == OP_MAC:
            r.add(self.b)
        if self.dyn != DYN_NONE:
            r.add(f"dz{self.z}")
        return {x for x in r if x not in SPECIALS}

    def writes(self):
        if self.op in (OP_NORMR, OP_NORMS):
            return {f"dz{self.z}"}
        if self.wb:
            return {("OUT_" if self.out else "") + self.dst}
        return set()


@dataclass
class Group:
    """Instructions issued back to back (they share the accumulator)."""
    instrs: list = field(default_factory=list)

    def reads(self):
        s = set()
        for i in self.instrs:
            s |= i.reads()
        return s

    def writes(self):
        s = set()
        for i in self.instrs:
            s |= i.writes()
        return s


class Asm:
    def __init__(self):
        self.groups: list[Group] = []

    def mac(self, terms, dst, sh, dyn=DYN_NONE, out=False, also=(), z=0):
        """dst = rnd_shr(sum(+-a*b), sh); terms: (a, b) or (a, b, '-').
        also: further (dst, sh, dyn, out) write-backs of the same accumulator."""
        g = Group()
        for k, t in enumerate(terms):
            a, b = t[0], t[1]
            if a in SPECIALS and a not in A_SPECIALS:
                raise ValueError(f"operand A cannot be the special {a}")
            neg = 1 if len(t) > 2 and t[2] == "-" else 0
            last = k == len(terms) - 1
            g.instrs.append(Instr(OP_MAC, a, b, dst if last else "ZERO", clr=int(k == 0),
                                  neg=neg, wb=int(last), out=int(out and last),
                                  dyn=dyn if last else DYN_NONE, sh=sh if last else 0, z=z))
        for d2, sh2, dyn2, out2 in also:
            g.instrs.append(Instr(OP_MAC, "ZERO", "ZERO", d2, wb=1, out=int(out2), dyn=dyn2,
                                  sh=sh2, z=z))
        self.groups.append(g)

    def single(self, op, a, dst="ZERO", sh=0, z=0):
        wb = 1 if op in (OP_SEEDR, OP_SEEDS) else 0
        self.groups.append(Group([Instr(op, a, "ZERO", dst, wb=wb, sh=sh, z=z)]))

    # -- numeric building blocks ------------------------------------------------------
    def isqrt(self, x, f_in, dst, f_out, tmp, z):
        """dst = 1/sqrt(x) (x > 0, format f_in, f_in odd): a 7-bit seed of 1/sqrt(m) and one
        second-order step y1 = y0 (1 + e/2 + 3 e^2/8), e = 1 - m y0^2 (error ~ e^3)."""
        assert f_in % 2 == 1
        m, y, t, e, v = tmp
        self.single(OP_NORMS, x, z=z)                          # dz even: m in [1, 4)
        self.mac([(x, "ONE30")], m, 30, dyn=DYN_DZ, z=z)       # m  s3.29
        self.single(OP_SEEDS, m, y)                            # y0 ~ 1/sqrt(m)  s2.30
        self.mac([(y, y)], t, 30)                              # t = y0^2  s2.30
        self.mac([("ONE29", "ONE30"), (m, t, "-")], e, 29)     # e = 1 - m t  s2.30
        self.mac([("HALF30", "ONE30"), ("C38", e)], v, 30)     # v = 1/2 + 3 e/8  s2.30
        self.mac([("ONE30", "ONE30"), (e, v)], t, 30)          # u = 1 + e v  s2.30
        # 1/sqrt(x) = y0 u * 2**((dz + f_in - 29)/2) (y0 u: 2**60 per unit); format f_out
        self.mac([(y, t)], dst, 60 - f_out - (f_in - 29) // 2, dyn=DYN_DZ2, z=z)


THETA = [f"TH{i}" for i in range(1, 6)]          # s9.23 (TH3 = theta3 / 2)
PHI = ["PHI1", "PHI2", "PHI3", "X1", "X2"]         # s2.30 (PHI3 = 2 x1 x2)


def P(i, j):                                      # s9.23, upper triangle stored
    i, j = min(i, j), max(i, j)
    return f"P{i}{j}"


def reset_program() -> Asm:
    """P <- kappa I (Eq. 7 reset); theta rescaled to the new input gain (exact shifts)."""
    a = Asm()
    for i in range(5):
        for j in range(i, 5):
            if i == j:
                a.mac([("ONE30", "KAPPA")], P(i, j), 30)
            else:
                a.mac([("ZERO", "ZERO")], P(i, j), 0)
    for i in range(5):
        a.mac([(THETA[i], "GS2" if i < 3 else "GS1")], THETA[i], 24)
    a.mac([("ONE30", "KAPPA")] * 5, "TR", 53 - F_OUT_TR, out=True)    # trace 5 kappa
    a.single(OP_END, "ZERO")
    return a


def update_program() -> Asm:
    """One RLS step (Eqs. 5-7) with lambda = 1/(1 + 2**-k):
        h = P phi,  hl = h / lambda,  s' = 1 + phi' hl (= s / lambda),  K = hl / s',
        theta += K e,  P <- P / lambda - K hl'   (= (P - K h') / lambda)."""
    a = Asm()
    # Eq. 5 regressor: phi = [x1^2, x2^2, 2 x1 x2, x1, x2]  (s2.30; x1, x2 are specials)
    a.mac([("X1", "X1")], "PHI1", 30)
    a.mac([("X2", "X2")], "PHI2", 30)
    a.mac([("X1", "X2")], "PHI3", 29)
    # prediction error e = 1 - phi' theta  (s9.23; to OUT E as s3.13 for the jump detector)
    a.mac([("ONE23", "ONE30")] + [(THETA[j], PHI[j], "-") for j in range(5)], "E", 30,
          also=[("E", 53 - F_OUT_E, DYN_NONE, True)])
    # h = P phi (s9.23), hl = h (1 + 2**-k)
    for i in range(5):
        a.mac([(P(i, j), PHI[j]) for j in range(5)], f"H{i}", 30)
    for i in range(5):
        a.mac([(f"H{i}", "ONEL")], f"L{i}", 23)
    # s' = 1 + phi' hl  (s12.20)
    a.mac([("ONE23", "ONE30")] + [(PHI[j], f"L{j}") for j in range(5)], "S", 33)
    # 1/s' from a 7-bit seed and one cubic step: m = s' << dz in [1, 2), y0 ~ 1/m,
    # e = 1 - m y0, u = 1 + e + e^2, 1/m = y0 u (1 + O(e^3))
    a.single(OP_NORMR, "S")
    a.mac([("S", "ONE30")], "RM", 30, dyn=DYN_DZ)              # m  s2.30
    a.single(OP_SEEDR, "RM", "RY")                             # y0  s2.30
    a.mac([("ONE30", "ONE30"), ("RM", "RY", "-")], "RE", 30)  # e  s2.30
    a.mac([("ONE30", "ONE30"), ("RE", "ONE30"), ("RE", "RE")], "RU", 30)   # u  s2.30
    # K = hl / s' = (hl y0) u 2**(dz - 10)  (s9.23)
    for i in range(5):
        a.mac([(f"L{i}", "RY")], f"Y{i}", 30)
    for i in range(5):
        a.mac([(f"Y{i}", "RU")], f"K{i}", 40, dyn=DYN_DZ)
    # theta += K e  (Eq. 7, s9.23)
    for i in range(5):
        a.mac([(THETA[i], "ONE23"), (f"K{i}", "E")], THETA[i], 23)
    # the trace of the new P (s12.4, for the trace bound), from the old diagonal
    a.mac([(P(i, i), "ONEL") for i in range(5)] + [(f"K{i}", f"L{i}", "-") for i in range(5)],
          "TR", 46 - F_OUT_TR, out=True)
    # P = P / lambda - K hl'  (upper triangle only: symmetric by construction)
    for i in range(5):
        for j in range(i, 5):
            a.mac([(P(i, j), "ONEL"), (f"K{i}", f"L{j}", "-")], P(i, j), 23)
    a.single(OP_END, "ZERO")
    return a


def extract_program() -> Asm:
    """Eq. 8 without CORDIC: centre, scale and the three correction coefficients.

    With t3 = theta3 / 2 (TH3), D4 = theta1 theta2 - t3^2 (= D/4 > 0 for an ellipse),
    N1 = (t3 theta5 - theta2 theta4) / 2, N2 = (t3 theta4 - theta1 theta5) / 2:
        m1 = N1 / D4,  m2 = N2 / D4
        G  = 1 - (theta4 m1 + theta5 m2) / 2 = (2 D4 - X) / (2 D4),
             X = theta4 N1 + theta5 N2
        w  = 1/sqrt(theta2 G) = sqrt(4 D4) W,  W = 1/sqrt(Y),  Y = 2 theta2 (2 D4 - X)
        c1 = sqrt(D4) w = 2 D4 W = 1/A1,  c12 = t3 w = sin(phi)/(A1 cos(phi)),
        c2 = theta2 w = R/(A1 cos(phi))   (Eq. 9 as u1c = c1 d1, u2c = c12 d1 + c2 d2)
    The two inverse square roots (of D4 and of Y) depend only on polynomials of theta, so
    they run side by side (two dz slots)."""
    a = Asm()
    th1, th2, th3, th4, th5 = THETA
    a.single(OP_CHK, th2)                                          # theta2 > 0
    a.mac([(th1, th2), (th3, th3, "-")], "D4", 46 - F_D)           # s13.19
    a.mac([(th3, th5), (th2, th4, "-")], "N1", 46 - F_D + 1)       # s13.19
    a.mac([(th3, th4), (th1, th5, "-")], "N2", 46 - F_D + 1)
    a.mac([(th4, "N1"), (th5, "N2")], "XH", 23 + 1)                # X / 2  s13.19
    a.mac([(th2, "D4"), (th2, "XH", "-")], "YY", F_TH + F_D - F_Y - 2)  # 4 th2 (D4 - X/2)
    a.isqrt("D4", F_D, "V", F_V, ("AM", "AY", "AT", "AE", "AV"), z=0)   # D4^-1/2 (> 0)
    a.isqrt("YY", F_Y, "W", F_V, ("BM", "BY", "BT", "BE", "BV"), z=1)   # Y^-1/2 (> 0)
    a.mac([("V", "V")], "RD", 2 * F_V - F_V)                       # 1/D4  s4.28
    a.mac([("D4", "V")], "SD", F_D + F_V - F_TH)                   # sqrt(D4)  s9.23
    a.mac([("N1", "RD")], "M1", F_D + F_V - F_OUT_M, out=True)     # m1, OUT s1.15
    a.mac([("N2", "RD")], "M2", F_D + F_V - F_OUT_M, out=True)
    a.mac([("D4", "W")], "C1", F_D + F_V - F_OUT_C - 1, out=True)  # 2 D4 W, s4.12
    a.mac([("SD", "W")], "SW", F_TH + F_V - F_TH)                  # sqrt(D4) W  s9.23
    a.mac([(th3, "SW")], "C12", 2 * F_TH - F_OUT_C - 1, out=True)  # 2 t3 sqrt(D4) W
    a.mac([(th2, "SW")], "C2", 2 * F_TH - F_OUT_C - 1, out=True)   # 2 th2 sqrt(D4) W
    a.single(OP_END, "ZERO")
    return a


# ---- register allocation, scheduling, encoding ------------------------------------------
def persistent_names() -> list:
    """Registers that keep their values between programs: constants, theta and P."""
    return list(CONSTS) + THETA + [P(i, j) for i in range(5) for j in range(i, 5)]


def allocate(programs) -> dict:
    """Register numbers: the persistent registers first, then each program's temporaries
    from the same base (programs never run at once, and a temporary is written before a
    program reads it, so programs share those registers)."""
    regs = {n: k for k, n in enumerate(persistent_names())}
    base = len(regs)
    for prog in programs:
        written, nxt = set(), base
        for g in prog.groups:
            for i in g.instrs:
                for n in (i.a, i.b):
                    if n in SPECIALS or n in regs and n in persistent_names():
                        continue
                    if n not in written:
                        raise ValueError(f"temporary {n} read before it is written")
                if i.wb and not i.out and i.dst not in persistent_names():
                    written.add(i.dst)
                    if i.dst not in regs:
                        regs[i.dst] = nxt
                        nxt += 1
                    elif regs[i.dst] < base:
                        raise ValueError(f"{i.dst} is persistent")
                # a name used by an earlier program is reused as is (same role)
            nxt = max(nxt, max((v + 1 for k, v in regs.items() if k in written), default=base))
        if nxt > RF_DEPTH:
            raise ValueError(f"register file overflow: {nxt} > {RF_DEPTH}")
    return regs


def _conflict(earlier: Group, later: Group) -> bool:
    """later may not be issued before earlier (RAW, WAR or WAW on a register or dz)."""
    er, ew, lr, lw = earlier.reads(), earlier.writes(), later.reads(), later.writes()
    return bool(lw & (er | ew) or lr & ew)


def _ready_as(ready, r, which, slot):
    """Register r may be read as operand `which` ('a' or 'b') in `slot`."""
    if r in SPECIALS:
        return True
    t = ready.get(r)
    return t is None or t[0 if which == "a" else 1] <= slot


def _fit(ins: Instr, ready, slot):
    """How ins can be issued in slot: 'keep', 'swap' (a MAC with its operands exchanged)
    or None."""
    dz_ok = all(_ready_as(ready, r, "a", slot) for r in ins.reads() if r.startswith("dz"))
    if not dz_ok:
        return None
    if ins.op != OP_MAC:
        return "keep" if all(_ready_as(ready, r, "a", slot) for r in ins.reads()) else None
    if _ready_as(ready, ins.a, "a", slot) and _ready_as(ready, ins.b, "b", slot):
        return "keep"
    if (ins.b not in SPECIALS or ins.b in A_SPECIALS) and \
            _ready_as(ready, ins.b, "a", slot) and _ready_as(ready, ins.a, "b", slot):
        return "swap"
    return None


def schedule(prog: Asm) -> list[Instr]:
    """List scheduling of groups: a group may be issued before earlier groups it does not
    depend on; among the groups whose operands are ready, the one with the longest
    dependent chain to the end goes first; NOPs fill slots where none is ready. A
    product's operands are exchanged when that lets it issue earlier (the engine forwards
    young results to operand A only)."""
    pending = list(prog.groups)
    end = pending.pop()                       # END stays last
    n = len(pending)
    # height: the longest chain of results (HAZARD_A per step, plus the group's length)
    # from a group to the end of the program
    height = [0] * n
    for i in range(n - 1, -1, -1):
        h = len(pending[i].instrs)
        for j in range(i + 1, n):
            if _conflict(pending[i], pending[j]):
                h = max(h, len(pending[i].instrs) - 1 + HAZARD_A + height[j])
        height[i] = h
    order = list(range(n))
    ready: dict = {}
    out: list[Instr] = []
    while order:
        chosen, fits = None, None
        for pos, gi in enumerate(order):
            g = pending[gi]
            if any(_conflict(pending[e], g) for e in order[:pos]):
                continue
            slot = len(out)
            f = [_fit(ins, ready, slot + k) for k, ins in enumerate(g.instrs)]
            if all(f) and (chosen is None or height[gi] > height[order[chosen]]):
                chosen, fits = pos, f
        if chosen is None:
            out.append(Instr(OP_NOP))
            continue
        g = pending[order.pop(chosen)]
        for ins, f in zip(g.instrs, fits):
            if f == "swap":
                ins = dataclasses.replace(ins, a=ins.b, b=ins.a)
            slot = len(out)
            for w in ins.writes():
                ready[w] = (slot + 1, slot + 1) if w.startswith("dz") else \
                    (slot + HAZARD_A, slot + HAZARD_B)
            out.append(ins)
    out.extend(end.instrs)   # END acts in the write-back stage, after every earlier write
    return out


def encode(ins: Instr, regs: dict) -> int:
    def reg(n):
        return SPECIALS[n] if n in SPECIALS else regs[n]
    dst = OUTS[ins.dst] if ins.out else regs[ins.dst]
    w = ins.op
    w |= ins.clr << 3
    w |= ins.neg << 4
    w |= ins.wb << 5
    w |= ins.out << 6
    w |= ins.dyn << 7
    w |= ins.sh << 9
    w |= ins.z << 15
    w |= reg(ins.a) << 16
    w |= reg(ins.b) << 23
    w |= dst << 30
    return w


def decode(w: int) -> dict:
    return dict(op=w & 7, clr=(w >> 3) & 1, neg=(w >> 4) & 1, wb=(w >> 5) & 1,
                out=(w >> 6) & 1, dyn=(w >> 7) & 3, sh=(w >> 9) & 63, z=(w >> 15) & 1,
                a=(w >> 16) & 127, b=(w >> 23) & 127, dst=(w >> 30) & 63)


def build():
    """Return (rom words, entry addresses, register file init, register map)."""
    progs = {"reset": reset_program(), "update": update_program(),
             "extract": extract_program()}
    regs = allocate(progs.values())
    rom, entry = [], {}
    for name, p in progs.items():           # packed; rtl/tables/rls_entries.vh tells the RTL
        entry[name] = len(rom)
        rom += [encode(i, regs) for i in schedule(p)]
    init = [0] * RF_DEPTH
    for n, v in CONSTS.items():
        init[regs[n]] = v
    for n, v in zip(THETA, THETA_INIT):
        init[regs[n]] = v
    return rom, entry, init, regs


ROM, ENTRY, RF_INIT, REGS = build()
