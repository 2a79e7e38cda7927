`timescale 1ns / 1ps
`default_nettype none
// uart_tx: UART transmitter, 8N1 (start bit 0, 8 data bits LSB first, stop bit 1), line
// idle high. DIV clocks per bit (baud = f_clk / DIV).
//
// Input (AXI stream): a byte is taken on an edge with s_axis_tvalid && s_axis_tready;
// s_axis_tready is high while the transmitter is idle (it does not depend on tvalid).
// txd_o is a register: the start bit begins after the taking edge and each bit lasts
// DIV clocks; tready returns high on the edge that ends the stop bit's DIV clocks, so
// back-to-back bytes take 10 DIV + 1 clocks each (one clock of idle line between them).
// rst: synchronous, active high (line idle, a byte in progress abandoned).
module uart_tx #(
    // clocks per bit (f_clk / baud), 2 .. 65535
    parameter DIV = 286
) (
    input  wire       clk,
    input  wire       rst,
    input  wire [7:0] s_axis_tdata,
    input  wire       s_axis_tvalid,
    output wire       s_axis_tready,
    output reg        txd_o            // serial output, idle high
);
    localparam [15:0] FULL = DIV - 1;

    reg        busy_q = 1'b0;
    reg [15:0] cnt_q = 16'd0;
    reg [3:0]  bit_q = 4'd0;                  // bits still to send after the current one
    reg [8:0]  shift_q = 9'h1ff;              // {stop, data} still to send

    initial txd_o = 1'b1;
    assign s_axis_tready = !busy_q;

    always @(posedge clk) begin
        if (!busy_q) begin
            if (s_axis_tvalid) begin
                busy_q <= 1'b1;
                txd_o <= 1'b0;                    // start bit
                shift_q <= {1'b1, s_axis_tdata};
                bit_q <= 4'd9;
                cnt_q <= FULL;
            end
        end else if (cnt_q != 16'd0) begin
            cnt_q <= cnt_q - 1'b1;
        end else if (bit_q != 4'd0) begin
            txd_o <= shift_q[0];
            shift_q <= {1'b1, shift_q[8:1]};
            bit_q <= bit_q - 1'b1;
            cnt_q <= FULL;
        end else begin
            busy_q <= 1'b0;                       // stop bit done
        end
        if (rst) begin
            busy_q <= 1'b0;
            txd_o <= 1'b1;
        end
    end
endmodule
`resetall
