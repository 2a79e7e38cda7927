"""pulse (Eq. 12, comparators with hysteresis) against sim.model.pulse, in both
forms of the comparison: the sine table's word (OPT_ADDR = 0) and its address against the
inverse threshold table (OPT_ADDR = 1, sim.model.tables.eq12_k_table).

Latency 1. The hysteresis state carries across samples, idle clocks (garbage on the data
inputs) and changes of eps; rst sets A = B = 1 again. Each value is a table entry: an
address k and the magnitude T[k] (rtl/lut.v gives both), with k at and around the row of
the threshold (k = K[E] - 2 .. K[E] + 2: T[k] at, just below and just above
ceil(eps / 2**(16 - SIN_W))), at the zeros' border (K[1]) and the ends, and random. eps
is taken two edges before the pulses it decides: after each change of eps two samples
are sent at once, decided by the eps before, then the segment (with the new one)."""
import random

import pytest

import fqtb

# (SIN_W, OPT_ADDR)
PARAMS = [(10, 0), (8, 0), (10, 1), (8, 1), (12, 1)]


@pytest.mark.parametrize("sin_w,addr", PARAMS, ids=[f"SIN{w}-ADDR{a}" for w, a in PARAMS])
@pytest.mark.parametrize("sim", fqtb.simulators("pulse"))
def test_pulse(sim, sin_w, addr):
    fqtb.run_block(sim, "pulse", fqtb.sources("pulse"), "test_pulse",
                   parameters=dict(SIN_W=sin_w, OPT_ADDR=addr,
                                   TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR)))


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402


def segment(rng, sin_w, eps, n):
    """n table entries (k, signed T[k]) that cross +-eps often (the module docstring)."""
    from sim.model import tables

    t = tables.sine_table(sin_w)
    kt = tables.eq12_k_table(sin_w)
    e = -(-eps >> (16 - sin_w))                         # ceil(eps / 2**(16 - SIN_W))
    kth = kt[e] if e < len(kt) else len(t)
    out = []
    for _ in range(n):
        r = rng.random()
        if r < 0.5:
            k = kth + rng.randint(-2, 2)
        elif r < 0.6:
            k = rng.choice((0, len(t) - 1, kt[1] - 1, kt[1]))
        else:
            k = rng.randint(0, len(t) - 1)
        k = min(len(t) - 1, max(0, k))
        out.append((k, -t[k] if rng.random() < 0.5 else t[k]))
    return out


@cocotb.test()
async def pulse_sequences(dut):
    import numpy as np
    from sim.model import pulse as pulse_m

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
    for _ in range(2):                        # the threshold registers' first words
        await bench.step()
    a_state, b_state = 1, 1
    eps_prev = 0
    bad = []
    n_checked = [0, 0]

    async def send(vals, eps, idle):
        """The samples (cos, sin entries) back to back or with idle clocks; their outputs
        against the model with `eps` from the current state."""
        nonlocal a_state, b_state
        c = np.array([v for (_, v), _ in vals], dtype=np.int64)
        sv = np.array([v for _, (_, v) in vals], dtype=np.int64)
        ea, eb = pulse_m.pulse(c, sv, eps, sin_w, a0=a_state, b0=b_state)
        for i, ((ck, cv), (sk, svi)) in enumerate(vals):
            # idle clocks with values that would flip the outputs if taken
            for _ in range(rng.choice((0, 0, 0, 1, 2)) if idle else 0):
                dut.valid_i.value = 0
                dut.cos_k_i.value = 2047
                dut.cos_mag_i.value = (1 << (sin_w - 1)) - 1
                dut.cos_neg_i.value = a_state
                dut.sin_k_i.value = 2047
                dut.sin_mag_i.value = (1 << (sin_w - 1)) - 1
                dut.sin_neg_i.value = b_state
                await bench.step()
                if fqtb.uval(dut.valid_o) != 0:
                    bad.append(f"valid_o high after an idle clock (eps={eps})")
            dut.valid_i.value = 1
            dut.cos_k_i.value = ck
            dut.cos_mag_i.value = abs(cv)
            dut.cos_neg_i.value = int(cv < 0 or (cv == 0 and rng.random() < 0.5))
            dut.sin_k_i.value = sk
            dut.sin_mag_i.value = abs(svi)
            dut.sin_neg_i.value = int(svi < 0 or (svi == 0 and rng.random() < 0.5))
            await bench.step()
            got = (fqtb.uval(dut.valid_o), fqtb.uval(dut.a_o), fqtb.uval(dut.b_o))
            exp = (1, int(ea[i]), int(eb[i]))
            n_checked[idle] += 1
            if got != exp:
                bad.append(f"eps={eps} sample {i} cos k={ck} {cv} sin k={sk} {svi}: "
                           f"(valid,a,b)={got}, model {exp}")
        a_state, b_state = int(ea[-1]), int(eb[-1])

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
        dut.eps_i.value = eps
        # the two edges after the change still decide with the eps before
        carry = list(zip(segment(rng, sin_w, eps_prev, 2), segment(rng, sin_w, eps_prev, 2)))
        await send(carry, eps_prev, idle=0)
        n = 300
        seg = list(zip(segment(rng, sin_w, eps, n), segment(rng, sin_w, eps, n)))
        await send(seg, eps, idle=1)
        eps_prev = eps
        dut.valid_i.value = 0
    assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])
    dut._log.info("pulse SIN_W=%d: %d samples equal (%d right after a change of eps)",
                  sin_w, sum(n_checked), n_checked[0])
