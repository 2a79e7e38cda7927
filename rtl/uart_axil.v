`timescale 1ns / 1ps
`default_nettype none
// uart_axil: UART (8N1) to AXI4-Lite master bridge, so that a PC can read and write the
// registers (host side: scripts/fqhost.py, class FqProtocol).
//
// Byte protocol (all multi-byte fields big-endian; CHK makes the 8-bit sum of all bytes
// of a frame, CHK included, zero: CHK = -(sum of the other bytes) mod 256):
//   read:   host -> 'R' (0x52) A1 A0 CHK                  (4 bytes)
//           FPGA -> ST D3 D2 D1 D0 CHK                     (6 bytes)
//   write:  host -> 'W' (0x57) A1 A0 D3 D2 D1 D0 CHK       (8 bytes)
//           FPGA -> ST CHK                                 (2 bytes)
//   A1 A0: 16-bit AXI byte address (finequad_core register k at 4 k); D3..D0: 32-bit word.
//   ST (status): 0x50 | {chk_err, RESP[1:0]}: 0x50 OKAY, 0x52 SLVERR, 0x53 DECERR (the
//   AXI response), 0x54 checksum error (the frame is not executed; a read returns D = 0).
//   A read answered SLVERR returns the bus's RDATA (0 from rtl/axil_regs.v).
// Robustness:
//   - bytes that are not 'R' or 'W' where a command is expected are ignored;
//   - a frame is abandoned, without a bus transaction or an answer, when more than
//     TIMEOUT clocks pass between two of its bytes, or on a framing error or a break
//     (line held low) at any time: a host that lost sync waits longer than TIMEOUT (or
//     sends a break) and the bridge is idle again;
//   - the checksum keeps a garbled frame from reaching the bus (a wrong CHK answers 0x54);
//   - one command at a time: bytes that arrive while a command executes or its answer is
//     sent are ignored (the host waits for the answer before the next command).
// The bridge waits for the bus's response without a time limit (AXI slaves must answer).
//
// AXI4-Lite master: one transaction at a time; AWVALID and WVALID rise together (WSTRB
// 4'hF, AWPROT/ARPROT 0) and each drops on its own handshake; BREADY/RREADY are high
// while the response is awaited. Valids are registers and never depend on the readies.
// Latency: the bus transaction starts on the edge after the frame's last byte is
// received (uart_rx: mid stop bit); the answer's first start bit follows the response
// handshake by 2 clocks.
// rst: synchronous, active high (idle, bus valids dropped: reset the slave with it).
module uart_axil #(
    // clocks per UART bit (f_clk / baud)
    parameter DIV = 286,
    // clocks allowed between two bytes of a frame before it is abandoned (< 2^20)
    parameter [19:0] TIMEOUT = 20'd262143
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        rxd_i,              // from the host (asynchronous)
    output wire        txd_o,              // to the host
    // AXI4-Lite master
    output reg  [15:0] m_axil_awaddr,
    output wire [2:0]  m_axil_awprot,
    output reg         m_axil_awvalid,
    input  wire        m_axil_awready,
    output reg  [31:0] m_axil_wdata,
    output wire [3:0]  m_axil_wstrb,
    output reg         m_axil_wvalid,
    input  wire        m_axil_wready,
    input  wire [1:0]  m_axil_bresp,
    input  wire        m_axil_bvalid,
    output reg         m_axil_bready,
    output wire [15:0] m_axil_araddr,
    output wire [2:0]  m_axil_arprot,
    output reg         m_axil_arvalid,
    input  wire        m_axil_arready,
    input  wire [31:0] m_axil_rdata,
    input  wire [1:0]  m_axil_rresp,
    input  wire        m_axil_rvalid,
    output reg         m_axil_rready,
    // diagnostics (one-clock pulses)
    output wire        frame_err_o,        // UART framing error or break
    output reg         drop_o              // a frame abandoned (timeout or framing error)
);
    localparam [7:0] CMD_R = 8'h52;
    localparam [7:0] CMD_W = 8'h57;

    localparam [2:0] S_CMD  = 3'd0;       // waiting for a command byte
    localparam [2:0] S_ARGS = 3'd1;       // receiving address, data, CHK
    localparam [2:0] S_BUS  = 3'd2;       // AXI transaction
    localparam [2:0] S_ST   = 3'd3;       // sending the status byte
    localparam [2:0] S_DATA = 3'd4;       // sending D3..D0 (reads)
    localparam [2:0] S_CHK  = 3'd5;       // sending CHK

    wire [7:0] rx_data;
    wire       rx_valid, rx_overrun;
    uart_rx #(.DIV(DIV)) u_rx (
        .clk(clk), .rst(rst), .rxd_i(rxd_i),
        .m_axis_tdata(rx_data), .m_axis_tvalid(rx_valid), .m_axis_tready(1'b1),
        .frame_err_o(frame_err_o), .overrun_o(rx_overrun)
    );
    reg  [7:0] tx_data_q = 8'd0;
    reg        tx_valid_q = 1'b0;
    wire       tx_ready;
    uart_tx #(.DIV(DIV)) u_tx (
        .clk(clk), .rst(rst), .s_axis_tdata(tx_data_q), .s_axis_tvalid(tx_valid_q),
        .s_axis_tready(tx_ready), .txd_o(txd_o)
    );

    reg [2:0]  state_q = S_CMD;
    reg        is_wr_q = 1'b0;
    reg [2:0]  left_q = 3'd0;             // bytes still to receive / data bytes to send
    reg [7:0]  sum_q = 8'd0;              // running 8-bit sum of the frame
    reg [19:0] idle_q = 20'd0;            // clocks since the last byte of the frame
    reg [7:0]  st_q = 8'h50;
    // A1 A0 shift into m_axil_awaddr (also the read address), D3..D0 into m_axil_wdata,
    // which then holds a read's RDATA while it is sent

    initial begin
        m_axil_awaddr = 16'd0;
        m_axil_awvalid = 1'b0;
        m_axil_wdata = 32'd0;
        m_axil_wvalid = 1'b0;
        m_axil_bready = 1'b0;
        m_axil_arvalid = 1'b0;
        m_axil_rready = 1'b0;
        drop_o = 1'b0;
    end
    assign m_axil_awprot = 3'd0;
    assign m_axil_arprot = 3'd0;
    assign m_axil_wstrb = 4'hF;
    assign m_axil_araddr = m_axil_awaddr;

    wire tx_take = tx_valid_q && tx_ready;
    wire [7:0] sum_rx = sum_q + rx_data;

    always @(posedge clk) begin
        drop_o <= 1'b0;
        case (state_q)
            S_CMD: begin
                sum_q <= rx_data;
                idle_q <= 20'd0;
                if (rx_valid && (rx_data == CMD_R || rx_data == CMD_W)) begin
                    is_wr_q <= (rx_data == CMD_W);
                    left_q <= (rx_data == CMD_W) ? 3'd7 : 3'd3;
                    state_q <= S_ARGS;
                end
            end
            S_ARGS: begin
                if (rx_valid) begin
                    idle_q <= 20'd0;
                    sum_q <= sum_rx;
                    left_q <= left_q - 1'b1;
                    // A1 A0 D3 D2 D1 D0 shift in: the address fills m_axil_awaddr first,
                    // then the data bytes m_axil_wdata (reads: two bytes, address only)
                    if ((is_wr_q && left_q >= 3'd6) || (!is_wr_q && left_q >= 3'd2))
                        m_axil_awaddr <= {m_axil_awaddr[7:0], rx_data};
                    else if (left_q != 3'd1)
                        m_axil_wdata <= {m_axil_wdata[23:0], rx_data};
                    if (left_q == 3'd1) begin        // CHK: the frame is complete
                        if (sum_rx != 8'd0) begin
                            st_q <= 8'h54;
                            m_axil_wdata <= 32'd0;
                            state_q <= S_ST;
                        end else begin
                            state_q <= S_BUS;
                            m_axil_awvalid <= is_wr_q;
                            m_axil_wvalid <= is_wr_q;
                            m_axil_bready <= is_wr_q;
                            m_axil_arvalid <= !is_wr_q;
                            m_axil_rready <= !is_wr_q;
                        end
                    end
                end else if (idle_q == TIMEOUT) begin
                    state_q <= S_CMD;
                    drop_o <= 1'b1;
                end else begin
                    idle_q <= idle_q + 1'b1;
                end
                if (frame_err_o) begin
                    state_q <= S_CMD;
                    drop_o <= 1'b1;
                end
            end
            S_BUS: begin
                if (m_axil_awready)
                    m_axil_awvalid <= 1'b0;
                if (m_axil_wready)
                    m_axil_wvalid <= 1'b0;
                if (m_axil_arready)
                    m_axil_arvalid <= 1'b0;
                if (m_axil_bready && m_axil_bvalid) begin
                    m_axil_bready <= 1'b0;
                    st_q <= {6'b010100, m_axil_bresp};
                    state_q <= S_ST;
                end
                if (m_axil_rready && m_axil_rvalid) begin
                    m_axil_rready <= 1'b0;
                    st_q <= {6'b010100, m_axil_rresp};
                    m_axil_wdata <= m_axil_rdata;
                    state_q <= S_ST;
                end
            end
            S_ST: begin
                if (!tx_valid_q) begin
                    tx_valid_q <= 1'b1;
                    tx_data_q <= st_q;
                    sum_q <= st_q;
                    left_q <= 3'd4;
                end else if (tx_take) begin
                    tx_valid_q <= 1'b0;
                    state_q <= is_wr_q ? S_CHK : S_DATA;
                end
            end
            S_DATA: begin
                if (!tx_valid_q) begin
                    tx_valid_q <= 1'b1;
                    tx_data_q <= m_axil_wdata[31:24];
                    sum_q <= sum_q + m_axil_wdata[31:24];
                    m_axil_wdata <= {m_axil_wdata[23:0], 8'd0};
                    left_q <= left_q - 1'b1;
                end else if (tx_take) begin
                    tx_valid_q <= 1'b0;
                    if (left_q == 3'd0)
                        state_q <= S_CHK;
                end
            end
            default: begin                            // S_CHK
                if (!tx_valid_q) begin
                    tx_valid_q <= 1'b1;
                    tx_data_q <= 8'd0 - sum_q;
                end else if (tx_take) begin
                    tx_valid_q <= 1'b0;
                    state_q <= S_CMD;
                end
            end
        endcase
        if (rst) begin
            state_q <= S_CMD;
            tx_valid_q <= 1'b0;
            m_axil_awvalid <= 1'b0;
            m_axil_wvalid <= 1'b0;
            m_axil_bready <= 1'b0;
            m_axil_arvalid <= 1'b0;
            m_axil_rready <= 1'b0;
            drop_o <= 1'b0;
        end
    end

    wire unused = &{1'b0, rx_overrun, 1'b0};
endmodule
`resetall
