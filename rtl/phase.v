`timescale 1ns / 1ps
`default_nettype none
// phase: the fine phase from the octant and the phase table, without the harmonic
// compensation (finequad_core with OPT_HARMONIC = 0; rtl/harmonic.v does the same
// assembly with the correction). Same timing as rtl/harmonic.v, a = the edge on which
// valid_i is high (the sample's arrival; t + 4 in the core):
//   a      oct2_i, neg_i taken
//   a + 1  the constant part 2048 oct2 + neg registered; ph_i = PH[j] (~PH[j] for
//          neg) is the phase table's output after this edge
//   a + 2  phase_o = phase_c_o = (2048 oct2 +- ph) mod 8192 (u13, - when neg), valid_o
// Every stage's registers take a sample only with its valid bit (a clock enable).
module phase (
    input  wire        clk,
    input  wire        valid_i,
    input  wire [1:0]  oct2_i,      // with valid_i: base phase 2048 oct2 (rtl/octant.v)
    input  wire        neg_i,       // with valid_i: phase = base - ph
    input  wire [11:0] ph_i,        // u12 PH[j], ~PH[j] for neg (rtl/lut.v), after a + 1
    output reg         valid_o = 1'b0,
    output reg  [12:0] phase_o = 13'd0,
    output wire [12:0] phase_c_o
);
    reg        v1 = 1'b0, v2 = 1'b0, neg1 = 1'b0, neg2 = 1'b0;
    reg [1:0]  oct1 = 2'd0;
    reg [12:0] k0 = 13'd0;                       // 2048 oct2 + neg (-ph = ~ph + 1)
    always @(posedge clk) begin
        v1 <= valid_i;
        v2 <= v1;
        valid_o <= v2;
        if (valid_i) begin
            oct1 <= oct2_i;
            neg1 <= neg_i;
        end
        if (v1) begin
            k0 <= {oct1, 11'd0} + {12'd0, neg1};
            neg2 <= neg1;
        end
        if (v2)
            phase_o <= k0 + {neg2, ph_i};          // - ph = ~ph + 1 = {1, ~ph} + 1
    end
    assign phase_c_o = phase_o;
endmodule
`resetall
