"""The UART register link in cocotb: scripts/fqhost.py's FqProtocol over cocotbext-uart.

UartLink(source, sink, bit_ns) sends a frame with a UartSource on the bridge's RX pin,
collects the answer with a UartSink on its TX pin, and decodes it with the same
FqProtocol and Deframer the host client uses on a real serial port: the answer is the
first frame whose echo matches the request's CRC. No such frame within `timeout_bits`
bit times of silence raises ProtocolError with what arrived, as pyserial's read timeout
does in FqHost.
"""
import sys

import fqtb

sys.path.insert(0, str(fqtb.REPO / "scripts"))
from fqhost import Deframer, FqProtocol, ProtocolError, BusError, Rejected  # noqa: E402,F401


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

    async def frames(self):
        """Every frame that arrives until the line has been quiet for timeout_ns."""
        d = Deframer()
        out = []
        while True:
            if self.sink.empty():
                await self.sink.wait(self.timeout_ns, "ns")
                if self.sink.empty():
                    return out
            out += d.feed(self.sink.read_nowait(self.sink.count()))

    async def answer(self, echo):
        """The content of the answer to the request with CRC field `echo` (b"" if none
        came before the line went quiet)."""
        d = Deframer()
        while True:
            if self.sink.empty():
                await self.sink.wait(self.timeout_ns, "ns")
                if self.sink.empty():
                    return b""
            for f in d.feed(self.sink.read_nowait(self.sink.count())):
                if f[1:3] == echo:
                    return f

    async def xfer(self, frame):
        self.sink.clear()
        await self.send(frame)
        return await self.answer(FqProtocol.echo(frame))

    async def read(self, addr: int) -> int:
        return self.proto.parse(await self.xfer(self.proto.read_frame(addr)), True, addr)

    async def write(self, addr: int, value: int):
        self.proto.parse(await self.xfer(self.proto.write_frame(addr, value)), False, addr)
