"""The UART register link in cocotb: scripts/fqhost.py's FqProtocol over cocotbext-uart.

UartLink(source, sink, bit_ns) sends a frame with a UartSource on the bridge's RX pin,
collects the answer with a UartSink on its TX pin, and decodes it with the same
FqProtocol class the host client uses on a real serial port. A missing answer (fewer
bytes than the protocol's answer length within `timeout_bits` bit times after the frame
went out) raises ProtocolError, as pyserial's read timeout does in FqHost.
"""
import sys

import fqtb

sys.path.insert(0, str(fqtb.REPO / "scripts"))
from fqhost import FqProtocol, ProtocolError, BusError, Rejected  # noqa: E402,F401


class UartLink:
    def __init__(self, source, sink, bit_ns, timeout_bits=200):
        self.src = source
        self.sink = sink
        self.bit_ns = bit_ns
        self.timeout_ns = timeout_bits * bit_ns
        self.proto = FqProtocol()

    async def send(self, data: bytes):
        await self.src.write(data)
        await self.src.wait()

    async def answer(self, n):
        """Up to n bytes, waiting at most timeout_ns for each."""
        out = bytearray()
        while len(out) < n:
            if self.sink.empty():
                await self.sink.wait(self.timeout_ns, "ns")
                if self.sink.empty():
                    break
            out += self.sink.read_nowait(min(n - len(out), self.sink.count()))
        return bytes(out)

    async def xfer(self, frame, n):
        self.sink.clear()
        await self.send(frame)
        return await self.answer(n)

    async def read(self, addr: int) -> int:
        ans = await self.xfer(self.proto.read_frame(addr), FqProtocol.READ_LEN)
        return self.proto.parse(ans, True, addr)

    async def write(self, addr: int, value: int):
        ans = await self.xfer(self.proto.write_frame(addr, value), FqProtocol.WRITE_LEN)
        self.proto.parse(ans, False, addr)
