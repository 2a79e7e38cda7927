"""Microcode of the RLS engine (rtl/rls_engine.v): the RLS update (Eqs. 5-7), extraction (Eq. 8).

The engine (rtl/rls_engine.v) is a small fixed-point VLIW machine with LANES (1 or 2)
lanes, each a pipelined 32x32 multiplier with its own 64-bit accumulator and write-back,
and a 64 x 32-bit register file in block RAM. This file writes its three programs in a
readable assembly, schedules them for the pipeline and the lanes (no hazards, NOPs where
needed) and encodes one ROM image per LANES. The bit-true model (sim/model/rls_engine.py)
executes exactly the same ROM image, so RTL and model can only differ if the machine
differs, which the block tests check.

Every register holds a 32-bit signed fixed-point number; its format is given where it is
used below as sI.F (I integer bits including sign, F fraction bits, I + F = 32).

Instruction semantics (one per lane and slot; a slot's lanes issue together):

  MAC   acc = (clr ? 0 : acc) + (neg ? -1 : 1) * A * B      (64-bit wrap; acc of the lane)
        if wb:  res = rnd_shr(acc, clamp(sh - dyn_amount, 0, 63))
                out ? OUT[dst] = sat16(res) (invalid if it saturates)
                    : RF[dst] = sat32(res)  (sticky 'sat' if it saturates)
  SEEDR acc = seed table[bits 29..23 of A << dz[z]] << 15   (1/m of the normalised
        mantissa m = A << dz in [1, 2), s2.30); write back as MAC (sh = 0)
  SEEDS the same for 1/sqrt(m), bits 30..24 of A << dz[z] (m in [1, 4), s3.29)
  NORMR dz[z] = clz32(A) - 1          (A <= 0: invalid, dz[z] = 0)
  NORMS dz[z] = the same, rounded down to even (for inverse square roots)
  CHK   invalid |= (A <= 0)
  END   the program ends (lane 0; the other lanes hold NOPs in that slot)

  A is a register or the special X1 / X2; B is a register or any special input.
  dyn_amount: 0, dz[z], or dz[z]/2, with the dz[z] of the last NORM writing slot z before
  the instruction (two slots, so two normalisations can overlap); the lanes share dz.

Timing (rtl/rls_engine.v): an instruction in slot k writes its register on edge S + k +
PIPE; a register written in slot k may be read (as A or B: both are forwarded) from slot
k + HAZARD on, a dz from slot k + 1 on. Reading a register (or dz) in the slot where a
later instruction writes it, or later, reads the new value, so the scheduler keeps every
read of an old value in an earlier slot than the write that replaces it, and a slot's
lanes never depend on each other: the model may execute a slot's lanes in any order.

Register file and lanes: with LANES = 2 the 64 registers form two banks, 0..31 written
only by lane 0 and 32..63 only by lane 1 (each bank is a block RAM per read port: four
read ports, one write port each); any lane reads any register. The scheduler assigns
every written register to the lane that writes it (persistent registers: as the UPDATE
program's schedule chose; RESET then writes them from the same lanes), and the
allocator places it in that lane's bank. With LANES = 1 there is one bank of 64.

Programs:
  reset    P = kappa I; OUT TR = 5 kappa; theta rescaled to a new input gain (exact
           shifts)
  update   one RLS step on a sample; OUT E (a-priori residual, for the jump detector),
           OUT TR (trace of the new P, from its stored diagonal, for the trace bound);
           invalid when s' = 1 + phi' hl is not positive (P no longer positive definite)
           or E or TR saturates (the estimator then resets P)
  extract  theta -> the correction bundle m1, m2, c1, c12, c2 (OUT); invalid when theta
           is not an ellipse or a coefficient does not fit its format
"""
from dataclasses import dataclass, field

# ---- opcodes and fields (rtl/rls_engine.v decodes the same) -----------------------------
OP_NOP, OP_MAC, OP_NORMR, OP_NORMS, OP_SEEDR, OP_SEEDS, OP_CHK, OP_END = range(8)
DYN_NONE, DYN_DZ, DYN_DZ2 = range(3)
IW = 36                        # instruction width (one lane); a ROM word holds LANES of them
ROM_W = IW                     # ROM word width with LANES = 1
RF_DEPTH = 64                  # register file depth (all banks)
LANES_ALL = (1, 2)
PIPE = 8                       # slot k writes on edge S + k + PIPE (END: the program ends)
HAZARD = 6                     # a register written in slot k is read from slot k + HAZARD on
HAZARD_A = HAZARD              # (rtl/rls_engine.v forwards the results 6 and 7 slots old
HAZARD_B = HAZARD              # to both operands and reads the register file after that)

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
    "FIVE27": 5 << 27,         # 5.0 in s5.27
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
    z: int = 0                 # dz slot of a NORM or SEED, or read by dyn

    def reads(self):
        """Register names (and dz0/dz1) read; specials are not registers."""
        if self.op in (OP_NOP, OP_END):
            return set()
        r = {self.a}
        if self.op == OP_MAC:
            r.add(self.b)
        if self.dyn != DYN_NONE or self.op in (OP_SEEDR, OP_SEEDS):
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
    """Instructions issued back to back in one lane (they share its accumulator). A MAC
    group is a sum of products (terms, in any order: the 64-bit sum is exact) written
    back by its last term, then by the further write-backs in `also` (same accumulator,
    other shifts or destinations, one slot each). Other groups hold one instruction."""
    terms: list = field(default_factory=list)    # [(a, b, neg)]
    wb: tuple = None                             # (dst, sh, dyn, out) of the last term
    also: list = field(default_factory=list)     # [(dst, sh, dyn, out)]
    z: int = 0
    single: Instr = None                         # NORM, SEED, CHK

    def __len__(self):
        return 1 if self.single else len(self.terms) + len(self.also)

    def instrs(self, order=None) -> list:
        if self.single:
            return [self.single]
        terms = [self.terms[k] for k in order] if order else self.terms
        out = []
        for k, (a, b, neg) in enumerate(terms):
            last = k == len(terms) - 1
            dst, sh, dyn, o = self.wb if last else ("ZERO", 0, DYN_NONE, False)
            out.append(Instr(OP_MAC, a, b, dst, clr=int(k == 0), neg=neg, wb=int(last),
                             out=int(o), dyn=dyn, sh=sh, z=self.z))
        for dst, sh, dyn, o in self.also:
            out.append(Instr(OP_MAC, "ZERO", "ZERO", dst, wb=1, out=int(o), dyn=dyn, sh=sh,
                             z=self.z))
        return out

    def reads(self):
        if not hasattr(self, "_r"):
            self._r = set().union(*(i.reads() for i in self.instrs()))
        return self._r

    def writes(self):
        if not hasattr(self, "_w"):
            self._w = set().union(*(i.writes() for i in self.instrs()))
        return self._w


class Asm:
    def __init__(self):
        self.groups: list[Group] = []

    def mac(self, terms, dst, sh, dyn=DYN_NONE, out=False, also=(), z=0):
        """dst = rnd_shr(sum(+-a*b), sh); terms: (a, b) or (a, b, '-').
        also: further (dst, sh, dyn, out) write-backs of the same accumulator."""
        ts = []
        for t in terms:
            a, b = t[0], t[1]
            if a in SPECIALS and a not in A_SPECIALS:
                if b in SPECIALS and b not in A_SPECIALS:
                    raise ValueError(f"operand A cannot be the special {a}")
                a, b = b, a
            ts.append((a, b, 1 if len(t) > 2 and t[2] == "-" else 0))
        self.groups.append(Group(ts, (dst, sh, dyn, out), list(also), z))

    def single(self, op, a, dst="ZERO", sh=0, z=0):
        wb = 1 if op in (OP_SEEDR, OP_SEEDS) else 0
        self.groups.append(Group(single=Instr(op, a, "ZERO", dst, clr=wb, wb=wb, sh=sh, z=z),
                                 z=z))

    # -- numeric building blocks ------------------------------------------------------
    def isqrt(self, x, f_in, dst, f_out, tmp, z):
        """dst = 1/sqrt(x) (x > 0, format f_in, f_in odd): a 7-bit seed of 1/sqrt(m) and one
        second-order step y1 = y0 (1 + e/2 + 3 e^2/8) = y0 + (y0 e) v, e = 1 - m y0^2,
        v = 1/2 + 3 e/8 (error ~ e^3)."""
        assert f_in % 2 == 1
        m, y, t, e, v, ye = tmp
        self.single(OP_NORMS, x, z=z)                          # dz even: m in [1, 4)
        self.mac([(x, "ONE30")], m, 30, dyn=DYN_DZ, z=z)       # m  s3.29
        self.single(OP_SEEDS, x, y, z=z)                       # y0 ~ 1/sqrt(m)  s2.30
        self.mac([(y, y)], t, 30)                              # t = y0^2  s2.30
        self.mac([("ONE29", "ONE30"), (m, t, "-")], e, 29)     # e = 1 - m t  s2.30
        self.mac([("HALF30", "ONE30"), ("C38", e)], v, 30)     # v = 1/2 + 3 e/8  s2.30
        self.mac([(y, e)], ye, 30)                             # y0 e  s2.30
        # 1/sqrt(x) = (y0 + y0 e v) * 2**((dz + f_in - 29)/2) (2**60 per unit); format f_out
        self.mac([(y, "ONE30"), (ye, v)], dst, 60 - f_out - (f_in - 29) // 2, dyn=DYN_DZ2,
                 z=z)


THETA = [f"TH{i}" for i in range(1, 6)]          # s9.23 (TH3 = theta3 / 2)
PHI = ["PHI1", "PHI2", "PHI3", "X1", "X2"]         # s2.30 (PHI3 = 2 x1 x2)


def P(i, j):                                      # s9.23, upper triangle stored
    i, j = min(i, j), max(i, j)
    return f"P{i}{j}"


def reset_program() -> Asm:
    """P <- kappa I (Eq. 7 reset), OUT TR = 5 kappa; theta rescaled to the new input gain
    (exact shifts)."""
    a = Asm()
    for i in range(5):
        for j in range(i, 5):
            if i == j:
                a.mac([("ONE30", "KAPPA")], P(i, j), 30)
            else:
                a.mac([("ZERO", "ZERO")], P(i, j), 0)
    for i in range(5):
        a.mac([(THETA[i], "GS2" if i < 3 else "GS1")], THETA[i], 24)
    # trace 5 kappa: s9.23 * s5.27 = 2**50 per unit; OUT TR s12.4
    a.mac([("FIVE27", "KAPPA")], "TR", 50 - F_OUT_TR, out=True)
    a.single(OP_END, "ZERO")
    return a


def update_program(ru_v=False) -> Asm:
    """One RLS step (Eqs. 5-7) with lambda = 1/(1 + 2**-k):
        h = P phi,  hl = h / lambda,  s' = 1 + phi' hl (= s / lambda),  K = hl / s',
        theta += K e,  P <- P / lambda - K hl'   (= (P - K h') / lambda),
        OUT TR = trace(P).
    ru_v: u = 1 + e (1 + e) instead of 1 + e + e^2 (bit for bit the same, one dependent
    product less, one product more: the shorter program for two lanes)."""
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
    # s' = 1 + (phi (1 + 2**-k))' h  (s12.20), with phi (1 + 2**-k) in s3.29 (|2 x1 x2| /
    # lambda < 4): s' waits for h, not for hl
    for j in range(5):
        a.mac([(PHI[j], "ONEL")], f"PL{j}", 24)
    a.mac([("ONE23", "ONE29")] + [(f"PL{j}", f"H{j}") for j in range(5)], "S", 32)
    # 1/s' from a 7-bit seed and one cubic step: m = s' << dz in [1, 2), y0 ~ 1/m,
    # e = 1 - m y0, u = 1 + e + e^2, 1/m = y0 u (1 + O(e^3)); the seed is read with the
    # normalised S (SEEDR shifts by dz), so it does not wait for m
    a.single(OP_NORMR, "S")
    a.mac([("S", "ONE30")], "RM", 30, dyn=DYN_DZ)              # m  s2.30
    a.single(OP_SEEDR, "S", "RY")                              # y0  s2.30
    a.mac([("ONE30", "ONE30"), ("RM", "RY", "-")], "RE", 30)  # e  s2.30
    if ru_v:
        # 1 + e = 2 - m y0 is RE + 2**30 exactly (the same rounding), so RE * RV is
        # RE + RE^2 exactly (also where RV saturates: then e >= 1 and u saturates too)
        a.mac([("ONE30", "ONE30"), ("ONE30", "ONE30"), ("RM", "RY", "-")], "RV", 30)
        a.mac([("ONE30", "ONE30"), ("RE", "RV")], "RU", 30)  # u  s2.30
    else:
        a.mac([("ONE30", "ONE30"), ("RE", "ONE30"), ("RE", "RE")], "RU", 30)   # u  s2.30
    # K = hl / s' = (hl y0) u 2**(dz - 10)  (s9.23)
    for i in range(5):
        a.mac([(f"L{i}", "RY")], f"Y{i}", 30)
    for i in range(5):
        a.mac([(f"Y{i}", "RU")], f"K{i}", 40, dyn=DYN_DZ)
    # theta += K e  (Eq. 7, s9.23)
    for i in range(5):
        a.mac([(THETA[i], "ONE23"), (f"K{i}", "E")], THETA[i], 23)
    # P = P / lambda - K hl'  (upper triangle only: symmetric by construction)
    for i in range(5):
        for j in range(i, 5):
            a.mac([(P(i, j), "ONEL"), (f"K{i}", f"L{j}", "-")], P(i, j), 23)
    # the trace of the new P, s12.4 to OUT TR (the trace bound), from its stored diagonal
    # (kept as TR / lambda - K' hl in a register instead, its error would grow by
    # 1/lambda per update: the recursion has no feedback from P)
    a.mac([(P(i, i), "ONE23") for i in range(5)], "TR", 46 - F_OUT_TR, out=True)
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
    # Y = 4 th2 D4 - 2 th2 (th4 N1 + th5 N2), with th2 th4 / 2 and th2 th5 / 2 formed
    # beside D4 and N1, N2 (s9.23), so that Y is two products deep, like D4
    a.mac([(th2, th4)], "T24", 24)
    a.mac([(th2, th5)], "T25", 24)
    a.mac([(th2, "D4"), ("T24", "N1", "-"), ("T25", "N2", "-")], "YY",
          F_TH + F_D - F_Y - 2)                                    # s21.11
    a.isqrt("D4", F_D, "V", F_V, ("AM", "AY", "AT", "AE", "AV", "AYE"), z=0)  # D4^-1/2
    a.isqrt("YY", F_Y, "W", F_V, ("BM", "BY", "BT", "BE", "BV", "BYE"), z=1)  # Y^-1/2
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


PROGRAMS = {"reset": reset_program, "update": update_program, "extract": extract_program}
# per LANES: the program variant (all bit for bit the same) and the scheduler's priority
# weights tried (the shortest schedule is kept; ties: the first)
VARIANT = {1: {"update": {}}, 2: {"update": {"ru_v": True}}}
ALPHAS = (0.0, 0.5)


# ---- scheduling --------------------------------------------------------------------------
def persistent_names() -> list:
    """Registers that keep their values between programs: constants, theta and P."""
    return list(CONSTS) + THETA + [P(i, j) for i in range(5) for j in range(i, 5)]


def _conflict(earlier: Group, later: Group) -> bool:
    """later depends on earlier (RAW, WAR or WAW on a register, dz or OUT)."""
    er, ew, lr, lw = earlier.reads(), earlier.writes(), later.reads(), later.writes()
    return bool(lw & (er | ew) or lr & ew)


def _raw(earlier: Group, later: Group) -> bool:
    return bool(later.reads() & earlier.writes())


def _heights(groups, lanes=1, alpha=1.0) -> list:
    """Priority of each group: the slots from its issue to the program's END if every
    dependence were the only constraint (RAW: the reading term HAZARD slots after the
    write, at the end of the reader; WAR/WAW: one slot later), or, where larger, alpha
    times the slots its dependent groups need on `lanes` lanes after its result."""
    n = len(groups)
    tail = [1] * n                 # END one slot after the group's last instruction
    succ = [set() for _ in range(n)]
    for i in range(n - 1, -1, -1):
        for j in range(i + 1, n):
            if _conflict(groups[i], groups[j]):
                d = HAZARD if _raw(groups[i], groups[j]) else 1
                tail[i] = max(tail[i], d + tail[j])
                succ[i] |= {j} | succ[j]
    work = [alpha * sum(len(groups[j]) for j in succ[i]) / lanes for i in range(n)]
    return [len(g) - 1 + max(t, (HAZARD + w) if w else 1)
            for g, t, w in zip(groups, tail, work)]


@dataclass
class Schedule:
    slots: list          # slots[k][lane] = Instr
    lane_of: dict        # register name -> lane that writes it


def schedule(prog: Asm, lanes: int = 1, bank=None, alpha=0.0) -> Schedule:
    """List scheduling with backfilling: the groups are placed one at a time, among those
    whose earlier dependences are placed the one with the longest chain to the end first
    (ties: program order), each at the earliest slot and lane where it fits: every
    term's operands ready in its slot (terms ordered by readiness), every write after
    the last read of the old value and after the previous write, the lane free for the
    group's length, and the destination in the lane's bank. bank: the lane of registers
    already placed (others take the lane of their first write)."""
    groups = list(prog.groups)
    end = groups.pop()                              # END stays last
    height = _heights(groups, lanes, alpha)
    lane_of = dict(bank or {})
    ready: dict = {}          # name -> first slot it may be read (latest value)
    last_read: dict = {}      # name -> last slot a placed instruction reads it
    last_write: dict = {}     # name -> slot of the last placed write
    used = [set() for _ in range(lanes)]
    placed: dict = {}         # (slot, lane) -> Instr
    deps = {j: [i for i in range(j) if _conflict(groups[i], groups[j])]
            for j in range(len(groups))}
    done = set()

    def rdy(name):
        return 0 if name in SPECIALS else ready.get(name, 0)

    def fit(g: Group, t: int, lane: int):
        """The instructions of g issued from slot t on lane, or None if it cannot."""
        if any(t + k in used[lane] for k in range(len(g))):
            return None
        if g.single:
            seq = [g.single]
        else:
            order = sorted(range(len(g.terms)),
                           key=lambda k: (max(rdy(g.terms[k][0]), rdy(g.terms[k][1])), k))
            seq = g.instrs(order)
        for k, ins in enumerate(seq):
            if any(rdy(r) > t + k for r in ins.reads()):
                return None
            for w in ins.writes():
                if last_read.get(w, -1) >= t + k or last_write.get(w, -1) >= t + k:
                    return None
                if not w.startswith(("dz", "OUT_")) and lane_of.get(w, lane) != lane:
                    return None
        return seq

    while len(done) < len(groups):
        cand = [i for i in range(len(groups))
                if i not in done and all(d in done for d in deps[i])]
        gi = max(cand, key=lambda i: (height[i], -i))
        g = groups[gi]
        best = None
        t = 0
        while best is None:
            for lane in range(lanes):
                seq = fit(g, t, lane)
                if seq is not None:
                    best = (t, lane, seq)
                    break
            t += 1
        t, lane, seq = best
        done.add(gi)
        for k, ins in enumerate(seq):
            s = t + k
            used[lane].add(s)
            placed[(s, lane)] = ins
            for r in ins.reads():
                last_read[r] = max(last_read.get(r, -1), s)
            for w in ins.writes():
                last_write[w] = s
                ready[w] = s + (1 if w.startswith("dz") else HAZARD)
                if not w.startswith(("dz", "OUT_")):
                    lane_of.setdefault(w, lane)
    n = max((s for s, _ in placed), default=-1) + 1
    slots = [[placed.get((k, lane), Instr(OP_NOP)) for lane in range(lanes)]
             for k in range(n)]
    slots.append([end.single] + [Instr(OP_NOP) for _ in range(lanes - 1)])
    return Schedule(slots, lane_of)


# ---- register allocation and encoding ----------------------------------------------------
def allocate(scheds: dict, lanes: int) -> dict:
    """Register numbers. Bank b (registers b * 64/LANES ..) holds the registers lane b
    writes. Persistent registers first (theta, P in the bank of their lane, then the
    constants wherever there is room), then each program's temporaries: a register is
    reused once its value's last read lies before the new value's first write."""
    per = RF_DEPTH // lanes
    regs: dict = {}
    free = {b: list(range(b * per, (b + 1) * per)) for b in range(lanes)}
    lane_of: dict = {}
    for s in scheds.values():
        for k, v in s.lane_of.items():
            if k in lane_of and lane_of[k] != v:
                raise ValueError(f"{k} written by lanes {lane_of[k]} and {v}")
            lane_of[k] = v
    for n in persistent_names():
        if n in CONSTS:
            continue
        b = lane_of.get(n, 0)
        regs[n] = free[b].pop(0)
    for n in CONSTS:
        b = max(range(lanes), key=lambda x: len(free[x]))
        regs[n] = free[b].pop(0)
    for name, s in scheds.items():
        first_w, first_r, last_r = {}, {}, {}
        for k, slot in enumerate(s.slots):
            for ins in slot:
                for r in ins.reads():
                    if not r.startswith("dz"):
                        first_r.setdefault(r, k)
                        last_r[r] = k
                for w in ins.writes():
                    if not w.startswith(("dz", "OUT_")):
                        first_w.setdefault(w, k)
        temps = sorted((n for n in first_w if n not in regs), key=lambda n: first_w[n])
        for n in set(last_r) - set(first_w) - set(regs):
            raise ValueError(f"{name}: temporary {n} read before it is written")
        busy_until = {}                       # register -> last slot its value is read
        for n in temps:
            if first_r.get(n, first_w[n]) <= first_w[n] and n in first_r:
                raise ValueError(f"{name}: {n} read before it is written")
            b = s.lane_of[n]
            cands = [r for r in free[b] if busy_until.get(r, -1) < first_w[n]]
            if not cands:
                raise ValueError(f"{name}: bank {b} full")
            regs[(name, n)] = cands[0]
            busy_until[cands[0]] = last_r.get(n, first_w[n])
    return regs


def encode(ins: Instr, reg) -> int:
    dst = OUTS[ins.dst] if ins.out else reg(ins.dst)
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
    """Fields of one lane's instruction (the low IW bits of w)."""
    return dict(op=w & 7, clr=(w >> 3) & 1, neg=(w >> 4) & 1, wb=(w >> 5) & 1,
                out=(w >> 6) & 1, dyn=(w >> 7) & 3, sh=(w >> 9) & 63, z=(w >> 15) & 1,
                a=(w >> 16) & 127, b=(w >> 23) & 127, dst=(w >> 30) & 63)


def decode_word(w: int, lanes: int) -> list:
    """The LANES instructions of a ROM word (lane 0 in the low bits)."""
    return [decode(w >> (IW * k)) for k in range(lanes)]


@dataclass
class Image:
    lanes: int
    rom: list            # ROM words (LANES * IW bits), programs at `entry`
    entry: dict          # program -> entry address (the same for every LANES)
    length: dict         # program -> slots up to and including END
    rf_init: list        # RF_DEPTH initial values (register number order)
    regs: dict           # persistent name -> register number
    temps: dict          # (program, name) -> register number
    scheds: dict


def _best(name: str, lanes: int, bank=None) -> Schedule:
    prog = PROGRAMS[name](**VARIANT[lanes].get(name, {}))
    best = None
    for alpha in ALPHAS:
        s = schedule(prog, lanes, bank, alpha)
        if best is None or len(s.slots) < len(best.slots):
            best = s
    return best


def _build_lanes(lanes: int):
    scheds = {"update": _best("update", lanes)}
    placed = {n: v for n, v in scheds["update"].lane_of.items() if n in persistent_names()}
    for n in ("reset", "extract"):
        scheds[n] = _best(n, lanes, bank=placed)
    order = {n: scheds[n] for n in PROGRAMS}
    return order, allocate(order, lanes)


def build_all() -> dict:
    """One Image per LANES, with the same entry addresses (rtl/tables/rls_entries.vh
    serves both): each program starts after the longest previous one."""
    built = {L: _build_lanes(L) for L in LANES_ALL}
    entry, pos = {}, 0
    for n in PROGRAMS:
        entry[n] = pos
        pos += max(len(built[L][0][n].slots) for L in LANES_ALL)
    images = {}
    for L, (scheds, regs) in built.items():
        rom = [0] * pos
        for n, s in scheds.items():
            def reg(x, n=n):
                if x in SPECIALS:
                    return SPECIALS[x]
                return regs[x] if x in regs else regs[(n, x)]
            for k, slot in enumerate(s.slots):
                w = 0
                for lane, ins in enumerate(slot):
                    w |= encode(ins, reg) << (IW * lane)
                rom[entry[n] + k] = w
        init = [0] * RF_DEPTH
        for n, v in CONSTS.items():
            init[regs[n]] = v
        for n, v in zip(THETA, THETA_INIT):
            init[regs[n]] = v
        images[L] = Image(L, rom, dict(entry), {n: len(s.slots) for n, s in scheds.items()},
                          init, {k: v for k, v in regs.items() if isinstance(k, str)},
                          {k: v for k, v in regs.items() if isinstance(k, tuple)}, scheds)
    return images


IMAGES = build_all()
# the one-lane image under the old names
ROM, ENTRY, RF_INIT, REGS = IMAGES[1].rom, IMAGES[1].entry, IMAGES[1].rf_init, IMAGES[1].regs


def listing(lanes: int, name: str) -> str:
    """Readable schedule of a program (for reviews and the README)."""
    s = IMAGES[lanes].scheds[name]
    lines = []
    for k, slot in enumerate(s.slots):
        cols = []
        for ins in slot:
            if ins.op == OP_NOP:
                cols.append("-")
            elif ins.op == OP_MAC:
                t = f"{'-' if ins.neg else '+'}{ins.a}*{ins.b}" + (" clr" if ins.clr else "")
                if ins.wb:
                    t += f" -> {'OUT ' if ins.out else ''}{ins.dst}>>{ins.sh}" + \
                        ("-dz" if ins.dyn == DYN_DZ else "-dz/2" if ins.dyn == DYN_DZ2 else "")
                cols.append(t)
            else:
                op = {OP_NORMR: "NORMR", OP_NORMS: "NORMS", OP_SEEDR: "SEEDR",
                      OP_SEEDS: "SEEDS", OP_CHK: "CHK", OP_END: "END"}[ins.op]
                cols.append(f"{op} {ins.a}" + (f" -> {ins.dst}" if ins.wb else ""))
        lines.append(f"{k:3d}  " + " | ".join(f"{c:34s}" for c in cols))
    return "\n".join(lines)
