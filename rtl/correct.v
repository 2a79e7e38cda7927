`timescale 1ns / 1ps
`default_nettype none
// correct: input gain, offsets and Eq. 9 as three products, ending in the magnitudes and
// signs of the corrected signals that the octant logic needs (sim/model/fastpath.py
// correct()). One sample per clock; the sample is strobed on edge t (valid_i high before
// t) and the coefficient bundle is sampled on the same edge, so a sample never mixes two
// bundles.
//   t    u_r  = u << (16 - ADC_W)                            s1.15 aligned code (raw_o)
//        x    = u_r * 2**g                                    s4.15 (exact)
//        d    = sat16(x - m)                                  s1.15
//        c1, c12, c2 registered with d (the DSP blocks' input registers)
//   t+1  p1 = d1 c1, p12 = d1 c12, p2 = d2 c2                 s5.27 (three DSP products)
//   t+2  v1 = p1, v2 = p12 + p2                               s6.27
//        ax = min(32767, (v1 ^ s1) >> 13), xn = s1 = v1 < 0    u15 magnitude (s2.14
//        ay, yn likewise from v2                              units: unit circle 16384)
//        zl = lzc15(ax | ay)                                  u4 leading zeros of the larger
//                                                             magnitude (for rtl/octant.v)
// Flags (registered with the values they describe):
//   clip_o (t)   a code is at or near an ADC rail: |u_r| >= clip_i (|-32768| = 32768)
//   nsat_o (t)   x leaves s1.15: the input gain saturates (the estimator excludes the
//                sample and resets; the fast path still uses d)
//   dsat_o (t)   x - m leaves s1.15 (d saturated)
//   rsat_o (t+2) a magnitude reaches 2 (the corrected signal saturates)
module correct #(
    // ADC word width, 12..16, two's complement
    parameter ADC_W = 16
) (
    input  wire                    clk,
    input  wire                    valid_i,
    input  wire signed [ADC_W-1:0] u1_i,    // ADC codes
    input  wire signed [ADC_W-1:0] u2_i,
    input  wire [15:0]             clip_i,  // u16 clip level (s1.15 magnitude)
    input  wire [1:0]              g_i,     // input gain 2**g
    input  wire signed [15:0]      m1_i,    // s1.15 offsets (normalised units)
    input  wire signed [15:0]      m2_i,
    input  wire signed [15:0]      c1_i,    // s4.12 coefficients
    input  wire signed [15:0]      c12_i,
    input  wire signed [15:0]      c2_i,
    // edge t
    output reg                     valid0_o,
    output reg  signed [15:0]      raw1_o,  // s1.15 aligned codes (for the estimator)
    output reg  signed [15:0]      raw2_o,
    output reg  [14:0]             amax_o,  // u15 max(|raw1|, |raw2|), 32768 as 32767
    output reg                     clip_o,
    output reg                     nsat_o,
    output reg                     dsat_o,
    // edge t+2
    output reg                     valid_o,
    output reg  [14:0]             ax_o,    // u15 |u1c|, s2.14 units, saturated
    output reg  [14:0]             ay_o,    // u15 |u2c|
    output reg                     xn_o,    // u1c < 0
    output reg                     yn_o,    // u2c < 0
    output reg  [3:0]              zl_o,    // lzc15(ax_o | ay_o): 0..14 (14 for 0 and 1)
    output reg                     rsat_o
);
    // ---- t: align, gain, offsets ------------------------------------------------------------
    wire signed [15:0] ua1 = {u1_i, {(16-ADC_W){1'b0}}};
    wire signed [15:0] ua2 = {u2_i, {(16-ADC_W){1'b0}}};
    wire signed [18:0] x1 = $signed({{3{ua1[15]}}, ua1}) <<< g_i;       // s4.15
    wire signed [18:0] x2 = $signed({{3{ua2[15]}}, ua2}) <<< g_i;
    wire signed [19:0] e1 = {x1[18], x1} - {{4{m1_i[15]}}, m1_i};       // s5.15
    wire signed [19:0] e2 = {x2[18], x2} - {{4{m2_i[15]}}, m2_i};
    // a value fits s1.15 when its bits above bit 15 are copies of bit 15
    function automatic fits16(input [19:0] v, input integer w);
        integer k;
        begin
            fits16 = 1'b1;
            for (k = 16; k < 20; k = k + 1)
                if (k < w && v[k] != v[15])
                    fits16 = 1'b0;
        end
    endfunction
    wire ef1 = fits16(e1, 20), ef2 = fits16(e2, 20);
    wire xf1 = fits16({x1[18], x1}, 19), xf2 = fits16({x2[18], x2}, 19);
    wire [15:0] ab1 = ua1[15] ? -ua1 : ua1;       // |-32768| = 32768: bit 15
    wire [15:0] ab2 = ua2[15] ? -ua2 : ua2;
    wire [14:0] am1 = ab1[15] ? 15'h7fff : ab1[14:0];
    wire [14:0] am2 = ab2[15] ? 15'h7fff : ab2[14:0];
    // |u1| >= |u2| from the codes, beside the magnitudes (not behind their carry chains):
    // by the signs, u1 >= u2 (both >= 0), u1 < u2 (both < 0), u1 + u2 >= 0 (u1 >= 0 > u2)
    // or u1 + u2 < 0 (u1 < 0 <= u2)
    wire signed [16:0] dif = {ua1[15], ua1} - {ua2[15], ua2};
    wire signed [16:0] smu = {ua1[15], ua1} + {ua2[15], ua2};
    // (ties pick either: the same magnitude)
    wire        gt1 = ((ua1[15] == ua2[15]) ? dif[16] : smu[16]) ^ !ua1[15];
    // |u| >= clip: u >= clip for u >= 0; -u >= clip <=> ~u >= clip - 1 for u < 0 (every
    // u < 0 when clip = 0), so no negation lies in front of the comparison
    wire [16:0] cm1 = {1'b0, clip_i} - 17'd1;
    function automatic clipped(input [15:0] u, input [15:0] clip, input [16:0] cm);
        clipped = u[15] ? (cm[16] || ({1'b0, ~u} >= cm)) : (u >= clip);
    endfunction
    (* keep *) reg signed [15:0] d1 = 0, d2 = 0;
    reg signed [15:0] c1q = 0, c12q = 0, c2q = 0;
    always @(posedge clk) begin
        d1 <= ef1 ? e1[15:0] : (e1[19] ? -16'sd32768 : 16'sd32767);
        d2 <= ef2 ? e2[15:0] : (e2[19] ? -16'sd32768 : 16'sd32767);
        c1q <= c1_i; c12q <= c12_i; c2q <= c2_i;
        raw1_o <= ua1;
        raw2_o <= ua2;
        amax_o <= gt1 ? am1 : am2;               // max(|u1|, |u2|), saturated
        clip_o <= clipped(ua1, clip_i, cm1) || clipped(ua2, clip_i, cm1);
        nsat_o <= !(xf1 && xf2);
        dsat_o <= !(ef1 && ef2);
        valid0_o <= valid_i;
    end

    // ---- t+1: products (DSP blocks with input and output registers) ----------------------
    reg signed [31:0] p1 = 0, p12 = 0, p2 = 0;
    reg v1q = 1'b0;
    always @(posedge clk) begin
        p1  <= d1 * c1q;
        p12 <= d1 * c12q;
        p2  <= d2 * c2q;
        v1q <= valid0_o;
    end

    // ---- t+2: magnitudes and signs ---------------------------------------------------------
    // v = p1 or p12 + p2 (s6.27); the octant logic takes |u| = floor(|v| / 2**13) as
    // (v ^ sign) >> 13, so no carry chain follows the sum: for v < 0 this is
    // floor((|v| - 1) / 2**13), 1 / 2**27 of a unit below |v|'s, and u is truncated, not
    // rounded (a bias of half an LSB of the unit circle, 3e-5: 0.01 nm on a 4 um scale).
    // The sum's bits [32:13] by carry select: both values of the upper 20 bits (carry in 0
    // and 1) beside the carry out of the low 13, chosen by AND-OR (a multiplexer would let
    // synthesis share the two adders again).
    wire signed [32:0] v1 = {p1[31], p1};
    wire [13:0] lo2  = {1'b0, p12[12:0]} + {1'b0, p2[12:0]};
    wire [19:0] hi20 = {p12[31], p12[31:13]} + {p2[31], p2[31:13]};
    wire [20:0] hi21c = {p12[31], p12[31:13], 1'b1} + {p2[31], p2[31:13], 1'b1};   // + 1
    wire [19:0] hi21 = hi21c[20:1];
    wire [19:0] csel = {20{lo2[13]}};
    wire [19:0] v2h  = (hi21 & csel) | (hi20 & ~csel);           // (p12 + p2) >> 13
    wire        n1 = v1[32], n2 = v2h[19];                       // v < 0
    wire [19:0] q1 = v1[32:13] ^ {20{n1}};                       // |u|, u20
    wire [19:0] q2 = v2h ^ {20{n2}};
    wire        sat1 = (q1[19:15] != 5'd0), sat2 = (q2[19:15] != 5'd0);
    // leading zeros in 15 bits, 14 for 0 and 1: those of the 16 bits {v[14:1], 1, 1}, as
    // a two-level tree (nibble priority beside the nibbles' own counts)
    function automatic [1:0] lzc4(input [3:0] v);
        casez (v)
            4'b1???: lzc4 = 2'd0;
            4'b01??: lzc4 = 2'd1;
            4'b001?: lzc4 = 2'd2;
            default: lzc4 = 2'd3;
        endcase
    endfunction
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [3:0] lzc15(input [14:0] v);     // v[0] does not matter
        reg [15:0] w;
        begin
            w = {v[14:1], 2'b11};
            casez ({|w[15:12], |w[11:8], |w[7:4]})
                3'b1??:  lzc15 = {2'd0, lzc4(w[15:12])};
                3'b01?:  lzc15 = {2'd1, lzc4(w[11:8])};
                3'b001:  lzc15 = {2'd2, lzc4(w[7:4])};
                default: lzc15 = {2'd3, lzc4(w[3:0])};
            endcase
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */

    wire [14:0] axn = sat1 ? 15'h7fff : q1[14:0];
    wire [14:0] ayn = sat2 ? 15'h7fff : q2[14:0];
    always @(posedge clk) begin
        ax_o <= axn;
        ay_o <= ayn;
        zl_o <= lzc15(axn | ayn);
        xn_o <= n1;
        yn_o <= n2;
        rsat_o <= sat1 || sat2;                                   // |u| >= 2 (32768)
        valid_o <= v1q;
    end

    initial begin
        valid0_o = 1'b0; raw1_o = 0; raw2_o = 0; amax_o = 0; clip_o = 1'b0; nsat_o = 1'b0;
        dsat_o = 1'b0; valid_o = 1'b0; ax_o = 0; ay_o = 0; xn_o = 1'b0; yn_o = 1'b0; zl_o = 0;
        rsat_o = 1'b0;
    end
    wire unused = &{1'b0, v1[12:0], lo2[12:0], hi21c[0], dif[15:0], smu[15:0], 1'b0};
endmodule
`resetall
