# Sources of finequad_core, in the order tools read them (paths from the repository
# root; include folders: rtl, rtl/tables). The Makefile, scripts/bitstream.sh and the cocotb
# tests (cocotb_tests/fqtb.py core_sources) all read this list.
rtl/finequad_core.v
rtl/correct.v
rtl/octant.v
rtl/lut.v
rtl/pulse.v
rtl/counter.v
rtl/estimator.v
rtl/rls_engine.v
rtl/harmonic.v
rtl/hbin.v
rtl/phase.v
rtl/monitor.v
rtl/abgen.v
rtl/refmark.v
rtl/dcode.v
