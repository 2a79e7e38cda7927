`timescale 1ns / 1ps
`default_nettype none
// counter: position count of the n-th order, two modes (sim/model/fastpath.py counter()).
// Counts up when the phase increases (u1 leads u2).
//
// Phase mode (mode_i = 0, the default): the count follows the unwrapped fine phase Phi
// (8192 units per signal period) exactly:
//     count = floor(4 n Phi / 8192) = B + q,   B = 4 n W,   q = floor(n f / 2048)
// with Phi = 8192 W + f, f the fine phase in [0, 8192) and W the signal periods, so no
// multiplier is needed here: q is the high part of the product n f that rtl/lut.v forms
// for the n-th order phase anyway, and B steps by -+4 n when the phase wraps. Per sample,
// with raw = f - f_prev (s14, f_prev = 0 after rst) and dph = wrap13(raw) in
// [-4096, 4095]: the phase moved by dph, and wrapped backwards when raw >= 4096
// (B -= 4 n) or forwards when raw < -4096 (B += 4 n). Nothing is lost at any speed below
// half a signal period per sample, whatever n. After rst, Phi starts at wrap13(f_0)
// (count aligned to the absolute phase, modulo 4 n counts). n is sampled with the sample
// on both stages: change it at standstill (B keeps the factor it was built with).
// Overspeed (ovs_o): |dph| >= 3072 (3/4 pi or more per sample; near pi the direction of
// the step, hence the position, becomes ambiguous); never on the first sample after rst.
// Hold (hold_i with valid_i, rtl/monitor.v: signal loss, a stuck channel or a glitch; the
// phase is not trusted): the sample changes nothing, its count is the one before (B,
// f_prev and count_o stay; no overspeed), so the next trusted sample steps from the last
// trusted phase: after an outage the count is right if the stage moved less than half
// a period meanwhile. The edge mode ignores hold_i.
//
// Edge mode (mode_i = 1, the paper's counter, Sec. 2.3, for comparison): an x4
// quadrature decoder of the Eq. 12 pulses A/B (rtl/pulse.v): +1 / -1 per single-channel
// step (quadrant step 1 / 3 modulo 4), 0 for none; a step where both A and B change is
// illegal: not counted (the count is lost), counted in ill_count_o. The decoder runs in
// both modes, from rst (ill_count_o counts the pulses' illegal steps either way; its
// count E starts at 0 with rst, so switch modes together with a reset). The pulses of a
// sample arrive two edges after its phase-mode count, so in edge mode count_o of a
// sample holds E as of its output edge: the steps of the samples strobed at least 3
// edges before it.
//
// Timing (e = the edge registering phase_i, t + 6 in the core):
//   e + 1  B, f_prev, the step flags; prod_i = n * phase_i arrives registered (rtl/lut.v)
//   e + 2  count_o = mode ? E : B + prod_i[21:11]; valid_o, ovs_o
//   pulses: pv_i with a_i, b_i on edge p (t + 9); E and ill_count_o updated on p + 1
module counter #(
    // counter width (wraps), 16..32
    parameter COUNT_W = 32
) (
    input  wire                      clk,
    input  wire                      rst,
    input  wire                      valid_i,
    input  wire                      hold_i,     // with valid_i: do not count this sample
    input  wire [12:0]               phase_i,    // u13 fine phase (registered, edge e)
    input  wire [21:0]               prod_i,     // u22 n * phase_i, registered on e + 1
    input  wire [8:0]                n_i,        // u9 n, 1..511
    input  wire                      mode_i,     // 0 phase, 1 edge (x4 of A/B)
    input  wire                      pv_i,       // Eq. 12 pulses of a sample
    input  wire                      a_i,
    input  wire                      b_i,
    output reg                       valid_o,
    output reg  signed [COUNT_W-1:0] count_o,    // s(COUNT_W), wraps
    output reg                       ovs_o,      // overspeed (with valid_o)
    output reg                       ill_o,      // an illegal A/B step (pulse, edge p + 1)
    output reg  [15:0]               ill_count_o // u16 illegal A/B steps since rst, wraps
);
    // ---- e + 1: wrap, B ------------------------------------------------------------------
    reg  [12:0] ph_prev = 13'd0;
    reg         primed = 1'b0;
    reg  signed [COUNT_W-1:0] b_acc = 0;         // B = 4 n W, s(COUNT_W), wraps
    wire [13:0] raw = {1'b0, phase_i} - {1'b0, ph_prev};         // s14
    wire        back = (raw[13:12] == 2'b01);   // raw >= 4096: wrapped backwards
    wire        fwd  = (raw[13:12] == 2'b10);   // raw < -4096: wrapped forwards
    wire [12:0] dph = raw[12:0];                 // wrap13, as u13
    wire        ovs = (dph >= 13'd3072) && (dph <= 13'd5120);   // |wrap13| >= 3072
    wire signed [COUNT_W-1:0] n4 = {{(COUNT_W-11){1'b0}}, n_i, 2'b00};
    reg         v1 = 1'b0, ovs1 = 1'b0, hold1 = 1'b0;
    always @(posedge clk) begin
        v1 <= valid_i;
        ovs1 <= primed && ovs && !hold_i;
        hold1 <= hold_i;
        if (valid_i && !hold_i) begin
            ph_prev <= phase_i;
            primed <= 1'b1;
            if (back)
                b_acc <= b_acc - n4;
            else if (fwd)
                b_acc <= b_acc + n4;
        end
        if (rst) begin
            v1 <= 1'b0;
            ph_prev <= 13'd0;
            primed <= 1'b0;
            b_acc <= 0;
        end
    end

    // ---- edge decoder (pulses) -----------------------------------------------------------
    // quadrant code: (1,1) 0, (0,1) 1, (0,0) 2, (1,0) 3
    reg  signed [COUNT_W-1:0] e_acc = 0;         // E
    reg  [1:0]  qd_prev = 2'd0;
    reg         eprimed = 1'b0;
    wire [1:0]  qd = {~b_i, a_i ^ b_i};
    wire [1:0]  dq = qd - qd_prev;
    always @(posedge clk) begin
        ill_o <= 1'b0;
        if (pv_i) begin
            qd_prev <= qd;
            eprimed <= 1'b1;
            if (dq == 2'd2 && eprimed) begin
                ill_o <= 1'b1;
                ill_count_o <= ill_count_o + 1'b1;
            end
        end
        if (pv_i && dq == 2'd1)
            e_acc <= e_acc + 1'b1;
        else if (pv_i && dq == 2'd3)
            e_acc <= e_acc - 1'b1;
        if (rst) begin
            qd_prev <= 2'd0;
            eprimed <= 1'b0;
            ill_o <= 1'b0;
            ill_count_o <= 16'd0;
            e_acc <= 0;
        end
    end

    // ---- e + 2: the count -----------------------------------------------------------------
    wire signed [COUNT_W-1:0] q = {{(COUNT_W-11){1'b0}}, prod_i[21:11]};
    always @(posedge clk) begin
        valid_o <= v1;
        ovs_o <= v1 && ovs1;
        if (v1 && (mode_i || !hold1))
            count_o <= mode_i ? e_acc : b_acc + q;
        if (rst) begin
            valid_o <= 1'b0;
            ovs_o <= 1'b0;
            count_o <= 0;
        end
    end
    initial begin
        valid_o = 1'b0; count_o = 0; ovs_o = 1'b0; ill_o = 1'b0; ill_count_o = 16'd0;
    end
    wire unused = &{1'b0, prod_i[10:0], 1'b0};
endmodule
`resetall
