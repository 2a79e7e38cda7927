`timescale 1ns / 1ps
`default_nettype none
// top_report: finequad_core with every port kept, for resource and timing reports
// (scripts/report.py, `make report`). A board shell leaves unused outputs unconnected
// and synthesis then removes the logic behind them; here every input comes from a
// register of a serial scan chain (one pin) and every output goes, four bits per LUT,
// into a register whose XOR reduction drives one pin, so nothing of the core can be
// optimised away and every core path starts and ends at a flip-flop (the paths to and
// from the pins are not the core's). Not a design to load: the pins carry no protocol.
//
// Cost of the wrapper itself: IN_W (75) scan flip-flops, OUT_G (29) output registers
// with one 4-input XOR each, and a 29-input XOR tree into sdo (scripts/report.py
// lists it per module as top_report).
module top_report #(
    // forwarded to finequad_core
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
    parameter ENGINE_LANES = 1,
    // 1: reg_rdata is observed (the whole read-back multiplexer is kept); 0: reg_re is
    // tied low and the read-back is removed by synthesis (a reduced variant, for a
    // device the full core does not fit)
    parameter [0:0] OPT_READBACK = 1'b1,
    // 1: the register port is driven from the scan chain; 0: reg_we and reg_re are tied
    // low, so every register keeps its reset value and synthesis folds it into the logic
    // (as a standalone board shell does; a further reduced variant)
    parameter [0:0] OPT_REGPORT = 1'b1
) (
    input  wire clk,
    input  wire sdi,        // scan chain in
    output reg  sdo = 1'b0  // XOR of the registered outputs
);
    // rst, s_valid, s_u1, s_u2, reg_we, reg_re, reg_addr, reg_wdata, s_ref
    localparam IN_W = 1 + 1 + 16 + 16 + 1 + 1 + 6 + 32 + 1;
    reg [IN_W-1:0] chain = 0;
    always @(posedge clk)
        chain <= {chain[IN_W-2:0], sdi};
    wire        rst       = chain[0];
    wire        s_valid   = chain[1];
    wire [15:0] s_u1      = chain[17:2];
    wire [15:0] s_u2      = chain[33:18];
    wire        reg_we    = OPT_REGPORT ? chain[34] : 1'b0;
    wire        reg_re    = (OPT_REGPORT && OPT_READBACK) ? chain[35] : 1'b0;
    wire [5:0]  reg_addr  = chain[41:36];
    wire [31:0] reg_wdata = chain[73:42];
    wire        s_ref     = chain[74];

    wire [31:0] reg_rdata, m_count, m_ref_count;
    wire        reg_err;
    wire [10:0] m_fault;
    wire        m_valid, m_a, m_b, m_z, m_homed, m_pos_valid;
    wire [65:0] eng_cmd;                 // 0: the core's engine is inside
    finequad_core #(.OPT_NTH_DSP(OPT_NTH_DSP), .OPT_HARMONIC(OPT_HARMONIC),
                    .OPT_DISTRAM(OPT_DISTRAM), .OPT_PHASE_4K(OPT_PHASE_4K),
                    .OPT_ECP5_MULT(OPT_ECP5_MULT), .OPT_PULSE_ADDR(OPT_PULSE_ADDR),
                    .OPT_MONITOR(OPT_MONITOR),
                    .OPT_JUMP(OPT_JUMP), .OPT_DCODE(OPT_DCODE),
                    .OPT_TUNABLE(OPT_TUNABLE), .ENGINE_LANES(ENGINE_LANES)) u_core (
        .clk(clk), .rst(rst),
        .s_valid(s_valid), .s_u1(s_u1), .s_u2(s_u2), .s_ref(s_ref),
        .reg_we(reg_we), .reg_re(reg_re), .reg_addr(reg_addr), .reg_wdata(reg_wdata),
        .reg_rdata(reg_rdata), .reg_err(reg_err),
        .m_valid(m_valid), .m_count(m_count), .m_fault(m_fault), .m_a(m_a), .m_b(m_b),
        .m_z(m_z), .m_ref_count(m_ref_count), .m_homed(m_homed), .m_pos_valid(m_pos_valid),
        .tdm_ok_i(1'b1), .eng_cmd_o(eng_cmd), .eng_rsp_i(115'd0)   // the engine inside
    );
    wire unused_eng = &{1'b0, eng_cmd, 1'b0};

    // outputs, four to a register (one LUT4 and its flip-flop), then one XOR tree
    localparam OUT_W = 32 + 32 + 11 + 3 + 1 + 32 + 3;
    localparam OUT_G = (OUT_W + 3) / 4;
    wire [4*OUT_G-1:0] outs = {{(4*OUT_G-OUT_W){1'b0}},
                               reg_err, reg_rdata, m_count, m_fault, m_valid, m_a, m_b,
                               m_ref_count, m_z, m_homed, m_pos_valid};
    reg  [OUT_G-1:0] outs_q = 0;
    integer i;
    always @(posedge clk) begin
        for (i = 0; i < OUT_G; i = i + 1)
            outs_q[i] <= ^outs[4*i +: 4];
        sdo <= ^outs_q;
    end
    wire unused = &{1'b0, chain[35:34], 1'b0};
endmodule
`resetall
