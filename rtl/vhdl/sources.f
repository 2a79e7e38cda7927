# The VHDL edition's files in the order GHDL analyses them: the packages, then each
# entity after the entities it instantiates. The one list the Makefile (make lint, the
# VHDL builds) and cocotb_tests/fqtb.py read; a new rtl/vhdl/*.vhd goes here too
# (sim/tests/test_vhdl_sources.py fails otherwise).
rtl/vhdl/finequad_util_pkg.vhd
rtl/vhdl/finequad_regs_pkg.vhd
rtl/vhdl/counter.vhd
rtl/vhdl/abgen.vhd
rtl/vhdl/correct.vhd
rtl/vhdl/octant.vhd
rtl/vhdl/lut.vhd
rtl/vhdl/phase.vhd
rtl/vhdl/monitor.vhd
# the report's top (make report EDITION=vhdl): finequad_core as a component, bound at
# elaboration
rtl/vhdl/top_report.vhd
rtl/vhdl/pulse.vhd
rtl/vhdl/refmark.vhd
rtl/vhdl/dcode.vhd
