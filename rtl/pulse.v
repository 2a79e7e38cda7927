`timescale 1ns / 1ps
`default_nettype none
// pulse: Eq. 12, comparators with hysteresis (sim/model/fastpath.py pulse()).
//   A = 1 if cos(n a) >= eps, 0 if cos(n a) <= -eps, else unchanged (B likewise from sin).
// The table values (u0.(SIN_W-1) with sign) are compared in u0.15 units with eps.
// Latency 1; A and B start at 1.
module pulse #(
    parameter SIN_W = 10
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             valid_i,
    input  wire [SIN_W-2:0] cos_mag_i,
    input  wire             cos_neg_i,
    input  wire [SIN_W-2:0] sin_mag_i,
    input  wire             sin_neg_i,
    input  wire [15:0]      eps_i,        // u0.15 hysteresis threshold
    output reg              valid_o,
    output reg              a_o,
    output reg              b_o
);
    // signed values in u0.15 units: v = +-T << (16 - SIN_W)
    wire signed [16:0] cv = cos_neg_i ? -$signed({2'b0, cos_mag_i, {(16-SIN_W){1'b0}}})
                                      :  $signed({2'b0, cos_mag_i, {(16-SIN_W){1'b0}}});
    wire signed [16:0] sv = sin_neg_i ? -$signed({2'b0, sin_mag_i, {(16-SIN_W){1'b0}}})
                                      :  $signed({2'b0, sin_mag_i, {(16-SIN_W){1'b0}}});
    wire signed [16:0] ep = $signed({1'b0, eps_i});
    always @(posedge clk) begin
        valid_o <= valid_i;
        if (valid_i) begin
            if (cv >= ep)
                a_o <= 1'b1;
            else if (cv <= -ep)
                a_o <= 1'b0;
            if (sv >= ep)
                b_o <= 1'b1;
            else if (sv <= -ep)
                b_o <= 1'b0;
        end
        if (rst) begin
            valid_o <= 1'b0;
            a_o <= 1'b1;
            b_o <= 1'b1;
        end
    end
    initial begin
        valid_o = 1'b0; a_o = 1'b1; b_o = 1'b1;
    end
endmodule
`resetall
