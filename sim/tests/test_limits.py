"""scripts/limits.py: Eq. 13, the A/B edge rate and Nyquist."""
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import limits  # noqa: E402


def test_papers_example_and_round_trip():
    # the example: 4 um, n = 100, 1 MS/s -> the edge counter fails above 1 cm/s
    r = limits.limits(4, 1e6, ab_sep=4, interp=100)
    assert r["edge_counter_v_max"] == pytest.approx(0.01)
    assert r["counter_v_max"] == pytest.approx(1.5) and r["nyquist_v"] == pytest.approx(2.0)
    # A/B: 36 MHz / 4 clocks = 9 M edges/s = 4 n v / pitch
    assert r["ab_v_max"] == pytest.approx(9e6 * 4e-6 / 400)
    back = limits.limits(4, 1e6, ab_sep=4, v=r["ab_v_max"])
    assert back["ab_n_max"] == pytest.approx(100)
    assert back["edge_counter_n_max"] == pytest.approx(100 * 0.01 / r["ab_v_max"])


def run(*args):
    return subprocess.run([sys.executable, str(ROOT / "scripts" / "limits.py"), *args],
                          capture_output=True, text=True)


def test_cli_prints_the_limits_and_rejects_bad_input():
    p = run("--pitch", "4", "--fs", "1e6", "--v", "0.01")
    assert p.returncode == 0 and "highest n for the paper's edge counter 100," in p.stdout
    p = run("--pitch", "4", "--fs", "1e6", "--interp", "100")
    assert p.returncode == 0 and "loses counts above 0.01 m/s" in p.stdout
    # n above the core's 511 is reported as 511, with the physical limit beside it
    p = run("--pitch", "4", "--fs", "1e6", "--v", "0.001", "--ab-sep", "4")
    assert p.returncode == 0 and "for the A/B outputs 511 (the core's largest; the limit is 9000)" in p.stdout
    p = run("--pitch", "4", "--fs", "1e6", "--interp", "512")
    assert p.returncode == 2 and "--interp must be 1..511" in p.stderr
    p = run("--pitch", "-4", "--fs", "1e6")
    assert p.returncode == 2 and "--pitch must be 0.001..100000 um, got -4.0" in p.stderr
    p = run("--pitch", "4", "--fs", "1e9")
    assert p.returncode == 2 and "cannot exceed --fclk" in p.stderr
    p = run("--pitch", "nan", "--fs", "1e6")
    assert p.returncode == 2 and "--pitch must be 0.001..100000 um, got nan" in p.stderr
    p = run("--pitch", "4", "--fs", "inf")
    assert p.returncode == 2 and "--fs must be 1..1e+10 Hz, got inf" in p.stderr
    p = run("--pitch", "4", "--fs", "1e6", "--v", "1e-320")
    assert p.returncode == 2 and "--v must be 1e-12..10000 m/s, got 1e-320" in p.stderr
    assert "Traceback" not in p.stderr
    p = run("--pitch", "4", "--fs", "1e6", "--ab-sep", "256")
    assert p.returncode == 2 and "--ab-sep must be 1..255" in p.stderr


def test_edge_separation_in_ns_and_the_counters():
    """The A/B edge separation in nanoseconds, and which named counters
    (sim/counters.py) can follow it: the reset value at 36 MHz follows LinuxCNC's
    hostmot2 with its default filter; 4 clocks (the earlier default) does not."""
    p = run("--pitch", "4", "--fs", "1e6")
    assert p.returncode == 0 and "A/B edge separation 24 clocks = 667 ns at 36 MHz" in p.stdout
    assert "hostmot2 encoder (LinuxCNC), filter on (the driver's default): needs 640 ns " \
        "between edges: follows" in p.stdout
    p = run("--pitch", "4", "--fs", "1e6", "--ab-sep", "4")
    assert "= 111 ns at 36 MHz" in p.stdout
    assert "filter on (the driver's default): needs 640 ns between edges: CANNOT follow " \
        "(ab_sep >= 24 clocks at this clock)" in p.stdout
    p = run("--pitch", "4", "--fs", "1e6", "--fclk", "100e6")
    assert "= 240 ns at 100 MHz" in p.stdout and "ab_sep >= 64 clocks" in p.stdout


def test_reference_speed_limit():
    """A reference is found while the stage moves less than w / 2 / max(1, ref_filt) per
    sample (sim/tests/test_refmark_model.py measures it on the model), and below the
    counter's overspeed limit."""
    assert limits.limits(4, 1e6, ref_width=0.5, ref_filt=2)["z_v_max"] == pytest.approx(0.5)
    assert limits.limits(4, 1e6, ref_width=0.5, ref_filt=0)["z_v_max"] == pytest.approx(1.0)
    assert limits.limits(4, 1e6, ref_width=1.0, ref_filt=0)["z_v_max"] == pytest.approx(1.5)
