`timescale 1ns / 1ps
`default_nettype none
// rls_engine_stub: formal-only stand-in for rtl/rls_engine.v (sim/formal/estimator.sby),
// ports as the real one. A program runs from start_i to done_o, which comes at the
// earliest 3 edges after the start and at any time after (real programs take 70..220
// edges); valid_o, out_o and sat_o are free (out_o may change on every clock), so the
// estimator's control is proved for any results the engine may produce. rst ends a
// program (the real engine clears its pipeline valid bits).
module rls_engine #(
    parameter TABLE_DIR = "rtl/tables/",
    parameter ROM_AW = 8,
    parameter LANES = 1
) (
    input  wire               clk,
    input  wire               rst,
    input  wire               start_i,
    input  wire [ROM_AW-1:0]  entry_i,
    input  wire signed [15:0] x1_i,
    input  wire signed [15:0] x2_i,
    input  wire [4:0]         lambda_k_i,
    input  wire               freeze_i,
    input  wire [15:0]        kappa_i,
    input  wire signed [2:0]  dg_i,
    input  wire               axis_i,      // (AXES = 1: unused)
    output reg                busy_o,
    output wire               done_o,
    output wire               valid_o,
    output wire [16*7-1:0]    out_o,
    output reg                sat_o
);
    (* anyseq *) wire f_end;
    (* anyseq *) wire f_valid;
    (* anyseq *) wire f_sat;
    (* anyseq *) wire [16*7-1:0] f_out;
    reg [1:0] age = 2'd0;                  // edges since the start, saturating at 3
    assign done_o  = busy_o && (age == 2'd3) && f_end;
    assign valid_o = f_valid;
    assign out_o   = f_out;
    always @(posedge clk) begin
        if (busy_o && age != 2'd3)
            age <= age + 1'b1;
        if (start_i) begin
            busy_o <= 1'b1;
            age <= 2'd1;
        end else if (done_o) begin
            busy_o <= 1'b0;
        end
        sat_o <= sat_o | f_sat;
        if (rst) begin
            busy_o <= 1'b0;
            sat_o <= 1'b0;
        end
    end
    initial begin
        busy_o = 1'b0; sat_o = 1'b0;
    end
    wire unused = &{1'b0, TABLE_DIR != 0, LANES, axis_i, entry_i, x1_i, x2_i, lambda_k_i, freeze_i,
                   kappa_i, dg_i, 1'b0};
endmodule
`resetall
