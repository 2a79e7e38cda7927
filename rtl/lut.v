`timescale 1ns / 1ps
`default_nettype none
// lut: Table 1 of the paper through two block-RAM look-ups (sim/model/fastpath.py Lut).
// Row i of Table 1 only depends on (n i) mod 8N, so the octant address first goes through
// a phase table (one octant, by symmetry) and the n-th order phase indexes one
// quarter-wave sine table that serves every n:
//   +1  ph    = PH[j]                                    u12 (phase_<table>.hex)
//   +2  phase = (oct2 * 2048 +- ph) mod 8192             u13, 8192 units per period
//   +3  pn    = (n * phase) mod 8192                     u13, phase of the n-th order
//   +4  cos(n a), sin(n a) as magnitude T[k] (u0.(SIN_W-1)) and sign
//       (quadrant q = pn[12:11], k = pn[10:0], mirrored k for odd q, negative for q >= 2)
// TABLE_EXACT = 1: j = round(2048 |small| / |large|) (rtl/octant.v), rows atan(j / 2048):
//   no linearisation error, and the angle noise of atan2 (the default);
// TABLE_EXACT = 0: j = round(2048 |small|), the paper's uniform angle per row.
// j_i may be combinational (rtl/octant.v forms the exact address with its last add): it
// only feeds the phase table's address here.
module lut #(
    parameter TABLE_DIR = "rtl/tables/",
    parameter [0:0] TABLE_EXACT = 1'b1,
    // sine word width (magnitude SIN_W-1 bits)
    parameter SIN_W = 10
) (
    input  wire              clk,
    input  wire              valid_i,
    input  wire [10:0]       j_i,          // u11 octant-local address
    input  wire [1:0]        oct2_i,
    input  wire              neg_i,
    input  wire [8:0]        n_i,          // interpolation factor
    output reg               phase_valid_o,
    output reg  [12:0]       phase_o,      // u13 fine phase (latency 2)
    output reg               valid_o,      // latency 4
    output reg  [12:0]       pn_o,         // u13 n-th order phase, aligned with the sines
    output reg  [SIN_W-2:0]  cos_mag_o,
    output reg               cos_neg_o,
    output reg  [SIN_W-2:0]  sin_mag_o,
    output reg               sin_neg_o
);
    localparam PH_FILE = TABLE_EXACT ? "phase_exact.hex" : "phase_paper.hex";
    reg [11:0]      ph_rom [0:2047];
    reg [SIN_W-1:0] sin_rom_c [0:2047];
    reg [SIN_W-1:0] sin_rom_s [0:2047];
    initial
        $readmemh({TABLE_DIR, PH_FILE}, ph_rom);
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

    // +1: phase table
    reg [11:0] ph_q = 0;
    reg [1:0]  oct2_q = 0;
    reg        neg_q = 1'b0, v1 = 1'b0;
    always @(posedge clk) begin
        ph_q   <= ph_rom[j_i];
        oct2_q <= oct2_i;
        neg_q  <= neg_i;
        v1     <= valid_i;
    end
    // +2: fine phase
    wire [12:0] base = {oct2_q, 11'd0};
    always @(posedge clk) begin
        phase_o <= neg_q ? base - {1'b0, ph_q} : base + {1'b0, ph_q};
        phase_valid_o <= v1;
    end
    // +3: n-th order phase. Only the low 13 bits of n * phase are needed, so it is a
    // shift-and-add in logic (the DSP blocks go to the correction and the estimator).
    reg  [12:0] prod;
    integer     bi;
    always @* begin
        prod = 13'd0;
        for (bi = 0; bi < 9; bi = bi + 1)
            if (n_i[bi])
                prod = prod + (phase_o << bi);
    end
    reg  [12:0] pn_q = 0;
    reg         v3 = 1'b0;
    always @(posedge clk) begin
        pn_q <= prod;
        v3   <= phase_valid_o;
    end
    // +4: quarter-wave sine table, cos(x) = sin(x + pi/2)
    wire [12:0] pc = pn_q + 13'd2048;
    wire [10:0] ks = pn_q[11] ? ~pn_q[10:0] : pn_q[10:0];
    wire [10:0] kc = pc[11] ? ~pc[10:0] : pc[10:0];
    reg [SIN_W-1:0] sraw = 0, craw = 0;
    always @(posedge clk) begin
        sraw      <= sin_rom_s[ks];
        craw      <= sin_rom_c[kc];
        sin_neg_o <= pn_q[12];
        cos_neg_o <= pc[12];
        pn_o      <= pn_q;
        valid_o   <= v3;
    end
    always @* begin
        sin_mag_o = sraw[SIN_W-2:0];
        cos_mag_o = craw[SIN_W-2:0];
    end
    initial begin
        phase_o = 0; phase_valid_o = 1'b0; valid_o = 1'b0; pn_o = 0;
        sin_neg_o = 1'b0; cos_neg_o = 1'b0;
    end
    wire unused = &{1'b0, sraw[SIN_W-1], craw[SIN_W-1], 1'b0};
endmodule
`resetall
