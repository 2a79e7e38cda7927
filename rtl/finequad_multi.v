`timescale 1ns / 1ps
`default_nettype none
// finequad_multi: AXES encoder axes, each a finequad_core (fast path, monitor, counter,
// A/B, registers, the estimator's control), sharing one RLS engine (rtl/rls_engine.v:
// microcode ROM, multipliers, seed table; a register file and a sticky saturation flag
// per axis). Bit-true model: each axis is sim/model/finequad_core.py's Core with Config.tdm =
// (AXES, i, TDM_L, TDM_W) on its own samples.
//
//   s_valid[i], s_u1/s_u2, s_ref[i] (axis i)
//     -> finequad_core i -> m_valid[i], m_count, m_fault, m_a/m_b/m_z, m_homed, m_pos_valid
//        | eng_cmd_o      ^ eng_rsp_i (done only for axis own)
//        v                |
//   window counter (wl, wi) -> tdm_ok_i[i] ;  own -> mux -> rls_engine (AXES register files)
//
// Time division: the engines's programs of the axes never overlap, and an axis's results
// depend only on its own samples and the edge number, never on the other axes. Edges are
// counted from power-up or the last rst (edge 0: the first). Axis i may decide a RESET or
// an UPDATE only on an edge e with
//     i TDM_L <= e mod (AXES TDM_L) < i TDM_L + TDM_W          (its window)
// and its EXTRACT follows its UPDATE at once as always. TDM_L = TDM_W + 1 +
// CYCLES[update] + CYCLES[extract] (rtl/tables/rls_cycles.vh for ENGINE_LANES): an UPDATE
// decided on the window's last edge starts one edge later and, with its EXTRACT, ends on
// edge i TDM_L + TDM_L at the latest, the first edge of the next axis's window (a program
// may be decided on the edge the previous one ends, as in one core). So an axis starts at
// most a program (RESET, UPDATE, or both) per window: per-axis updates at most f_clk /
// (AXES TDM_L) per second (ENGINE_LANES = 1, TDM_W = 64: TDM_L = 259 clocks).
// A covariance reset is decided on a sample's arrival (the edge after the strobe), so with
// a reset pending the strobes of an axis must be at most TDM_W clocks apart for one to
// fall in each window (else the reset, and the updates behind it, wait for a strobe that
// does).
// AXES = 1: one finequad_core with its own engine (no windows), exactly rtl/finequad_core.v.
//
// Register port: the core registers (rtl/regs/finequad.rdl) of axis reg_axis; reg_we
// writes on the edge, reg_re reads, reg_rdata holds the value after that edge (the axis
// read last). reg_err: the write is refused (the axis's core refuses it, or reg_axis >=
// AXES: nothing written); reads of reg_axis >= AXES return 0.
// Latency and formats per axis as rtl/finequad_core.v (m_count s(COUNT_W), m_fault 11
// bits, a sample strobed on edge t out after edge t + 8; A/B and Z on t + 10).
// Reference marks per axis (rtl/refmark.v): s_ref[i] is axis i's reference input,
// sampled with its s_valid[i]; m_z[i] its Z pin, m_homed[i] and m_pos_valid[i] its
// REF_STATUS.homed and pos_valid. The count latched at the reference is read as that
// axis's REF_COUNT register (reg_axis), not brought out as a port.
module finequad_multi #(
    parameter TABLE_DIR = "rtl/tables/",
    // axes sharing the RLS engine, 1..8
    parameter AXES = 2,
    // window (edges) in which an axis may start an engine program (>= the longest gap
    // between an axis's strobes, see above)
    parameter TDM_W = 64,
    // ADC word width, 12..16 (every axis)
    parameter ADC_W = 16,
    // sine table word width: 8, 10, 12 or 16
    parameter SIN_W = 10,
    // counter width
    parameter COUNT_W = 32,
    // 1: exact table, 0: the paper's uniform table
    parameter [0:0] TABLE_EXACT = 1'b1,
    // input gain after power-up
    parameter [1:0] G_INIT = 2'd0,
    // 1: n * phase with a DSP block; 0: in logic
    parameter [0:0] OPT_NTH_DSP = 1'b1,
    // 1: adaptive harmonic compensation; 0: none
    parameter [0:0] OPT_HARMONIC = 1'b1,
    // 1: the harmonic table in distributed RAM; 0: block RAM (rtl/finequad_core.v)
    parameter [0:0] OPT_DISTRAM = 1'b0,
    // 1: the exact phase table in 4096 rows per sign (rtl/finequad_core.v)
    parameter [0:0] OPT_PHASE_4K = 1'b0,
    // 1: the ratio multiply's operand registers and the n-th order product's register in
    // ECP5 DSP blocks (rtl/finequad_core.v)
    parameter [0:0] OPT_ECP5_MULT = 1'b0,
    // 1: Eq. 12 on the sine table's address side (rtl/finequad_core.v)
    parameter [0:0] OPT_PULSE_ADDR = 1'b0,
    // 1: every setting is a register; 0: the tuning settings keep their reset values
    parameter [0:0] OPT_TUNABLE = 1'b1,
    // 1: the signal monitor's fault checks, the jump detector; 0: none (rtl/finequad_core.v)
    parameter [0:0] OPT_MONITOR = 1'b1,
    parameter [0:0] OPT_JUMP = 1'b1,
    // distance-coded reference marks (rtl/finequad_core.v OPT_DCODE)
    parameter [0:0] OPT_DCODE = 1'b1,
    // lanes of the shared RLS engine, 1 or 2
    parameter ENGINE_LANES = 1
) (
    input  wire                         clk,
    input  wire                         rst,
    // sample streams: axis i strobes s_valid[i] with s_u1/s_u2[ADC_W i +: ADC_W]
    // (sADC_W, two's complement, MSB-aligned to s1.15 internally)
    input  wire [AXES-1:0]              s_valid,
    input  wire [AXES*ADC_W-1:0]        s_u1,
    input  wire [AXES*ADC_W-1:0]        s_u2,
    // reference input of axis i (a comparator's output, sampled with s_valid[i])
    input  wire [AXES-1:0]              s_ref,
    // register port of axis reg_axis
    input  wire                         reg_we,
    input  wire                         reg_re,
    input  wire [((AXES > 1) ? $clog2(AXES) : 1)-1:0] reg_axis,
    input  wire [5:0]                   reg_addr,
    input  wire [31:0]                  reg_wdata,
    output reg  [31:0]                  reg_rdata,
    // the write on the port is refused (combinational): the axis's core refuses it
    // (rtl/finequad_core.v reg_err), or reg_axis names no axis
    output wire                         reg_err,
    // per-sample results of axis i: m_count[COUNT_W i +: COUNT_W] (s(COUNT_W)),
    // m_fault[11 i +: 11]
    output wire [AXES-1:0]              m_valid,
    output wire [AXES*COUNT_W-1:0]      m_count,
    output wire [AXES*11-1:0]           m_fault,
    // A/B outputs of axis i
    output wire [AXES-1:0]              m_a,
    output wire [AXES-1:0]              m_b,
    // reference marks of axis i: Z, homed, position valid (REF_COUNT: over reg_axis)
    output wire [AXES-1:0]              m_z,
    output wire [AXES-1:0]              m_homed,
    output wire [AXES-1:0]              m_pos_valid
);
/* verilator lint_off UNUSEDPARAM */
`include "rls_cycles.vh"                  // CYCLES_<PROGRAM>_<LANES> (estimator.py)
/* verilator lint_on UNUSEDPARAM */
    localparam AXW = (AXES > 1) ? $clog2(AXES) : 1;
    // window spacing (sim/model/finequad_core.py tdm_period)
    localparam integer TDM_L = TDM_W + 1 + ((ENGINE_LANES == 2) ?
                               CYCLES_UPDATE_2 + CYCLES_EXTRACT_2 :
                               CYCLES_UPDATE_1 + CYCLES_EXTRACT_1);
    localparam [0:0] SHARED = (AXES > 1);

    wire [AXES-1:0]      tdm_ok;           // axis i may decide a program on the coming edge
    wire [66*AXES-1:0]   cmd_all;          // rtl/estimator.v eng_cmd_o of axis i
    wire [115*AXES-1:0]  rsp_all;          // rtl/estimator.v eng_rsp_i of axis i
    wire [32*AXES-1:0]   rdata_all;
    wire [AXES-1:0]      err_all;          // axis i refuses the write

    // ---- the axes --------------------------------------------------------------------------
    genvar i;
    generate
        for (i = 0; i < AXES; i = i + 1) begin : g_axis
            localparam [AXW-1:0] IDX = i;
            wire sel = (AXES == 1) || (reg_axis == IDX);   // this axis's registers
            wire signed [COUNT_W-1:0] count;
            wire signed [COUNT_W-1:0] ref_count;           // REF_COUNT reads it
            finequad_core #(.TABLE_DIR(TABLE_DIR), .ADC_W(ADC_W), .SIN_W(SIN_W),
                            .COUNT_W(COUNT_W), .TABLE_EXACT(TABLE_EXACT), .G_INIT(G_INIT),
                            .OPT_NTH_DSP(OPT_NTH_DSP), .OPT_HARMONIC(OPT_HARMONIC),
                            .OPT_DISTRAM(OPT_DISTRAM), .OPT_PHASE_4K(OPT_PHASE_4K),
                            .OPT_ECP5_MULT(OPT_ECP5_MULT), .OPT_PULSE_ADDR(OPT_PULSE_ADDR),
                            .OPT_MONITOR(OPT_MONITOR),
                            .OPT_JUMP(OPT_JUMP), .OPT_DCODE(OPT_DCODE),
                            .OPT_TUNABLE(OPT_TUNABLE), .ENGINE_LANES(ENGINE_LANES),
                            .OPT_EXT_ENGINE(SHARED),
                            .EXT_PERIOD(SHARED ? AXES * TDM_L : 0)) u_core (
                .clk(clk), .rst(rst),
                .s_valid(s_valid[i]), .s_u1(s_u1[ADC_W*i +: ADC_W]),
                .s_u2(s_u2[ADC_W*i +: ADC_W]), .s_ref(s_ref[i]),
                .reg_we(reg_we && sel), .reg_re(reg_re && sel), .reg_addr(reg_addr),
                .reg_wdata(reg_wdata), .reg_rdata(rdata_all[32*i +: 32]),
                .reg_err(err_all[i]),
                .m_valid(m_valid[i]), .m_count(count), .m_fault(m_fault[11*i +: 11]),
                .m_a(m_a[i]), .m_b(m_b[i]),
                .m_z(m_z[i]), .m_ref_count(ref_count), .m_homed(m_homed[i]),
                .m_pos_valid(m_pos_valid[i]),
                .tdm_ok_i(tdm_ok[i]), .eng_cmd_o(cmd_all[66*i +: 66]),
                .eng_rsp_i(rsp_all[115*i +: 115])
            );
            assign m_count[COUNT_W*i +: COUNT_W] = count;
            wire unused_ref = &{1'b0, ref_count, 1'b0};
        end
    endgenerate

    // a write to a reg_axis beyond the axes reaches no core: refused too
    localparam [31:0] N_AXES = AXES;
    wire axis_ok = (AXES == 1) || ({{(32-AXW){1'b0}}, reg_axis} < N_AXES);
    assign reg_err = |err_all || (reg_we && !axis_ok);

    // ---- register read-back: the axis read last ------------------------------------------------
    reg [AXW-1:0] rd_axis = 0;
    always @(posedge clk)
        if (reg_re)
            rd_axis <= reg_axis;
    integer j;
    always @* begin
        reg_rdata = 32'd0;
        for (j = 0; j < AXES; j = j + 1)
            if (AXES == 1 || rd_axis == j[AXW-1:0])
                reg_rdata = rdata_all[32*j +: 32];
    end

    // ---- the shared engine and its windows -----------------------------------------------------
    generate
        if (SHARED) begin : g_shared
            localparam LW = $clog2(TDM_L);
            localparam integer L_LASTI = TDM_L - 1, W_LASTI = TDM_W - 1, A_LASTI = AXES - 1;
            localparam [LW-1:0]  L_LAST = L_LASTI[LW-1:0];
            localparam [LW-1:0]  W_LAST = W_LASTI[LW-1:0];
            localparam [AXW-1:0] A_LAST = A_LASTI[AXW-1:0];
            // before edge e: wl = e mod TDM_L, wi = the axis whose window span holds e
            // (floor(e mod (AXES TDM_L) / TDM_L)), in_w = wl < TDM_W; own = wi one edge
            // earlier: the axis whose programs start or end on edge e (all of axis i's
            // start on edges i TDM_L + 1 .. i TDM_L + TDM_W and end by (i + 1) TDM_L)
            reg [LW-1:0]  wl = 0;
            reg [AXW-1:0] wi = 0;
            reg           in_w = 1'b1;
            reg [AXW-1:0] own = A_LAST;
            always @(posedge clk) begin
                if (wl == L_LAST) begin
                    wl <= 0;
                    wi <= (wi == A_LAST) ? {AXW{1'b0}} : wi + 1'b1;
                    in_w <= 1'b1;
                end else begin
                    wl <= wl + 1'b1;
                    if (wl == W_LAST)
                        in_w <= 1'b0;
                end
                own <= wi;
                if (rst) begin
                    wl <= 0;
                    wi <= 0;
                    in_w <= 1'b1;
                    own <= A_LAST;
                end
            end
            genvar a;
            for (a = 0; a < AXES; a = a + 1) begin : g_ok
                localparam [AXW-1:0] IDX = a;
                assign tdm_ok[a] = in_w && (wi == IDX);
            end

            // the owner's command (the other axes' start bits are low: they are outside
            // their windows and their programs have ended)
            reg [65:0] cmd;
            integer k;
            always @* begin
                cmd = 66'd0;
                for (k = 0; k < AXES; k = k + 1)
                    if (own == k[AXW-1:0])
                        cmd = cmd_all[66*k +: 66];
            end
            wire               e_start = cmd[65];
            wire [7:0]         e_entry = cmd[64:57];
            wire signed [15:0] e_x1 = cmd[56:41];          // s1.15
            wire signed [15:0] e_x2 = cmd[40:25];          // s1.15
            wire [4:0]         e_lambda_k = cmd[24:20];
            wire               e_freeze = cmd[19];
            wire [15:0]        e_kappa = cmd[18:3];        // u8.8
            wire signed [2:0]  e_dg = cmd[2:0];
            wire e_busy, e_done, e_valid;
            wire [111:0] e_out;                            // OUT registers (rls_engine.v)
            wire [AXES-1:0] e_sat;
            rls_engine #(.TABLE_DIR(TABLE_DIR), .LANES(ENGINE_LANES), .AXES(AXES)) u_engine (
                .clk(clk), .rst(rst),
                .start_i(e_start), .entry_i(e_entry), .x1_i(e_x1), .x2_i(e_x2),
                .lambda_k_i(e_lambda_k), .freeze_i(e_freeze), .kappa_i(e_kappa), .dg_i(e_dg),
                .axis_i(own), .busy_o(e_busy), .done_o(e_done), .valid_o(e_valid),
                .out_o(e_out), .sat_o(e_sat)
            );
            for (a = 0; a < AXES; a = a + 1) begin : g_rsp
                localparam [AXW-1:0] IDX = a;
                assign rsp_all[115*a +: 115] = {e_sat[a], e_done && own == IDX, e_valid,
                                                e_out};
            end
            wire unused_s = &{1'b0, e_busy, 1'b0};
        end else begin : g_single
            assign tdm_ok = {AXES{1'b1}};
            assign rsp_all = {115*AXES{1'b0}};
            wire unused_s = &{1'b0, cmd_all, 1'b0};
        end
    endgenerate
endmodule
`resetall
