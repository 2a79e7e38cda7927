"""adc_pmod_ad1 against the Pmod AD1 model (cocotb_tests/ad7476_model.py), both simulators.

Each parameter set runs the front end at its board clock against two AD7476A models that
serve a recording (corner codes 0x000, 0x001, 0x7FF, 0x800, 0xFFE, 0xFFF, walking ones and
zeros, then seeded random codes; 600 conversions): every sample must come out exactly
(m_u = (code - 2048) * 2^(OUT_W - 12), both channels), m_valid exactly PERIOD clocks apart
and S + 30H + 1 clock edges after the CS_N falling edge that sampled it, the first CS_N
falling edge PERIOD - S - 31H edges after the last rst edge, m_err only on the conversion
whose leading zeros the model corrupts, and the model must see no timing violation
(fSCLK, SCLK duty, t1, t2, t8 + tQUIET, 16 SCLK falling edges per frame; data sampled
inside the t4..t7 window, outside it the model drives random bits).

  icebreaker   20.25 MHz (49.382 ns), SCLK_HALF 1, CS_SETUP 1, PERIOD 33, OUT_W 12
  ulx3s        35.714 MHz (28 ns), SCLK_HALF 1, CS_SETUP 1, PERIOD 36, OUT_W 12
  slow16       100 MHz, SCLK_HALF 3, CS_SETUP 3, PERIOD 110, OUT_W 16 (CS_SETUP 2 = 20 ns
               was caught by the model: the first leading zero comes t3 = 22 ns after
               CS_N and m_err rose on random bits)
The model's checks are themselves tested (Icarus): parameter sets that break the timing
must be caught:
  bad_quiet    33 MHz, PERIOD 33: the next CS_N falls 60.6 ns after the 16th SCLK falling
               edge (< 86 ns)
  bad_fast     100 MHz, SCLK_HALF 1: 50 MHz SCLK, and the bits sampled 20 ns after the
               falling edge (before t4 = 40 ns): period violations and wrong samples
"""
import os
import random

import pytest

import fqtb

SETS = {
    "icebreaker": dict(CLK_PS=49382, SCLK_HALF=1, CS_SETUP=1, PERIOD=33, OUT_W=12),
    "ulx3s": dict(CLK_PS=28000, SCLK_HALF=1, CS_SETUP=1, PERIOD=36, OUT_W=12),
    "slow16": dict(CLK_PS=10000, SCLK_HALF=3, CS_SETUP=3, PERIOD=110, OUT_W=16),
    "bad_quiet": dict(CLK_PS=30304, SCLK_HALF=1, CS_SETUP=1, PERIOD=33, OUT_W=12,
                      EXPECT="16th SCLK falling edge"),
    "bad_fast": dict(CLK_PS=10000, SCLK_HALF=1, CS_SETUP=1, PERIOD=40, OUT_W=12,
                     EXPECT="SCLK period"),
}
N = 600


@pytest.mark.parametrize("name", list(SETS))
@pytest.mark.parametrize("sim", fqtb.simulators("adc_pmod_ad1"))
def test_adc_pmod_ad1(sim, name):
    s = dict(SETS[name])
    if "EXPECT" in s and sim != "icarus":
        pytest.skip("checks of the model: one simulator is enough")
    if fqtb.is_vhdl(sim) and name == "ulx3s":
        # CI time: GHDL runs icebreaker and slow16, which between them give every
        # generic two values (ulx3s differs from icebreaker only in PERIOD and the clock)
        pytest.skip("GHDL runs icebreaker and slow16")
    expect = s.pop("EXPECT", "")
    clk_ps = s.pop("CLK_PS")
    fqtb.run_block(sim, "adc_pmod_ad1", fqtb.sources("adc_pmod_ad1"), "test_adc_pmod_ad1",
                   parameters=s, extra_env=dict(CLK_PS=clk_ps, N=N, EXPECT=expect or "-",
                                                **s))


def recording(n, seed):
    corner = [0x000, 0x001, 0x7FF, 0x800, 0xFFE, 0xFFF]
    walk = [1 << i for i in range(12)] + [0xFFF ^ (1 << i) for i in range(12)]
    rng = random.Random(seed)
    c1 = corner + walk
    c2 = list(reversed(corner)) + walk[::-1]
    while len(c1) < n:
        c1.append(rng.getrandbits(12))
        c2.append(rng.getrandbits(12))
    return c1[:n], c2[:n]


# ---- simulator side ----------------------------------------------------------------------
try:
    import cocotb
    from cocotb.clock import Clock
    from cocotb.triggers import FallingEdge, RisingEdge
    from cocotb.utils import get_sim_time
except ImportError:
    cocotb = None


def _cocotb_test(f):
    return cocotb.test()(f) if cocotb else f


@_cocotb_test
async def adc_run(dut):
    from ad7476_model import PmodAD1Model
    e = fqtb.env_int
    T = e("CLK_PS")
    H, S, P, W, n = e("SCLK_HALF"), e("CS_SETUP"), e("PERIOD"), e("OUT_W"), e("N")
    expect = fqtb.env_str("EXPECT")
    seed = int(os.environ.get("COCOTB_RANDOM_SEED", "1"))
    c1, c2 = recording(n, seed)
    lead_bad = 7

    dut.rst.value = 1
    dut.sdata1_i.value = 0
    dut.sdata2_i.value = 0
    Clock(dut.clk, T, unit="ps").start(start_high=False)
    model = PmodAD1Model(dut.cs_n_o, dut.sclk_o, dut.sdata1_i, dut.sdata2_i, c1, c2,
                         seed=seed, lead_ones=(lead_bad,))
    for _ in range(3):
        await RisingEdge(dut.clk)
    t_rst = get_sim_time(unit="ps")             # the last edge with rst high
    await FallingEdge(dut.clk)
    dut.rst.value = 0

    got = []                                    # (edge time, u1, u2, err)
    limit = (n + 2) * P + 200
    for _ in range(limit):
        await FallingEdge(dut.clk)
        if int(dut.m_valid.value):
            got.append((get_sim_time(unit="ps") - T // 2, dut.m_u1.value.to_signed(),
                        dut.m_u2.value.to_signed(), int(dut.m_err.value)))
            if len(got) == n:
                break
    errors = list(model.errors)        # the model runs on (the next conversion is past
                                       # the recording); its verdict up to here counts

    if expect != "-":
        assert any(expect in m for m in errors), errors[:5]
        dut._log.info("model caught: %s (%d violations)", errors[0], len(errors))
        return
    assert not errors, errors[:10]
    assert len(got) == n, len(got)
    sh = W - 12
    bad = [(k, g[1:3], ((a - 2048) << sh, (b - 2048) << sh))
           for k, (g, a, b) in enumerate(zip(got, c1, c2))
           if (g[1], g[2]) != ((a - 2048) << sh, (b - 2048) << sh)]
    assert not bad, bad[:5]
    assert [k for k, g in enumerate(got) if g[3]] == [lead_bad]
    # rate, latency from the sampling instant, first conversion after rst
    assert all(b[0] - a[0] == P * T for a, b in zip(got, got[1:]))
    lat = {g[0] - c for g, c in zip(got, model.cs_fall_ps)}
    assert lat == {(S + 30 * H + 1) * T}, lat
    assert model.cs_fall_ps[0] - t_rst == (P - S - 31 * H) * T, \
        (model.cs_fall_ps[0] - t_rst) / T
    dut._log.info("%d samples exact, %.4f MS/s, SCLK %.2f MHz", n, 1e6 / (P * T),
                  1e6 / (2 * H * T))
