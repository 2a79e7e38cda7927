"""The register map's generated views (scripts/gen_regs.py from rtl/regs/finequad.rdl).

* The C header (PeakRDL-cheader) compiles with gcc -std=c99 -Wall -Wextra -Werror; a
  driver-style program (sim/tests/c/regs_example.c) uses it and checks its own results;
  and a program generated here prints every register's offset and every field's macros,
  which must equal sim/model/regs.py (two generators of one description agree).
* The VHDL package (rtl/vhdl/finequad_regs_pkg.vhd) analyses under GHDL (VHDL-2008), and
  a bench generated here prints every register's index, every field's position, reset
  and legal values, and fq_write_ok's verdict on boundary and random words for three
  option sets, which must equal sim/model/regs.py (REGS, illegal()).
* `--check` (run by `make test`) fails when a generated file is stale: on a copy of the
  tree, an edit of the description or of a generated file makes it exit 1 naming the file,
  and changes nothing; the untouched copy passes.
* A description the generators cannot serve is refused with a line naming the place.
* The model's settings (sim.model.finequad_core.Config) default to the reset values, and
  register_writes() of the default Config writes every settings register's reset word.
"""
import pathlib
import shutil
import subprocess
import sys

import pytest

from sim.model import finequad_core as core
from sim.model import regs

ROOT = pathlib.Path(__file__).resolve().parents[2]
GEN = ROOT / "scripts" / "gen_regs.py"
CFLAGS = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic-errors",
          "-Wno-error=pedantic"]
needs_gcc = pytest.mark.skipif(shutil.which("gcc") is None, reason="no gcc")
needs_ghdl = pytest.mark.skipif(shutil.which("ghdl") is None, reason="no ghdl")


def gen(*args, cwd=ROOT):
    return subprocess.run([sys.executable, str(GEN), *args], cwd=cwd, capture_output=True,
                          text=True)


def compile_run(tmp_path, src, name):
    exe = tmp_path / name
    cc = subprocess.run(["gcc", *CFLAGS[:4], "-I", str(ROOT / "rtl/regs"), str(src), "-o",
                         str(exe)], capture_output=True, text=True)
    assert cc.returncode == 0 and not cc.stderr, f"gcc: {cc.stderr}"
    return subprocess.run([str(exe)], capture_output=True, text=True)


@needs_gcc
def test_c_header_compiles_and_a_driver_uses_it(tmp_path):
    r = compile_run(tmp_path, ROOT / "sim/tests/c/regs_example.c", "example")
    assert r.returncode == 0, r.stdout
    assert r.stdout.strip() == "0 failure(s)"


@needs_gcc
def test_c_header_agrees_with_the_python_view(tmp_path):
    lines = ['#include <stddef.h>', '#include <stdio.h>', '#include "finequad_regs.h"',
             "int main(void) {"]
    expect = []
    for name, r in regs.REGS.items():
        member = "CTRL_STATUS" if name in ("CTRL", "STATUS") else name
        lines.append(f'    printf("{name} %lu\\n", (unsigned long)offsetof(finequad_t, '
                     f'{member}));')
        expect.append(f"{name} {r.addr}")
        for f in r.fields.values():
            m = f"FINEQUAD__{name}__{f.name.upper()}"
            lines.append(f'    printf("{name}.{f.name} %lu %lu %lu\\n", (unsigned long){m}_bp, '
                         f'(unsigned long){m}_bw, (unsigned long){m}_bm);')
            expect.append(f"{name}.{f.name} {f.lsb} {f.width} "
                          f"{((1 << f.width) - 1) << f.lsb}")
            if f.reset is not None and (f.write or name == "ID"):
                lines.append(f'    printf("{name}.{f.name} reset %lu\\n", '
                             f'(unsigned long){m}_reset);')
                expect.append(f"{name}.{f.name} reset {f.reset & ((1 << f.width) - 1)}")
    lines += ["    return 0;", "}"]
    src = tmp_path / "agree.c"
    src.write_text("\n".join(lines) + "\n")
    r = compile_run(tmp_path, src, "agree")
    assert r.returncode == 0
    assert r.stdout.split("\n")[:-1] == expect


def _write_checks(seed=5):
    """(index, word) pairs for fq_write_ok: every index of the port; per writable register
    0, all ones, its reset word, each field at lo - 1, lo, hi, hi + 1 (others at reset),
    one bit outside the fields, and random words."""
    import random
    rng = random.Random(seed)
    out = []
    for a in range(64):
        out += [(a, 0), (a, 0xFFFFFFFF)]
    for r in regs.REGS.values():
        if not r.write:
            continue
        out.append((r.index, r.reset))
        for f in r.fields.values():
            m = (1 << f.width) - 1
            for v in (f.lo - 1, f.lo, f.hi, f.hi + 1):
                out.append((r.index, (r.reset & ~(m << f.lsb)) | ((v & m) << f.lsb)))
        free = ~r.wmask & 0xFFFFFFFF
        if free:
            out.append((r.index, r.reset | (free & -free)))
        out += [(r.index, rng.getrandbits(32)) for _ in range(6)]
        out += [(r.index, rng.getrandbits(32) & r.wmask) for _ in range(6)]
    return out


VHDL_OPTION_SETS = (dict(OPT_DCODE=1, OPT_HARMONIC=1, OPT_JUMP=1, OPT_MONITOR=1, OPT_TUNABLE=1),
                    dict(OPT_DCODE=0, OPT_HARMONIC=0, OPT_JUMP=0, OPT_MONITOR=0, OPT_TUNABLE=0),
                    dict(OPT_DCODE=1, OPT_HARMONIC=0, OPT_JUMP=1, OPT_MONITOR=0, OPT_TUNABLE=1))


@needs_ghdl
def test_vhdl_package_agrees_with_the_python_view(tmp_path):
    writable = {r.index: name for name, r in regs.REGS.items() if r.write}
    lines = ["library ieee;", "  use ieee.std_logic_1164.all;", "  use ieee.numeric_std.all;",
             "library std;", "  use std.textio.all;", "library work;",
             "  use work.finequad_regs_pkg.all;", "entity agree is", "end entity agree;",
             "architecture sim of agree is", "begin", "  process is",
             "    variable l : line;", "  begin"]
    expect = []

    def put(expr, want):
        lines.append(f"    write(l, {expr}); writeline(output, l);")
        expect.append(want)

    for name, r in regs.REGS.items():
        put(f'"{name} " & to_string(to_integer(FQ_{name}))', f"{name} {r.index}")
        for f in r.fields.values():
            p = f"FQ_{name}_{f.name.upper()}"
            put(f'"{name}.{f.name} " & to_string({p}_LSB) & " " & to_string({p}_MSB) & " " '
                f'& to_string({p}_W)', f"{name}.{f.name} {f.lsb} {f.lsb + f.width - 1} {f.width}")
            if f.reset is not None and (f.write or name == "ID"):
                put(f'"{name}.{f.name} reset " & to_string({p}_RESET)',
                    f"{name}.{f.name} reset {f.reset & ((1 << f.width) - 1):0{f.width}b}")
            if f.write and not f.pulse and not f.w1c:
                put(f'"{name}.{f.name} legal " & to_string({p}_LO) & " " & to_string({p}_HI)',
                    f"{name}.{f.name} legal {f.lo} {f.hi}")
        if r.write:
            put(f'"{name} wmask " & to_hstring(FQ_{name}_WMASK) & " reset " '
                f'& to_hstring(FQ_{name}_RESET)', f"{name} wmask {r.wmask:08X} reset {r.reset:08X}")
    checks = _write_checks()
    for k, opts in enumerate(VHDL_OPTION_SETS):
        rec = ", ".join(f"{o.lower()} => {'true' if v else 'false'}" for o, v in opts.items())
        lines.append(f"    -- options {k}")
        for a, w in checks:
            name = writable.get(a)
            ok = name is not None and regs.illegal(name, w, build=opts) is None
            put(f'"{k} {a} {w:08x} " & boolean\'image(fq_write_ok(6x"{a:02x}", x"{w:08x}", '
                f"({rec})))", f"{k} {a} {w:08x} {'true' if ok else 'false'}")
    lines += ["    wait;", "  end process;", "end architecture sim;"]
    src = tmp_path / "agree.vhd"
    src.write_text("\n".join(lines) + "\n")
    pkg = ROOT / "rtl/vhdl/finequad_regs_pkg.vhd"
    for cmd in (["-a", "--std=08", str(pkg), str(src)], ["-e", "--std=08", "agree"]):
        r = subprocess.run(["ghdl", *cmd], cwd=tmp_path, capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
    r = subprocess.run(["ghdl", "-r", "--std=08", "agree"], cwd=tmp_path, capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
    got = r.stdout.splitlines()
    assert len(got) == len(expect)
    bad = [f"{g!r} != {e!r}" for g, e in zip(got, expect) if g != e]
    assert not bad, f"{len(bad)} differ:\n" + "\n".join(bad[:20])
    assert sum(e.endswith("true") for e in expect) > 100        # both verdicts are exercised
    assert sum(e.endswith("false") for e in expect) > 100


def _copy_tree(tmp_path):
    """The description and the generated files, copied to a tree of their own."""
    out = {}
    for rel in ["rtl/regs/finequad.rdl", *gen_files()]:
        dst = tmp_path / rel
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / rel, dst)
        out[rel] = dst
    return out


def gen_files():
    sys.path.insert(0, str(ROOT / "scripts"))
    import gen_regs
    return list(gen_regs.files().keys())


def test_the_committed_files_are_current():
    r = gen("--check")
    assert r.returncode == 0, r.stderr


def test_check_names_a_stale_file_and_changes_nothing(tmp_path):
    files = _copy_tree(tmp_path)
    rdl = files["rtl/regs/finequad.rdl"]
    args = ["--check", "--rdl", str(rdl), "--root", str(tmp_path)]
    assert gen(*args).returncode == 0                       # the copy as committed
    # the description edited: INTERP's reset value
    text = rdl.read_text()
    assert "interp[8:0] = 100;" in text
    rdl.write_text(text.replace("interp[8:0] = 100;", "interp[8:0] = 101;"))
    before = {k: p.read_bytes() for k, p in files.items()}
    r = gen(*args)
    assert r.returncode == 1
    for rel in ("rtl/finequad_regs.vh", "sim/model/regs.py", "rtl/regs/finequad_regs.h",
                "rtl/regs/README.md", "sim/harness/regs.h", "rtl/vhdl/finequad_regs_pkg.vhd"):
        assert rel in r.stderr, (rel, r.stderr)
    assert {k: p.read_bytes() for k, p in files.items()} == before   # --check wrote nothing
    # a generated file edited by hand, the description as committed
    rdl.write_text(text)
    vh = files["rtl/finequad_regs.vh"]
    vh.write_text(vh.read_text().replace("6'h01;", "6'h02;", 1))
    r = gen(*args)
    assert r.returncode == 1 and "rtl/finequad_regs.vh" in r.stderr
    assert "sim/model/regs.py" not in r.stderr
    # writing (make regs) makes it current again
    assert gen("--rdl", str(rdl), "--root", str(tmp_path)).returncode == 0
    assert gen(*args).returncode == 0


@pytest.mark.parametrize("edit, message", [
    (("legal = \"1..511\"", "legal = \"1..512\""), "legal 1..512 outside the field's 9-bit range"),
    (("legal = \"1..511\"", "legal = \"one to 511\""), "expected \"lo..hi\""),
    (("} COAST @ 0x94;", "} COAST @ 0x96;"), "COAST at byte 0x96: not word-aligned"),
    (("jump_min[10:0] = 41;", "eps[10:0] = 41;"), "setting 'eps' in EPS and JUMP"),
    (("glitch[10:10] = 0;", "glitch[11:11] = 0;"), "FAULT_STICKY: its fields must be single bits"),
    (("} INTERP @ 0x04;", "} INTERP @ 0x04"), "does not compile"),
])
def test_a_bad_description_is_refused_with_its_place(tmp_path, edit, message):
    files = _copy_tree(tmp_path)
    rdl = files["rtl/regs/finequad.rdl"]
    text = rdl.read_text()
    assert edit[0] in text
    rdl.write_text(text.replace(edit[0], edit[1], 1))
    before = {k: p.read_bytes() for k, p in files.items()}
    r = gen("--rdl", str(rdl), "--root", str(tmp_path))
    assert r.returncode == 2 and r.stderr.startswith("gen_regs: error: "), r.stderr
    assert message in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert {k: p.read_bytes() for k, p in files.items()} == before


def test_model_defaults_are_the_reset_values():
    cfg = core.Config()
    for name, f in regs.SETTINGS.items():
        if f.reg in core.BUNDLE_REGS:
            continue
        assert getattr(cfg, name) == f.reset, name
    writes = dict(core.register_writes(cfg))
    for name, r in regs.REGS.items():
        settings = [f for f in r.fields.values() if f.write and not f.pulse and not f.w1c]
        if settings and name not in core.BUNDLE_REGS:
            assert writes[r.index] == r.reset, name
    assert core.BUNDLE0 == tuple(regs.SETTINGS[f].reset if f != "gain" else 0
                                 for f in ("gain", "m1", "m2", "c1", "c12", "c2"))


def test_word_helpers():
    assert regs.word("HARM", harm_mu=3) == regs.REGS["HARM"].reset | 0x30
    assert regs.value("M1", "m1", 0xFFFF8000) == -32768
    assert regs.illegal("INTERP", 512) is not None
    assert regs.illegal("INTERP", 0) == "INTERP.interp = 0: outside 1..511"
    assert regs.illegal("INTERP", 511) is None
    assert regs.illegal("M1", 0x8000) is not None             # +32768: not s16
    assert regs.illegal("M1", 0xFFFF8000) is None
    assert regs.illegal("JUMP", 1 << 14) is not None           # a bit no field holds
    assert regs.word_read("STATUS", loaded=1) == 1 << regs.REGS["STATUS"].fields["loaded"].lsb
