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
//                      thresholds j reaches (rtl/tables/hbin.vh, sim/model/tables.py
//                      bin_buckets)
module octant #(
    parameter TABLE_DIR = "rtl/tables/",
    parameter [0:0] TABLE_EXACT = 1'b1,
    // 1: normalise both magnitudes in parallel and select after the comparison (shorter
    // path, more logic; the same values)
    parameter [0:0] OPT_PAR_NORM = 1'b0
) (
    input  wire        clk,
    input  wire        valid_i,
    input  wire [14:0] ax_i,      // u15 |u1c|, s2.14 units
    input  wire [14:0] ay_i,      // u15 |u2c|
    input  wire        xn_i,      // u1c < 0
    input  wire        yn_i,      // u2c < 0
    output reg         valid_o,
    output wire [10:0] j_o,
    output wire [5:0]  bin_o,
    output reg  [1:0]  oct2_o,
    output reg         neg_o
);
`include "hbin.vh"

    reg [13:0] rcp_rom [0:511];
    initial
        $readmemh({TABLE_DIR, "recip.hex"}, rcp_rom);

    function [3:0] lzc15;               // leading zeros in 15 bits, 14 for 0
        input [14:0] v;
        integer b;
        begin
            lzc15 = 4'd14;
            for (b = 0; b < 15; b = b + 1)
                if (v[b])
                    lzc15 = 4'd14 - b[3:0];
        end
    endfunction

    // ---- e+1: octant, normalisation, reciprocal ------------------------------------------
    wire        low = (ay_i <= ax_i);
    wire [14:0] sm = low ? ay_i : ax_i;         // small
    wire [3:0]  zx = lzc15(ax_i);
    wire [3:0]  zy = lzc15(ay_i);
    wire [14:0] ln, ns;                          // large << zl (bit 15 is 0), small << zl
    generate
        if (OPT_PAR_NORM) begin : g_par
            wire [14:0] lx = ax_i << zx, ly = ay_i << zy;      // each magnitude normalised
            wire [14:0] sx = ay_i << zx, sy = ax_i << zy;      // the other one, same shift
            assign ln = low ? lx : ly;
            assign ns = low ? sx : sy;
        end else begin : g_ser
            wire [14:0] lg = low ? ax_i : ay_i;     // large
            wire [3:0]  zl = low ? zx : zy;
            assign ln = lg << zl;
            assign ns = sm << zl;
        end
    endgenerate
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
    always @* begin
        valid_o = v1;
        oct2_o = oct2_q;
        neg_o = neg_q;
    end

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
    // #{k : j >= T_k} from the bucket of 128 rows that j falls in: the thresholds below
    // the bucket (a 16-entry table in logic) plus the one inside it, if j reaches it
    localparam [63:0]  HB_LO_N = TABLE_EXACT ? HB_LO_EXACT_N : HB_LO_PAPER_N;
    localparam [127:0] HB_LO_T = TABLE_EXACT ? HB_LO_EXACT_T : HB_LO_PAPER_T;
    localparam [63:0]  HB_HI_N = TABLE_EXACT ? HB_HI_EXACT_N : HB_HI_PAPER_N;
    localparam [127:0] HB_HI_T = TABLE_EXACT ? HB_HI_EXACT_T : HB_HI_PAPER_T;
    wire [3:0]  bk = j_o[10:7];
    wire [3:0]  bn = neg_2 ? HB_HI_N[4*bk +: 4] : HB_LO_N[4*bk +: 4];
    wire [7:0]  bt = neg_2 ? HB_HI_T[8*bk +: 8] : HB_LO_T[8*bk +: 8];
    wire [3:0]  cnt = bn + {3'd0, ({1'b0, j_o[6:0]} >= bt)};   // floor or ceil(PH[j] / 128)
    assign bin_o = neg_2 ? {oct2_2, 4'd0} - {2'd0, cnt} : {oct2_2, 4'd0} + {2'd0, cnt};

    wire unused = &{1'b0, psum[15:0], jq[2:0], ns[0], ln[14], ln[4:0], 1'b0};
endmodule
`resetall
