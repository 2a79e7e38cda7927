"""Bit-true model of rtl/dcode.v: distance-coded reference marks. The scale's layout, the
decode and its rules are in rtl/dcode.v's header; this model follows them edge by edge.

The decoder sees, on each sample's edge t + 10 (sim/model/refmark.py's stage 2): the
sample's crossing of a reference point (+1, -1 or 0: the signed count of signal periods
travelled), its latch (with the raw count x at the reference), and inv (a coast that lost
the travel, or an overspeed sample). A decode starts on a latch's edge E and ends on E + DC_LAT; a latch
or inv on an edge E + 1 .. E + DC_LAT abandons it (a latch: an overrun, flagged).
"""
from .fixed import wrap

DC_LAT = 27          # edges from a latch's edge to its decode's result (rtl/dcode.v)
DR_FAR = 4095        # |periods since the last latch| at which the distance is too far


def decode(m, fwd, spacing, coded):
    """The pair of marks m signal periods apart (m > 0), crossed forwards (fwd) or back:
    (ok, xa, fa): ok when m is a distance of the layout, xa the second mark's position
    and fa the first's, in signal periods from the scale's first mark (rtl/dcode.v)."""
    a, b = spacing, coded
    if a == 0 or a % 2 or b <= a or m >= a:
        return False, 0, 0
    e = m - a // 2
    d = b - a
    if e == 0 or abs(e) % d:
        return False, 0, 0
    k = abs(e) // d
    epos = e > 0
    if fwd == epos:
        xa = k * b - a // 2
    else:
        xa = k * a - (0 if fwd else a)
    fa = xa - m if fwd else xa + m
    return True, xa, fa


class DCode:
    """The decoder's state from rst. refmark.RefMark calls `edge` on every sample's
    t + 10 and, before it, `finish` for a decode that has ended by then."""

    def __init__(self, count_w=32, spacing=0, coded=0, confirm=0, n=1, home=0):
        self.count_w = count_w
        self.a, self.b, self.conf = int(spacing), int(coded), int(confirm)
        self.n = int(n)
        self.home = int(home)
        self.dr = 0                  # signed periods since the last latch
        self.far = False
        self.have = False            # a mark since rst / inv: dr counts from it
        self.pv = False              # the last mark's position is known (ap)
        self.ap = 0
        self.sp = True               # the direction of the pair that gave ap
        self.abs_valid = 0
        self.abs_count = 0           # ABS_COUNT
        self.pending = None          # (F, m, fwd, far, x): a decode under way, its last
                                     # edge F
        self.errors = 0              # dc_err pulses (REF_STICKY.dc_err), counted

    @property
    def enabled(self):
        return self.a != 0

    def finish(self, edge, rm):
        """Completes a decode whose last edge F <= edge, on F (the caller has fed every
        event before F, and on F none that abandons it). With REF.home armed, a decode
        that leaves abs_valid 1 homes rm (refmark.RefMark) on F."""
        if self.pending is None or self.pending[0] > edge:
            return
        f, m, fwd, far, x = self.pending
        self.pending = None
        ok, xa, fa = decode(m, fwd, self.a, self.b)
        if not ok or far:
            self.errors += 1
            self.abs_valid, self.pv = 0, False
            return
        if self.pv and fa != self.ap:
            self.errors += 1
            self.abs_valid = 0
            self.pv, self.ap, self.sp = True, xa, fwd
            return
        nv = (not self.conf) or self.abs_valid == 1 or (self.pv and fwd == self.sp)
        self.pv, self.ap, self.sp = True, xa, fwd
        if not nv:
            return
        self.abs_valid = 1
        self.abs_count = wrap(xa * 4 * self.n, self.count_w)
        rm.arm_homes(f)
        if rm.home_armed:
            rm.off = wrap(self.home - x + self.abs_count, self.count_w)
            rm.ref_count = wrap(self.home + self.abs_count, self.count_w)
            rm.pos_valid = 1
            rm.home_armed = False

    def edge(self, e, cross, lat, x, inv):
        """The events of edge e (a sample's t + 10): its crossing (+1, -1, 0), its latch
        (with its raw count x) and inv. A decode ending on e has been finished by the
        caller unless a latch or inv on e abandons it (rtl/dcode.v)."""
        busy = self.pending is not None and self.pending[0] >= e
        if inv:
            self.pending = None
            self.have = self.pv = False
            self.abs_valid = 0
        elif lat and busy:
            self.pending = None
            self.errors += 1
            self.have, self.pv = True, False
            self.abs_valid = 0
        dr = ((self.dr + cross + 4096) % 8192) - 4096
        far = self.far or abs(dr) >= DR_FAR
        if lat and not inv and not busy:
            if self.have and dr != 0:
                self.pending = (e + DC_LAT, abs(dr), dr > 0, far, x)
            self.have = True
        if lat:
            dr, far = 0, False
        self.dr, self.far = dr, far
