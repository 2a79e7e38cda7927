"""axil_regs (AXI4-Lite slave -> finequad_core register port), on Icarus, Verilator and GHDL.

Against a register-file model of the core's port (axil_check.RegPortModel, registered
read like the core) with ADDR_TOP = 0x2f (word indices 0x30.. are unmapped: SLVERR):
  timing     the documented edge timing, AXI pins driven by hand: a write's AW and W
             taken on edge h -> reg_we after h + 1, BVALID after h + 2 (OKAY, or SLVERR
             when the port's reg_err refuses the write during reg_we's clock: the model
             refuses writes with bit 31 set to word 0x2e); a read's AR taken on h ->
             reg_re after h + 1, RVALID after h + 2; BVALID/RVALID held under
             back-pressure; AW before W and W before AW
  directed   cocotbext-axi AxiLiteMaster: every mapped word written and read back, each
             write reaching the port exactly once with its data; a write the port refuses
             -> SLVERR, the word unchanged; partial and empty WSTRB
             -> SLVERR and no write; unmapped words (inside and beyond the 6-bit port)
             -> SLVERR, RDATA 0, nothing on the port; byte offsets 1..3 of a word address
             hit the word
  random     seeded: batches of up to 8 concurrent reads and writes (distinct words per
             batch, so every result is defined whatever order the slave serves them in),
             random back-pressure on all five channels (pause generators of the master's
             AW, W, AR sources and B, R sinks), partial strobes and unmapped words mixed
             in; every response and the port's write log checked against the model, and
             the handshake rules on every channel (axil_check.AxilMonitor) on every clock
Against the real finequad_core (cocotb_tests/tb_axil_core.v: axil_regs in front of it):
  core       ID = sim.model.finequad_core.ID, reset values, INTERP/EPS/GATE write/read-back,
             CTRL's counter-mode bit, partial write rejected, a word above the system's
             ADDR_TOP -> SLVERR; every writable register's range (test_core_ranges below):
             each bound and one past it, a bit outside the fields, a read-only word ->
             SLVERR and the register keeps its value
"""
import os
import random

import pytest

import fqtb

ADDR_TOP = 0x2f
REFUSED_WORD = 0x2e          # the model port refuses writes with bit 31 set to this word


def refuse(addr, wdata):
    return addr == REFUSED_WORD and wdata >> 31


@pytest.mark.parametrize("sim", fqtb.simulators("axil_regs"))
def test_axil_regs(sim):
    fqtb.run_block(sim, "axil_regs", fqtb.sources("axil_regs"), "test_axil_regs",
                   parameters=dict(ADDR_W=16, ADDR_TOP=ADDR_TOP),
                   testcase="timing,directed,random_backpressure")


# GHDL runs tb_axil_core.vhd, the bench's VHDL twin (fqtb.vhdl_sources)
@pytest.mark.parametrize("sim", fqtb.simulators("finequad_core"))
def test_axil_core(sim):
    fqtb.run_block(sim, "tb_axil_core",
                   [fqtb.HERE / "tb_axil_core.v", fqtb.RTL / "axil_regs.v"]
                   + fqtb.core_sources(),
                   "test_axil_regs", parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR)),
                   testcase="axil_core,core_ranges")


# ---- simulator side ----------------------------------------------------------------------
try:
    import cocotb
except ImportError:      # pytest collection without cocotb's simulator module
    cocotb = None


def _cocotb_test(f):
    return cocotb.test()(f) if cocotb else f


OKAY, SLVERR = 0, 2


async def _setup(dut, master=True):
    from cocotbext.axi import AxiLiteBus, AxiLiteMaster
    from axil_check import RegPortModel, AxilMonitor

    bench = fqtb.ClockedBench(dut)
    dut.rst.value = 1
    for s in ("awvalid", "wvalid", "arvalid", "bready", "rready"):
        getattr(dut, f"s_axil_{s}").value = 0
    await bench.start()
    regs = RegPortModel(dut, dut.clk, init=[0] * 64, refuse=refuse)
    mon = AxilMonitor(dut, dut.clk)
    await bench.goto(1)
    dut.rst.value = 0
    await bench.step()
    regs.log.clear()
    m = None
    if master:
        m = AxiLiteMaster(AxiLiteBus.from_prefix(dut, "s_axil"), dut.clk, dut.rst)
    return bench, regs, mon, m


def _word(v):
    return v.to_bytes(4, "little")


@_cocotb_test
async def timing(dut):
    """Edge timing of the handshakes, driven pin by pin (ClockedBench slots)."""
    bench, regs, mon, _ = await _setup(dut, master=False)
    d = dut
    e0 = bench.edge

    async def at(e):
        await bench.goto(e0 + e)

    # write: AW and W together before edge 1 (taken on h = 1)
    d.s_axil_awaddr.value = 0x0C
    d.s_axil_awprot.value = 0
    d.s_axil_wdata.value = 0x12345678
    d.s_axil_wstrb.value = 0xF
    d.s_axil_awvalid.value = 1
    d.s_axil_wvalid.value = 1
    d.s_axil_bready.value = 0
    await at(1)
    assert int(d.s_axil_awready.value) == 0 and int(d.s_axil_wready.value) == 0
    d.s_axil_awvalid.value = 0
    d.s_axil_wvalid.value = 0
    await at(2)
    assert int(d.reg_we.value) == 1 and int(d.reg_addr.value) == 3
    assert int(d.reg_wdata.value) == 0x12345678
    assert int(d.s_axil_bvalid.value) == 0          # the port's verdict comes first
    await at(3)
    assert int(d.s_axil_bvalid.value) == 1 and int(d.s_axil_bresp.value) == OKAY
    for e in range(4, 7):            # held while BREADY is low; reg_we was one edge
        await at(e)
        assert int(d.s_axil_bvalid.value) == 1 and int(d.reg_we.value) == 0
    d.s_axil_bready.value = 1
    await at(7)
    assert int(d.s_axil_bvalid.value) == 0
    d.s_axil_bready.value = 0
    assert regs.writes() == [(3, 0x12345678)]

    # read: AR taken on edge 8 -> reg_re after 9, RVALID after 10
    d.s_axil_araddr.value = 0x0C
    d.s_axil_arprot.value = 0
    d.s_axil_arvalid.value = 1
    d.s_axil_rready.value = 0
    await at(8)
    d.s_axil_arvalid.value = 0
    assert int(d.s_axil_rvalid.value) == 0 and int(d.reg_re.value) == 0
    await at(9)
    assert int(d.reg_re.value) == 1 and int(d.reg_addr.value) == 3
    assert int(d.s_axil_rvalid.value) == 0
    await at(10)
    assert int(d.s_axil_rvalid.value) == 1 and int(d.s_axil_rdata.value) == 0x12345678
    assert int(d.s_axil_rresp.value) == OKAY
    for e in range(11, 14):
        await at(e)
        assert int(d.s_axil_rvalid.value) == 1 and int(d.s_axil_rdata.value) == 0x12345678
    d.s_axil_rready.value = 1
    await at(14)
    assert int(d.s_axil_rvalid.value) == 0
    d.s_axil_rready.value = 0

    # AW first (edge 15), W three edges later (edge 18): write after 19
    d.s_axil_awaddr.value = 0x10
    d.s_axil_awvalid.value = 1
    await at(15)
    d.s_axil_awvalid.value = 0
    assert int(d.s_axil_awready.value) == 0 and int(d.s_axil_wready.value) == 1
    await at(17)
    assert int(d.reg_we.value) == 0 and int(d.s_axil_bvalid.value) == 0
    d.s_axil_wdata.value = 0xCAFEF00D
    d.s_axil_wvalid.value = 1
    await at(18)
    d.s_axil_wvalid.value = 0
    await at(19)
    assert int(d.reg_we.value) == 1 and int(d.reg_addr.value) == 4
    assert int(d.s_axil_bvalid.value) == 0
    await at(20)
    assert int(d.s_axil_bvalid.value) == 1
    d.s_axil_bready.value = 1
    await at(21)
    d.s_axil_bready.value = 0
    # W first (edge 22), AW on edge 24: write after 25
    d.s_axil_wdata.value = 0x0BADBEEF
    d.s_axil_wvalid.value = 1
    await at(22)
    d.s_axil_wvalid.value = 0
    await at(23)
    assert int(d.s_axil_wready.value) == 0 and int(d.s_axil_awready.value) == 1
    d.s_axil_awaddr.value = 0x14
    d.s_axil_awvalid.value = 1
    await at(24)
    d.s_axil_awvalid.value = 0
    await at(25)
    assert int(d.reg_we.value) == 1 and int(d.reg_addr.value) == 5
    assert int(d.reg_wdata.value) == 0x0BADBEEF
    d.s_axil_bready.value = 1
    await at(27)
    d.s_axil_bready.value = 0
    # a write the port refuses (reg_err during reg_we's clock): SLVERR after h + 2
    d.s_axil_awaddr.value = 4 * REFUSED_WORD
    d.s_axil_wdata.value = 0x80000001
    d.s_axil_awvalid.value = 1
    d.s_axil_wvalid.value = 1
    await at(28)
    d.s_axil_awvalid.value = 0
    d.s_axil_wvalid.value = 0
    await at(29)
    assert int(d.reg_we.value) == 1 and int(d.reg_addr.value) == REFUSED_WORD
    await at(30)
    assert int(d.s_axil_bvalid.value) == 1 and int(d.s_axil_bresp.value) == SLVERR
    d.s_axil_bready.value = 1
    await at(31)
    d.s_axil_bready.value = 0
    assert regs.writes() == [(3, 0x12345678), (4, 0xCAFEF00D), (5, 0x0BADBEEF)]
    assert regs.mem[REFUSED_WORD] == 0
    assert not mon.errors, mon.errors[:5]


@_cocotb_test
async def directed(dut):
    bench, regs, mon, m = await _setup(dut)
    rng = random.Random(7)
    vals = {w: rng.getrandbits(32) for w in range(ADDR_TOP + 1)}
    vals[REFUSED_WORD] &= 0x7FFFFFFF
    for w, v in vals.items():
        r = await m.write(4 * w, _word(v))
        assert r.resp == OKAY, (w, r.resp)
    assert regs.writes() == list(vals.items())
    # a write the port refuses: SLVERR, the word keeps its value
    r = await m.write(4 * REFUSED_WORD, _word(0xFFFFFFFF))
    assert r.resp == SLVERR and regs.mem[REFUSED_WORD] == vals[REFUSED_WORD]
    for w, v in vals.items():
        r = await m.read(4 * w, 4)
        assert r.resp == OKAY and int.from_bytes(r.data, "little") == v, (w, r)
    n_log = len(regs.log)

    # partial strobes: SLVERR, nothing written (a 1-, 2- and 3-byte write; WSTRB 0 below)
    for off, length in ((0, 1), (1, 2), (0, 3), (2, 2), (3, 1)):
        r = await m.write(4 * 5 + off, bytes(range(1, length + 1)))
        assert r.resp == SLVERR, (off, length, r.resp)
    assert len(regs.log) == n_log and regs.mem[5] == vals[5]

    # unmapped: inside the port (0x30..0x3f) and beyond it
    for w in (ADDR_TOP + 1, 0x3f, 0x40, 0x41, 0x3fff):
        r = await m.write(4 * w, _word(0xFFFFFFFF))
        assert r.resp == SLVERR, (w, r.resp)
        r = await m.read(4 * w, 4)
        assert r.resp == SLVERR and r.data == bytes(4), (w, r)
    assert len(regs.log) == n_log, regs.log[n_log:]

    # byte offsets of a word address: the word (AXI4-Lite: the master puts the lanes)
    r = await m.read(4 * 9 + 2, 2)
    assert r.resp == OKAY and r.data == _word(vals[9])[2:4]
    assert not mon.errors, mon.errors[:5]


async def _batches(dut, m, regs, mon, rng, n_batches):
    model = list(regs.mem)
    n0 = len(regs.log)
    nw = nr = nerr = 0
    log_w = []
    for _ in range(n_batches):
        k = rng.randint(1, 8)
        words = rng.sample(range(0x48), k)       # some beyond ADDR_TOP and the port
        ops = []
        for w in words:
            kind = rng.random()
            if kind < 0.45:
                v = rng.getrandbits(32)
                if rng.random() < 0.15:          # partial write
                    off = rng.randint(0, 3)
                    n = rng.randint(1, min(3, 4 - off))
                    data = bytes(rng.getrandbits(8) for _ in range(n))
                    ops.append(("P", w, m.init_write(4 * w + off, data)))
                else:
                    ops.append(("W", w, v, m.init_write(4 * w, _word(v))))
            else:
                ops.append(("R", w, m.init_read(4 * w, 4)))
        for op in ops:
            await op[-1].wait()
        for op in ops:
            res = op[-1].data
            w = op[1]
            mapped = w <= ADDR_TOP
            if op[0] == "W":
                refused = refuse(w, op[2])
                assert res.resp == (OKAY if mapped and not refused else SLVERR), (op, res)
                if mapped and not refused:
                    log_w.append((w, op[2]))
                    nw += 1
                else:
                    nerr += 1
            elif op[0] == "P":
                assert res.resp == SLVERR, (op, res)
                nerr += 1
            else:
                if mapped:
                    assert res.resp == OKAY, (op, res)
                    got = int.from_bytes(res.data, "little")
                    assert got == model[w], (op, hex(got), hex(model[w]))
                    nr += 1
                else:
                    assert res.resp == SLVERR and res.data == bytes(4), (op, res)
                    nerr += 1
        for op in ops:
            if op[0] == "W" and op[1] <= ADDR_TOP and not refuse(op[1], op[2]):
                model[op[1]] = op[2]
    writes = [(a, v) for _, k, a, v in regs.log[n0:] if k == "W"]
    assert sorted(writes) == sorted(log_w), (len(writes), len(log_w))
    assert regs.mem == model
    return nw, nr, nerr


@_cocotb_test
async def random_backpressure(dut):
    from axil_check import pauses
    seed = int(os.environ.get("COCOTB_RANDOM_SEED", "1"))
    rng = random.Random(seed)
    bench, regs, mon, m = await _setup(dut)
    chans = {"aw": m.write_if.aw_channel, "w": m.write_if.w_channel,
             "b": m.write_if.b_channel, "ar": m.read_if.ar_channel, "r": m.read_if.r_channel}
    total = [0, 0, 0]
    for p in (0.0, 0.3, 0.7):
        for ch in chans.values():
            ch.set_pause_generator(pauses(random.Random(rng.getrandbits(32)), p))
        stalls0 = dict(mon.stalls)
        res = await _batches(dut, m, regs, mon, rng, 60)
        total = [a + b for a, b in zip(total, res)]
        if p:     # the master's sinks held READY low with a response waiting
            assert mon.stalls["b"] > stalls0["b"] and mon.stalls["r"] > stalls0["r"], \
                (p, mon.stalls)
    # the slave's own back-pressure (one transaction at a time) stalled the sources
    assert mon.stalls["aw"] and mon.stalls["w"] and mon.stalls["ar"], mon.stalls
    assert not mon.errors, mon.errors[:5]
    dut._log.info("random: %d writes, %d reads, %d error responses checked; stalls %s",
                  *total, mon.stalls)
    assert min(total) > 50


async def _core_master(dut):
    """tb_axil_core out of reset: cocotbext-axi's master, the protocol monitor and a word
    read that expects OKAY."""
    from cocotbext.axi import AxiLiteBus, AxiLiteMaster
    from axil_check import AxilMonitor

    bench = fqtb.ClockedBench(dut)
    dut.rst.value = 1
    await bench.start()
    mon = AxilMonitor(dut, dut.clk)
    await bench.goto(2)
    dut.rst.value = 0
    m = AxiLiteMaster(AxiLiteBus.from_prefix(dut, "s_axil"), dut.clk, dut.rst)

    async def rd(w):
        r = await m.read(4 * w, 4)
        assert r.resp == OKAY, (hex(w), r)
        return int.from_bytes(r.data, "little")
    return m, mon, rd


@_cocotb_test
async def axil_core(dut):
    """axil_regs in front of the real finequad_core (tb_axil_core.v)."""
    from sim.model import finequad_core as core_model
    from sim.model import regs

    m, mon, rd = await _core_master(dut)

    async def wr(w, v, resp=OKAY):
        r = await m.write(4 * w, _word(v))
        assert r.resp == resp, (hex(w), r)

    cfg = core_model.Config()
    assert await rd(regs.ID) == core_model.ID
    assert await rd(regs.INTERP) == cfg.interp
    assert await rd(regs.EPS) == cfg.eps
    assert await rd(regs.GATE) == cfg.gate
    assert await rd(regs.COUNT) == 0               # no samples: count 0
    await wr(regs.INTERP, 37)
    await wr(regs.EPS, 0x1234)
    await wr(regs.GATE, 0x1abc)
    assert await rd(regs.INTERP) == 37
    assert await rd(regs.EPS) == 0x1234
    assert await rd(regs.GATE) == 0x1abc
    await wr(regs.ID, 0, resp=SLVERR)              # read-only: refused
    assert await rd(regs.ID) == core_model.ID
    r = await m.write(4 * regs.INTERP + 1, b"\x05")   # partial: rejected, INTERP kept
    assert r.resp == SLVERR
    assert await rd(regs.INTERP) == 37
    st = await rd(regs.STATUS)
    await wr(regs.CTRL, regs.word("CTRL", count_mode=1))   # counter mode 1 (edge)
    assert await rd(regs.STATUS) == st | regs.word_read("STATUS", count_mode=1)
    r = await m.read(4 * (regs.ADDR_TOP + 1), 4)
    assert r.resp == SLVERR and r.data == bytes(4)
    r = await m.write(4 * (regs.ADDR_TOP + 1), _word(1))
    assert r.resp == SLVERR
    assert not mon.errors, mon.errors[:5]


@_cocotb_test
async def core_ranges(dut):
    """Every writable register's bounds through AXI4-Lite against the real core
    (regcases.cases()): each field at its bounds taken (OKAY, read back), one past a
    bound, a bit outside the fields, a read-only or unused word refused (SLVERR) with
    the register unchanged."""
    import regcases

    m, mon, rd = await _core_master(dut)

    bad = []
    n = 0
    for name, word, taken in regcases.cases():
        w = regcases.index(name)
        before = await rd(w)
        r = await m.write(4 * w, _word(word))
        n += 1
        if r.resp != (OKAY if taken else SLVERR):
            bad.append(f"{name} <- {word:#010x}: {'OKAY' if r.resp == OKAY else 'SLVERR'}")
            continue
        after = await rd(w)
        exp = regcases.readback(name, word) if taken else before
        if exp is not None and after != exp and (taken or name in regcases.regs.REGS):
            bad.append(f"{name} <- {word:#010x}: reads {after:#010x}, expected {exp:#010x}")
    assert not bad, f"{len(bad)} of {n} writes:\n" + "\n".join(bad)
    assert not mon.errors, mon.errors[:5]
    dut._log.info("core_ranges: %d writes, each taken or refused as the description says", n)
