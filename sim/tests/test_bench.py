"""scripts/bench_accuracy.py end to end on one scenario, bit-true model only (the RTL side
is `make bench-accuracy`; RTL == model is checked in sim/tests/test_rtlsim.py)."""
import json
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]


def bench(*args):
    return subprocess.run([sys.executable, str(ROOT / "scripts" / "bench_accuracy.py"),
                           *args], capture_output=True, text=True)


def test_bench_scores_every_method_and_writes_the_tables(tmp_path):
    p = bench("--no-rtl", "--only", "constant", "--build", str(tmp_path))
    assert p.returncode == 0, p.stderr
    r = json.loads((tmp_path / "accuracy.json").read_text())
    (row,) = r["scenarios"]
    assert row["scenario"] == "constant" and row["rtl_equals_model"] is None
    for m in ("rtl", "float", "paper_table", "paper", "heydemann", "raw"):
        s = row[m]
        assert s["floor_nm"] == row["rtl"]["floor_nm"] and s["rms_nm"] > 0, m
    assert row["rtl"]["ratio"] < 1.15 and row["rtl"]["slips"] == 0
    assert row["rtl"]["convergence_samples"][0] is not None
    # the paper's table counting the fine phase: its linearisation error, no lost counts;
    # the method as printed: lost counts (illegal steps) at n = 100 with 0.5 % noise
    assert 2 < row["paper_table"]["ratio"] < 6 and row["paper_table"]["slips"] == 0
    assert row["paper_illegal_steps"] > 0 and row["paper"]["slips"] > 0
    md = (tmp_path / "accuracy.md").read_text()
    assert "| constant | " in md and "paper table, fine-phase count" in md


def test_bench_fails_a_scenario_over_the_target(tmp_path):
    p = bench("--no-rtl", "--only", "constant", "--build", str(tmp_path), "--target", "1.0")
    assert p.returncode == 1 and "over 1.0x the floor or slipping: constant" in p.stderr, p.stderr
    assert (tmp_path / "accuracy.json").exists()          # the tables are still written


def test_bench_fails_a_constant_scenario_behind_the_offline_fit(tmp_path):
    """constant is within 2 % of the offline fit (its parameters are constant); with the
    bound at 0.9 it fails, and the table marks it."""
    p = bench("--no-rtl", "--only", "constant", "--build", str(tmp_path), "--offline", "0.9")
    assert p.returncode == 1 and "over 0.9x the offline fit's RMS with constant parameters: " \
        "constant" in p.stderr, p.stderr
    row = json.loads((tmp_path / "accuracy.json").read_text())["scenarios"][0]
    assert row["drifts"] is False and 0.9 < row["rtl_over_offline"] <= 1.02
    assert "**over**" in (tmp_path / "accuracy.md").read_text()


def test_bench_rejects_bad_arguments(tmp_path):
    p = bench("--no-rtl", "--only", "nosuch", "--build", str(tmp_path))
    assert p.returncode == 2 and "nosuch" in p.stderr
    p = bench("--interp", "600", "--build", str(tmp_path))
    assert p.returncode == 2 and "--interp must be 1..511" in p.stderr
    for bad in ("0", "-1", "nan"):
        for opt in ("--target", "--offline"):
            p = bench(opt, bad, "--build", str(tmp_path))
            assert p.returncode == 2 and f"{opt} must be a ratio > 0" in p.stderr, (opt, bad)


def test_publish_takes_the_whole_suite_of_the_verilog_or_vhdl_edition(tmp_path):
    for extra in (("--only", "constant"), ("--edition", "vhdl-synth"), ("--no-rtl",)):
        p = bench("--publish", "--build", str(tmp_path), *extra)
        assert p.returncode == 2 and "--publish records the whole suite" in p.stderr, extra
    assert not list(tmp_path.iterdir())                   # nothing was run or written


def test_only_a_whole_run_at_the_defaults_is_published_or_compared():
    import argparse
    sys.path.insert(0, str(ROOT / "scripts"))
    import bench_accuracy as b
    from sim.model import finequad_core as core
    whole = dict(only=None, no_rtl=False, interp=core.Config().interp, target=b.TARGET,
                 offline=b.OFFLINE)
    assert b.not_whole(argparse.Namespace(**whole)) is None
    for k, v, why in (("only", ["constant"], "--only"), ("no_rtl", True, "--no-rtl"),
                      ("interp", 50, "--interp"), ("target", 1.0, "--target"),
                      ("offline", 0.9, "--offline")):
        assert b.not_whole(argparse.Namespace(**dict(whole, **{k: v}))) == why, k


def test_a_kept_ghdl_run_is_used_again_only_while_nothing_it_depends_on_changed(
        tmp_path, monkeypatch):
    import shutil
    if shutil.which("ghdl") is None:
        import pytest
        pytest.skip("ghdl not installed")
    sys.path.insert(0, str(ROOT / "scripts"))
    import bench_accuracy as b
    dep = tmp_path / "dep.vhd"                    # stands in for a file of the edition
    dep.write_text("a")
    monkeypatch.setattr(b, "RUN_INPUTS", b.RUN_INPUTS + (str(dep),))
    (tmp_path / "in.csv").write_text("u1,u2\n1,2\n")
    cmd = b.rtl_cmd(tmp_path / "in.csv", tmp_path / "rtl.csv", 100, 16, 0, "vhdl")
    key = b.run_key(tmp_path, cmd)
    assert b.run_key(tmp_path, b.rtl_cmd(tmp_path / "in.csv", tmp_path / "x" / "o.csv", 100,
                                         16, 0, "vhdl")) == key     # (where it ran: not)
    assert b.run_key(tmp_path, b.rtl_cmd(tmp_path / "in.csv", tmp_path / "rtl.csv", 50, 16,
                                         0, "vhdl")) != key         # another setting
    dep.write_text("b")
    assert b.run_key(tmp_path, cmd) != key                          # the VHDL changed
    dep.write_text("a")
    assert b.run_key(tmp_path, cmd) == key
    (tmp_path / "in.csv").write_text("u1,u2\n1,3\n")
    assert b.run_key(tmp_path, cmd) != key                          # the recording
