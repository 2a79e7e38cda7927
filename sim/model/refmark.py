"""Bit-true model of rtl/refmark.v: the reference window, the reference crossing, Z at
the paced A/B pins, REF_COUNT, homing and pos_valid. The rules and their reasons are in
rtl/refmark.v's header; this model follows them sample by sample and edge by edge:

* Sample k (strobe edge t_k; its count c_k on t_k + 8): on t_k + 9 the window takes the
  filtered reference input, the crossing of c_(k-1) -> c_k over a count = ref_q (mod 4 n)
  is found (x), Z is armed at x, and the pins' target becomes c_k (the pins step towards
  it from t_k + 10). On t_k + 10 the latch, homing and pos_valid take the sample.
* Z is disarmed on an edge where the window (as registered) is closed and the pins and
  their target both lie strictly on one side of z_at. Between two registrations of the
  target and the window (t_j + 10 .. t_(j+1) + 9) the pins move monotonically towards a
  fixed target, so once that holds it holds to the end of the span: the model tests it
  on the span's last edge, t_(j+1) + 9, the edge of sample j + 1's own update (its
  crossing wins). A disarm earlier in the span changes no sampled Z: after it the pins
  stay strictly on one side of z_at.
* Z after edge e: armed (before e) and the pins after e at z_at (before e).
* Distance-coded marks (sim/model/dcode.py): each sample's crossing, latch and
  invalidation reach the decoder on t + 10; a decode that ends between two samples'
  t + 10 is finished before the later sample (no event in between can abandon it), and
  its homing changes the offset on its last edge.
* With the Eq. 12 pulses on the pins (ab_src = 1) the pins are sample j's pulses from
  t_j + 10, and Z beside them (rtl/refmark.v: the count the pulses show is ref_q, inside
  the window, or it was and the pulses have not moved).
"""
import numpy as np

from .dcode import DCode
from .fixed import wrap

QUAD = {(1, 1): 0, (0, 1): 1, (0, 0): 2, (1, 0): 3}   # quadrant code {~B, A ^ B}


class RefMark:
    """The block's state from rst; `run` takes the next samples."""

    def __init__(self, count_w=32, ref_q=0, ref_filt=2, home_count=0, home_arm=False,
                 homes=(), dc_spacing=0, dc_coded=0, dc_confirm=0):
        self.count_w = count_w
        self.ref_q, self.ref_filt = int(ref_q), int(ref_filt)
        self.home = wrap(int(home_count), count_w)
        # stage 1 (t + 9)
        self.cp = 0                  # the previous sample's count (low 12 bits used)
        self.primed = False
        self.win = 0
        self.fc = 0
        self.arm = False
        self.z_en = False
        self.z_at = 0
        self.target = 0              # the pins' target (the last count registered)
        # stage 2 (t + 10)
        self.off = 0
        self.ref_count = 0
        self.homed = 0
        self.pos_valid = 0
        self.home_armed = bool(home_arm)
        self.homes = sorted(int(w) for w in homes)   # edges of REF.home writes (pending)
        self.pins = (1, 1)           # the Eq. 12 pins (pulses one edge late) and their Z
        self.zp = 0
        self.latches = 0             # latch pulses (REF_STICKY.latched), counted
        self.losses = 0              # pos_valid falls (REF_STICKY.lost), counted
        # results registered after the last sample fed, shown on later edges: (edge, off),
        # (edge, pins, zp); Z's state before the last stage-1 update and that update's edge
        self.off_pend, self.pins_pend = [], []
        self.off_shown, self.pins_shown = 0, ((1, 1), 0)
        self.z_before, self.z_edge = (False, 0), -1
        # distance-coded marks (sim/model/dcode.py; DCODE.dc_spacing = 0: off)
        self.dc = DCode(count_w, dc_spacing, dc_coded, dc_confirm, home=self.home)

    def arm_homes(self, edge):
        """REF.home writes on edges w <= edge - 2 arm homing for a latch or decode on
        `edge` (a write on w arms it on w + 1)."""
        while self.homes and self.homes[0] <= edge - 2:
            self.homes.pop(0)
            self.home_armed = True

    def _dc_finish(self, edge, pend):
        """A decode ending by `edge` (no event left that could abandon it); its homing
        changes the offset on its last edge."""
        p = self.dc.pending
        if p is not None and p[0] <= edge:
            off = self.off
            self.dc.finish(edge, self)
            if self.off != off:
                pend.append((p[0], self.off))

    def crossing(self, c, q, n, held, ovs, mode):
        """(hit, x) of one sample: does the step from the previous count to c cross a
        count = ref_q (mod 4 n) (hit: +1 forwards, -1 back, 0 not), and at which count
        (rtl/refmark.v)."""
        n4 = 4 * n
        if not self.primed or mode or held or ovs or self.ref_q >= n4:
            return 0, 0
        kf = (q - self.ref_q) % n4
        kr = (self.ref_q - q) % n4
        dc = ((c - self.cp) + 2048) % 4096 - 2048        # 12-bit two's complement
        if dc > 0 and kf < dc:
            return 1, wrap(c - kf, self.count_w)
        if dc < 0 and kr < -dc:
            return -1, wrap(c + kr, self.count_w)
        return 0, 0

    def run(self, t, count, q, n, held, ovs, ref, mode, ab, pa=None, pb=None, *, lost):
        """Samples with strobe edges t, raw counts, q = prod >> 11, held, ovs, ref (per
        sample arrays), n, mode (count_mode), and the pins (abgen.Follower, run to no
        later than the first sample's t + 8); lost (per sample: the monitor's coast lost the
        travel, sim/model/monitor.py) clears pos_valid, as ovs does. Returns per-sample arrays:
        a, b, ab_ovf (pins after t + 8), z (after t + 8), off8 (the offset after t + 8:
        m_count = count + off8), ref_count, homed, pos_valid (after t + 10); with the
        sample's Eq. 12 pulses pa, pb: the pins ep_a, ep_b and ep_z (after t + 8) when
        they show the pulses; abs_valid and abs_count (ABS_COUNT) after t + 10."""
        n_s = len(t)
        out = {k: np.zeros(n_s, np.int64) for k in
               ("a", "b", "ab_ovf", "z", "off8", "ref_count", "homed", "pos_valid",
                "ep_a", "ep_b", "ep_z", "abs_valid", "abs_count")}
        self.dc.n = n
        dc_on = self.dc.enabled
        if pa is None:
            pa = pb = np.ones(n_s, np.int64)
        pal, pbl = [int(v) for v in pa], [int(v) for v in pb]
        n4 = 4 * n
        tl = [int(v) for v in t]
        cl = [int(v) for v in count]
        ql = [int(v) for v in q]
        hl = [bool(v) for v in held]
        ll = [bool(v) for v in lost]
        ol = [bool(v) for v in ovs]
        rl = [int(v) for v in ref]
        cw = self.count_w
        # stage-2 results wait for their edge t + 10 (m_count's offset is read on t + 8);
        # with samples on consecutive edges, sample k - 1's stage-1 update (t_(k-1) + 9 =
        # t_k + 8) comes after the Z of sample k
        pend, pins_pend = self.off_pend, self.pins_pend
        for k in range(n_s):
            tk = tl[k]
            if dc_on and self.dc.pending is not None:
                self._dc_finish(tk + 9, pend)
            while pend and pend[0][0] <= tk + 8:
                self.off_shown = pend.pop(0)[1]
            out["off8"][k] = self.off_shown
            # ---- the pins and Z after t_k + 8 (each target was set for its edge t_j + 10,
            # so the pins run to t_k + 8 with the targets registered before) -------------
            a, b, ovf = ab.sample(tk + 8)
            p8 = ab.st.pos
            out["a"][k], out["b"][k], out["ab_ovf"][k] = a, b, ovf
            z_en, z_at = (self.z_en, self.z_at) if self.z_edge < tk + 8 else self.z_before
            out["z"][k] = int(z_en and p8 == z_at)
            while pins_pend and pins_pend[0][0] <= tk + 8:
                self.pins_shown = pins_pend.pop(0)[1:]
            (out["ep_a"][k], out["ep_b"][k]), out["ep_z"][k] = self.pins_shown
            # ---- stage 1 of sample k on t_k + 9 -------------------------------------------
            # pins before t_k + 9 = after t_k + 8 (p8); the target and the window before it:
            # the span's registered values (c_(k-1), win_(k-1))
            hit, x = self.crossing(cl[k], ql[k], n, hl[k], ol[k], mode)
            r = rl[k]
            flip = r != self.win and self.fc >= self.ref_filt
            win_n = r if flip else self.win
            xc = hit != 0 and win_n == 1
            arm_n = self.arm or (win_n == 1 and self.win == 0)
            lat = xc and arm_n
            if xc:
                z_en, z_at = True, x
            else:
                z_en, z_at = self.z_en, self.z_at
                if self.z_en and self.win == 0:
                    sp = wrap(p8 - self.z_at, cw)
                    st = wrap(self.target - self.z_at, cw)
                    if sp != 0 and st != 0 and (sp < 0) == (st < 0):
                        z_en = False
            self.fc = 0 if (r == self.win or flip) else self.fc + 1
            self.win = win_n
            self.arm = arm_n and win_n == 1 and not lat
            self.z_before, self.z_edge = (self.z_en, self.z_at), tk + 9
            self.z_en, self.z_at = z_en, z_at
            self.cp = cl[k]
            self.primed = not hl[k] and not mode
            self.target = cl[k]
            ab.set(tk + 10, cl[k])
            # ---- stage 2 on t_k + 10 -----------------------------------------------------
            self.arm_homes(tk + 10)
            inv = ll[k] or ol[k]
            # a decode ending on this edge, unless this latch or inv abandons it
            if dc_on and not lat and not inv and self.dc.pending is not None:
                self._dc_finish(tk + 10, pend)
            if self.pos_valid and inv:
                self.losses += 1
            if lat:
                self.latches += 1
                self.homed = 1
                if self.home_armed and not self.dc.enabled:
                    self.pos_valid = 1
                    self.off = wrap(self.home - x, cw)
                    self.ref_count = self.home
                    self.home_armed = False
                else:
                    self.ref_count = wrap(x + self.off, cw)
            if inv:
                self.pos_valid = 0
            if dc_on:                    # off: the decoder stays cleared (rtl: inv)
                self.dc.edge(tk + 10, hit, lat, x, inv)
            pend.append((tk + 10, self.off))
            # ---- the Eq. 12 pins and their Z on t_k + 10 ------------------------------------
            pins = (pal[k], pbl[k])
            pq, pq_d = QUAD[pins], QUAD[self.pins]
            dl = (ql[k] - pq) & 3
            kf = (ql[k] - self.ref_q) % n4
            at_ref = kf == (n4 - 1 if dl == 3 else dl)
            self.zp = int((self.win == 1 and self.ref_q < n4 and at_ref)
                          or (self.zp == 1 and pq == pq_d))
            self.pins = pins
            pins_pend.append((tk + 10, pins, self.zp))
            out["ref_count"][k] = self.ref_count
            out["homed"][k] = self.homed
            out["pos_valid"][k] = self.pos_valid
            out["abs_valid"][k] = self.dc.abs_valid
            out["abs_count"][k] = self.dc.abs_count
        return out
