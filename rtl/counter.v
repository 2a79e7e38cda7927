`timescale 1ns / 1ps
`default_nettype none
// counter: position count of the n-th order, two modes (sim/model/fastpath.py counter()).
// Counts up when the phase increases (u1 leads u2). Both modes share one accumulator
//   S    s(COUNT_W+13), wraps; count_o = S >>> 13 (its top COUNT_W bits): one count is
//        8192 units of S, i.e. S holds 4 n * phase in u13 units of the fundamental
// and see every valid sample (phase_prev and the A/B quadrant are tracked in both modes).
// After rst: S = 0, phase_prev = 0, quadrant_prev = 0 (A = B = 1, rtl/pulse.v's reset).
//
// mode_i = 0, "phase" (default): S += 4 * n * dph, dph = wrap13(phase - phase_prev)
//   dph  s13, [-4096, 4095], 8192 per period of the fundamental
//   D    s23 = dph * n (shift-and-add in logic; |D| <= 4096 * 511 < 2^21)
//   The count follows the unwrapped phase exactly, with no count lost at any speed up to
//   |dph| < 4096 (half a period per sample): S = 4 n Phi with Phi = wrap13(phase_0) +
//   sum of the dph (phase_prev starts at 0, so the first sample adds 4 n wrap13(phase_0)),
//   count = floor(4 n Phi / 8192), aligned to the absolute phase (modulo 4 n counts).
//   Flag ("overspeed"): |dph| >= 3072 (3/4 pi or more per sample; near pi the direction
//   of the step, hence the position, becomes ambiguous).
// mode_i = 1, "edge" (the paper's counter, Sec. 2.3, for comparison): plain x4 quadrature
//   decoder of A/B: S += 8192 * e, e = +1 / -1 per single-channel step (quadrant step
//   dq = 1 / 3 modulo 4), 0 for no change. A step where both A and B change (dq = 2) is
//   illegal: not counted (the count is lost), flagged. A four-quadrant step is invisible.
//   S's 13 low bits are not touched, so switching modes keeps the count continuous.
// The flag (illegal_o, pulsed with valid_o) is never raised on the first valid sample
// after rst (its step is from the reset state, not from a sample); flagged samples are
// counted in illegal_count_o (u32, wraps). Switch modes at standstill.
// Latency 3: a sample on edge e (valid_i, a_i, b_i, phase_i, mode_i) is on the outputs
// after edge e + 2; n_i is used on edge e + 1.
module counter #(
    // counter width (wraps), 16..32
    parameter COUNT_W = 32
) (
    input  wire                      clk,
    input  wire                      rst,
    input  wire                      valid_i,
    input  wire                      a_i,
    input  wire                      b_i,
    input  wire [12:0]               phase_i,    // u13 fine phase, aligned with A/B
    input  wire [8:0]                n_i,        // u9 n, 1..511
    input  wire                      mode_i,     // 0 phase, 1 edge (x4 of A/B)
    output reg                       valid_o,
    output wire signed [COUNT_W-1:0] count_o,    // s(COUNT_W), wraps
    output reg                       a_o,
    output reg                       b_o,
    output reg                       illegal_o,  // phase: overspeed; edge: lost step
    output reg  [31:0]               illegal_count_o
);
    localparam SW = COUNT_W + 13;                // accumulator S: s(COUNT_W).13
    // quadrant code: (1,1) 0, (0,1) 1, (0,0) 2, (1,0) 3
    wire [1:0]  qd = {~b_i, a_i ^ b_i};
    reg  [1:0]  qd_prev = 2'd0;
    reg  [12:0] ph_prev = 13'd0;
    reg         primed = 1'b0;
    // +1: steps
    wire [12:0] dph = phase_i - ph_prev;         // u13 difference = wrap13 as s13
    wire        ovs = (dph >= 13'd3072) && (dph <= 13'd5120);   // |wrap13| >= 3072
    reg  [1:0]  dq1 = 2'd0;                      // u2 quadrant step modulo 4
    reg  signed [12:0] dph1 = 13'sd0;            // s13
    reg         ovs1 = 1'b0, m1 = 1'b0;
    reg         v1 = 1'b0, p1 = 1'b0, a1 = 1'b1, b1 = 1'b1;
    always @(posedge clk) begin
        if (valid_i) begin
            qd_prev <= qd;
            ph_prev <= phase_i;
            primed  <= 1'b1;
        end
        dq1  <= qd - qd_prev;
        dph1 <= $signed(dph);
        ovs1 <= ovs;
        m1 <= mode_i;
        v1 <= valid_i;
        p1 <= primed;
        a1 <= a_i;
        b1 <= b_i;
        if (rst) begin
            qd_prev <= 2'd0;
            ph_prev <= 13'd0;
            primed <= 1'b0;
            v1 <= 1'b0;
        end
    end
    // +2: n-th order step, edge step, flag. D = dph * n as shift-and-add in logic (no DSP:
    // the octant's ratio multiply has it): nine rows n[b] * (dph << b), sign-extended to
    // s23, reduced by four levels of 3:2 counters to two vectors, then one carry add.
    function [45:0] csa;                         // {sum, carry} of three s23, mod 2**23
        input [22:0] a, b, c;
        begin
            csa = {a ^ b ^ c, ((a & b) | (a & c) | (b & c)) << 1};
        end
    endfunction
    wire [23*9-1:0] rows;
    genvar gb;
    generate
        for (gb = 0; gb < 9; gb = gb + 1) begin : g_rows
            assign rows[23*gb +: 23] = n_i[gb] ? ({{10{dph1[12]}}, dph1} << gb) : 23'd0;
        end
    endgenerate
    wire [22:0] ra0, rb0, ra1, rb1, ra2, rb2;                // 9 -> 6
    assign {ra0, rb0} = csa(rows[0 +: 23], rows[23 +: 23], rows[46 +: 23]);
    assign {ra1, rb1} = csa(rows[69 +: 23], rows[92 +: 23], rows[115 +: 23]);
    assign {ra2, rb2} = csa(rows[138 +: 23], rows[161 +: 23], rows[184 +: 23]);
    wire [22:0] rc0, rd0, rc1, rd1;                          // 6 -> 4
    assign {rc0, rd0} = csa(ra0, rb0, ra1);
    assign {rc1, rd1} = csa(rb1, ra2, rb2);
    wire [22:0] re0, rf0, rs0, rs1;
    assign {re0, rf0} = csa(rc0, rd0, rc1);                  // 4 -> 3
    assign {rs0, rs1} = csa(re0, rf0, rd1);                  // 3 -> 2
    reg  signed [22:0] d2 = 23'sd0;              // s23: D = dph * n
    reg  signed [1:0]  e2 = 2'sd0;               // s2: edge step -1, 0, +1
    reg         f2 = 1'b0, m2 = 1'b0;
    reg         v2 = 1'b0, a2 = 1'b1, b2 = 1'b1;
    always @(posedge clk) begin
        d2 <= $signed(rs0 + rs1);
        e2 <= (dq1 == 2'd1) ? 2'sd1 : (dq1 == 2'd3) ? -2'sd1 : 2'sd0;
        f2 <= p1 && (m1 ? (dq1 == 2'd2) : ovs1);
        m2 <= m1;
        v2 <= v1; a2 <= a1; b2 <= b1;
        if (rst)
            v2 <= 1'b0;
    end
    // +3: accumulate
    reg  signed [SW-1:0] s_acc = 0;              // S, s(COUNT_W).13
    wire signed [SW-1:0] inc_ph = {{(SW-25){d2[22]}}, d2, 2'b00};          // 4 D
    wire signed [SW-1:0] inc_ed = {{(SW-15){e2[1]}}, e2, 13'd0};           // 8192 e
    always @(posedge clk) begin
        valid_o <= v2;
        a_o <= a2;
        b_o <= b2;
        illegal_o <= v2 && f2;
        if (v2) begin
            s_acc <= s_acc + (m2 ? inc_ed : inc_ph);
            if (f2)
                illegal_count_o <= illegal_count_o + 1'b1;
        end
        if (rst) begin
            valid_o <= 1'b0;
            illegal_o <= 1'b0;
            s_acc <= 0;
            illegal_count_o <= 0;
        end
    end
    assign count_o = s_acc[SW-1:13];
    initial begin
        valid_o = 1'b0; a_o = 1'b1; b_o = 1'b1; illegal_o = 1'b0;
        illegal_count_o = 0;
    end
endmodule
`resetall
