# The VHDL edition's files in the order GHDL analyses them: the packages, then each
# entity after the entities it instantiates. The one list the Makefile (make lint, the
# VHDL builds) and cocotb_tests/fqtb.py read; a new rtl/vhdl/*.vhd goes here too
# (sim/tests/test_vhdl_sources.py fails otherwise).
rtl/vhdl/finequad_util_pkg.vhd
rtl/vhdl/finequad_regs_pkg.vhd
rtl/vhdl/hbin_pkg.vhd
rtl/vhdl/rls_pkg.vhd
rtl/vhdl/builds_pkg.vhd
# the core's blocks
rtl/vhdl/counter.vhd
rtl/vhdl/abgen.vhd
rtl/vhdl/correct.vhd
rtl/vhdl/octant.vhd
rtl/vhdl/lut.vhd
rtl/vhdl/phase.vhd
rtl/vhdl/monitor.vhd
rtl/vhdl/pulse.vhd
rtl/vhdl/refmark.vhd
rtl/vhdl/dcode.vhd
rtl/vhdl/hbin.vhd
rtl/vhdl/harmonic.vhd
rtl/vhdl/rls_engine.vhd
rtl/vhdl/estimator.vhd
# the system's blocks: AXI4-Lite slave, UART bridge, Pmod AD1 front end
rtl/vhdl/uart_rx.vhd
rtl/vhdl/uart_tx.vhd
rtl/vhdl/axil_regs.vhd
rtl/vhdl/adc_pmod_ad1.vhd
rtl/vhdl/uart_axil.vhd
rtl/vhdl/finequad_core.vhd
rtl/vhdl/finequad_multi.vhd
rtl/vhdl/finequad_system.vhd
# the tops: the board tops instantiate finequad_system; the report's top (make report
# EDITION=vhdl) takes finequad_core as a component, bound at elaboration
rtl/vhdl/top_icebreaker.vhd
rtl/vhdl/top_ulx3s.vhd
rtl/vhdl/top_report.vhd
