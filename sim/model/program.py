"""Microcode of the estimator engine: RLS update (Eqs. 5-7) and CORDIC-free extraction (Eq. 8).

The engine (rtl/estimator.v) is a small fixed-point machine with one pipelined 32x32
multiplier, a 64-bit accumulator and a 64 x 32-bit register file in block RAM. This file
writes its two programs in a readable assembly, schedules them for the pipeline (no
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
  NORMR dz = clz32(A) - 1          (A <= 0: invalid, dz = 0)
  NORMS dz = same, rounded down to even (for inverse square roots)
  CHK   invalid |= (A <= 0)
  END   the program ends; the update program commits OUT[] if not invalid

  A is always a register; B is a register or a special input (sample, settings).
  dyn_amount: 0, dz, or dz/2, with the dz of the last NORM before the instruction.
"""
from dataclasses import dataclass, field

# ---- opcodes and fields (rtl/estimator.v decodes the same) -----------------------------
OP_NOP, OP_MAC, OP_NORMR, OP_NORMS, OP_SEEDR, OP_SEEDS, OP_CHK, OP_END = range(8)
DYN_NONE, DYN_DZ, DYN_DZ2 = range(3)
FIXED_ENTRY = {"reset": 0, "update": 32}   # rtl/estimator.v ENTRY_RESET, ENTRY_UPDATE
ROM_W = 36                     # instruction word width (34 bits used)
RF_DEPTH = 64                  # register file depth
HAZARD = 10                    # a register written by the instruction in slot p may be
                               # read by the instruction in slot p + HAZARD or later

# Special B-operand inputs (index >= 64), latched by the engine at program start.
SPECIALS = {
    "X1": 64,     # s1.30  normalised sample u1 * 2**g (Eq. 5 regressor source)
    "X2": 65,     # s1.30  normalised sample u2 * 2**g
    "LAM": 66,    # s9.23  2**-k  (forgetting: 1/lambda = 1 + 2**-k)
    "KAPPA": 67,  # s9.23  kappa (covariance reset value)
    "GS1": 68,    # s8.24  2**-dg   (theta4,5 rescale when the input gain changes by dg)
    "GS2": 69,    # s8.24  2**-2dg  (theta1,2,3 rescale)
}
OUTS = {"M1": 0, "M2": 1, "C1": 2, "C12": 3, "C2": 4,
        "E": 5}           # the update's a-priori residual 1 - phi' theta, s3.13 (jump detector)

# Formats (fraction bits) used by the program.
F_TH = 23     # theta, P, e, h, K: s9.23
F_X = 30      # x, phi, 1/s, NR mantissas: s2.30 (values within [-2, 2))
F_S = 20      # s = 1 + phi' h: s12.20
F_D = 19      # D/4, theta2*G, numerators: s13.19
F_V = 28      # invsqrt results, 1/D: s4.28
F_M = 30      # offsets m1, m2: s2.30
F_OUT_M = 15  # fast-path offsets: s1.15 (16 bit)
F_OUT_C = 12  # fast-path coefficients c1, c12, c2: s4.12 (16 bit)
F_OUT_E = 13  # residual for the jump detector: s3.13 (16 bit; |e| >= 4 saturates: invalid)

# Constants (register file initial values; never written).
CONSTS = {
    "ZERO": 0,
    "ONE30": 1 << 30,          # 1.0 in s2.30
    "ONE23": 1 << 23,          # 1.0 in s9.23
    "HALF30": 1 << 29,         # 0.5 in s2.30
    "THREE29": 3 << 29,        # 3.0 in s3.29
}
# Initial theta: a centred circle of radius 0.5 (normalised units): theta = [4, 4, 0, 0, 0].
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

    def reads(self):
        if self.op in (OP_NOP, OP_END):
            return set()
        r = {self.a}
        if self.op == OP_MAC:
            r.add(self.b)
        if self.dyn != DYN_NONE:
            r.add("dz")
        return {x for x in r if x not in SPECIALS}

    def writes(self):
        if self.op in (OP_NORMR, OP_NORMS):
            return {"dz"}
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

    def mac(self, terms, dst, sh, dyn=DYN_NONE, out=False, also=()):
        """dst = rnd_shr(sum(+-a*b), sh); terms: (a, b) or (a, b, '-').
        also: further (dst, sh, dyn, out) write-backs of the same accumulator."""
        g = Group()
        for k, t in enumerate(terms):
            a, b = t[0], t[1]
            neg = 1 if len(t) > 2 and t[2] == "-" else 0
            last = k == len(terms) - 1
            g.instrs.append(Instr(OP_MAC, a, b, dst if last else "ZERO", clr=int(k == 0),
                                  neg=neg, wb=int(last), out=int(out and last),
                                  dyn=dyn if last else DYN_NONE, sh=sh if last else 0))
        for d2, sh2, dyn2, out2 in also:
            g.instrs.append(Instr(OP_MAC, "ZERO", "ZERO", d2, wb=1, out=int(out2), dyn=dyn2,
                                  sh=sh2))
        self.groups.append(g)

    def single(self, op, a, dst="ZERO", sh=0):
        wb = 1 if op in (OP_SEEDR, OP_SEEDS) else 0
        self.groups.append(Group([Instr(op, a, "ZERO", dst, wb=wb, sh=sh)]))

    # -- numeric building blocks ------------------------------------------------------
    def recip(self, x, f_in, dst, f_out, tmp):
        """dst = 1/x (x > 0, format f_in) by Newton-Raphson y <- y (2 - m y), 2 iterations."""
        m, y, t = tmp
        self.single(OP_NORMR, x)                               # dz: m = x << dz in [1, 2)
        self.mac([(x, "ONE30")], m, 30, dyn=DYN_DZ)            # m  s2.30
        self.single(OP_SEEDR, m, y)                            # y0 ~ 1/m  s2.30
        for _ in range(2):
            self.mac([(m, y)], t, 30)                          # t = m y
            self.mac([(y, "ONE30"), (y, "ONE30"), (y, t, "-")], y, 30)  # y = 2y - y t
        # 1/x = y * 2**(dz + f_in - 30); written in format f_out
        self.mac([(y, "ONE30")], dst, 90 - f_in - f_out, dyn=DYN_DZ)

    def isqrt(self, x, f_in, dst, f_out, tmp):
        """dst = 1/sqrt(x) (x > 0, format f_in, f_in odd) by y <- y (3 - m y^2) / 2, 2 its."""
        assert f_in % 2 == 1
        m, y, t = tmp
        self.single(OP_NORMS, x)                               # dz even: m in [1, 4)
        self.mac([(x, "ONE30")], m, 30, dyn=DYN_DZ)            # m  s3.29
        self.single(OP_SEEDS, m, y)                            # y0 ~ 1/sqrt(m)  s2.30
        for _ in range(2):
            self.mac([(y, y)], t, 30)                          # t = y^2      s2.30
            self.mac([(m, t)], t, 30)                          # t = m y^2    s3.29
            self.mac([(y, "THREE29"), (y, t, "-")], y, 30)     # y = (3y - y t)/2  s2.30
        # 1/sqrt(x) = y * 2**((dz + f_in - 29)/2); written in format f_out
        self.mac([(y, "ONE30")], dst, 60 - f_out - (f_in - 29) // 2, dyn=DYN_DZ2)


NR_TMP = ("TM", "TY", "TT")                     # Newton-Raphson scratch (shared)
THETA = [f"TH{i}" for i in range(1, 6)]          # s9.23
PHI = ["PHI1", "PHI2", "PHI3", "PHI4", "PHI5"]    # s2.30


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
    a.single(OP_END, "ZERO")
    return a


def update_program() -> Asm:
    """One RLS step (Eqs. 5-7, lambda = 1/(1 + 2**-k)) followed by extraction (Eq. 8)."""
    a = Asm()
    # Eq. 5 regressor: phi = [x1^2, x2^2, x1 x2, x1, x2]  (s2.30)
    a.mac([("ONE30", "X1")], "PHI4", 30)
    a.mac([("ONE30", "X2")], "PHI5", 30)
    a.mac([("PHI4", "X1")], "PHI1", 30)
    a.mac([("PHI5", "X2")], "PHI2", 30)
    a.mac([("PHI4", "X2")], "PHI3", 30)
    # prediction error e = 1 - phi' theta  (s9.23; to OUT E as s3.13 for the jump detector)
    a.mac([("ONE23", "ONE30")] + [(THETA[j], PHI[j], "-") for j in range(5)], "E", 30,
          also=[("E", 53 - F_OUT_E, DYN_NONE, True)])
    # Pl = P / lambda = P (1 + 2**-k);  h = Pl phi:  hp = P phi, h = hp (1 + 2**-k)  (s9.23)
    for i in range(5):
        a.mac([(P(i, j), PHI[j]) for j in range(5)], f"H{i}", 30)
    for i in range(5):
        a.mac([(f"H{i}", "ONE23"), (f"H{i}", "LAM")], f"H{i}", 23)
    # s = 1 + phi' h  (s12.20);  r = 1/s  (s2.30)
    a.mac([("ONE23", "ONE30")] + [(PHI[j], f"H{j}") for j in range(5)], "S", 33)
    a.recip("S", F_S, "R", F_X, NR_TMP)
    # K = h / s  (s9.23)
    for i in range(5):
        a.mac([(f"H{i}", "R")], f"K{i}", 30)
    # theta += K e  (Eq. 7, s9.23)
    for i in range(5):
        a.mac([(THETA[i], "ONE23"), (f"K{i}", "E")], THETA[i], 23)
    # P = Pl - K h'  (upper triangle only: symmetric by construction)
    for i in range(5):
        for j in range(i, 5):
            a.mac([(P(i, j), "ONE23"), (P(i, j), "LAM"), (f"K{i}", f"H{j}", "-")],
                  P(i, j), 23)
    extraction(a)
    a.single(OP_END, "ZERO")
    return a


def extraction(a: Asm):
    """Eq. 8 without CORDIC: centre, scale and the three correction coefficients.

    D4 = theta1 theta2 - (theta3/2)^2 (= D/4 > 0 for an ellipse)
    m1 = (theta3/2 theta5 - theta2 theta4) / (2 D4)
    m2 = (theta3/2 theta4 - theta1 theta5) / (2 D4)
    G  = 1 - (theta4 m1 + theta5 m2) / 2       (= 1 + Q(m), the level of the centred form)
    w  = 1/sqrt(theta2 G)
    c1 = sqrt(D4) w = 1/A1,  c12 = theta3/2 w = sin(phi)/(A1 cos(phi)),
    c2 = theta2 w = R/(A1 cos(phi))            (Eq. 9 as u1c = c1 d1, u2c = c12 d1 + c2 d2)
    """
    th1, th2, th3, th4, th5 = THETA
    a.single(OP_CHK, th2)                                          # theta2 > 0
    a.mac([(th3, "HALF30")], "T3H", 30)                            # theta3/2  s9.23
    a.mac([(th1, th2), ("T3H", "T3H", "-")], "D4", 46 - F_D)       # s13.19
    a.isqrt("D4", F_D, "V", F_V, NR_TMP)               # v = D4^-1/2 (checks > 0)
    a.mac([("V", "V")], "RD", 2 * F_V - F_V)                       # 1/D4  s4.28
    a.mac([("T3H", th5), (th2, th4, "-")], "N1", 46 - F_D + 1)     # numerator / 2  s13.19
    a.mac([("T3H", th4), (th1, th5, "-")], "N2", 46 - F_D + 1)
    a.mac([("N1", "RD")], "M1", F_D + F_V - F_M,
          also=[("M1", F_D + F_V - F_OUT_M, DYN_NONE, True)])     # m1 s2.30, OUT s1.15
    a.mac([("N2", "RD")], "M2", F_D + F_V - F_M,
          also=[("M2", F_D + F_V - F_OUT_M, DYN_NONE, True)])
    a.mac([("ONE23", "ONE30"), ("ONE23", "ONE30"), (th4, "M1", "-"), (th5, "M2", "-")],
          "G", 31)                                                 # 2G >> 1: G s9.23
    a.single(OP_CHK, "G")
    a.mac([(th2, "G")], "Q", 46 - F_D)                             # theta2 G  s13.19
    a.isqrt("Q", F_D, "W", F_V, NR_TMP)
    a.mac([("D4", "V")], "SD", F_D + F_V - F_TH)                   # sqrt(D4)  s9.23
    a.mac([("SD", "W")], "C1", F_TH + F_V - F_OUT_C, out=True)     # s4.12
    a.mac([("T3H", "W")], "C12", F_TH + F_V - F_OUT_C, out=True)
    a.mac([(th2, "W")], "C2", F_TH + F_V - F_OUT_C, out=True)


# ---- register allocation, scheduling, encoding ------------------------------------------
def allocate(programs) -> dict:
    names = list(CONSTS) + THETA
    for prog in programs:
        for g in prog.groups:
            for i in g.instrs:
                for n in (i.a, i.b) + (() if i.out else (i.dst,)):
                    if n not in SPECIALS and n not in names:
                        names.append(n)
    if len(names) > RF_DEPTH:
        raise ValueError(f"register file overflow: {len(names)} > {RF_DEPTH}")
    return {n: k for k, n in enumerate(names)}


def schedule(prog: Asm) -> list[Instr]:
    """List scheduling of groups: a group may be issued before earlier groups it does not
    depend on; NOPs fill slots where no group's operands are ready."""
    pending = list(prog.groups)
    end = pending.pop()                       # END stays last
    ready: dict = {}
    out: list[Instr] = []
    while pending:
        chosen = None
        for idx, g in enumerate(pending):
            gr, gw = g.reads(), g.writes()
            blocked = False
            for e in pending[:idx]:
                er, ew = e.reads(), e.writes()
                if gw & (er | ew) or gr & ew:
                    blocked = True
                    break
            if blocked:
                continue
            slot = len(out)
            ok = all(ready.get(r, 0) <= slot + k
                     for k, ins in enumerate(g.instrs) for r in ins.reads())
            if ok:
                chosen = idx
                break
        if chosen is None:
            out.append(Instr(OP_NOP))
            continue
        g = pending.pop(chosen)
        for ins in g.instrs:
            slot = len(out)
            for w in ins.writes():
                ready[w] = slot + (1 if w == "dz" else HAZARD)
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
    w |= reg(ins.a) << 15
    w |= reg(ins.b) << 21
    w |= dst << 28
    return w


def decode(w: int) -> dict:
    return dict(op=w & 7, clr=(w >> 3) & 1, neg=(w >> 4) & 1, wb=(w >> 5) & 1,
                out=(w >> 6) & 1, dyn=(w >> 7) & 3, sh=(w >> 9) & 63, a=(w >> 15) & 63,
                b=(w >> 21) & 127, dst=(w >> 28) & 63)


def build():
    """Return (rom words, entry addresses, register file init, register map)."""
    progs = {"reset": reset_program(), "update": update_program()}
    regs = allocate(progs.values())
    rom, entry = [], {}
    for name, p in progs.items():
        if name in FIXED_ENTRY:
            if len(rom) > FIXED_ENTRY[name]:
                raise ValueError(f"program before '{name}' overlaps its entry {FIXED_ENTRY[name]}")
            rom += [encode(Instr(OP_NOP), regs)] * (FIXED_ENTRY[name] - len(rom))
        entry[name] = len(rom)
        rom += [encode(i, regs) for i in schedule(p)]
    init = [0] * RF_DEPTH
    for n, v in CONSTS.items():
        init[regs[n]] = v
    for n, v in zip(THETA, THETA_INIT):
        init[regs[n]] = v
    return rom, entry, init, regs


ROM, ENTRY, RF_INIT, REGS = build()
