"""finequad_core's parameter checks (rtl/finequad_core.v) and those of its blocks that
can be used alone, as their VHDL twins' ranges (lut's SIN_W; counter's, abgen's,
refmark's and dcode's COUNT_W; correct's ADC_W): a value out of range stops elaboration in
Icarus and in Yosys with the rule's name, and values at the ends of each range elaborate."""
import pathlib
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SOURCES = [ROOT / ln.strip() for ln in (ROOT / "rtl/finequad_core.f").read_text().splitlines()
           if ln.strip() and not ln.startswith("#")]
INCLUDES = ["-I", str(ROOT / "rtl"), "-I", str(ROOT / "rtl/tables")]

# (parameter, value, the rule's module name or None for a legal value)
CASES = [
    ("ADC_W", 11, "finequad_core_ADC_W_must_be_12_to_16"),
    ("ADC_W", 17, "finequad_core_ADC_W_must_be_12_to_16"),
    ("ADC_W", 12, None),
    ("SIN_W", 9, "finequad_core_SIN_W_must_be_8_10_12_or_16"),
    ("SIN_W", 8, None),
    ("SIN_W", 16, None),
    ("COUNT_W", 16, "finequad_core_COUNT_W_must_be_17_to_32"),
    ("COUNT_W", 33, "finequad_core_COUNT_W_must_be_17_to_32"),
    ("COUNT_W", 17, None),
    ("ENGINE_LANES", 0, "finequad_core_ENGINE_LANES_must_be_1_or_2"),
    ("ENGINE_LANES", 3, "finequad_core_ENGINE_LANES_must_be_1_or_2"),
    ("ENGINE_LANES", 2, None),
]


# the tops that read rtl/tables/ (TABLE_DIR)
TABLE_TOPS = ("finequad_core", "lut")


def _icarus(name, value, tmp_path, top="finequad_core"):
    tables = ([f"-P{top}.TABLE_DIR=\"{ROOT / 'rtl/tables'}/\""] if top in TABLE_TOPS
              else [])
    return subprocess.run(["iverilog", "-g2005", *INCLUDES, "-s", top,
                           f"-P{top}.{name}={value}", *tables,
                           "-o", str(tmp_path / "a.vvp"), *map(str, SOURCES)],
                          capture_output=True, text=True)


def _yosys(name, value, _tmp_path, top="finequad_core"):
    script = (f"read_verilog {' '.join(INCLUDES[i] + INCLUDES[i + 1] for i in (0, 2))} "
              + " ".join(map(str, SOURCES))
              + f"; chparam -set {name} {value} {top}"
              + f"; hierarchy -check -top {top}")
    # (from the repository root: TABLE_DIR's default, rtl/tables/, is relative to it)
    return subprocess.run(["yosys", "-q", "-p", script], capture_output=True, text=True,
                          cwd=ROOT)


# a block's own checks, with the block as the top: (block, parameter, value, rule or None)
BLOCK_CASES = [
    ("lut", "SIN_W", 9, "lut_SIN_W_must_be_8_10_12_or_16"),
    ("lut", "SIN_W", 11, "lut_SIN_W_must_be_8_10_12_or_16"),
    ("lut", "SIN_W", 8, None),
    ("lut", "SIN_W", 16, None),
    ("counter", "COUNT_W", 15, "counter_COUNT_W_must_be_16_to_32"),
    ("counter", "COUNT_W", 33, "counter_COUNT_W_must_be_16_to_32"),
    ("counter", "COUNT_W", 16, None),
    ("counter", "COUNT_W", 32, None),
    ("abgen", "COUNT_W", 16, "abgen_COUNT_W_must_be_17_or_more"),
    ("abgen", "COUNT_W", 17, None),
    ("refmark", "COUNT_W", 16, "refmark_COUNT_W_must_be_17_to_32"),
    ("refmark", "COUNT_W", 33, "refmark_COUNT_W_must_be_17_to_32"),
    ("refmark", "COUNT_W", 17, None),
    ("dcode", "COUNT_W", 16, "dcode_COUNT_W_must_be_17_to_32"),
    ("dcode", "COUNT_W", 33, "dcode_COUNT_W_must_be_17_to_32"),
    ("dcode", "COUNT_W", 32, None),
    ("correct", "ADC_W", 11, "correct_ADC_W_must_be_12_to_16"),
    ("correct", "ADC_W", 17, "correct_ADC_W_must_be_12_to_16"),
    ("correct", "ADC_W", 12, None),
]


@pytest.mark.parametrize("tool", ["icarus", "yosys"])
@pytest.mark.parametrize("top,name,value,rule",
                         [("finequad_core", *c) for c in CASES] + BLOCK_CASES,
                         ids=lambda v: str(v))
def test_parameter_range(tool, top, name, value, rule, tmp_path):
    exe = {"icarus": "iverilog", "yosys": "yosys"}[tool]
    if shutil.which(exe) is None:
        pytest.skip(f"needs {exe}")
    r = {"icarus": _icarus, "yosys": _yosys}[tool](name, value, tmp_path, top)
    out = r.stdout + r.stderr
    if rule is None:
        assert r.returncode == 0, f"{name}={value} should elaborate:\n{out[-2000:]}"
        assert "must_be" not in out
    else:
        assert r.returncode != 0, f"{name}={value} elaborated"
        assert rule in out, f"{name}={value}: the error does not name {rule}:\n{out[-2000:]}"
