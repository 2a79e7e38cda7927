"""cocotb model of Digilent's Pmod AD1: two AD7476A sharing CS_N and SCLK, one SDATA each.

Serves a recording (one 12-bit straight-binary code per conversion and channel) with the
data sheet's serial timing (Analog Devices AD7476A/AD7477A/AD7478A, Rev. F, Table 4,
Figures 3 and 4), worst case everywhere, and checks the master's timing:

  CS_N falling        samples the next recording entry and starts a conversion; SDATA
                      leaves three-state and shows the first leading zero t3 = 22 ns later
  SCLK falling k      (k = 1..16) the master reads bit k - 1 at this edge; the line keeps it
                      for t7 = 10 ns (hold, VDD <= 3.3 V), then is undefined until
                      t4 = 40 ns (access time), then shows bit k (DB11 first after the 4
                      zeros); after the 16th falling edge it goes three-state (t8)
  three-state, undefined
                      the model drives a random bit (seeded), so a master that samples at
                      the wrong time reads wrong bits, in Verilator (two-state) too

Violations recorded in ``errors`` (the tests fail on any):
  SCLK not high when CS_N falls; t2 = CS_N falling to the first SCLK falling < 10 ns;
  an SCLK period (falling to falling) < 50 ns (fSCLK > 20 MHz); SCLK high or low
  < 0.4 of the period; CS_N high < t1 = 10 ns; the next CS_N falling less than
  t8 + tQUIET = 36 + 50 ns after the 16th SCLK falling edge (tQUIET counts from the end of
  the bus relinquish, t8 max after that edge); CS_N rising before 16 SCLK falling edges
  (conversion aborted); a 17th falling edge while CS_N is low; a conversion after the
  recording is exhausted.

``cs_fall_ps`` keeps the time of every CS_N falling edge (the sampling instants).
PmodAD1Fast (below) serves the same protocol without the timing checks, for long system
simulations.
"""
import random

import cocotb
from cocotb.triggers import First, Timer
from cocotb.utils import get_sim_time

T1 = 10_000         # ps: minimum CS_N pulse width
T2 = 10_000         # CS_N falling to SCLK falling setup
T3 = 22_000         # CS_N falling to SDATA out of three-state (max)
T4 = 40_000         # data access after SCLK falling (max)
T7 = 10_000         # data hold after SCLK falling (min, VDD <= 3.3 V)
T8 = 36_000         # SCLK falling to three-state (max)
TQUIET = 50_000     # bus relinquish to the next CS_N falling (min)
TSCLK_MIN = 50_000  # fSCLK <= 20 MHz
DUTY_MIN = 0.4


def v(sig):
    return 1 if str(sig.value) == "1" else 0


class PmodAD1Model:
    def __init__(self, cs_n, sclk, sdata1, sdata2, codes1, codes2, seed=1, lead_ones=()):
        self.cs_n, self.sclk = cs_n, sclk
        self.lines = (sdata1, sdata2)
        self.codes = (list(codes1), list(codes2))
        assert len(self.codes[0]) == len(self.codes[1])
        for c in self.codes[0] + self.codes[1]:
            assert 0 <= c <= 0xFFF, c
        self.lead_ones = set(lead_ones)      # conversions whose 2nd leading bit is 1
        self.rng = random.Random(seed)
        self.errors = []
        self.cs_fall_ps = []
        self.k = 0                # SCLK falling edges in this frame
        self.words = (0, 0)
        self.sched = []           # [(time_ps, bit index or None = undefined)]
        self.t_cs_fall = self.t_cs_rise = None
        self.t_fall = self.t_rise = None
        self.t_fall16 = None
        self.period = None
        for ln in self.lines:
            ln.value = self.rng.getrandbits(1)
        self.task = cocotb.start_soon(self._run())

    @property
    def served(self):
        return len(self.cs_fall_ps)

    def _err(self, now, msg):
        self.errors.append(f"{now / 1000:.3f} ns: {msg}")

    def _drive(self, idx):
        for ln, w in zip(self.lines, self.words):
            if idx is None:
                ln.value = self.rng.getrandbits(1)
            else:
                ln.value = (w >> (15 - idx)) & 1

    def _cs_fall(self, now):
        if not v(self.sclk):
            self._err(now, "SCLK low when CS_N falls")
        if self.t_cs_rise is not None and now - self.t_cs_rise < T1:
            self._err(now, f"CS_N high for {(now - self.t_cs_rise) / 1000:.1f} ns < t1")
        if self.t_fall16 is not None and now - self.t_fall16 < T8 + TQUIET:
            self._err(now, f"CS_N falls {(now - self.t_fall16) / 1000:.1f} ns after the "
                           f"16th SCLK falling edge < t8 + tQUIET = 86 ns")
        n = self.served
        if n >= len(self.codes[0]):
            self._err(now, "conversion after the end of the recording")
            self.words = (0x0800, 0x0800)
        else:
            lead = 0x4000 if n in self.lead_ones else 0
            self.words = (self.codes[0][n] | lead, self.codes[1][n] | lead)
        self.cs_fall_ps.append(now)
        self.t_cs_fall = now
        self.k = 0
        self.t_fall = self.t_rise = None
        self.t_fall16 = None
        self._drive(None)
        self.sched = [(now + T3, 0)]

    def _sclk_fall(self, now):
        self.k += 1
        k = self.k
        if k == 1:
            if now - self.t_cs_fall < T2:
                self._err(now, f"t2 = {(now - self.t_cs_fall) / 1000:.1f} ns < 10 ns")
        else:
            per = now - self.t_fall
            if per < TSCLK_MIN:
                self._err(now, f"SCLK period {per / 1000:.1f} ns < 50 ns")
            if self.t_rise is None or self.t_rise <= self.t_fall:
                self._err(now, "SCLK falling without a rising edge")
            else:
                low, high = self.t_rise - self.t_fall, now - self.t_rise
                if min(low, high) < DUTY_MIN * per:
                    self._err(now, f"SCLK low {low / 1000:.1f} / high {high / 1000:.1f} ns "
                                   f"in a {per / 1000:.1f} ns period (< 40 %)")
            self.period = per
        if k > 16:
            self._err(now, f"SCLK falling edge {k} while CS_N is low")
            return
        self.t_fall = now
        # bit k - 1 is read now; undefined from t7, bit k (or three-state) from t4
        self.sched = [(now + T7, None)]
        if k < 16:
            self.sched.append((now + T4, k))
        else:
            self.t_fall16 = now

    def _sclk_rise(self, now):
        if self.t_fall is not None and self.period is not None and \
                now - self.t_fall < DUTY_MIN * self.period and self.k == 16:
            self._err(now, f"SCLK low {(now - self.t_fall) / 1000:.1f} ns after the 16th "
                           f"falling edge (< 40 % of the period)")
        self.t_rise = now

    def _cs_rise(self, now):
        if self.t_cs_fall is None or (self.t_cs_rise is not None
                                      and self.t_cs_rise > self.t_cs_fall):
            return                    # power-up: X -> 1, no frame
        if self.k < 16:
            self._err(now, f"CS_N rises after {self.k} SCLK falling edges (aborted)")
        self.t_cs_rise = now
        self.sched = []
        self._drive(None)

    async def _run(self):
        cs, sclk = self.cs_n, self.sclk
        last_cs, last_sclk = v(cs), v(sclk)
        while True:
            now = get_sim_time(unit="ps")
            trig = [cs.value_change, sclk.value_change]
            if self.sched:
                trig.append(Timer(max(self.sched[0][0] - now, 1), unit="ps"))
            await First(*trig)
            now = get_sim_time(unit="ps")
            while self.sched and self.sched[0][0] <= now:
                self._drive(self.sched.pop(0)[1])
            c, s = v(cs), v(sclk)
            if c != last_cs and not c:
                self._cs_fall(now)
            if s != last_sclk:
                if s:
                    self._sclk_rise(now)
                elif not c:
                    self._sclk_fall(now)
            if c != last_cs and c:
                self._cs_rise(now)
            last_cs, last_sclk = c, s


class PmodAD1Fast:
    """The same two converters without the timing checks, for long system simulations:
    one wake-up per SCLK falling edge (17 per conversion instead of about 67). On each
    falling edge the next bit is driven at once, after the front end has sampled the
    previous one on that clock edge; after the 16th the lines carry random bits. The serial
    timing of the front end with the same parameters is checked by PmodAD1Model in
    cocotb_tests/test_adc_pmod_ad1.py. After the recording, the last entry is served
    again (hold_last) so that the converters keep running while a test reads registers;
    ``served`` counts the conversions, ``cs_fall_ps`` their CS_N falling edges."""

    def __init__(self, cs_n, sclk, sdata1, sdata2, codes1, codes2, seed=1):
        from cocotb.triggers import FallingEdge
        self._fe = FallingEdge
        self.cs_n, self.sclk = cs_n, sclk
        self.lines = (sdata1, sdata2)
        self.codes = (list(codes1), list(codes2))
        self.rng = random.Random(seed)
        self.cs_fall_ps = []
        self.errors = []
        self.task = cocotb.start_soon(self._run())

    @property
    def served(self):
        return len(self.cs_fall_ps)

    async def _run(self):
        l1, l2 = self.lines
        c1, c2 = self.codes
        last = len(c1) - 1
        while True:
            await self._fe(self.cs_n)
            n = min(self.served, last)
            self.cs_fall_ps.append(get_sim_time(unit="ps"))
            w1, w2 = c1[n], c2[n]
            l1.value = 0
            l2.value = 0
            for k in range(1, 17):
                await self._fe(self.sclk)
                if str(self.cs_n.value) != "0":
                    self.errors.append(f"conversion {n}: CS_N rose after {k - 1} edges")
                    break
                if k < 16:
                    l1.value = (w1 >> (15 - k)) & 1
                    l2.value = (w2 >> (15 - k)) & 1
                else:
                    l1.value = self.rng.getrandbits(1)
                    l2.value = self.rng.getrandbits(1)
