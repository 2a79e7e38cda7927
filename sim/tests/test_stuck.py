"""The stuck-channel check on coarse converters (sim/model/monitor.py, stuck_span()):
slow scans digitised with 8, 10 and 12 bits raise no stuck flag once MONITOR.code_step
tells the core the converter's resolution (without it the 8- and 10-bit scans do); a
channel that dies still raises it, within the distance the check allows. The RTL equals
the model on such a scan: test_rtlsim.py::test_coarse_adc_scan_equals_model."""
import numpy as np
import pytest

from sim import siggen
from sim.model import finequad_core as core
from sim.model.monitor import STUCK_SPAN_MIN, stuck_span, worst_motion

FS, PITCH = 1e6, 4e-6                 # 1 MS/s, a 4 um scale


def coarse_scan(bits, amp, v, n, seed=1, noise=0.0005):
    """Codes of an ADC with `bits` bits on the 16-bit port (shifted left), a scan at v m/s."""
    sig = siggen.Signal(A1=amp, A2=0.9 * amp, m1=0.01, m2=-0.01, noise=noise, adc_bits=bits)
    u1, u2, a = siggen.encode(siggen.constant_speed(n, FS, v), PITCH, sig, seed)
    return u1 << (16 - bits), u2 << (16 - bits), a


def stuck_flags(u1, u2, code_step):
    r = core.run(u1, u2, core.Config(code_step=code_step))
    return (r["fault"] >> core.FAULT_BITS["stuck"]) & 1


@pytest.mark.parametrize("bits", [8, 10, 12])
@pytest.mark.parametrize("amp", [0.6, 0.25])
@pytest.mark.parametrize("v", [0.5e-3, 5e-3])
def test_coarse_slow_scan_raises_no_stuck_flag(bits, amp, v):
    """Five signal periods at 0.5 mm/s (8000 samples per period) or 50 at 5 mm/s, with
    little noise (the codes do not dither): no sample is flagged stuck."""
    u1, u2, _ = coarse_scan(bits, amp, v, 40000)
    st = stuck_flags(u1, u2, 16 - bits)
    assert not st.any(), f"{int(st.sum())} samples flagged stuck, first {np.flatnonzero(st)[:5]}"


@pytest.mark.parametrize("bits,amp", [(8, 0.6), (8, 0.25), (10, 0.25)])
def test_without_the_code_step_the_coarse_scan_is_flagged(bits, amp):
    """The same scans with MONITOR.code_step = 0 (the port's resolution assumed): the
    check fires at the channels' peaks, so the test above can fail."""
    u1, u2, _ = coarse_scan(bits, amp, 0.5e-3, 40000)
    assert stuck_flags(u1, u2, 0).sum() > 100


@pytest.mark.parametrize("bits", [8, 12, 16])
@pytest.mark.parametrize("chan", [0, 1])
def test_dead_channel_is_caught_within_its_span(bits, chan):
    """A channel freezes at its code of sample 20 000 while the stage moves on at 5 mm/s
    (800 samples per period): the stuck flag rises within the worst-case motion for its
    span (worst_motion()) plus STUCK_N samples, and stays up for 90 % of the rest (a
    noisy frozen code may still toggle). With 16 bits the span is STUCK_SPAN_MIN, the
    distance the check has always had; with 12 bits within 10 % of it."""
    n, k0 = 30000, 20000
    u1, u2, a = coarse_scan(bits, 0.6, 5e-3, n, noise=0.005)
    u = (u1, u2)[chan]
    u[k0:] = u[k0]
    st = stuck_flags(u1, u2, 16 - bits)
    assert not st[:k0].any()
    hit = np.flatnonzero(st[k0:])
    assert hit.size, "the dead channel was never flagged"
    first = k0 + int(hit[0])
    # the span the sample at k0 stores (after calibration: c ~ 2^27 / (A 32768))
    c = round(2 ** 27 / ((0.6 if chan == 0 else 0.54) * 32768))
    span = stuck_span(c, 16 - bits)
    if bits == 16:
        assert span == STUCK_SPAN_MIN
    elif bits == 12:
        assert span <= 1.1 * STUCK_SPAN_MIN
    # the most motion in which the other channel moves by the span, then STUCK_N samples
    # (and one more: the snapshot is the sample before the freeze at the latest)
    worst = worst_motion(span / 16384) + (core.Config().stuck_n + 1) * 2 * np.pi / 800
    assert a[first] - a[k0] <= worst, \
        f"flagged after {np.degrees(a[first] - a[k0]):.0f} deg of motion"
    assert st[first:].mean() > 0.9, "the flag does not stay up while the channel is dead"
