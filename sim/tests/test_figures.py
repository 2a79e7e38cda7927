"""The headline figures (scripts/figures.py): records written by the measuring commands,
README.md's block rendered from them and checked by `make test`."""
import json
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import figures  # noqa: E402

README = f"# x\n\nintro\n\n{figures.BEGIN}\nold\n{figures.END}\n\nrest\n"
BENCH = dict(scenarios=11, ratio_min=1.0, ratio_max=1.095, slips=0, rtl_equal=11)


def test_committed_readme_block_is_current():
    assert figures.check(), "README.md's figures block is stale: python3 scripts/figures.py"


def test_publish_writes_record_table_and_readme(tmp_path):
    res, readme = tmp_path / "results", tmp_path / "README.md"
    readme.write_text(README)
    figures.publish("bench_accuracy", "make bench-accuracy", BENCH, "| a | b |\n|---|---|",
                    results=res, readme=readme)
    rec = json.loads((res / "bench_accuracy.json").read_text())
    assert rec["command"] == "make bench-accuracy" and rec["headline"] == BENCH
    md = (res / "bench_accuracy.md").read_text()
    assert md.startswith(f"Measured with `make bench-accuracy` on {rec['date']}.")
    text = readme.read_text()
    assert text.startswith("# x\n\nintro\n\n") and text.endswith("\n\nrest\n")
    assert "old" not in text and "1.000 to 1.095" in text and rec["date"] in text
    assert figures.check(res, readme)
    # a figure typed into the block by hand is stale
    readme.write_text(text.replace("1.095", "1.050"))
    assert not figures.check(res, readme)
    # a second record adds its rows, in table order
    readme.write_text(text)
    figures.publish("demo", "make demo", dict(rms_nm=4.66, ratio=1.04, rtl_equals_model=True),
                    "t", results=res, readme=readme)
    text = readme.read_text()
    assert text.index("Accuracy") < text.index("Demo recording") and figures.check(res, readme)


def test_bad_readme_and_records_are_named(tmp_path):
    res, readme = tmp_path / "results", tmp_path / "README.md"
    readme.write_text("no markers\n")
    with pytest.raises(figures.FiguresError, match="expected one block"):
        figures.publish("demo", "make demo", dict(rms_nm=1, ratio=1, rtl_equals_model=True),
                        "t", results=res, readme=readme)
    with pytest.raises(figures.FiguresError, match="unknown record 'x'"):
        figures.publish("x", "make x", {}, "t", results=res, readme=readme)
    res.mkdir(exist_ok=True)
    (res / "demo.json").write_text(json.dumps({"name": "demo", "headline": {}}))
    with pytest.raises(figures.FiguresError, match="demo.json: not a record of demo"):
        figures.render(res)


def test_the_vhdl_editions_record_says_whether_its_table_is_the_verilog_editions(tmp_path):
    res, readme = tmp_path / "results", tmp_path / "README.md"
    readme.write_text(README)
    figures.publish("bench_accuracy", "make bench-accuracy", BENCH, "| a | b |", results=res,
                    readme=readme)
    vt = figures.table("bench_accuracy", res)
    assert vt == "| a | b |\n"                            # without the line naming the run
    head = dict(BENCH, same_as_verilog=True, verilog_table_sha256=figures.sha256(vt))
    figures.publish("bench_accuracy_vhdl", "make bench-accuracy EDITION=vhdl", head, "t",
                    results=res, readme=readme)
    text = readme.read_text()
    assert "VHDL == model on 11 of 11; 1.000 to 1.095 x the floor; 0 slips; table identical " \
        "to the Verilog edition's | `make bench-accuracy EDITION=vhdl`" in text
    assert text.index("RTL == model") < text.index("VHDL == model")   # table order
    assert figures.check(res, readme) and not figures.stale(res)
    # the Verilog table published again, the same: still current; different: stale
    figures.publish("bench_accuracy", "make bench-accuracy", BENCH, "| a | b |",
                    results=res, readme=readme)
    assert figures.check(res, readme)
    figures.publish("bench_accuracy", "make bench-accuracy", BENCH, "| a | c |",
                    results=res, readme=readme)
    (why,) = figures.stale(res)
    assert "bench_accuracy_vhdl.json was compared with a Verilog accuracy table" in why
    assert "make bench-accuracy EDITION=vhdl" in why and not figures.check(res, readme)
    figures.publish("bench_accuracy_vhdl", "make bench-accuracy EDITION=vhdl",
                    dict(head, same_as_verilog=False), "t", results=res, readme=readme)
    assert "table NOT the same as the Verilog edition's" in readme.read_text()


def test_a_table_is_read_only_as_publish_wrote_it(tmp_path):
    assert figures.table("bench_accuracy", tmp_path) is None          # none published
    (tmp_path / "bench_accuracy.md").write_text("n = 100\n\n| a |\n")
    with pytest.raises(figures.FiguresError, match="bench_accuracy.md: not a table publish"):
        figures.table("bench_accuracy", tmp_path)
    # the committed one is the table make bench-accuracy printed
    assert figures.table("bench_accuracy").startswith("n = 100, 4 um pitch")
