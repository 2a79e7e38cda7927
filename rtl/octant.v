`timescale 1ns / 1ps
`default_nettype none
// octant: Table 2 of the paper. The octant comes from the signs of u1c, u2c and the
// comparison of their magnitudes (as the paper, for both tables); the table address from
// the magnitudes. Mirrors sim/model/fastpath.py octant() and ratio().
//   TABLE_EXACT = 1: the ratio t = |small| / |large| in [0, 1], the tangent of the
//     octant-local angle (so both signals contribute: the angle noise is sigma/A at every
//     angle, the Cramer-Rao bound, where the small signal alone gives sigma/(A cos a));
//     the phase table holds atan. No divider: a reciprocal of the normalised |large| from
//     a 512-word table (2 block RAMs), one multiply |small| * recip (a DSP block).
//   TABLE_EXACT = 0: the smaller magnitude, linear (Eq. 10), bit for bit the paper's.
// Also the bin of the harmonic table (rtl/harmonic.v), phase >> 7, found from j before
// the phase table is read (thresholds from sim/model/tables.py bin_thresholds(),
// rtl/tables/hbin.vh), so the two tables are read on the same edge.
//
// Timing: inputs registered on edge e (= t + 2 in the core); outputs:
//   e+1  rcp     u0.14 RECIP[ln[13:5]] ~ 2**14 / m, m = ln / 2**14 in [1, 2) (block RAM;
//                recip.hex); ln = large << zl in [2**14, 2**15) (0 for large = 0),
//                zl = lzc15(large)
//        sn      u14   (small << zl) >> 1: small on the normalised scale, t = 2 sn / ln
//        jp      u11   paper address min(2047, (small + 4) >> 3)
//        oct2_o  u2    base phase 2048 oct2 (u13 units, 8192 per period)
//        neg_o   u1    phase = base - PH[j] (else base + PH[j])
//        valid_o       (octant: |u2c| <= |u1c| is the low octant 0, 3, 4 or 7; ties low)
//   e+2  p       u28   sn * rcp = t * 2**27 (1 + O(2**-10)) (a DSP block)
//   e+3 (combinational from the registers of e+2, for the block RAM addresses):
//        j_o     u11   exact: min(2047, (p + 2**15) >> 16) = round(2048 t), clipped; paper: jp
//        bin_o   u6    (base +- PH[j]) >> 7: 16 oct2 + floor(PH[j] / 128), or, when neg,
//                      16 oct2 - ceil(PH[j] / 128), mod 64; floor and ceil are counts of
//                      thresholds j reaches, found from p without the rounding add
//                      (rtl/tables/hbin.vh, sim/model/tables.py bin_buckets)
module octant #(
    parameter TABLE_DIR = "rtl/tables/",
    parameter [0:0] TABLE_EXACT = 1'b1
) (
    input  wire        clk,
    input  wire        valid_i,
    input  wire [14:0] ax_i,      // u15 |u1c|, s2.14 units
    input  wire [14:0] ay_i,      // u15 |u2c|
    input  wire        xn_i,      // u1c < 0
    input  wire        yn_i,      // u2c < 0
    output wire        valid_o,
    output wire [10:0] j_o,
    output wire [5:0]  bin_o,
    output wire [1:0]  oct2_o,
    output wire        neg_o
);
`include "hbin.vh"

    reg [13:0] rcp_rom [0:511];
    initial
        $readmemh({TABLE_DIR, "recip.hex"}, rcp_rom);

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

    // ---- e+1: octant, normalisation, reciprocal ------------------------------------------
    wire        low = (ay_i <= ax_i);
    wire [14:0] sm = low ? ay_i : ax_i;         // small
    // both magnitudes normalised by their own leading zeros and by the other's, side by
    // side with the comparison, which then only selects (AND-OR: with a multiplexer,
    // synthesis shares the shifters behind the comparison, a longer path)
    wire [3:0]  zx = lzc15(ax_i);
    wire [3:0]  zy = lzc15(ay_i);
    wire [14:0] lx = ax_i << zx, ly = ay_i << zy;      // large, if it is ax / ay
    wire [14:0] sx = ay_i << zx, sy = ax_i << zy;      // small, shifted as that large
    wire [14:0] sel = {15{low}};
    wire [14:0] ln = (lx & sel) | (ly & ~sel);   // large << zl (bit 15 is 0), zl = lzc15(large)
    wire [14:0] ns = (sx & sel) | (sy & ~sel);   // small << zl
    wire [15:0] jq = ({1'b0, sm} + 16'd4) >> 3;
    reg  [13:0] rcp = 0;
    reg  [13:0] sn = 0;
    reg  [10:0] jp = 0;
    reg  [1:0]  oct2_q = 0;
    reg         neg_q = 1'b0, v1 = 1'b0;
    always @(posedge clk) begin
        rcp    <= rcp_rom[ln[13:5]];
        sn     <= ns[14:1];
        jp     <= (jq[15:11] != 5'd0) ? 11'd2047 : jq[10:0];
        oct2_q <= low ? (xn_i ? 2'd2 : 2'd0) : (yn_i ? 2'd3 : 2'd1);
        neg_q  <= low ? (xn_i ^ yn_i) : !(xn_i ^ yn_i);
        v1     <= valid_i;
    end
    // continuous assignments (an always @* of registers that keep their initial value
    // never runs in Icarus, and its outputs stay x)
    assign valid_o = v1;
    assign oct2_o = oct2_q;
    assign neg_o = neg_q;

    // ---- e+2: p = sn * rcp (a DSP block) ------------------------------------------------------
    reg [27:0] p = 0;
    reg [10:0] jp_q = 0;
    reg [1:0]  oct2_2 = 0;
    reg        neg_2 = 1'b0;
    always @(posedge clk) begin
        p       <= sn * rcp;
        jp_q    <= jp;
        oct2_2  <= oct2_q;
        neg_2   <= neg_q;
    end

    // ---- e+3 (combinational): address, bin --------------------------------------------------
    wire [28:0] psum = {1'b0, p} + 29'h8000;
    wire [10:0] jr = (psum[28:27] != 2'b00) ? 11'd2047 : psum[26:16];
    assign j_o = TABLE_EXACT ? jr : jp_q;
    // The bin counts the thresholds T_k that j reaches, on the scale t = floor(p / 2**15)
    // (j = (t + 1) >> 1, j >= T <=> t >= 2 T - 1; t = 4095 where j clips; paper: t = 2 j),
    // so it does not wait for the rounding add: the count of the thresholds below t's
    // bucket of 256 (a 16-entry table) plus the one inside it, if t reaches it.
    localparam [63:0]  HB_LO_N = TABLE_EXACT ? HB_LO_EXACT_N : HB_LO_PAPER_N;
    localparam [143:0] HB_LO_T = TABLE_EXACT ? HB_LO_EXACT_T : HB_LO_PAPER_T;
    localparam [63:0]  HB_HI_N = TABLE_EXACT ? HB_HI_EXACT_N : HB_HI_PAPER_N;
    localparam [143:0] HB_HI_T = TABLE_EXACT ? HB_HI_EXACT_T : HB_HI_PAPER_T;
    // bin = (16 oct2 + cnt) mod 64, or (16 oct2 - cnt) mod 64 when neg, cnt = N + c <= 12:
    // {oct2 - br, lo} with {br, lo} from the tables below, per bucket and c (no adder)
    function [79:0] offsets(input [63:0] nt, input neg, input inc);
        integer k;
        reg [3:0] c;
        begin
            for (k = 0; k < 16; k = k + 1) begin
                c = nt[4*k +: 4] + {3'd0, inc};
                offsets[5*k +: 5] = neg ? {c != 4'd0, 4'd0 - c} : {1'b0, c};
            end
        end
    endfunction
    localparam [79:0] OFF_LO0 = offsets(HB_LO_N, 1'b0, 1'b0);
    localparam [79:0] OFF_LO1 = offsets(HB_LO_N, 1'b0, 1'b1);
    localparam [79:0] OFF_HI0 = offsets(HB_HI_N, 1'b1, 1'b0);
    localparam [79:0] OFF_HI1 = offsets(HB_HI_N, 1'b1, 1'b1);
    // t = {bk, tl}; the exact table's clip (p >= 2**27, t = 4095) is taken at the end
    wire [11:0] tq = TABLE_EXACT ? p[26:15] : {jp_q, 1'b0};
    wire        clip = TABLE_EXACT ? p[27] : 1'b0;
    wire [3:0]  bk = tq[11:8];
    wire [8:0]  bt = neg_2 ? HB_HI_T[9*bk +: 9] : HB_LO_T[9*bk +: 9];
    wire        c  = ({1'b0, tq[7:0]} >= bt);
    wire [4:0]  o0 = neg_2 ? OFF_HI0[5*bk +: 5] : OFF_LO0[5*bk +: 5];
    wire [4:0]  o1 = neg_2 ? OFF_HI1[5*bk +: 5] : OFF_LO1[5*bk +: 5];
    // t = 4095 counts every threshold of bucket 15 (the last one is below 4095)
    wire [4:0]  oc = neg_2 ? (HB_HI_T[9*15 +: 9] == 9'd256 ? OFF_HI0[5*15 +: 5] : OFF_HI1[5*15 +: 5])
                           : (HB_LO_T[9*15 +: 9] == 9'd256 ? OFF_LO0[5*15 +: 5] : OFF_LO1[5*15 +: 5]);
    wire [4:0]  o  = clip ? oc : c ? o1 : o0;
    assign bin_o = {oct2_2 - {1'b0, o[4]}, o[3:0]};

    wire unused = &{1'b0, psum[15:0], jq[2:0], ns[0], ln[14], ln[4:0], 1'b0};
endmodule
`resetall
