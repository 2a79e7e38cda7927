"""lut (Table 1 through the phase and quarter-wave sine tables) against sim.model.fastpath.Lut.

An address presented on edge e gives phase_o after edge e + 1 (latency 2) and pn/cos/sin
after edge e + 3 (latency 4); n_i is used on edge e + 2, so it is only changed while the
pipeline is empty. The signed model sinusoids are compared as magnitude and sign, the sign
being the model's quadrant rule (q >= 2)."""
import random

import pytest

import fqtb

PARAMS = [(1, 10), (0, 10), (1, 8)]     # (TABLE_EXACT, SIN_W)


@pytest.mark.parametrize("exact,sin_w", PARAMS, ids=[f"EXACT{a}-SIN{b}" for a, b in PARAMS])
@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_lut(sim, exact, sin_w):
    fqtb.run_block(sim, "lut", fqtb.sources("lut"), "test_lut",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR), TABLE_EXACT=exact,
                                   SIN_W=sin_w),
                   extra_env=dict(TABLE_EXACT=exact, SIN_W=sin_w))


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402

N_LIST = [1, 2, 3, 7, 64, 100, 255, 256, 257, 300, 511]


def expected(lut, vec, n):
    import numpy as np
    a = np.array(vec, dtype=np.int64)
    j, oct2, neg = a.T
    phase = lut.phase(j, oct2 * 2048, neg)
    pn, cosn, sinn = lut.nth(phase, n)
    cneg = ((pn + 2048) & 8191) >= 4096
    sneg = pn >= 4096
    return [tuple(int(x) for x in t) for t in
            zip(phase, pn, np.abs(cosn), cneg, np.abs(sinn), sneg, cosn, sinn)]


@cocotb.test()
async def lut_all(dut):
    from sim.model import fastpath as fp

    exact = fqtb.env_int("TABLE_EXACT")
    sin_w = fqtb.env_int("SIN_W")
    assert len(dut.cos_mag_o) == sin_w - 1
    lut = fp.Lut("exact" if exact else "paper", sin_w)
    rng = random.Random(400 + 10 * exact + sin_w)

    # bursts of (n, vectors): every table address with n = 1 (and 511), then random
    # addresses with j = 0, 2047 and random octants for each n
    bursts = []
    sweep = [(j, rng.randint(0, 3), rng.randint(0, 1)) for j in range(2048)]
    bursts.append((1, sweep))
    bursts.append((511, [(j, o ^ 1, 1 - s) for j, o, s in sweep]))
    for n in N_LIST + [rng.randint(1, 511) for _ in range(4)]:
        vec = [(rng.choice((0, 2047, rng.randint(0, 2047))), rng.randint(0, 3),
                rng.randint(0, 1)) for _ in range(400)]
        vec += [(j, o, s) for j in (0, 1, 2046, 2047) for o in range(4) for s in (0, 1)]
        bursts.append((n, vec))

    bench = fqtb.ClockedBench(dut)
    await bench.start()
    bad = []
    n_checked = 0
    for n, vec in bursts:
        exp = expected(lut, vec, n)
        dut.n_i.value = n
        gaps = [0 if rng.random() < 0.7 else rng.randint(1, 3) for _ in vec]
        start = bench.edge + 1
        edges, e = [], start
        for gp in gaps:
            e += gp
            edges.append(e)
            e += 1
        by_edge = {e: i for i, e in enumerate(edges)}
        ph_at = {e + 1: i for i, e in enumerate(edges)}
        out_at = {e + 3: i for i, e in enumerate(edges)}
        for e in range(start - 1, edges[-1] + 5):
            if e >= start:
                pv, v = fqtb.uval(dut.phase_valid_o), fqtb.uval(dut.valid_o)
                if e in ph_at:
                    i = ph_at[e]
                    got = fqtb.uval(dut.phase_o)
                    if pv != 1 or got != exp[i][0]:
                        bad.append(f"n={n} (j,oct2,neg)={vec[i]}: phase_valid={pv} "
                                   f"phase={got}, model {exp[i][0]}")
                elif pv:
                    bad.append(f"phase_valid_o high after edge {e}")
                if e in out_at:
                    i = out_at[e]
                    got = (fqtb.uval(dut.pn_o), fqtb.uval(dut.cos_mag_o),
                           fqtb.uval(dut.cos_neg_o), fqtb.uval(dut.sin_mag_o),
                           fqtb.uval(dut.sin_neg_o))
                    c = -got[1] if got[2] else got[1]
                    s = -got[3] if got[4] else got[3]
                    if v != 1 or got != exp[i][1:6] or (c, s) != exp[i][6:]:
                        bad.append(f"n={n} (j,oct2,neg)={vec[i]}: valid={v} (pn,|cos|,"
                                   f"cneg,|sin|,sneg)={got}, model {exp[i][1:6]}")
                    n_checked += 1
                elif v:
                    bad.append(f"valid_o high after edge {e}")
            if e + 1 in by_edge:
                j, o, s = vec[by_edge[e + 1]]
                dut.valid_i.value = 1
            else:
                j, o, s = rng.randint(0, 2047), rng.randint(0, 3), rng.randint(0, 1)
                dut.valid_i.value = 0
            dut.j_i.value = j
            dut.oct2_i.value = o
            dut.neg_i.value = s
            await bench.step()
        assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])
    dut._log.info("lut TABLE_EXACT=%d SIN_W=%d: %d look-ups equal", exact, sin_w, n_checked)
