"""Closed-loop simulation of the paper's single-axis slider (Ulu et al. 2014, Sec. 3, Fig. 12).

A slider driven by a permanent-magnet linear motor follows a 7 um S-curve under a
discrete PID controller. The position the controller sees is the count of the bit-true
model of the core (sim/model/finequad_core.py, proved equal to the RTL elsewhere), fed piece by
piece with the encoder signals (sim/siggen.py) of the plant's true position: one piece
of `samples_per_tick` ADC samples per control period, so the measurement has exactly the
resolution, the noise and the interpolation errors of the gateware.

Plant (SI units; `Slider`):

    m dv/dt = F_motor + F_dist - b v - F_c sgn(v),    dx/dt = v
    F_motor = clip(u, -F_max, F_max)   (u from the controller, held over the period)
    stiction: at v = 0 the slider stays put while |F_motor + F_dist| <= F_c

Between two control ticks the force is constant, so the motion is solved exactly
(exponential approach to (F - F_c sgn v) / b, with the events where v reaches 0: stick
or reverse), evaluated at every ADC sample instant; no integration step size enters.

The paper describes its slider only as "driven by a permanent magnet linear motor",
1 um encoder resolution (a 4 um signal period, METHOD.md), 120 mm travel; it gives no
mass, friction or gains. The defaults below are typical of such a slider (an ironless
linear motor on a preloaded linear guide, a small aluminium carriage) and are labelled
as our assumptions:

    mass_kg        2.0    carriage, motor coil, readhead
    viscous_Ns_m   10.0   guide lubricant and seals (a current-mode amplifier adds no
                          back-EMF damping)
    coulomb_N      1.0    preloaded miniature ball guide, two carriages with seals
    force_limit_N  50.0   peak force of a small ironless motor with its amplifier
    dist_bias_N    0.3    constant drag of the cable carrier
    dist_rms_N     0.02   amplifier current noise (about 1 mA RMS at 20 N/A), white at
                          the control rate, seeded

Controller (`Pid`): parallel PID on the error e = r - y at `loop_hz` (10 kHz: the
core's 1 MS/s in pieces of 100 samples), derivative through a first-order low-pass
(`d_cutoff_hz`, 1 kHz), integrator with clamping anti-windup, output limited to
force_limit_N. The gains place the three closed-loop poles of the rigid slider
(m s^3 + (b + Kd) s^2 + Kp s + Ki) at -w, w = 2 pi `bandwidth_hz` (50 Hz, a typical
positioning bandwidth for such a slider at a 10 kHz loop):

    Kp = 3 m w^2,   Ki = m w^3,   Kd = 3 m w - b

Experiment (`Experiment`): 20 ms at rest, the 7 um S-curve (sinusoidal acceleration,
siggen.s_curve's profile: peak speed 70 um/s, peak acceleration 1.1 mm/s^2) in 0.2 s,
0.1 s at rest; 3200 control ticks. The RMS tracking error is taken over all of it.

The same gains serve "without interpolation" (the x4 count of the encoder's own signal,
n = 1: pitch / 4 = 1 um) and "with interpolation" (n = 100: 10 nm), as in the paper.

Measurement: the controller takes the count c of the last sample of the previous period
(the core's latency, 8 clocks at 36 MHz, is far below a period) as the position
y = (c + 1/2) q, q = pitch / (4 n): the centre of the count's cell, so that the
quantiser is unbiased. The reference starts at the measured position when the loop
starts, r(t) = y(0) + S(t). The true tracking error is r(t) - x(t) with x the true
position in the scale's frame (the count's arbitrary whole number of signal periods at
power-up, and the arbitrary start of the edge mode's x4 count, are removed once, at
rest before the loop starts; see `run`); before the loop starts, the stage makes a
homing move of ten signal periods so that the estimator has calibrated.
"""
from dataclasses import dataclass, field, replace

import numpy as np

from . import siggen
from .model import finequad_core as core
from .model import regs


# ---------------------------------------------------------------------------- plant

@dataclass
class Slider:
    """Rigid slider on a linear motor: mass, viscous and Coulomb friction, force limit,
    force disturbance (a constant plus white noise held over each control period)."""
    mass_kg: float = 2.0
    viscous_Ns_m: float = 10.0
    coulomb_N: float = 1.0
    force_limit_N: float = 50.0
    dist_bias_N: float = 0.3
    dist_rms_N: float = 0.02

    def __post_init__(self):
        bad = [f"{k} must be > 0, got {v!r}" for k, v in
               (("mass_kg", self.mass_kg), ("viscous_Ns_m", self.viscous_Ns_m),
                ("force_limit_N", self.force_limit_N)) if not v > 0]
        bad += [f"{k} must be >= 0, got {v!r}" for k, v in
                (("coulomb_N", self.coulomb_N), ("dist_rms_N", self.dist_rms_N))
                if not v >= 0]
        if not np.isfinite(self.dist_bias_N):
            bad.append(f"dist_bias_N must be finite, got {self.dist_bias_N!r}")
        if bad:
            raise ValueError("Slider: " + "; ".join(bad))

    def advance(self, x, v, force, times):
        """Exact motion under a constant total external force `force` (N, motor plus
        disturbance) from state (x m, v m/s) at time 0. Returns (positions at `times`
        (s, ascending, >= 0), x and v at times[-1])."""
        times = np.asarray(times, float)
        if times.ndim != 1 or len(times) == 0 or times[0] < 0 or np.any(np.diff(times) < 0):
            raise ValueError("advance: times must be a non-empty ascending 1-D array >= 0")
        m, b, fc = self.mass_kg, self.viscous_Ns_m, self.coulomb_N
        tau = m / b
        out = np.empty(len(times))
        t0, i, n = 0.0, 0, len(times)
        x, v = float(x), float(v)
        while i < n:
            if v == 0.0:
                if abs(force) <= fc:              # stuck for the rest of the period
                    out[i:] = x
                    return out, x, 0.0
                s = np.sign(force)
            else:
                s = np.sign(v)
            vinf = (force - s * fc) / b           # terminal speed in this regime
            t_zero = np.inf                       # when v reaches 0 (if it does)
            if s * vinf < 0:
                t_zero = t0 + tau * np.log((v - vinf) / -vinf)
            j = i + int(np.searchsorted(times[i:], t_zero, side="left"))
            dt = times[i:j] - t0
            decay = np.exp(-dt / tau)
            out[i:j] = x + vinf * dt + (v - vinf) * tau * (1 - decay)
            if j == n:
                dt = times[-1] - t0
                decay = np.exp(-dt / tau)
                return out, x + vinf * dt + (v - vinf) * tau * (1 - decay), \
                    vinf + (v - vinf) * decay
            dt = t_zero - t0                      # v = 0 inside the period: stick or reverse
            x = x + vinf * dt + (v - vinf) * tau * (1 - (-vinf) / (v - vinf))
            v = 0.0
            t0, i = t_zero, j
        return out, x, v


# ---------------------------------------------------------------------------- controller

@dataclass
class Pid:
    """Discrete PID (parallel form) with a low-pass derivative and clamping anti-windup.

    u_k = Kp e_k + I_k + Kd d_k, clipped to +-limit;  d_k = a d_(k-1) + (1 - a)(e_k -
    e_(k-1)) / T, a = exp(-2 pi f_d T) (d_0 = 0);  I_(k+1) = I_k + Ki T e_k unless the
    output is saturated and e_k pushes further into the limit."""
    kp: float
    ki: float
    kd: float
    period_s: float
    d_cutoff_hz: float
    limit: float
    integ: float = 0.0
    e_prev: float = None
    d: float = 0.0

    def __post_init__(self):
        if not (self.period_s > 0 and self.d_cutoff_hz > 0 and self.limit > 0):
            raise ValueError(f"Pid: period_s, d_cutoff_hz and limit must be > 0, got "
                             f"{self.period_s}, {self.d_cutoff_hz}, {self.limit}")
        if min(self.kp, self.ki, self.kd) < 0:
            raise ValueError(f"Pid: gains must be >= 0, got Kp={self.kp}, Ki={self.ki}, "
                             f"Kd={self.kd}")
        self.alpha = float(np.exp(-2 * np.pi * self.d_cutoff_hz * self.period_s))

    def step(self, e):
        if self.e_prev is not None:
            self.d = self.alpha * self.d + (1 - self.alpha) * (e - self.e_prev) / self.period_s
        self.e_prev = e
        u_raw = self.kp * e + self.integ + self.kd * self.d
        u = min(max(u_raw, -self.limit), self.limit)
        if u == u_raw or (u_raw > self.limit) != (e > 0):
            self.integ += self.ki * self.period_s * e
        return u


def pid_gains(slider: Slider, bandwidth_hz):
    """(Kp N/m, Ki N/(m s), Kd N s/m): triple closed-loop pole at -2 pi bandwidth_hz."""
    if not bandwidth_hz > 0:
        raise ValueError(f"bandwidth_hz must be > 0, got {bandwidth_hz!r}")
    w = 2 * np.pi * bandwidth_hz
    m = slider.mass_kg
    kd = 3 * m * w - slider.viscous_Ns_m
    if kd < 0:
        raise ValueError(f"bandwidth {bandwidth_hz} Hz is below what the viscous friction "
                         f"alone gives (Kd would be {kd:.3g} N s/m < 0)")
    return 3 * m * w ** 2, m * w ** 3, kd


# ---------------------------------------------------------------------------- experiment

@dataclass
class Experiment:
    """The Fig. 12 experiment. Lengths in nm, times in s."""
    slider: Slider = field(default_factory=Slider)
    sig: siggen.Signal = field(default_factory=siggen.Signal)
    pitch_nm: float = 4000.0
    fs: float = 1e6                    # ADC sample rate
    samples_per_tick: int = 100        # control period = samples_per_tick / fs
    bandwidth_hz: float = 50.0
    d_cutoff_hz: float = 1000.0
    stroke_nm: float = 7000.0          # the S-curve (siggen.s_curve)
    t_before: float = 0.02             # dwell before the move
    t_move: float = 0.2
    t_after: float = 0.1               # dwell after it
    home_nm: float = 40000.0           # homing move before the loop starts (calibration)
    home_speed_nm_s: float = 2e6
    start_nm: float = 1e6              # where the homing move starts (scale frame)
    seed: int = 1

    def __post_init__(self):
        bad = []
        if not (isinstance(self.samples_per_tick, (int, np.integer)) and self.samples_per_tick >= 1):
            bad.append(f"samples_per_tick must be an integer >= 1, got {self.samples_per_tick!r}")
        for k in ("pitch_nm", "fs", "t_move", "home_nm", "home_speed_nm_s"):
            if not getattr(self, k) > 0:
                bad.append(f"{k} must be > 0, got {getattr(self, k)!r}")
        for k in ("t_before", "t_after"):
            if not getattr(self, k) >= 0:
                bad.append(f"{k} must be >= 0, got {getattr(self, k)!r}")
        if bad:
            raise ValueError("Experiment: " + "; ".join(bad))

    @property
    def period_s(self):
        return self.samples_per_tick / self.fs

    def reference(self):
        """S(t) at the control ticks (nm, from 0), and the tick count."""
        ticks = int(round((self.t_before + self.t_move + self.t_after) / self.period_s))
        t = np.arange(ticks) * self.period_s
        tau = np.clip((t - self.t_before) / self.t_move, 0.0, 1.0)
        return self.stroke_nm * (tau - np.sin(2 * np.pi * tau) / (2 * np.pi)), ticks


def run(exp: Experiment, interp, cfg: core.Config = None):
    """One closed-loop run with the core counting at `interp` (cfg: the core's other
    settings, default Config()). Returns a dict of arrays per control tick (t s, ref_nm,
    meas_nm, true_nm at the tick, force_N motor, err_true_nm = r - x, err_meas_nm = r - y)
    and per ADC sample (x_nm), and the summary numbers (RMS in nm)."""
    f = regs.SETTINGS["interp"]
    if not (isinstance(interp, (int, np.integer)) and f.lo <= interp <= f.hi):
        raise ValueError(f"interp must be an integer {f.lo}..{f.hi}, got {interp!r}")
    cfg = replace(cfg or core.Config(), interp=int(interp))
    sl = exp.slider
    q = exp.pitch_nm / (4 * interp)
    c = core.Core(cfg)
    # homing: a jerk-limited move of home_nm, then 5 ms at rest (open loop; the
    # estimator calibrates on it)
    xh = exp.start_nm + siggen.jerk_limited(exp.home_nm, exp.home_speed_nm_s, 1e9, 1e11,
                                            exp.fs)
    xh = np.concatenate([xh, np.full(int(0.005 * exp.fs), xh[-1])])
    u1, u2, _ = siggen.encode(xh, exp.pitch_nm, exp.sig, seed=[exp.seed, 0])
    res = c.feed(u1, u2, trace=True)
    uncal = (int(res["fault"][-1]) >> core.FAULT_BITS["uncal"]) & 1
    if uncal:
        raise RuntimeError("closedloop: the core did not calibrate during the homing move")
    x0 = float(xh[-1])
    # Zero of the measurement, set once at rest after the homing: the phase-mode count
    # (count_phase, computed in both counter modes) is floor(4 n Phi / 8192) of the
    # unwrapped fine phase, aligned to the absolute phase up to whole signal periods;
    # the edge mode's x4 count starts from an arbitrary quadrant, so its offset to the
    # phase-mode count is taken here too (what a reference mark would give).
    c_ph = int(res["count_phase"][-1])
    offset = c_ph - int(res["count"][-1])
    y_raw = (c_ph + 0.5) * q
    shift = exp.pitch_nm * round((x0 - y_raw) / exp.pitch_nm)

    S, ticks = exp.reference()
    kp, ki, kd = pid_gains(sl, exp.bandwidth_hz)
    pid = Pid(kp, ki, kd, exp.period_s, exp.d_cutoff_hz, sl.force_limit_N)
    rng = np.random.default_rng([exp.seed, 1])
    dist = sl.dist_bias_N + sl.dist_rms_N * rng.standard_normal(ticks)
    spt = exp.samples_per_tick
    ts = np.arange(spt) / exp.fs
    x_m, v = x0 * 1e-9, 0.0
    y0 = y_raw + shift
    out = {k: np.empty(ticks) for k in ("ref_nm", "meas_nm", "true_nm", "force_N")}
    x_all = np.empty(ticks * spt)
    y = y0
    for k in range(ticks):
        r = y0 + S[k]
        u = pid.step((r - y) * 1e-9)
        out["ref_nm"][k], out["meas_nm"][k], out["true_nm"][k] = r, y, x_m * 1e9
        out["force_N"][k] = u
        xs, x_m, v = sl.advance(x_m, v, u + dist[k], np.append(ts[1:], exp.period_s))
        # samples of this period: the tick instant and the next spt - 1
        xk = np.concatenate([[out["true_nm"][k] * 1e-9], xs[:-1]]) * 1e9
        x_all[k * spt:(k + 1) * spt] = xk
        u1, u2, _ = siggen.encode(xk, exp.pitch_nm, exp.sig, seed=[exp.seed, 2, k])
        res = c.feed(u1, u2)
        y = (int(res["count"][-1]) + offset + 0.5) * q + shift
    out["t"] = np.arange(ticks) * exp.period_s
    out["x_nm"] = x_all
    out["err_true_nm"] = out["ref_nm"] - out["true_nm"]
    out["err_meas_nm"] = out["ref_nm"] - out["meas_nm"]
    out["rms_true_nm"] = float(np.sqrt(np.mean(out["err_true_nm"] ** 2)))
    out["rms_meas_nm"] = float(np.sqrt(np.mean(out["err_meas_nm"] ** 2)))
    out["peak_true_nm"] = float(np.max(np.abs(out["err_true_nm"])))
    out["illegal_steps"] = int(res["illegal_count"])
    out["gains"] = dict(kp_N_per_m=kp, ki_N_per_m_s=ki, kd_Ns_per_m=kd)
    out["resolution_nm"] = q
    return out
