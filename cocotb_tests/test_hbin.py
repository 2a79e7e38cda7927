"""hbin (the harmonic table's bin from the octant address's scale t) against the model's
phase >> 7, exhaustively: every t the block can see (exact: 0..4095, the clipped scale
of rtl/octant.v; paper: t = 2 j for every j), every octant and both directions, for both
tables.

Expected (sim.model): j = min(2047, (t + 1) >> 1) (exact) or t >> 1 (paper), the phase
Lut(kind).phase(j, 2048 oct2, neg) and the bin phase >> 7. Besides bin_o: the candidates
b0_o and b1_o depend on t's bucket t >> 8 only (constant over each bucket), b1 is b0's
neighbour in the direction of the count (b0 + 1 mod 64 for neg = 0, b0 - 1 for neg = 1)
and c_o tells which one the bin is; every bucket that holds a threshold shows both
values of c_o (else the comparison inside the bucket would go untested).
Combinational: inputs set, then the outputs read 1 ns later."""
import pytest

import fqtb


@pytest.mark.parametrize("exact", [1, 0], ids=["EXACT1", "EXACT0"])
@pytest.mark.parametrize("sim", fqtb.simulators("hbin"))
def test_hbin(sim, exact):
    fqtb.run_block(sim, "hbin", fqtb.sources("hbin"), "test_hbin",
                   parameters=dict(TABLE_EXACT=exact), extra_env=dict(TABLE_EXACT=exact))


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402
from cocotb.triggers import Timer  # noqa: E402


def expected(exact):
    """{(oct2, neg, t): bin} from the model, for every t of the table kind."""
    import numpy as np
    from sim.model import lut as lut_m

    kind = "exact" if exact else "paper"
    ts = np.arange(4096) if exact else 2 * np.arange(2048)
    j = np.minimum((ts + 1) >> 1, 2047) if exact else ts >> 1
    lut = lut_m.Lut(kind)
    out = {}
    for oct2 in range(4):
        for neg in (0, 1):
            ph = lut.phase(j, np.full_like(j, 2048 * oct2), np.full_like(j, neg))
            for t, b in zip(ts.tolist(), (ph >> 7).tolist()):
                out[(oct2, neg, t)] = b
    return out


@cocotb.test()
async def hbin_exhaustive(dut):
    exact = fqtb.env_int("TABLE_EXACT")
    exp = expected(exact)
    bad = []
    cands = {}                      # (oct2, neg, bucket) -> {(b0, b1)}
    cs = {}                         # (oct2, neg, bucket) -> {c}
    for (oct2, neg, t), b in exp.items():
        dut.oct2_i.value, dut.neg_i.value, dut.t_i.value = oct2, neg, t
        await Timer(1, "ns")
        got = fqtb.uval(dut.bin_o)
        b0, b1, c = fqtb.uval(dut.b0_o), fqtb.uval(dut.b1_o), fqtb.uval(dut.c_o)
        if got != b:
            bad.append(f"oct2={oct2} neg={neg} t={t}: bin {got}, model {b}")
        if got != (b1 if c else b0):
            bad.append(f"oct2={oct2} neg={neg} t={t}: bin {got} is not c ? b1 : b0 "
                       f"({c}, {b1}, {b0})")
        if b1 != (b0 + (-1 if neg else 1)) % 64:
            bad.append(f"oct2={oct2} neg={neg} t={t}: b1 {b1} is not b0 {b0} "
                       f"{'- 1' if neg else '+ 1'}")
        key = (oct2, neg, t >> 8)
        cands.setdefault(key, set()).add((b0, b1))
        cs.setdefault(key, set()).add(c)
        if len(bad) > 40:
            break
    assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])
    varying = [k for k, v in cands.items() if len(v) != 1]
    assert not varying, f"candidates not constant over a bucket: {varying[:8]}"
    # a bucket holds a threshold exactly where the model's bin changes inside it
    split = {k for k in cs
             if len({exp[(k[0], k[1], t)] for t in range(k[2] << 8, (k[2] + 1) << 8)
                     if (k[0], k[1], t) in exp}) > 1}
    assert split, "no bucket holds a threshold"
    assert all(cs[k] == {0, 1} for k in split), "a threshold's two sides not both seen"
    dut._log.info("hbin (%s): %d (oct2, neg, t) equal to the model; %d buckets with a "
                  "threshold", "exact" if exact else "paper", len(exp), len(split))
