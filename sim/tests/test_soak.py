"""scripts/soak.py: the parameter walk's envelope, and a short run through the RTL harness
(the 10^8-sample run is `make soak`, outside the tests)."""
import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import soak  # noqa: E402

HARNESS = ROOT / "build" / "rtlsim_exact_adc16" / "Vfinequad_core"


def test_the_walk_stays_inside_the_interface_envelope():
    p = soak.Params(np.random.default_rng(3))
    seen = []
    for i in range(3000):
        p.walk()
        if i % 50 == 0:
            p.jump()
        v = p.v
        seen.append(v["A2"] / v["A1"])
        r = v["A2"] / v["A1"]
        assert 0.3 <= v["A1"] <= 0.85 and 0.8 - 1e-12 <= r <= 1.25 + 1e-12
        assert abs(v["m1"]) <= 0.065 * v["A1"] + 1e-12
        assert abs(v["m2"]) <= 0.065 * v["A2"] + 1e-12
        assert abs(v["phi"]) <= 0.17 and 0 <= v["h3"] <= 0.01
        assert 0.002 <= v["noise"] <= 0.02
    assert min(seen) < 0.85 and max(seen) > 1.2          # it does wander


def test_a_jump_steps_m1_a2_and_phi_at_once():
    p = soak.Params(np.random.default_rng(4))
    before = p.v
    sig = p.signal(1000, jump_at=400)
    after = p.v
    for k in ("m1", "A2", "phi"):
        arr = np.asarray(getattr(sig, k))
        assert arr[0] == pytest.approx(before[k]) and arr[-1] == pytest.approx(after[k])
        assert np.count_nonzero(np.diff(arr)) == 1 and np.diff(arr)[399] != 0
    assert after["m1"] > before["m1"] and after["A2"] < before["A2"]


@pytest.mark.skipif(not HARNESS.exists(), reason="make harnesses first")
def test_short_soak_through_the_rtl(tmp_path):
    p = subprocess.run([sys.executable, str(ROOT / "scripts" / "soak.py"), "--samples", "2e5",
                        "--out", str(tmp_path), "--harness", str(HARNESS)],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stdout + p.stderr
    st = json.loads((tmp_path / "soak.json").read_text())
    assert st["samples"] >= 200_000 and st["slips"] == 0
    assert st["regs"]["UPDATES"] > 0 and st["max_err_nm"] < 100
    assert st["history"][0]["kind"] == "move"
    p = subprocess.run([sys.executable, str(ROOT / "scripts" / "soak.py"), "--samples", "10",
                        "--out", str(tmp_path)], capture_output=True, text=True)
    assert p.returncode != 0 and "--samples must be at least 10000" in p.stderr
    for bad in ("nan", "inf"):                  # (a traceback and an orphan harness before)
        p = subprocess.run([sys.executable, str(ROOT / "scripts" / "soak.py"), "--samples", bad,
                            "--out", str(tmp_path)], capture_output=True, text=True)
        assert p.returncode != 0 and "--samples must be at least 10000" in p.stderr, p.stderr
