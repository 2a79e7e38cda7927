"""What every GHDL run of the VHDL edition shares: its files in GHDL's analysis order
(rtl/vhdl/sources.f) and the back end the `ghdl` command runs (cocotb_tests/fqtb.py,
sim/run_vhdl.py, scripts/ghdl_netlist.py)."""
import os
import pathlib
import shutil

ROOT = pathlib.Path(__file__).resolve().parents[1]
SOURCES_F = ROOT / "rtl" / "vhdl" / "sources.f"
# GHDL's back ends, the fastest first (rtl/vhdl/README.md has the measurement)
BACKENDS = ("llvm", "gcc", "mcode")


def vhdl_files():
    """Every file of the VHDL edition (paths from the repository root), in GHDL's
    analysis order: packages, then each entity after those it instantiates."""
    lines = SOURCES_F.read_text().splitlines()
    return [ln.strip() for ln in lines if ln.strip() and not ln.lstrip().startswith("#")]


def fastest_backend():
    """The fastest GHDL back end installed beside the `ghdl` command (Debian's `ghdl`
    runs the one GHDL_BACKEND names), or None without GHDL."""
    ghdl = shutil.which("ghdl")
    if ghdl is None:
        return None
    bindir = os.path.dirname(ghdl)
    return next((b for b in BACKENDS if os.access(os.path.join(bindir, f"ghdl-{b}"), os.X_OK)),
                None)
