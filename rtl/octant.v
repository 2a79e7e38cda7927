`timescale 1ns / 1ps
`default_nettype none
// octant: Table 2 of the paper. The octant comes from the signs of u1c, u2c and the
// comparison of their magnitudes; the table address from the smaller magnitude
// (the signal below sin(pi/4), Eq. 10). Mirrors sim/model/fastpath.py octant().
// Latency 2.
//   j     u11  address = min(2047, (|smag| + 4) >> 3): |smag| in steps of 1/2048
//   oct2  u2   base phase oct2 * 2048 (u13 units, 8192 per period)
//   neg   u1   phase = base - PH[j] (else base + PH[j])
module octant (
    input  wire               clk,
    input  wire               valid_i,
    input  wire signed [15:0] u1c_i,   // s2.14
    input  wire signed [15:0] u2c_i,   // s2.14
    output reg                valid_o,
    output reg  [10:0]        j_o,
    output reg  [1:0]         oct2_o,
    output reg                neg_o
);
    // +1: magnitudes (saturated to 15 bits) and signs
    wire [15:0] ax_f = u1c_i[15] ? -u1c_i : u1c_i;
    wire [15:0] ay_f = u2c_i[15] ? -u2c_i : u2c_i;
    reg  [14:0] ax = 0, ay = 0;
    reg         xn = 1'b0, yn = 1'b0, v1 = 1'b0;
    always @(posedge clk) begin
        ax <= ax_f[15] ? 15'h7fff : ax_f[14:0];
        ay <= ay_f[15] ? 15'h7fff : ay_f[14:0];
        xn <= u1c_i[15];
        yn <= u2c_i[15];
        v1 <= valid_i;
    end
    // +2: octant and address; both candidate addresses are formed side by side with the
    // magnitude comparison, then selected
    wire low = ay <= ax;                 // |u2c| <= |u1c|: octants 0, 3, 4, 7
    wire [15:0] jx = ({1'b0, ax} + 16'd4) >> 3;
    wire [15:0] jy = ({1'b0, ay} + 16'd4) >> 3;
    wire [10:0] jxc = (jx[15:11] != 5'd0) ? 11'd2047 : jx[10:0];
    wire [10:0] jyc = (jy[15:11] != 5'd0) ? 11'd2047 : jy[10:0];
    always @(posedge clk) begin
        j_o    <= low ? jyc : jxc;
        oct2_o <= low ? (xn ? 2'd2 : 2'd0) : (yn ? 2'd3 : 2'd1);
        neg_o  <= low ? (xn ^ yn) : !(xn ^ yn);
        valid_o <= v1;
    end
    initial begin
        valid_o = 1'b0; j_o = 0; oct2_o = 0; neg_o = 1'b0;
    end
endmodule
`resetall
