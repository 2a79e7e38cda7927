"""The A/B counters that finequad's paced outputs are meant to drive, and a model of the
kind of input filter they have.

A counter that filters its inputs sees a level only once it has held for the filter time
(plus up to one sample of the filter's clock, the phase of the first sample being
random); a level that changes back sooner is lost. In quadrature the shortest level is
one edge separation (the pins step one way and back, or A and B alternate), so the A/B
outputs' minimum edge separation ABGEN.ab_sep / f_clk must be at least `min_sep_ns` of
every counter that is to follow them. A faster setting loses position silently: the
filtered A and B of such a counter never change together, so it raises no quadrature
error. `make limits` and `scripts/fqhost.py` name the counters a setting is too fast for;
rtl/README.md lists them.

The figures are the counters' documented defaults (with the source); the filter model is
written from their description, not from their code.
"""
from dataclasses import dataclass


@dataclass(frozen=True)
class Counter:
    name: str
    setting: str            # the setting the figure is for
    filter_ns: float        # a level must hold this long to be seen
    sample_ns: float        # the filter's sampling period (the uncertainty of its start)
    source: str

    @property
    def min_sep_ns(self):
        """The shortest A/B edge separation the counter follows with certainty."""
        return self.filter_ns + self.sample_ns


COUNTERS = (
    Counter("Mesa hostmot2 encoder (LinuxCNC)", "filter on (the driver's default)",
            15 * 40.0, 40.0, "LinuxCNC hostmot2(9), encoder parameter 'filter': a change "
            "must hold for 15 samples of the encoder's 25 MHz sample clock"),
    Counter("Mesa hostmot2 encoder (LinuxCNC)", "filter off", 3 * 40.0, 40.0,
            "LinuxCNC hostmot2(9), encoder parameter 'filter' = 0: 3 samples"),
    Counter("Beckhoff EL5101", "input filter on (0x8010:08 = 0)", 2400.0, 0.0,
            "Beckhoff EL5101 documentation, index 0x8010:08: with the filter an edge must be "
            "present for at least 2.4 us (the filter is off by default)"),
)


def too_fast(sep_ns, counters=COUNTERS):
    """The counters that cannot follow A/B edges sep_ns apart."""
    return [c for c in counters if sep_ns < c.min_sep_ns]


class IntegratingFilter:
    """One input of a filtering counter: an up/down integrator clocked at the sample
    rate, counting towards the input level and saturating at 0 and `depth`; the output
    changes to 1 when the integrator reaches `depth`, to 0 when it reaches 0. With depth
    15 a level must hold for 15 samples to pass (hostmot2's default)."""

    def __init__(self, depth, level=1):
        self.depth = depth
        self.acc = depth if level else 0
        self.out = level

    def sample(self, v):
        if v:
            self.acc = min(self.acc + 1, self.depth)
        else:
            self.acc = max(self.acc - 1, 0)
        if self.acc == self.depth:
            self.out = 1
        elif self.acc == 0:
            self.out = 0
        return self.out


class FilteringCounter:
    """A quadrature counter behind two integrating filters, sampling its inputs every
    `sample_ns` from `phase_ns`: x4 counting of the filtered A, B (the order (1,1),
    (0,1), (0,0), (1,0) counts up); a step where both filtered inputs change is a
    quadrature error, not counted."""
    QUAD = {(1, 1): 0, (0, 1): 1, (0, 0): 2, (1, 0): 3}

    def __init__(self, depth, sample_ns, phase_ns=0.0, a=1, b=1):
        self.fa = IntegratingFilter(depth, a)
        self.fb = IntegratingFilter(depth, b)
        self.sample_ns = sample_ns
        self.next_ns = phase_ns
        self.q = self.QUAD[(a, b)]
        self.count = 0
        self.errors = 0

    def run(self, times_ns, a, b):
        """Pins (a[i], b[i]) from time times_ns[i] until times_ns[i + 1] (increasing);
        samples every sample period up to the last time."""
        i = 0
        n = len(times_ns)
        end = times_ns[-1]
        while self.next_ns <= end:
            while i + 1 < n and times_ns[i + 1] <= self.next_ns:
                i += 1
            q = self.QUAD[(self.fa.sample(a[i]), self.fb.sample(b[i]))]
            d = (q - self.q) & 3
            if d == 1:
                self.count += 1
            elif d == 3:
                self.count -= 1
            elif d == 2:
                self.errors += 1
            self.q = q
            self.next_ns += self.sample_ns
        return self.count
