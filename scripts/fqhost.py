#!/usr/bin/env python3
"""Host client of the finequad UART register link (rtl/uart_axil.v), e.g.

    scripts/fqhost.py -p /dev/ttyUSB1 id
    scripts/fqhost.py -p /dev/ttyUSB1 read count m1 m2 c1 c12 c2
    scripts/fqhost.py -p /dev/ttyUSB1 write interp 200
    scripts/fqhost.py -p /dev/ttyUSB1 write ab_sep 36          (a field: read-modify-write)
    scripts/fqhost.py -p /dev/ttyUSB1 dump
    scripts/fqhost.py -p /dev/ttyUSB1 watch count --interval 0.1

Registers and fields by their names in rtl/regs/finequad.rdl (lower case; word 0 reads
STATUS and writes CTRL). A value outside the field's legal range is refused here, before
anything is sent, naming the field, the value and the range; the core refuses it too
(SLVERR). A/B edge separations that a common counter's input filter cannot follow are
warned about (sim/counters.py; --fclk: the FPGA's clock).

The frames (8N1, HDLC-like framing, CRC-16/CCITT-FALSE, answers matched to their request
by its echoed CRC) are rtl/uart_axil.v's header; the ULX3S build runs at 115 207 baud
(35.714 MHz / 310: use 115200). This client retries a read whose answer is missing or
garbled and a write answered 0x54 (not executed); a write whose answer is missing is not
repeated, because it may have been applied (FAULT_STICKY's write-1-to-clear and CTRL's
pulses act once).

FqProtocol is transport-free (frames in, values out): this script drives it over pyserial,
the cocotb tests (cocotb_tests/fqlink.py) over cocotbext-uart's UartSource/UartSink.
"""
import argparse
import binascii
import pathlib
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from sim import counters  # noqa: E402
from sim.model import regs  # noqa: E402
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import builds  # noqa: E402

# finequad_core's registers by their names (rtl/regs/finequad.rdl, lower case; word 0 is
# STATUS when read, CTRL when written); numbers are accepted for any other word
REGS = {name.lower(): r.index for name, r in regs.REGS.items()}
SIGNED = {name.lower() for name, r in regs.REGS.items()
          if any(f.signed for f in r.fields.values())}
# the ULX3S build's clock (the board with the host link; rtl/builds.toml)
FCLK_HZ = builds.clock("ulx3s")["mhz"] * 1e6


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
    FLAG = 0x7E
    ESC = 0x7D
    ST_OKAY = 0x50
    ST_SLVERR = 0x52
    ST_DECERR = 0x53
    ST_CRCERR = 0x54
    READ_LEN = 9             # answers' content lengths (unescaped)
    WRITE_LEN = 5

    @staticmethod
    def crc(data) -> int:
        """CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, not reflected, no final XOR)."""
        return binascii.crc_hqx(bytes(data), 0xFFFF)

    @classmethod
    def stuff(cls, content: bytes) -> bytes:
        """A frame's bytes on the line: FLAG, the content with 0x7E/0x7D escaped, FLAG."""
        out = bytearray([cls.FLAG])
        for c in content:
            if c in (cls.FLAG, cls.ESC):
                out += bytes([cls.ESC, c ^ 0x20])
            else:
                out.append(c)
        out.append(cls.FLAG)
        return bytes(out)

    @classmethod
    def seal(cls, body: bytes) -> bytes:
        """body with its CRC appended (big-endian)."""
        return body + cls.crc(body).to_bytes(2, "big")

    @staticmethod
    def _addr(addr):
        if not 0 <= addr <= 0xFFFF:
            raise ValueError(f"address 0x{addr:x} outside 16 bits")
        return addr.to_bytes(2, "big")

    def read_frame(self, addr: int) -> bytes:
        return self.stuff(self.seal(bytes([self.CMD_R]) + self._addr(addr)))

    def write_frame(self, addr: int, value: int) -> bytes:
        if not 0 <= value <= 0xFFFFFFFF:
            raise ValueError(f"value {value} outside 32 bits")
        return self.stuff(self.seal(bytes([self.CMD_W]) + self._addr(addr)
                                    + value.to_bytes(4, "big")))

    @classmethod
    def echo(cls, frame: bytes) -> bytes:
        """The CRC field of a request frame (as sent), which its answer echoes."""
        return cls.unstuff(frame)[-2:]

    @classmethod
    def unstuff(cls, frame: bytes) -> bytes:
        """The content of one frame as stuff() makes it."""
        return Deframer().feed(frame)[0]

    def parse(self, content: bytes, is_read: bool, addr: int):
        """Value of a read (None for a write) from its answer's content; BusError for
        SLVERR/DECERR, Rejected for a CRC error reported by the bridge, ProtocolError for
        anything malformed (length, status, CRC)."""
        n = self.READ_LEN if is_read else self.WRITE_LEN
        if len(content) != n:
            raise ProtocolError(f"address 0x{addr:04x}: answer of {len(content)} byte(s), "
                                f"expected {n}: {content.hex()}")
        if self.crc(content):
            raise ProtocolError(f"address 0x{addr:04x}: bad CRC in {content.hex()}")
        st = content[0]
        if st == self.ST_CRCERR:
            raise Rejected(f"address 0x{addr:04x}: the bridge saw a bad CRC")
        if st in (self.ST_SLVERR, self.ST_DECERR):
            raise BusError(addr, st)
        if st != self.ST_OKAY:
            raise ProtocolError(f"address 0x{addr:04x}: unknown status 0x{st:02x}")
        return int.from_bytes(content[3:7], "big") if is_read else None


class Deframer:
    """Frames out of a byte stream: the content between two FLAGs, unescaped; a FLAG after
    0x7D (an abort) drops the frame; bytes before the first FLAG are not a frame."""

    def __init__(self):
        self.buf = None          # None: no FLAG seen yet
        self.esc = False

    def feed(self, data: bytes):
        out = []
        for c in data:
            if c == FqProtocol.FLAG:
                if self.buf and not self.esc:
                    out.append(bytes(self.buf))
                self.buf = bytearray()
                self.esc = False
            elif self.buf is None:
                continue
            elif c == FqProtocol.ESC and not self.esc:
                self.esc = True
            else:
                self.buf.append(c ^ 0x20 if self.esc else c)
                self.esc = False
        return out


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
                print(f"fqhost: error: cannot open {port}: {e}", file=sys.stderr)
                raise SystemExit(2)
        self.ser = ser

    def _resync(self):
        time.sleep(self.RESYNC_S)
        self.ser.reset_input_buffer()

    def _answer(self, echo):
        """The content of the answer whose E1 E0 is `echo`, or what arrived (b"" for
        nothing) when the port's read times out first; answers to other requests are
        skipped."""
        d = Deframer()
        last = b""
        while True:
            data = self.ser.read(1)
            if not data:
                return last
            for f in d.feed(data):
                if f[1:3] == echo:
                    return f
                last = f if len(f) < 3 else last

    def _xfer(self, frame, is_read, addr):
        self.ser.write(frame)
        self.ser.flush()
        return self.proto.parse(self._answer(FqProtocol.echo(frame)), is_read, addr)

    def read(self, addr: int) -> int:
        frame = self.proto.read_frame(addr)
        for attempt in range(self.retries + 1):
            try:
                return self._xfer(frame, True, addr)
            except ProtocolError:
                if attempt == self.retries:
                    raise
                self._resync()

    def write(self, addr: int, value: int):
        frame = self.proto.write_frame(addr, value)
        for attempt in range(self.retries + 1):
            try:
                return self._xfer(frame, False, addr)
            except Rejected:
                if attempt == self.retries:
                    raise
                self._resync()
            except ProtocolError as e:
                raise ProtocolError(f"{e} (the write may or may not have been applied)") \
                    from None


# the fields a write may name alone (read-modify-write of their register): every
# writable field by its name, unique across the map (rtl/regs/finequad.rdl)
FIELDS = {f.name: f for r in regs.REGS.values() for f in r.fields.values()
          if f.write and not f.w1c and r.name != "STATUS"}


def target(text):
    """A read or write target: a register name, a field name (writes) or a word index."""
    t = text.lower()
    if t in REGS or t in FIELDS:
        return t
    try:
        w = int(t, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"unknown register or field '{text}' (registers: {', '.join(sorted(REGS))}; "
            f"fields: {', '.join(sorted(FIELDS))}; or a word index such as 0x1f)")
    if not 0 <= w <= 0x3fff:
        raise argparse.ArgumentTypeError(f"word index {text} outside 0..0x3fff")
    return w


def is_field(what):
    """Whether a write target names a field: a field name that is not the name of a
    writable register (CTRL.capture, not the read-only CAPTURE)."""
    if not isinstance(what, str) or what not in FIELDS:
        return False
    return what not in REGS or not any(r.write for r in regs.REGS.values()
                                       if r.index == REGS[what])


def reg_word(text):
    t = target(text)
    if t in FIELDS:
        raise argparse.ArgumentTypeError(f"'{text}' is a field of {FIELDS[t].reg}: read "
                                         f"{FIELDS[t].reg.lower()}")
    return REGS[t] if isinstance(t, str) else t


def number(text):
    try:
        return int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number")


def u32(v):
    """A 32-bit word from a number (a negative one as two's complement)."""
    if -(1 << 31) <= v < 0:
        v &= 0xFFFFFFFF
    if not 0 <= v <= 0xFFFFFFFF:
        raise ValueError(f"{v} does not fit 32 bits")
    return v


def word_name(word):
    """The register a word reads (word 0: STATUS)."""
    return next((n for n, r in regs.REGS.items() if r.index == word and r.read), None)


def show(word, v):
    """A read's line: name, word, hex, decimal (signed registers as signed). Word 0x00
    reads STATUS (CTRL is what a write to it sets)."""
    name = word_name(word)
    label = name.lower() if name else f"0x{word:02x}"
    s = v - (1 << 32) if (name and name.lower() in SIGNED and v >> 31) else v
    return f"{label:13s} 0x{word:02x}  0x{v:08x}  {s}"


def ab_warning(sep_clocks, fclk_hz):
    """A warning if A/B edges sep_clocks apart are faster than a named counter follows."""
    sep_ns = max(sep_clocks, 1) / fclk_hz * 1e9
    slow = counters.too_fast(sep_ns)
    if not slow:
        return None
    return (f"ABGEN.ab_sep = {sep_clocks} clocks = {sep_ns:.0f} ns at {fclk_hz / 1e6:.3f} MHz: "
            "too fast for " + "; ".join(f"{c.name}, {c.setting} (needs {c.min_sep_ns:.0f} ns)"
                                        for c in slow)
            + ": such a counter loses counts without a quadrature error")


def plan_write(host, what, value, fclk_hz):
    """(word, word value, warning or None) of `write what value`, the value checked
    against the field's range before anything is sent (ValueError says why)."""
    if isinstance(what, int):
        name = next((n for n, r in regs.REGS.items() if r.index == what and r.write), None)
        word = u32(value)
        if name is None:
            return what, word, None         # a word the map does not know: the core decides
    elif is_field(what):                    # read-modify-write of its register
        f = FIELDS[what]
        if not f.lo <= value <= f.hi:
            raise ValueError(f"{f.reg}.{f.name} = {value}: outside {f.lo}..{f.hi}")
        name = f.reg
        r = regs.REGS[name]
        cur = {}
        if name == "CTRL":                  # its count_mode reads in STATUS, pulses are 0
            cur["count_mode"] = regs.value("STATUS", "count_mode", host.read(4 * r.index))
        elif r.read:
            old = host.read(4 * r.index)
            cur = {k: regs.value(name, k, old) for k, g in r.fields.items()
                   if g.write and g.read and not g.pulse}
        cur[f.name] = value
        word = regs.word(name, **cur)
    else:
        name = what.upper()
        if not regs.REGS[name].write:
            name = next((n for n, r in regs.REGS.items()
                         if r.index == regs.REGS[name].index and r.write), name)
        word = u32(value)
    why = regs.illegal(name, word)
    if why:
        raise ValueError(why)
    warn = None
    if name == "ABGEN":
        warn = ab_warning(regs.value("ABGEN", "ab_sep", word), fclk_hz)
    return regs.REGS[name].index, word, warn


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-p", "--port", required=True, help="serial port, e.g. /dev/ttyUSB1")
    ap.add_argument("-b", "--baud", type=int, default=115200)
    ap.add_argument("--fclk", type=float, default=FCLK_HZ,
                    help="the FPGA's clock in Hz, for the A/B edge separation in ns "
                         f"(default {FCLK_HZ:.6g}: the ULX3S build)")
    sub = ap.add_subparsers(dest="cmd", required=True)
    sub.add_parser("id", help="read the ID register")
    r = sub.add_parser("read", help="read registers (names or word indices)")
    r.add_argument("regs", nargs="+", type=reg_word)
    w = sub.add_parser("write", help="write a register or one field (names as in the "
                                     "register reference)")
    w.add_argument("target", type=target)
    w.add_argument("value", type=number)
    sub.add_parser("dump", help="read every named register")
    wa = sub.add_parser("watch", help="read registers repeatedly")
    wa.add_argument("regs", nargs="+", type=reg_word)
    wa.add_argument("--interval", type=float, default=0.2)
    wa.add_argument("--count", type=int, default=0, help="reads (0: until Ctrl-C)")
    a = ap.parse_args(argv)
    if a.cmd == "watch" and not (0 <= a.interval <= 3600 and a.count >= 0):   # (not nan)
        ap.error(f"watch: --interval must be 0..3600 s and --count >= 0, got {a.interval} "
                 f"and {a.count}")
    if not 1e6 <= a.fclk <= 1e9:                                               # (not nan)
        ap.error(f"--fclk must be 1e6..1e9 Hz, got {a.fclk}")
    if a.cmd == "write":                     # checked before the port opens
        try:
            if is_field(a.target):
                f = FIELDS[a.target]
                if not f.lo <= a.value <= f.hi:
                    raise ValueError(f"{f.reg}.{f.name} = {a.value}: outside {f.lo}..{f.hi}")
            else:
                plan_write(None, a.target, a.value, a.fclk)
        except ValueError as e:
            ap.error(f"write: {e}")

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
            try:
                word, value, warn = plan_write(host, a.target, a.value, a.fclk)
            except ValueError as e:
                sys.exit(f"fqhost: error: write: {e}")
            if warn:
                print(f"fqhost: warning: {warn}", file=sys.stderr)
            host.write(4 * word, value)
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
