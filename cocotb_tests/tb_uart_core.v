`timescale 1ns / 1ps
`default_nettype none
// tb_uart_core: test bench top of cocotb_tests/test_uart_axil.py (uart_core): the UART
// bridge (uart_axil) and axil_regs (ADDR_TOP the core's top word, as in
// rtl/finequad_system.v) in front of the real finequad_core, no samples.
module tb_uart_core #(
    // folder of the core's $readmemh tables
    parameter TABLE_DIR = "rtl/tables/",
    // clocks per UART bit
    parameter DIV = 16,
    // clocks between two bytes of a frame before it is dropped
    parameter [19:0] TIMEOUT = 20'd2000
) (
    input  wire clk,
    input  wire rst,
    input  wire rxd_i,
    output wire txd_o,
    output wire drop_o
);
    `include "finequad_regs.vh"
    wire [15:0] awaddr, araddr;
    wire [2:0]  awprot, arprot;
    wire        awvalid, awready, wvalid, wready, bvalid, bready;
    wire        arvalid, arready, rvalid, rready;
    wire [31:0] wdata, rdata;
    wire [3:0]  wstrb;
    wire [1:0]  bresp, rresp;
    wire        frame_err;
    uart_axil #(.DIV(DIV), .TIMEOUT(TIMEOUT)) u_bridge (
        .clk(clk), .rst(rst), .rxd_i(rxd_i), .txd_o(txd_o),
        .m_axil_awaddr(awaddr), .m_axil_awprot(awprot), .m_axil_awvalid(awvalid),
        .m_axil_awready(awready), .m_axil_wdata(wdata), .m_axil_wstrb(wstrb),
        .m_axil_wvalid(wvalid), .m_axil_wready(wready), .m_axil_bresp(bresp),
        .m_axil_bvalid(bvalid), .m_axil_bready(bready), .m_axil_araddr(araddr),
        .m_axil_arprot(arprot), .m_axil_arvalid(arvalid), .m_axil_arready(arready),
        .m_axil_rdata(rdata), .m_axil_rresp(rresp), .m_axil_rvalid(rvalid),
        .m_axil_rready(rready), .frame_err_o(frame_err), .drop_o(drop_o)
    );
    wire        reg_we, reg_re, reg_err;
    wire [5:0]  reg_addr;
    wire [31:0] reg_wdata, reg_rdata;
    axil_regs #(.ADDR_W(16), .ADDR_TOP(FQ_ADDR_TOP)) u_regs (
        .clk(clk), .rst(rst),
        .s_axil_awaddr(awaddr), .s_axil_awprot(awprot), .s_axil_awvalid(awvalid),
        .s_axil_awready(awready), .s_axil_wdata(wdata), .s_axil_wstrb(wstrb),
        .s_axil_wvalid(wvalid), .s_axil_wready(wready), .s_axil_bresp(bresp),
        .s_axil_bvalid(bvalid), .s_axil_bready(bready), .s_axil_araddr(araddr),
        .s_axil_arprot(arprot), .s_axil_arvalid(arvalid), .s_axil_arready(arready),
        .s_axil_rdata(rdata), .s_axil_rresp(rresp), .s_axil_rvalid(rvalid),
        .s_axil_rready(rready),
        .reg_we(reg_we), .reg_re(reg_re), .reg_addr(reg_addr), .reg_wdata(reg_wdata),
        .reg_rdata(reg_rdata), .reg_err(reg_err)
    );
    wire        m_valid, m_a, m_b, m_z, m_homed, m_pos_valid;
    wire [31:0] m_count, m_ref_count;
    wire [10:0] m_fault;
    wire [65:0] eng_cmd;                 // 0: the core's engine is inside
    finequad_core #(.TABLE_DIR(TABLE_DIR), .ADC_W(12)) u_core (
        .clk(clk), .rst(rst), .s_valid(1'b0), .s_u1(12'd0), .s_u2(12'd0), .s_ref(1'b0),
        .reg_we(reg_we), .reg_re(reg_re), .reg_addr(reg_addr), .reg_wdata(reg_wdata),
        .reg_rdata(reg_rdata), .reg_err(reg_err),
        .m_valid(m_valid), .m_count(m_count), .m_fault(m_fault), .m_a(m_a), .m_b(m_b),
        .m_z(m_z), .m_ref_count(m_ref_count), .m_homed(m_homed), .m_pos_valid(m_pos_valid),
        .tdm_ok_i(1'b1), .eng_cmd_o(eng_cmd), .eng_rsp_i(115'd0)   // the engine inside
    );
    wire unused = &{1'b0, frame_err, m_valid, m_count, m_fault, m_a, m_b, eng_cmd,
                    m_z, m_ref_count, m_homed, m_pos_valid, 1'b0};
endmodule
`resetall
