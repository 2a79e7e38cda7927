"""The tools refuse bad input with one line (what, where, the legal range) and their
documented exit code (2), never a traceback or a hang: each input here once ended in a
traceback, a wrong exit code, or a run that never stopped."""
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
PY = sys.executable


def run(script, *args, timeout=60):
    p = subprocess.run([PY, str(ROOT / "scripts" / script), *map(str, args)],
                       capture_output=True, text=True, timeout=timeout)
    return p


def one_error_line(p, prog):
    assert "Traceback" not in p.stderr, p.stderr
    lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith(f"{prog}: error: "), p.stderr
    return lines[0]


def test_soak_bad_seed_ends_at_once(tmp_path):
    # (a negative seed killed the generator thread, and the run waited for it forever)
    p = run("soak.py", "--samples", "1e4", "--seed", "-1", "--out", tmp_path / "s",
            timeout=30)
    assert p.returncode == 2
    assert "--seed must be 0..4294967295, got -1" in one_error_line(p, "soak")


def test_soak_out_that_is_a_file(tmp_path):
    f = tmp_path / "f"
    f.write_text("x")
    p = run("soak.py", "--samples", "1e4", "--out", f, timeout=30)
    assert p.returncode == 2
    assert f"--out {f}: exists and is not a folder" in one_error_line(p, "soak")
    assert f.read_text() == "x"


def test_demo_bad_seed_and_build_that_is_a_file(tmp_path):
    p = run("demo.py", "--seed", "-1", "--build", tmp_path / "d")
    assert p.returncode == 2
    assert "--seed must be 0..4294967295, got -1" in one_error_line(p, "demo")
    f = tmp_path / "f"
    f.write_text("x")
    p = run("demo.py", "--build", f)
    assert p.returncode == 2
    assert f"--build {f}: exists and is not a folder" in one_error_line(p, "demo")
    assert f.read_text() == "x"


def test_limits_denormal_speed():
    p = run("limits.py", "--pitch", "4", "--fs", "1e6", "--v", "1e-320")
    assert p.returncode == 2
    assert "--v must be 1e-12..10000 m/s, got 1e-320" in one_error_line(p, "limits")


VCD_HEAD = """$timescale 1ps $end
$scope module top $end
$var wire 32 ! data [31:0] $end
$upscope $end
$enddefinitions $end
#0
"""


@pytest.mark.parametrize("args,msg", [
    (["--period-ps", "nan"], "--period-ps must be 0.001..1e12 (a clock period in ps), got nan"),
    (["--period-ps", "0"], "--period-ps must be 0.001..1e12"),
])
def test_vcdcompare_bad_period(tmp_path, args, msg):
    a = tmp_path / "a.vcd"
    a.write_text(VCD_HEAD + "b101 !\n")
    p = run("vcdcompare.py", a, a, *args)
    assert p.returncode == 2 and msg in one_error_line(p, "vcdcompare")


def test_vcdcompare_value_wider_than_its_signal(tmp_path):
    # (a 100 000-bit value of a 32-bit signal made a 'mismatch', exit 1)
    ref = tmp_path / "ref.vcd"
    ref.write_text(VCD_HEAD + "b101 !\n")
    rtl = tmp_path / "rtl.vcd"
    rtl.write_text(VCD_HEAD + "b" + "1" * 100_000 + " !\n")
    p = run("vcdcompare.py", rtl, ref)
    assert p.returncode == 2
    line = one_error_line(p, "vcdcompare")
    assert f"RTL VCD '{rtl}': a value of 100000 bits for 'top.data[31:0]', declared 32 " \
        "bits wide" in line, line
