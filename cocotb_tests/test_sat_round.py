"""sat_round: out = sat_OW(rnd_shr(in, sh)) against sim.model.fixed (combinational)."""
import random

import pytest

import fqtb

# (IW, OW, SW): the two instances of the core (rls_engine, correct) and a small one whose
# shift range reaches past the input width
PARAMS = [(64, 32, 6), (33, 16, 4), (12, 8, 4)]


@pytest.mark.parametrize("iw,ow,sw", PARAMS, ids=[f"IW{a}-OW{b}-SW{c}" for a, b, c in PARAMS])
@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_sat_round(sim, iw, ow, sw):
    fqtb.run_block(sim, "sat_round", fqtb.sources("sat_round"), "test_sat_round",
                   parameters=dict(IW=iw, OW=ow, SW=sw), testcase="sat_round_all")


@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_sat_round_shift_past_width(sim):
    """Shift amounts beyond the input width (sh > IW): the rounding constant 2**(sh-1)
    must not overflow the adder (IW=12: in=0, sh=13 once gave -1 instead of 0)."""
    fqtb.run_block(sim, "sat_round", fqtb.sources("sat_round"), "test_sat_round",
                   parameters=dict(IW=12, OW=8, SW=4), testcase="sat_round_shift_past_width")


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402


def vectors(iw, sw, n_random, seed):
    lo, hi = -(1 << (iw - 1)), (1 << (iw - 1)) - 1
    shmax = (1 << sw) - 1
    vec = []
    specials = [0, 1, -1, 2, -2, 3, -3, lo, lo + 1, hi, hi - 1]
    for sh in range(shmax + 1):
        for v in specials:
            vec.append((v, sh))
        if sh:
            half = 1 << (sh - 1)
            # ties: x.5 in both signs, and the neighbours of each tie
            for m in (0, 1, 2, 5, -1, -2, -3, -6):
                for d in (-1, 0, 1):
                    v = m * (1 << sh) + half + d
                    if lo <= v <= hi:
                        vec.append((v, sh))
        # around the saturation thresholds of the output (both ways)
    rng = random.Random(seed)
    for _ in range(n_random):
        sh = rng.randint(0, shmax)
        r = rng.random()
        if r < 0.4:
            v = rng.randint(lo, hi)
        else:  # values of all magnitudes (log-uniform)
            b = rng.randint(0, iw - 1)
            v = rng.randint(-(1 << b), (1 << b) - 1)
        vec.append((v, sh))
    return vec


def sat_vectors(iw, ow, sw):
    """Inputs that land exactly on / next to the output rails after the shift."""
    lo, hi = -(1 << (iw - 1)), (1 << (iw - 1)) - 1
    omax, omin = (1 << (ow - 1)) - 1, -(1 << (ow - 1))
    vec = []
    for sh in range((1 << sw)):
        for target in (omax, omax + 1, omin, omin - 1):
            for d in (-1, 0, 1):
                base = target << sh
                for off in (-(1 << sh >> 1) - 1, -(1 << sh >> 1), (1 << sh >> 1) - 1,
                            (1 << sh >> 1)):
                    v = base + off + d
                    if lo <= v <= hi:
                        vec.append((v, sh))
    return vec


async def check(dut, vec):
    from cocotb.triggers import Timer
    from sim.model.fixed import is_sat, rnd_shr, sat

    iw, ow, sw = len(dut.in_i), len(dut.out_o), len(dut.sh_i)
    bad = []
    for v, sh in vec:
        dut.in_i.value = v
        dut.sh_i.value = sh
        await Timer(1, unit="ns")
        r = rnd_shr(v, sh)
        exp, exp_sat = sat(r, ow), int(is_sat(r, ow))
        got, got_sat = fqtb.sval(dut.out_o), fqtb.uval(dut.sat_o)
        if (got, got_sat) != (exp, exp_sat):
            bad.append(f"in={v} sh={sh}: out={got} sat={got_sat}, model out={exp} sat={exp_sat}")
    assert not bad, f"{len(bad)} of {len(vec)} mismatches (IW={iw} OW={ow} SW={sw}):\n" + \
        "\n".join(bad[:20])
    dut._log.info("sat_round IW=%d OW=%d SW=%d: %d vectors equal", iw, ow, sw, len(vec))


@cocotb.test()
async def sat_round_all(dut):
    """Directed (ties, rails, saturation both ways, sh=0) and seeded random vectors with
    every shift amount the core can produce for this width (sh <= IW)."""
    iw, ow, sw = len(dut.in_i), len(dut.out_o), len(dut.sh_i)
    vec = sat_vectors(iw, ow, sw) + vectors(iw, sw, 3000, seed=iw * 1000 + ow * 10 + sw)
    await check(dut, [(v, sh) for v, sh in vec if sh <= iw])


@cocotb.test()
async def sat_round_shift_past_width(dut):
    """sh > IW agrees with the model."""
    iw, ow, sw = len(dut.in_i), len(dut.out_o), len(dut.sh_i)
    assert (1 << sw) - 1 > iw, "this parameter set cannot shift past the input width"
    vec = sat_vectors(iw, ow, sw) + vectors(iw, sw, 3000, seed=7)
    await check(dut, [(v, sh) for v, sh in vec if sh > iw])
