`timescale 1ns / 1ps
`default_nettype none
// tb_axil_core: test bench top of cocotb_tests/test_axil_regs.py (axil_core): axil_regs
// (ADDR_TOP the core's top word, as in rtl/finequad_system.v) in front of finequad_core,
// no samples.
module tb_axil_core #(
    // folder of the core's $readmemh tables
    parameter TABLE_DIR = "rtl/tables/"
) (
    input  wire        clk,
    input  wire        rst,
    input  wire [15:0] s_axil_awaddr,
    input  wire [2:0]  s_axil_awprot,
    input  wire        s_axil_awvalid,
    output wire        s_axil_awready,
    input  wire [31:0] s_axil_wdata,
    input  wire [3:0]  s_axil_wstrb,
    input  wire        s_axil_wvalid,
    output wire        s_axil_wready,
    output wire [1:0]  s_axil_bresp,
    output wire        s_axil_bvalid,
    input  wire        s_axil_bready,
    input  wire [15:0] s_axil_araddr,
    input  wire [2:0]  s_axil_arprot,
    input  wire        s_axil_arvalid,
    output wire        s_axil_arready,
    output wire [31:0] s_axil_rdata,
    output wire [1:0]  s_axil_rresp,
    output wire        s_axil_rvalid,
    input  wire        s_axil_rready
);
    `include "finequad_regs.vh"
    wire        reg_we, reg_re;
    wire [5:0]  reg_addr;
    wire [31:0] reg_wdata, reg_rdata;
    wire        reg_err;
    axil_regs #(.ADDR_W(16), .ADDR_TOP(FQ_ADDR_TOP)) u_regs (
        .clk(clk), .rst(rst),
        .s_axil_awaddr(s_axil_awaddr), .s_axil_awprot(s_axil_awprot),
        .s_axil_awvalid(s_axil_awvalid), .s_axil_awready(s_axil_awready),
        .s_axil_wdata(s_axil_wdata), .s_axil_wstrb(s_axil_wstrb),
        .s_axil_wvalid(s_axil_wvalid), .s_axil_wready(s_axil_wready),
        .s_axil_bresp(s_axil_bresp), .s_axil_bvalid(s_axil_bvalid),
        .s_axil_bready(s_axil_bready),
        .s_axil_araddr(s_axil_araddr), .s_axil_arprot(s_axil_arprot),
        .s_axil_arvalid(s_axil_arvalid), .s_axil_arready(s_axil_arready),
        .s_axil_rdata(s_axil_rdata), .s_axil_rresp(s_axil_rresp),
        .s_axil_rvalid(s_axil_rvalid), .s_axil_rready(s_axil_rready),
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
    wire unused = &{1'b0, m_valid, m_count, m_fault, m_a, m_b, eng_cmd,
                    m_z, m_ref_count, m_homed, m_pos_valid, 1'b0};
endmodule
`resetall
