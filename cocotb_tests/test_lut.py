"""lut (Table 1 through the phase table and the quarter-wave sine table) against
sim.model.fastpath.Lut, bit for bit, for both table kinds, sine widths 8..16 and both
forms of the n * phase product (DSP `*` and the carry-save rows in logic).

Timing (rtl/lut.v): an address j_i presented for edge A gives ph_o = PH[j] after edge A
(the phase table, read on edge t + ADDR_AT in the core). A fine phase with n_i presented
for edge E (valid_i) gives nth_valid_o and prod_o = n * phase after edge E, and valid_o,
pn_o and the sines (magnitude and sign) after edge E + 1. The two streams run
independently, back to back and with idle clocks (garbage inputs); n changes per sample
in part of the run. Every table address is read (with both extreme n and every octant
for the phase part), every n from 1 to 511 is used."""
import random

import pytest

import fqtb

PARAMS = [(1, 10, 1), (0, 10, 0), (1, 8, 0), (1, 12, 1), (1, 16, 0)]   # EXACT, SIN_W, DSP


@pytest.mark.parametrize("exact,sin_w,dsp", PARAMS,
                         ids=[f"EXACT{a}-SIN{b}-DSP{c}" for a, b, c in PARAMS])
@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_lut(sim, exact, sin_w, dsp):
    fqtb.run_block(sim, "lut", fqtb.sources("lut"), "test_lut",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR), TABLE_EXACT=exact,
                                   SIN_W=sin_w, OPT_NTH_DSP=dsp),
                   extra_env=dict(TABLE_EXACT=exact, SIN_W=sin_w))


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402


def schedule(rng, count, dense=0.7):
    """Edges (from 0) for `count` items, back to back with random idle clocks."""
    edges, e = [], 0
    for _ in range(count):
        e += 0 if rng.random() < dense else rng.randint(1, 3)
        edges.append(e)
        e += 1
    return edges


@cocotb.test()
async def lut_all(dut):
    import numpy as np
    from sim.model import fastpath as fp

    exact = fqtb.env_int("TABLE_EXACT")
    sin_w = fqtb.env_int("SIN_W")
    assert len(dut.cos_mag_o) == sin_w - 1
    lut = fp.Lut("exact" if exact else "paper", sin_w)
    rng = random.Random(400 + 10 * exact + sin_w)

    # phase-table stream: every address, then random ones
    js = list(range(2048)) + [rng.randint(0, 2047) for _ in range(2000)]
    # n-th order stream: every n with random phases and the phase extremes, then every
    # phase with n = 1 and n = 511, then random (phase, n) pairs
    nth = []
    for n in range(1, 512):
        nth += [(rng.randint(0, 8191), n), (0, n), (8191, n), (4095 + rng.randint(0, 1), n)]
    nth += [(p, 1) for p in range(0, 8192, 3)] + [(p, 511) for p in range(1, 8192, 5)]
    nth += [(rng.randint(0, 8191), rng.randint(1, 511)) for _ in range(3000)]
    ph_exp = [int(lut.ph[j]) for j in js]
    a = np.array(nth, dtype=np.int64)
    prod, pn, cosn, sinn = lut.nth(a[:, 0], a[:, 1])
    nth_exp = [(int(p), int(q), int(abs(c)), int(c < 0 or (((q + 2048) & 8191) >= 4096)),
                int(abs(s)), int(q >= 4096), int(c), int(s))
               for p, q, c, s in zip(prod, pn, cosn, sinn)]

    ej = schedule(rng, len(js))
    en = schedule(rng, len(nth))
    j_at = {e: i for i, e in enumerate(ej)}
    n_at = {e: i for i, e in enumerate(en)}
    ph_out = {e: i for i, e in enumerate(ej)}           # ph_o after edge A
    p_out = {e: i for i, e in enumerate(en)}            # prod_o after edge E
    s_out = {e + 1: i for i, e in enumerate(en)}        # sines after edge E + 1

    bench = fqtb.ClockedBench(dut)
    await bench.start()
    bad = []
    last = max(ej[-1], en[-1] + 1) + 2
    for e in range(-1, last + 1):
        if e >= 0:
            if e in ph_out:
                i = ph_out[e]
                got = fqtb.uval(dut.ph_o)
                if got != ph_exp[i]:
                    bad.append(f"j={js[i]}: ph_o={got}, model {ph_exp[i]}")
            nv, v = fqtb.uval(dut.nth_valid_o), fqtb.uval(dut.valid_o)
            if (nv == 1) != (e in p_out):
                bad.append(f"nth_valid_o={nv} after edge {e}")
            if (v == 1) != (e in s_out):
                bad.append(f"valid_o={v} after edge {e}")
            if e in p_out:
                i = p_out[e]
                got = fqtb.uval(dut.prod_o)
                if got != nth_exp[i][0]:
                    bad.append(f"(phase,n)={nth[i]}: prod_o={got}, model {nth_exp[i][0]}")
            if e in s_out:
                i = s_out[e]
                got = (fqtb.uval(dut.pn_o), fqtb.uval(dut.cos_mag_o),
                       fqtb.uval(dut.cos_neg_o), fqtb.uval(dut.sin_mag_o),
                       fqtb.uval(dut.sin_neg_o))
                c = -got[1] if got[2] else got[1]
                s = -got[3] if got[4] else got[3]
                x = nth_exp[i]
                want = (x[1], x[2], int(((x[1] + 2048) & 8191) >= 4096), x[4], x[5])
                if got != want or (c, s) != (x[6], x[7]):
                    bad.append(f"(phase,n)={nth[i]}: (pn,|cos|,cneg,|sin|,sneg)={got}, "
                               f"model {want} (cos, sin = {x[6]}, {x[7]})")
        nxt = e + 1
        dut.j_i.value = js[j_at[nxt]] if nxt in j_at else rng.randint(0, 2047)
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
    dut._log.info("lut TABLE_EXACT=%d SIN_W=%d: %d phase-table reads, %d n-th order "
                  "samples equal", exact, sin_w, len(js), len(nth))
