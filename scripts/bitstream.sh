#!/usr/bin/env bash
# Synthesise (Yosys), place and route (nextpnr-ice40) and pack (icepack) the iCEBreaker
# top; print resources and the maximum clock frequency from the timing report. Exits 1
# when the clock the board runs at (33 MHz) is not met.
#   scripts/bitstream.sh [build dir] [seed]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/bitstream}
seed=${2:-1}
mhz=33          # the PLL of rtl/boards/top_icebreaker.v
mkdir -p "$out"
rtl="rtl/boards/top_icebreaker.v $(grep -v '^#' rtl/finequad_core.f | tr '\n' ' ')"
for t in yosys nextpnr-ice40 icepack; do
    command -v $t >/dev/null || { echo "bitstream: error: $t not found (apt-get install yosys nextpnr-ice40 fpga-icestorm)" >&2; exit 2; }
done
yosys -q -l "$out/yosys.log" -p "read_verilog -Irtl/tables $rtl;
    chparam -set TABLE_DIR \"$PWD/rtl/tables/\" finequad_core;
    synth_ice40 -dsp -top top_icebreaker -json $out/top.json"
nextpnr-ice40 --up5k --package sg48 --json "$out/top.json" --pcf constraints/icebreaker.pcf \
    --asc "$out/top.asc" --freq "$mhz" --timing-allow-fail --seed "$seed" --report "$out/report.json" \
    -l "$out/nextpnr.log" -q
icepack "$out/top.asc" "$out/top.bin"
python3 scripts/pnr_report.py "$out/report.json" "$out/nextpnr.log" --target-mhz "$mhz" \
    --bitstream "$out/top.bin" --require
