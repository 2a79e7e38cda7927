# Sources of finequad_system besides the core's (rtl/finequad_core.f), in the order tools
# read them (paths from the repository root). scripts/bitstream.sh, the Makefile's lint
# and the cocotb system test read this list.
rtl/finequad_system.v
rtl/adc_pmod_ad1.v
rtl/axil_regs.v
rtl/uart_axil.v
rtl/uart_rx.v
rtl/uart_tx.v
