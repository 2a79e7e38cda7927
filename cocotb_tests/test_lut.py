"""lut (Table 1 through the phase table and the quarter-wave sine table) against
sim.model.Lut, bit for bit, every output of every sample and both valid outputs
on every edge, for both table kinds, sine widths 8..16 and both forms of the n * phase
product (DSP `*` and the carry-save rows in logic).

Timing (rtl/lut.v header; sim.model.finequad_core ADDR_AT, PHASE_AT, NTH_AT, SIN_AT): an address
j_i presented for edge A (= t + ADDR_AT in the core), with the octant's sign neg_i
presented for edge A - 1, gives ph_o = PH[j] after edge A, or its 12-bit complement for
neg (the block RAM's output register; the complement after it); with OPT_PHASE_4K the
scale t_i instead (rtl/octant.v t_o, j = min(2047, (t + 1) >> 1)), PH of that j (its
complement read from the table's second half), and j_i carries garbage (t_i does
without OPT_PHASE_4K). neg_i carries garbage on the other edges. A fine phase with n_i
presented for edge E (valid_i; the phase is registered on t + PHASE_AT, so
E = t + PHASE_AT + 1) gives nth_valid_o and
prod_o = n * phase (u22) after edge E + (NTH_AT - PHASE_AT - 1), and valid_o, pn_o =
prod mod 8192 and the sines (magnitude, and sign from pn's quadrant: cos negative for
(pn + 2048) mod 8192 >= 4096, sin for pn >= 4096; the signed values equal Lut.nth's)
after edge E + (SIN_AT - PHASE_AT - 1).

Vectors: the phase table at every address (OPT_PHASE_4K: every t) with either sign, then
random ones with random signs; the n-th order at
every n from 0 to 511 (with the phase extremes 0, 8191, around 4096 and a random one),
every phase with n = 1 (every sine address in every quadrant, for the cosine and the
sine: checked before the run), every phase of a stride with n = 511, walking ones and
zeros and alternating bits of n against those of the phase (the carry-save rows and their
carries), then seeded random pairs. The two streams run independently, back to back and
with random idle clocks, where the inputs hold random garbage with the valid low."""
import random

import pytest

import fqtb

# EXACT, SIN_W, DSP, PHASE_4K
PARAMS = [(1, 10, 1, 0), (0, 10, 0, 0), (1, 8, 0, 0), (1, 12, 1, 1), (1, 16, 0, 0)]


@pytest.mark.parametrize("exact,sin_w,dsp,ph4k", PARAMS,
                         ids=[f"EXACT{a}-SIN{b}-DSP{c}-PH4K{d}" for a, b, c, d in PARAMS])
@pytest.mark.parametrize("sim", fqtb.simulators("lut"))
def test_lut(sim, exact, sin_w, dsp, ph4k):
    fqtb.run_block(sim, "lut", fqtb.sources("lut"), "test_lut",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR), TABLE_EXACT=exact,
                                   SIN_W=sin_w, OPT_NTH_DSP=dsp, OPT_PHASE_4K=ph4k),
                   extra_env=dict(TABLE_EXACT=exact, SIN_W=sin_w, PH4K=ph4k))


# (not on GHDL's netlist: the bench reads the VHDL's instance by its name, and synthesis
# leaves MULT18X18D a black box)
@pytest.mark.parametrize("sim", [s for s in fqtb.simulators("lut")
                                 if s not in ("verilator", "ghdl-synth")])
def test_lut_mult18(sim):
    """OPT_ECP5_MULT = 1 with the DSP product as synthesis sees it (the MULT18X18D
    instance, whose output register is prod_o), with a behavioural stand-in of the
    primitive: the instance's wiring (operand and product bit order, the register's
    timing) gives the same outputs as the inferred form on the same vectors (the ECP5
    report build's tables: exact, 4096 rows). Icarus compiles rtl/lut.v with SYNTHESIS
    defined and cocotb_tests/sim_mult18x18d.v; GHDL runs rtl/vhdl/lut.vhd, which
    instantiates the primitive whenever OPT_ECP5_MULT = 1, with
    cocotb_tests/sim_mult18x18d.vhd."""
    vhdl = fqtb.is_vhdl(sim)
    fqtb.run_block(sim, "lut",
                   fqtb.sources("lut")
                   + [fqtb.HERE / ("sim_mult18x18d.vhd" if vhdl else "sim_mult18x18d.v")],
                   "test_lut",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR), TABLE_EXACT=1,
                                   SIN_W=10, OPT_NTH_DSP=1, OPT_PHASE_4K=1,
                                   OPT_ECP5_MULT=1),
                   extra_env=dict(TABLE_EXACT=1, SIN_W=10, PH4K=1, MULT18=1), tag="mult18",
                   extra_build_args=() if vhdl else ("-DSYNTHESIS",))


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402


def schedule(rng, count, dense=0.85):
    """Edges (from 0) for `count` items, back to back with random idle clocks (1..3)."""
    edges, e = [], 0
    for _ in range(count):
        e += 0 if rng.random() < dense else rng.randint(1, 3)
        edges.append(e)
        e += 1
    return edges


def nth_vectors(rng):
    """(phase, n) pairs of the n-th order stream (see the module docstring)."""
    v = []
    for n in range(0, 512):
        v += [(rng.randint(0, 8191), n), (0, n), (8191, n), (4095 + rng.randint(0, 1), n)]
    v += [(p, 1) for p in range(8192)] + [(p, 511) for p in range(1, 8192, 7)]
    # bit patterns of n against those of the phase: every carry-save row alone, all but
    # one, every row with all ones, alternating bits
    ns = sorted({1 << b for b in range(9)} | {511 ^ (1 << b) for b in range(9)}
                | {511, 0x155, 0x0AA})
    ps = sorted({1 << b for b in range(13)} | {8191 ^ (1 << b) for b in range(13)}
                | {8191, 0x1555, 0x0AAA})
    v += [(p, n) for n in ns for p in ps]
    v += [(rng.randint(0, 8191), rng.randint(0, 511)) for _ in range(2000)]
    return v


def check_sine_coverage(pn):
    """Every sine-table address is read for the cosine and for the sine, in every
    quadrant (so through both the direct and the mirrored address, with both signs)."""
    seen_s, seen_c = set(), set()
    for q in pn:
        c = (q + 2048) & 8191
        seen_s.add((q >> 11, q & 2047))
        seen_c.add((c >> 11, c & 2047))
    want = {(a, k) for a in range(4) for k in range(2048)}
    assert seen_s == want and seen_c == want


@cocotb.test()
async def lut_all(dut):
    import numpy as np
    from sim.model import finequad_core as core
    from sim.model import lut as lut_m

    exact = fqtb.env_int("TABLE_EXACT")
    if fqtb.env_int("MULT18", 0):
        # the primitive's branch was elaborated (not the inferred form)
        assert dut.g_mult18.u_mult is not None
    sin_w = fqtb.env_int("SIN_W")
    assert len(dut.cos_mag_o) == sin_w - 1
    lut = lut_m.Lut("exact" if exact else "paper", sin_w)
    rng = random.Random(400 + 10 * exact + sin_w)
    d_ph = 0                                      # ph_o: the RAM's output register
    d_prod = core.NTH_AT - core.PHASE_AT - 1      # prod_o after edge E + d_prod
    d_sin = core.SIN_AT - core.PHASE_AT - 1       # sines after edge E + d_sin

    # phase-table stream: every address (every t with OPT_PHASE_4K), then random ones
    ph4k = fqtb.env_int("PH4K")
    n_a = 4096 if ph4k else 2048
    # (the first address's sign, 0, is that of neg_q from power-up: no edge comes before it)
    js = list(range(n_a)) * 2 + [rng.randint(0, n_a - 1) for _ in range(2000)]
    negs = [0] * n_a + [1] * n_a + [rng.randint(0, 1) for _ in range(2000)]
    nth = nth_vectors(rng)
    ph_exp = [int(lut.ph[min(2047, (j + 1) >> 1) if ph4k else j]) ^ (4095 * ng)
              for j, ng in zip(js, negs)]
    a = np.array(nth, dtype=np.int64)
    prod, pn, cosn, sinn = lut.nth(a[:, 0], a[:, 1])
    check_sine_coverage(pn.tolist())
    assert set(a[:, 1].tolist()) == set(range(512))
    nth_exp = [(int(p), int(q), int(c), int(s)) for p, q, c, s in zip(prod, pn, cosn, sinn)]

    ej = schedule(rng, len(js))
    en = schedule(rng, len(nth))
    j_at = {e: i for i, e in enumerate(ej)}
    n_at = {e: i for i, e in enumerate(en)}
    ph_out = {e + d_ph: i for i, e in enumerate(ej)}
    p_out = {e + d_prod: i for i, e in enumerate(en)}
    s_out = {e + d_sin: i for i, e in enumerate(en)}

    bench = fqtb.ClockedBench(dut)
    await bench.start()
    bad = []
    last = max(ej[-1] + d_ph, en[-1] + max(d_prod, d_sin)) + 2
    checked = [0, 0, 0]
    for e in range(-1, last + 1):
        if e >= 0:
            if e in ph_out:
                i = ph_out[e]
                got = fqtb.uval(dut.ph_o)
                checked[0] += 1
                if got != ph_exp[i]:
                    bad.append(f"{'t' if ph4k else 'j'}={js[i]}, neg={negs[i]}: "
                               f"ph_o={got}, model {ph_exp[i]}")
            nv, v = fqtb.uval(dut.nth_valid_o), fqtb.uval(dut.valid_o)
            if (nv == 1) != (e in p_out):
                bad.append(f"nth_valid_o={nv} after edge {e}")
            if (v == 1) != (e in s_out):
                bad.append(f"valid_o={v} after edge {e}")
            if e in p_out:
                i = p_out[e]
                got = fqtb.uval(dut.prod_o)
                checked[1] += 1
                if got != nth_exp[i][0]:
                    bad.append(f"(phase,n)={nth[i]}: prod_o={got}, model {nth_exp[i][0]}")
            if e in s_out:
                i = s_out[e]
                got = (fqtb.uval(dut.pn_o), fqtb.uval(dut.cos_mag_o),
                       fqtb.uval(dut.cos_neg_o), fqtb.uval(dut.sin_mag_o),
                       fqtb.uval(dut.sin_neg_o))
                checked[2] += 1
                _, q, c, s = nth_exp[i]
                # magnitudes and values from the model; the sign bits from the quadrant
                # (a zero magnitude, SIN_W = 8, still carries its quadrant's sign)
                want = (q, abs(c), int(((q + 2048) & 8191) >= 4096), abs(s), int(q >= 4096))
                val = (-got[1] if got[2] else got[1], -got[3] if got[4] else got[3])
                if got != want or val != (c, s):
                    bad.append(f"(phase,n)={nth[i]}: (pn,|cos|,cneg,|sin|,sneg)={got}, "
                               f"model {want} (cos, sin = {c}, {s})")
        nxt = e + 1
        a_in = js[j_at[nxt]] if nxt in j_at else rng.randint(0, n_a - 1)
        dut.j_i.value = rng.randint(0, 2047) if ph4k else a_in     # the other: garbage
        dut.t_i.value = a_in if ph4k else rng.randint(0, 4095)
        # the sign one edge before its address
        dut.neg_i.value = negs[j_at[nxt + 1]] if nxt + 1 in j_at else rng.randint(0, 1)
        if nxt in n_at:
            p, n = nth[n_at[nxt]]
            dut.valid_i.value = 1
        else:
            p, n = rng.randint(0, 8191), rng.randint(0, 511)
            dut.valid_i.value = 0
        dut.phase_i.value = p
        dut.n_i.value = n
        await bench.step()
        if len(bad) > 50:
            break
    assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])
    assert checked == [len(js), len(nth), len(nth)]
    dut._log.info("lut TABLE_EXACT=%d SIN_W=%d: %d phase-table reads, %d n-th order "
                  "samples equal", exact, sin_w, len(js), len(nth))
