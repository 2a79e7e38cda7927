"""scripts/ghdl_netlist.py's repairs of GHDL's Verilog, on fixtures written the way GHDL
2.0 writes them (the netlists themselves are checked against the model by
cocotb_tests/test_netlists.py and make rtlsim EDITION=vhdl-synth)."""
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import ghdl_netlist  # noqa: E402

GHDL = """module m
  (input  clk,
   input  [3:0] a,
   output [3:0] y);
  reg [3:0] p1;
  wire [4:0] psum;
  wire [3:0] twin1;
  wire [3:0] twin2;
  reg [3:0] n5_q;
  wire [4:0] n7_o;
  wire [3:0] n9_o;
  assign y = n5_q;
  /* m.vhd:10:10  */
  always @*
    p1 = n5_q; // (isignal)
  initial
    p1 <= 4'b0000;
  /* m.vhd:11:10  */
  assign psum = n7_o; // (signal)
  assign twin1 = n9_o; // (signal)
  assign twin2 = n9_o; // (signal)
  assign n7_o = {1'b0, p1} + 5'b00001;
  assign n9_o = psum[3:0];
  always @(posedge clk)
    n5_q <= a;
  initial
    n5_q <= 4'b0000;
endmodule

module other
  (output [3:0] q);
  wire [3:0] n5_q;
  assign q = n5_q;
  assign n5_q = 4'b0001;
endmodule
"""


def test_named_nets_gives_each_signal_its_name():
    out = ghdl_netlist.named_nets(GHDL)
    m, other = out.split("endmodule\n")[:2]
    # the register and the expression take the signals' names; aliases and the
    # signals' own declarations are gone
    assert "  reg [3:0] p1;\n" in m and "n5_q" not in m
    assert "    p1 <= a;\n" in m and "  assign y = p1;\n" in m
    assert "  wire [4:0] psum;\n" in m and "n7_o" not in m
    assert "  assign psum = {1'b0, p1} + 5'b00001;\n" in m
    assert "(isignal)" not in m and "assign psum = psum" not in m
    assert m.count("reg [3:0] p1;") == 1 and m.count("wire [4:0] psum;") == 1
    # a net with two aliases keeps its name, and so do both aliases
    assert "assign twin1 = n9_o; // (signal)" in m and "assign twin2 = n9_o; // (signal)" in m
    # each module on its own: the other module's n5_q is not the first's
    assert "  assign q = n5_q;\n" in other


def test_named_nets_leaves_a_netlist_without_aliases_alone():
    text = "module t\n  (output y);\n  assign y = 1'b1;\nendmodule\n"
    assert ghdl_netlist.named_nets(text) == text
