`timescale 1ns / 1ps
`default_nettype none
// lut: Table 1 of the paper through two block-RAM look-ups (sim/model/fastpath.py Lut).
// Row i of Table 1 only depends on (n i) mod 8N, so the octant address first goes through
// a phase table (one octant, by symmetry) and the n-th order phase indexes one
// quarter-wave sine table that serves every n:
//   phase table: ph = PH[j] (u12, phase_<table>.hex), read on the edge j_i is presented
//     (j_i may be combinational: rtl/octant.v forms it with its last add); ph_o is the
//     block RAM's output, valid after that edge. OPT_PHASE_4K (exact table): the table in
//     4096 rows (phase_exact_4k.hex), read at the scale t_i instead (row t holds
//     PH[min(2047, (t + 1) >> 1)]), so the address does not wait for j's rounding add. The fine phase itself,
//     (2048 oct2 +- ph) mod 8192, is assembled with the harmonic correction in
//     rtl/harmonic.v.
//   n-th order: the full product P = n * phase (u22) of the (corrected) fine phase
//     registered on edge e is registered on e + 1: its low 13 bits are the n-th order
//     phase pn = (n phase) mod 8192, its high bits the counter's fine count
//     q = floor(n phase / 2048) = P >> 11 (u11, rtl/counter.v).
//   sines on e + 2: cos(n a), sin(n a) as magnitude T[k] (u0.(SIN_W-1)) and sign
//     (quadrant q = pn[12:11], k = pn[10:0], mirrored k for odd q, negative for q >= 2).
// TABLE_EXACT = 1: j = round(2048 |small| / |large|) (rtl/octant.v), rows atan(j / 2048):
//   no linearisation error, and the angle noise of atan2 (the default);
// TABLE_EXACT = 0: j = round(2048 |small|), the paper's uniform angle per row.
module lut #(
    parameter TABLE_DIR = "rtl/tables/",
    parameter [0:0] TABLE_EXACT = 1'b1,
    // sine word width (magnitude SIN_W-1 bits)
    parameter SIN_W = 10,
    // 1: n * phase with the `*` operator (a DSP block where the device has one to
    // spare, e.g. ECP5); 0: shift-and-add in logic (iCE40 UP5K: its 8 DSP blocks are taken)
    parameter [0:0] OPT_NTH_DSP = 1'b1,
    // 1 (with TABLE_EXACT): the phase table in 4096 rows addressed by t_i, no rounding add
    // before the block RAM (for clock rates near 100 MHz, e.g. ECP5: 3 block RAMs instead
    // of 2); 0: 2048 rows addressed by j_i (iCE40: its block RAMs are counted)
    parameter [0:0] OPT_PHASE_4K = 1'b0
) (
    input  wire              clk,
    // phase table
    input  wire [10:0]       j_i,          // u11 octant-local address
    input  wire [11:0]       t_i,          // u12 its scale (OPT_PHASE_4K), with j_i
    output wire [11:0]       ph_o,         // u12 PH[j], one edge after j_i
    // n-th order
    input  wire              valid_i,      // with phase_i
    input  wire [12:0]       phase_i,      // u13 fine phase (registered)
    input  wire [8:0]        n_i,          // interpolation factor
    output reg               nth_valid_o,  // latency 1
    output reg  [21:0]       prod_o,       // u22 n * phase: pn = [12:0], q = [21:11]
    output reg               valid_o,      // latency 2
    output reg  [12:0]       pn_o,         // u13 n-th order phase, aligned with the sines
    output wire [SIN_W-2:0]  cos_mag_o,
    output reg               cos_neg_o,
    output wire [SIN_W-2:0]  sin_mag_o,
    output reg               sin_neg_o
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
        end else begin : g_sin10
            initial begin
                $readmemh({TABLE_DIR, "sine_10.hex"}, sin_rom_c);
                $readmemh({TABLE_DIR, "sine_10.hex"}, sin_rom_s);
            end
        end
    endgenerate

    // ---- phase table ------------------------------------------------------------------------
    reg [11:0] ph_q = 0;
    generate
        if (PH4K) begin : g_ph4k
            reg [11:0] ph_rom [0:4095];
            initial
                $readmemh({TABLE_DIR, "phase_exact_4k.hex"}, ph_rom);
            always @(posedge clk)
                ph_q <= ph_rom[t_i];
            wire unused_j = &{1'b0, j_i, 1'b0};
        end else begin : g_ph2k
            reg [11:0] ph_rom [0:2047];
            initial
                $readmemh({TABLE_DIR, PH_FILE}, ph_rom);
            always @(posedge clk)
                ph_q <= ph_rom[j_i];
            wire unused_t = &{1'b0, t_i, 1'b0};
        end
    endgenerate
    assign ph_o = ph_q;

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
    always @(posedge clk) begin
        prod_o <= prod;
        nth_valid_o <= valid_i;
    end

    // ---- sines: quarter-wave table, cos(x) = sin(x + pi/2) ----------------------------------
    wire [12:0] pn = prod_o[12:0];
    wire [12:0] pc = pn + 13'd2048;
    wire [10:0] ks = pn[11] ? ~pn[10:0] : pn[10:0];
    wire [10:0] kc = pc[11] ? ~pc[10:0] : pc[10:0];
    reg [SIN_W-1:0] sraw = 0, craw = 0;
    always @(posedge clk) begin
        sraw      <= sin_rom_s[ks];
        craw      <= sin_rom_c[kc];
        sin_neg_o <= pn[12];
        cos_neg_o <= pc[12];
        pn_o      <= pn;
        valid_o   <= nth_valid_o;
    end
    assign sin_mag_o = sraw[SIN_W-2:0];
    assign cos_mag_o = craw[SIN_W-2:0];
    initial begin
        nth_valid_o = 1'b0; prod_o = 0; valid_o = 1'b0; pn_o = 0;
        sin_neg_o = 1'b0; cos_neg_o = 1'b0;
    end
    wire unused = &{1'b0, sraw[SIN_W-1], craw[SIN_W-1], 1'b0};
endmodule
`resetall
