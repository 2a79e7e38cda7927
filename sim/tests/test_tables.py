"""The harmonic bin lookup of rtl/hbin.v (tables.bin_buckets, rtl/tables/hbin.vh)
against the bin it stands for, for every value of the ratio scale t it sees."""
import pytest

from sim.model import tables


@pytest.mark.parametrize("kind", tables.KINDS)
def test_bin_buckets_give_floor_and_ceil_of_the_phase_bin(kind):
    """For every t (exact: floor(p / 2**15), 0..4095 with 4095 where j clips; paper: 2 j),
    count + ((t & 255) >= inside) of t's bucket equals floor(PH[j] / 128) (LO set, neg = 0)
    and ceil(PH[j] / 128) (HI set, neg = 1), j = min(2047, (t + 1) >> 1)."""
    ph = tables.phase_table(kind)
    lo, hi = tables.bin_thresholds(kind)
    ts = range(4096) if kind == "exact" else range(0, 4096, 2)
    for thr, want in ((lo, lambda v: v // 128), (hi, lambda v: -(-v // 128))):
        bk = tables.bin_buckets(thr)
        assert len(bk) == 16
        for t in ts:
            j = min(tables.ROWS - 1, (t + 1) >> 1)
            n, inside = bk[t >> 8]
            assert n + ((t & 255) >= inside) == want(ph[j]), (kind, t, j)


def test_bin_buckets_hold_at_most_one_threshold_each():
    for kind in tables.KINDS:
        for thr in tables.bin_thresholds(kind):
            for n, inside in tables.bin_buckets(thr):
                assert 0 <= n <= 15 and 0 <= inside <= 256


@pytest.mark.parametrize("sin_w", tables.EQ12_K_SIN_W)
def test_eq12_k_table(sin_w):
    """The contract rtl/pulse.v's address form relies on (sim/formal/pulse.sby prf_a
    assumes it): for every row E >= 1 and every sine-table address k, T[k] >= E <=>
    k >= K[E], and T[k] = 0 <=> k < K[1]; rows beyond the table (E >= 2**(SIN_W-1)) are
    reached by no k."""
    import numpy as np

    t = np.array(tables.sine_table(sin_w))
    kt = np.array(tables.eq12_k_table(sin_w))
    assert len(kt) == 1 << (sin_w - 1) and kt[0] == 0
    assert t.max() < len(kt)
    k = np.arange(len(t))
    e = np.arange(1, len(kt))[:, None]
    assert np.array_equal(t[None, :] >= e, k[None, :] >= kt[1:, None])
    assert np.array_equal(t == 0, k < kt[1])
    assert kt.max() <= len(t) < 1 << tables.EQ12_K_W


def test_eq12_k_table_refuses_a_wide_sine():
    with pytest.raises(ValueError, match="SIN_W must be one of"):
        tables.eq12_k_table(16)


@pytest.mark.parametrize("sin_w", [8, 10, 12, 16])
def test_sine_table_file_is_the_rounded_quarter_wave(sin_w):
    """rtl/tables/sine_<W>.hex (what the RTL reads, and the model through the same
    generator) against the formula in numpy: T[k] = round(A sin((k + 1/2) pi / 4096)),
    A = 2**(W-1) - 1, to within half an LSB, so a wrong rounding or offset of the
    generator cannot pass as RTL == model."""
    import pathlib
    import numpy as np
    path = pathlib.Path(__file__).resolve().parents[2] / "rtl" / "tables" / f"sine_{sin_w}.hex"
    t = np.array([int(w, 16) for w in path.read_text().split()], dtype=float)
    amp = 2 ** (sin_w - 1) - 1
    exact = amp * np.sin((np.arange(2048) + 0.5) * np.pi / 4096)
    assert len(t) == 2048
    assert np.abs(t - exact).max() <= 0.5 + 1e-9
