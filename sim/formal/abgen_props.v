`timescale 1ns / 1ps
`default_nettype none
// Formal wrapper for rtl/abgen.v (BMC from the initial values; every input free on every
// clock: rst, target_i (any jump), sep_i (0..255), bound_i). COUNT_W = 18 keeps the
// arithmetic small; nothing below depends on the width.
// Run (not yet wired into scripts/formal.py):
//   yosys -q -p 'read_verilog -formal rtl/abgen.v sim/formal/abgen_props.v;
//                prep -top fv_abgen; write_smt2 -wires /tmp/abgen.smt2'
//   yosys-smtbmc -s z3 -i -t 40 /tmp/abgen.smt2     (-i: also prove each property at
//                                                    every depth by induction, step mode)
// The wrapper keeps a ghost timer (gap, independent of the RTL's) from the A/B changes.
// Properties (on a clock after an edge that was not rst):
//  P1 never both a_o and b_o change.
//  P2 the quadrant code {~b, a ^ b} of rtl/counter.v equals pos_o mod 4, so an x4 decoder
//     counting a_o/b_o reads pos_o.
//  P3 pos_o moves by 0 or +-1, and only toward the target: by sign(target - pos) of the
//     edge (modular difference).
//  P4 an edge only when at least max(sep, 1) clocks have passed since the last one.
//  P5 no pacing lost: target != pos and max(sep, 1) clocks passed -> pos moved.
//  P6 ovf_o == |target - pos| > bound on the edge; backlog_o == sat16(target - pos);
//     ovf_sticky_o == previous sticky | ovf_o.
//  P7 after rst: pos 0, A = B = 1, flags 0.
module fv_abgen (
    input wire               clk,
    input wire               rst,
    input wire signed [17:0] target_i,
    input wire        [7:0]  sep_i,
    input wire        [15:0] bound_i
);
    localparam CW = 18;
    wire                 a_o, b_o, ovf_o, ovf_sticky_o;
    wire signed [CW-1:0] pos_o;
    wire signed [15:0]   backlog_o;

    abgen #(.COUNT_W(CW)) u_dut (
        .clk(clk), .rst(rst), .target_i(target_i), .sep_i(sep_i), .bound_i(bound_i),
        .a_o(a_o), .b_o(b_o), .pos_o(pos_o), .backlog_o(backlog_o), .ovf_o(ovf_o),
        .ovf_sticky_o(ovf_sticky_o)
    );

    // inputs and outputs of the previous edge
    reg                 past_valid = 1'b0;
    reg                 p_rst = 1'b0;
    reg signed [CW-1:0] p_target = 0, p_pos = 0;
    reg [7:0]           p_sep = 8'd0;
    reg [15:0]          p_bound = 16'd0;
    reg                 p_a = 1'b1, p_b = 1'b1, p_sticky = 1'b0;
    wire a_chg = (a_o != p_a), b_chg = (b_o != p_b);
    wire edge_now = a_chg || b_chg;

    always @(posedge clk) begin
        past_valid <= 1'b1;
        p_rst    <= rst;
        p_target <= target_i;
        p_pos    <= pos_o;
        p_sep    <= sep_i;
        p_bound  <= bound_i;
        p_a      <= a_o;
        p_b      <= b_o;
        p_sticky <= ovf_sticky_o;
    end

    wire signed [CW-1:0] d = p_target - p_pos;            // modular, on the last edge
    wire        [CW:0]   absd = d[CW-1] ? -{d[CW-1], d} : {1'b0, d};
    wire        [7:0]    sep_e = (p_sep == 8'd0) ? 8'd1 : p_sep;
    wire signed [15:0]   sat_d = (d > 32767) ? 16'sh7FFF : (d < -32768) ? 16'sh8000
                                                                           : d[15:0];
    wire signed [CW-1:0] dpos = pos_o - p_pos;

    // ghost timer, independent of the RTL's: after edge e, gap = e - j for the last edge j
    // with an A/B change (saturating at 255; 255 after rst and at start), i.e. how many
    // clocks had passed since the last output edge when edge e was taken
    reg [7:0] gap = 8'd255;
    always @(posedge clk) begin
        if (rst)
            gap <= 8'd255;
        else if (past_valid && !p_rst && edge_now)
            gap <= 8'd1;
        else if (gap != 8'd255)
            gap <= gap + 8'd1;
    end

    always @(*) begin
        if (past_valid && !p_rst) begin
            assert (!(a_chg && b_chg));                                          // P1
            assert ({~b_o, a_o ^ b_o} == pos_o[1:0]);                            // P2
            assert (dpos == 0 || (dpos == 1 && !d[CW-1] && d != 0)
                    || (dpos == -1 && d[CW-1]));                                 // P3
            assert (edge_now == (dpos != 0));
            if (edge_now)
                assert (gap >= sep_e);                                           // P4
            if (d != 0 && gap >= sep_e)
                assert (edge_now);                                               // P5
            assert (ovf_o == (absd > {{(CW-15){1'b0}}, p_bound}));              // P6
            assert (backlog_o == sat_d);
            assert (ovf_sticky_o == (p_sticky | ovf_o));
        end
        if (past_valid && p_rst)
            assert (pos_o == 0 && a_o && b_o && !ovf_o && !ovf_sticky_o
                    && backlog_o == 0);                                          // P7
    end
endmodule
`resetall
