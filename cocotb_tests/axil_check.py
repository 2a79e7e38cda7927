"""Shared cocotb helpers of the AXI4-Lite and system tests (simulator side).

* ``RegPortModel``: a 64 x 32-bit register file behind finequad_core's register port
  (reg_we / reg_re / reg_addr / reg_wdata in, reg_rdata out, registered: the value read on
  edge e is on reg_rdata after e and held until the next reg_re), with a log of every
  write and read the port saw, in edge order.
* ``AxilMonitor``: checks the AXI4-Lite handshake rules on all five channels of a bus:
  once VALID is high it stays high, with its payload unchanged, until the edge on which
  READY is high too. Violations are collected in ``errors``.
* ``pauses(rng, p)``: a pause generator for cocotbext-axi channels (True = pause: a
  source holds VALID low, a sink holds READY low) with probability p per clock.

Signals are sampled half a period after each rising edge (on the falling edge), where
every register output of the DUT is settled in both simulators.
"""
import cocotb
from cocotb.triggers import FallingEdge, RisingEdge

MASK32 = 0xFFFFFFFF


def pauses(rng, p):
    while True:
        yield rng.random() < p


class RegPortModel:
    """finequad_core's register port as a memory of 64 words: a write on an edge with
    reg_we stores, a read on an edge with reg_re returns the word after it (registered).
    refuse(addr, wdata): the writes the core would refuse; the model drives reg_err for
    them during reg_we's clock (as the core's combinational verdict) and stores nothing."""

    def __init__(self, dut, clk, init=None, refuse=None):
        self.dut = dut
        self.clk = clk
        self.mem = list(init) if init is not None else [0] * 64
        self.log = []          # (edge, 'W' | 'R' | 'X' (refused), addr, data)
        self.edge = 0
        self.refuse = refuse or (lambda addr, wdata: False)
        dut.reg_rdata.value = 0
        dut.reg_err.value = 0
        self._task = cocotb.start_soon(self._run())

    async def _run(self):
        d = self.dut
        while True:
            await FallingEdge(self.clk)
            we = int(d.reg_we.value)
            re = int(d.reg_re.value)
            addr = int(d.reg_addr.value)
            wdata = int(d.reg_wdata.value)
            err = bool(we and self.refuse(addr, wdata))
            d.reg_err.value = int(err)
            await RisingEdge(self.clk)
            self.edge += 1
            if re:
                self.log.append((self.edge, "R", addr, self.mem[addr]))
                d.reg_rdata.value = self.mem[addr]
            if we and err:
                self.log.append((self.edge, "X", addr, wdata))
            elif we:
                self.log.append((self.edge, "W", addr, wdata))
                self.mem[addr] = wdata

    def writes(self):
        return [(a, v) for _, k, a, v in self.log if k == "W"]

    def reads(self):
        return [(a, v) for _, k, a, v in self.log if k == "R"]


CHANNELS = {
    "aw": ("awvalid", "awready", ("awaddr", "awprot")),
    "w": ("wvalid", "wready", ("wdata", "wstrb")),
    "b": ("bvalid", "bready", ("bresp",)),
    "ar": ("arvalid", "arready", ("araddr", "arprot")),
    "r": ("rvalid", "rready", ("rdata", "rresp")),
}


class AxilMonitor:
    def __init__(self, dut, clk, prefix="s_axil"):
        self.clk = clk
        self.sig = {ch: (getattr(dut, f"{prefix}_{v}"), getattr(dut, f"{prefix}_{r}"),
                         [getattr(dut, f"{prefix}_{p}") for p in pl])
                    for ch, (v, r, pl) in CHANNELS.items()}
        self.errors = []
        self.handshakes = {ch: 0 for ch in CHANNELS}
        self.stalls = {ch: 0 for ch in CHANNELS}     # clocks with VALID high, READY low
        self._task = cocotb.start_soon(self._run())

    async def _run(self):
        pending = {ch: None for ch in CHANNELS}     # payload held while waiting
        n = 0
        while True:
            await FallingEdge(self.clk)
            n += 1
            for ch, (v, r, pl) in self.sig.items():
                valid = str(v.value) == "1"
                ready = str(r.value) == "1"
                payload = tuple(str(p.value) for p in pl)
                if pending[ch] is not None:
                    if not valid:
                        self.errors.append(f"clock {n}: {ch}valid dropped before {ch}ready")
                    elif payload != pending[ch]:
                        self.errors.append(f"clock {n}: {ch} payload changed while waiting "
                                           f"({pending[ch]} -> {payload})")
                if valid and ready:
                    self.handshakes[ch] += 1
                    pending[ch] = None
                elif valid:
                    self.stalls[ch] += 1
                    pending[ch] = payload
                else:
                    pending[ch] = None
