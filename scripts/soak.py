#!/usr/bin/env python3
"""Soak run: a long recording through the RTL (`make soak`, not part of the tests).

Streams a generated encoder recording, at least 10^8 samples by default (100 s at
1 MS/s), through the Verilator harness of `make rtlsim` in its --raw mode (int16 pairs
in, one record per sample out: no files), and scores every sample against the truth.
The recording repeats a cycle of situations, each drawn from a seeded generator:

  move       jerk-limited moves of 0.3..3 mm at 5..200 mm/s (signal up to 50 kHz)
  standstill 1..3 s at rest (noise 0.5..2 %: the estimator must not wind up)
  creep      1.5 signal periods at 10^5..10^6 samples per period
  dither     a servo dither of +-0.2..0.6 um at 30..80 Hz for 0.5 s (short arcs)
  fast       a pass at a signal frequency of 0.2..0.35 fs (0.8..1.4 m/s)
  jump       a move during which m1, A2 and phi jump at once (the jump detector)
  faults     a slow move (0.5..2 mm/s) with injected faults: signal loss (amplitude
             x 0.02, 200..400 samples), a stuck channel (300..600), single-sample
             glitches, a channel on the rail (40..80) and over-range (amplitude x 1.5,
             100..200)
  drift      a move along which every signal parameter drifts

The signal parameters (A1, A2, m1, m2, phi, harmonics, noise) carry over from one
situation to the next, so over the run they wander (a random walk within the 1 Vpp
interface's specification, with margin: Params) as on a real scale. Faults are short enough that the stage moves less than a quarter of a period
while they last, so the count must be right when the signal is back.

Scored (count in units of pitch / (4 n), truth in nm): the error of the counter against
the truth, minus one constant offset (the counter's zero is the phase of the first
sample) found on the first calibrated samples; a slip is a sample the monitor trusts
(no fault bit 0, 7, 9 or 10), outside an injected fault and after the first hand-over,
that is off by more than pitch / 8. Reported: samples, wall time and simulation speed,
slips (samples and events), the samples with each fault bit, the injected faults of each
kind and how many the monitor flagged, the final error, the largest error outside the
faults, the RMS error while moving and at rest, the estimator's updates and jumps
(registers read at the end). Writes build/soak/soak.json; exit 1 on a slip or a failed
run, 2 on bad input (one line naming it).

  scripts/soak.py [--samples N] [--seed S] [--div D] [--harness PATH] [--out DIR]
"""
import argparse
import json
import os
import pathlib
import queue
import subprocess
import sys
import threading
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from sim import siggen  # noqa: E402
from sim.model import finequad_core as core  # noqa: E402
from sim.run_model import DIV_MAX  # noqa: E402

PITCH_NM = 4000.0
FS = 1e6
INTERP = 100
CHUNK = 1 << 20                      # samples per piece sent to the harness
REC = np.dtype([("count", "<i4"), ("fault", "<u2"), ("a", "u1"), ("b", "u1")])
HELD = [core.FAULT_BITS[b] for b in ("clip", "loss", "stuck", "glitch")]
KINDS = ("move", "standstill", "creep", "dither", "fast", "jump", "faults", "drift")
FAULTS = ("loss", "stuck", "glitch", "rail", "over")


class Params:
    """The signal's parameters, carried from one situation to the next (a bounded walk).

    The walk covers the 1 Vpp interface's specification with margin, as a readhead's
    signals wander along a scale and with temperature: the amplitude A1 from 0.3 to 0.85
    of full scale (0.6 to 1.2 Vpp is 2:1; this is 2.8:1), the amplitude ratio A2 / A1
    0.8..1.25, offsets up to 6.5 % of the amplitude, the phase error up to +-0.17 rad
    (10 degrees), third harmonic up to 1 %, noise 0.2..2 % of the amplitude. (Walking A1,
    A2 and the offsets independently over 0.15..0.85 and +-6 % of full scale reached
    5:1 mismatches with offsets of 40 % of an amplitude and 10 % noise on one channel: a
    broken readhead, which is the monitor's business, not a test of accuracy.)"""

    LIM = dict(A1=(0.30, 0.85), ratio=(0.8, 1.25), mr1=(-0.065, 0.065),
               mr2=(-0.065, 0.065), phi=(-0.17, 0.17), h3=(0.0, 0.01), noise=(0.002, 0.02))
    STEP = dict(A1=0.03, ratio=0.02, mr1=0.006, mr2=0.006, phi=0.01, h3=0.002, noise=0.002)

    def __init__(self, rng):
        self.rng = rng
        self.w = dict(A1=0.60, ratio=0.9, mr1=0.05, mr2=-0.037, phi=0.08, h3=0.0,
                      noise=0.005)

    @property
    def v(self):
        """The signal's parameters (A1, A2, m1, m2 in full-scale units)."""
        w = self.w
        a2 = w["A1"] * w["ratio"]
        return dict(A1=w["A1"], A2=a2, m1=w["mr1"] * w["A1"], m2=w["mr2"] * a2,
                    phi=w["phi"], h3=w["h3"], noise=w["noise"])

    def walk(self):
        for k in self.w:
            self.w[k] = float(np.clip(self.w[k] + self.rng.normal(0, self.STEP[k]),
                                      *self.LIM[k]))

    def jump(self):
        """The jump situation's step (m1 +3 % of full scale, A2 -5 %, phi +0.05 rad),
        folded back into the walk's bounds."""
        w = self.w
        w["mr1"] = float(np.clip(w["mr1"] + 0.03 / w["A1"], *self.LIM["mr1"]))
        w["ratio"] = float(np.clip(w["ratio"] - 0.05 / w["A1"], *self.LIM["ratio"]))
        w["phi"] = float(np.clip(w["phi"] + 0.05, *self.LIM["phi"]))

    def signal(self, n, jump_at=None, drift=False):
        """siggen.Signal for n samples with the current values; a jump (m1, A2 and phi
        step at once: Params.jump) at jump_at, or every value drifting to a new one."""
        old = self.v
        arr = {}
        if drift:
            self.walk()
            self.walk()
            new = self.v
            for k in ("A1", "A2", "m1", "m2", "phi"):
                arr[k] = np.linspace(old[k], new[k], n)
        elif jump_at is not None:
            self.jump()
            new = self.v
            for k in ("m1", "A2", "phi"):
                arr[k] = siggen.jump(np.full(n, old[k]), jump_at, new[k] - old[k])
        return siggen.Signal(A1=arr.get("A1", old["A1"]), A2=arr.get("A2", old["A2"]),
                             m1=arr.get("m1", old["m1"]), m2=arr.get("m2", old["m2"]),
                             phi=arr.get("phi", old["phi"]), h3=old["h3"],
                             noise=old["noise"], adc_bits=16)


def situation(kind, rng, x0, params, seed):
    """(u1, u2, x, injected [(what, first, stop)]) of one situation, positions in nm."""
    um, mm = 1e3, 1e6
    inj = []
    jump_at, drift = None, False
    if kind == "standstill":
        x = np.full(int(rng.uniform(1.0, 3.0) * FS), x0)
    elif kind == "creep":
        per = rng.uniform(1e5, 1e6)                   # samples per signal period
        x = x0 + np.arange(int(1.5 * per)) * PITCH_NM / per * rng.choice((1, -1))
    elif kind == "dither":
        amp, f = rng.uniform(0.2, 0.6) * um, rng.uniform(30, 80)
        x = x0 + amp * np.sin(2 * np.pi * f * np.arange(int(0.5 * FS)) / FS)
    elif kind == "fast":
        v = rng.uniform(0.2, 0.35) * FS * PITCH_NM    # nm/s
        x = siggen.moves(FS, [("move", rng.choice((1, -1)) * rng.uniform(20, 60) * mm, v,
                                2e10, 1e13)], x0)
    else:
        d = rng.choice((1, -1)) * rng.uniform(0.3, 3.0) * mm
        v = {"move": rng.uniform(5, 200), "faults": rng.uniform(0.5, 2.0)}.get(
            kind, rng.uniform(5, 20)) * mm
        x = siggen.moves(FS, [("dwell", 0.005), ("move", d, v, 1e9, 1e11),
                              ("dwell", 0.005)], x0)
        n = len(x)
        if kind == "jump":
            jump_at = n // 2
        elif kind == "drift":
            drift = True
        elif kind == "faults":
            # one of each, spread over the move, each where the stage moves less than a
            # quarter period over its length (at 2 mm/s: 600 samples are 0.3 period)
            speed = np.abs(np.diff(x, prepend=x[0]))          # nm per sample
            for i, what in enumerate(FAULTS):
                ln = {"loss": (200, 400), "stuck": (300, 600), "glitch": (2000, 2001),
                      "rail": (40, 80), "over": (100, 200)}[what]
                ln = int(rng.integers(*ln))
                lo = int(n * (0.15 + 0.15 * i))
                # slide to where the motion over the fault stays below pitch / 4
                cand = [k for k in range(lo, min(n - ln, lo + n // 10), 97)
                        if what == "glitch" or speed[k:k + ln].sum() < PITCH_NM / 4]
                if cand:
                    inj.append((what, cand[0], cand[0] + ln))
    sig = params.signal(len(x), jump_at=jump_at, drift=drift)
    drop = tuple((a, b, 0.02 if w == "loss" else 1.5) for w, a, b in inj
                 if w in ("loss", "over"))
    if drop:
        sig.dropout = drop
    u1, u2 = np.empty(len(x), np.int16), np.empty(len(x), np.int16)
    for a in range(0, len(x), CHUNK):                  # noise per piece, seeded
        b = min(len(x), a + CHUNK)
        part = _slice_signal(sig, a, b)
        c1, c2, _ = siggen.encode(x[a:b], PITCH_NM, part, seed=seed * 1009 + a // CHUNK)
        u1[a:b], u2[a:b] = c1, c2
    for what, a, b in inj:
        if what == "stuck":
            u1[a:b] = u1[a]
        elif what == "rail":
            u1[a:b] = 32767
        elif what == "glitch":
            for k in np.linspace(a, b - 1, 8).astype(int):
                g = rng.uniform(0, 2 * np.pi)
                u1[k] = int(0.5 * 32767 * np.cos(g))
                u2[k] = int(0.5 * 32767 * np.sin(g))
    if kind != "standstill":
        params.walk()
    return u1, u2, x, inj


def _slice_signal(sig, a, b):
    """The Signal restricted to samples [a, b) (arrays sliced, dropouts shifted)."""
    kw = {}
    for k in ("A1", "A2", "m1", "m2", "phi"):
        v = getattr(sig, k)
        kw[k] = v[a:b] if np.ndim(v) else v
    drop = tuple((max(0, f - a), max(0, s - a), lv) for f, s, lv in sig.dropout
                 if s > a and f < b)
    return siggen.Signal(h2=sig.h2, h3=sig.h3, noise=sig.noise, adc_bits=sig.adc_bits,
                         dropout=drop, **kw)


def generate(total, seed, out_q):
    """Producer: situations until `total` samples, as (u1, u2, x, kind, injected); an
    exception is handed on as an ('error', text) item, so the consumer stops too."""
    try:
        _generate(total, seed, out_q)
    except Exception as e:                       # noqa: BLE001 (any failure ends the run)
        out_q.put(("error", f"{type(e).__name__}: {e}"))
        out_q.put(None)


def _generate(total, seed, out_q):
    rng = np.random.default_rng(seed)
    params = Params(rng)
    x0, n, i = 0.0, 0, 0
    order = ["move"] + list(KINDS)                    # a first move calibrates
    while n < total:
        kind = order[i] if i < len(order) else KINDS[int(rng.integers(len(KINDS)))]
        u1, u2, x, inj = situation(kind, rng, x0, params, seed * 7919 + i)
        out_q.put((u1, u2, x, kind, inj))
        x0 = float(x[-1])
        n += len(x)
        i += 1
    out_q.put(None)


def bad_input(msg):
    """Bad input: one line naming it, exit 2 (as argparse's own errors)."""
    print(f"soak: error: {msg}", file=sys.stderr)
    raise SystemExit(2)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=float, default=1e8)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--div", type=int, default=36, help="clocks per sample")
    ap.add_argument("--harness", default=str(ROOT / "build/rtlsim_exact_adc16/Vfinequad_core"))
    ap.add_argument("--out", default=str(ROOT / "build/soak"))
    ap.add_argument("--stop-on-slip", action="store_true",
                    help="stop at the first situation with a slip (for debugging)")
    ap.add_argument("--record-from", type=int, default=None, metavar="K",
                    help="save situations K, K+1, ... sample by sample (codes, truth, count, "
                         "fault) to OUT/situation_<i>.npz (for debugging)")
    a = ap.parse_args()
    if not (1e4 <= a.samples < 1e15):        # (also rejects nan and inf)
        bad_input(f"--samples must be at least 10000 and below 1e15, got "
                 f"{a.samples}")
    if not 1 <= a.div <= DIV_MAX:
        bad_input(f"--div must be 1..{DIV_MAX} (clocks per sample), got {a.div}")
    if not 0 <= a.seed < 1 << 32:
        bad_input(f"--seed must be 0..{(1 << 32) - 1}, got {a.seed}")
    out = pathlib.Path(a.out)
    if out.exists() and not out.is_dir():
        bad_input(f"--out {out}: exists and is not a folder")
    if not pathlib.Path(a.harness).is_file():
        bad_input(f"harness {a.harness} not found (make harnesses)")
    if not os.access(a.harness, os.X_OK):
        bad_input(f"harness {a.harness} is not executable")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        bad_input(f"--out {out}: cannot make the folder: {e.strerror}")

    proc = subprocess.Popen([a.harness, "--raw", "--dump-regs", "--interp", str(INTERP),
                             "--div", str(a.div)], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    gen_q, truth_q = queue.Queue(maxsize=4), queue.Queue()

    def writer():
        try:
            while True:
                item = gen_q.get()
                if item is None:
                    break
                if isinstance(item[0], str):         # ("error", text)
                    truth_q.put(item)
                    break
                u1, u2 = item[0], item[1]
                truth_q.put(item)
                proc.stdin.write(np.stack([u1, u2], axis=1).astype("<i2").tobytes())
        except BrokenPipeError:
            pass
        finally:
            truth_q.put(None)
            try:
                proc.stdin.close()
            except BrokenPipeError:
                pass

    t0 = time.time()
    threading.Thread(target=generate, args=(int(a.samples), a.seed, gen_q),
                     daemon=True).start()
    threading.Thread(target=writer, daemon=True).start()

    scale = PITCH_NM / (4 * INTERP)                   # nm per count
    st = dict(samples=0, slips=0, slip_events=0, max_err_nm=0.0, final_err_nm=None,
              fault_samples={k: 0 for k in core.FAULT_BITS}, injected={f: 0 for f in FAULTS},
              flagged={f: 0 for f in FAULTS}, situations={k: 0 for k in KINDS})
    sq = {"moving": [0.0, 0], "rest": [0.0, 0]}
    per_kind = {k: dict(samples=0, sq=0.0, max_nm=0.0) for k in KINDS}
    offset, cal_seen, prev_slip = None, False, False
    offs = []
    history = []                      # per situation: what happened
    while True:
        item = truth_q.get()
        if item is None:
            break
        if isinstance(item[0], str):                 # ("error", text)
            proc.kill()
            sys.exit(f"soak: error: the recording's generator failed: {item[1]}")
        u1, u2, x, kind, inj = item
        n = len(x)
        raw = proc.stdout.read(n * REC.itemsize)
        if len(raw) != n * REC.itemsize:
            proc.kill()
            sys.exit(f"soak: error: the harness stopped after {st['samples']} samples: "
                     f"{proc.stderr.read().decode().strip()}")
        r = np.frombuffer(raw, dtype=REC)
        f = r["fault"].astype(np.int64)
        for k, bit in core.FAULT_BITS.items():
            st["fault_samples"][k] += int(((f >> bit) & 1).sum())
        st["situations"][kind] += 1
        during = np.zeros(n, dtype=bool)
        for what, lo, hi in inj:
            during[lo:hi] = True
            st["injected"][what] += 1
            bits = {"loss": "loss", "stuck": "stuck", "glitch": "glitch", "rail": "clip",
                    "over": "over"}[what]
            st["flagged"][what] += int(((f[lo:hi] >> core.FAULT_BITS[bits]) & 1).any())
        held = np.zeros(n, dtype=bool)
        for bit in HELD:
            held |= ((f >> bit) & 1).astype(bool)
        uncal = ((f >> core.FAULT_BITS["uncal"]) & 1).astype(bool)
        err = r["count"].astype(np.float64) * scale - x
        ok = ~held & ~during
        if not cal_seen:
            cal = ok & ~uncal
            if cal.sum() > 20000 or offs:
                offs.extend(err[cal].tolist())
            if len(offs) > 20000:
                offset = float(np.median(offs))
                cal_seen = True
        rec = dict(index=len(history), kind=kind, first_sample=st["samples"], samples=n,
                   injected=[w for w, _, _ in inj],
                   faults={k: int(((f >> b) & 1).sum()) for k, b in core.FAULT_BITS.items()
                           if ((f >> b) & 1).any()})
        if offset is not None:
            e = err - offset
            scored = ok & ~uncal
            bad = scored & (np.abs(e) > PITCH_NM / 8)
            rec.update(max_err_nm=round(float(np.abs(e[scored]).max()), 1) if scored.any()
                       else None, slips=int(bad.sum()))
            st["slips"] += rec["slips"]
            edges = np.diff(np.concatenate([[prev_slip], bad]).astype(int))
            st["slip_events"] += int((edges == 1).sum())
            prev_slip = bool(bad[-1]) if n else prev_slip
            if scored.any():
                st["max_err_nm"] = max(st["max_err_nm"], float(np.abs(e[scored]).max()))
            st["final_err_nm"] = float(e[-1])
            moving = np.abs(np.diff(x, prepend=x[0])) > 0
            for key, m in (("moving", scored & moving), ("rest", scored & ~moving)):
                sq[key][0] += float((e[m] ** 2).sum())
                sq[key][1] += int(m.sum())
            pk = per_kind[kind]
            pk["samples"] += int(scored.sum())
            pk["sq"] += float((e[scored] ** 2).sum())
            if scored.any():
                pk["max_nm"] = max(pk["max_nm"], float(np.abs(e[scored]).max()))
        history.append(rec)
        if a.record_from is not None and rec["index"] >= a.record_from:
            np.savez_compressed(out / f"situation_{rec['index']}.npz", u1=u1, u2=u2, x=x,
                                count=r["count"], fault=r["fault"], kind=kind,
                                offset=np.nan if offset is None else offset)
        st["samples"] += n
        if a.stop_on_slip and rec.get("slips"):
            print(f"soak: stopping at situation {rec['index']} ({kind}): {rec}")
            proc.kill()
            st["history"] = history
            (out / "soak.json").write_text(json.dumps(st, indent=1))
            return 1
    rest = proc.stdout.read()
    proc.wait()
    regs_line = proc.stderr.read().decode().strip()
    if proc.returncode or rest:
        sys.exit(f"soak: error: harness exit {proc.returncode}, {len(rest)} stray bytes: "
                 f"{regs_line}")
    wall = time.time() - t0
    regs = dict(kv.split("=") for kv in regs_line.split()[1:]) if regs_line.startswith(
        "regs:") else {}
    st.update(wall_s=round(wall, 1), samples_per_s=round(st["samples"] / wall),
              div=a.div, seed=a.seed, interp=INTERP, pitch_nm=PITCH_NM,
              rms_moving_nm=(sq["moving"][0] / max(1, sq["moving"][1])) ** 0.5,
              rms_rest_nm=(sq["rest"][0] / max(1, sq["rest"][1])) ** 0.5,
              regs={k: int(v) for k, v in regs.items()},
              per_situation={k: dict(samples=v["samples"], max_nm=round(v["max_nm"], 1),
                                     rms_nm=round((v["sq"] / max(1, v["samples"])) ** 0.5,
                                                  2)) for k, v in per_kind.items()},
              history=history)
    (out / "soak.json").write_text(json.dumps(st, indent=1))
    print(f"soak: {st['samples']} samples in {st['wall_s']} s ({st['samples_per_s']} "
          f"samples/s, {a.div} clocks per sample), n = {INTERP}, 4 um pitch")
    print("  situations: " + ", ".join(f"{k} {v}" for k, v in st["situations"].items()))
    print(f"  slips: {st['slips']} samples ({st['slip_events']} events) off by more than "
          f"pitch/8 among the trusted samples")
    print(f"  error: final {st['final_err_nm']:.1f} nm, largest {st['max_err_nm']:.1f} nm "
          f"(trusted, outside faults), RMS moving {st['rms_moving_nm']:.2f} nm, at rest "
          f"{st['rms_rest_nm']:.2f} nm")
    print("  per situation (scored samples, RMS, largest error): " + "; ".join(
        f"{k} {v['samples']} / {v['rms_nm']} nm / {v['max_nm']} nm"
        for k, v in st["per_situation"].items()))
    print("  injected faults flagged: " + ", ".join(
        f"{w} {st['flagged'][w]}/{st['injected'][w]}" for w in FAULTS))
    print("  samples with each fault bit: " + ", ".join(
        f"{k} {v}" for k, v in st["fault_samples"].items()))
    print(f"  registers at the end: {regs_line}")
    print(f"wrote {out / 'soak.json'}")
    return 1 if st["slips"] else 0


if __name__ == "__main__":
    sys.exit(main())
