"""rls_engine (microcoded RLS machine) against sim.model.rls_engine.RlsEngine, for every
LANES (the engine's parameter; the model executes the ROM image scheduled for it).

A RESET program (entry ENTRY['reset']) and then many UPDATE and EXTRACT programs
(ENTRY['update'], ENTRY['extract']) on samples of noisy ellipses, with resets in between
that change the input gain (dg_i != 0, theta rescaled) and kappa, varying lambda and the
trace-bound freeze. Programs start back to back (the next on the edge after the last
one's END) or after random gaps, so results are forwarded across programs too. For every
program started on edge S the bench checks: busy_o high after edges S .. S+C-1 and low
after edge S+C, done_o high exactly after edge S+C-1 (C = sim.model.rls_engine.CYCLES
[program] of the model with the same LANES); then valid_o, out_o (the seven 16-bit OUT
registers) and the sticky sat_o equal the model's after that program. A few programs run
on garbage samples so that invalid results and saturation occur."""
import math
import random

import pytest

import fqtb


@pytest.mark.parametrize("lanes", [1, 2])
@pytest.mark.parametrize("sim", fqtb.simulators("rls_engine"))
def test_rls_engine(sim, lanes):
    fqtb.run_block(sim, "rls_engine", fqtb.sources("rls_engine"),
                   "test_rls_engine",
                   parameters=dict(TABLE_DIR=fqtb.qstr(fqtb.TABLE_DIR), LANES=lanes),
                   extra_env=dict(N_PROGRAMS=400, LANES=lanes))


# ---- cocotb side ------------------------------------------------------------------------
import cocotb  # noqa: E402


def s16(v):
    return max(-32768, min(32767, int(round(v))))


def make_programs(rng, n):
    """[(name, x1, x2, lambda_k, kappa, dg)]"""
    progs = [("reset", 0, 0, 8, 64 << 8, 0)]
    g = 0
    ang = rng.uniform(0, 2 * math.pi)
    A1, A2, m1, m2, phi = 0.22, 0.2, 0.01, -0.008, 0.07
    lambda_k = 8
    while len(progs) < n:
        if len(progs) in (n // 3, 2 * n // 3):
            # a burst that winds the estimate up (garbage samples, then a standing point,
            # with fast forgetting): invalid extractions and saturated registers; then a
            # reset to recover
            const = (rng.randint(-3000, 3000), rng.randint(-3000, 3000))
            for i in range(30):
                x = (rng.randint(-32768, 32767), rng.randint(-32768, 32767)) if i < 15 \
                    else const
                progs.append(("update", *x, 1, 0, 0))
            progs.append(("reset", 0, 0, lambda_k, 64 << 8, 0))
            continue
        r = rng.random()
        if r < 0.02:            # reset with a gain change (and a new kappa)
            dg = rng.choice([d for d in (-3, -2, -1, 1, 2, 3) if 0 <= g + d <= 3])
            g += dg
            progs.append(("reset", rng.randint(-32768, 32767), rng.randint(-32768, 32767),
                          lambda_k, rng.choice((64 << 8, 16 << 8, 200 << 8, 1 << 8)), dg))
            lambda_k = rng.choice((4, 6, 8, 8, 10, 12))
            continue
        if r < 0.03:            # reset without a gain change
            progs.append(("reset", 0, 0, lambda_k, 64 << 8, 0))
            continue
        if r < 0.05:            # garbage sample (saturations, invalid extraction)
            x1, x2 = rng.randint(-32768, 32767), rng.randint(-32768, 32767)
            k = rng.randint(1, 23)
        else:
            ang += rng.uniform(0.05, 0.5) * rng.choice((1, 1, 1, -1))
            sc = 32768 * (1 << g)
            x1 = s16(sc * (A1 * math.cos(ang) + m1 + rng.gauss(0, 0.002)))
            x2 = s16(sc * (A2 * math.sin(ang - phi) + m2 + rng.gauss(0, 0.002)))
            k = lambda_k
        progs.append(("update", x1, x2, k, rng.randint(0, 65535), rng.randint(-3, 3)))
        if rng.random() < 0.15:
            progs.append(("extract", 0, 0, k, 0, 0))
    return progs


@cocotb.test()
async def rls_programs(dut):
    from sim.model import program as prog
    from sim.model.rls_engine import RlsEngine

    lanes = fqtb.env_int("LANES", 1)
    rng = random.Random(707)
    progs = make_programs(rng, fqtb.env_int("N_PROGRAMS", 300))
    est = RlsEngine(lanes)
    CYCLES = est.cycles
    bench = fqtb.ClockedBench(dut)
    dut.rst.value = 1
    dut.start_i.value = 0
    await bench.start()
    await bench.step()                      # edge 0: rst
    dut.rst.value = 0
    await bench.step()
    bad = []
    n_invalid = n_updates = n_resets = n_extracts = 0
    for pi, (name, x1, x2, lambda_k, kappa, dg) in enumerate(progs):
        C = CYCLES[name]
        S = bench.edge + 1 + rng.choice((0, 0, 1, 2, rng.randint(0, 30)))
        freeze = rng.random() < 0.2
        await bench.goto(S - 1)
        dut.start_i.value = 1
        dut.entry_i.value = prog.ENTRY[name]
        dut.x1_i.value = x1
        dut.x2_i.value = x2
        dut.lambda_k_i.value = lambda_k
        dut.freeze_i.value = int(freeze)
        dut.kappa_i.value = kappa
        dut.dg_i.value = dg
        await bench.goto(S)
        # the inputs are latched on the start edge only: garbage afterwards
        dut.start_i.value = 0
        dut.entry_i.value = rng.randint(0, 255)
        dut.x1_i.value = rng.randint(-32768, 32767)
        dut.x2_i.value = rng.randint(-32768, 32767)
        dut.lambda_k_i.value = rng.randint(1, 23)
        dut.freeze_i.value = rng.randint(0, 1)
        dut.kappa_i.value = rng.randint(0, 65535)
        dut.dg_i.value = rng.randint(-3, 3)
        if fqtb.uval(dut.busy_o) != 1:
            bad.append(f"program {pi} ({name}) started on edge {S}: busy_o low after it")
        if name == "update":
            ok = est.run("update", x1=x1, x2=x2, lambda_k=lambda_k, freeze=int(freeze))
            n_updates += 1
        elif name == "extract":
            ok = est.run("extract")
            n_extracts += 1
        else:
            ok = est.run("reset", kappa=kappa, dg=dg)
            n_resets += 1
        n_invalid += not ok
        await bench.goto(S + C - 2)
        b, d = fqtb.uval(dut.busy_o), fqtb.uval(dut.done_o)
        if (b, d) != (1, 0):
            bad.append(f"program {pi} ({name}) from edge {S}: after edge S+{C - 2} "
                       f"busy={b} done={d}, expected 1 0")
        await bench.goto(S + C - 1)
        b, d = fqtb.uval(dut.busy_o), fqtb.uval(dut.done_o)
        if (b, d) != (1, 1):
            bad.append(f"program {pi} ({name}) from edge {S}: after edge S+{C - 1} "
                       f"busy={b} done={d}, expected 1 1 (END retires on edge S+{C})")
        await bench.goto(S + C)
        b, d = fqtb.uval(dut.busy_o), fqtb.uval(dut.done_o)
        if (b, d) != (0, 0):
            bad.append(f"program {pi} ({name}) from edge {S}: after edge S+{C} "
                       f"busy={b} done={d}, expected 0 0")
        out = fqtb.uval(dut.out_o)
        got_out = [((out >> (16 * i)) & 0xFFFF) - (((out >> (16 * i)) & 0x8000) << 1)
                   for i in range(len(est.out))]
        got = (fqtb.uval(dut.valid_o), got_out, fqtb.uval(dut.sat_o))
        exp = (int(ok), list(est.out), int(est.sat))
        if got != exp:
            bad.append(f"program {pi} ({name} x=({x1},{x2}) lambda_k={lambda_k} kappa={kappa} "
                       f"dg={dg} freeze={freeze}): (valid,out[m1,m2,c1,c12,c2,e,tr],sat)="
                       f"{got}, model {exp}")
        if len(bad) > 20:
            break
    assert not bad, f"{len(bad)} mismatches:\n" + "\n".join(bad[:20])
    assert n_invalid > 0 and est.sat, "the sequence should reach invalid and saturating programs"
    assert n_extracts > 20
    dut._log.info("rls_engine LANES=%d: %d updates, %d extractions, %d resets (%d invalid) "
                  "equal, clocks %s; final theta %s", lanes, n_updates, n_extracts, n_resets,
                  n_invalid, CYCLES, est.theta())
