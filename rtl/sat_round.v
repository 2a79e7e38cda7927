`timescale 1ns / 1ps
`default_nettype none
// sat_round: out = sat_OW(rnd_shr(in, sh)) -- arithmetic shift right by sh with
// round-half-up (add 2**(sh-1) first, in XW bits: wide enough for the input plus one bit
// and for the largest rounding constant, so it cannot overflow), then saturation to OW
// bits. Mirrors sim/model/fixed.py rnd_shr + sat. Combinational.
module sat_round #(
    // input width
    parameter IW = 64,
    // output width
    parameter OW = 32,
    // width of the shift amount
    parameter SW = 6
) (
    input  wire signed [IW-1:0] in_i,
    input  wire        [SW-1:0] sh_i,
    output reg  signed [OW-1:0] out_o,
    output reg                  sat_o   // 1 when the value was clamped
);
    localparam XW = (IW + 1 > (1 << SW)) ? IW + 1 : (1 << SW);
    reg signed [XW-1:0] ext, rnd, shifted;
    always @* begin
        ext = {{(XW-IW){in_i[IW-1]}}, in_i};
        rnd = (sh_i == 0) ? {XW{1'b0}} : ({{(XW-1){1'b0}}, 1'b1} <<< (sh_i - 1'b1));
        shifted = (ext + rnd) >>> sh_i;
        // fits in OW bits exactly when bits [XW-1:OW-1] are all copies of the sign
        if (!(&shifted[XW-1:OW-1]) && (|shifted[XW-1:OW-1])) begin
            out_o = shifted[XW-1] ? {1'b1, {(OW-1){1'b0}}} : {1'b0, {(OW-1){1'b1}}};
            sat_o = 1'b1;
        end else begin
            out_o = shifted[OW-1:0];
            sat_o = 1'b0;
        end
    end
endmodule
`resetall
