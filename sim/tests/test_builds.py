"""rtl/builds.toml and scripts/builds.py: the builds resolve through the RTL, the generated
files follow the description, every mistake in it is one error line that changes nothing,
and the Makefile's PROFILE= and knobs give each build's parameters."""
import pathlib
import re
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import builds  # noqa: E402


def test_generated_files_are_current():
    for path, text in builds.generated().items():
        assert (ROOT / path).read_text() == text, f"{path} is stale: make builds"


def test_core_parameters_go_through_each_top():
    """A report build's top hands its parameters on by name; a board's finequad_system
    hands its own (its defaults where the build sets none) and literals (the Pmod AD1's
    12 bits) to its finequad_core."""
    core = {k: d for k, (_, d) in builds.module_params("finequad_core").items()}
    assert builds.core_overrides("default") == {}
    assert builds.core_overrides("up5k") == {k: v for k, v in builds.build("up5k")["params"].items()}
    conns = builds.instance_params("finequad_system", "finequad_core")
    assert conns["ADC_W"] == "12" and conns["OPT_NTH_DSP"] == "OPT_NTH_DSP"
    ice = builds.core_params("icebreaker")
    assert ice["ADC_W"] == 12 and ice["OPT_NTH_DSP"] == 0 and ice["OPT_HARMONIC"] == 0
    assert ice["OPT_TUNABLE"] == core["OPT_TUNABLE"]         # not a system parameter
    ulx = builds.core_params("ulx3s")
    assert ulx["OPT_NTH_DSP"] == 1 and ulx["OPT_DISTRAM"] == 1 and ulx["ADC_W"] == 12
    # finequad_system's own default differs from the core's: a board build that left
    # OPT_NTH_DSP out would get the system's
    assert builds.module_params("finequad_system")["OPT_NTH_DSP"][1] != core["OPT_NTH_DSP"]
    assert not builds.is_core_build("up5k_multi")
    with pytest.raises(builds.NotOneCore):
        builds.core_params("ecp5_multi")
    assert builds.build("ecp5_multi")["params"]["ENGINE_LANES"] == 2      # from its base


def test_board_clocks_and_their_header():
    ice, ulx = builds.clock("icebreaker"), builds.clock("ulx3s")
    assert ice["mhz"] == 12 * 54 / 32 == 20.25 and ice["freq"] == 20.25
    assert ulx["mhz"] == pytest.approx(250 / 7) and ulx["freq"] == 35.71
    vh = (ROOT / builds.OUT_VH).read_text()
    assert '`define FQ_ULX3S_CLKOP_MHZ "35.7143"' in vh
    assert "`define FQ_ICEBREAKER_PLL .DIVR(4'd0), .DIVF(7'd53), .DIVQ(3'd5)" in vh
    for n in builds.boards():
        src = builds.module_source(builds.build(n)["top"])[1]
        assert f"`FQ_{n.upper()}_PARAMS" in src and f"`FQ_{n.upper()}_PLL" in src
        assert builds.params_module(n) == "finequad_system"
        # every parameter of the build is in the list its top hands finequad_system
        line = next(ln for ln in vh.splitlines() if ln.startswith(f"`define FQ_{n.upper()}_PARAMS"))
        assert sorted(re.findall(r"\.(\w+)\(", line)) == sorted(builds.build(n)["params"])


def test_vhdl_package_and_tops():
    """rtl/vhdl/builds_pkg.vhd: per board every finequad_system generic but TABLE_DIR (the
    build's value, else the default) and the PLL's dividers; each VHDL board top maps
    every one of them from its build's constants."""
    pkg = (ROOT / builds.OUT_VHD).read_text()
    assert 'constant ULX3S_CLKOP_MHZ : string            := "35.7143";' in pkg
    ice_pll = re.search(r"ICEBREAKER_PLL\s*:[^;]*;", pkg).group(0)
    assert 'DIVF         => "0110101"' in ice_pll and 'DIVQ         => "101"' in ice_pll
    sysp = [k for k in builds.module_params("finequad_system") if k != "TABLE_DIR"]
    for n in builds.boards():
        N = n.upper()
        block = re.search(rf"{N}_SYSTEM\s*:[^;]*;", pkg).group(0)
        vals = dict(re.findall(r"(\w+)\s+=>\s+(\d+)", block))
        want = {k: builds.module_params("finequad_system")[k][1] for k in sysp}
        want.update(builds.build(n)["params"])
        assert {k: int(v) for k, v in vals.items()} == want
        top = (ROOT / "rtl" / "vhdl" / f"{builds.build(n)['top']}.vhd").read_text()
        maps = dict(re.findall(r"(\w+)\s+=>\s+" + N + r"_SYSTEM\.(\w+)", top))
        assert {k.upper(): v for k, v in maps.items()} == {k: k for k in sysp}
        for k in builds.PLL[builds.build(n)["device"]["family"]]:
            assert re.search(rf"{k}\s+=>\s+{N}_PLL\.{k}\b", top, re.I)


@pytest.fixture
def tree(tmp_path):
    """A copy of what scripts/builds.py and the Makefile read: rtl/, constraints/, the
    script, its generated files and the Makefile."""
    for d in ("rtl", "constraints"):
        shutil.copytree(ROOT / d, tmp_path / d)
    (tmp_path / "scripts").mkdir()
    for f in ("scripts/builds.py", "scripts/builds.mk", "finequad.core", "Makefile"):
        shutil.copy(ROOT / f, tmp_path / f)
    return tmp_path


def _run(tree, *args):
    return subprocess.run([sys.executable, str(tree / "scripts/builds.py"), *args],
                          capture_output=True, text=True)


def _generated(tree):
    return {p: (tree / p).read_bytes()
            for p in (builds.OUT_MK, builds.OUT_VH, builds.OUT_VHD, builds.OUT_CORE)}


def test_check_finds_a_stale_file_and_write_brings_it_up_to_date(tree):
    assert _run(tree, "--check").returncode == 0
    toml = tree / "rtl/builds.toml"
    toml.write_text(toml.read_text().replace("ADC_PERIOD = 33", "ADC_PERIOD = 34"))
    before = _generated(tree)
    r = _run(tree, "--check")
    assert r.returncode == 1 and _generated(tree) == before
    assert r.stderr.strip().splitlines() == [
        "builds: error: stale: scripts/builds.mk, rtl/boards/builds.vh, "
        "rtl/vhdl/builds_pkg.vhd (rtl/builds.toml or the RTL changed since they were "
        "generated: run make builds)"]
    assert _run(tree).returncode == 0
    assert ".ADC_PERIOD(34)" in (tree / builds.OUT_VH).read_text()
    assert re.search(r"ICEBREAKER_SYSTEM[^;]*ADC_PERIOD +=> 34,",
                     (tree / builds.OUT_VHD).read_text())
    assert _run(tree, "--check").returncode == 0


ECP5_LINE = (ROOT / "rtl/builds.toml").read_text().splitlines().index("[ecp5]") + 1
# (what to replace in rtl/builds.toml, or in a file of the tree; the one error line)
MISTAKES = [
    ("OPT_JUMP = 0, OPT_DCODE", "OPT_JUMPS = 0, OPT_DCODE",
     "rtl/builds.toml: [up5k] params: OPT_JUMPS is not a parameter of top_report "
     "(rtl/boards/top_report.v)"),
    ('top = "top_report"\ndevice = { family = "ice40"',
     'top = "top_reprot"\ndevice = { family = "ice40"',
     "no module top_reprot in rtl/*.v or rtl/boards/*.v"),
    ('[default]\n', '[default]\nparam = { ADC_W = 12 }\n',
     "rtl/builds.toml: [default]: unknown key 'param' (keys: description, top, base, "
     "device, constraints, clock, params, axes)"),
    ('base = "up5k"', 'base = "up5x"', "rtl/builds.toml: [up5k_multi] base: no build 'up5x'"),
    ('[default]\n', '[default]\nbase = "default"\n',
     "rtl/builds.toml: [default] base: a loop (default -> default)"),
    ("OPT_HOSTLINK = 0", "OPT_HOSTLINK = 2",
     "rtl/builds.toml: [icebreaker] params.OPT_HOSTLINK = 2: finequad_system's OPT_HOSTLINK "
     "has 1 bit (rtl/finequad_system.v)"),
    ("OPT_HOSTLINK = 0", "OPT_HOSTLINK = false",
     "rtl/builds.toml: [icebreaker] params.OPT_HOSTLINK = False: a non-negative integer "
     "(one-bit options 0 or 1)"),
    ("DIVF = 53", "DIVF = 100",
     "rtl/builds.toml: [icebreaker] clock: the VCO at 1212 MHz is outside 533..1066 MHz"),
    ("DIVF = 53, ", "",
     "rtl/builds.toml: [icebreaker] clock.DIVF: missing or outside 0..127"),
    ('family = "ecp5", part = "25k", package = "CABGA381"',
     'family = "ecp6", part = "25k", package = "CABGA381"',
     "rtl/builds.toml: [ulx3s] device.family: 'ecp6' is not one of ice40, ecp5"),
    ('"constraints/ulx3s.lpf"', '"constraints/ulx3s.pcf"',
     "rtl/builds.toml: [ulx3s] constraints: no file constraints/ulx3s.pcf"),
    ("axes = [1, 2, 4]\n\n", "axes = [0, 2]\n\n",
     "rtl/builds.toml: [up5k_multi] axes: a list of axis counts >= 1"),
    ("[ecp5]\n", "[ecp5\n", "rtl/builds.toml: Expected ']' at the end of a table declaration "
     f"(at line {ECP5_LINE}, column 6)"),
    ("ENGINE_LANES = 2, OPT_DISTRAM", "ENGINE_LANES = 3, OPT_DISTRAM",
     "rtl/builds.toml: [ecp5]: finequad_core's ENGINE_LANES = 3 (make rtlsim takes 1, 2)"),
    (("rtl/boards/top_ulx3s.v", "`FQ_ULX3S_PARAMS"), "`FQ_ULX3_PARAMS",
     "rtl/boards/top_ulx3s.v: top_ulx3s does not use `FQ_ULX3S_PARAMS (the parameters of "
     "build ulx3s, rtl/boards/builds.vh)"),
]


@pytest.mark.parametrize("old,new,msg", MISTAKES, ids=[m[2][:40] for m in MISTAKES])
def test_a_mistake_is_one_line_that_names_it_and_changes_nothing(tree, old, new, msg):
    path, old = (old if isinstance(old, tuple) else ("rtl/builds.toml", old))
    f = tree / path
    text = f.read_text()
    assert text.count(old) == 1, old
    f.write_text(text.replace(old, new))
    before = _generated(tree)
    for args in ((), ("--check",), ("show",)):
        r = _run(tree, *args)
        assert r.returncode == 2, (args, r.stdout)
        assert r.stderr.splitlines() == [f"builds: error: {msg}"], (args, r.stderr)
    assert _generated(tree) == before


def _make(*args, cwd=ROOT):
    """make -n: what make would run, as if the core's RTL had changed (so a harness that
    is built already is built again in the listing)."""
    return subprocess.run(["make", "-s", "-n", "-W", "rtl/finequad_core.v", "-C", str(cwd),
                           *args], capture_output=True, text=True)


def _gflags(out):
    """finequad_core's -G options of `make -n rtlsim`'s Verilator command."""
    line = next(ln for ln in out.splitlines() if "verilator --cc --exe" in ln)
    return dict(re.findall(r"-G(\w+)=(\S+)", line))


@pytest.mark.parametrize("name", [n for n in builds.names() if builds.is_core_build(n)])
def test_profile_gives_the_builds_core_parameters(name):
    """make rtlsim PROFILE=<build> builds its harness with every knob at the build's value
    (scripts/builds.mk against scripts/builds.py), in a folder of its own."""
    r = _make("rtlsim", f"PROFILE={name}")
    assert r.returncode == 0, r.stderr
    g = _gflags(r.stdout)
    cp = builds.core_params(name)
    assert {k: int(v) for k, v in g.items() if k != "TABLE_DIR"} == {k: cp[k] for k in builds.KNOBS}
    mdir = re.search(r"--Mdir (\S+)", r.stdout).group(1)
    assert mdir.startswith("build/rtlsim_exact_adc") and f"adc{cp['ADC_W']}" in mdir
    m = _make("model", f"PROFILE={name}", "IN=x", "OUT=y")
    cmd = " ".join(m.stdout.replace("\\\n", " ").split())
    for opt, k in (("engine-lanes", "ENGINE_LANES"), ("opt-harmonic", "OPT_HARMONIC"),
                   ("opt-monitor", "OPT_MONITOR"), ("opt-jump", "OPT_JUMP"),
                   ("opt-dcode", "OPT_DCODE")):
        assert f"--{opt} {cp[k]}" in cmd, (opt, cmd)


def test_knobs_override_the_profile_under_either_name():
    ecp5 = _gflags(_make("rtlsim", "PROFILE=ecp5").stdout)
    for knob in ("LANES=1", "ENGINE_LANES=1"):
        g = _gflags(_make("rtlsim", "PROFILE=ecp5", knob).stdout)
        assert g == {**ecp5, "ENGINE_LANES": "1"}
    assert _gflags(_make("rtlsim", "TABLE=paper").stdout)["TABLE_EXACT"] == "0"
    assert "rtlsim_paper_adc16 " in _make("rtlsim", "TABLE_EXACT=0").stdout + " "
    lint = _make("lint", "PROFILE=up5k").stdout
    assert lint.count("--top-module finequad_core") == 2       # the selection only
    assert "-GOPT_JUMP=1'b0" in lint.split("--top-module finequad_core")[0]
    assert _make("lint").stdout.split("; do")[0].count('"') == 2 * (
        len([n for n in builds.names() if builds.is_core_build(n)]) + 4)


@pytest.mark.parametrize("args,msg", [
    (["PROFILE=up5"], "PROFILE='up5': not a build of one finequad_core in rtl/builds.toml "
     "(those are: default up5k ecp5 icebreaker ulx3s); make profiles lists them"),
    (["PROFILE=up5k_multi"], "PROFILE='up5k_multi': not a build of one finequad_core"),
    (["LANES=2", "ENGINE_LANES=1"], "LANES='2' and ENGINE_LANES='1' disagree: give one of them"),
    (["TABLE=paper", "TABLE_EXACT=1"], "TABLE='paper' and TABLE_EXACT='1' disagree"),
    (["OPT_TUNABLE=2"], "OPT_TUNABLE='2': must be 0 or 1"),
])
def test_a_bad_profile_or_knob_is_one_error_line(args, msg):
    r = _make("rtlsim", *args)
    assert r.returncode != 0 and r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and msg in lines[0] and lines[0].startswith("Makefile:"), r.stderr


def test_makefile_refuses_a_builds_mk_older_than_the_description(tree):
    """An edit of rtl/builds.toml without make builds stops every target (but make builds)
    with one line, before a stale PROFILE= is used."""
    toml = tree / "rtl/builds.toml"
    assert _make("help", cwd=tree).returncode == 0
    toml.write_text(toml.read_text().replace("ADC_PERIOD = 33", "ADC_PERIOD = 34"))
    r = _make("help", cwd=tree)
    assert r.returncode != 0
    assert r.stderr.strip().endswith("rtl/builds.toml differs from the one scripts/builds.mk "
                                     "was generated from: run make builds.  Stop.")


def test_bitstream_names_the_boards_for_an_unknown_board(tmp_path):
    r = subprocess.run([str(ROOT / "scripts/bitstream.sh"), str(tmp_path / "b"), "1", "ulx4s"],
                       capture_output=True, text=True)
    assert r.returncode == 2 and not (tmp_path / "b").exists()
    assert r.stderr.strip() == ("builds: error: 'ulx4s' is not a board build of "
                                "rtl/builds.toml (boards: icebreaker, ulx3s)")
