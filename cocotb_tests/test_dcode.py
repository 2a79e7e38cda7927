"""Distance-coded reference marks (rtl/dcode.v): finequad_core against
sim.model.finequad_core.run bit for bit on a scale with distance-coded marks, and the
absolute position it homes to checked against the true one.

The scale (SPACING = 20, CODED = 21 signal periods: marks at 0, 11, 20, 32, 40, 53, 60,
74, .. periods from the first fixed mark, which lies P0 periods from the encoder's zero);
n = 25 (100 counts per period), the reference point REF_Q. The recording: calibrate, then
cross marks forwards (homing armed: the count is set at the first decode that makes
abs_valid rise), cross a spurious mark (a window where the scale has none) and, coming
back, miss a real one (its window left out), lose the signal for 400 samples (the coast's
uncertainty passes a quarter period: pos_valid and abs_valid fall), arm homing again and
cross two more marks. Two runs:
* "two": DCODE.dc_confirm = 0, the spurious mark after homing, a strobe every 26 clocks
  (each decode ends one edge after the next sample's t + 10): abs_valid from the second
  mark, cleared (dc_err) where the spurious and the missing mark break the layout;
* "confirm": dc_confirm = 1, the spurious mark between the first two real marks: homing
  only after three marks agree, and never to a wrong position; a strobe every 27 clocks
  (each decode ends on the next sample's t + 10).

Checks: every sample, count after t + 8 and ref_count, homed, pos_valid, abs_valid and
ABS_COUNT (the decoder's outputs, read inside the core) after t + 10 equal the model's; wherever pos_valid = 1 the count is the true absolute count (the raw
count less the count at the first fixed mark's reference point); the model's decodes give
the layout's positions; DC errors where the recording breaks the layout, as many in the
RTL (its dc_err pulses) as in the model; REF_STATUS,
REF_STICKY and ABS_COUNT read back as the model ends. A third run ("gaps") repeats
"confirm" with random gaps between strobes, so that decodes end between samples.
"""
import numpy as np
import pytest

import fqtb
from sim import siggen
from sim.model import dcode
from sim.model import finequad_core as core_model
from sim.model import regs

CORE_SOURCES = fqtb.core_sources()
PITCH = 20.0
INTERP = 25
N4 = 4 * INTERP
REF_Q = 37
SPACING, CODED = 20, 21
P0 = 30                        # the first fixed mark's signal period
DIV = 36
HOME_COUNT = -5000
VMAX = 0.08                    # periods per sample (the window's limit is 0.125)
LAYOUT = siggen.distance_coded(SPACING, CODED, 200)
# strobes every 26 and 27 clocks: a decode (DC_LAT = 27 edges) ends just after and on the
# next sample's t + 10
RUNS = {"two": dict(confirm=0, spurious=45, div=26),
        "confirm": dict(confirm=1, spurious=5, div=27),
        # random gaps between strobes (1 .. 30 clocks, bursts back to back): the decode's
        # 27 edges end at any point between samples
        "gaps": dict(confirm=1, spurious=5, gaps=True)}
MISSING = 60                   # the mark left out on the way back


def centre(s):
    """The window's centre of a mark s periods from the first fixed mark."""
    return PITCH * (P0 + s + (REF_Q + 0.5) / N4)


def _move(x0, x1):
    n = max(8, int(np.ceil(2 * abs(x1 - x0) / (VMAX * PITCH))))
    return siggen.s_curve(n, 1.0, x1 - x0, float(n), 0.0, x0)


def recording(spurious):
    """(x, ref, ev): positions, the reference input, sample ranges of the parts."""
    parts, ev = [], {}

    def add(name, seg):
        start = sum(len(p) for p in parts)
        parts.append(np.asarray(seg, float))
        ev[name] = (start, start + len(seg))

    add("calibrate", siggen.s_curve(6000, 1.0, 12 * PITCH, 5800.0, 100.0, 0.0))
    add("forward", _move(12 * PITCH, centre(78)))
    add("back", _move(centre(78), centre(45)))
    add("loss", np.linspace(centre(45), centre(44.7), 600))
    add("final", _move(centre(44.7), centre(15)))
    x = np.concatenate(parts)
    marks = [centre(s) for s in LAYOUT if s != MISSING] + [centre(spurious)]
    ref = siggen.reference(x, marks, 0.5 * PITCH, jitter=0.002 * PITCH, seed=2)
    # the missing mark is missing on the way back only
    lo, hi = ev["forward"]
    ref[lo:hi] |= (np.abs(x[lo:hi] - centre(MISSING)) <= 0.25 * PITCH).astype(np.int64)
    return x, ref, ev


def config(run):
    return core_model.Config(interp=INTERP, ref_q=REF_Q, home_count=HOME_COUNT,
                             home_arm=True, div=DIV, dc_spacing=SPACING, dc_coded=CODED,
                             dc_confirm=RUNS[run]["confirm"])


@pytest.mark.parametrize("run", list(RUNS))
# GHDL runs "gaps" only (CI time: some 16 clocks per sample, where the other runs take 26
# and 27; dc_confirm = 1 and decodes ending anywhere between samples); the labels it
# reads inside the core, g_dcode.u_dcode, are the same in rtl/vhdl/finequad_core.vhd
@pytest.mark.parametrize("sim", fqtb.simulators("finequad_core"))
def test_dcode(sim, run):
    if sim == "icarus":
        pytest.skip("Verilator only (the whole recording; Icarus runs test_refmark)")
    if sim == "ghdl" and run != "gaps":
        pytest.skip(f"{run}: not on GHDL (GHDL runs gaps)")
    fqtb.run_block(sim, "finequad_core", CORE_SOURCES, "test_dcode",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR), TABLE_EXACT=1),
                   extra_env=dict(RUN=run), testcase="dcode_run")


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402


async def _count_pulses(sig, out):
    from cocotb.triggers import RisingEdge
    while True:
        await RisingEdge(sig)
        out.append(1)


@cocotb.test()
async def dcode_run(dut):
    run = fqtb.env_str("RUN")
    x, ref, ev = recording(RUNS[run]["spurious"])
    u1, u2, _ = siggen.encode(x, PITCH, siggen.Signal(
        noise=0.005, dropout=((ev["loss"][0] + 100, ev["loss"][0] + 500, 0.03),)), seed=5)
    n = len(x)
    if RUNS[run].get("gaps"):
        rng = np.random.default_rng(4)
        gaps = rng.integers(1, 31, n)
        gaps[rng.random(n) < 0.2] = 1
        t = 32 + np.concatenate([[0], np.cumsum(gaps[:-1])])
    else:
        t = core_model.strobe_edges(n, RUNS[run].get("div", DIV))
    w_home = int(t[ev["final"][0]]) + 3
    cfg = config(run)
    cfg.homes = [w_home]
    res = core_model.run(u1, u2, cfg, strobes=t, ref=ref, trace=True)
    writes = dict(enumerate(core_model.register_writes(cfg)))
    writes[len(writes)] = (regs.REF, regs.word("REF", ref_q=REF_Q, ref_filt=cfg.ref_filt,
                                               home=1))
    assert max(writes) < int(t[0])
    writes[w_home] = writes[max(writes)]
    got8 = np.zeros(n, np.int64)
    got10 = np.zeros((n, 5), np.int64)
    u_dc = dut.g_dcode.u_dcode               # abs_valid and ABS_COUNT have no port
    bench = fqtb.ClockedBench(dut)
    for p in ("rst", "s_valid", "s_u1", "s_u2", "s_ref", "reg_we", "reg_re", "reg_addr",
              "reg_wdata"):
        getattr(dut, p).value = 0
    await bench.start()
    errs = []                                # the decoder's dc_err pulses, counted
    cocotb.start_soon(_count_pulses(u_dc.err_o, errs))
    await bench.run_samples(t, u1, u2, ref, writes, {
        core_model.LATENCY: (lambda: fqtb.sval(dut.m_count), got8),
        core_model.LATCH_AT: (lambda: (fqtb.sval(dut.m_ref_count), fqtb.uval(dut.m_homed),
                                       fqtb.uval(dut.m_pos_valid),
                                       fqtb.uval(u_dc.abs_valid_o), fqtb.sval(u_dc.abs_o)),
                              got10)})

    # ---- RTL == model, every sample ----------------------------------------------------------
    exp10 = np.stack([res["ref_count"], res["homed"], res["pos_valid"], res["abs_valid"],
                      res["abs_count"]], axis=1)
    diff = np.nonzero((got8 != res["count"]) | (got10 != exp10).any(axis=1))[0]
    assert not len(diff), (
        f"{run}: {len(diff)} of {n} samples differ, first: " +
        "; ".join(f"sample {k} (edge {int(t[k])}): rtl {int(got8[k])} "
                  f"{tuple(int(v) for v in got10[k])}, model {int(res['count'][k])} "
                  f"{tuple(int(v) for v in exp10[k])}" for k in diff[:8]))

    # ---- the absolute position: right wherever pos_valid is 1 -------------------------------
    c0 = N4 * P0 + REF_Q             # the raw count at the first fixed mark's reference point
    pv = np.asarray(res["pos_valid"]) == 1
    # count after t + 8, pos_valid after t + 10: a sample whose pos_valid is 1 and the one
    # before it too has its count homed
    both = pv[1:] & pv[:-1]
    wrong = np.flatnonzero(both & (res["count"][1:] != res["count_raw"][1:] - c0 + HOME_COUNT))
    assert not len(wrong), f"{run}: homed to a wrong count at samples {wrong[:5] + 1}"
    homings = np.flatnonzero(np.diff(pv.astype(np.int8)) == 1) + 1
    assert len(homings) == 2, f"{run}: pos_valid rose at samples {homings}"
    lo, hi = ev["loss"]
    assert pv[lo - 1] and not pv[hi - 1] and pv[-1]
    # ABS_COUNT while abs_valid: the absolute count of the last mark latched (its raw
    # count less c0), except, with dc_confirm = 0, while that mark is the spurious one
    av = np.asarray(res["abs_valid"])
    ac = np.asarray(res["abs_count"])
    raw_ref = res["ref_count"] - (res["count"] - res["count_raw"])
    spur = (raw_ref - c0) == N4 * RUNS[run]["spurious"]
    chk = (av == 1) & ~(spur & (cfg.dc_confirm == 0))
    # not while a latch's decode runs (DC_LAT edges from its t + 10) nor on a homing's sample
    chk[np.flatnonzero(np.diff(res["count"] - res["count_raw"])) + 1] = False
    for k in np.flatnonzero(np.diff(res["ref_count"])) + 1:
        chk[k:np.searchsorted(t, t[k] + dcode.DC_LAT + 1)] = False
    wrong = np.flatnonzero(chk & (ac != raw_ref - c0))
    assert not len(wrong), (f"{run}: ABS_COUNT wrong at samples {wrong[:5]}: "
                            f"{ac[wrong[:5]]}, marks at {raw_ref[wrong[:5]] - c0}")
    # errors: the spurious mark and the missing one break the layout; the RTL flagged as
    # many (dc_err pulses, none back to back: marks are far apart)
    assert res["dc_errors"] >= 2, res["dc_errors"]
    assert len(errs) == res["dc_errors"], (len(errs), res["dc_errors"])

    # ---- registers after the run -----------------------------------------------------------------
    bad = []
    for name, want_v in (
            ("REF_STATUS", regs.word_read("REF_STATUS", win=int(ref[-1]), homed=1,
                                          pos_valid=int(pv[-1]), home_armed=0,
                                          abs_valid=int(av[-1]))),
            ("REF_STICKY", regs.word_read("REF_STICKY", latched=1, lost=1, dc_err=1)),
            ("ABS_COUNT", int(ac[-1]) & 0xFFFFFFFF),
            ("DCODE", regs.word_read("DCODE", dc_spacing=SPACING, dc_coded=CODED,
                                     dc_confirm=cfg.dc_confirm))):
        v = await bench.reg_read(regs.REGS[name].index)
        if v != want_v:
            bad.append(f"{name}: rtl {v:#x}, expected {want_v:#x}")
    assert not bad, f"{run}: " + "; ".join(bad)
    dut._log.info("%s: %d samples equal; %d latches, %d DC errors, homed twice, at the true "
                  "absolute count; ABS_COUNT %d at the end", run, n, res["ref_latches"],
                  res["dc_errors"], int(ac[-1]))
