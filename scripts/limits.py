#!/usr/bin/env python3
"""Speed and resolution limits of an interpolator build (Eq. 13 of the paper, Nyquist).

    python3 scripts/limits.py --pitch UM --fs HZ [--v M_PER_S | --interp N]
                              [--ab-sep CLOCKS] [--fclk HZ]

  --pitch     signal period of the scale, um (4 for the paper's slider)
  --fs        sample rate of the ADC, Hz
  --v         a speed, m/s: prints the highest interpolation factors at that speed
  --interp    an interpolation factor n: prints the highest speeds for it
  --ab-sep    minimum separation of A/B output edges, clocks (ABGEN.ab_sep; default its
              reset value)
  --fclk      clock of the core, Hz (default 36e6)

Limits (x4 counting: one count per quarter of an n-th order period, pitch / (4 n)):
  paper's edge counter (Eq. 13): the n-th order sinusoid must move less than a quarter
      period per sample: v < pitch fs / (4 n)   (N_n = 4 samples per n-th order period)
  A/B outputs: at most one edge per ab_sep clocks: v <= pitch fclk / (4 n ab_sep)
  internal fine-phase counter: the angle step per sample must stay below pi (Nyquist);
      the core flags overspeed from 3/4 pi, so v < 3/8 pitch fs is the usable range,
      independent of n.
  counters behind the A/B pins: the edge separation ab_sep / fclk must be at least what
      their input filter needs (sim/counters.py); a faster one loses counts silently.
  Z (reference marks, rtl/refmark.v): one count wide at the pins at any speed (the paced
      pins step one count at a time and Z marks one of them); a reference is found while
      the stage moves less than w / 2 / max(1, ref_filt) per sample (w the window's width,
      REF.ref_filt the glitch filter: --ref-width, --ref-filt) and below the internal
      counter's limit (a crossing on an overspeed sample is not taken); above the A/B
      limit Z comes as late as the pins' backlog.
"""
import argparse
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from sim import counters  # noqa: E402
from sim.model.regs import SETTINGS  # noqa: E402

N_MAX = SETTINGS["interp"].hi   # the core's largest n (INTERP)


def limits(pitch_um, fs, ab_sep=SETTINGS["ab_sep"].reset, fclk=36e6, v=None, interp=None,
           ref_width=0.5, ref_filt=SETTINGS["ref_filt"].reset):
    """Dict of the limits (speeds in m/s, factors as floats before rounding down)."""
    p = pitch_um * 1e-6
    out = {"counter_v_max": 3 / 8 * p * fs, "nyquist_v": p * fs / 2}
    # Z: a crossing without overspeed, on a sample inside the filtered window (ref_width in
    # signal periods)
    out["z_v_max"] = min(out["counter_v_max"], ref_width / 2 / max(1, ref_filt) * p * fs)
    if interp is not None:
        out["edge_counter_v_max"] = p * fs / (4 * interp)
        out["ab_v_max"] = p * fclk / (4 * interp * ab_sep)
    if v is not None:
        out["edge_counter_n_max"] = p * fs / (4 * v)
        out["ab_n_max"] = p * fclk / (4 * v * ab_sep)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pitch", type=float, required=True, help="signal period, um")
    ap.add_argument("--fs", type=float, required=True, help="sample rate, Hz")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--v", type=float, help="speed, m/s")
    g.add_argument("--interp", type=int,
                   help="interpolation factor n (default without --v: INTERP's reset value)")
    ap.add_argument("--ab-sep", type=int, default=SETTINGS["ab_sep"].reset,
                    help="A/B edge separation, clocks (ABGEN.ab_sep; default its reset value)")
    ap.add_argument("--fclk", type=float, default=36e6, help="core clock, Hz")
    ap.add_argument("--ref-width", type=float, default=0.5,
                    help="reference mark's window, signal periods (default 0.5)")
    ap.add_argument("--ref-filt", type=int, default=SETTINGS["ref_filt"].reset,
                    help="the window's glitch filter, samples (REF.ref_filt; default its "
                         "reset value)")
    a = ap.parse_args(argv)
    if a.v is None and a.interp is None:
        a.interp = SETTINGS["interp"].reset
    # each number within a range where the arithmetic means something (nan and inf
    # are outside every range)
    ranges = (("pitch", a.pitch, 1e-3, 1e5, "um"), ("fs", a.fs, 1.0, 1e10, "Hz"),
              ("fclk", a.fclk, 1e3, 1e10, "Hz"), ("v", a.v, 1e-12, 1e4, "m/s"))
    bad = [f"--{k} must be {lo:g}..{hi:g} {unit}, got {v}" for k, v, lo, hi, unit in ranges
           if v is not None and not lo <= v <= hi]
    if not 0 < a.ref_width <= 1:
        bad.append(f"--ref-width must be above 0 and at most 1 signal period, got "
                   f"{a.ref_width}")
    filt = SETTINGS["ref_filt"]
    if not filt.lo <= a.ref_filt <= filt.hi:
        bad.append(f"--ref-filt must be {filt.lo}..{filt.hi} (REF.ref_filt), got {a.ref_filt}")
    if a.interp is not None and a.interp < 1:
        bad.append(f"--interp must be 1..{N_MAX} (the core's INTERP), got {a.interp}")
    sep = SETTINGS["ab_sep"]
    if not sep.lo <= a.ab_sep <= sep.hi:
        bad.append(f"--ab-sep must be {sep.lo}..{sep.hi} (ABGEN.ab_sep), got {a.ab_sep}")
    if a.interp is not None and a.interp > N_MAX:
        bad.append(f"--interp must be 1..{N_MAX} (the core's INTERP), got {a.interp}")
    if a.fs is not None and a.fclk is not None and a.fs > a.fclk > 0:
        bad.append(f"--fs ({a.fs:g} Hz) cannot exceed --fclk ({a.fclk:g} Hz): one sample "
                   "per clock at most")
    if bad:
        print("limits: error: " + "; ".join(bad), file=sys.stderr)
        return 2
    r = limits(a.pitch, a.fs, a.ab_sep, a.fclk, a.v, a.interp, a.ref_width, a.ref_filt)
    sep_ns = a.ab_sep / a.fclk * 1e9
    print(f"pitch {a.pitch:g} um, fs {a.fs:g} Hz, A/B edge separation {a.ab_sep} clocks "
          f"= {sep_ns:.0f} ns at {a.fclk / 1e6:g} MHz")
    for c in counters.COUNTERS:
        ok = sep_ns >= c.min_sep_ns
        print(f"  {c.name}, {c.setting}: needs {c.min_sep_ns:.0f} ns between edges: "
              + ("follows" if ok else f"CANNOT follow (ab_sep >= "
                 f"{-(-c.min_sep_ns * a.fclk // 1e9):.0f} clocks at this clock)"))
    print(f"  internal counter (fine phase) tracks up to {r['counter_v_max']:.4g} m/s "
          f"(overspeed flag from 3/4 pi per sample; Nyquist {r['nyquist_v']:.4g} m/s), "
          f"at any n")
    print(f"  Z (reference mark): one count wide at the pins at any speed; a reference is "
          f"found up to {r['z_v_max']:.4g} m/s (window {a.ref_width:g} period, filter "
          f"{a.ref_filt})" + (f"; above {r['ab_v_max']:.4g} m/s Z comes as late as the A/B "
                             f"backlog" if a.interp is not None else ""))
    if a.interp is not None:
        n = a.interp
        print(f"  n = {n}: resolution {a.pitch * 1e3 / (4 * n):.4g} nm")
        print(f"    paper's edge counter (Eq. 13) loses counts above "
              f"{r['edge_counter_v_max']:.4g} m/s")
        print(f"    A/B outputs keep up to {r['ab_v_max']:.4g} m/s (above: backlog, then "
              f"overflow flag)")
    if a.v is not None:
        def n_of(x):
            n = int(x + 1e-9)
            return f"{N_MAX} (the core's largest; the limit is {n})" if n > N_MAX else str(n)
        print(f"  at {a.v:g} m/s: highest n for the paper's edge counter "
              f"{n_of(r['edge_counter_n_max'])}, for the A/B outputs {n_of(r['ab_n_max'])}"
              + ("" if a.v < r["counter_v_max"] else
                 "; the internal counter cannot follow this speed"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
