`timescale 1ns / 1ps
`default_nettype none
// abgen: paced A/B quadrature output that follows the position counter
// (sim/model/abgen.py abgen()).
//
// pos (the count the outputs represent, i.e. what an x4 decoder counting a_o/b_o from rst
// reads) chases target_i by one count per edge, with at least sep_i clocks between two
// output edges. Per clock edge (not rst), with d = target_i - pos (mod 2^COUNT_W, signed)
// and cnt = clocks since the last output edge (saturating at 255, 255 after rst):
//   step = (d != 0) && (cnt >= sep_i)       (sep_i = 0 acts as 1: cnt is never 0)
//   pos <= pos + sign(d) when step;   cnt <= step ? 1 : min(cnt + 1, 255)
//   (a_o, b_o) <= AB(pos) with AB(q) for q = pos mod 4: 0 (1,1), 1 (0,1), 2 (0,0), 3 (1,0)
//   i.e. the quadrant code {~b, a ^ b} of rtl/counter.v (edge mode) is pos mod 4: one of
//   A/B toggles per step, never both; counting up is (1,1)->(0,1)->(0,0)->(1,0)->(1,1).
//   backlog_o <= sat16(d),  ovf_o <= |d| > bound_i,  ovf_sticky_o <= ovf_sticky_o | that
// backlog_o and ovf_o describe the distance on the edge, before that edge's step:
// after edge e, backlog_o = target_i(e) - pos_o(after edge e-1).
// d is the modular difference, so a wrapping target (a counter running over 2^COUNT_W)
// is followed the short way; it equals the plain difference while |target - pos| stays
// below 2^(COUNT_W-1). Nothing is lost: the backlog is paid at one count per sep clocks.
// rst (sync): pos = 0, A = B = 1, cnt = 255 (first step allowed on the next edge), backlog
// 0, flags 0. The core resets the position counter (target) to 0 together with this block.
// Latency 1: target_i on edge e can move pos_o after edge e.
// Cost: one COUNT_W subtract (d), one COUNT_W increment/decrement (pos), a 16-bit compare
// carry chain (ovf), an 8-bit saturating timer and 8-bit compare. No multipliers.
module abgen #(
    parameter COUNT_W = 32                 // >= 17
) (
    input  wire                      clk,
    input  wire                      rst,          // sync, active high
    input  wire signed [COUNT_W-1:0] target_i,     // s(COUNT_W).0 counts (x4 units)
    input  wire        [7:0]         sep_i,        // u8 min clocks between edges (0 as 1)
    input  wire        [15:0]        bound_i,      // u16 counts, backlog bound for ovf
    output reg                       a_o,
    output reg                       b_o,
    output reg  signed [COUNT_W-1:0] pos_o,        // s(COUNT_W).0 counts, 0 after rst
    output reg  signed [15:0]        backlog_o,    // s16.0 counts, sat(target - pos)
    output reg                       ovf_o,        // |target - pos| > bound (registered)
    output reg                       ovf_sticky_o  // ovf seen since rst
);
    // d = target - pos, s(COUNT_W).0 modular
    wire signed [COUNT_W-1:0] d = target_i - pos_o;
    wire        neg = d[COUNT_W-1];
    wire        nz  = |d;

    // timer: u8 clocks since the last edge, 1..255 (saturating)
    reg  [7:0]  cnt = 8'hFF;
    wire        step = nz && (cnt >= sep_i);

    // next position and its A/B (quadrant q = pos mod 4)
    wire [COUNT_W-1:0] pos_n = pos_o + {{(COUNT_W-1){neg}}, 1'b1};   // pos +- 1
    wire [1:0]         q_n   = pos_n[1:0];

    // |d| > bound: with m = d ^ {sign} (= d if d >= 0, = |d| - 1 if d < 0)
    //   d >= 0: m > bound  <=> m + ~bound     >= 2^16 (or m >= 2^16)
    //   d <  0: m >= bound <=> m + ~bound + 1 >= 2^16 (or m >= 2^16)
    wire [COUNT_W-1:0] m = d ^ {COUNT_W{neg}};
    /* verilator lint_off UNUSEDSIGNAL */
    wire [16:0]        cmp = {1'b0, m[15:0]} + {1'b0, ~bound_i} + {16'd0, neg};
    /* verilator lint_on UNUSEDSIGNAL */
    wire               ovf_n = (|m[COUNT_W-1:16]) | cmp[16];  // only the carry is used

    // backlog: d saturated to s16
    wire        fits = (m[COUNT_W-1:15] == {(COUNT_W-15){1'b0}});
    wire [15:0] bl_n = fits ? d[15:0] : {neg, {15{~neg}}};

    always @(posedge clk) begin
        if (step) begin
            pos_o <= pos_n;
            a_o   <= ~(q_n[1] ^ q_n[0]);
            b_o   <= ~q_n[1];
            cnt   <= 8'd1;
        end else if (cnt != 8'hFF) begin
            cnt   <= cnt + 8'd1;
        end
        backlog_o    <= bl_n;
        ovf_o        <= ovf_n;
        ovf_sticky_o <= ovf_sticky_o | ovf_n;
        if (rst) begin
            pos_o        <= {COUNT_W{1'b0}};
            a_o          <= 1'b1;
            b_o          <= 1'b1;
            cnt          <= 8'hFF;
            backlog_o    <= 16'sd0;
            ovf_o        <= 1'b0;
            ovf_sticky_o <= 1'b0;
        end
    end

    initial begin
        a_o = 1'b1; b_o = 1'b1; pos_o = {COUNT_W{1'b0}}; backlog_o = 16'sd0;
        ovf_o = 1'b0; ovf_sticky_o = 1'b0;
    end
endmodule
`resetall
