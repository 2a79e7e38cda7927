`timescale 1ns / 1ps
`default_nettype none
// octant: Table 2 of the paper. The octant comes from the signs of u1c, u2c and the
// comparison of their magnitudes (as the paper, for both tables); the table address from
// the magnitudes. Mirrors sim/model/octant.py octant(), ratio() and scale().
//   TABLE_EXACT = 1: the ratio t = |small| / |large| in [0, 1], the tangent of the
//     octant-local angle (so both signals contribute: the angle noise is sigma/A at every
//     angle, the Cramer-Rao bound, where the small signal alone gives sigma/(A cos a));
//     the phase table holds atan. No divider: a reciprocal of the normalised |large| from
//     a 512-word table (2 block RAMs), one multiply |small| * recip (a DSP block).
//   TABLE_EXACT = 0: the smaller magnitude, linear (Eq. 10), bit for bit the paper's.
// Also the address's scale t_o, from which rtl/harmonic.v finds the bin of its table
// before the phase table is read (so the two tables are read on the same edge), and
// which addresses the exact phase table of 4096 rows per sign (rtl/lut.v OPT_PHASE_4K)
// without the rounding add.
//
// The stages' registers take a sample only with its valid bit (a clock enable; between
// samples they hold the last one's values: j_o and t_o then too).
// Timing: inputs registered on edge e (= t + 2 in the core); outputs:
//   e    zl_i    u4    lzc15(|u1c| | |u2c|) = lzc15(large), formed by rtl/correct.v beside
//                      the magnitudes: the leading one of the larger magnitude is that of
//                      the OR, so the shift waits neither for the comparison nor for a
//                      leading-zero count; both magnitudes are shifted by it and the
//                      comparison only selects
//   e+1  rcp     u0.14 RECIP[ln[13:5]] ~ 2**14 / m, m = ln / 2**14 in [1, 2) (block RAM;
//                      recip.hex); ln = large << zl in [2**14, 2**15) (0 for large = 0)
//        sn      u14   (small << zl) >> 1: small on the normalised scale, t = 2 sn / ln
//        jp      u11   paper address min(2047, (small + 4) >> 3)
//        oct2_o  u2    base phase 2048 oct2 (u13 units, 8192 per period)
//        neg_o   u1    phase = base - PH[j] (else base + PH[j]); rtl/lut.v takes it on
//                      e+2 for the phase table's word (read on e+3)
//        valid_o       (octant: |u2c| <= |u1c| is the low octant 0, 3, 4 or 7; ties low)
//   e+2  rcp_q   u0.14 rcp again, sn_q u14 sn: the block RAM's output in flip-flops (its
//                      clock-to-output time, 5.6 ns on the ECP5, leaves no room for a
//                      multiply behind it in one clock); with OPT_ECP5_MULT these two
//                      registers are the DSP block's input registers
//   e+3 (combinational from the registers of e+2, for the block RAM addresses):
//        p       u28   sn_q * rcp_q = t * 2**27 (1 + O(2**-10)) (a DSP block)
//        j_o     u11   exact: min(2047, (p + 2**15) >> 16) = round(2048 t), clipped; paper: jp
//        t_o     u12   exact: min(4095, floor(p / 2**15)), so j = (t_o + 1) >> 1 clipped
//                      at 2047; paper: 2 jp (the scale of rtl/tables/hbin.vh)
module octant #(
    parameter TABLE_DIR = "rtl/tables/",
    parameter [0:0] TABLE_EXACT = 1'b1,
    // 1: the ratio multiply's operand registers (rcp_q, sn_q) are the DSP block's own
    // input registers: an ECP5 MULT18X18D instantiated (synthesis does not pack registers
    // into it), which saves the route from the flip-flops to the block in front of the
    // logic behind t_o (ECP5 at ~100 MHz: rtl/harmonic.v OPT_DISTRAM forms its bins'
    // addresses from t_o and registers them). Synthesis only (`SYNTHESIS, as Yosys
    // defines it); simulations run the inferred form, the same registers and product
    // (cocotb_tests/test_octant.py test_octant_mult18 runs the instance against a
    // stand-in of the primitive). 0: inferred (any device)
    parameter [0:0] OPT_ECP5_MULT = 1'b0
) (
    input  wire        clk,
    input  wire        valid_i,
    input  wire [14:0] ax_i,      // u15 |u1c|, s2.14 units
    input  wire [14:0] ay_i,      // u15 |u2c|
    input  wire        xn_i,      // u1c < 0
    input  wire        yn_i,      // u2c < 0
    input  wire [3:0]  zl_i,      // lzc15(ax_i | ay_i) (rtl/correct.v), with them
    output wire        valid_o,
    output wire [10:0] j_o,
    output wire [11:0] t_o,
    output wire [1:0]  oct2_o,
    output wire        neg_o
);

    // ---- e+1: octant, normalisation, reciprocal ------------------------------------------
    // (as functions evaluated in the clock enable's branch: simulation computes this
    // logic only for a sample)
    // one normalising shift for both magnitudes (zl); the comparison low = |u2c| <= |u1c|,
    // side by side with it, then selects by AND-OR (with a multiplexer synthesis would
    // share the shifters behind the comparison, a longer path): large << zl (bit 15 is 0)
    // or, with want_small, small << zl
    function automatic [14:0] norm(input [14:0] ax, input [14:0] ay, input [3:0] zl,
                                   input want_small);
        reg [14:0] lx, ly, sel;
        begin
            lx = ax << zl;
            ly = ay << zl;
            sel = {15{(ay <= ax) ^ want_small}};
            norm = (lx & sel) | (ly & ~sel);
        end
    endfunction
    // sn = (small << zl) >> 1
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [13:0] snorm(input [14:0] ax, input [14:0] ay, input [3:0] zl);
        reg [14:0] ns;
        begin
            ns = norm(ax, ay, zl, 1'b1);
            snorm = ns[14:1];
        end
    endfunction
    // the paper's address min(2047, (small + 4) >> 3)
    function automatic [10:0] paddr(input [14:0] ax, input [14:0] ay);
        reg [15:0] jq;
        begin
            jq = ({1'b0, (ay <= ax) ? ay : ax} + 16'd4) >> 3;
            paddr = (jq[15:11] != 5'd0) ? 11'd2047 : jq[10:0];
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    reg  [13:0] rcp_rom [0:511];
    initial
        $readmemh({TABLE_DIR, "recip.hex"}, rcp_rom);
    reg  [13:0] rcp = 0;
    reg  [13:0] sn = 0;
    reg  [10:0] jp = 0;
    reg  [1:0]  oct2_q = 0;
    reg         neg_q = 1'b0, v1 = 1'b0;
    wire [14:0] ln = norm(ax_i, ay_i, zl_i, 1'b0);   // the reciprocal's address (a RAM's)
    wire        low = (ay_i <= ax_i);                // (only the octant below)
    always @(posedge clk) begin
        if (valid_i) begin
            rcp    <= rcp_rom[ln[13:5]];
            sn     <= snorm(ax_i, ay_i, zl_i);
            jp     <= paddr(ax_i, ay_i);
            oct2_q <= low ? (xn_i ? 2'd2 : 2'd0) : (yn_i ? 2'd3 : 2'd1);
            neg_q  <= low ? (xn_i ^ yn_i) : !(xn_i ^ yn_i);
        end
        v1     <= valid_i;
    end
    // continuous assignments (an always @* of registers that keep their initial value
    // never runs in Icarus, and its outputs stay x)
    assign valid_o = v1;
    assign oct2_o = oct2_q;
    assign neg_o = neg_q;

    // ---- e+2: the reciprocal and the small magnitude in flip-flops (rcp_q, sn_q: below,
    // beside the multiply) ----------------------------------------------------------------
    reg [10:0] jp_q = 0;
    always @(posedge clk)
        if (v1)
            jp_q    <= jp;

    // ---- e+3 (combinational): ratio (a DSP block), address, scale --------------------------
    wire [27:0] p;                                   // u28 sn_q * rcp_q
`ifdef SYNTHESIS
    localparam [0:0] MULT18 = OPT_ECP5_MULT;
`else
    localparam [0:0] MULT18 = OPT_ECP5_MULT & 1'b0;   // (simulation: inferred)
`endif
    generate
        if (MULT18) begin : g_mult18
`ifdef SYNTHESIS
            // rcp_q and sn_q in the block's input registers A and B (CLK0 = clk,
            // CE0 = v1); unsigned 14 x 14 bits, no output or pipeline register
            wire [35:0] pw;
            MULT18X18D #(
                .REG_INPUTA_CLK("CLK0"), .REG_INPUTA_CE("CE0"), .REG_INPUTA_RST("RST0"),
                .REG_INPUTB_CLK("CLK0"), .REG_INPUTB_CE("CE0"), .REG_INPUTB_RST("RST0")
            ) u_mult (
                .A17(1'b0), .A16(1'b0), .A15(1'b0), .A14(1'b0), .A13(rcp[13]),
                .A12(rcp[12]), .A11(rcp[11]), .A10(rcp[10]), .A9(rcp[9]), .A8(rcp[8]),
                .A7(rcp[7]), .A6(rcp[6]), .A5(rcp[5]), .A4(rcp[4]), .A3(rcp[3]),
                .A2(rcp[2]), .A1(rcp[1]), .A0(rcp[0]),
                .B17(1'b0), .B16(1'b0), .B15(1'b0), .B14(1'b0), .B13(sn[13]),
                .B12(sn[12]), .B11(sn[11]), .B10(sn[10]), .B9(sn[9]), .B8(sn[8]),
                .B7(sn[7]), .B6(sn[6]), .B5(sn[5]), .B4(sn[4]), .B3(sn[3]), .B2(sn[2]),
                .B1(sn[1]), .B0(sn[0]),
                .C17(1'b0), .C16(1'b0), .C15(1'b0), .C14(1'b0), .C13(1'b0), .C12(1'b0),
                .C11(1'b0), .C10(1'b0), .C9(1'b0), .C8(1'b0), .C7(1'b0), .C6(1'b0),
                .C5(1'b0), .C4(1'b0), .C3(1'b0), .C2(1'b0), .C1(1'b0), .C0(1'b0),
                .SIGNEDA(1'b0), .SIGNEDB(1'b0), .SOURCEA(1'b0), .SOURCEB(1'b0),
                .CLK0(clk), .CLK1(1'b0), .CLK2(1'b0), .CLK3(1'b0),
                .CE0(v1), .CE1(1'b0), .CE2(1'b0), .CE3(1'b0),
                .RST0(1'b0), .RST1(1'b0), .RST2(1'b0), .RST3(1'b0),
                .P35(pw[35]), .P34(pw[34]), .P33(pw[33]), .P32(pw[32]), .P31(pw[31]),
                .P30(pw[30]), .P29(pw[29]), .P28(pw[28]), .P27(pw[27]), .P26(pw[26]),
                .P25(pw[25]), .P24(pw[24]), .P23(pw[23]), .P22(pw[22]), .P21(pw[21]),
                .P20(pw[20]), .P19(pw[19]), .P18(pw[18]), .P17(pw[17]), .P16(pw[16]),
                .P15(pw[15]), .P14(pw[14]), .P13(pw[13]), .P12(pw[12]), .P11(pw[11]),
                .P10(pw[10]), .P9(pw[9]), .P8(pw[8]), .P7(pw[7]), .P6(pw[6]),
                .P5(pw[5]), .P4(pw[4]), .P3(pw[3]), .P2(pw[2]), .P1(pw[1]), .P0(pw[0])
            );
            assign p = pw[27:0];
            wire unused_pw = &{1'b0, pw[35:28], 1'b0};
`endif
        end else begin : g_mult
            reg [13:0] rcp_q = 0;                    // u0.14 rcp
            reg [13:0] sn_q = 0;                     // u14 sn
            always @(posedge clk)
                if (v1) begin
                    rcp_q <= rcp;
                    sn_q  <= sn;
                end
            assign p = sn_q * rcp_q;
        end
    endgenerate
    wire [28:0] psum = {1'b0, p} + 29'h8000;
    wire [10:0] jr = (psum[28:27] != 2'b00) ? 11'd2047 : psum[26:16];
    assign j_o = TABLE_EXACT ? jr : jp_q;
    assign t_o = TABLE_EXACT ? (p[27] ? 12'hfff : p[26:15]) : {jp_q, 1'b0};

    wire unused = &{1'b0, psum[15:0], p[14:0], ln[14], ln[4:0], 1'b0};
endmodule
`resetall
