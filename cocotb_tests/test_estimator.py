"""estimator: the VHDL edition (rtl/vhdl/estimator.vhd, with its rls_engine) against the
Verilog (rtl/estimator.v) edge for edge. The estimator's own test is finequad_core's
(test_finequad_core.py, against sim/model); this one runs the two editions on the same
seeded stimulus, Icarus and GHDL, records every output after every edge and compares the
two records: samples of a drifting ellipse with gaps, excluded and garbage samples,
amplitude jumps (gain changes, the jump detector), LOADs, reset requests, rst, and the
tuning inputs changed now and then; with OPT_EXT_ENGINE a random engine response. Ports
only, so it runs on any simulator; skipped while the estimator has no VHDL edition."""
import math
import os
import random

import pytest

import fqtb

N_EDGES = 8000
CASES = {
    "L1": dict(ENGINE_LANES=1),
    "L2": dict(ENGINE_LANES=2, OPT_TUNABLE=0),
    "EXT": dict(OPT_EXT_ENGINE=1, EXT_PERIOD=518),
}


# (the ids name both simulators, so `-k ghdl` selects this test with the VHDL blocks')
@pytest.mark.parametrize("case", list(CASES), ids=[f"icarus-ghdl-{c}" for c in CASES])
def test_estimator_editions(case, tmp_path):
    if not fqtb.has_vhdl("estimator"):
        pytest.skip("no VHDL edition of estimator")
    params = dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR), **CASES[case])
    traces = {}
    # (Icarus: the Verilog reference; Verilator runs it alike, one is enough; GHDL, and
    # with FQ_GHDL_SYNTH=1 GHDL's netlist too: fqtb.simulators)
    vhdl = [s for s in fqtb.simulators("estimator") if fqtb.is_vhdl(s)]
    for sim in ["icarus"] + vhdl:
        path = tmp_path / f"{sim}.trace"
        fqtb.run_block(sim, "estimator", fqtb.sources("estimator", "rls_engine"),
                       "test_estimator", parameters=params,
                       extra_env=dict(TRACE=path, N_EDGES=N_EDGES,
                                      EXT=CASES[case].get("OPT_EXT_ENGINE", 0)))
        traces[sim] = path.read_text().splitlines()
    a = traces["icarus"]
    for sim in vhdl:
        b = traces[sim]
        assert len(a) == len(b) == N_EDGES, (sim, len(a), len(b))
        bad = [i for i in range(len(a)) if a[i] != b[i]]
        assert not bad, (f"{sim}: {len(bad)} edges differ, the first {bad[0]}:\n"
                         f"  Verilog {a[bad[0]]}\n  VHDL    {b[bad[0]]}")
    # the stimulus reaches updates, LOADs and (engine inside) hand-overs; what else it
    # reached is printed (jumps, holds, saturation)
    rec = [dict(kv.split("=") for kv in ln.split()) for ln in a]
    seen = {k: {r[k] for r in rec} for k in ("updates_o", "uncal_o", "loaded_o", "jumps_o",
                                             "hold_o", "sat_o")}
    print(case, {k: len(v) for k, v in seen.items()})
    assert len(seen["updates_o"]) > 20 and seen["loaded_o"] == {"0", "1"}
    if not CASES[case].get("OPT_EXT_ENGINE"):
        assert "0" in seen["uncal_o"]


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402

OUTPUTS = ("g_o", "m1_o", "m2_o", "c1_o", "c12_o", "c2_o", "uncal_o", "hold_o", "loaded_o",
           "ref_o", "updates_o", "jumps_o", "sat_o", "eng_cmd_o")


def s16(v):
    return max(-32768, min(32767, int(v)))


@cocotb.test()
async def estimator_trace(dut):
    n = fqtb.env_int("N_EDGES")
    ext = fqtb.env_int("EXT", 0)
    rng = random.Random(2929)
    bench = fqtb.ClockedBench(dut)
    tuning = dict(lambda_k_i=8, kappa_i=64 << 8, kappa5_i=5 * (64 << 8) >> 4, period_i=0,
                  settle_i=4, gate_i=20, jump_on_i=1, jump_min_i=200)
    fixed = dict(rst=1, smp_valid_i=0, u1_i=0, u2_i=0, amax_i=0, ph_valid_i=0, phase_i=0,
                 excl_i=0, travel_i=0, load_i=0, ld_g_i=0, ld_m1_i=0, ld_m2_i=0, ld_c1_i=0,
                 ld_c12_i=0, ld_c2_i=0, req_reset_i=0, tdm_ok_i=1, eng_rsp_i=0)
    last = {}

    def put(name, v):
        # (only a change is written: the bench's time is in Python, per edge)
        if last.get(name) != v:
            getattr(dut, name).value = v
            last[name] = v

    for k, v in {**fixed, **tuning}.items():
        put(k, v)
    await bench.start()
    th, w, amp = rng.uniform(0, 6.3), 0.02, 0.3
    valid_hist = [0] * 7
    travel = 0
    lines = []
    for e in range(n):
        # the inputs of edge e
        put("rst", int(e < 2 or rng.random() < 1 / 6000))
        sv = int(rng.random() < 0.75)
        put("smp_valid_i", sv)
        if sv:
            th += w
            if rng.random() < 1 / 2000:
                w = -w
            if rng.random() < 1 / 3000:
                amp = 0.08 if amp > 0.2 else 0.35          # a jump, and a new gain
            u1 = s16(32767 * (amp * math.cos(th) + 0.01) + rng.randint(-40, 40))
            u2 = s16(32767 * (0.9 * amp * math.sin(th - 0.1) - 0.02) + rng.randint(-40, 40))
            if rng.random() < 1 / 500:
                u1, u2 = rng.randint(-32768, 32767), rng.randint(-32768, 32767)
            put("u1_i", u1)
            put("u2_i", u2)
            put("amax_i", min(32767, max(abs(u1), abs(u2))))
        valid_hist = [sv] + valid_hist[:-1]
        pv = valid_hist[6]                                  # PH_DELAY = 6 edges later
        put("ph_valid_i", pv)
        put("excl_i", int(rng.random() < 1 / 32))
        if pv:
            put("phase_i", rng.randint(0, 8191))
        travel = (travel + (rng.randint(0, 63) if pv else 0)) & 0xFFFFF
        put("travel_i", travel)
        load = rng.random() < 1 / 2000
        put("load_i", int(load))
        if load:
            put("ld_g_i", rng.randint(0, 3))
            for k in ("ld_m1_i", "ld_m2_i", "ld_c1_i", "ld_c12_i", "ld_c2_i"):
                put(k, rng.randint(-32768, 32767))
        put("req_reset_i", int(rng.random() < 1 / 5000))
        if rng.random() < 1 / 3000:
            tuning = dict(lambda_k_i=rng.randint(0, 31),
                          kappa_i=rng.choice((64 << 8, 0, rng.randint(0, 65535))),
                          kappa5_i=rng.randint(0, 32767),
                          period_i=rng.choice((0, rng.randint(1, 200))),
                          settle_i=rng.randint(0, 15), gate_i=rng.randint(0, 63),
                          jump_on_i=rng.randint(0, 1), jump_min_i=rng.randint(0, 2047))
            for k, v in tuning.items():
                put(k, v)
        if ext:
            put("tdm_ok_i", int(rng.random() < 0.875))
            rsp = rng.getrandbits(115) & ~(1 << 113)
            put("eng_rsp_i", rsp | (int(rng.random() < 1 / 40) << 113))
        await bench.step()
        lines.append(" ".join(f"{k}={fqtb.uval(getattr(dut, k))}" for k in OUTPUTS))
    with open(os.environ["FQ_TRACE"], "w") as f:
        f.write("\n".join(lines) + "\n")
