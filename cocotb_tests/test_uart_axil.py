"""UART receiver, transmitter and the UART -> AXI4-Lite bridge; the host client.

uart_rx (DIV = 16), against cocotbext-uart's UartSource:
  rx_bytes   256 random bytes back to back at the nominal bit time and at whole-ns bit
             times at least 3.5 % shorter and longer (-3.75 %, +3.75 %): every byte out,
             in order, nothing else
  rx_errors  pin-driven: a stop bit of 0 -> frame_err_o, no byte; a break (line low for
             40 bit times) -> one frame_err_o, no byte; a 4-clock low glitch -> nothing;
             overrun (tready low, two bytes) -> the first held, overrun_o once, the second
             dropped; a good byte after each
uart_tx (DIV = 16), against cocotbext-uart's UartSink:
  tx_bytes   300 random bytes with random gaps in tvalid: all received in order; the
             start bit begins on the taking edge; back-to-back bytes are 10 DIV + 1
             clocks apart; tready never depends on tvalid
uart_axil + axil_regs (tb_uart_axil.v, DIV 16, TIMEOUT 2000 clocks, ADDR_TOP 0x2f), the
register port served by axil_check.RegPortModel, frames through scripts/fqhost.py's
FqProtocol (cocotb_tests/fqlink.py):
  bridge     every mapped word written and read back; unmapped -> SLVERR (0x52), nothing
             on the port; a bad CHK -> 0x54, nothing on the port; garbage bytes (not 'R'
             or 'W') ignored; a partial frame abandoned after TIMEOUT (drop_o) and not
             executed; a frame whose bytes come just under TIMEOUT apart executed; a
             break in a frame abandons it; a byte sent during an answer is ignored;
             seeded random reads and writes against the model
fqhost (no simulator): FqHost over a scripted serial port: retries of reads after a
garbled, short or missing answer; a write answered 0x54 is repeated, a write with no
answer is not; SLVERR -> BusError; bad CLI input -> a clear argparse error.
"""
import os
import random
import sys

import pytest

import fqtb

DIV = 16
BIT_NS = DIV * fqtb.PERIOD_PS // 1000
TIMEOUT = 2000


@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_uart_rx(sim):
    fqtb.run_block(sim, "uart_rx", fqtb.sources("uart_rx"), "test_uart_axil",
                   parameters=dict(DIV=DIV), testcase="rx_bytes,rx_errors")


@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_uart_tx(sim):
    fqtb.run_block(sim, "uart_tx", fqtb.sources("uart_tx"), "test_uart_axil",
                   parameters=dict(DIV=DIV), testcase="tx_bytes")


@pytest.mark.parametrize("sim", fqtb.SIMULATORS)
def test_uart_axil(sim):
    fqtb.run_block(sim, "tb_uart_axil",
                   [fqtb.HERE / "tb_uart_axil.v"]
                   + fqtb.sources("uart_axil", "uart_rx", "uart_tx", "axil_regs"),
                   "test_uart_axil", parameters=dict(DIV=DIV, TIMEOUT=TIMEOUT),
                   testcase="bridge")


# ---- host client without a simulator ------------------------------------------------------
sys.path.insert(0, str(fqtb.REPO / "scripts"))
import fqhost  # noqa: E402


class ScriptedSerial:
    """A serial port whose answers are scripted: each write() queues the next answer."""

    def __init__(self, answers):
        self.answers = list(answers)
        self.frames = []
        self.buf = b""

    def write(self, data):
        self.frames.append(bytes(data))
        self.buf = self.answers.pop(0) if self.answers else b""

    def flush(self):
        pass

    def read(self, n):
        out, self.buf = self.buf[:n], self.buf[n:]
        return out

    def reset_input_buffer(self):
        self.buf = b""


def _ans(st, data=None):
    body = bytes([st]) + (data.to_bytes(4, "big") if data is not None else b"")
    return body + bytes([fqhost.FqProtocol.chk(body)])


def test_fqhost(monkeypatch):
    P = fqhost.FqProtocol
    monkeypatch.setattr(fqhost.FqHost, "RESYNC_S", 0.0)
    # frames: sum of bytes 0
    f = P().write_frame(0x7c, 0xdeadbeef)
    assert f[0] == ord("W") and f[1:3] == b"\x00\x7c" and sum(f) & 0xff == 0 and len(f) == 8
    f = P().read_frame(0x1234)
    assert f == bytes([0x52, 0x12, 0x34, (-(0x52 + 0x12 + 0x34)) & 0xff])
    with pytest.raises(ValueError):
        P().read_frame(0x10000)
    with pytest.raises(ValueError):
        P().write_frame(0, 1 << 32)
    # read: garbled (bad checksum), short, then good
    bad = bytearray(_ans(0x50, 7))
    bad[2] ^= 1
    s = ScriptedSerial([bytes(bad), _ans(0x50, 7)[:3], _ans(0x50, 0x46510003)])
    h = fqhost.FqHost(None, ser=s)
    assert h.read(0x7c) == 0x46510003 and len(s.frames) == 3
    # read: no answer at all, retries exhausted -> ProtocolError
    s = ScriptedSerial([])
    with pytest.raises(fqhost.ProtocolError, match="0 byte"):
        fqhost.FqHost(None, ser=s, retries=2).read(0)
    assert len(s.frames) == 3
    # unknown status byte
    with pytest.raises(fqhost.ProtocolError, match="unknown status"):
        fqhost.FqHost(None, ser=ScriptedSerial([_ans(0x41, 0)] * 4)).read(0)
    # SLVERR -> BusError, not retried
    s = ScriptedSerial([_ans(0x52, 0)])
    with pytest.raises(fqhost.BusError, match="SLVERR"):
        fqhost.FqHost(None, ser=s).read(0x80)
    assert len(s.frames) == 1
    # write answered 0x54 (not executed) is repeated; a lost answer is not
    s = ScriptedSerial([_ans(0x54), _ans(0x50)])
    fqhost.FqHost(None, ser=s).write(4, 100)
    assert len(s.frames) == 2 and s.frames[0] == s.frames[1]
    s = ScriptedSerial([b""])
    with pytest.raises(fqhost.ProtocolError, match="may or may not"):
        fqhost.FqHost(None, ser=s).write(4, 100)
    assert len(s.frames) == 1
    # a read's line names the register read: word 0 reads STATUS, signed ones as signed
    assert fqhost.show(0x00, 5).split() == ["status", "0x00", "0x00000005", "5"]
    assert fqhost.show(0x08, 0xffffffff).split() == ["count", "0x08", "0xffffffff", "-1"]
    assert fqhost.show(0x1e, 7).split() == ["0x1e", "0x1e", "0x00000007", "7"]
    # CLI input errors are argparse errors (exit 2) with the reason
    for argv in (["-p", "x", "read", "nonsense"], ["-p", "x", "write", "interp", "0x1g"],
                 ["-p", "x", "write", "interp", str(1 << 32)], ["read", "id"]):
        with pytest.raises(SystemExit) as e:
            fqhost.main(argv)
        assert e.value.code == 2


# ---- simulator side ----------------------------------------------------------------------
try:
    import cocotb
    from cocotb.triggers import FallingEdge, RisingEdge, Timer
except ImportError:
    cocotb = None


def _cocotb_test(f):
    return cocotb.test()(f) if cocotb else f


async def _start(dut, rst_edges=2):
    bench = fqtb.ClockedBench(dut)
    dut.rst.value = 1
    await bench.start()
    await bench.goto(rst_edges - 1)
    dut.rst.value = 0
    await bench.step()
    return bench


class Collector:
    """Bytes (and pulse counts) out of uart_rx, sampled between edges."""

    def __init__(self, dut):
        self.dut = dut
        self.bytes = []
        self.frame_err = 0
        self.overrun = 0
        self.task = cocotb.start_soon(self._run())

    async def _run(self):
        d = self.dut
        while True:
            await FallingEdge(d.clk)
            if int(d.m_axis_tvalid.value) and int(d.m_axis_tready.value):
                self.bytes.append(int(d.m_axis_tdata.value))
            self.frame_err += int(d.frame_err_o.value)
            self.overrun += int(d.overrun_o.value)
            await RisingEdge(d.clk)


@_cocotb_test
async def rx_bytes(dut):
    from cocotbext.uart import UartSource
    dut.rxd_i.value = 1
    dut.m_axis_tready.value = 1
    await _start(dut)
    col = Collector(dut)
    rng = random.Random(int(os.environ.get("COCOTB_RANDOM_SEED", "1")))
    # the nominal bit time and whole-ns ones at least 3.5 % shorter and longer (154 and
    # 166 ns against 160: -3.75 % and +3.75 %)
    for bit_ns in (BIT_NS, BIT_NS * 965 // 1000, -(-BIT_NS * 1035 // 1000)):
        src = UartSource(dut.rxd_i, baud=1e9 / bit_ns, bits=8, stop_bits=1)
        data = bytes(rng.getrandbits(8) for _ in range(256))
        n0 = len(col.bytes)
        await src.write(data)
        await src.wait()
        await Timer(3 * BIT_NS, "ns")
        assert bytes(col.bytes[n0:]) == data, (bit_ns, len(col.bytes) - n0)
        src._run_cr.cancel()
    assert col.frame_err == 0 and col.overrun == 0


async def _pin_byte(dut, byte, bit_ns=BIT_NS, stop=1):
    dut.rxd_i.value = 0
    await Timer(bit_ns, "ns")
    for k in range(8):
        dut.rxd_i.value = (byte >> k) & 1
        await Timer(bit_ns, "ns")
    dut.rxd_i.value = stop
    await Timer(bit_ns, "ns")
    dut.rxd_i.value = 1


@_cocotb_test
async def rx_errors(dut):
    dut.rxd_i.value = 1
    dut.m_axis_tready.value = 1
    await _start(dut)
    col = Collector(dut)
    await Timer(2 * BIT_NS, "ns")
    # stop bit 0
    await _pin_byte(dut, 0xA5, stop=0)
    await Timer(3 * BIT_NS, "ns")
    assert col.bytes == [] and col.frame_err == 1
    await _pin_byte(dut, 0x3C)
    await Timer(2 * BIT_NS, "ns")
    assert col.bytes == [0x3C] and col.frame_err == 1
    # break: 40 bit times low -> one framing error, no byte
    dut.rxd_i.value = 0
    await Timer(40 * BIT_NS, "ns")
    dut.rxd_i.value = 1
    await Timer(2 * BIT_NS, "ns")
    assert col.bytes == [0x3C] and col.frame_err == 2
    await _pin_byte(dut, 0x00)
    await Timer(2 * BIT_NS, "ns")
    assert col.bytes == [0x3C, 0x00]
    # glitch: 4 clocks low (half a bit is 8)
    dut.rxd_i.value = 0
    await Timer(4 * fqtb.PERIOD_PS, "ps")
    dut.rxd_i.value = 1
    await Timer(12 * BIT_NS, "ns")
    assert col.bytes == [0x3C, 0x00] and col.frame_err == 2
    # overrun: the first byte is held, the second dropped
    dut.m_axis_tready.value = 0
    await _pin_byte(dut, 0x11)
    await Timer(BIT_NS, "ns")
    await _pin_byte(dut, 0x22)
    await Timer(2 * BIT_NS, "ns")
    assert col.overrun == 1 and int(dut.m_axis_tvalid.value) == 1
    assert int(dut.m_axis_tdata.value) == 0x11
    dut.m_axis_tready.value = 1
    await Timer(2 * BIT_NS, "ns")
    await _pin_byte(dut, 0x33)
    await Timer(2 * BIT_NS, "ns")
    assert col.bytes == [0x3C, 0x00, 0x11, 0x33] and col.frame_err == 2 and col.overrun == 1


@_cocotb_test
async def tx_bytes(dut):
    from cocotbext.uart import UartSink
    dut.s_axis_tvalid.value = 0
    dut.s_axis_tdata.value = 0
    bench = await _start(dut)
    sink = UartSink(dut.txd_o, baud=1e9 / BIT_NS, bits=8, stop_bits=1)
    rng = random.Random(int(os.environ.get("COCOTB_RANDOM_SEED", "1")) + 1)
    data = bytes(rng.getrandbits(8) for _ in range(300))
    k = 0
    takes = []
    gap = 0
    while k < len(data):
        # inputs for the next edge
        if gap:
            gap -= 1
            dut.s_axis_tvalid.value = 0
        else:
            dut.s_axis_tvalid.value = 1
            dut.s_axis_tdata.value = data[k]
        await bench.settle()
        ready_before = int(dut.s_axis_tready.value)
        valid = int(dut.s_axis_tvalid.value)
        await bench.step()
        if valid and ready_before:
            takes.append(bench.edge)
            assert int(dut.txd_o.value) == 0, "start bit must begin after the taking edge"
            k += 1
            gap = rng.choice((0, 0, 0, 1, 5, 40, 200))
    dut.s_axis_tvalid.value = 0
    await Timer(12 * BIT_NS, "ns")
    got = sink.read_nowait()
    assert bytes(got) == data, (len(got), len(data))
    d = [b - a for a, b in zip(takes, takes[1:])]
    assert min(d) == 10 * DIV + 1, min(d)
    # tready: low exactly while a byte is on the line (not a function of tvalid)
    dut.s_axis_tvalid.value = 0
    assert int(dut.s_axis_tready.value) == 1


@_cocotb_test
async def bridge(dut):
    from cocotbext.uart import UartSource, UartSink
    from axil_check import RegPortModel
    from fqlink import UartLink, BusError, ProtocolError, FqProtocol

    dut.rxd_i.value = 1
    await _start(dut)
    regs = RegPortModel(dut, dut.clk)
    src = UartSource(dut.rxd_i, baud=1e9 / BIT_NS, bits=8, stop_bits=1)
    sink = UartSink(dut.txd_o, baud=1e9 / BIT_NS, bits=8, stop_bits=1)
    link = UartLink(src, sink, BIT_NS, timeout_bits=40)
    drops = [0]

    async def count_drops():
        while True:
            await FallingEdge(dut.clk)
            drops[0] += int(dut.drop_o.value)
    cocotb.start_soon(count_drops())
    P = FqProtocol
    rng = random.Random(int(os.environ.get("COCOTB_RANDOM_SEED", "1")) + 2)
    model = [0] * 64

    vals = {w: rng.getrandbits(32) for w in range(0x30)}
    for w, v in vals.items():
        await link.write(4 * w, v)
        model[w] = v
    assert regs.writes() == list(vals.items())
    for w in range(0x30):
        assert await link.read(4 * w) == vals[w], hex(w)
    n = len(regs.log)

    # unmapped: SLVERR, nothing on the port
    for w in (0x30, 0x3f, 0x40, 0x3fff):
        try:
            await link.read(4 * w)
            assert False, "read of an unmapped word answered OKAY"
        except BusError as e:
            assert e.status == P.ST_SLVERR
        try:
            await link.write(4 * w, 1)
            assert False, "write of an unmapped word answered OKAY"
        except BusError as e:
            assert e.status == P.ST_SLVERR
    assert len(regs.log) == n

    # bad CHK: 0x54, not executed
    f = bytearray(P().write_frame(4 * 3, 0x11111111))
    f[-1] ^= 0x40
    assert await link.xfer(bytes(f), P.WRITE_LEN) == bytes([0x54, 0xAC])
    f = bytearray(P().read_frame(4 * 3))
    f[2] ^= 1
    assert await link.xfer(bytes(f), P.READ_LEN) == bytes([0x54, 0, 0, 0, 0, 0xAC])
    assert len(regs.log) == n

    # garbage between frames (no 'R', 'W')
    junk = bytes(b for b in (rng.getrandbits(8) for _ in range(64)) if b not in (0x52, 0x57))
    await link.send(junk)
    assert await link.read(4 * 7) == model[7]
    assert sink.empty()

    # a partial write frame, then silence longer than TIMEOUT: dropped, not executed
    d0 = drops[0]
    await link.send(P().write_frame(4 * 9, 0xFFFFFFFF)[:5])
    await Timer((TIMEOUT + 50) * fqtb.PERIOD_PS, "ps")
    assert drops[0] == d0 + 1 and sink.empty()
    assert await link.read(4 * 9) == model[9]
    # bytes just under TIMEOUT apart: executed
    f = P().write_frame(4 * 9, 0x09090909)
    sink.clear()
    for b in f:
        await link.send(bytes([b]))
        await Timer((TIMEOUT - 10 * DIV - 40) * fqtb.PERIOD_PS, "ps")
    assert P().parse(await link.answer(P.WRITE_LEN), False, 4 * 9) is None
    model[9] = 0x09090909
    assert await link.read(4 * 9) == model[9]
    # a break in a frame abandons it
    d0 = drops[0]
    await link.send(P().write_frame(4 * 10, 0)[:4])
    dut.rxd_i.value = 0
    await Timer(20 * BIT_NS, "ns")
    dut.rxd_i.value = 1
    await Timer(2 * BIT_NS, "ns")
    assert drops[0] == d0 + 1 and int(dut.frame_err_o.value) == 0
    assert await link.read(4 * 10) == model[10]
    # a byte during the answer is ignored
    sink.clear()
    await link.send(P().read_frame(4 * 11) + b"W")
    assert P().parse(await link.answer(P.READ_LEN), True, 0) == model[11]
    assert await link.read(4 * 12) == model[12]
    # a silent line after a lost frame: the host's read times out with ProtocolError
    await link.send(b"R\x00")
    try:
        await link.read(4 * 13)      # its bytes complete the stale frame (bad CHK)
        assert False
    except ProtocolError:
        pass
    await Timer((TIMEOUT + 50) * fqtb.PERIOD_PS, "ps")
    assert await link.read(4 * 13) == model[13]

    # seeded random against the model
    nops = 0
    for _ in range(60):
        w = rng.randrange(0x34)
        if rng.random() < 0.5:
            v = rng.getrandbits(32)
            try:
                await link.write(4 * w, v)
                assert w < 0x30
                model[w] = v
            except BusError:
                assert w >= 0x30
        else:
            try:
                assert await link.read(4 * w) == model[w]
                assert w < 0x30
            except BusError:
                assert w >= 0x30
        nops += 1
    assert regs.mem[:0x30] == model[:0x30]
    dut._log.info("bridge: %d random operations, %d port accesses", nops, len(regs.log))
