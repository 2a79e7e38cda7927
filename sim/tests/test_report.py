"""scripts/report.py (`make report`) and its parts, scripts/reporting/: parsing and
aggregation, on fixtures and on one real tiny design through Yosys and nextpnr-ice40 (a
few seconds; skipped without the tools)."""
import importlib.util
import json
import pathlib
import re
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import builds  # noqa: E402
from reporting import common, devices, flow, markdown, netlist, timing  # noqa: E402


def test_median_odd_even_unsorted_and_empty():
    assert common.median([31.2, 29.0, 33.5]) == 31.2
    assert common.median([4, 1, 3, 2]) == 2.5
    assert common.median([7]) == 7.0
    with pytest.raises(common.ReportError):
        common.median([])


def _step(kind, cell_from, cell_to, delay, net=None):
    s = {"type": kind, "delay": delay, "from": {"cell": cell_from, "port": "A"},
         "to": {"cell": cell_to, "port": "B"}}
    if net:
        s["net"] = net
    return s


PATH = [
    _step("clk-to-q", "u_core.u_octant.rcp_rom.0.0", "u_core.u_octant.rcp_rom.0.0", 5.61),
    _step("routing", "u_core.u_octant.rcp_rom.0.0", "u_core.u_octant.p_MULT", 1.75, "n1"),
    _step("logic", "u_core.u_octant.p_MULT", "u_core.u_octant.p_MULT", 3.93),
    _step("routing", "u_core.u_octant.p_MULT", "u_core.u_est.u_engine.acc_FF", 1.19, "n2"),
    _step("logic", "u_core.u_est.u_engine.acc_FF", "u_core.u_est.u_engine.acc_FF", 0.5),
    _step("routing", "u_core.u_est.u_engine.acc_FF", "sdo_FF", 0.25, "n3"),
    _step("setup", "sdo_FF", "sdo_FF", 0.1),
]


def _report_json(tmp_path, fmax=None, util=None, paths=None):
    rep = {"utilization": util if util is not None else {
        "ICESTORM_LC": {"used": 4815, "available": 5280},
        "ICESTORM_DSP": {"used": 8, "available": 8},
        "ICESTORM_RAM": {"used": 26, "available": 30}}}
    if fmax is not None:
        rep["fmax"] = {name: {"achieved": f, "constraint": 36} for name, f in fmax.items()}
    if paths is not None:
        rep["critical_paths"] = paths
    p = tmp_path / "rep.json"
    p.write_text(json.dumps(rep))
    return p


def test_parse_pnr_report_takes_the_worst_clock_and_the_reg_to_reg_path(tmp_path):
    p = _report_json(tmp_path, fmax={"clk": 31.22, "clk2": 45.0}, paths=[
        {"from": "<async>", "to": "posedge clk", "path": PATH[:1]},
        {"from": "posedge clk", "to": "posedge clk", "path": PATH},
        {"from": "posedge clk", "to": "<async>", "path": PATH[-2:]}])
    util, fmax, crit = flow.parse_pnr_report(p)
    assert util["ICESTORM_LC"] == (4815, 5280)
    assert fmax == pytest.approx(31.22)
    assert crit is PATH or crit == PATH


def test_parse_pnr_report_skips_packer_nets_and_takes_the_longest_path(tmp_path):
    # nextpnr-ice40 lists its constant net's paths as a clock's, after the real one
    short = PATH[:2] + PATH[-1:]
    p = _report_json(tmp_path, fmax={"clk": 28.3}, paths=[
        {"from": "posedge clk", "to": "posedge clk", "path": short},
        {"from": "posedge clk", "to": "posedge clk", "path": PATH},
        {"from": "posedge $PACKER_GND_NET", "to": "posedge clk", "path": PATH + PATH},
        {"from": "posedge clk", "to": "posedge $PACKER_GND_NET", "path": PATH + PATH}])
    _, _, crit = flow.parse_pnr_report(p)
    assert crit == PATH


def test_parse_pnr_report_pack_only_has_no_fmax(tmp_path):
    util, fmax, crit = flow.parse_pnr_report(_report_json(tmp_path))
    assert fmax is None and crit is None and util["ICESTORM_RAM"] == (26, 30)


@pytest.mark.parametrize("text,msg", [
    (None, "cannot read"),
    ("{not json", "not JSON"),
    ('{"fmax": {}}', "no 'utilization'"),
    ('{"utilization": {"ICESTORM_LC": {"used": 3}}}', "lacks used/available"),
    ('{"utilization": {}, "fmax": {"clk": {"constraint": 36}}}', "no 'achieved'"),
])
def test_parse_pnr_report_rejects_bad_input_clearly(tmp_path, text, msg):
    p = tmp_path / "bad.json"
    if text is not None:
        p.write_text(text)
    with pytest.raises(common.ReportError, match=msg):
        flow.parse_pnr_report(p)


def test_ice40_ffs_from_the_packer_lines():
    log = ("Info: Packing LUT-FFs..\nInfo:     3459 LCs used as LUT4 only\n"
           "Info:     1065 LCs used as LUT4 and DFF\nInfo: Packing non-LUT FFs..\n"
           "Info:     1201 LCs used as DFF only\n")
    assert flow.ice40_ffs_from_log(log) == 2266
    with pytest.raises(common.ReportError, match="DFF"):
        flow.ice40_ffs_from_log("Info: 1065 LCs used as LUT4 and DFF\n")


def test_instance_of_known_prefix_and_fallback():
    inst = ["u_core", "u_core.u_est", "u_core.u_est.u_engine", "u_core.g_harm.u_harmonic"]
    assert timing.instance_of("u_core.u_est.u_engine.acc_FF", inst) == "u_core.u_est.u_engine"
    assert timing.instance_of("u_core.g_harm.u_harmonic.tab.0.0", inst) == \
        "u_core.g_harm.u_harmonic"
    assert timing.instance_of("u_core.r_kappa_SB_DFFESR_Q_10_DFFLC", inst) == "u_core"
    # without the hierarchy: the leading u_*/g_* components; a BRAM's ".0.0" is not one
    assert timing.instance_of("u_core.u_octant.rcp_rom.0.0") == "u_core.u_octant"
    assert timing.instance_of("sdo_FF") == ""


def test_summarise_path_sums_delays_and_attributes_routing_to_the_sink():
    s = timing.summarise_path(PATH)
    assert s["total_ns"] == pytest.approx(5.61 + 1.75 + 3.93 + 1.19 + 0.5 + 0.25 + 0.1)
    assert s["routing_ns"] == pytest.approx(1.75 + 1.19 + 0.25)
    assert s["logic_ns"] == pytest.approx(5.61 + 3.93 + 0.5 + 0.1)
    assert s["logic_levels"] == 2
    assert s["from"] == "u_core.u_octant.rcp_rom.0.0" and s["to"] == "sdo_FF"
    assert [i for i, _ in s["through"]] == ["u_core.u_octant", "u_core.u_est.u_engine",
                                           "top_report"]
    assert s["through"][0][1] == pytest.approx(5.61 + 1.75 + 3.93)
    assert s["through"][1][1] == pytest.approx(1.19 + 0.5)
    with pytest.raises(common.ReportError):
        timing.summarise_path([])


def _netlist():
    one = "00000000000000000000000000000001"
    return {"modules": {
        "top": {"attributes": {"top": one}, "cells": {
            "u_a": {"type": "$paramod$abc\\leaf_a"}, "u_b": {"type": "mid"},
            "ff0": {"type": "SB_DFF"}, "s": {"type": "$scopeinfo"}}},
        "$paramod$abc\\leaf_a": {"attributes": {"hdlname": "leaf_a"}, "cells": {
            "l1": {"type": "SB_LUT4"}, "l2": {"type": "SB_LUT4"}, "c": {"type": "SB_CARRY"},
            "f": {"type": "SB_DFFESR"}, "m": {"type": "SB_MAC16"}}},
        "mid": {"attributes": {}, "cells": {
            "u_c": {"type": "$paramod$abc\\leaf_a"}, "r": {"type": "SB_RAM40_4K"},
            "l": {"type": "SB_LUT4"}, "x": {"type": "SB_WEIRD"}}},
        # a cell library module in the netlist is a leaf, not a submodule
        "SB_LUT4": {"attributes": {"blackbox": one}, "cells": {}},
    }}


def test_hierarchy_breakdown_own_and_inclusive_counts():
    rows = netlist.hierarchy_breakdown(_netlist(), devices.DEVICES["ice40_up5k"]["cells"])
    by = {r["instance"]: r for r in rows}
    assert [r["instance"] for r in rows] == ["top", "u_a", "u_b", "u_b.u_c"]
    assert by["u_a"]["module"] == "leaf_a" and by["u_b.u_c"]["depth"] == 2
    assert by["u_a"]["own"] == {"lut4": 2, "carry": 1, "ff": 1, "dsp": 1}
    assert by["u_b"]["own"] == {"bram": 1, "lut4": 1, "other": 1}
    assert by["u_b"]["total"] == {"bram": 1, "lut4": 3, "other": 1, "carry": 1, "ff": 1,
                                  "dsp": 1}
    assert by["top"]["own"] == {"ff": 1}
    assert by["top"]["total"]["lut4"] == 5 and by["top"]["total"]["ff"] == 3
    bad = _netlist()
    bad["modules"]["mid"]["attributes"]["top"] = "1"
    with pytest.raises(common.ReportError, match="2 top modules"):
        netlist.hierarchy_breakdown(bad, devices.DEVICES["ice40_up5k"]["cells"])


SIM = {"fast_path_samples_per_clock": 1.0, "clocks_per_update": 220.0, "latency_cycles": 8,
       "sim_samples_per_s": 150000}
UTIL_ICE = {"ICESTORM_LC": (4815, 5280), "ICESTORM_DSP": (8, 8), "ICESTORM_RAM": (27, 30)}


def test_each_device_is_measured_with_its_build():
    """The device's build of rtl/builds.toml is what is synthesised (its top and params),
    placed (nextpnr's part and package) and simulated: the probe's finequad_core gets
    every core parameter the build's top hands its finequad_core, and make model the
    build's PROFILE."""
    core = builds.module_params("finequad_core")
    for dev in devices.DEVICES:
        b = builds.build(devices.build_of(dev))
        assert devices.top(dev) == b["top"] == "top_report"
        assert devices.synth_params(dev) == b["params"]
        assert devices.nextpnr(dev)[1:] == builds.nextpnr_device(devices.build_of(dev))
        probe = devices.probe_params(dev)
        for k, v in b["params"].items():
            if k in core:                     # top_report forwards these by name
                assert probe.get(k, core[k][1]) == v, (dev, k)
        assert set(probe) <= set(core) and devices.adc_w(dev) == 16
    assert devices.synth_params("ice40_up5k")["OPT_HARMONIC"] == 0
    assert devices.probe_params("ecp5_25f")["ENGINE_LANES"] == 2
    assert devices.nextpnr("ecp5_25f")[1:] == ["--25k", "--package", "CABGA256"]


def test_entry_has_exactly_the_keys_with_numbers_and_percentages():
    e = devices.entry("ice40_up5k", UTIL_ICE, 2266, True, 31.22, SIM, 36.0, [1, 2, 3])
    assert devices.check_entry(e)
    assert set(devices.KEYS) <= set(e)
    assert e["fmax_mhz"] == 31.22 and e["max_sample_rate_msps"] == 31.22
    assert e["rls_updates_msps"] == pytest.approx(31.22 / 220.0, abs=1e-4)
    assert e["luts"] == 4815 and e["ffs"] == 2266 and e["dsps"] == 8 and e["brams"] == 27
    assert e["percent"] == {"luts": 91.2, "ffs": 42.9, "dsps": 100.0, "brams": 90.0}
    assert json.loads(json.dumps(e)) == e


def test_entry_of_a_design_that_does_not_fit_reaches_no_clock():
    util = dict(UTIL_ICE, ICESTORM_LC=(6008, 5280))
    e = devices.entry("ice40_up5k", util, 2300, False, 31.0, SIM, 36.0, [1], {"fmax_mhz": 31.0})
    assert e["fits"] is False and e["fmax_mhz"] == 0.0
    assert e["max_sample_rate_msps"] == 0.0 and e["rls_updates_msps"] == 0.0
    assert e["percent"]["luts"] == 113.8 and e["placed_variant"]["fmax_mhz"] == 31.0


def test_entry_ecp5_takes_ffs_from_nextpnr_and_rejects_missing_cells():
    util = {"TRELLIS_COMB": (4811, 24288), "TRELLIS_FF": (2513, 24288),
            "MULT18X18D": (9, 28), "DP16KD": (9, 56)}
    e = devices.entry("ecp5_25f", util, None, True, 77.9, SIM, 100.0, [1])
    assert e["ffs"] == 2513 and e["percent"]["dsps"] == 32.1
    del util["DP16KD"]
    with pytest.raises(common.ReportError, match="DP16KD"):
        devices.entry("ecp5_25f", util, None, True, 77.9, SIM, 100.0, [1])


def test_check_entry_rejects_a_missing_or_non_numeric_key():
    e = devices.entry("ice40_up5k", UTIL_ICE, 2266, True, 31.22, SIM, 36.0, [1])
    for k, bad in (("fmax_mhz", None), ("luts", "4815"), ("fits_x", None), ("brams", True)):
        f = dict(e)
        if bad is None:
            f.pop(k, None)
        else:
            f[k] = bad
        if k in devices.KEYS:
            with pytest.raises(common.ReportError, match=k):
                devices.check_entry(f)
        else:
            assert devices.check_entry(f)


def test_targets_met_and_missed():
    e = devices.entry("ice40_up5k", UTIL_ICE, 2266, True, 37.0, SIM, 36.0, [1])
    got = {q: ok for q, _, _, ok in devices.targets_of("ice40_up5k", e)}
    assert got == {"LUTs": False, "Fmax": True, "samples per clock": True,
                   "estimator updates": False, "latency": True, "simulation": False}


ICE40_TOOLS = pytest.mark.skipif(
    not (shutil.which("yosys") and shutil.which("nextpnr-ice40")),
    reason="yosys / nextpnr-ice40 not installed")


def _synth_ice40(folder, verilog, top, dsp=False):
    """Yosys synth_ice40 of `verilog` (written to folder/<top>.v) -> folder/<top>.json."""
    (folder / f"{top}.v").write_text(verilog)
    subprocess.run(["yosys", "-q", "-p", f"read_verilog {top}.v; synth_ice40 "
                    f"{'-dsp ' if dsp else ''}-top {top} -json {top}.json"], cwd=folder,
                   check=True)
    return folder / f"{top}.json"


TINY = """
module tiny (input wire clk, input wire d, output reg [7:0] q = 0);
    always @(posedge clk) q <= {q[6:0], d} + q;
endmodule
"""


@ICE40_TOOLS
def test_real_tiny_design_through_yosys_and_nextpnr(tmp_path):
    _synth_ice40(tmp_path, TINY, "tiny")
    subprocess.run(["nextpnr-ice40", "--up5k", "--package", "sg48", "--json", "tiny.json",
                    "--freq", "50", "--seed", "1", "--report", "rep.json", "-l", "pnr.log",
                    "-q", "--timing-allow-fail", "--sdf", "tiny.sdf"], cwd=tmp_path,
                   check=True)
    util, fmax, crit = flow.parse_pnr_report(tmp_path / "rep.json")
    assert fmax > 50 and util["ICESTORM_LC"][1] == 5280
    assert 8 <= util["ICESTORM_LC"][0] < 40
    assert flow.ice40_ffs_from_log((tmp_path / "pnr.log").read_text()) == 8
    s = timing.summarise_path(crit)
    assert s["total_ns"] == pytest.approx(1000.0 / fmax, rel=0.02)
    assert s["logic_levels"] >= 1 and len(s["through"]) == 1   # no hierarchy: all top
    # the static timing of the SDF finds nextpnr's critical path
    ends = timing.sdf_endpoints((tmp_path / "tiny.sdf").read_text())
    assert ends[0][0] == pytest.approx(1000.0 / fmax, abs=0.005)
    assert ends[0][1].rsplit("/", 1)[0] == s["to"]           # nextpnr's endpoint cell
    over = timing.over_target(tmp_path / "tiny.sdf", 0.5 * ends[0][0])
    longer = [e for e in ends if e[0] > 0.5 * ends[0][0]]
    assert over["endpoints"] == len(longer) >= 1
    assert timing.over_target(tmp_path / "tiny.sdf", ends[0][0])["endpoints"] == 0


def test_summarise_path_names_cells_the_placer_inserted():
    path = [_step("clk-to-q", "u_core.u_est.x_LC", "u_core.u_est.x_LC", 1.0),
            _step("routing", "u_core.u_est.x_LC", "$nextpnr_ICESTORM_LC_0", 0.5, "n"),
            _step("logic", "$nextpnr_ICESTORM_LC_0", "$nextpnr_ICESTORM_LC_0", 0.8)]
    s = timing.summarise_path(path)
    assert s["through"] == [["u_core.u_est", 1.0], ["(nextpnr cell)", 1.3]]
    assert s["steps"][1] == ["routing", 0.5, "$nextpnr_ICESTORM_LC_0"]


HIST = """Info: Slack histogram:
Info:  legend: * represents 20 endpoint(s)
Info:          + represents [1,20) endpoint(s)
Info: [ -5522,  -4006) |+
Info: [ -4006,  -2490) |*+
Info: [ -2490,   -974) |**
Info: [  -974,    542) |***+
Info: [   542,   2058) |***+
"""


def test_failing_endpoints_from_the_last_slack_histogram():
    # fully negative bins: 1..19, 21..39, 40; the bin holding 0 adds 0..79 at most
    assert timing.failing_endpoints("Info: placed\n" + HIST) == (62, 98 + 79)
    older = HIST.replace("|**\n", "|*****\n")
    assert timing.failing_endpoints(older + "Info: routed\n" + HIST) == (62, 177)
    assert timing.failing_endpoints("Info: no timing here\n") is None
    with pytest.raises(common.ReportError, match="legend"):
        timing.failing_endpoints("Slack histogram:\nInfo: [ -1, 2) |*\n")


def test_top_report_lints_clean_against_the_core_with_every_variant():
    """A core port that changes width would be cut silently by the report's top (its logic
    then removed by synthesis): report.py lints first, and so does this test."""
    for params in [{"OPT_NTH_DSP": 0}, {}] + [p for p, _ in devices.VARIANTS]:
        flow.lint_top(params)


def _mac(**params):
    """An SB_MAC16 cell of a Yosys JSON netlist: A and B driven by nets, C and D tied."""
    p = {"A_REG": "0", "B_REG": "0", "TOP_8x8_MULT_REG": "0", "BOT_8x8_MULT_REG": "0",
         "PIPELINE_16x16_MULT_REG1": "0", "PIPELINE_16x16_MULT_REG2": "0",
         "TOPOUTPUT_SELECT": "11", "BOTOUTPUT_SELECT": "11"}
    p.update({k: format(v, "b") for k, v in params.items()})
    conn = {"A": list(range(2, 18)), "B": list(range(18, 34)), "C": ["0"] * 16,
            "D": ["0"] * 16, "O": list(range(100, 132))}
    return {"type": "SB_MAC16", "parameters": p, "connections": conn,
            "port_directions": {"A": "input", "B": "input", "C": "input", "D": "input",
                                "O": "output"}}


def _dsp_rows(cells, read=range(100, 132)):
    """ice40_dsp_modes on one module whose output port reads the O bits `read`."""
    mod = {"cells": cells, "ports": {"o": {"direction": "output", "bits": list(read)}}}
    return {r["cell"]: r["combinational"]
            for r in netlist.ice40_dsp_modes({"modules": {"top": mod}})}


def test_ice40_dsp_modes_names_every_stage_without_a_register():
    cells = {
        "full": _mac(A_REG=1, B_REG=1, TOPOUTPUT_SELECT=1, BOTOUTPUT_SELECT=1),
        "reg2": _mac(A_REG=1, B_REG=1, PIPELINE_16x16_MULT_REG2=1),
        "a_comb": _mac(B_REG=1, TOPOUTPUT_SELECT=1, BOTOUTPUT_SELECT=1),
        "sum": _mac(A_REG=1, B_REG=1, TOP_8x8_MULT_REG=1, BOT_8x8_MULT_REG=1,
                    PIPELINE_16x16_MULT_REG1=1),
        "mixed": _mac(A_REG=1, B_REG=1, BOTOUTPUT_SELECT=1),
        "adder": _mac(TOPOUTPUT_SELECT=0, BOTOUTPUT_SELECT=0),
        "x8": _mac(A_REG=1, B_REG=1, TOPOUTPUT_SELECT=2, BOTOUTPUT_SELECT=2,
                   TOP_8x8_MULT_REG=1),
        "lut": {"type": "SB_LUT4", "parameters": {}, "connections": {}},
    }
    cells["a_const"] = _mac(TOPOUTPUT_SELECT=1, BOTOUTPUT_SELECT=1, B_REG=1)
    cells["a_const"]["connections"]["A"] = ["1"] + ["0"] * 15
    # the octant's form: product + constant through the adder, nothing registered
    cells["madd"] = _mac(TOPOUTPUT_SELECT=0, BOTOUTPUT_SELECT=0, TOPADDSUB_LOWERINPUT=2,
                         BOTADDSUB_LOWERINPUT=2)
    cells["c_in"] = _mac(A_REG=1, B_REG=1, TOPOUTPUT_SELECT=1, BOTOUTPUT_SELECT=1)
    cells["c_in"]["connections"]["C"] = list(range(40, 56))
    assert _dsp_rows(cells) == {
        "full": [], "reg2": [], "a_comb": ["A in"], "a_const": [], "c_in": ["C in"],
        "sum": ["O[31:16] out (product sum)", "O[15:0] out (product sum)"],
        "mixed": ["O[31:16] out (multiplier)"],
        "adder": ["A in", "B in", "O[31:16] out (adder)", "O[15:0] out (adder)"],
        "madd": ["A in", "B in", "O[31:16] out (multiplier+adder)",
                 "O[15:0] out (multiplier+adder)"],
        "x8": ["O[15:0] out (8x8 product)"]}
    # an output half nothing reads is no stage of a path
    assert _dsp_rows({"madd": cells["madd"]}, read=range(116, 129)) == {
        "madd": ["A in", "B in", "O[31:16] out (multiplier+adder)"]}
    bad = _mac()
    bad["parameters"]["A_REG"] = "x"
    with pytest.raises(common.ReportError, match="A_REG"):
        _dsp_rows({"bad": bad})


MULS = """
module mul_reg(input clk, input [15:0] a, input [15:0] b, output reg [31:0] p);
    reg [15:0] ar, br;
    always @(posedge clk) begin ar <= a; br <= b; p <= ar * br; end
endmodule
module mul_comb(input clk, input [15:0] a, input [15:0] b, output reg [31:0] p);
    always @(posedge clk) p <= a * b;
endmodule
"""


# Yosys maps the register behind a product to the block's 8x8 product and 16x16 pipeline
# registers (not the output register): the sum of those partial products reaches O
# without a register
SUM = ["O[31:16] out (product sum)", "O[15:0] out (product sum)"]


@pytest.mark.skipif(shutil.which("yosys") is None, reason="needs yosys")
@pytest.mark.parametrize("top, comb", [("mul_reg", SUM), ("mul_comb", ["A in", "B in"] + SUM)])
def test_ice40_dsp_modes_on_real_yosys_output(tmp_path, top, comb):
    net = _synth_ice40(tmp_path, MULS, top, dsp=True)
    rows = netlist.ice40_dsp_modes(json.loads(net.read_text()))
    assert [r["combinational"] for r in rows] == [comb]


SDF = """(DELAYFILE
  (SDFVERSION "3.0")
  (TIMESCALE 1ps)
  (CELL
    (CELLTYPE "top")
    (INSTANCE )
    (DELAY
      (ABSOLUTE
        (INTERCONNECT u_a.x_SB_DFF_Q_LC/O u_b.g_l\\[0\\].y_LC/I0 (2000:2000:2000) (2000:2000:2000))
        (INTERCONNECT u_a.z_SB_DFF_Q_LC/O u_b.g_l\\[0\\].y_LC/I1 (500:500:500) (500:500:500))
        (INTERCONNECT u_b.g_l\\[0\\].y_LC/O u_c.q_SB_DFFE_Q_LC/I2 (1000:1000:1000) (1000:1000:1000))
        (INTERCONNECT const_LC/O u_c.k_LC/I0 (300:300:300) (300:300:300))
        (INTERCONNECT gbuf/O u_a.x_SB_DFF_Q_LC/CLK (700:700:700) (700:700:700))
        (INTERCONNECT gbuf/O u_a.z_SB_DFF_Q_LC/CLK (700:700:700) (700:700:700))
      )
    )
  )
  (CELL
    (CELLTYPE "ICESTORM_LC")
    (INSTANCE u_a.x_SB_DFF_Q_LC)
    (DELAY (ABSOLUTE (IOPATH CLK O (1400:1400:1400) (1400:1400:1400))))
  )
  (CELL
    (CELLTYPE "ICESTORM_LC")
    (INSTANCE u_a.z_SB_DFF_Q_LC)
    (DELAY (ABSOLUTE (IOPATH CLK O (1400:1400:1400) (1400:1400:1400))))
  )
  (CELL
    (CELLTYPE "ICESTORM_LC")
    (INSTANCE u_b.g_l\\[0\\].y_LC)
    (DELAY (ABSOLUTE
      (IOPATH I0 O (450:450:450) (450:450:450))
      (IOPATH I1 O (600:600:600) (600:600:600))))
  )
  (CELL
    (CELLTYPE "ICESTORM_LC")
    (INSTANCE u_c.q_SB_DFFE_Q_LC)
    (TIMINGCHECK
      (SETUPHOLD (posedge I2) (posedge CLK) (200:200:200) (0:0:0))
      (SETUPHOLD (negedge I2) (posedge CLK) (250:250:250) (0:0:0)))
  )
  (CELL
    (CELLTYPE "ICESTORM_LC")
    (INSTANCE u_c.k_LC)
    (TIMINGCHECK (SETUPHOLD (posedge I0) (posedge CLK) (200:200:200) (0:0:0)))
  )
)
"""


def test_sdf_endpoints_longest_arrival_plus_setup_from_clocked_starts_only():
    ends = timing.sdf_endpoints(SDF)
    # x: 1.4 + 2.0 + 0.45 + 1.0 + 0.25 = 5.1; z: 1.4 + 0.5 + 0.6 + 1.0 + 0.25 = 3.75; the
    # constant's pin has no clocked start
    assert ends == [(5.1, "u_c.q_SB_DFFE_Q_LC/I2", "u_a.x_SB_DFF_Q_LC")]
    cls = timing.path_classes(ends, 5.0, ["u_a", "u_c"])
    assert cls == [{"worst_ns": 5.1, "endpoints": 1, "from": "u_a: x", "to": "u_c: q"}]
    assert timing.path_classes(ends, 5.1, ["u_a", "u_c"]) == []
    with pytest.raises(common.ReportError, match="TIMESCALE"):
        timing.sdf_endpoints(SDF.replace("(TIMESCALE 1ps)", ""))
    assert "error" in timing.over_target(pathlib.Path("/nonexistent.sdf"), 10.0)


def test_sdf_endpoints_rise_fall_negative_setup_constant_clocks_and_errors():
    base = SDF.replace("(450:450:450) (450:450:450)", "(450:450:450) (1450:1450:1450)")
    assert timing.sdf_endpoints(base)[0][0] == 6.1                  # the fall is larger
    neg = SDF.replace("(posedge I2) (posedge CLK) (200:200:200)",
                      "(posedge I2) (posedge CLK) (-50:-50:-50)").replace(
        "(negedge I2) (posedge CLK) (250:250:250)", "(negedge I2) (posedge CLK) (-80:-80:-80)")
    assert timing.sdf_endpoints(neg)[0][0] == 4.8                   # setup -50 ps
    ns = SDF.replace("(TIMESCALE 1ps)", "(TIMESCALE 1 ns)").replace("2000:2000:2000", "2")
    assert timing.sdf_endpoints(ns)[0][0] == 3750.0                # z: 1400 + 500 + 600 + 1000 + 250 ns
    # a flip-flop whose clock pin a constant drives starts nothing
    gnd = SDF.replace("gbuf/O u_a.x_SB_DFF_Q_LC/CLK", "$PACKER_GND/O u_a.x_SB_DFF_Q_LC/CLK")
    assert timing.sdf_endpoints(gnd) == [(3.75, "u_c.q_SB_DFFE_Q_LC/I2", "u_a.z_SB_DFF_Q_LC")]
    # a setup check without an edge on its data pin
    plain = SDF.replace("(SETUPHOLD (posedge I0) (posedge CLK) (200:200:200) (0:0:0))",
                        "(SETUP I0 (posedge CLK) (200:200:200))")
    assert timing.sdf_endpoints(plain) == timing.sdf_endpoints(SDF)
    with pytest.raises(common.ReportError, match="INTERCONNECT"):
        timing.sdf_endpoints(SDF.replace("(1000:1000:1000) (1000:1000:1000)", "(oops)"))
    loop = SDF.replace("u_c.k_LC/I0 (300", "u_b.g_l\\\\[0\\\\].y_LC/I1 (300").replace(
        "(INTERCONNECT const_LC/O", "(INTERCONNECT u_b.g_l\\\\[0\\\\].y_LC/O")
    with pytest.raises(common.ReportError, match="loop"):
        timing.sdf_endpoints(loop)


def test_signal_of_strips_what_synthesis_and_packing_append():
    assert timing.signal_of("u_core.u_correct.zl_o_SB_DFFE_Q_3_D_SB_LUT4_O_LC") == "zl_o"
    assert timing.signal_of("u_core.u_est.cwin_TRELLIS_FF_Q_3") == "cwin"
    assert timing.signal_of("$nextpnr_ICESTORM_LC_27") == "$nextpnr_ICESTORM_LC_27"
    assert timing.signal_of("u_core.u_correct.p12_SB_MAC16_O_DSP") == "p12"
    assert timing.signal_of("u_core.u_lut.g_ph4k.ph_rom.0.1_RAM") == "ph_rom"
    assert timing.signal_of("u_core.u_est.mem.0.14$RAMW_BLOCK1") == "mem"


# ---- constraints/up5k_dsp.py: the UP5K's DSP floorplan (a nextpnr --pre-place script) ----
_fspec = importlib.util.spec_from_file_location("up5k_dsp", ROOT / "constraints" / "up5k_dsp.py")
up5k_dsp = importlib.util.module_from_spec(_fspec)
_fspec.loader.exec_module(up5k_dsp)


class _Cell:
    def __init__(self, type_):
        self.type = type_


def _dsp_cells(*regs, other=(), type_="ICESTORM_DSP"):
    return ([(f"{r}_SB_MAC16_O_DSP", _Cell(type_)) for r in regs]
            + [(n, _Cell("ICESTORM_LC")) for n in other])


def test_floorplan_locks_each_named_block_and_ignores_the_rest():
    regs = ["u_core.u_correct.p1", "u_core.u_correct.p12", "u_core.u_correct.p2",
            "u_core.u_octant.psum", "u_core.u_est.g_int.u_engine.g_lane[0].pp_ll"]
    # (a logic cell named like a block is not one)
    got = up5k_dsp.floorplan(_dsp_cells(*regs, other=["u_core.u_correct.p12_SB_MAC16_O_LC"]))
    assert got == {"u_core.u_correct.p1_SB_MAC16_O_DSP": "X25/Y23/mac16_0",
                   "u_core.u_correct.p12_SB_MAC16_O_DSP": "X25/Y10/mac16_0",
                   "u_core.u_correct.p2_SB_MAC16_O_DSP": "X25/Y15/mac16_0",
                   "u_core.u_octant.psum_SB_MAC16_O_DSP": "X25/Y5/mac16_0"}
    # p1 does not match p12 by prefix; a top without u_core; Yosys's cell type (before
    # nextpnr packs it)
    assert up5k_dsp.floorplan(_dsp_cells("u_correct.p1", "u_correct.p12", "u_correct.p2",
                                         "u_octant.psum", type_="SB_MAC16")
                              )["u_correct.p1_SB_MAC16_O_DSP"] == "X25/Y23/mac16_0"


def test_report_checks_the_floorplan_against_the_netlist(tmp_path):
    """make report: the UP5K's placement script finds its blocks in the synthesised
    netlist, or the report stops with the script's message before nextpnr runs."""
    def netlist(regs):
        cells = {f"u_core.{r}_SB_MAC16_O": {"type": "SB_MAC16"} for r in regs}
        cells["u_core.u_correct.p1_SB_DFF_Q"] = {"type": "SB_DFF"}
        f = tmp_path / "top.json"
        f.write_text(json.dumps({"modules": {"top_report": {"cells": cells}}}))
        return f
    regs = ["u_correct.p1", "u_correct.p12", "u_correct.p2", "u_octant.psum"]
    got = flow.check_preplace("ice40_up5k", netlist(regs))
    assert sorted(got.values()) == sorted(up5k_dsp.FLOORPLAN.values())
    with pytest.raises(common.ReportError, match=r"ice40_up5k: .*top.json: .*u_correct.p2: "
                       r"no DSP blocks"):
        flow.check_preplace("ice40_up5k", netlist(regs[:2] + regs[3:]))
    assert flow.check_preplace("ecp5_25f", tmp_path / "none.json") is None   # no script


def test_floorplan_names_a_block_missing_or_found_twice():
    # (u_xoctant is not u_octant) the blocks the design has are listed
    with pytest.raises(ValueError, match=r"u_octant.psum: no DSP blocks; the design's DSP "
                       r"blocks: u_core.u_correct.p12_SB_MAC16_O_DSP, .*u_xoctant.psum_SB"):
        up5k_dsp.floorplan(_dsp_cells("u_core.u_correct.p1", "u_core.u_correct.p12",
                                      "u_core.u_correct.p2", "u_core.u_xoctant.psum"))
    with pytest.raises(ValueError, match=r"u_correct.p2: 2 DSP blocks \(a.u_correct.p2_SB"):
        up5k_dsp.floorplan(_dsp_cells("a.u_correct.p1", "a.u_correct.p12", "a.u_correct.p2",
                                      "b.u_correct.p2", "a.u_octant.psum"))


def test_floorplan_names_signals_of_the_core():
    """Each entry names a signal declared in the module of its instance (rtl/
    finequad_core.v): a product register (rtl/correct.v) or the octant's rounding sum psum
    (a wire, rtl/octant.v, that Yosys names the block after). A renamed signal or instance
    fails here; `make report` checks the names against the synthesised netlist."""
    core = (ROOT / "rtl" / "finequad_core.v").read_text()
    for key in up5k_dsp.FLOORPLAN:
        inst, reg = key.split(".")
        m = re.search(r"\b(\w+)\s*(?:#\s*\((?:[^()]|\([^()]*\))*\))?\s*" + inst + r"\s*\(", core)
        assert m, f"no instance {inst} in rtl/finequad_core.v"
        src = (ROOT / "rtl" / f"{m.group(1)}.v").read_text()
        assert re.search(r"\b(reg|wire)\b[^;]*\b" + reg + r"\b\s*(=|;|,)", src), \
            f"{reg} is not declared in rtl/{m.group(1)}.v"


# four products under the core's instance names (flattened by synth_ice40, as top_report)
FLOOR_V = """
module prod (input wire clk, input wire signed [15:0] a, b, output reg signed [31:0] p = 0);
    always @(posedge clk) p <= a * b;
endmodule
module cor (input wire clk, input wire signed [15:0] a, b, c, output wire signed [31:0] s);
    reg signed [15:0] aq = 0, bq = 0, cq = 0;
    reg signed [31:0] p1 = 0, p12 = 0, p2 = 0;
    always @(posedge clk) begin
        aq <= a; bq <= b; cq <= c;
        p1 <= aq * bq; p12 <= aq * cq; p2 <= bq * cq;
    end
    assign s = p1 ^ p12 ^ p2;
endmodule
module floor (input wire clk, input wire din, output wire y);    // operands: a shift
    reg [79:0] sr = 0;                                             // register (few pins)
    wire signed [31:0] s, q;
    always @(posedge clk) sr <= {sr[78:0], din};
    cor u_correct (.clk(clk), .a(sr[15:0]), .b(sr[31:16]), .c(sr[47:32]), .s(s));
    oct u_octant (.clk(clk), .a(sr[63:48]), .b(sr[79:64]), .q(q));
    assign y = ^(s ^ q);
endmodule
module oct (input wire clk, input wire signed [15:0] a, b, output wire signed [31:0] q);
    reg signed [15:0] aq = 0, bq = 0;
    reg signed [31:0] psum = 0;
    always @(posedge clk) begin aq <= a; bq <= b; psum <= aq * bq; end
    assign q = psum;
endmodule
"""


@ICE40_TOOLS
def test_floorplan_places_the_blocks_through_nextpnr(tmp_path):
    _synth_ice40(tmp_path, FLOOR_V, "floor", dsp=True)
    pnr = ["nextpnr-ice40", "--up5k", "--package", "sg48", "--json", "floor.json", "-q",
           "--pre-place", str(ROOT / "constraints" / "up5k_dsp.py")]
    subprocess.run(pnr + ["--write", "placed.json"], cwd=tmp_path, check=True,
                   capture_output=True)
    cells = json.loads((tmp_path / "placed.json").read_text())["modules"]["top"]["cells"]
    bels = {up5k_dsp.register_of(n): c["attributes"]["NEXTPNR_BEL"]
            for n, c in cells.items() if c["type"] == "ICESTORM_DSP"}
    assert bels == up5k_dsp.FLOORPLAN
    # a block the design does not have stops nextpnr with its name, and make report with
    # the script's message (not as a seed that did not route)
    _synth_ice40(tmp_path, FLOOR_V.replace("psum", "qsum"), "floor", dsp=True)
    p = subprocess.run(pnr, cwd=tmp_path, capture_output=True, text=True)
    assert p.returncode != 0
    assert "u_octant.psum: no DSP blocks" in p.stdout + p.stderr
    with pytest.raises(common.ReportError, match=r"ice40_up5k nextpnr seed1: the placement "
                       r"script constraints/up5k_dsp.py stopped it: ValueError: .*"
                       r"u_octant.psum: no DSP blocks"):
        flow.pnr("ice40_up5k", tmp_path / "floor.json", tmp_path, 1, 36.0)


# ---- build/report.md (scripts/reporting/markdown.py) -------------------------------------------
def _full_report(fits=True, rtl_equals_model=True):
    """A report_full.json as scripts/report.py writes it, for both devices."""
    sim = {"probe_params": {"OPT_HARMONIC": 0}, "model_args": {"PROFILE": "up5k"},
           "latency": {"valid": 8, "count": 8, "ab_paced": 9, "ab_paced_min": 9,
                       "ab_paced_trials": 100, "trials": 100},
           "fast_path": {"samples": 40000, "results": 40000, "edges": 40000, "max_gap": 0,
                         "rtl_equals_model": rtl_equals_model,
                         "first_difference": None if rtl_equals_model else 123},
           "updates": [{"units_per_sample": 1.0, "clocks": 290000, "updates": 2200,
                        "clocks_per_update": 131.8, "extracts": 1, "resets": 0,
                        "busy_per_update": {"update": 128.0, "extract": 0.03, "reset": 0.0},
                        "idle_per_update": 3.8, "gate_blocks": 0, "jumps": 0}],
           "probe_build_s": 60.0}
    run = {"seed": 1, "fmax_mhz": 30.07, "seconds": 40.0, "error": None,
           "failing_endpoints": [170, 190], "critical_path": timing.summarise_path(PATH),
           "over_target": {"period_ns": 27.778, "endpoints": 3, "worst_ns": 33.3,
                           "classes": [{"worst_ns": 33.3, "endpoints": 3,
                                        "from": "u_core.u_abgen: next", "to": "u_core.u_abgen: pos"}],
                           "classes_total": 1}}
    rows = netlist.hierarchy_breakdown(_netlist(), devices.DEVICES["ice40_up5k"]["cells"])
    devs = {}
    for dev, util in (("ice40_up5k", UTIL_ICE), ("ecp5_25f", {
            "TRELLIS_COMB": (8351, 24288), "TRELLIS_FF": (3515, 24288),
            "MULT18X18D": (13, 28), "DP16KD": (11, 56)})):
        e = devices.entry(dev, util, 1565 if dev == "ice40_up5k" else None, fits, 30.07,
                          {**SIM, "sim_samples_per_wall_s": 200000}, 36.0, [1],
                          None if fits else {"variant": 1, "design": "top_report with x",
                                             "why": "the full core does not fit",
                                             "fits": True, "seeds_placed": 1,
                                             "fmax_mhz": 31.0, "runs": [run],
                                             "util": {"luts": [5000, 5280]},
                                             "not_placed": []})
        devs[dev] = {**e, "build": devices.build_of(dev), "top": "top_report",
                     "params": devices.synth_params(dev), "runs": [run], "breakdown": rows,
                     "dsp_modes": [{"cell": "u_core.u_octant.psum", "combinational": ["A in"]}]
                     if dev == "ice40_up5k" else None,
                     "times": {"synth_full_s": 60.0, "pnr_s": 40.0}}
    return {"command": "make report", "date": "2026-01-01 00:00", "commit": "abc1234",
            "sources_sha256": "0123456789abcdef", "tools": {"yosys": "Yosys 0.23"},
            "wall_s": 660.0, "devices": devs,
            "sim": {"builds": {d: sim for d in devs},
                    "sim_speed": {"samples": 20000, "div": 36, "clocks": 720000,
                                  "wall_s": [2.0], "cpu_s": [1.9], "samples_per_s": 261483,
                                  "samples_per_wall_s": 250000,
                                  "samples_per_wall_s_median": 240000,
                                  "load_average": [1.0, 1.0, 1.0]},
                    "seconds": 300.0}}


def test_markdown_is_tables_and_labels_with_a_link_to_the_method():
    md = markdown.markdown(_full_report(), readme="../scripts/README.md")
    lines = md.splitlines()
    assert f"(../scripts/README.md{markdown.SECTION})" in md
    # the section linked is there: scripts/README.md's heading "## `make report`"
    heads = (ROOT / "scripts" / "README.md").read_text().splitlines()
    assert "## `make report`" in heads and markdown.SECTION == "#make-report"
    # every line a heading, a table row or a short label: no paragraphs of prose
    prose = [ln for ln in lines if ln and not ln.startswith(("#", "|", "**"))]
    assert all(len(ln) <= 160 for ln in prose), [ln for ln in prose if len(ln) > 160]
    assert len(prose) <= 12, prose
    rows = [ln for ln in lines if ln.startswith("| `")]
    for k in devices.KEYS:
        assert any(ln.startswith(f"| `{k}`") for ln in rows), k
    assert "| `fmax_mhz` (median of the routed seeds) | 30.07 | 30.07 |" in md
    assert "| ice40_up5k | 100 | 8 | 8 | 9 .. 9 (100) | (ABGEN constant) |" in md
    assert "`make model PROFILE=up5k`" in md and "OPT_HARMONIC=0" in md
    assert "| 33.3 | 3 | `u_core.u_abgen: next` | `u_core.u_abgen: pos` |" in md
    assert "| `u_core.u_octant.psum` | A in |" in md
    assert "**RTL != model**" not in md and "Reduced variants" not in md
    # every table's rows have as many cells as its head
    for i, ln in enumerate(lines):
        if ln.startswith("|---") or ln.startswith("|--"):
            n = lines[i - 1].count("|")
            j = i + 1
            while j < len(lines) and lines[j].startswith("|"):
                assert lines[j].count("|") == n, (lines[i - 1], lines[j])
                j += 1


def test_markdown_flags_rtl_not_model_and_a_core_that_does_not_fit():
    md = markdown.markdown(_full_report(fits=False, rtl_equals_model=False))
    assert "**RTL != model** at DIV=1, build of ice40_up5k, from sample 123" in md
    assert "| **NO** |" in md
    assert "## Reduced variants (the full core did not place)" in md
    assert "0 (the full core does not fit; reduced variant 1: 31.00)" in md


def test_nested_make_gets_none_of_the_outer_make_command_line(tmp_path):
    # `make report EDITION=vhdl` puts EDITION=vhdl in its recipes' environment as well as
    # in MAKEFLAGS; a nested `make rtlsim` that inherited it ran the VHDL edition
    mk = tmp_path / "Makefile"
    mk.write_text("all:\n\t@" + sys.executable + " -c 'import json, os; "
                  "print(json.dumps(dict(os.environ)))'\n")
    out = subprocess.run(["make", "-s", "-f", str(mk), "EDITION=vhdl",
                          "SETTINGS=--eps 1000 --interp 5", "PROFILE=up5k"],
                         capture_output=True, text=True, check=True).stdout
    outer = json.loads(out)
    assert outer["EDITION"] == "vhdl" and "MAKEFLAGS" in outer
    assert common.command_line_vars(outer["MAKEFLAGS"]) == {"EDITION", "SETTINGS", "PROFILE"}
    env = common.make_env(outer)
    assert not {"EDITION", "SETTINGS", "PROFILE", "MAKEFLAGS", "MFLAGS"} & set(env)
    assert env["PATH"] == outer["PATH"]
    assert common.command_line_vars("s") == set() and common.command_line_vars("") == set()


@pytest.mark.parametrize("published", [False, True])
def test_compare_editions_reads_a_full_and_a_published_verilog_report(tmp_path, capsys,
                                                                      published):
    spec = importlib.util.spec_from_file_location("report_main", ROOT / "scripts" / "report.py")
    report = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(report)
    full = {"ice40_up5k": {"luts": 5000, "ffs": 1800, "dsps": 8, "brams": 28,
                           "fmax_mhz": 24.0}}
    ver = ({"name": "report", "headline": {"ice40_up5k": {"luts": 5000, "fmax_mhz": 24.0},
                                           "latency_cycles": 8}}
           if published else full)
    (tmp_path / "report.json").write_text(json.dumps(ver))
    vhdl = {"ice40_up5k": {"luts": 5100, "ffs": 1800, "dsps": 8, "brams": 28,
                           "fmax_mhz": 25.2}}
    report.compare_editions(vhdl, tmp_path / "report.json")
    out = capsys.readouterr().out
    assert "| ice40_up5k | luts | 5000 | 5100 | +2.0% |" in out
    assert "| ice40_up5k | fmax_mhz | 24.0 | 25.2 | +5.0% |" in out
    assert ("| ice40_up5k | ffs | - | 1800 | - |" if published
            else "| ice40_up5k | ffs | 1800 | 1800 | +0.0% |") in out
