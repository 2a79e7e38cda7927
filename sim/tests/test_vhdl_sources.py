"""rtl/vhdl/sources.f, the VHDL edition's analysis order, names every rtl/vhdl/*.vhd once,
and every entity of the edition has a Verilog twin of the same name in rtl/."""
import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
VHDL = REPO / "rtl" / "vhdl"


def listed():
    lines = (VHDL / "sources.f").read_text().splitlines()
    return [ln.strip() for ln in lines if ln.strip() and not ln.startswith("#")]


def test_sources_list_every_file_once():
    files = listed()
    assert len(files) == len(set(files)), "rtl/vhdl/sources.f names a file twice"
    on_disk = sorted(str(p.relative_to(REPO)) for p in VHDL.glob("*.vhd"))
    assert sorted(files) == on_disk, (
        f"rtl/vhdl/sources.f and rtl/vhdl/*.vhd differ: only listed "
        f"{sorted(set(files) - set(on_disk))}, only on disk {sorted(set(on_disk) - set(files))}")


def test_entities_have_verilog_twins():
    for f in listed():
        for name in re.findall(r"^\s*entity\s+(\w+)\s+is", (REPO / f).read_text(), re.M | re.I):
            twins = list((REPO / "rtl").rglob(f"{name}.v"))
            assert twins, f"{f}: entity {name} has no Verilog module rtl/**/{name}.v"
