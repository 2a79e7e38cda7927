#!/usr/bin/env python3
"""Host client of the finequad UART register link (rtl/uart_axil.v), e.g.

    scripts/fqhost.py -p /dev/ttyUSB1 id
    scripts/fqhost.py -p /dev/ttyUSB1 read count m1 m2 c1 c12 c2
    scripts/fqhost.py -p /dev/ttyUSB1 write interp 200
    scripts/fqhost.py -p /dev/ttyUSB1 dump
    scripts/fqhost.py -p /dev/ttyUSB1 watch count --interval 0.1

Protocol (8N1; the ULX3S build runs at 115 207 baud, 35.714 MHz / 310: use 115200;
big-endian; CHK makes the 8-bit sum of a frame's bytes zero):
    read   'R' A1 A0 CHK                ->  ST D3 D2 D1 D0 CHK
    write  'W' A1 A0 D3 D2 D1 D0 CHK    ->  ST CHK
A = AXI byte address (register k of finequad_core at 4 k). ST: 0x50 OKAY, 0x52 SLVERR,
0x53 DECERR, 0x54 checksum error (frame not executed). The bridge drops a partial frame
after TIMEOUT clocks without a byte (283 000 clocks on the ULX3S: 7.9 ms) or
on a break; this client waits RESYNC_S (20 ms) after a bad or missing answer, flushes its
input and retries (reads, and writes answered 0x54; a write whose answer was lost is not
repeated, because it may have been applied: FAULT_STICKY's write-1-to-clear and CTRL's
reset request act once).

FqProtocol is transport-free (frames in, values out): this script drives it over pyserial,
the cocotb tests (cocotb_tests/fqlink.py) over cocotbext-uart's UartSource/UartSink.
"""
import argparse
import pathlib
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from sim.model import regs  # noqa: E402

# finequad_core's registers by their names (rtl/regs/finequad.rdl, lower case; word 0 is
# STATUS when read, CTRL when written); numbers are accepted for any other word
REGS = {name.lower(): r.index for name, r in regs.REGS.items()}
SIGNED = {name.lower() for name, r in regs.REGS.items()
          if any(f.signed for f in r.fields.values())}


class ProtocolError(Exception):
    """No answer, or an answer that does not follow the protocol."""


class Rejected(ProtocolError):
    """The bridge answered 0x54: it saw a bad checksum and did not execute the frame."""


class BusError(Exception):
    """The bridge answered, and the AXI response was SLVERR or DECERR."""

    def __init__(self, addr, status):
        self.addr = addr
        self.status = status
        name = {0x52: "SLVERR", 0x53: "DECERR"}.get(status, f"status 0x{status:02x}")
        super().__init__(f"address 0x{addr:04x}: {name}")


class FqProtocol:
    CMD_R = 0x52
    CMD_W = 0x57
    ST_OKAY = 0x50
    ST_SLVERR = 0x52
    ST_DECERR = 0x53
    ST_CHKERR = 0x54
    READ_LEN = 6             # answer lengths
    WRITE_LEN = 2

    @staticmethod
    def chk(data) -> int:
        return -sum(data) & 0xFF

    @staticmethod
    def _addr(addr):
        if not 0 <= addr <= 0xFFFF:
            raise ValueError(f"address 0x{addr:x} outside 16 bits")
        return addr.to_bytes(2, "big")

    def read_frame(self, addr: int) -> bytes:
        f = bytes([self.CMD_R]) + self._addr(addr)
        return f + bytes([self.chk(f)])

    def write_frame(self, addr: int, value: int) -> bytes:
        if not 0 <= value <= 0xFFFFFFFF:
            raise ValueError(f"value {value} outside 32 bits")
        f = bytes([self.CMD_W]) + self._addr(addr) + value.to_bytes(4, "big")
        return f + bytes([self.chk(f)])

    def parse(self, answer: bytes, is_read: bool, addr: int):
        """Value of a read (None for a write) from its answer; BusError for SLVERR/DECERR,
        ProtocolError for anything malformed (length, status, checksum)."""
        n = self.READ_LEN if is_read else self.WRITE_LEN
        if len(answer) != n:
            raise ProtocolError(f"address 0x{addr:04x}: answer of {len(answer)} byte(s), "
                                f"expected {n}: {answer.hex()}")
        if sum(answer) & 0xFF:
            raise ProtocolError(f"address 0x{addr:04x}: bad checksum in {answer.hex()}")
        st = answer[0]
        if st == self.ST_CHKERR:
            raise Rejected(f"address 0x{addr:04x}: the bridge saw a bad checksum")
        if st in (self.ST_SLVERR, self.ST_DECERR):
            raise BusError(addr, st)
        if st != self.ST_OKAY:
            raise ProtocolError(f"address 0x{addr:04x}: unknown status 0x{st:02x}")
        return int.from_bytes(answer[1:5], "big") if is_read else None


class FqHost:
    """The register link over a serial port (pyserial)."""
    RESYNC_S = 0.02

    def __init__(self, port, baud=115200, timeout=0.2, retries=3, ser=None):
        self.proto = FqProtocol()
        self.retries = retries
        if ser is None:
            try:
                import serial
            except ImportError:
                raise SystemExit("fqhost: error: pyserial is not installed (run it with the "
                                 "project's .venv/bin/python, or pip install pyserial)")
            try:
                ser = serial.Serial(port, baud, timeout=timeout)
            except (serial.SerialException, ValueError) as e:
                raise SystemExit(f"fqhost: error: cannot open {port}: {e}")
        self.ser = ser

    def _resync(self):
        time.sleep(self.RESYNC_S)
        self.ser.reset_input_buffer()

    def _xfer(self, frame, n, is_read, addr):
        self.ser.write(frame)
        self.ser.flush()
        return self.proto.parse(self.ser.read(n), is_read, addr)

    def read(self, addr: int) -> int:
        frame = self.proto.read_frame(addr)
        for attempt in range(self.retries + 1):
            try:
                return self._xfer(frame, FqProtocol.READ_LEN, True, addr)
            except ProtocolError:
                if attempt == self.retries:
                    raise
                self._resync()

    def write(self, addr: int, value: int):
        frame = self.proto.write_frame(addr, value)
        for attempt in range(self.retries + 1):
            try:
                return self._xfer(frame, FqProtocol.WRITE_LEN, False, addr)
            except Rejected:
                if attempt == self.retries:
                    raise
                self._resync()
            except ProtocolError as e:
                raise ProtocolError(f"{e} (the write may or may not have been applied)") \
                    from None


def reg_word(text):
    t = text.lower()
    if t in REGS:
        return REGS[t]
    try:
        w = int(t, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"unknown register '{text}' (names: {', '.join(sorted(REGS))}, or a word "
            "index such as 0x1f)")
    if not 0 <= w <= 0x3fff:
        raise argparse.ArgumentTypeError(f"word index {text} outside 0..0x3fff")
    return w


def u32(text):
    try:
        v = int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number")
    if -(1 << 31) <= v < 0:
        v &= 0xFFFFFFFF
    if not 0 <= v <= 0xFFFFFFFF:
        raise argparse.ArgumentTypeError(f"{text} does not fit 32 bits")
    return v


def show(word, v):
    """A read's line: name, word, hex, decimal (signed registers as signed). Word 0x00
    reads STATUS (CTRL is what a write to it sets)."""
    names = [n for n, w in REGS.items() if w == word and n != "ctrl"]
    name = names[0] if names else f"0x{word:02x}"
    s = v - (1 << 32) if (names and names[0] in SIGNED and v >> 31) else v
    return f"{name:13s} 0x{word:02x}  0x{v:08x}  {s}"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-p", "--port", required=True, help="serial port, e.g. /dev/ttyUSB1")
    ap.add_argument("-b", "--baud", type=int, default=115200)
    sub = ap.add_subparsers(dest="cmd", required=True)
    sub.add_parser("id", help="read the ID register")
    r = sub.add_parser("read", help="read registers (names or word indices)")
    r.add_argument("regs", nargs="+", type=reg_word)
    w = sub.add_parser("write", help="write one register")
    w.add_argument("reg", type=reg_word)
    w.add_argument("value", type=u32)
    sub.add_parser("dump", help="read every named register")
    wa = sub.add_parser("watch", help="read registers repeatedly")
    wa.add_argument("regs", nargs="+", type=reg_word)
    wa.add_argument("--interval", type=float, default=0.2)
    wa.add_argument("--count", type=int, default=0, help="reads (0: until Ctrl-C)")
    a = ap.parse_args(argv)
    if a.cmd == "watch" and not (0 <= a.interval <= 3600 and a.count >= 0):   # (not nan)
        ap.error(f"watch: --interval must be 0..3600 s and --count >= 0, got {a.interval} "
                 f"and {a.count}")

    host = FqHost(a.port, a.baud)
    try:
        if a.cmd == "id":
            v = host.read(4 * REGS["id"])
            print(f"ID 0x{v:08x} ('{v >> 24:c}{(v >> 16) & 0xff:c}' version "
                  f"{(v >> 8) & 0xff}.{v & 0xff})")
        elif a.cmd == "read":
            for word in a.regs:
                print(show(word, host.read(4 * word)))
        elif a.cmd == "write":
            host.write(4 * a.reg, a.value)
        elif a.cmd == "dump":
            for word in sorted(set(REGS.values())):
                print(show(word, host.read(4 * word)))
        else:
            k = 0
            while not a.count or k < a.count:
                print("  ".join(f"{host.read(4 * w):#010x}" for w in a.regs), flush=True)
                k += 1
                time.sleep(a.interval)
    except (ProtocolError, BusError) as e:
        sys.exit(f"fqhost: error: {e}")
    except OSError as e:            # the port went away (pyserial's SerialException too)
        sys.exit(f"fqhost: error: {a.port}: {e}")
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
