`timescale 1ns / 1ps
`default_nettype none
// hbin: the bin of the harmonic table (rtl/harmonic.v), b = phase >> 7 (64 bins of 128
// phase units), found from the octant address's scale t before the phase table is read
// (sim/model/tables.py bin_thresholds, bin_buckets; rtl/tables/hbin.vh). Combinational.
//
// With ph = PH[j] and base = 2048 oct2: (base + ph) >> 7 = 16 oct2 + floor(ph / 128) and
// ((base - ph) mod 8192) >> 7 = 16 oct2 - ceil(ph / 128) (mod 64); floor and ceil count
// the thresholds T_k that j reaches (j >= T <=> t >= 2 T - 1 on t's scale: exact t =
// min(4095, floor(p / 2**15)) of the ratio product, j = (t + 1) >> 1 clipped at 2047;
// paper t = 2 j; rtl/octant.v t_o). In t's bucket bk = t >> 8 of 256 there are N[bk]
// thresholds below it and at most one inside it, reached when c = (t & 255) >= T[bk]:
//   cnt = N[bk] + c,  b = (16 oct2 + cnt) mod 64, or (16 oct2 - cnt) mod 64 when neg
// The two candidates b0 (c = 0) and b1 (c = 1) need only the bucket, so rtl/harmonic.v
// reads the table at both and lets c select afterwards: the comparison is off the
// address path. Each is {oct2 - br, lo} with {br, lo} a constant per bucket and c (no
// adder).
module hbin #(
    // the thresholds: 1 the exact table's, 0 the paper's
    parameter [0:0] TABLE_EXACT = 1'b1
) (
    input  wire [1:0]  oct2_i,    // base phase 2048 oct2
    input  wire        neg_i,     // phase = base - PH[j]
    input  wire [11:0] t_i,       // u12 the address's scale
    output wire [5:0]  b0_o,      // u6 the bin if t does not reach its bucket's threshold
    output wire [5:0]  b1_o,      // u6 the bin if it does
    output wire        c_o,       // it does: b = c ? b1 : b0
    output wire [5:0]  bin_o      // u6 b
);
`include "hbin.vh"
    localparam [63:0]  HB_LO_N = TABLE_EXACT ? HB_LO_EXACT_N : HB_LO_PAPER_N;
    localparam [143:0] HB_LO_T = TABLE_EXACT ? HB_LO_EXACT_T : HB_LO_PAPER_T;
    localparam [63:0]  HB_HI_N = TABLE_EXACT ? HB_HI_EXACT_N : HB_HI_PAPER_N;
    localparam [143:0] HB_HI_T = TABLE_EXACT ? HB_HI_EXACT_T : HB_HI_PAPER_T;
    // {br, lo} per bucket: cnt = N + inc, {0, cnt} (pos) or {cnt != 0, -cnt} (neg)
    function [79:0] offsets(input [63:0] nt, input neg, input inc);
        integer k;
        reg [3:0] cn;
        begin
            for (k = 0; k < 16; k = k + 1) begin
                cn = nt[4*k +: 4] + {3'd0, inc};
                offsets[5*k +: 5] = neg ? {cn != 4'd0, 4'd0 - cn} : {1'b0, cn};
            end
        end
    endfunction
    localparam [79:0] OFF_LO0 = offsets(HB_LO_N, 1'b0, 1'b0);
    localparam [79:0] OFF_LO1 = offsets(HB_LO_N, 1'b0, 1'b1);
    localparam [79:0] OFF_HI0 = offsets(HB_HI_N, 1'b1, 1'b0);
    localparam [79:0] OFF_HI1 = offsets(HB_HI_N, 1'b1, 1'b1);

    wire [3:0] bk = t_i[11:8];
    wire [4:0] o0 = neg_i ? OFF_HI0[5*bk +: 5] : OFF_LO0[5*bk +: 5];
    wire [4:0] o1 = neg_i ? OFF_HI1[5*bk +: 5] : OFF_LO1[5*bk +: 5];
    wire [8:0] bt = neg_i ? HB_HI_T[9*bk +: 9] : HB_LO_T[9*bk +: 9];
    assign b0_o = {oct2_i - {1'b0, o0[4]}, o0[3:0]};
    assign b1_o = {oct2_i - {1'b0, o1[4]}, o1[3:0]};
    assign c_o = ({1'b0, t_i[7:0]} >= bt);
    assign bin_o = c_o ? b1_o : b0_o;
endmodule
`resetall
