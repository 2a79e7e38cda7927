`timescale 1ns / 1ps
`default_nettype none
// top_report_multi: finequad_multi (AXES axes, one shared RLS engine) with every port
// kept, for the multi-axis resource report (scripts/report_multi.py, `make
// report-multi`), built as rtl/boards/top_report.v builds the single core: every input
// from a register of a serial scan chain (one pin), every output, four bits per LUT, into
// a register whose XOR reduction drives one pin, so synthesis removes nothing and every
// path starts and ends at a flip-flop. Not a design to load.
module top_report_multi #(
    // forwarded to finequad_multi
    parameter AXES = 2,
    parameter TDM_W = 64,
    parameter [0:0] OPT_NTH_DSP = 1'b1,
    parameter [0:0] OPT_HARMONIC = 1'b1,
    parameter [0:0] OPT_DISTRAM = 1'b0,
    parameter [0:0] OPT_PHASE_4K = 1'b0,
    parameter [0:0] OPT_ECP5_MULT = 1'b0,
    parameter [0:0] OPT_PULSE_ADDR = 1'b0,
    parameter [0:0] OPT_TUNABLE = 1'b1,
    parameter [0:0] OPT_MONITOR = 1'b1,
    parameter [0:0] OPT_JUMP = 1'b1,
    // distance-coded reference marks (rtl/finequad_core.v OPT_DCODE)
    parameter [0:0] OPT_DCODE = 1'b1,
    parameter ENGINE_LANES = 1
) (
    input  wire clk,
    input  wire sdi,        // scan chain in
    output reg  sdo = 1'b0  // XOR of the registered outputs
);
    localparam AXW = (AXES > 1) ? $clog2(AXES) : 1;
    // scan chain: {s_ref, reg_wdata, reg_addr, reg_axis, reg_re, reg_we, s_u2, s_u1, s_valid,
    // rst}
    localparam IN_W = 1 + AXES * (1 + 16 + 16) + 2 + AXW + 6 + 32 + AXES;
    reg [IN_W-1:0] chain = 0;
    always @(posedge clk)
        chain <= {chain[IN_W-2:0], sdi};
    wire [31:0] reg_wdata;
    wire [5:0]  reg_addr;
    wire [AXW-1:0] reg_axis;
    wire        reg_re, reg_we, rst;
    wire [AXES-1:0] s_valid, s_ref;
    wire [16*AXES-1:0] s_u1, s_u2;
    assign {s_ref, reg_wdata, reg_addr, reg_axis, reg_re, reg_we, s_u2, s_u1, s_valid, rst} =
        chain;

    wire [31:0] reg_rdata;
    wire        reg_err;
    wire [32*AXES-1:0] m_count;
    wire [11*AXES-1:0] m_fault;
    wire [AXES-1:0] m_valid, m_a, m_b, m_z, m_homed, m_pos_valid;
    finequad_multi #(.AXES(AXES), .TDM_W(TDM_W), .OPT_NTH_DSP(OPT_NTH_DSP),
                     .OPT_HARMONIC(OPT_HARMONIC), .OPT_TUNABLE(OPT_TUNABLE),
                     .OPT_DISTRAM(OPT_DISTRAM), .OPT_PHASE_4K(OPT_PHASE_4K),
                     .OPT_ECP5_MULT(OPT_ECP5_MULT), .OPT_PULSE_ADDR(OPT_PULSE_ADDR),
                     .OPT_MONITOR(OPT_MONITOR),
                     .OPT_JUMP(OPT_JUMP), .OPT_DCODE(OPT_DCODE), .ENGINE_LANES(ENGINE_LANES)) u_multi (
        .clk(clk), .rst(rst), .s_valid(s_valid), .s_u1(s_u1), .s_u2(s_u2), .s_ref(s_ref),
        .reg_we(reg_we), .reg_re(reg_re), .reg_axis(reg_axis), .reg_addr(reg_addr),
        .reg_wdata(reg_wdata), .reg_rdata(reg_rdata), .reg_err(reg_err),
        .m_valid(m_valid), .m_count(m_count), .m_fault(m_fault), .m_a(m_a), .m_b(m_b),
        .m_z(m_z), .m_homed(m_homed), .m_pos_valid(m_pos_valid)
    );

    // every output bit into a 4-input XOR register, then one XOR tree into sdo
    localparam OUT_W = 33 + AXES * (32 + 11 + 3 + 3);
    localparam OUT_G = (OUT_W + 3) / 4;
    wire [4*OUT_G-1:0] outs;
    assign outs[OUT_W-1:0] = {reg_err, reg_rdata, m_count, m_fault, m_valid, m_a, m_b, m_z,
                              m_homed, m_pos_valid};
    generate
        if (4 * OUT_G > OUT_W) begin : g_pad
            assign outs[4*OUT_G-1:OUT_W] = 0;
        end
    endgenerate
    reg [OUT_G-1:0] xq = 0;
    integer g;
    always @(posedge clk) begin
        for (g = 0; g < OUT_G; g = g + 1)
            xq[g] <= ^outs[4*g +: 4];
        sdo <= ^xq;
    end
endmodule
`resetall
