"""The engine's ROM images (sim/model/program.py) against the machine's rules, checked on
the encoded words independently of the scheduler, and the images of the two LANES
against each other (the bit-true model executes them; the RTL equals the model:
cocotb_tests/test_rls_engine.py)."""
import random
import sys
from pathlib import Path

import pytest

from sim.model import program
from sim.model.rls_engine import CYCLES_BY_LANES, RlsEngine

REGS = 64                   # operand numbers below this are registers
HAZARD = 6                  # rtl/rls_engine.v forwards results from the round and write
                            # stages: a register written in slot k is read from k + 6 on


def _words(lanes, name):
    im = program.IMAGES[lanes]
    k = im.entry[name]
    out = []
    while True:
        fs = program.decode_word(im.rom[k], lanes)
        out.append(fs)
        if fs[0]["op"] == program.OP_END:
            return out
        k += 1


def _reads(f):
    op = f["op"]
    if op in (program.OP_NOP, program.OP_END):
        return []
    r = [f["a"]]
    if op == program.OP_MAC:
        r.append(f["b"])
    return [x for x in r if x < REGS]


def _writes_reg(f):
    return f["op"] in (program.OP_MAC, program.OP_SEEDR, program.OP_SEEDS) and f["wb"] \
        and not f["out"]


def _reads_dz(f):
    return (f["op"] in (program.OP_SEEDR, program.OP_SEEDS)) or \
        (f["op"] in (program.OP_MAC,) and f["wb"] and f["dyn"] != program.DYN_NONE)


@pytest.mark.parametrize("lanes", program.LANES_ALL)
@pytest.mark.parametrize("name", list(program.PROGRAMS))
def test_schedule_obeys_the_engine_timing(lanes, name):
    """Every register read sees the last write at least HAZARD slots before it (no write to
    it in the HAZARD - 1 slots before nor in its own slot: the RTL would read the old value
    where the model reads the new one), a dz is not written in the slot that reads it, a
    register is written only by the lane that owns its bank, no slot writes a register,
    an OUT or a dz twice, every accumulation starts with clr in its lane, END is in lane 0
    with NOPs beside it, and OUT E is written at least 4 slots before END (the estimator's
    jump detector registers it over three edges)."""
    words = _words(lanes, name)
    per = program.RF_DEPTH // lanes
    last_w = {}
    acc_set = [False] * lanes
    e_slot = None
    for k, fs in enumerate(words):
        writes, outs, dzw = set(), set(), set()
        for lane, f in enumerate(fs):
            if f["op"] == program.OP_END:
                assert lane == 0 and k == len(words) - 1
                assert all(g["op"] == program.OP_NOP for g in fs[1:]), (name, k)
            for r in _reads(f):
                assert k - last_w.get(r, -100) >= HAZARD, (name, k, lane, r)
            if f["op"] == program.OP_MAC and not f["clr"]:
                assert acc_set[lane], (name, k, lane, "accumulates before a clr")
            if f["op"] in (program.OP_MAC, program.OP_SEEDR, program.OP_SEEDS):
                acc_set[lane] = True
            if _writes_reg(f):
                assert f["dst"] // per == lane, (name, k, lane, f["dst"], "bank")
                assert f["dst"] not in writes, (name, k)
                writes.add(f["dst"])
            if f["wb"] and f["out"]:
                assert f["dst"] not in outs, (name, k)
                outs.add(f["dst"])
                if f["dst"] == program.OUTS["E"]:
                    e_slot = k
            if f["op"] in (program.OP_NORMR, program.OP_NORMS):
                assert f["z"] not in dzw
                dzw.add(f["z"])
        for lane, f in enumerate(fs):
            if _reads_dz(f):
                assert f["z"] not in dzw, (name, k, "dz written in the slot that reads it")
            others = {g["dst"] for m, g in enumerate(fs) if m != lane and _writes_reg(g)}
            assert not (set(_reads(f)) & others), (name, k, "read and written in one slot")
        for r in writes:
            last_w[r] = k
    if name == "update":
        assert e_slot is not None and len(words) - 1 - e_slot >= 4


def test_two_lanes_take_fewer_clocks():
    c1, c2 = CYCLES_BY_LANES[1], CYCLES_BY_LANES[2]
    assert all(c2[n] < c1[n] for n in c1), (c1, c2)
    assert all(c == len(_words(L, n)) - 1 + program.PIPE
               for L in program.LANES_ALL for n, c in CYCLES_BY_LANES[L].items())


def _programs(n):
    sys.path.insert(0, str(Path(program.__file__).resolve().parents[2] / "cocotb_tests"))
    from test_rls_engine import make_programs
    return make_programs(random.Random(11), n)


def test_every_lanes_computes_the_same_bits():
    """The same program sequence (noisy ellipses, resets with gain changes, extractions,
    bursts of garbage that make programs invalid and registers saturate) on the model of
    each LANES: after every program the outputs, valid, sat and every persistent register
    agree."""
    rng = random.Random(5)
    ests = [RlsEngine(L) for L in program.LANES_ALL]
    n_inv = 0
    for name, x1, x2, k, kappa, dg in _programs(2000):
        fr = rng.random() < 0.2
        res = []
        for e in ests:
            if name == "update":
                ok = e.run(name, x1=x1, x2=x2, lambda_k=k, freeze=fr)
            elif name == "reset":
                ok = e.run(name, kappa=kappa, dg=dg)
            else:
                ok = e.run(name)
            res.append((ok, list(e.out), e.sat, [e.reg(r) for r in program.persistent_names()]))
        assert all(r == res[0] for r in res[1:]), name
        n_inv += not res[0][0]
    assert n_inv > 0 and ests[0].sat


def test_out_tr_is_the_trace_of_the_stored_p():
    """OUT TR (s12.4) is the rounded sum of P's stored diagonal after every UPDATE, and 5
    kappa after a RESET."""
    est = RlsEngine()
    n = 0
    for name, x1, x2, k, kappa, dg in _programs(600):
        if name == "update":
            est.run(name, x1=x1, x2=x2, lambda_k=k)
            s = sum(est.reg(program.P(i, i)) for i in range(5))
            tr = (s + (1 << 18)) >> 19
            assert est.out[program.OUTS["TR"]] == max(-32768, min(32767, tr))
            n += 1
        elif name == "reset":
            est.run(name, kappa=kappa, dg=dg)
            assert est.out[program.OUTS["TR"]] == (5 * kappa) >> 4
    assert n > 400
