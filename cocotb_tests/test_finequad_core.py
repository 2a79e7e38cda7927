"""finequad_core, the whole pipeline, against sim.model.finequad_core.run (bit-true, every sample).

Each scenario is a generated encoder recording (sim/siggen.py: s-curve moves, imperfect
signals, 0.5 % noise) driven sample by sample with the model's timing contract
(sim/model/finequad_core.py): the registers are written on edges 0, 1, ... from the
scenario's Config (setup_writes(): every settings register, defaults too, CTRL last:
sim.model.finequad_core.register_writes), sample k is strobed (s_valid high for one clock)
on edge t_k, and its result must be on m_* after edge t_k + LATENCY (the constant of
sim/model/finequad_core.py, which rtl/finequad_core.v declares), with m_valid high after
exactly those edges. count, a, b and the 11-bit fault word of every sample must equal the
model's. During the run the registered read port is held on AB_BACKLOG (reg_re high
except on a write edge): the value read after each sample's output edge must equal the backlog of
the model's A/B follower (backlog_at()).

Scenarios (one simulator process each, from power-up):
  uniform    strobes every 36 clocks from edge 32 (the harness timing), TABLE_EXACT=1,
             the other registers at their defaults (the harness's configuration)
  gaps       random idle gaps between strobes (1 .. 60 clocks, bursts back to back),
             small signals (input gain 2), rail spikes (clip, gain and correction
             saturation), n = 256, periodic covariance resets, TABLE_EXACT=1; A/B edges
             at least 12 clocks apart with a backlog bound of 6 counts (backlog during
             the bursts, overflow: fault bit 6), jump floor 60
  paper      TABLE_EXACT=0 (the paper's table), n = 7, strobes every 24 clocks, edge
             mode (CTRL.count_mode), the Eq. 12 pulses on the A/B pins, harmonic step 2^-6 (gear 0)
  reset_req  reset requests written to CTRL.cov_reset (see below), TABLE_EXACT=1, jump
             detector off
  highspeed  calibration at 0.02 fs, the signal frequency ramped to 0.4 fs, held, ramped
             to standstill, a dwell (HIGHSPEED); n = 10, A/B edges 3 clocks apart
             (backlog, overflow, catch-up); overspeed flags (3/4 pi per sample) at the top
  faults     a calibration (the model's final bundle on the same recording) staged in
             GAIN..C2 and LOADed (CTRL.load) before the first sample, so the radius
             checks are armed from the start while "not calibrated" stays up until the
             estimator hands over; during one move: the signal lost (amplitude x 0.03),
             channel 1 stuck, single-sample glitches (a point at a random angle), a short
             over-range (amplitude x 1.6) and clipped samples (FAULT_EVENTS); the monitor's
             registers written to non-default values
  upsets     the estimator's exceptions (Verilator only): KAPPA at its maximum (0xffff,
             5 kappa = 1280: the trace bound's full range), a step in amplitudes and
             offsets during the move (the jump detector fires), then a stretch where
             channel 2 shrinks to 10 % of A1 (UPSETS: the estimate is no longer a usable
             ellipse, the extraction fails and the last bundle is held, fault bit 5,
             until the signal returns) but for two short spikes back to full size (the
             residual saturates: invalid updates, each resetting P), with the radius
             checks opened and the glitch test off so those samples reach the
             estimator; the engine saturates a register (STATUS.sat). The model must
             see each of these, or the test fails
  faults_lean  the faults recording through the UP5K report build's options (OPT_MONITOR=0:
             no fault checks, OPT_JUMP=0: no jump detector; Verilator only): nothing is
             flagged or held while the full model flags the faults; RADIUS and MONITOR
             read 0, JUMP 0x8000

Beyond RTL == model, independent checks: every change of m_a / m_b (paced outputs:
scenarios other than paper) is on a clock edge, never both pins on one edge, at least
ab_sep clocks after the previous one, and an x4 decoder of the pins in the test ends on
the final count once the backlog is paid (check_ab_pins); in highspeed and faults the
count of every sample the monitor trusts stays within pitch / 8 of the true position (no
slips) from calibration on (check_truth), so every fault is ridden through.

After the last sample the bench reads the registers back through the registered read
port (reg_re with reg_addr for one edge, reg_rdata after it): ID, every settings
register, COUNT, ILLEGAL, UPDATES, JUMPS, STATUS, GAIN and M1..C2, AB_BACKLOG and TRAVEL
must equal the model's final state. Two writes during the run: CTRL.capture on the
output edge of a sample near the middle whose count differs from the final one, which
CAPTURE must hold after the run, and FAULT_STICKY cleared (ones written) on the edge that
ORs in the fault word of the last sample that has a fault bit no later sample has (where
the scenario allows, after a bit none of them has): FAULT_STICKY must read the OR of that
sample's word and all later ones (a fault on the clearing edge stays; a clear that lost
to it reads otherwise). Then a capture of the final count, and writing ones to
FAULT_STICKY clears those bits (0x15, then 0, then 0x40 for the A/B overflow, then 0x7f,
then all).
The model's final bundle is that of a phantom sample strobed (in the model only) after every
program has ended; a reset request on that phantom keeps it from starting an update.

Reset requests (CTRL.cov_reset): the model (Config.resets) takes the index k of the sample
whose arrival decision (edge t_k + RESET_STAGE, sim.model.finequad_core.RESET_STAGE: the estimator
decides on a reset on the edge after a sample's arrival) is the first to see the request.
A write on edge w is seen by decisions on edges w + 1 and later, so it belongs to sample k
exactly when t_(k-1) + RESET_STAGE <= w <= t_k + RESET_STAGE - 1 (the write keeps CTRL's
counter-mode bit). The test writes
requests alternately on the latest edge of that window (t_k + RESET_STAGE - 1) and on the
earliest (t_(k-1) + RESET_STAGE), at samples where attributing the request to the
neighbouring sample (k + 1, resp. k - 1) would change the model's outputs, so an
off-by-one edge in the RTL cannot pass.
"""
import os

import pytest

import fqtb
from sim.model import finequad_core as core_model
from sim.model import regs
from sim.model import estimator

CORE_SOURCES = fqtb.core_sources()
# the report builds' finequad_core parameters (rtl/builds.toml): the ECP5's, and the UP5K's
# options that change results (its other RTL is make rtlsim's: sim/tests/test_rtlsim.py)
ECP5 = fqtb.builds().core_overrides("ecp5")
UP5K_LEAN = {k: v for k, v in fqtb.builds().core_overrides("up5k").items()
             if k in ("OPT_MONITOR", "OPT_JUMP")}


OUT_LATENCY = core_model.LATENCY   # sim/model/finequad_core.py: the RTL's pipeline timing
T_FIRST = 32                # first strobe edge (sim/harness/harness.cpp)
T_FIRST_LOAD = 48           # with a LOAD before it (more register writes)
BACKLOG = regs.AB_BACKLOG   # read every sample during the run

# samples per simulator: Icarus simulates this core at some 10k clocks/s, Verilator with
# cocotb some 20x faster. regs: core.Config fields (the model's configuration), written to
# the registers before the first strobe (setup_writes()); the ones left out keep their
# defaults, which the bench writes too.
SCENARIOS = {
    "uniform": dict(exact=1, n={"icarus": 7000, "verilator": 40000, "ghdl": 2000},
                    regs=dict(interp=100, eps=1638, lambda_k=8, kappa=64 << 8, period=4096,
                              settle=64, gate=64)),
    # A/B pacing slower than the count in the bursts, with a small bound: backlog and the
    # overflow (fault bit 6) during the run; jump detector floor raised
    "gaps": dict(exact=1, n={"icarus": 8000, "verilator": 30000},
                 regs=dict(interp=256, eps=3000, lambda_k=6, kappa=32 << 8, period=200,
                           settle=16, gate=40, ab_sep=12, ab_bound=6, jump_min=60)),
    # edge mode (the count from the x4 decoder of the pulses), the pulses on the A/B pins,
    # the slowest harmonic step
    "paper": dict(exact=0, n={"icarus": 6000, "verilator": 30000, "ghdl": 2000},
                  regs=dict(interp=7, eps=1638, lambda_k=8, kappa=64 << 8, period=4096,
                            settle=32, gate=64, count_mode=1, ab_src=1, harm_mu=3)),
    # jump detector off (JUMP bit 15)
    "reset_req": dict(exact=1, n={"icarus": 5000, "verilator": 20000},
                      regs=dict(interp=100, eps=1000, lambda_k=9, kappa=100 << 8, period=0,
                                settle=24, gate=48, jump_off=1)),
    # the signal frequency ramps up to 0.4 fs and back (HIGHSPEED): the phase-mode counter
    # against the truth; n = 10 and A/B edges 3 clocks apart (12 counts per sample at 36
    # clocks per sample) fall behind the count (16 counts per sample at 0.4 fs): backlog,
    # overflow (bound 1024), and the catch-up in the final dwell
    "highspeed": dict(exact=1, n={"icarus": 4000, "verilator": 24000},
                      regs=dict(interp=10, ab_sep=3, ab_bound=1024)),
    # signal faults during a move, a calibration loaded before the first sample
    "faults": dict(exact=1, n={"icarus": 6000, "verilator": 30000, "ghdl": 5000},
                   regs=dict(interp=100, clip=32000, loss=4000, over=21000, glitch_k=9,
                             stuck_n=6), load=True),
    # the ECP5 build's RTL (rtl/builds.toml [ecp5]): two engine lanes (the model's
    # ENGINE_LANES), the harmonic table in distributed RAM, the 4096-row phase table, Eq. 12
    # on the sine table's address side (OPT_ECP5_MULT: synthesis only); the bursts of
    # "gaps" (samples on consecutive clocks), Verilator only
    "ecp5": dict(exact=1, n={"icarus": 0, "verilator": 30000, "ghdl": 3000},
                 regs=dict(interp=256, eps=3000, lambda_k=6, kappa=32 << 8, period=200,
                           settle=16, gate=40, ab_sep=12, ab_bound=6, jump_min=60),
                 build=ECP5, like="gaps"),
    # the estimator's exceptions: jumps, a failed extraction (hold), engine saturation,
    # KAPPA at its maximum (UPSETS)
    "upsets": dict(exact=1, n={"icarus": 0, "verilator": 20000},
                   regs=dict(interp=100, kappa=0xFFFF, lambda_k=7, period=0, settle=16,
                             gate=32, loss=800, over=65535, glitch_k=0)),
    # the UP5K report build's (rtl/builds.toml [up5k]) options: no fault checks in the
    # monitor, no jump detector (OPT_MONITOR=0, OPT_JUMP=0); the signal and registers of
    # "faults":
    # nothing is flagged or held (the model with the same options), RADIUS and MONITOR
    # read 0, JUMP 0x8000 (off) and JUMPS 0; Verilator only
    "faults_lean": dict(exact=1, n={"icarus": 0, "verilator": 30000},
                        regs=dict(interp=100, clip=32000, loss=4000, over=21000, glitch_k=9,
                                  stuck_n=6), load=True,
                        build=UP5K_LEAN, like="faults"),
}
# faults: (fraction of the recording where it starts, what, length in samples); the move
# runs from 0.05 to 0.95 of the recording at about 1800 samples per signal period at any
# length, so a loss or a stuck channel spans 1/6 of a period (the monitor needs 1/16 of
# travel to call a channel stuck), the glitches 10 samples spread over 1000
FAULT_EVENTS = ((0.30, "loss", 300), (0.45, "stuck", 300), (0.55, "glitch", 1000),
                (0.72, "over", 150), (0.80, "clip", 60))

# upsets: where the step comes and where the flattened stretch lies (fractions of the
# recording); amplitudes and offsets (A1, A2, m1, m2, full scale) before and after the
# step; channel 2's amplitude in the stretch (10 % of A1 after the step)
UPSETS = dict(step=0.30, flat=(0.55, 0.72), before=(0.5, 0.45, 0.01, -0.01),
              after=(0.6, 0.5, 0.05, -0.01), flat_a2=0.06, spikes=(0.62, 0.66), spike_len=30)

# highspeed: (start, end) of each phase as fractions of the recording, and the signal
# frequency (f / fs) there: calibration at 0.02 fs, linear ramps, 0.4 fs, stop, dwell
HIGHSPEED = ((0.0, 0.25, 0.02, 0.02), (0.25, 0.4, 0.02, 0.4), (0.4, 0.55, 0.4, 0.4),
             (0.55, 0.7, 0.4, 0.0), (0.7, 1.0, 0.0, 0.0))
SLIP = 1 / 8                # a slip: the counter off the truth by more than pitch / 8


# ---- register words from a Config (the model's settings, named as the registers' fields) --
def ctrl_word(cfg, **pulses):
    """CTRL: the counter mode and the pulses given (cov_reset, load, capture)."""
    return regs.word("CTRL", count_mode=cfg.count_mode, **pulses)


def readback(cfg, name):
    """A settings register as it reads back after register_writes(cfg): the fields a read
    returns (the build's options zero some, rtl/regs/finequad.rdl)."""
    r = regs.REGS[name]
    if (name == "HARM" and not cfg.OPT_HARMONIC) or \
            (name in ("RADIUS", "MONITOR", "COAST") and not cfg.OPT_MONITOR):
        return 0
    if name == "JUMP" and not cfg.OPT_JUMP:
        return regs.word("JUMP", jump_off=1, jump_min=0)
    return dict(core_model.register_writes(cfg))[r.index] & r.rmask


def setup_writes(cfg):
    """[(addr, data)] written on edges 0, 1, ... before the first strobe: the settings
    (core_model.register_writes); with cfg.loads (one LOAD) the bundle staged in
    GAIN..C2, then CTRL.load on its edge w."""
    w = core_model.register_writes(cfg)
    for edge, bundle in cfg.loads:
        w += [(regs.REGS[r].index, regs.word(r, **{r.lower(): v}))
              for r, v in zip(core_model.BUNDLE_REGS, bundle)]
        assert edge == len(w), (edge, len(w))
        w.append((regs.CTRL, ctrl_word(cfg, load=1)))
    return w


def load_edge(cfg):
    """The edge of the LOAD write that setup_writes() makes for cfg (loads still empty)."""
    return len(setup_writes(cfg)) + 6


def backlog_at(count, t, reads, cfg):
    """The A/B backlog register (AB_BACKLOG, registered from rtl/abgen.v's backlog_o) as read
    back after each edge of `reads` (increasing), from the model (sim/model/abgen.py,
    the Follower that sim/model/finequad_core.py runs on the count before the homing
    offset, `count`): reg_rdata after edge r holds backlog_o after edge r - 1, the
    saturated distance of edge r - 2. The pins' target takes sample k's count on
    t_k + AB_AT - 1, the target of edges t_k + AB_AT on."""
    from sim.model import abgen
    from sim.model.fixed import sat
    fol = abgen.Follower(cfg.ab_sep, cfg.ab_bound, cfg.COUNT_W)
    # (last edge run, kind, index, edge) in edge order: set(y) runs the edges before y,
    # sample(q) the edges up to q; on a tie (q = y - 1) either order gives the same state
    ev = [(int(e) + core_model.AB_AT - 1, 1, k, int(e) + core_model.AB_AT)
          for k, e in enumerate(t)]
    ev += [(int(r) - 2, 0, i, int(r) - 2) for i, r in enumerate(reads)]
    out = [0] * len(reads)
    for _, is_set, i, edge in sorted(ev):
        if is_set:
            fol.set(edge, int(count[i]))
        else:
            fol.sample(edge)
            out[i] = sat(fol.st.d, 16) & 0xFFFFFFFF
    return out


# GHDL (the VHDL edition, rtl/vhdl/finequad_core.vhd) runs the scenarios with a "ghdl"
# sample count, chosen so that every generic branch of the core that a scenario selects is
# simulated once and the GHDL share of CI stays near 3 minutes: uniform (the default
# build), paper (TABLE_EXACT=0; edge mode, the pulses on the pins), faults (the monitor's
# checks, a LOAD; 5000 samples: with fewer the model's count slips past pitch / 8 before
# the calibration) and ecp5 (ENGINE_LANES=2, OPT_DISTRAM=1, OPT_PHASE_4K=1,
# OPT_PULSE_ADDR=1; OPT_ECP5_MULT: see test_core). Not on GHDL: gaps, reset_req and
# highspeed (the build of uniform; their features are the blocks' own, which Icarus and
# Verilator cover here), upsets (20 000 samples for its exceptions) and faults_lean
# (OPT_MONITOR=0, OPT_JUMP=0: the jump it checks for needs some 6000 samples; add it,
# "ghdl": 6000, if the time allows). Every scenario drives and reads ports only, so any of
# them runs on GHDL as it is.
CASES = [pytest.param(sim, scenario, id=f"{sim}-{scenario}")
         for sim in fqtb.simulators("finequad_core") for scenario in SCENARIOS
         if not fqtb.is_vhdl(sim) or "ghdl" in SCENARIOS[scenario]["n"]]


@pytest.mark.parametrize(("sim", "scenario"), CASES)
def test_core(sim, scenario):
    sc = SCENARIOS[scenario]
    n = int(os.environ.get("FQ_CORE_SAMPLES", 0)) or sc["n"][fqtb.plan_sim(sim)]
    if n == 0:
        pytest.skip(f"{scenario}: not run on {sim}")
    build = dict(sc.get("build", {}))
    if fqtb.is_vhdl(sim):
        # OPT_ECP5_MULT = 1 instantiates the ECP5 MULT18X18D, which Icarus and Verilator
        # do not see (no SYNTHESIS define: rtl/octant.v and rtl/lut.v simulate the inferred
        # form, the logic of OPT_ECP5_MULT = 0); VHDL has no such define, so GHDL simulates
        # that same form with 0 (the instances' wiring: test_lut.py, test_octant.py)
        build.pop("OPT_ECP5_MULT", None)
    fqtb.run_block(sim, "finequad_core", CORE_SOURCES, "test_finequad_core",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR),
                                   TABLE_EXACT=sc["exact"], **build),
                   extra_env=dict(SCENARIO=scenario, SAMPLES=n), testcase="core_run")


# ---- stimulus (used by the cocotb test; importable without a simulator) ---------------
PITCH = 20.0                # position units per signal period in these recordings


def highspeed_motion(n):
    """Position (PITCH units) of the highspeed scenario: the signal frequency f / fs of
    HIGHSPEED, piecewise linear, integrated sample by sample."""
    import numpy as np
    k = np.arange(n)
    f = np.zeros(n)
    for a, b, f0, f1 in HIGHSPEED:
        i = (k >= a * n) & (k < b * n)
        f[i] = f0 + (f1 - f0) * (k[i] - a * n) / ((b - a) * n)
    return PITCH * np.concatenate([[0.0], np.cumsum(f[:-1])])


def recording(scenario, n):
    """(u1, u2, strobe edges, reset request list [(sample index, write edge)])."""
    import numpy as np
    from sim import siggen

    scenario = SCENARIOS[scenario].get("like", scenario)      # another build, same signal
    fs, pitch = 1e6, PITCH
    T = n / fs
    sc = n / 20000          # distances scale with the length: the same speeds for any n
    seed = {"uniform": 1, "gaps": 2, "paper": 3, "reset_req": 4, "highspeed": 5,
            "faults": 6, "upsets": 7}[scenario]
    moves = []
    if scenario == "uniform":
        moves = [(160, 0.5, 0.05), (-120, 0.25, 0.6)]       # (um, duration, start) / T
        sig = siggen.Signal()
    elif scenario == "gaps":
        moves = [(90, 0.5, 0.05), (-60, 0.25, 0.6)]
        sig = siggen.Signal(A1=0.2, A2=0.18, m1=0.012, m2=-0.01, phi=-0.05)
    elif scenario == "paper":
        moves = [(300, 0.6, 0.05)]
        sig = siggen.Signal(A1=0.45, A2=0.5, m1=-0.02, m2=0.025, phi=0.1)
    elif scenario == "reset_req":
        moves = [(140, 0.4, 0.05), (160, 0.3, 0.6)]
        sig = siggen.Signal(A1=0.5, A2=0.55)
    elif scenario == "faults":
        moves = [(200, 0.9, 0.05)]
        span = {what: (int(at * n), int(at * n) + ln) for at, what, ln in FAULT_EVENTS}
        sig = siggen.Signal(dropout=(span["loss"] + (0.03,), span["over"] + (1.6,)))
    elif scenario == "upsets":
        moves = [(200, 0.9, 0.05)]
        amp = np.array([UPSETS["before"]] * n, dtype=float)      # A1, A2, m1, m2
        amp[int(UPSETS["step"] * n):] = UPSETS["after"]
        a, b = (int(f * n) for f in UPSETS["flat"])
        amp[a:b, 1] = UPSETS["flat_a2"]
        for f in UPSETS["spikes"]:                               # channel 2 back, briefly
            k = int(f * n)
            amp[k:k + UPSETS["spike_len"], 1] = UPSETS["after"][1]
        sig = siggen.Signal(A1=amp[:, 0], A2=amp[:, 1], m1=amp[:, 2], m2=amp[:, 3],
                            phi=0.06)
    else:
        sig = siggen.Signal()
    x = highspeed_motion(n) if scenario == "highspeed" else np.zeros(n)
    for dist, t_move, t_start in moves:
        x = x + siggen.s_curve(n, fs, dist * sc, t_move * T, t_start * T)
    u1, u2, _ = siggen.encode(x, pitch, sig, seed=seed)
    rng = np.random.default_rng(seed + 100)
    if scenario == "faults":
        a, b = span["stuck"]
        u1[a:b] = u1[a]                                  # channel 1 frozen
        a, b = span["glitch"]
        for k in np.linspace(a, b, 12).astype(int)[1:-1]:
            g = rng.uniform(0, 2 * np.pi)                # one sample at a random angle
            u1[k] = int(0.6 * 32767 * np.cos(g))
            u2[k] = int(0.54 * 32767 * np.sin(g))
        a, b = span["clip"]
        u1[a:b] = 32767                                  # on the rail
    if scenario == "gaps":
        # rail spikes in the second half (after the small signals got input gain 2): clip
        # flags, gain saturation, offset/correction saturation
        for _ in range(max(4, n // 1000)):
            k = int(rng.integers(n // 2, n - 10))
            ln = int(rng.integers(1, 4))
            u1[k:k + ln] = rng.choice([32767, -32768])
            if rng.random() < 0.5:
                u2[k:k + ln] = rng.choice([32767, -32768])
        gaps = rng.choice([1, 1, 1, 2, 3, 5, 9, 14, 20, 30, 36, 45, 60], size=n)
        t = T_FIRST + np.concatenate([[0], np.cumsum(gaps[:-1])])
    else:
        div = 24 if scenario == "paper" else 36
        t0 = T_FIRST_LOAD if SCENARIOS[scenario].get("load") else T_FIRST
        t = t0 + div * np.arange(n, dtype=np.int64)
    requests = []
    if scenario == "reset_req":
        requests = pick_requests(u1, u2, t)
    return u1.astype(np.int64), u2.astype(np.int64), t.astype(np.int64), requests


def _config(scenario, resets, n=None):
    """The model's configuration of a scenario; with a LOAD (faults) the bundle to load
    is the model's final bundle on the same recording of n samples."""
    from sim.model import finequad_core as core
    sc = SCENARIOS[scenario]
    build = sc.get("build", {})
    cfg = core.Config(TABLE="exact" if sc["exact"] else "paper", resets=list(resets),
                      ENGINE_LANES=build.get("ENGINE_LANES", 1),
                      OPT_MONITOR=build.get("OPT_MONITOR", 1), OPT_JUMP=build.get("OPT_JUMP", 1),
                      **sc["regs"])
    if sc.get("load") and n is not None:
        cfg.loads = [(load_edge(cfg), calibration(scenario, n))]
    return cfg


def calibration(scenario, n):
    """A saved calibration: the bundle in use after the model's run without a LOAD."""
    from sim.model import finequad_core as core
    u1, u2, t, _ = recording(scenario, n)
    r = core.run(u1, u2, _config(scenario, []), strobes=t, trace=True)
    assert r["fault"][-1] >> core.FAULT_BITS["uncal"] & 1 == 0, "never calibrated"
    return tuple(int(r[f][-1]) for f in ("g", "m1", "m2", "c1", "c12", "c2"))


# where in the recording the reset requests go (fractions of its length): early enough
# that enough travel follows for a hand-over (settle updates and all eight octants)
REQUEST_AT = (0.15, 0.3, 0.65, 0.75)


def pick_requests(u1, u2, t):
    """Reset requests [(sample k, write edge w)] that the outputs can tell apart from the
    neighbouring sample: one on the latest edge that belongs to k (t_k + RESET_STAGE - 1,
    one edge later would be sample k + 1), one on the earliest (t_(k-1) + RESET_STAGE, one
    edge earlier would be sample k - 1), alternately, during the moves (REQUEST_AT)."""
    import numpy as np
    from sim.model import finequad_core as core

    n = len(u1)

    def outputs(resets):
        r = core.run(u1, u2, _config("reset_req", resets), strobes=t)
        return np.stack([r["count"], r["a"], r["b"], r["fault"]])

    chosen = []
    for i, frac in enumerate(REQUEST_AT):
        latest = i % 2 == 0
        base = [k for k, _ in chosen]
        for k in range(int(n * frac), int(n * frac) + 100):
            alt = k + 1 if latest else k - 1
            if not (outputs(base + [k]) == outputs(base + [alt])).all():
                w = int(t[k]) + estimator.RESET_STAGE - 1 if latest else \
                    int(t[k - 1]) + estimator.RESET_STAGE
                chosen.append((k, w))
                break
        else:
            raise RuntimeError(f"no reset request near {frac} of the recording changes the "
                               "outputs when moved by one sample")
    return chosen


def model_run(scenario, n):
    """Model results for the recording plus the phantom sample (index n)."""
    import numpy as np
    from sim.model import finequad_core as core
    from sim.model.rls_engine import CYCLES

    u1, u2, t, requests = recording(scenario, n)
    start_delay = getattr(core, "START_DELAY", 0)
    t_ph = int(t[-1]) + estimator.PHASE_STAGE + start_delay + max(CYCLES.values()) + 16
    cfg = _config(scenario, [k for k, _ in requests] + [n], n)
    res = core.run(np.append(u1, u1[-1]), np.append(u2, u2[-1]), cfg,
                   strobes=np.append(t, t_ph), trace=True)
    return u1, u2, t, requests, t_ph, res


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402


async def _watch(sig, log):
    """Record every change of a 1-bit output as (time in ps, new value)."""
    from cocotb.triggers import ValueChange
    from cocotb.utils import get_sim_time
    while True:
        await ValueChange(sig)
        log.append((get_sim_time(unit="ps"), fqtb.uval(sig)))


def _intervals(edges):
    out = []
    for e in sorted(edges):
        if out and out[-1][1] == e - 1:
            out[-1][1] = e
        else:
            out.append([e, e])
    return [tuple(x) for x in out]


# x4 quadrature decoder, independent of rtl/abgen.v and sim/model/abgen.py: the Gray
# sequence (A, B) = (1,1) -> (0,1) -> (0,0) -> (1,0) -> (1,1) counts up (rtl/README.md, Paced A/B outputs)
GRAY_UP = {(1, 1): 0, (0, 1): 1, (0, 0): 2, (1, 0): 3}


def check_ab_pins(ab_log, ab_init, bench, cfg, final_count, scenario):
    """Every change of m_a / m_b since power-up: on a clock edge, never both on one edge,
    at least ab_sep clocks (0 as 1) between two edges, and an x4 decoder counting them
    from (1, 1) = 0 ends on the final count (mod 2^COUNT_W)."""
    assert ab_init == (1, 1), f"A/B after power-up {ab_init}, expected (1, 1)"
    ev = {}
    for ch, log in ab_log.items():
        for tm, v in log:
            e, r = divmod(tm - bench.t0, fqtb.PERIOD_PS)
            assert r == 0, f"m_{ch} changed between clock edges (t={tm} ps)"
            assert e not in ev, f"{scenario}: A and B both changed after edge {e}"
            ev[e] = (ch, v)
    sep = max(cfg.ab_sep, 1)
    state, pos, last, bad = ab_init, 0, None, []
    for e in sorted(ev):
        ch, v = ev[e]
        nxt = (v, state[1]) if ch == "a" else (state[0], v)
        assert nxt != state, f"{scenario}: m_{ch} 'changed' to its own value after edge {e}"
        if last is not None and e - last < sep:
            bad.append(f"edges {last} and {e}: {e - last} clocks apart (minimum {sep})")
        step = (GRAY_UP[nxt] - GRAY_UP[state]) % 4
        pos += 1 if step == 1 else -1           # step 2 would need both pins: excluded
        state, last = nxt, e
    assert not bad, f"{scenario}: {len(bad)} A/B edges too close, first: {bad[:5]}"
    w = 1 << cfg.COUNT_W
    dec = (pos + w // 2) % w - w // 2
    assert dec == final_count, (f"{scenario}: an x4 decoder of the A/B pins reads {dec} "
                                f"after {len(ev)} edges, the counter ended on {final_count}")


def check_truth(scenario, res, n, log):
    """The phase-mode count minus 4 n x / pitch (the truth in counts) stays within pitch /
    8 of its median (no slips) on every sample the monitor trusts (no loss, stuck,
    glitch or clip flag), from calibration on (faults: from the first sample: a calibration
    was loaded), except while an injected loss, stuck channel or clip lasts: the count is
    held, or follows a distorted phase until the stuck channel is flagged, and must be
    right again as soon as the signal is back. highspeed: the signal frequency reaches 0.4 fs, the A/B backlog overflowed
    and overspeed (>= 3/4 pi per sample) was flagged; faults: every fault was flagged."""
    import numpy as np
    cfg = _config(scenario, [])
    f = np.asarray(res["fault"][:n])
    bit = core_model.FAULT_BITS

    def flag(name):
        return ((f >> bit[name]) & 1).astype(bool)

    if scenario == "highspeed":
        x = highspeed_motion(n)
        cal = np.nonzero(~flag("uncal"))[0]
        assert len(cal), "highspeed: never calibrated"
        start = int(cal[0])
        fmax = float(np.diff(x).max() / PITCH)
        assert fmax > 0.399, f"highspeed: the motion peaks at {fmax:.3f} fs, not 0.4 fs"
        need = ("abovf", "ovs")
    else:
        from sim import siggen
        x = sum(siggen.s_curve(n, 1e6, d * n / 20000, tm * n / 1e6, ts * n / 1e6)
                for d, tm, ts in [(200, 0.9, 0.05)])
        start = 0
        need = ("loss", "stuck", "glitch", "over", "clip")
        assert flag("uncal")[0] and not flag("uncal")[-1] and res["loaded"][0] == 1
        during = np.zeros(n, dtype=bool)
        for at, what, ln in FAULT_EVENTS:
            if what in ("loss", "stuck", "clip"):
                during[int(at * n):int(at * n) + ln] = True
    per_period = 4 * cfg.interp                  # counts per signal period
    trusted = ~(flag("loss") | flag("stuck") | flag("glitch") | flag("clip"))
    trusted[:start] = False
    if scenario == "faults":
        trusted &= ~during
    err = np.asarray(res["count"][:n]) - per_period * x / PITCH
    e = err[trusted] - np.median(err[trusted])
    worst = float(np.abs(e).max())
    assert worst < SLIP * per_period, (f"{scenario}: the counter is {worst:.2f} counts off "
                                       f"the truth (a slip is > {SLIP * per_period:g})")
    for name in need:
        assert flag(name).any(), f"{scenario}: no {name} flag"
    log.info("%s: counter within %.2f counts (pitch/%d) of the truth on %d trusted samples "
             "from sample %d; flags %s", scenario, worst, per_period, int(trusted.sum()),
             start, {nm: int(flag(nm).sum()) for nm in need})


@cocotb.test()
async def core_run(dut):
    import numpy as np

    scenario = fqtb.env_str("SCENARIO")
    n = fqtb.env_int("SAMPLES")
    u1, u2, t, requests, t_ph, res = model_run(scenario, n)
    log = dut._log
    log.info("scenario %s: %d samples, last strobe on edge %d, %d model updates",
             scenario, n, int(t[-1]), res["n_updates"])
    if scenario == "upsets":
        # the recording must reach every exception it is there for (in the model)
        hold = (res["fault"][:n] >> core_model.FAULT_BITS["hold"]) & 1
        cfg0 = _config(scenario, [], n)
        assert res["jumps"], "upsets: the jump detector never fired"
        assert res["invalid_updates"] >= 2, "upsets: fewer than two invalid updates"
        assert hold.any() and not hold[-1], \
            "upsets: no failed extraction held the bundle, or the hold never ended"
        assert res["sat"], "upsets: the engine saturated no register"
        assert (5 * cfg0.kappa) >> 4 >= 1 << 14, "upsets: 5 kappa fits 14 bits"

    # ---- schedule: slot e = between edge e and e + 1 -------------------------------------
    strobe = {int(e): k for k, e in enumerate(t)}
    reads = {int(e) + OUT_LATENCY: k for k, e in enumerate(t)}   # slot t_k + LATENCY
    cfg = _config(scenario, [], n)
    reg_writes = dict(enumerate(setup_writes(cfg)))             # edges 0, 1, ...
    assert max(reg_writes) < int(t[0])
    for k, w in requests:
        assert w not in reg_writes
        reg_writes[w] = (regs.CTRL, ctrl_word(cfg, cov_reset=1))
    # mid-run: a capture (CTRL bit 2) on the output edge of sample kc (it latches m_count
    # one edge later: kc's count; kc the sample nearest the middle whose count differs
    # from the final one), and FAULT_STICKY cleared (write 1s) on the edge that ORs
    # sample kf's fault word in: kf's bits stay. kf: the last sample with a fault bit no
    # later sample has (so the clear winning over the fault shows), where the scenario has
    # one after a bit that no sample from kf on has (so a clear that does nothing shows
    # here too; the writes after the run test the clear itself in every scenario)
    cnt = np.asarray(res["count"][:n])
    kc = min(np.nonzero(cnt != cnt[n - 1])[0], key=lambda k: abs(k - n // 2), default=None)
    assert kc is not None, f"{scenario}: the count never differs from its final value"
    w_cap = int(t[kc]) + OUT_LATENCY
    faults = np.asarray(res["fault"][:n], dtype=np.int64)
    later = np.bitwise_or.accumulate(np.concatenate([[0], faults[::-1]]))[::-1]  # OR of k..n-1
    before = np.bitwise_or.accumulate(np.concatenate([[0], faults]))            # OR of 0..k-1
    own = [k for k in range(n - 1, -1, -1) if faults[k] & ~later[k + 1]]
    kf = next((k for k in own if before[k] & ~later[k]), own[0] if own else None)
    assert kf is not None, f"{scenario}: no fault word to clear in the middle of the run"
    w_clr = int(t[kf]) + OUT_LATENCY + 1
    for w, wd in ((w_cap, (regs.CTRL, ctrl_word(cfg, capture=1))),
                  (w_clr, (regs.FAULT_STICKY, (1 << core_model.FAULT_W) - 1))):
        assert w not in reg_writes and w > int(t[0]), w
        reg_writes[w] = wd
    slots = set()
    for e in strobe:
        slots.add(e - 1)
        slots.add(e)
    slots.update(reads)
    for e in reg_writes:
        slots.add(e - 1)
        slots.add(e)
    slots = sorted(slots)

    got = np.zeros((n, 5), dtype=np.int64)          # m_valid, count, a, b, fault
    # the backlog register is read on every edge (reg_re high, reg_addr = BACKLOG) except
    # where a write takes reg_addr; each sample's output slot records it
    got_bl = np.zeros(n, dtype=np.int64)
    bench = fqtb.ClockedBench(dut)
    dut.rst.value = 0
    dut.s_valid.value = 0
    dut.s_u1.value = 0
    dut.s_u2.value = 0
    dut.s_ref.value = 0
    dut.reg_we.value = 0
    dut.reg_re.value = 0
    dut.reg_addr.value = 0
    dut.reg_wdata.value = 0
    await bench.start()
    vlog, ab_log = [], {"a": [], "b": []}
    ab_init = (fqtb.uval(dut.m_a), fqtb.uval(dut.m_b))
    cocotb.start_soon(_watch(dut.m_valid, vlog))
    cocotb.start_soon(_watch(dut.m_a, ab_log["a"]))
    cocotb.start_soon(_watch(dut.m_b, ab_log["b"]))
    for s in slots:
        await bench.goto(s)
        k = reads.get(s)
        if k is not None:
            got[k] = (fqtb.uval(dut.m_valid), fqtb.sval(dut.m_count), fqtb.uval(dut.m_a),
                      fqtb.uval(dut.m_b), fqtb.uval(dut.m_fault))
            got_bl[k] = fqtb.uval(dut.reg_rdata)
        nxt = s + 1
        k = strobe.get(nxt)
        if k is not None:
            dut.s_valid.value = 1
            dut.s_u1.value = int(u1[k])
            dut.s_u2.value = int(u2[k])
        elif s in strobe:
            dut.s_valid.value = 0
        if nxt in reg_writes:
            a, d = reg_writes[nxt]
            dut.reg_we.value = 1
            dut.reg_addr.value = a
            dut.reg_wdata.value = d
        elif s in reg_writes:
            dut.reg_we.value = 0
        if s + 1 == int(t[0]):
            dut.reg_re.value = 1
        if nxt not in reg_writes and nxt >= int(t[0]):
            dut.reg_addr.value = BACKLOG

    # ---- output latency (a clear message when the pipeline depth changed) -----------------
    first_rise = next((tm for tm, v in vlog if v == 1), None)
    assert first_rise is not None, "m_valid never went high"
    lat = (first_rise - bench.t0) // fqtb.PERIOD_PS - int(t[0])
    assert lat == OUT_LATENCY, (f"the first sample (strobe edge {int(t[0])}) came out after "
                                f"edge t + {lat}, the test expects t + {OUT_LATENCY}")

    # ---- every sample --------------------------------------------------------------------
    exp = np.stack([np.ones(n + 1, dtype=np.int64), res["count"], res["a"], res["b"],
                    res["fault"]], axis=1)[:n]
    diff = np.nonzero((got != exp).any(axis=1))[0]
    if len(diff):
        lines = []
        for k in diff[:12]:
            tr = {f: int(res[f][k]) for f in ("g", "m1", "m2", "c1", "c12", "c2", "u1c", "u2c",
                                             "phase")}
            lines.append(f"sample {k} (strobe edge {int(t[k])}, u=({int(u1[k])},{int(u2[k])})):"
                         f" rtl (valid,count,a,b,fault)={tuple(int(x) for x in got[k])}, model "
                         f"{tuple(int(x) for x in exp[k])}; model trace {tr}")
        raise AssertionError(f"{scenario}: {len(diff)} of {n} samples differ, first:\n" +
                             "\n".join(lines))
    # the backlog register after each output edge (not where a write took the address)
    rd_edges = [int(e) + OUT_LATENCY for e in t]
    exp_bl = np.array(backlog_at(res["count_raw"][:n], t, rd_edges, cfg), dtype=np.int64)
    seen = np.array([e not in reg_writes for e in rd_edges])
    diff = np.nonzero(seen & (got_bl != exp_bl))[0]
    if len(diff):
        lines = [f"sample {k} (output edge {rd_edges[k]}): rtl {int(got_bl[k]):#x}, "
                 f"model {int(exp_bl[k]):#x}" for k in diff[:12]]
        raise AssertionError(f"{scenario}: AB_BACKLOG differs at {len(diff)} of "
                             f"{int(seen.sum())} samples, first:\n" + "\n".join(lines))

    # ---- m_valid high after exactly the edges t_k + LATENCY --------------------------------
    await bench.goto(max(bench.edge, int(t[-1]) + OUT_LATENCY + 2))
    high, rise = [], None
    for tm, v in vlog:
        e, r = divmod(tm - bench.t0, fqtb.PERIOD_PS)
        assert r == 0, f"m_valid changed between clock edges (t={tm} ps)"
        if v == 1 and rise is None:
            rise = e
        elif v == 0 and rise is not None:
            high.append((rise, e - 1))
            rise = None
    assert rise is None
    want = _intervals(int(e) + OUT_LATENCY for e in t)
    if high != want:
        extra = sorted(set(high) ^ set(want))[:6]
        raise AssertionError(f"m_valid high intervals differ from the strobes + {OUT_LATENCY}: "
                             f"{len(high)} vs {len(want)}, first differences {extra}")

    # ---- registers after the run -----------------------------------------------------------
    dut.reg_re.value = 0
    await bench.goto(t_ph + 2)

    rd, wr = bench.reg_read, bench.reg_write

    def u32(v):
        return int(v) & 0xFFFFFFFF

    ph = n                                  # the phantom's index in the model results
    bad = []

    def check(what, got_v, exp_v):
        if got_v != exp_v:
            bad.append(f"{what}: rtl {got_v:#x}, model {exp_v:#x}")

    check(f"CAPTURE (CTRL.capture on edge {w_cap}, sample {kc})", await rd(regs.CAPTURE),
          u32(res["count"][kc]))

    check("ID", await rd(regs.ID), core_model.ID)
    for name in ("INTERP", "EPS", "LAMBDA_K", "KAPPA", "PERIOD", "SETTLE", "GATE", "HARM",
                 "JUMP", "ABGEN", "AB_BOUND", "CLIP", "RADIUS", "MONITOR"):
        check(name, await rd(regs.REGS[name].index), readback(cfg, name))
    check("COUNT", await rd(regs.COUNT), u32(res["count"][n - 1]))
    check("ILLEGAL", await rd(regs.ILLEGAL), int(np.sum(res["ill"][:n])) & 0xFFFF)
    check("UPDATES", await rd(regs.UPDATES), u32(res["n_updates"]))
    fault_ph = int(res["fault"][ph])
    fb = core_model.FAULT_BITS
    check("STATUS", await rd(regs.STATUS),
          regs.word_read("STATUS", uncal=(fault_ph >> fb["uncal"]) & 1,
                         hold=(fault_ph >> fb["hold"]) & 1, sat=int(res["sat"]),
                         count_mode=cfg.count_mode, loaded=int(res["loaded"][ph])))
    check("TRAVEL", await rd(regs.TRAVEL), int(res["travel"][n - 1]))   # real samples only
    check("GAIN", await rd(regs.GAIN), int(res["g"][ph]))
    check("JUMPS", await rd(regs.JUMPS), len(res["jumps"]) & 0xFFFF)
    if not cfg.OPT_MONITOR:
        held = sum(1 << core_model.FAULT_BITS[b] for b in ("loss", "over", "stuck", "glitch"))
        assert not np.bitwise_and(res["fault"][:n], held).any(), \
            f"{scenario}: a fault check flagged without the monitor's checks"
        full = core_model.run(np.asarray(u1), np.asarray(u2),
                              _config(SCENARIOS[scenario]["like"], [], n), strobes=t)
        assert np.bitwise_and(full["fault"][:n], held).any(), \
            f"{scenario}: the signal has no fault for the full monitor to flag"
    if not cfg.OPT_JUMP:
        assert not res["jumps"], f"{scenario}: a jump without the jump detector"
        import dataclasses
        assert core_model.run(np.asarray(u1), np.asarray(u2),
                              dataclasses.replace(_config(scenario, [], n), OPT_JUMP=1),
                              strobes=t)["jumps"], \
            f"{scenario}: the jump detector would not fire on this signal"
    bl_got = await rd(BACKLOG)
    check(f"AB_BACKLOG (after edge {bench.edge})", bl_got,
          backlog_at(res["count_raw"][:n], t, [bench.edge], cfg)[0])
    for f in ("m1", "m2", "c1", "c12", "c2"):
        check(f.upper(), await rd(regs.REGS[f.upper()].index), u32(res[f][ph]))
    # (cleared on sample kf's edge, which ORs kf's word in)
    sticky = int(later[kf])
    check(f"FAULT_STICKY (cleared with sample {kf})", await rd(regs.FAULT_STICKY), sticky)
    # write 1 to clear: a read-only register first (no effect), then two steps
    await wr(regs.ID, 0)
    check("ID after a write", await rd(regs.ID), core_model.ID)
    cleared = 0
    for ones in (0x15, 0x00, 0x40, 0x7F, (1 << core_model.FAULT_W) - 1):
        await wr(regs.FAULT_STICKY, ones)
        cleared |= ones
        check(f"FAULT_STICKY after writing {ones:#x}", await rd(regs.FAULT_STICKY),
              sticky & ~cleared)
    # a capture (CTRL.capture) of the count; reading the count register does not latch
    await wr(regs.CTRL, ctrl_word(cfg, capture=1))
    check("CAPTURE", await rd(regs.CAPTURE), u32(res["count"][n - 1]))
    assert not bad, f"{scenario}: register read-back differs:\n" + "\n".join(bad)

    # ---- the A/B pins, edge by edge (paced outputs only) ------------------------------------
    if not cfg.ab_src:
        # let the pins pay any backlog left (one count per ab_sep clocks), then decode
        left = abs(backlog_at(res["count_raw"][:n], t, [bench.edge], cfg)[0])
        await bench.goto(bench.edge + left * max(cfg.ab_sep, 1) + 4)
        check_ab_pins(ab_log, ab_init, bench, cfg, int(res["count"][n - 1]), scenario)

    # ---- the counter against the truth ------------------------------------------------------
    if scenario in ("highspeed", "faults"):
        check_truth(scenario, res, n, log)

    f = res["fault"][:n]
    cov = {name: int(((f >> bit) & 1).sum()) for name, bit in
           core_model.FAULT_BITS.items()}
    bl = exp_bl.astype(np.uint32).astype(np.int32)
    log.info("scenario %s: %d samples equal (fault bit counts %s), g %s, final count %d, "
             "sticky %#x, %d jumps, A/B backlog nonzero at %d samples (max %d)", scenario, n,
             cov, sorted(set(res["g"][:n].tolist())), int(res["count"][n - 1]), sticky,
             len(res["jumps"]), int((bl != 0).sum()), int(np.abs(bl).max()))
