"""The accuracy suite: named, seeded encoder recordings with their ground truth.

Every scenario is a 4 um pitch scale sampled at 1 MS/s (the paper's slider), with the
paper-like imperfections of siggen.Signal unless it says otherwise. It is scored from the
first sample at which both `settle_s` seconds have passed and the stage has travelled
`settle_periods` signal periods (the settling window, the same for every method), and
`events` lists the samples of sudden parameter changes (convergence is reported after
them).
"""
from dataclasses import dataclass, field, replace

import numpy as np

from . import siggen

PITCH_NM = 4000.0
FS = 1e6
UM, MM = 1e3, 1e6                   # positions are in nm


@dataclass
class Scenario:
    name: str
    title: str
    x: np.ndarray                   # true position, nm, one per sample
    sig: siggen.Signal
    seed: int = 1
    settle_s: float = 0.01
    settle_periods: float = 2.0
    events: list = field(default_factory=list)
    port_bits: int = 0              # the core's ADC port (ADC_W) when wider than the
                                    # converter: codes shifted left, MONITOR.code_step set
    drifts: bool = False            # the signal's parameters change along the record
                                    # (an offline fit of the whole record cannot follow)

    def port(self):
        """(ADC_W, code_step): the core's port width and the converter's code step on it."""
        w = self.port_bits or self.sig.adc_bits
        return w, w - self.sig.adc_bits

    def codes(self):
        """(u1, u2, angle): codes on the core's ADC port and the true angle."""
        u1, u2, a = siggen.encode(self.x, PITCH_NM, self.sig, seed=self.seed)
        sh = self.port()[1]
        return u1 << sh, u2 << sh, a

    def start(self):
        """First scored sample."""
        travel = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(self.x)))])
        k = np.nonzero(travel >= self.settle_periods * PITCH_NM)[0]
        if len(k) == 0:
            raise ValueError(f"scenario {self.name}: never travels {self.settle_periods} "
                             f"signal periods")
        return max(int(k[0]), int(round(self.settle_s * FS)))


def _speed(f_over_fs):
    """Stage speed (nm/s) for a signal frequency f/fs."""
    return f_over_fs * FS * PITCH_NM


def _move(dist, vmax, amax=1e9, jmax=1e11):
    return ("move", dist, vmax, amax, jmax)


def suite():
    """The scenarios of `make bench-accuracy`, in table order."""
    base = siggen.Signal()
    s = []

    x = siggen.constant_speed(200_000, FS, 2 * MM)
    s.append(Scenario("constant", "constant speed 2 mm/s (f = 500 Hz)", x, base, seed=11))

    x = siggen.moves(FS, [("dwell", 0.02), _move(0.5 * MM, 20 * MM), ("dwell", 0.05),
                          _move(-0.3 * MM, 20 * MM), ("dwell", 0.03)])
    s.append(Scenario("s_curve", "jerk-limited moves 0.5 mm / -0.3 mm, 20 mm/s, 1 m/s^2, "
                      "with dwells", x, base, seed=12))

    n = 300_000
    x = siggen.constant_speed(n, FS, 5 * MM)
    k = n // 2
    sig = replace(base,
                  A1=siggen.along(x, 0.60, 0.50),
                  A2=siggen.jump(siggen.along(x, 0.54, 0.50), k, -0.05),
                  m1=siggen.jump(siggen.along(x, 0.03, 0.01), k, 0.03),
                  m2=siggen.along(x, -0.02, 0.0),
                  phi=siggen.jump(siggen.along(x, 0.08, 0.12), k, 0.05))
    s.append(Scenario("drift_jump", "5 mm/s; A1, A2, m1, m2, phi drift along 1.5 mm; at "
                      "0.15 s m1 +3 % FS, A2 -5 % FS, phi +0.05 rad", x, sig, seed=13,
                      events=[k], drifts=True))

    x = siggen.reversals(250_000, FS, 20 * UM, 20.0)
    s.append(Scenario("reversals", "back and forth over 40 um at 20 Hz (2.5 mm/s peak, "
                      "10 reversals)", x, base, seed=14))

    x = siggen.moves(FS, [("dwell", 0.01), _move(1 * MM, 10 * MM), ("dwell", 0.01),
                          _move(-1 * MM, 10 * MM)])
    s.append(Scenario("harmonic3", "1 % third harmonic; moves of 1 mm at 10 mm/s", x,
                      replace(base, h3=0.01), seed=15))

    x = siggen.moves(FS, [("dwell", 0.01), _move(0.6 * MM, 10 * MM), ("dwell", 0.02),
                          _move(-0.4 * MM, 10 * MM), ("dwell", 0.01)])
    s.append(Scenario("adc12_fullscale", "12-bit ADC, A1 0.93 / A2 0.90 of full scale, "
                      "0.1 % noise", x,
                      replace(base, A1=0.93, A2=0.90, m1=0.02, m2=-0.015, phi=0.05,
                              noise=0.001, adc_bits=12), seed=16))

    # coarse converters on a 12-bit port, scanning slowly: a code stays unchanged across
    # a channel's peak for hundreds of samples (the stuck check must know the code step)
    x = siggen.moves(FS, [("dwell", 0.01), _move(0.1 * MM, 0.5 * MM, 0.05 * MM * 1e3),
                          ("dwell", 0.01), _move(-0.05 * MM, 0.5 * MM, 0.05 * MM * 1e3)])
    s.append(Scenario("adc8_slow", "8-bit ADC on a 12-bit port, A1 0.6 / A2 0.54, "
                      "0.1 % noise; moves of 0.1 mm / -0.05 mm at 0.5 mm/s", x,
                      replace(base, noise=0.001, adc_bits=8), seed=22, port_bits=12))
    x = siggen.moves(FS, [("dwell", 0.01), _move(0.2 * MM, 2 * MM, 0.2 * MM * 1e3),
                          ("dwell", 0.01), _move(-0.1 * MM, 2 * MM, 0.2 * MM * 1e3)])
    s.append(Scenario("adc10_slow", "10-bit ADC on a 12-bit port at 30 % of full scale, "
                      "0.1 % noise; moves of 0.2 mm / -0.1 mm at 2 mm/s", x,
                      replace(base, A1=0.30, A2=0.27, m1=0.015, m2=-0.01, noise=0.001,
                              adc_bits=10), seed=23, port_bits=12))

    # slow scans with mixed harmonics (the harmonic table learns on decimated, averaged
    # samples below 16 units/sample: sim/model/harmonic.py), with a reversal
    mixed = dict(h2=0.005, h3=0.01, h5=0.003)
    x = siggen.moves(FS, [("dwell", 0.01), _move(0.3 * MM, 0.5 * MM, 0.05 * MM * 1e3)])
    s.append(Scenario("slow05", "0.5 mm/s scan of 0.3 mm; 2nd 0.5 %, 3rd 1 %, 5th 0.3 % "
                      "harmonic", x, replace(base, **mixed), seed=31))
    x = siggen.moves(FS, [("dwell", 0.01), _move(1.0 * MM, 2 * MM, 0.2 * MM * 1e3),
                          ("dwell", 0.01), _move(-0.6 * MM, 2 * MM, 0.2 * MM * 1e3)])
    s.append(Scenario("slow2", "2 mm/s scans of 1 mm / -0.6 mm; 2nd 0.2 %, 3rd 2 %, 5th "
                      "0.5 % harmonic", x, replace(base, h2=0.002, h3=0.02, h5=0.005),
                      seed=32))
    x = siggen.moves(FS, [("dwell", 0.01), _move(2 * MM, 5 * MM, 0.5 * MM * 1e3),
                          ("dwell", 0.01), _move(-1.5 * MM, 5 * MM, 0.5 * MM * 1e3)])
    s.append(Scenario("slow5", "5 mm/s scans of 2 mm / -1.5 mm; 2nd 1 %, 3rd 0.5 %, 5th "
                      "1 % harmonic", x, replace(base, h2=0.01, h3=0.005, h5=0.01),
                      seed=33))
    # a magnetic ring of 256 signal periods per revolution at 29.3 rpm (125 periods/s,
    # the speed of a 0.5 mm/s scan on a 4 um scale), 0.3 revolution and back by 0.1: the
    # amplitudes and offsets follow the ring's run-out once per revolution
    per_rev = 256
    x = siggen.moves(FS, [("dwell", 0.01), _move(0.3 * per_rev * PITCH_NM, 0.5 * MM,
                                                 0.1 * MM * 1e3),
                          ("dwell", 0.01), _move(-0.1 * per_rev * PITCH_NM, 0.5 * MM,
                                                 0.1 * MM * 1e3)])
    rev = 2 * np.pi * x / (per_rev * PITCH_NM)
    s.append(Scenario("rotary", "magnetic ring, 256 periods/rev, 29.3 rpm, 0.3 rev and back "
                      "0.1 rev; amplitude +-3 % and offsets +-1 % FS once per revolution; "
                      "2nd 0.3 %, 3rd 1.5 %, 5th 0.5 % harmonic", x,
                      replace(base, A1=0.60 * (1 + 0.03 * np.sin(rev)),
                              A2=0.54 * (1 + 0.03 * np.sin(rev + 0.5)),
                              m1=0.03 + 0.01 * np.cos(rev), m2=-0.02 + 0.01 * np.sin(rev),
                              h2=0.003, h3=0.015, h5=0.005), seed=34, drifts=True))

    # a magnetic scale like recorded ones: a 12-bit converter, 1000 samples per period,
    # strong 3rd and 5th harmonics, constant parameters (the online fit against the offline one)
    x = siggen.constant_speed(600_000, FS, _speed(1e-3))
    s.append(Scenario("magnetic12", "magnetic scale: 12-bit ADC, 1000 samples per period, "
                      "A1 0.45 / A2 0.40, offsets 2 % / -1.5 %, phase 0.05 rad, 2nd 0.5 %, "
                      "3rd 2 %, 5th 0.8 % harmonic, 0.2 % noise", x,
                      replace(base, A1=0.45, A2=0.40, m1=0.02, m2=-0.015, phi=0.05,
                              h2=0.005, h3=0.02, h5=0.008, noise=0.002, adc_bits=12),
                      seed=35))

    # a dwell scores its own rounding error (with noise below a count it is fixed), so one
    # dwell's ratio depends on where it falls in its count cell (0.78..1.08 when the
    # record is shifted); six more dwells at random places in their cells average that
    rng = np.random.default_rng(17)
    plan = [("dwell", 0.02), _move(0.2 * MM, 10 * MM), ("dwell", 1.0)]
    for i in range(6):
        plan += [_move((-1) ** (i + 1) * (0.05 * MM + rng.uniform(0, PITCH_NM)), 10 * MM),
                 ("dwell", 0.1)]
    x = siggen.moves(FS, plan)
    s.append(Scenario("standstill", "1 s standstill between moves of 0.2 mm, then six "
                      "0.1 s dwells at random places in their count cells", x, base,
                      seed=17))

    x = siggen.constant_speed(500_000, FS, _speed(1e-5))
    s.append(Scenario("creep", "creep at 40 um/s: 100 000 samples per signal period, "
                      "scored after the first period", x, base, seed=18, settle_s=0.0,
                      settle_periods=1.0))

    x = siggen.constant_speed(1_500_000, FS, _speed(1e-6))
    s.append(Scenario("creep1m", "creep at 4 um/s: 10^6 samples per signal period, "
                      "scored after the first period", x, base, seed=21, settle_s=0.0,
                      settle_periods=1.0))

    x = siggen.constant_speed(200_000, FS, 2 * MM)
    s.append(Scenario("noise2", "2 % noise, constant speed 2 mm/s", x,
                      replace(base, noise=0.02), seed=19))

    x = siggen.constant_speed(100_000, FS, _speed(0.3))
    s.append(Scenario("highspeed", "signal frequency 0.3 fs (1.2 m/s, 300 kHz)", x, base,
                      seed=20))
    return s


def by_name(names=None):
    sc = suite()
    if not names:
        return sc
    known = {x.name: x for x in sc}
    bad = [n for n in names if n not in known]
    if bad:
        raise ValueError(f"unknown scenario(s) {', '.join(bad)}; known: {', '.join(known)}")
    return [known[n] for n in names]
