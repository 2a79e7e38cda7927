"""pulse (Eq. 12, comparators with hysteresis) against sim.model.fastpath.pulse.

Latency 1. The hysteresis state carries across samples, idle clocks (garbage on the data
inputs) and changes of eps; rst sets A = B = 1 again."""
import random

import pytest

import fqtb

SIN_WS = [10, 8]


@pytest.mark.parametrize("sin_w", SIN_WS, ids=[f"SIN{w}" for w in SIN_WS])
@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_pulse(sim, sin_w):
    fqtb.run_block(sim, "pulse", fqtb.sources("pulse"), "test_pulse",
                   parameters=dict(SIN_W=sin_w))


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402


def segment(rng, sin_w, eps, n):
    """n signed table values (magnitude < 2**(SIN_W-1)) that cross +-eps often."""
    sh = 16 - sin_w
    mmax = (1 << (sin_w - 1)) - 1
    thr = min(mmax, eps >> sh)
    out = []
    for _ in range(n):
        r = rng.random()
        if r < 0.5:         # at and around the threshold (ties when eps % 2**sh == 0)
            m = min(mmax, max(0, thr + rng.randint(-2, 2)))
        elif r < 0.6:
            m = rng.choice((0, mmax))
        else:
            m = rng.randint(0, mmax)
        out.append(-m if rng.random() < 0.5 else m)
    return out


@cocotb.test()
async def pulse_sequences(dut):
    import numpy as np
    from sim.model import fastpath as fp

    sin_w = len(dut.cos_mag_i) + 1
    sh = 16 - sin_w
    rng = random.Random(500 + sin_w)
    # (eps, reset before the segment)
    eps_list = [1638, 0, 1638, 1 << sh, 100 << sh, (100 << sh) + 1, 1, 32767, 65535, 0,
                rng.randint(0, 32767), rng.randint(0, 32767), 4000]
    bench = fqtb.ClockedBench(dut)
    dut.rst.value = 1
    dut.valid_i.value = 0
    dut.eps_i.value = 0
    await bench.start()
    await bench.step()                        # edge 0 with rst
    dut.rst.value = 0
    a_state, b_state = 1, 1
    bad = []
    n_checked = 0
    for si, eps in enumerate(eps_list):
        do_reset = si in (6, 10)
        if do_reset:                          # rst on one edge, no sample on it
            dut.rst.value = 1
            dut.valid_i.value = 0
            await bench.step()
            if (fqtb.uval(dut.a_o), fqtb.uval(dut.b_o), fqtb.uval(dut.valid_o)) != (1, 1, 0):
                bad.append(f"after rst: a={fqtb.uval(dut.a_o)} b={fqtb.uval(dut.b_o)} "
                           f"valid={fqtb.uval(dut.valid_o)}")
            dut.rst.value = 0
            a_state, b_state = 1, 1
        n = 300
        c, s = segment(rng, sin_w, eps, n), segment(rng, sin_w, eps, n)
        ea, eb = fp.pulse(np.array(c, dtype=np.int64), np.array(s, dtype=np.int64), eps,
                          sin_w, a0=a_state, b0=b_state)
        dut.eps_i.value = eps
        for i in range(n):
            # idle clocks with values that would flip the outputs if taken
            for _ in range(rng.choice((0, 0, 0, 1, 2))):
                dut.valid_i.value = 0
                dut.cos_mag_i.value = (1 << (sin_w - 1)) - 1
                dut.cos_neg_i.value = a_state
                dut.sin_mag_i.value = (1 << (sin_w - 1)) - 1
                dut.sin_neg_i.value = b_state
                await bench.step()
                if fqtb.uval(dut.valid_o) != 0:
                    bad.append(f"valid_o high after an idle clock (eps={eps})")
            dut.valid_i.value = 1
            dut.cos_mag_i.value = abs(c[i])
            dut.cos_neg_i.value = int(c[i] < 0 or (c[i] == 0 and rng.random() < 0.5))
            dut.sin_mag_i.value = abs(s[i])
            dut.sin_neg_i.value = int(s[i] < 0 or (s[i] == 0 and rng.random() < 0.5))
            await bench.step()
            got = (fqtb.uval(dut.valid_o), fqtb.uval(dut.a_o), fqtb.uval(dut.b_o))
            exp = (1, int(ea[i]), int(eb[i]))
            n_checked += 1
            if got != exp:
                bad.append(f"eps={eps} segment {si} sample {i} cos={c[i]} sin={s[i]}: "
                           f"(valid,a,b)={got}, model {exp}")
        a_state, b_state = int(ea[-1]), int(eb[-1])
        dut.valid_i.value = 0
    assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])
    dut._log.info("pulse SIN_W=%d: %d samples equal", sin_w, n_checked)
