`timescale 1ns / 1ps
`default_nettype none
// lut: Table 1 of the paper through two block-RAM look-ups (sim/model/lut.py Lut).
// Row i of Table 1 only depends on (n i) mod 8N, so the octant address first goes through
// a phase table (one octant, by symmetry) and the n-th order phase indexes one
// quarter-wave sine table that serves every n:
//   phase table: ph = PH[j] (u12, phase_<table>.hex), read on the edge j_i is presented
//     (j_i may be combinational: rtl/octant.v forms it with its last add), with the
//     octant's sign neg_i presented one edge before (registered here); ph_o = PH[j], or
//     its complement ~PH[j] (12 bits) for neg, valid after the read edge: the fine phase
//     (2048 oct2 +- PH) mod 8192 = 2048 oct2 + neg + {neg, ph_o} needs no inversion
//     after the table (it is assembled with the harmonic correction in rtl/harmonic.v,
//     or rtl/phase.v). Default: 2048 rows, the complement taken after the block RAM.
//     OPT_PHASE_4K (exact table): 4096 rows per sign (phase_exact_4k.hex: row t holds
//     PH[min(2047, (t + 1) >> 1)], row 4096 + t its complement), read at {neg, t_i}: the
//     address does not wait for j's rounding add, and ph_o is the block RAM's output.
//   n-th order: the full product P = n * phase (u22) of the (corrected) fine phase
//     registered on edge e is registered on e + 1: its low 13 bits are the n-th order
//     phase pn = (n phase) mod 8192, its high bits the counter's fine count
//     q = floor(n phase / 2048) = P >> 11 (u11, rtl/counter.v).
//   sines on e + 2: cos(n a), sin(n a) as magnitude T[k] (u0.(SIN_W-1)) and sign
//     (quadrant q = pn[12:11], k = pn[10:0], mirrored k for odd q, negative for q >= 2),
//     and the addresses k themselves (for rtl/pulse.v's comparison on the address side).
// TABLE_EXACT = 1: j = round(2048 |small| / |large|) (rtl/octant.v), rows atan(j / 2048):
//   no linearisation error, and the angle noise of atan2 (the default);
// TABLE_EXACT = 0: j = round(2048 |small|), the paper's uniform angle per row.
module lut #(
    parameter TABLE_DIR = "rtl/tables/",
    parameter [0:0] TABLE_EXACT = 1'b1,
    // sine word width (magnitude SIN_W-1 bits): 8, 10, 12 or 16 (rtl/tables/sine_<SIN_W>.hex)
    parameter SIN_W = 10,
    // 1: n * phase with the `*` operator (a DSP block where the device has one to
    // spare, e.g. ECP5); 0: shift-and-add in logic (iCE40 UP5K: its 8 DSP blocks are taken)
    parameter [0:0] OPT_NTH_DSP = 1'b1,
    // 1 (with TABLE_EXACT): the phase table in 4096 rows per sign addressed by {neg, t_i},
    // no rounding add before the block RAM and no inversion after it (for clock rates
    // near 100 MHz, e.g. ECP5: 6 block RAMs instead of 2); 0: 2048 rows addressed by j_i
    // (iCE40: its block RAMs are counted)
    parameter [0:0] OPT_PHASE_4K = 1'b0,
    // 1 (with OPT_NTH_DSP): prod_o is the output register of an ECP5 MULT18X18D
    // instantiated for n * phase (synthesis does not pack registers into it), which saves
    // the route from the block to flip-flops behind the multiply (ECP5 at ~100 MHz: the
    // phase correction's add lies in front of it). Synthesis only (`SYNTHESIS, as Yosys
    // defines it); simulations run the inferred form, the same register and product
    // (cocotb_tests/test_lut.py test_lut_mult18 runs the instance against a stand-in of
    // the primitive). 0: inferred (any device)
    parameter [0:0] OPT_ECP5_MULT = 1'b0
) (
    input  wire              clk,
    // phase table
    input  wire [10:0]       j_i,          // u11 octant-local address
    input  wire [11:0]       t_i,          // u12 its scale (OPT_PHASE_4K), with j_i
    input  wire              neg_i,        // the sample's octant sign, one edge before j_i
    output wire [11:0]       ph_o,         // u12 PH[j] (~PH[j] for neg), one edge after j_i
    // n-th order
    input  wire              valid_i,      // with phase_i
    input  wire [12:0]       phase_i,      // u13 fine phase (registered)
    input  wire [8:0]        n_i,          // interpolation factor
    output reg               nth_valid_o,  // latency 1
    output wire [21:0]       prod_o,       // u22 n * phase: pn = [12:0], q = [21:11]
    output reg               valid_o,      // latency 2
    output reg  [12:0]       pn_o,         // u13 n-th order phase, aligned with the sines
    output wire [SIN_W-2:0]  cos_mag_o,
    output reg               cos_neg_o,
    output wire [SIN_W-2:0]  sin_mag_o,
    output reg               sin_neg_o,
    output reg  [10:0]       cos_k_o,      // u11 the sines' table addresses, registered
    output reg  [10:0]       sin_k_o       // with them (rtl/pulse.v OPT_ADDR)
);
    localparam PH_FILE = TABLE_EXACT ? "phase_exact.hex" : "phase_paper.hex";
    localparam [0:0] PH4K = TABLE_EXACT && OPT_PHASE_4K;
    reg [SIN_W-1:0] sin_rom_c [0:2047];
    reg [SIN_W-1:0] sin_rom_s [0:2047];
    // one branch per sine file: Icarus 11 turns a ?: between strings of different
    // lengths ("sine_8.hex" vs "sine_10.hex") into an empty string
    generate
        if (SIN_W == 8) begin : g_sin8
            initial begin
                $readmemh({TABLE_DIR, "sine_8.hex"}, sin_rom_c);
                $readmemh({TABLE_DIR, "sine_8.hex"}, sin_rom_s);
            end
        end else if (SIN_W == 12) begin : g_sin12
            initial begin
                $readmemh({TABLE_DIR, "sine_12.hex"}, sin_rom_c);
                $readmemh({TABLE_DIR, "sine_12.hex"}, sin_rom_s);
            end
        end else if (SIN_W == 16) begin : g_sin16
            initial begin
                $readmemh({TABLE_DIR, "sine_16.hex"}, sin_rom_c);
                $readmemh({TABLE_DIR, "sine_16.hex"}, sin_rom_s);
            end
        end else if (SIN_W == 10) begin : g_sin10
            initial begin
                $readmemh({TABLE_DIR, "sine_10.hex"}, sin_rom_c);
                $readmemh({TABLE_DIR, "sine_10.hex"}, sin_rom_s);
            end
        end else begin : g_bad_sin_w
            // no table of that width: an undefined module named after the rule stops
            // elaboration (as rtl/finequad_core.v; rtl/vhdl/lut.vhd asserts the same)
            lut_SIN_W_must_be_8_10_12_or_16 u_bad ();
        end
    endgenerate

    // ---- phase table ------------------------------------------------------------------------
    reg [11:0] ph_q = 0;
    reg        neg_q = 1'b0;                     // neg_i, on the edge before the read
    always @(posedge clk)
        neg_q <= neg_i;
    generate
        if (PH4K) begin : g_ph4k
            reg [11:0] ph_rom [0:8191];
            initial
                $readmemh({TABLE_DIR, "phase_exact_4k.hex"}, ph_rom);
            always @(posedge clk)
                ph_q <= ph_rom[{neg_q, t_i}];
            assign ph_o = ph_q;
            wire unused_j = &{1'b0, j_i, 1'b0};
        end else begin : g_ph2k
            reg [11:0] ph_rom [0:2047];
            reg        neg_r = 1'b0;             // neg_q with the read
            initial
                $readmemh({TABLE_DIR, PH_FILE}, ph_rom);
            always @(posedge clk) begin
                ph_q <= ph_rom[j_i];
                neg_r <= neg_q;
            end
            assign ph_o = ph_q ^ {12{neg_r}};
            wire unused_t = &{1'b0, t_i, 1'b0};
        end
    endgenerate

    // ---- n-th order phase: P = n * phase ----------------------------------------------------
    wire [21:0] prod;
    generate
        if (OPT_NTH_DSP) begin : g_dsp
            assign prod = n_i * phase_i;
        end else begin : g_csa
            // nine rows n[b] * (phase << b), reduced by 3:2 counters to two, one carry add
            function [43:0] csa;                 // {sum, carry} of three u22, mod 2**22
                input [21:0] a, b, c;
                begin
                    csa = {a ^ b ^ c, ((a & b) | (a & c) | (b & c)) << 1};
                end
            endfunction
            wire [22*9-1:0] rows;
            genvar gb;
            for (gb = 0; gb < 9; gb = gb + 1) begin : g_rows
                assign rows[22*gb +: 22] = n_i[gb] ? ({9'd0, phase_i} << gb) : 22'd0;
            end
            wire [21:0] a0, b0, a1, b1, a2, b2, c0, d0, c1, d1, e0, f0, s0, s1;
            assign {a0, b0} = csa(rows[0 +: 22], rows[22 +: 22], rows[44 +: 22]);   // 9 -> 6
            assign {a1, b1} = csa(rows[66 +: 22], rows[88 +: 22], rows[110 +: 22]);
            assign {a2, b2} = csa(rows[132 +: 22], rows[154 +: 22], rows[176 +: 22]);
            assign {c0, d0} = csa(a0, b0, a1);                                      // 6 -> 4
            assign {c1, d1} = csa(b1, a2, b2);
            assign {e0, f0} = csa(c0, d0, c1);                                      // 4 -> 3
            assign {s0, s1} = csa(e0, f0, d1);                                      // 3 -> 2
            assign prod = s0 + s1;
        end
    endgenerate
    reg [21:0] prod_q = 0;
    always @(posedge clk) begin
        prod_q <= prod;
        nth_valid_o <= valid_i;
    end
    generate
        if (OPT_NTH_DSP && OPT_ECP5_MULT) begin : g_mult18
`ifdef SYNTHESIS
            // phase (u13) on A, n (u9) on B, unsigned; P registered on every edge (CE0 = 1)
            wire [35:0] pw;
            MULT18X18D #(
                .REG_OUTPUT_CLK("CLK0"), .REG_OUTPUT_CE("CE0"), .REG_OUTPUT_RST("RST0")
            ) u_mult (
                .A17(1'b0), .A16(1'b0), .A15(1'b0), .A14(1'b0), .A13(1'b0),
                .A12(phase_i[12]), .A11(phase_i[11]), .A10(phase_i[10]), .A9(phase_i[9]),
                .A8(phase_i[8]), .A7(phase_i[7]), .A6(phase_i[6]), .A5(phase_i[5]),
                .A4(phase_i[4]), .A3(phase_i[3]), .A2(phase_i[2]), .A1(phase_i[1]),
                .A0(phase_i[0]),
                .B17(1'b0), .B16(1'b0), .B15(1'b0), .B14(1'b0), .B13(1'b0), .B12(1'b0),
                .B11(1'b0), .B10(1'b0), .B9(1'b0), .B8(n_i[8]), .B7(n_i[7]), .B6(n_i[6]),
                .B5(n_i[5]), .B4(n_i[4]), .B3(n_i[3]), .B2(n_i[2]), .B1(n_i[1]),
                .B0(n_i[0]),
                .C17(1'b0), .C16(1'b0), .C15(1'b0), .C14(1'b0), .C13(1'b0), .C12(1'b0),
                .C11(1'b0), .C10(1'b0), .C9(1'b0), .C8(1'b0), .C7(1'b0), .C6(1'b0),
                .C5(1'b0), .C4(1'b0), .C3(1'b0), .C2(1'b0), .C1(1'b0), .C0(1'b0),
                .SIGNEDA(1'b0), .SIGNEDB(1'b0), .SOURCEA(1'b0), .SOURCEB(1'b0),
                .CLK0(clk), .CLK1(1'b0), .CLK2(1'b0), .CLK3(1'b0),
                .CE0(1'b1), .CE1(1'b0), .CE2(1'b0), .CE3(1'b0),
                .RST0(1'b0), .RST1(1'b0), .RST2(1'b0), .RST3(1'b0),
                .P35(pw[35]), .P34(pw[34]), .P33(pw[33]), .P32(pw[32]), .P31(pw[31]),
                .P30(pw[30]), .P29(pw[29]), .P28(pw[28]), .P27(pw[27]), .P26(pw[26]),
                .P25(pw[25]), .P24(pw[24]), .P23(pw[23]), .P22(pw[22]), .P21(pw[21]),
                .P20(pw[20]), .P19(pw[19]), .P18(pw[18]), .P17(pw[17]), .P16(pw[16]),
                .P15(pw[15]), .P14(pw[14]), .P13(pw[13]), .P12(pw[12]), .P11(pw[11]),
                .P10(pw[10]), .P9(pw[9]), .P8(pw[8]), .P7(pw[7]), .P6(pw[6]),
                .P5(pw[5]), .P4(pw[4]), .P3(pw[3]), .P2(pw[2]), .P1(pw[1]), .P0(pw[0])
            );
            assign prod_o = pw[21:0];
            wire unused_pw = &{1'b0, pw[35:22], prod_q, 1'b0};
`else
            assign prod_o = prod_q;
`endif
        end else begin : g_prod
            assign prod_o = prod_q;
        end
    endgenerate

    // ---- sines: quarter-wave table, cos(x) = sin(x + pi/2) ----------------------------------
    wire [12:0] pn = prod_o[12:0];
    wire [12:0] pc = pn + 13'd2048;
    wire [10:0] ks = pn[11] ? ~pn[10:0] : pn[10:0];
    wire [10:0] kc = pc[11] ? ~pc[10:0] : pc[10:0];
    reg [SIN_W-1:0] sraw = 0, craw = 0;
    always @(posedge clk) begin
        sraw      <= sin_rom_s[ks];
        craw      <= sin_rom_c[kc];
        sin_k_o   <= ks;
        cos_k_o   <= kc;
        sin_neg_o <= pn[12];
        cos_neg_o <= pc[12];
        pn_o      <= pn;
        valid_o   <= nth_valid_o;
    end
    assign sin_mag_o = sraw[SIN_W-2:0];
    assign cos_mag_o = craw[SIN_W-2:0];
    initial begin
        nth_valid_o = 1'b0; valid_o = 1'b0; pn_o = 0; cos_k_o = 0; sin_k_o = 0;
        sin_neg_o = 1'b0; cos_neg_o = 1'b0;
    end
    wire unused = &{1'b0, sraw[SIN_W-1], craw[SIN_W-1], 1'b0};
endmodule
`resetall
