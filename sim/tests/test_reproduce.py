"""scripts/reproduce.py --quick: every figure and the JSON / Markdown outputs are written,
with the keys and numbers the issue asks for; bad arguments are rejected."""
import json
import math
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "reproduce.py"
FIGURES = ["fig02_measured", "fig03_parameters", "fig04_corrected", "fig05_interp_n25",
           "fig06_index", "fig07_pulses", "fig09_interp_n50", "fig10_interp_n100",
           "fig11_validation", "fig12_tracking", "limits_speed", "limits_noise"]


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    d = tmp_path_factory.mktemp("reproduce")
    p = subprocess.run([sys.executable, str(SCRIPT), "--quick", "--build", str(d)],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    return d, p.stdout


def test_every_figure_is_a_png(quick):
    d, _ = quick
    for name in FIGURES:
        f = d / f"{name}.png"
        assert f.is_file(), name
        head = f.read_bytes()[:8]
        assert head == b"\x89PNG\r\n\x1a\n" and f.stat().st_size > 20_000, name


def test_json_holds_the_numbers(quick):
    d, _ = quick
    r = json.loads((d / "reproduce.json").read_text())
    w, i = r["tracking_rms_nm_without"], r["tracking_rms_nm_with"]
    assert math.isfinite(w) and math.isfinite(i) and 0 < i < w
    assert r["tracking_improvement"] == pytest.approx(w / i)
    assert r["paper"]["tracking_rms_nm_without"] == 312.14
    assert r["paper"]["tracking_rms_nm_with"] == 121.53
    # the plant sensitivity: another plant, the same encoder, a different improvement
    (name, ps), = r["plant_sensitivity"].items()
    assert "Coulomb" in name and 0 < ps["with"] < ps["without"]
    assert ps["ratio"] == pytest.approx(ps["without"] / ps["with"])
    assert ps["with"] != pytest.approx(i)
    v = r["validation"]["0.005"]
    for n in ("50", "100"):
        for design in ("default", "paper-literal", "printed"):
            assert math.isfinite(v[n][design]["rms_nm"])
        # the default design is within 1.3x of its floor against the 3 nm reference
        row = v[n]["default"]
        assert row["rms_nm"] < 1.3 * row["floor_vs_ref_nm"]
    # the linear index's error (METHOD.md: 15.7 nm RMS) and the exact table's noise floor
    e = r["fine_phase_err_rms_nm_2mm_s"]
    assert 13 < e["paper"] < 19 and e["exact"] < 5
    kinds = {s["kind"] for s in r["limits_speed"]}
    assert kinds == {"edge", "ab", "phase"}
    assert {x["design"] for x in r["limits_noise"]} == {"default", "paper-literal"}
    assert r["closed_loop"]["loop_hz"] == pytest.approx(1e4)


def test_markdown_table_sits_beside_the_papers_numbers(quick):
    d, out = quick
    md = (d / "reproduce.md").read_text()
    for s in ("| quantity | paper | paper-literal design | default design |", "312.14",
              "121.53", "8.3", "7.2", "2.57x"):
        assert s in md
    assert md.strip() in out


def test_bad_arguments():
    p = subprocess.run([sys.executable, str(SCRIPT), "--jobs", "0"], capture_output=True,
                       text=True)
    assert p.returncode == 2 and "--jobs must be >= 1" in p.stderr
