"""scripts/report_multi.py (`make report-multi`): its builds, cell counting, the update rate
and the table, on fixtures and the model (no synthesis: the flow is scripts/reporting's)."""
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import builds  # noqa: E402
import report_multi as rm  # noqa: E402
from sim.model import estimator

# the window of the multi-axis builds (rtl/builds.toml [up5k_multi], [ecp5_multi])
TDM_W = builds.build("up5k_multi")["params"]["TDM_W"]


def test_cell_counts_of_the_flattened_top():
    net = {"modules": {
        "top_report_multi": {"attributes": {"top": "00000000000000000000000000000001"},
                             "cells": {"a": {"type": "SB_LUT4"}, "b": {"type": "SB_LUT4"},
                                       "c": {"type": "SB_DFFE"}, "d": {"type": "SB_MAC16"},
                                       "e": {"type": "SB_RAM40_4K"},
                                       "f": {"type": "SB_CARRY"}}}}}
    assert rm.cell_counts(net, "ice40_up5k") == {"lut4": 2, "ff": 1, "dsp": 1, "bram": 1,
                                                 "carry": 1}


@pytest.mark.parametrize("lanes", [1, 2])
@pytest.mark.parametrize("axes", [1, 2, 4])
def test_update_rate_is_one_per_window_round(axes, lanes):
    """With the device's engine lanes (the ECP5 build has two): its program length and
    its window L."""
    r = rm.update_rate(axes, {"ENGINE_LANES": lanes}, TDM_W, n=6000)
    if axes == 1:
        # back to back: an UPDATE every CYCLES[update] + 1 clocks; with two lanes the
        # short run's measured stretch also holds the hand-over's EXTRACT (one gap of 149
        # clocks among those of 87)
        from sim.model.rls_engine import CYCLES_BY_LANES
        top = 1 / (CYCLES_BY_LANES[lanes]["update"] + 1)
        if lanes == 1:
            assert r == pytest.approx(top)
        else:
            assert 0.97 * top < r <= top
    else:
        assert r == pytest.approx(1 / (axes * estimator.tdm_period(TDM_W, lanes)))


def test_model_config_of_the_device_builds():
    """The model runs what each device builds (rtl/builds.toml: the multi-axis builds
    take the report builds' core parameters)."""
    assert rm.model_config(builds.build("ecp5_multi")["params"]) == {"ENGINE_LANES": 2}
    assert rm.model_config(builds.build("up5k_multi")["params"]) == {
        "OPT_HARMONIC": 0, "OPT_MONITOR": 0, "OPT_JUMP": 0}


def test_multi_builds_are_the_report_builds_with_a_window():
    """Each device's multi-axis build is its report build's parameters on top_report_multi
    with the window TDM_W, and the axes make report-multi measures."""
    for dev in rm.DEVICES:
        b = builds.build(rm.multi_build(dev))
        base = builds.build(rm.DEVICES[dev]["build"])
        assert rm.top(dev) == b["top"] == "top_report_multi"
        assert {k: v for k, v in b["params"].items() if k != "TDM_W"} == base["params"]
        assert rm.tdm_w(dev) == TDM_W and b["axes"] == [1, 2, 4]
        assert rm.sources(rm.top(dev))[:2] == ["rtl/boards/top_report_multi.v",
                                              "rtl/finequad_multi.v"]


def test_markdown_rows():
    rep = {"seed": 1,
           "runs": [
               {"device": "ice40_up5k", "axes": 1, "fits": False, "tdm_l": 259,
                "updates_per_clock": 1 / 128,
                "util": {"luts": [7000, 5280], "ffs": [2600, 5280], "dsps": [8, 8],
                         "brams": [27, 30]},
                "synth_cells": {"lut4": 6000, "carry": 900, "ff": 2600, "dsp": 8, "bram": 27}},
               {"device": "ecp5_25f", "axes": 2, "fits": True, "fmax_mhz": 70.0,
                "tdm_l": 259, "updates_per_clock": 1 / 518,
                "util": {"luts": [11000, 24288], "ffs": [5000, 24288], "dsps": [14, 28],
                         "brams": [18, 56]},
                "synth_cells": {"lut4": 10000, "ff": 5000, "dsp": 14, "bram": 18}},
               {"device": "ice40_up5k", "axes": 2, "pack_error": "ERROR: x", "fits": False,
                "tdm_l": 259, "updates_per_clock": 1 / 518,
                "synth_cells": {"lut4": 12000}}]}
    md = rm.markdown(rep).splitlines()
    assert len(md) == 5
    assert "7000 / 5280 (132.6 %)" in md[2] and "| no |" in md[2] and "| - |" in md[2]
    assert "| 259 |" in md[3] and "| 70.0 |" in md[3] and "135.1 k (69.5 k)" in md[3]
    assert "no (pack failed)" in md[4]
