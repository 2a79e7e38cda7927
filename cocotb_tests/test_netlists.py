"""GHDL's synthesised netlist of the VHDL edition (`ghdl --synth --out=verilog`, under
Icarus: fqtb.run_block's simulator "ghdl-synth") against the same cocotb tests as the
blocks' RTL, one parameter set per block: the netlist is what `make bitstream` and
`make report EDITION=vhdl` synthesise, and GHDL 2.0's Verilog writer gets some constructs
wrong where its simulation is right (rtl/vhdl/README.md lists them). Every block's other
sets, and the blocks left out here, run on their netlist with FQ_GHDL_SYNTH=1
(`FQ_GHDL_SYNTH=1 pytest cocotb_tests/test_<block>.py -k ghdl-synth`); the core's
netlist also runs against the model in sim/tests/test_run_vhdl.py (`make rtlsim
EDITION=vhdl-synth`, Verilator).

Chosen for CI time: the smallest set of each block, 56 s for the 13 from fresh builds
(a shared 2-core machine, 2026-11-29), 1 to 10 s each. Left out: monitor (30
and 50 s; the core's netlist runs it), uart_axil's bridge (some 45 s), finequad_core (28
s for `uniform`; test_run_vhdl.py's netlist run covers it), finequad_multi (68 s) and the
estimator (its three cases, some 30 s)."""
import pytest

import test_abgen
import test_adc_pmod_ad1
import test_axil_regs
import test_correct
import test_counter
import test_harmonic
import test_hbin
import test_lut
import test_octant
import test_pulse
import test_rls_engine
import test_uart_axil

SIM = "ghdl-synth"
CASES = {
    "counter-COUNT16": lambda: test_counter.test_counter(SIM, 16),
    "abgen-CW18": lambda: test_abgen.test_abgen(SIM, 18),
    "correct-ADC12": lambda: test_correct.test_correct(SIM, 12),
    "hbin-EXACT1": lambda: test_hbin.test_hbin(SIM, 1),
    "octant-EXACT1": lambda: test_octant.test_octant(SIM, 1),
    "lut-EXACT1-SIN8": lambda: test_lut.test_lut(SIM, 1, 8, 0, 0),
    "pulse-SIN8-ADDR1": lambda: test_pulse.test_pulse(SIM, 8, 1),
    "harmonic-directed": lambda: test_harmonic.test_harmonic(SIM, "directed", 0),
    "rls_engine-LANES1": lambda: test_rls_engine.test_rls_engine(SIM, 1),
    "axil_regs": lambda: test_axil_regs.test_axil_regs(SIM),
    "adc_pmod_ad1-icebreaker":
        lambda: test_adc_pmod_ad1.test_adc_pmod_ad1(SIM, "icebreaker"),
    "uart_rx": lambda: test_uart_axil.test_uart_rx(SIM),
    "uart_tx": lambda: test_uart_axil.test_uart_tx(SIM),
}


@pytest.mark.parametrize("case", list(CASES), ids=[f"{SIM}-{c}" for c in CASES])
def test_netlist(case):
    CASES[case]()
