`timescale 1ns / 1ps
`default_nettype none
// uart_axil: UART (8N1) to AXI4-Lite master bridge, so that a PC can read and write the
// registers (host side: scripts/fqhost.py, class FqProtocol).
//
// Frames (HDLC-like framing, RFC 1662's byte stuffing): FLAG (0x7E) opens and closes every
// frame; inside it a 0x7E or 0x7D byte is sent as 0x7D followed by the byte XOR 0x20.
// The content (multi-byte fields big-endian):
//   read:   host -> 'R' (0x52) A1 A0 C1 C0                 (5 bytes)
//           FPGA -> ST E1 E0 D3 D2 D1 D0 C1 C0             (9 bytes)
//   write:  host -> 'W' (0x57) A1 A0 D3 D2 D1 D0 C1 C0     (9 bytes)
//           FPGA -> ST E1 E0 C1 C0                         (5 bytes)
//   A1 A0: 16-bit AXI byte address (finequad_core register k at 4 k); D3..D0: 32-bit word;
//   C1 C0: CRC-16/CCITT-FALSE (polynomial 0x1021, initial 0xFFFF, not reflected, no final
//   XOR) of the frame's bytes before it; E1 E0: the request's C1 C0 as received (the host
//   matches an answer to its request by it). ST (status): 0x50 OKAY, 0x52 SLVERR, 0x53
//   DECERR (the AXI response; SLVERR also for a write the core refuses), 0x54 CRC error
//   (the request had a command's length but a wrong CRC: not executed; a read returns
//   D = 0). A read answered SLVERR returns the bus's RDATA (0 from rtl/axil_regs.v).
// Robustness (no frame that was not sent whole can be executed):
//   - a frame is executed only on its closing FLAG, with a known command, its length and
//     a CRC of residue 0; every other frame is dropped without an answer (drop_o): one
//     of an unknown command or the wrong length (a frame cut short by a killed client is
//     closed by the next frame's opening FLAG, so it cannot be joined to it), 0x7D
//     followed by FLAG (an abort), a framing error or a break (line held low) at any
//     point, or more than TIMEOUT clocks between two bytes of a frame;
//   - bytes outside a frame are ignored, and so are bytes that arrive while a command
//     executes or its answer is sent (the host waits for the answer); after an answer the
//     bridge waits for a FLAG;
//   - a corrupted frame passes the CRC only by chance: every error burst of up to 16 bits
//     and every odd number of bit errors is detected (the polynomial has the factor
//     x + 1), any other corruption with a probability of 2^-16 of passing, and then only
//     if the frame still has a command's length.
// The bridge waits for the bus's response without a time limit (AXI slaves must answer).
//
// AXI4-Lite master: one transaction at a time; AWVALID and WVALID rise together (WSTRB
// 4'hF, AWPROT/ARPROT 0) and each drops on its own handshake; BREADY/RREADY are high
// while the response is awaited. Valids are registers and never depend on the readies.
// Latency: the bus transaction starts on the edge after the closing FLAG is received
// (uart_rx: mid stop bit); the answer's opening FLAG follows the response handshake by 2
// clocks.
// rst: synchronous, active high (idle, bus valids dropped: reset the slave with it).
module uart_axil #(
    // clocks per UART bit (f_clk / baud)
    parameter DIV = 286,
    // clocks allowed between two bytes of a frame before it is dropped (< 2^20)
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
    output reg         drop_o              // a frame dropped (see above)
);
    localparam [7:0] CMD_R = 8'h52;
    localparam [7:0] CMD_W = 8'h57;
    localparam [7:0] FLAG  = 8'h7E;
    localparam [7:0] ESC   = 8'h7D;
    localparam [7:0] ST_CRC = 8'h54;

    localparam [1:0] S_HUNT = 2'd0;       // waiting for a FLAG
    localparam [1:0] S_RX   = 2'd1;       // receiving a frame (opened by a FLAG)
    localparam [1:0] S_BUS  = 2'd2;       // AXI transaction
    localparam [1:0] S_TX   = 2'd3;       // sending the answer

    // CRC-16/CCITT-FALSE of one more byte (MSB first)
    function automatic [15:0] crc_step(input [15:0] c, input [7:0] b);
        integer i;
        reg [15:0] r;
        begin
            r = c ^ {b, 8'd0};
            for (i = 0; i < 8; i = i + 1)
                r = r[15] ? ({r[14:0], 1'b0} ^ 16'h1021) : {r[14:0], 1'b0};
            crc_step = r;
        end
    endfunction

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

    reg [1:0]  state_q = S_HUNT;
    // receiver: the frame's first byte (the command), the last 8 bytes after it
    reg [7:0]  cmd_q = 8'd0;
    reg [63:0] sh_q = 64'd0;
    reg [3:0]  n_q = 4'd0;                // bytes of the frame so far (saturates at 10)
    reg        esc_q = 1'b0;              // the last byte was 0x7D
    reg [15:0] crc_q = 16'hFFFF;          // CRC over the frame's bytes so far
    reg [19:0] idle_q = 20'd0;            // clocks since the frame's last byte
    // the request being served and its answer
    reg        is_wr_q = 1'b0;
    reg [15:0] echo_q = 16'd0;            // the request's C1 C0
    reg [7:0]  st_q = 8'h50;
    // transmitter: byte k of the answer (0: the opening FLAG, then ST E1 E0 [D3..D0]
    // C1 C0, then the closing FLAG), its escape pending
    reg [3:0]  k_q = 4'd0;
    reg        tx_esc_q = 1'b0;           // 0x7D sent, the byte XOR 0x20 is next
    reg [15:0] tcrc_q = 16'hFFFF;

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

    // ---- the received byte, unescaped --------------------------------------------------------
    wire [7:0] rx_byte = esc_q ? (rx_data ^ 8'h20) : rx_data;
    // the frame closed by a FLAG: a command with its length
    wire is_wr_next = (cmd_q == CMD_W);
    wire len_ok = (cmd_q == CMD_R && n_q == 4'd5) || (cmd_q == CMD_W && n_q == 4'd9);

    // ---- the answer's bytes ----------------------------------------------------------------------
    wire [3:0] n_ans = is_wr_q ? 4'd5 : 4'd9;       // content bytes: ST E1 E0 [D] C1 C0
    reg  [7:0] ans_byte;                             // content byte k - 1
    always @* begin
        case (k_q)
            4'd1: ans_byte = st_q;
            4'd2: ans_byte = echo_q[15:8];
            4'd3: ans_byte = echo_q[7:0];
            default: ans_byte = 8'd0;
        endcase
        if (k_q >= 4'd4 && k_q < n_ans - 4'd1)     // D3..D0 (reads)
            ans_byte = m_axil_wdata[31:24];
        else if (k_q == n_ans - 4'd1)
            ans_byte = tcrc_q[15:8];
        else if (k_q == n_ans)
            ans_byte = tcrc_q[7:0];
    end
    wire tx_take = tx_valid_q && tx_ready;
    wire special = (ans_byte == FLAG) || (ans_byte == ESC);

    always @(posedge clk) begin
        drop_o <= 1'b0;
        case (state_q)
            S_HUNT: begin
                if (rx_valid && rx_data == FLAG) begin
                    state_q <= S_RX;
                    n_q <= 4'd0;
                    esc_q <= 1'b0;
                    crc_q <= 16'hFFFF;
                    idle_q <= 20'd0;
                end
            end
            S_RX: begin
                k_q <= 4'd0;                         // the answer starts afresh
                tx_esc_q <= 1'b0;
                tcrc_q <= 16'hFFFF;
                if (rx_valid) begin
                    idle_q <= 20'd0;
                    if (rx_data == FLAG) begin
                        // the frame closes (and the FLAG opens the next one)
                        n_q <= 4'd0;
                        esc_q <= 1'b0;
                        crc_q <= 16'hFFFF;
                        if (n_q != 4'd0 && !esc_q && len_ok) begin
                            is_wr_q <= (cmd_q == CMD_W);
                            echo_q <= sh_q[15:0];
                            if (is_wr_next) begin
                                m_axil_awaddr <= sh_q[63:48];
                                m_axil_wdata <= sh_q[47:16];
                            end else begin
                                m_axil_awaddr <= sh_q[31:16];
                            end
                            if (crc_q == 16'd0) begin
                                state_q <= S_BUS;
                                m_axil_awvalid <= is_wr_next;
                                m_axil_wvalid <= is_wr_next;
                                m_axil_bready <= is_wr_next;
                                m_axil_arvalid <= !is_wr_next;
                                m_axil_rready <= !is_wr_next;
                            end else begin
                                st_q <= ST_CRC;
                                m_axil_wdata <= 32'd0;
                                state_q <= S_TX;
                            end
                        end else if (n_q != 4'd0 || esc_q) begin
                            drop_o <= 1'b1;
                        end
                    end else if (rx_data == ESC && !esc_q) begin
                        esc_q <= 1'b1;
                    end else begin
                        esc_q <= 1'b0;
                        if (n_q == 4'd0)
                            cmd_q <= rx_byte;
                        else
                            sh_q <= {sh_q[55:0], rx_byte};
                        if (n_q != 4'd10)
                            n_q <= n_q + 1'b1;
                        crc_q <= crc_step(crc_q, rx_byte);
                    end
                end else if (n_q != 4'd0 || esc_q) begin
                    if (idle_q == TIMEOUT) begin
                        state_q <= S_HUNT;
                        drop_o <= 1'b1;
                    end else begin
                        idle_q <= idle_q + 1'b1;
                    end
                end
                if (frame_err_o) begin
                    state_q <= S_HUNT;
                    drop_o <= (n_q != 4'd0) || esc_q;
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
                    state_q <= S_TX;
                end
                if (m_axil_rready && m_axil_rvalid) begin
                    m_axil_rready <= 1'b0;
                    st_q <= {6'b010100, m_axil_rresp};
                    m_axil_wdata <= m_axil_rdata;
                    state_q <= S_TX;
                end
            end
            default: begin                            // S_TX
                if (!tx_valid_q) begin
                    tx_valid_q <= 1'b1;
                    if (k_q == 4'd0 || k_q > n_ans)
                        tx_data_q <= FLAG;
                    else if (tx_esc_q)
                        tx_data_q <= ans_byte ^ 8'h20;
                    else if (special)
                        tx_data_q <= ESC;
                    else
                        tx_data_q <= ans_byte;
                end else if (tx_take) begin
                    tx_valid_q <= 1'b0;
                    if (k_q != 4'd0 && k_q <= n_ans && special && !tx_esc_q) begin
                        tx_esc_q <= 1'b1;             // the escaped byte follows
                    end else begin
                        tx_esc_q <= 1'b0;
                        if (k_q > n_ans) begin
                            state_q <= S_HUNT;        // the closing FLAG went out
                        end else begin
                            k_q <= k_q + 1'b1;
                            if (k_q != 4'd0 && k_q < n_ans - 4'd1)
                                tcrc_q <= crc_step(tcrc_q, ans_byte);
                            if (k_q >= 4'd4 && k_q < n_ans - 4'd1)
                                m_axil_wdata <= {m_axil_wdata[23:0], 8'd0};
                        end
                    end
                end
            end
        endcase
        if (rst) begin
            state_q <= S_HUNT;
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
