`timescale 1ns / 1ps
`default_nettype none
// correct: input gain and Eq. 9 as three products (sim/model/fastpath.py normalize,
// correct). Latency 5 clocks, one sample per clock. The coefficient bundle is sampled
// on the same edge as the sample (stage 1) and travels with it, so a sample never mixes
// two bundles.
//   stage 1  u_n = sat16(u << g)                      s1.15
//   stage 2  d   = sat16(u_n - m)                     s1.15
//   stage 3  p1 = d1 c1, p12 = d1 c12, p2 = d2 c2     s5.27 (three DSP products)
//   stage 4  p12 + p2                                 s6.27
//   stage 5  u1c = sat16(rnd(p1 >> 13)), u2c = sat16(rnd((p12 + p2) >> 13))   s2.14
module correct (
    input  wire               clk,
    input  wire               valid_i,
    input  wire signed [15:0] u1_i,    // s1.15 aligned ADC sample
    input  wire signed [15:0] u2_i,
    input  wire [1:0]         g_i,     // input gain 2**g
    input  wire signed [15:0] m1_i,    // s1.15 offsets (normalised units)
    input  wire signed [15:0] m2_i,
    input  wire signed [15:0] c1_i,    // s4.12 coefficients
    input  wire signed [15:0] c12_i,
    input  wire signed [15:0] c2_i,
    output reg                valid_o,
    output reg  signed [15:0] u1c_o,   // s2.14 corrected signals, unit circle = 16384
    output reg  signed [15:0] u2c_o,
    output reg                nsat_o,  // u << g saturated
    output reg                csat_o   // offset removal or correction saturated
);
    // stage 1: gain
    wire signed [18:0] w1 = $signed({{3{u1_i[15]}}, u1_i}) <<< g_i;
    wire signed [18:0] w2 = $signed({{3{u2_i[15]}}, u2_i}) <<< g_i;
    // w leaves 16 bits exactly when bits [18:15] are not all copies of the sign
    wire s1 = !(&w1[18:15] || !(|w1[18:15]));
    wire s2 = !(&w2[18:15] || !(|w2[18:15]));
    reg signed [15:0] un1 = 0, un2 = 0, m1q = 0, m2q = 0;
    reg signed [15:0] c1q = 0, c12q = 0, c2q = 0;
    reg v1 = 1'b0, ns1 = 1'b0;
    always @(posedge clk) begin
        un1 <= s1 ? (w1[18] ? -16'sd32768 : 16'sd32767) : w1[15:0];
        un2 <= s2 ? (w2[18] ? -16'sd32768 : 16'sd32767) : w2[15:0];
        ns1 <= s1 | s2;
        m1q <= m1_i; m2q <= m2_i;
        c1q <= c1_i; c12q <= c12_i; c2q <= c2_i;
        v1 <= valid_i;
    end
    // stage 2: offsets
    wire signed [16:0] e1 = un1 - m1q;
    wire signed [16:0] e2 = un2 - m2q;
    wire es1 = e1[16] ^ e1[15];
    wire es2 = e2[16] ^ e2[15];
    reg signed [15:0] d1 = 0, d2 = 0, c1r = 0, c12r = 0, c2r = 0;
    reg v2 = 1'b0, ns2 = 1'b0, cs2 = 1'b0;
    always @(posedge clk) begin
        d1 <= es1 ? (e1[16] ? -16'sd32768 : 16'sd32767) : e1[15:0];
        d2 <= es2 ? (e2[16] ? -16'sd32768 : 16'sd32767) : e2[15:0];
        cs2 <= es1 | es2;
        ns2 <= ns1;
        c1r <= c1q; c12r <= c12q; c2r <= c2q;
        v2 <= v1;
    end
    // stage 3: products
    reg signed [31:0] p1 = 0, p12 = 0, p2 = 0;
    reg v3 = 1'b0, ns3 = 1'b0, cs3 = 1'b0;
    always @(posedge clk) begin
        p1  <= d1 * c1r;
        p12 <= d1 * c12r;
        p2  <= d2 * c2r;
        v3 <= v2; ns3 <= ns2; cs3 <= cs2;
    end
    // stage 4: sum of the u2c products
    reg signed [32:0] q1 = 0, q2 = 0;
    reg v4 = 1'b0, ns4 = 1'b0, cs4 = 1'b0;
    always @(posedge clk) begin
        q1 <= {p1[31], p1};
        q2 <= {p12[31], p12} + {p2[31], p2};
        v4 <= v3; ns4 <= ns3; cs4 <= cs3;
    end
    // stage 5: round and saturate
    wire signed [15:0] r1, r2;
    wire rs1, rs2;
    sat_round #(.IW(33), .OW(16), .SW(4)) u_r1 (.in_i(q1), .sh_i(4'd13),
                                                .out_o(r1), .sat_o(rs1));
    sat_round #(.IW(33), .OW(16), .SW(4)) u_r2 (.in_i(q2), .sh_i(4'd13),
                                                .out_o(r2), .sat_o(rs2));
    always @(posedge clk) begin
        u1c_o <= r1;
        u2c_o <= r2;
        nsat_o <= ns4;
        csat_o <= cs4 | rs1 | rs2;
        valid_o <= v4;
    end
    initial begin
        valid_o = 1'b0; u1c_o = 0; u2c_o = 0; nsat_o = 1'b0; csat_o = 1'b0;
    end
endmodule
`resetall
