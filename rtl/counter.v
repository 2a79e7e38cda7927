`timescale 1ns / 1ps
`default_nettype none
// counter: x4 up/down counter of the A/B edges (sim/model/fastpath.py counter()).
// Counts up when the phase increases (u1 leads u2). A/B show the n-th order quadrant
// only modulo 4: a two-quadrant step (both channels change at once, illegal for a
// quadrature decoder) is ambiguous and a four-quadrant step is invisible. The exact n-th
// order step D = n * wrap13(phase - phase_prev) resolves both:
//   dq  in {-1, 0, 1, 2}    A/B quadrant step
//   k   = (D - 2048 dq + 4096) >>> 13           nearest multiple of four quadrants
//   count += dq + 4 k; illegal when dq == 2 or k != 0 (flagged and counted)
// Latency 3. The first valid sample only primes the state.
module counter #(
    // counter width (wraps)
    parameter COUNT_W = 32
) (
    input  wire                      clk,
    input  wire                      rst,
    input  wire                      valid_i,
    input  wire                      a_i,
    input  wire                      b_i,
    input  wire [12:0]               phase_i,    // u13 fine phase, aligned with A/B
    input  wire [8:0]                n_i,
    output reg                       valid_o,
    output reg  signed [COUNT_W-1:0] count_o,
    output reg                       a_o,
    output reg                       b_o,
    output reg                       illegal_o,
    output reg  [31:0]               illegal_count_o
);
    // quadrant code: (1,1) 0, (0,1) 1, (0,0) 2, (1,0) 3
    wire [1:0] qd = {~b_i, a_i ^ b_i};
    reg  [1:0] qd_prev = 2'd0;
    reg [12:0] ph_prev = 0;
    reg        primed = 1'b0;
    // +1: steps
    reg  [1:0] dq1 = 0;
    reg signed [13:0] dph1 = 0;
    reg        v1 = 1'b0, p1 = 1'b0, a1 = 1'b1, b1 = 1'b1;
    wire [12:0] dph = phase_i - ph_prev;
    always @(posedge clk) begin
        if (valid_i) begin
            qd_prev <= qd;
            ph_prev <= phase_i;
            primed  <= 1'b1;
        end
        dq1  <= qd - qd_prev;
        dph1 <= $signed({dph[12], dph});
        v1 <= valid_i;
        p1 <= primed;
        a1 <= a_i;
        b1 <= b_i;
        if (rst) begin
            primed <= 1'b0;
            v1 <= 1'b0;
        end
    end
    // +2: exact n-th order step
    reg signed [23:0] d2 = 0;
    reg signed [2:0]  dq2 = 0;
    reg        v2 = 1'b0, p2 = 1'b0, a2 = 1'b1, b2 = 1'b1;
    always @(posedge clk) begin
        d2  <= dph1 * $signed({1'b0, n_i});
        dq2 <= (dq1 == 2'd3) ? -3'sd1 : $signed({1'b0, dq1});
        v2 <= v1; p2 <= p1; a2 <= a1; b2 <= b1;
        if (rst)
            v2 <= 1'b0;
    end
    // +3: count
    wire signed [24:0] dqx = {{22{dq2[2]}}, dq2};
    wire signed [24:0] kx = $signed({d2[23], d2}) - (dqx <<< 11) + 25'sd4096;
    wire signed [11:0] k = kx[24:13];
    wire signed [COUNT_W-1:0] inc = $signed({{(COUNT_W-3){dq2[2]}}, dq2}) +
                                    $signed({{(COUNT_W-14){k[11]}}, k, 2'b00});
    wire illegal = p2 && (dq2 == 3'sd2 || k != 0);
    wire unused = &{1'b0, kx[12:0], 1'b0};
    always @(posedge clk) begin
        valid_o <= v2;
        a_o <= a2;
        b_o <= b2;
        illegal_o <= v2 && illegal;
        if (v2 && p2) begin
            count_o <= count_o + inc;
            if (illegal)
                illegal_count_o <= illegal_count_o + 1'b1;
        end
        if (rst) begin
            valid_o <= 1'b0;
            count_o <= 0;
            illegal_count_o <= 0;
        end
    end
    initial begin
        valid_o = 1'b0; count_o = 0; a_o = 1'b1; b_o = 1'b1; illegal_o = 1'b0;
        illegal_count_o = 0;
    end
endmodule
`resetall
