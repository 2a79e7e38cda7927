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
//   d_q <= d,  bound_q <= bound_i;  from those (the edge before):
//   backlog_o <= sat16(d_q),  ovf_o <= |d_q| > bound_q,  ovf_sticky_o <= ovf_sticky_o | that
// backlog_o and ovf_o describe the distance one edge before, before that edge's step:
// after edge e, backlog_o = target_i(e-1) - pos_o(after edge e-2) (0 after rst).
// d is the modular difference, so a wrapping target (a counter running over 2^COUNT_W)
// is followed the short way; it equals the plain difference while |target - pos| stays
// below 2^(COUNT_W-1). Nothing is lost: the backlog is paid at one count per sep clocks.
// rst (sync): pos = 0, A = B = 1, cnt = 255 (first step allowed on the next edge), backlog
// 0, flags 0. The core resets the position counter (target) to 0 together with this block.
// Latency 1: target_i on edge e can move pos_o after edge e.
// Z (z_o, registered with a_o, b_o): z_o <= z_en_i && (pos after the edge == z_at_i), with
// z_en_i, z_at_i as they stand before the edge: high exactly while the pins show the
// count z_at_i (rtl/refmark.v arms it at the reference), so a decoder sees Z in one A/B
// state, one count wide, in both directions; 0 after rst.
// Cost: one COUNT_W subtract (d), one COUNT_W add of +-1 (pos), a 16-bit compare
// carry chain (ovf), an 8-bit saturating timer and 8-bit compare; for Z one COUNT_W
// subtract (z_at - pos, beside d) and three equality trees. No multipliers.
module abgen #(
    parameter COUNT_W = 32,                // >= 17
    // 1: sep_i, bound_i are registers; 0: constants (rtl/finequad_core.v OPT_TUNABLE = 0):
    // compared bit by bit, which synthesis folds into a few LUTs
    parameter [0:0] OPT_TUNABLE = 1'b1
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
    output reg                       ovf_sticky_o, // ovf seen since rst
    input  wire                      z_en_i,       // Z armed (rtl/refmark.v)
    input  wire signed [COUNT_W-1:0] z_at_i,       // s(COUNT_W).0 the count Z marks
    output reg                       z_o           // Z: the pins at z_at_i, armed
);
`include "geu.vh"                          // geu(a, b): a >= b, unsigned, bit by bit
    // parameter check (as rtl/finequad_core.v; rtl/vhdl/abgen.vhd's range): ovf reads
    // d above bit 15, so COUNT_W >= 17; an undefined module named after the rule stops
    // elaboration
    generate
        if (COUNT_W < 17) begin : g_bad_count_w
            abgen_COUNT_W_must_be_17_or_more u_bad ();
        end
    endgenerate
    // d = target - pos, s(COUNT_W).0 modular; whether it is zero comes from an equality
    // tree beside the subtraction
    wire signed [COUNT_W-1:0] d = target_i - pos_o;
    wire        neg = d[COUNT_W-1];
    wire        nz  = (target_i != pos_o);

    // timer: u8 clocks since the last edge, 1..255 (saturating)
    reg  [7:0]  cnt = 8'hFF;
    wire        step = nz && (OPT_TUNABLE ? cnt >= sep_i : geu({24'd0, cnt}, {24'd0, sep_i}));

    // next position and its A/B (quadrant q = pos mod 4)
    // pos + 1 or pos - 1 in one carry chain (pos + {-1 or 0, 1}) behind d's sign
    wire [COUNT_W-1:0] pos_n = pos_o + {{(COUNT_W-1){neg}}, 1'b1};
    wire [1:0]         q_n   = pos_n[1:0];

    // the flags come from d registered (one edge later: the subtraction and the
    // comparison in one clock were the UP5K's critical path)
    reg signed [COUNT_W-1:0] d_q = 0;
    reg        [15:0]        bound_q = 16'd0;
    wire       neg_q = d_q[COUNT_W-1];
    // |d| > bound: with m = d ^ {sign} (= d if d >= 0, = |d| - 1 if d < 0)
    //   d >= 0: m > bound  <=> m + ~bound     >= 2^16 (or m >= 2^16)
    //   d <  0: m >= bound <=> m + ~bound + 1 >= 2^16 (or m >= 2^16)
    wire [COUNT_W-1:0] m = d_q ^ {COUNT_W{neg_q}};
    /* verilator lint_off UNUSEDSIGNAL */
    wire [16:0]        cmp = {1'b0, m[15:0]} + {1'b0, ~bound_q} + {16'd0, neg_q};
    /* verilator lint_on UNUSEDSIGNAL */
    // (constant bound: m >= bound + 1 when d >= 0, m >= bound when d < 0, bit by bit)
    wire [16:0]        bnd1 = {1'b0, bound_q} + 17'd1;
    wire               ovf_n = (|m[COUNT_W-1:16]) |
                               (OPT_TUNABLE ? cmp[16]           // only the carry is used
                                : neg_q ? geu({16'd0, m[15:0]}, {16'd0, bound_q})
                                        : geu({16'd0, m[15:0]}, {15'd0, bnd1}));

    // Z: the position after this edge is pos + sign(d) on a step, else pos; e = z_at - pos
    // beside d, so the choice waits only for d's sign (as pos_n does)
    wire [COUNT_W-1:0] ze = z_at_i - pos_o;
    wire               z_n = z_en_i && (step ? (neg ? (ze == {COUNT_W{1'b1}})
                                                    : (ze == {{(COUNT_W-1){1'b0}}, 1'b1}))
                                             : (ze == {COUNT_W{1'b0}}));

    // backlog: d saturated to s16
    wire        fits = (m[COUNT_W-1:15] == {(COUNT_W-15){1'b0}});
    wire [15:0] bl_n = fits ? d_q[15:0] : {neg_q, {15{~neg_q}}};

    always @(posedge clk) begin
        if (step) begin
            pos_o <= pos_n;
            a_o   <= ~(q_n[1] ^ q_n[0]);
            b_o   <= ~q_n[1];
            cnt   <= 8'd1;
        end else if (cnt != 8'hFF) begin
            cnt   <= cnt + 8'd1;
        end
        d_q          <= d;
        bound_q      <= bound_i;
        backlog_o    <= bl_n;
        ovf_o        <= ovf_n;
        ovf_sticky_o <= ovf_sticky_o | ovf_n;
        z_o          <= z_n;
        if (rst) begin
            pos_o        <= {COUNT_W{1'b0}};
            a_o          <= 1'b1;
            b_o          <= 1'b1;
            cnt          <= 8'hFF;
            d_q          <= {COUNT_W{1'b0}};
            backlog_o    <= 16'sd0;
            ovf_o        <= 1'b0;
            ovf_sticky_o <= 1'b0;
            z_o          <= 1'b0;
        end
    end

    initial begin
        a_o = 1'b1; b_o = 1'b1; pos_o = {COUNT_W{1'b0}}; backlog_o = 16'sd0;
        ovf_o = 1'b0; ovf_sticky_o = 1'b0; z_o = 1'b0;
    end

`ifdef FORMAL
    // ---- formal properties (sim/formal/abgen.sby; every input free on every clock) ------------
    //  P1 never both a_o and b_o change.
    //  P2 the quadrant code {~b, a ^ b} of rtl/counter.v equals pos_o mod 4, so an x4
    //     decoder counting a_o/b_o reads pos_o.
    //  P3 pos_o moves by 0 or +-1, and only toward the target: by sign(target - pos) of the
    //     edge (modular difference).
    //  P4 an A/B edge only when at least max(sep, 1) clocks have passed since the last one
    //     (a ghost timer from the A/B changes, independent of cnt).
    //  P5 no pacing lost: target != pos and max(sep, 1) clocks passed -> pos moved.
    //  P6 ovf_o == |target - pos| > bound on the edge before; backlog_o == sat16(target -
    //     pos) of that edge; ovf_sticky_o == previous sticky | ovf_o.
    //  P7 after rst: pos 0, A = B = 1, flags 0, Z 0.
    //  Z1 Z only at the count it marks, armed: z_o -> z_en_i and pos_o == z_at_i as they
    //     stood before the edge. So Z is never wider than one count and never outside
    //     that count's A/B state (P2: the quadrant is pos mod 4).
    //  Z2 Z whenever the pins stand at that count, armed (it is never missed).
    reg                      f_past_valid = 1'b0;
    reg                      f_rst = 1'b0;
    reg signed [COUNT_W-1:0] f_target = 0, f_pos = 0;
    reg [7:0]                f_sep = 8'd0;
    reg [15:0]               f_bound = 16'd0;
    reg                      f_a = 1'b1, f_b = 1'b1, f_sticky = 1'b0;
    reg [7:0]                f_cnt = 8'hFF;
    reg                      f_rst2 = 1'b1;               // rst two edges back (or start)
    reg [COUNT_W:0]          f_absd2 = 0;                 // |d| and bound of the edge before
    reg [15:0]               f_bound2 = 16'd0;
    reg                      f_zen = 1'b0;
    reg signed [COUNT_W-1:0] f_zat = 0;
    reg signed [15:0]        f_sat_d2 = 16'sd0;
    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_cnt    <= cnt;
        f_rst2   <= f_rst || !f_past_valid;
        f_absd2  <= f_absd;
        f_bound2 <= f_bound;
        f_sat_d2 <= f_sat_d;
        f_rst    <= rst;
        f_target <= target_i;
        f_pos    <= pos_o;
        f_sep    <= sep_i;
        f_bound  <= bound_i;
        f_a      <= a_o;
        f_b      <= b_o;
        f_sticky <= ovf_sticky_o;
        f_zen    <= z_en_i;
        f_zat    <= z_at_i;
    end
    wire                     f_achg = (a_o != f_a), f_bchg = (b_o != f_b);
    wire                     f_edge = f_achg || f_bchg;
    wire signed [COUNT_W-1:0] f_d = f_target - f_pos;          // modular, on the last edge
    wire [COUNT_W:0]         f_absd = f_d[COUNT_W-1] ? -{f_d[COUNT_W-1], f_d} : {1'b0, f_d};
    wire [7:0]               f_sep_e = (f_sep == 8'd0) ? 8'd1 : f_sep;
    wire signed [15:0]       f_sat_d = (f_d > 32767) ? 16'sh7FFF : (f_d < -32768) ? 16'sh8000
                                                                              : f_d[15:0];
    wire signed [COUNT_W-1:0] f_dpos = pos_o - f_pos;
    // after edge e: the clocks that had passed since the last A/B change when e was taken
    // (saturating at 255; 255 after rst and at start)
    reg [7:0] f_gap = 8'd255;
    always @(posedge clk) begin
        if (rst)
            f_gap <= 8'd255;
        else if (f_past_valid && !f_rst && f_edge)
            f_gap <= 8'd1;
        else if (f_gap != 8'd255)
            f_gap <= f_gap + 8'd1;
    end
    always @(*) begin
        if (f_past_valid && !f_rst) begin
            assert (!(f_achg && f_bchg));                                        // P1
            assert ({~b_o, a_o ^ b_o} == pos_o[1:0]);                            // P2
            assert (f_dpos == 0 || (f_dpos == 1 && !f_d[COUNT_W-1] && f_d != 0)
                    || (f_dpos == -1 && f_d[COUNT_W-1]));                        // P3
            assert (f_edge == (f_dpos != 0));
            if (f_edge)
                assert (f_gap >= f_sep_e);                                       // P4
            if (f_d != 0 && f_gap >= f_sep_e)
                assert (f_edge);                                                 // P5
            if (!f_rst2) begin
                assert (ovf_o == (f_absd2 > {{(COUNT_W-15){1'b0}}, f_bound2}));  // P6
                assert (backlog_o == f_sat_d2);
            end
            assert (ovf_sticky_o == (f_sticky | ovf_o));
            assert (z_o == (f_zen && pos_o == f_zat));                           // Z1, Z2
        end
        if (f_past_valid && f_rst)
            assert (pos_o == 0 && a_o && b_o && !ovf_o && !ovf_sticky_o
                    && backlog_o == 0 && d_q == 0 && !z_o);                      // P7
        // the registered distance is the one of the edge before (induction invariant)
        if (f_past_valid && !f_rst)
            assert (d_q == f_d);
        // the ghost timer is the block's own timer as it stood before the edge (an
        // invariant for the induction; the ghost restarts with rst)
        if (f_past_valid && !f_rst)
            assert (f_gap == f_cnt);
        assert ({~b_o, a_o ^ b_o} == pos_o[1:0]);
    end
    // reachability: a paced burst (an edge right at the separation after a long backlog),
    // an overflow that clears, a reversal mid-backlog
    always @(posedge clk) begin
        if (f_past_valid && !f_rst) begin
            cover (f_edge && f_sep_e == 8'd5 && f_gap == 8'd5 && f_absd > 3);
            cover (f_sticky && !ovf_o && f_d != 0);
            cover (f_edge && f_dpos == -1 && f_target > f_pos + 2);
            cover (z_o && f_edge && f_dpos == -1);      // Z entered from above
            cover (z_o && f_edge && f_dpos == 1);       // and from below
        end
    end
`endif
endmodule
`resetall
