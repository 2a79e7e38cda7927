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
    // With v = +-m (m the magnitude in u0.15) one unsigned comparison m >= eps decides:
    //   v >= eps   <=>  (!neg && m >= eps) || (m == 0 && eps == 0)
    //   v <= -eps  <=>  ( neg && m >= eps) || (m == 0 && eps == 0)   (used when not v >= eps)
    wire [15:0] cm = {1'b0, cos_mag_i, {(16-SIN_W){1'b0}}};
    wire [15:0] sm = {1'b0, sin_mag_i, {(16-SIN_W){1'b0}}};
    wire c_ge = cm >= eps_i;
    wire s_ge = sm >= eps_i;
    wire zero_eps = (eps_i == 16'd0);
    wire c_pos = (!cos_neg_i && c_ge) || (zero_eps && cm == 16'd0);
    wire c_neg = cos_neg_i && c_ge;
    wire s_pos = (!sin_neg_i && s_ge) || (zero_eps && sm == 16'd0);
    wire s_neg = sin_neg_i && s_ge;
    always @(posedge clk) begin
        valid_o <= valid_i;
        if (valid_i) begin
            if (c_pos)
                a_o <= 1'b1;
            else if (c_neg)
                a_o <= 1'b0;
            if (s_pos)
                b_o <= 1'b1;
            else if (s_neg)
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
