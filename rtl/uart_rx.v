`timescale 1ns / 1ps
`default_nettype none
// uart_rx: UART receiver, 8N1 (one start bit, 8 data bits LSB first, one stop bit), line
// idle high. DIV clocks per bit (baud = f_clk / DIV).
//
// rxd_i is asynchronous: two flip-flops synchronise it (2 clocks of latency). A low level
// starts a frame; it is checked again half a bit later (a shorter glitch is no start
// bit), then each data bit and the stop bit are sampled once, in the middle of the bit
// (DIV clocks apart). The receiver tolerates a baud mismatch of about +-4 % (half a bit
// over 9.5 bits; the sender's and this receiver's errors add up).
//
// Output (AXI-stream style, no back-pressure on the line): m_axis_tdata/m_axis_tvalid
// after the edge that sampled the stop bit (about 9.5 bit times after the start bit's
// falling edge, plus 2 clocks), held until m_axis_tready. A byte that completes while the
// previous one is still held is dropped and overrun_o pulses (one clock).
// frame_err_o pulses (one clock) when the stop bit is 0 (a framing error or a break: the
// line held low); the byte is dropped and the receiver waits for the line to return high
// before it looks for the next start bit, so a break is one event, not a series of bytes.
// rst: synchronous, active high (back to idle, nothing held).
module uart_rx #(
    // clocks per bit (f_clk / baud), 8 .. 65535
    parameter DIV = 286
) (
    input  wire       clk,
    input  wire       rst,
    input  wire       rxd_i,           // serial input, asynchronous
    output reg  [7:0] m_axis_tdata,    // received byte
    output reg        m_axis_tvalid,
    input  wire       m_axis_tready,
    output reg        frame_err_o,     // pulse: stop bit 0 (byte dropped)
    output reg        overrun_o        // pulse: byte dropped, the previous one not taken
);
    localparam [15:0] FULL = DIV - 1;          // clocks from one sample to the next, - 1
    localparam [15:0] HALF = DIV / 2 - 1;      // start edge to the middle of the start bit

    localparam [1:0] S_IDLE = 2'd0;
    localparam [1:0] S_BITS = 2'd1;           // start check, 8 data bits, stop bit
    localparam [1:0] S_HIGH = 2'd2;           // after a framing error: wait for idle

    reg [1:0]  sync_q = 2'b11;
    reg [1:0]  state_q = S_IDLE;
    reg [15:0] cnt_q = 16'd0;
    reg [3:0]  bit_q = 4'd0;                  // 0 start, 1..8 data, 9 stop
    reg [7:0]  shift_q = 8'd0;
    wire       rx = sync_q[1];

    initial begin
        m_axis_tdata = 8'd0;
        m_axis_tvalid = 1'b0;
        frame_err_o = 1'b0;
        overrun_o = 1'b0;
    end

    always @(posedge clk) begin
        sync_q <= {sync_q[0], rxd_i};
        frame_err_o <= 1'b0;
        overrun_o <= 1'b0;
        if (m_axis_tvalid && m_axis_tready)
            m_axis_tvalid <= 1'b0;
        case (state_q)
            S_IDLE: begin
                if (!rx) begin
                    state_q <= S_BITS;
                    cnt_q <= HALF;
                    bit_q <= 4'd0;
                end
            end
            S_BITS: begin
                if (cnt_q != 16'd0) begin
                    cnt_q <= cnt_q - 1'b1;
                end else begin
                    cnt_q <= FULL;
                    bit_q <= bit_q + 1'b1;
                    if (bit_q == 4'd0) begin
                        if (rx)                   // glitch, not a start bit
                            state_q <= S_IDLE;
                    end else if (bit_q != 4'd9) begin
                        shift_q <= {rx, shift_q[7:1]};
                    end else begin
                        if (!rx) begin
                            frame_err_o <= 1'b1;
                            state_q <= S_HIGH;
                        end else begin
                            state_q <= S_IDLE;
                            if (m_axis_tvalid && !m_axis_tready) begin
                                overrun_o <= 1'b1;
                            end else begin
                                m_axis_tdata <= shift_q;
                                m_axis_tvalid <= 1'b1;
                            end
                        end
                    end
                end
            end
            default: begin                        // S_HIGH
                if (rx)
                    state_q <= S_IDLE;
            end
        endcase
        if (rst) begin
            state_q <= S_IDLE;
            m_axis_tvalid <= 1'b0;
            frame_err_o <= 1'b0;
            overrun_o <= 1'b0;
        end
    end
endmodule
`resetall
