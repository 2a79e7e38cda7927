# The VHDL edition's files in the order GHDL analyses them: the packages, then each
# entity after the entities it instantiates. The one list the Makefile (make lint, the
# VHDL builds) and cocotb_tests/fqtb.py read; a new rtl/vhdl/*.vhd goes here too
# (sim/tests/test_vhdl_sources.py fails otherwise).
rtl/vhdl/finequad_util_pkg.vhd
rtl/vhdl/finequad_regs_pkg.vhd
rtl/vhdl/counter.vhd
rtl/vhdl/abgen.vhd
rtl/vhdl/finequad_core.vhd
rtl/vhdl/finequad_multi.vhd
rtl/vhdl/finequad_system.vhd
