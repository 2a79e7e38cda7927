`timescale 1ns / 1ps
`default_nettype none
// finequad_core: adaptive quadrature interpolator (Ulu, Gecer Ulu, Cakmakci 2014, and
// beyond). Bit-true model: sim/model/finequad_core.py. One sample per clock on the fast path.
//
//   s_u1/s_u2 -> correct (gain, Eq. 9, |u|) -> octant (Table 2) -> lut: phase table
//        |                                              | bin                | ph
//        |                                              v                    v
//        +--> estimator (Eqs. 3-8) <-- phase --- harmonic: phase assembly, compensation
//             coefficient bundle -> correct                  | corrected phase
//                                                             v
//                           lut: n * phase -> counter (B + q) -> m_count -> abgen -> A/B
//                                  | pn -> sines (Table 1) -> pulse (Eq. 12) -> edge mode
//
// Latency: a sample strobed on edge t (s_valid high before it) appears on m_valid,
// m_count, m_fault after edge t + LATENCY (8); the A/B outputs (paced, or the Eq. 12
// pulses) and Z follow the count two edges later (t + 10); m_ref_count, m_homed, m_pos_valid take the sample on
// t + 10 (rtl/refmark.v). Stages: t correct (offsets), t+1 products, t+2 magnitudes, t+3
// reciprocal, t+4 ratio, t+5 address and bin (block RAM reads), t+6 fine phase, t+7
// n * phase and the period count, t+8 count; Eq. 12 sines t+8, pulses t+9, the edge-mode
// count E t+10 (in edge mode m_count of a sample holds E as of its own output edge: the
// steps of the samples strobed on or before t-3; rtl/counter.v).
// Fault bits (m_fault): 0 clip (at or near a rail), 1 gain saturation, 2 correction
// saturation, 3 overspeed (|phase step| >= 3/4 pi per sample), 4 not calibrated,
// 5 estimate held (last theta invalid), 6 A/B backlog over its bound, 7 signal loss,
// 8 over-range, 9 stuck channel, 10 glitch (rtl/monitor.v). Bits 9, 10, 0 with 8, and 7
// below COAST.floor hold the counter (the sample's phase is not trusted: the count holds
// while the counter follows the monitor's line, and catches up after; a coast whose
// uncertainty reaches a quarter period clears pos_valid); 0, 7, 9, 10 and a short bit 8
// keep the sample from the estimator. With OPT_MONITOR = 0 bits 7..10 stay 0 and
// nothing holds the counter; clipped samples are still kept from the estimator.
// Reference marks (rtl/refmark.v): s_ref is the reference input of the sample (a
// comparator's output, sampled with s_u1/s_u2); m_z is Z, high while the paced A/B pins
// show the reference count (with the Eq. 12 pulses on the pins, AB_SRC = 1, while they
// show its A/B state in its n-th order period: rtl/refmark.v). Homing
// adds an offset to the counter's count: m_count = count + off (the pins keep the count
// without it).
// Register port: reg_we writes reg_wdata to reg_addr on the edge, unless reg_err (a
// combinational verdict on reg_we, reg_addr, reg_wdata) refuses it: a register that takes
// no writes (read-only, unmapped, constant in this build), a bit no field holds, a field
// outside its legal values; a refused write changes nothing. reg_re reads reg_addr,
// reg_rdata holds the value after that edge (registered; rtl/axil_regs.v puts an AXI4-Lite
// slave in front and answers SLVERR for a refused write). The register map:
// rtl/regs/finequad.rdl (reference: rtl/regs/README.md).
module finequad_core #(
    parameter TABLE_DIR = "rtl/tables/",
    // ADC word width, 12..16, two's complement, MSB-aligned to s1.15 internally
    parameter ADC_W = 16,
    // sine table word width: 8, 10, 12 or 16
    parameter SIN_W = 10,
    // counter width, 17..32
    parameter COUNT_W = 32,
    // 1: exact table (address |small|/|large|, atan rows), 0: the paper's uniform table
    parameter [0:0] TABLE_EXACT = 1'b1,
    // input gain after power-up
    parameter [1:0] G_INIT = 2'd0,
    // 1: the n * phase product with `*` (a DSP block); 0: in logic (iCE40 UP5K)
    parameter [0:0] OPT_NTH_DSP = 1'b1,
    // 1: adaptive harmonic compensation of the fine phase (rtl/harmonic.v); 0: none
    // (rtl/phase.v; HARM reads 0: for devices too small for it)
    parameter [0:0] OPT_HARMONIC = 1'b1,
    // 1: the harmonic table in distributed RAM, read from a registered address (ECP5 and
    // the like: the read starts at flip-flops); 0: in block RAM (iCE40)
    parameter [0:0] OPT_DISTRAM = 1'b0,
    // 1: the exact phase table in 4096 rows per octant sign, addressed without a rounding
    // add and read without an inversion behind it (rtl/lut.v; four more block RAMs, a
    // shorter path: for ~100 MHz); 0: 2048 rows (iCE40)
    parameter [0:0] OPT_PHASE_4K = 1'b0,
    // 1: the ratio multiply's operand registers (rtl/octant.v) and the n-th order
    // product's output register (rtl/lut.v, with OPT_NTH_DSP) inside ECP5 DSP blocks
    // (MULT18X18D instantiated; synthesis only, simulation runs the inferred form);
    // 0: inferred (any device)
    parameter [0:0] OPT_ECP5_MULT = 1'b0,
    // 1: Eq. 12 compares the sine table's address with an inverse threshold read from a
    // table (rtl/pulse.v OPT_ADDR: no comparison behind the sine table's block RAM; one
    // more block RAM; SIN_W 8, 10 or 12; for ~100 MHz); 0: the table's word
    parameter [0:0] OPT_PULSE_ADDR = 1'b0,
    // 1: every setting is a register; 0: the tuning registers (those whose `requires` in
    // rtl/regs/finequad.rdl names OPT_TUNABLE) keep their reset values, which synthesis
    // folds into the logic (writes are refused with reg_err, reads return them, except as
    // OPT_MONITOR and OPT_JUMP say below); CTRL, INTERP, the staged coefficients and
    // FAULT_STICKY stay writable (for a small device, e.g. the iCE40 UP5K)
    parameter [0:0] OPT_TUNABLE = 1'b1,
    // 1: the signal monitor's fault checks (loss, over-range, stuck channel, glitch:
    // rtl/monitor.v); 0: none (the counter never holds, those fault bits are 0, RADIUS and
    // MONITOR read 0; the travel that gates the estimator stays: for a small device)
    parameter [0:0] OPT_MONITOR = 1'b1,
    // 1: the estimator's jump detector (rtl/estimator.v); 0: none (JUMP reads 0x8000,
    // disabled, and JUMPS 0: for a small device)
    parameter [0:0] OPT_JUMP = 1'b1,
    // 1: distance-coded reference marks (rtl/dcode.v, DCODE, ABS_COUNT); 0: none (DCODE
    // takes no writes, ABS_COUNT and REF_STATUS.abs_valid read 0: for a small device)
    parameter [0:0] OPT_DCODE = 1'b1,
    // lanes of the estimator's RLS engine, 1 or 2 (2: four more DSP blocks, shorter
    // programs: rtl/rls_engine.v, sim/model/rls_engine.py CYCLES_BY_LANES)
    parameter ENGINE_LANES = 1,
    // 0: the RLS engine inside (tdm_ok_i, eng_rsp_i unused, eng_cmd_o 0); 1: the engine
    // outside, shared by several axes, through eng_cmd_o / eng_rsp_i, a program decided
    // only on edges with tdm_ok_i (rtl/finequad_multi.v, rtl/estimator.v)
    parameter [0:0] OPT_EXT_ENGINE = 1'b0,
    // with OPT_EXT_ENGINE: the axis's window period in clocks (rtl/finequad_multi.v), the
    // span of the estimator's dither; 0: one axis
    parameter integer EXT_PERIOD = 0
) (
    input  wire                      clk,
    input  wire                      rst,
    // sample stream
    input  wire                      s_valid,
    input  wire signed [ADC_W-1:0]   s_u1,
    input  wire signed [ADC_W-1:0]   s_u2,
    input  wire                      s_ref,      // the reference input (rtl/refmark.v)
    // register port
    input  wire                      reg_we,
    input  wire                      reg_re,
    input  wire [5:0]                reg_addr,
    input  wire [31:0]               reg_wdata,
    output reg  [31:0]               reg_rdata,
    output wire                      reg_err,
    // per-sample results
    output wire                      m_valid,
    output wire signed [COUNT_W-1:0] m_count,
    output wire [10:0]               m_fault,
    // A/B outputs (paced quadrature following the count before the homing offset, or the
    // Eq. 12 pulses)
    output wire                      m_a,
    output wire                      m_b,
    // reference marks (rtl/refmark.v; REF_COUNT, REF_STATUS.homed, REF_STATUS.pos_valid)
    output wire                      m_z,
    output wire signed [COUNT_W-1:0] m_ref_count,
    output wire                      m_homed,
    output wire                      m_pos_valid,
    // shared RLS engine (OPT_EXT_ENGINE = 1; formats: rtl/estimator.v eng_cmd_o, eng_rsp_i)
    input  wire                      tdm_ok_i,
    output wire [65:0]               eng_cmd_o,
    input  wire [114:0]              eng_rsp_i
);
    localparam LATENCY = 8;
    localparam CORR_AT = 2;       // magnitudes registered on edge t + CORR_AT
    localparam PHASE_AT = 6;      // fine phase registered on edge t + PHASE_AT

    // ---- parameter checks: a value out of range instantiates an undefined module named
    // after the rule, which stops every tool's elaboration with that name (as rtl/pulse.v)
    generate
        if (ADC_W < 12 || ADC_W > 16) begin : g_bad_adc_w
            finequad_core_ADC_W_must_be_12_to_16 u_bad ();
        end
        if (SIN_W != 8 && SIN_W != 10 && SIN_W != 12 && SIN_W != 16) begin : g_bad_sin_w
            finequad_core_SIN_W_must_be_8_10_12_or_16 u_bad ();
        end
        if (COUNT_W < 17 || COUNT_W > 32) begin : g_bad_count_w
            finequad_core_COUNT_W_must_be_17_to_32 u_bad ();
        end
        if (ENGINE_LANES != 1 && ENGINE_LANES != 2) begin : g_bad_lanes
            finequad_core_ENGINE_LANES_must_be_1_or_2 u_bad ();
        end
    endgenerate

    // ---- registers: the map is generated from rtl/regs/finequad.rdl (make regs) ---------
    // FQ_<REG> word indices, FQ_<REG>_<FIELD>_LSB/_W/_RESET field positions and reset values
    `include "finequad_regs.vh"
    // m_fault is declared 11 bits wide (a port cannot use the header's localparams)
    generate
        if (FQ_FAULT_W != 11) begin : g_bad_fault_w
            finequad_core_m_fault_width_differs_from_FAULT_STICKY u_bad ();
        end
    endgenerate
    localparam [31:0] ID = FQ_ID_ID_RESET;
    reg [FQ_INTERP_INTERP_W-1:0]     r_interp = FQ_INTERP_INTERP_RESET;        // n
    // EPS u0.15: a write on edge w (or rst) decides the pulses from w + 3 (rtl/pulse.v)
    reg [FQ_EPS_EPS_W-1:0]           r_eps = FQ_EPS_EPS_RESET;
    reg [FQ_LAMBDA_K_LAMBDA_K_W-1:0] r_lambda_k = FQ_LAMBDA_K_LAMBDA_K_RESET;  // 1/(1 + 2**-k)
    reg [FQ_KAPPA_KAPPA_W-1:0]       r_kappa = FQ_KAPPA_KAPPA_RESET;           // u8.8
    // u11.4 5 max(kappa, 1/256) >> 4, the estimator's trace bound, formed with the write
    // (rtl/estimator.v; a register, so no adder lies between kappa and the comparison);
    // 5 * 255.996 = 1279.98 needs the 11 integer bits
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [14:0] kappa5(input [15:0] k);
        reg [15:0] kk;
        reg [18:0] k5;
        begin
            kk = (k == 16'd0) ? 16'd1 : k;
            k5 = {3'b000, kk} + {1'b0, kk, 2'b00};        // u19: 5 * 65535 = 327675
            kappa5 = k5[18:4];
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    localparam [14:0] KAPPA5_RESET = kappa5(FQ_KAPPA_KAPPA_RESET);
    reg [14:0] r_kappa5 = KAPPA5_RESET;
    reg [FQ_PERIOD_PERIOD_W-1:0]     r_period = FQ_PERIOD_PERIOD_RESET;  // updates per reset
    reg [FQ_SETTLE_SETTLE_W-1:0]     r_settle = FQ_SETTLE_SETTLE_RESET;  // before a hand-over
    reg [FQ_GATE_GATE_W-1:0]         r_gate = FQ_GATE_GATE_RESET;        // u13 travel gate
    reg                              r_jump_off = FQ_JUMP_JUMP_OFF_RESET;
    reg [FQ_JUMP_JUMP_MIN_W-1:0]     r_jump_min = FQ_JUMP_JUMP_MIN_RESET;  // u0.13 of |e|
    reg [FQ_FAULT_W-1:0]             r_fault_sticky = 0;      // write 1 to clear
    reg                              r_count_mode = FQ_CTRL_COUNT_MODE_RESET;  // 0 phase, 1 edge
    reg                              r_harm_apply = FQ_HARM_HARM_APPLY_RESET;
    reg                              r_harm_learn = FQ_HARM_HARM_LEARN_RESET;
    reg [FQ_HARM_HARM_MU_W-1:0]      r_harm_mu = FQ_HARM_HARM_MU_RESET;  // 2^-(3 + mu), gear 0
    reg                              r_harm_clear = 1'b0;                // a pulse
    reg [FQ_ABGEN_AB_SEP_W-1:0]      r_ab_sep = FQ_ABGEN_AB_SEP_RESET;   // clocks per edge
    reg                              r_ab_src = FQ_ABGEN_AB_SRC_RESET;   // 1: Eq. 12 pulses
    reg [FQ_AB_BOUND_AB_BOUND_W-1:0] r_ab_bound = FQ_AB_BOUND_AB_BOUND_RESET;  // counts
    reg [FQ_CLIP_CLIP_W-1:0]         r_clip = FQ_CLIP_CLIP_RESET;        // |u| clipped at
    reg [FQ_RADIUS_LOSS_W-1:0]       r_loss = FQ_RADIUS_LOSS_RESET;      // s2.14 radius
    reg [FQ_RADIUS_OVER_W-1:0]       r_over = FQ_RADIUS_OVER_RESET;      // s2.14 radius
    reg [FQ_MONITOR_GLITCH_K_W-1:0]  r_glitch_k = FQ_MONITOR_GLITCH_K_RESET;  // 2^K
    reg [FQ_MONITOR_STUCK_N_W-1:0]   r_stuck_n = FQ_MONITOR_STUCK_N_RESET;    // samples
    reg [FQ_MONITOR_CODE_STEP_W-1:0] r_code_step = FQ_MONITOR_CODE_STEP_RESET; // 2^k LSBs
    reg [FQ_COAST_FLOOR_W-1:0]       r_floor = FQ_COAST_FLOOR_RESET;     // s2.14 radius
    reg [FQ_COAST_COAST_ACC_W-1:0]   r_coast_acc = FQ_COAST_COAST_ACC_RESET; // u0.12
    // staged bundle (GAIN, M1, M2, C1, C12, C2), handed to the fast path by CTRL.load
    reg [1:0]  st_gain = G_INIT;
    reg signed [15:0] st_m1 = FQ_M1_M1_RESET[15:0], st_m2 = FQ_M2_M2_RESET[15:0];
    reg signed [15:0] st_c1 = FQ_C1_C1_RESET[15:0], st_c12 = FQ_C12_C12_RESET[15:0];
    reg signed [15:0] st_c2 = FQ_C2_C2_RESET[15:0];
    reg        req_cov_reset = 1'b0;            // CTRL.cov_reset (a pulse)
    reg        req_load = 1'b0;                 // CTRL.load (a pulse)
    reg        req_capture = 1'b0;              // CTRL.capture (a pulse)
    reg [FQ_REF_REF_Q_W-1:0]    r_ref_q = FQ_REF_REF_Q_RESET;        // counts, 0 .. 4n - 1
    reg [FQ_REF_REF_FILT_W-1:0] r_ref_filt = FQ_REF_REF_FILT_RESET;  // samples
    reg [31:0]                  r_home = FQ_HOME_HOME_COUNT_RESET;   // s32
    reg        req_home = 1'b0;                 // REF.home (a pulse)
    // the count loses its scale (a pulse): a write that changes INTERP, or edge mode
    reg        req_inval = 1'b0;
    reg [2:0]  r_ref_sticky = 3'b000;           // REF_STICKY {dc_err, lost, latched}, w1c
    reg [FQ_DCODE_DC_SPACING_W-1:0] r_dc_spacing = FQ_DCODE_DC_SPACING_RESET;  // periods
    reg [FQ_DCODE_DC_CODED_W-1:0]   r_dc_coded = FQ_DCODE_DC_CODED_RESET;      // periods
    reg        r_dc_confirm = FQ_DCODE_DC_CONFIRM_RESET;
    reg        req_dc_inval = 1'b0;             // a DCODE write changed the layout (a pulse)
    // the write the core takes: reg_we unless refused (rtl/regs/finequad.rdl, fq_write_ok)
    wire wr_take = reg_we && `FQ_WRITE_OK(reg_addr, reg_wdata);
    assign reg_err = reg_we && !wr_take;
    always @(posedge clk) begin
        req_cov_reset <= 1'b0;
        req_load <= 1'b0;
        req_capture <= 1'b0;
        r_harm_clear <= 1'b0;
        req_home <= 1'b0;
        req_inval <= 1'b0;
        req_dc_inval <= 1'b0;
        if (wr_take) begin
            case (reg_addr)
                FQ_CTRL: begin
                    req_cov_reset <= reg_wdata[FQ_CTRL_COV_RESET_LSB];
                    req_load <= reg_wdata[FQ_CTRL_LOAD_LSB];
                    req_capture <= reg_wdata[FQ_CTRL_CAPTURE_LSB];
                    r_count_mode <= reg_wdata[FQ_CTRL_COUNT_MODE_LSB];
                    req_inval <= reg_wdata[FQ_CTRL_COUNT_MODE_LSB];
                end
                FQ_INTERP: begin
                    r_interp <= reg_wdata[FQ_INTERP_INTERP_MSB:FQ_INTERP_INTERP_LSB];
                    req_inval <= (reg_wdata[FQ_INTERP_INTERP_MSB:FQ_INTERP_INTERP_LSB] !=
                                  r_interp);
                end
                FQ_REF: begin
                    r_ref_q <= reg_wdata[FQ_REF_REF_Q_MSB:FQ_REF_REF_Q_LSB];
                    r_ref_filt <= reg_wdata[FQ_REF_REF_FILT_MSB:FQ_REF_REF_FILT_LSB];
                    req_home <= reg_wdata[FQ_REF_HOME_LSB];
                end
                FQ_HOME: r_home <= reg_wdata[FQ_HOME_HOME_COUNT_MSB:FQ_HOME_HOME_COUNT_LSB];
                FQ_DCODE: if (OPT_DCODE) begin
                    req_dc_inval <= (reg_wdata[FQ_DCODE_DC_SPACING_MSB:FQ_DCODE_DC_SPACING_LSB] !=
                                     r_dc_spacing) ||
                                    (reg_wdata[FQ_DCODE_DC_CODED_MSB:FQ_DCODE_DC_CODED_LSB] !=
                                     r_dc_coded);
                    r_dc_spacing <= reg_wdata[FQ_DCODE_DC_SPACING_MSB:FQ_DCODE_DC_SPACING_LSB];
                    r_dc_coded <= reg_wdata[FQ_DCODE_DC_CODED_MSB:FQ_DCODE_DC_CODED_LSB];
                    r_dc_confirm <= reg_wdata[FQ_DCODE_DC_CONFIRM_LSB];
                end
                FQ_GAIN: st_gain <= reg_wdata[FQ_GAIN_GAIN_MSB:FQ_GAIN_GAIN_LSB];
                FQ_M1: st_m1 <= reg_wdata[FQ_M1_M1_LSB + 15:FQ_M1_M1_LSB];
                FQ_M2: st_m2 <= reg_wdata[FQ_M2_M2_LSB + 15:FQ_M2_M2_LSB];
                FQ_C1: st_c1 <= reg_wdata[FQ_C1_C1_LSB + 15:FQ_C1_C1_LSB];
                FQ_C12: st_c12 <= reg_wdata[FQ_C12_C12_LSB + 15:FQ_C12_C12_LSB];
                FQ_C2: st_c2 <= reg_wdata[FQ_C2_C2_LSB + 15:FQ_C2_C2_LSB];
                default: ;
            endcase
        end
        // the tuning registers: constant with OPT_TUNABLE = 0 (fq_write_ok refuses their
        // writes too; the parameter here lets synthesis fold them)
        if (wr_take && OPT_TUNABLE) begin
            case (reg_addr)
                FQ_EPS: r_eps <= reg_wdata[FQ_EPS_EPS_MSB:FQ_EPS_EPS_LSB];
                FQ_LAMBDA_K:
                    r_lambda_k <= reg_wdata[FQ_LAMBDA_K_LAMBDA_K_MSB:FQ_LAMBDA_K_LAMBDA_K_LSB];
                FQ_KAPPA: begin
                    r_kappa <= reg_wdata[FQ_KAPPA_KAPPA_MSB:FQ_KAPPA_KAPPA_LSB];
                    r_kappa5 <= kappa5(reg_wdata[FQ_KAPPA_KAPPA_MSB:FQ_KAPPA_KAPPA_LSB]);
                end
                FQ_PERIOD: r_period <= reg_wdata[FQ_PERIOD_PERIOD_MSB:FQ_PERIOD_PERIOD_LSB];
                FQ_SETTLE: r_settle <= reg_wdata[FQ_SETTLE_SETTLE_MSB:FQ_SETTLE_SETTLE_LSB];
                FQ_GATE: r_gate <= reg_wdata[FQ_GATE_GATE_MSB:FQ_GATE_GATE_LSB];
                FQ_HARM: begin
                    r_harm_apply <= reg_wdata[FQ_HARM_HARM_APPLY_LSB];
                    r_harm_learn <= reg_wdata[FQ_HARM_HARM_LEARN_LSB];
                    r_harm_mu <= reg_wdata[FQ_HARM_HARM_MU_MSB:FQ_HARM_HARM_MU_LSB];
                    r_harm_clear <= reg_wdata[FQ_HARM_HARM_CLEAR_LSB];
                end
                FQ_JUMP: begin
                    r_jump_off <= reg_wdata[FQ_JUMP_JUMP_OFF_LSB];
                    r_jump_min <= reg_wdata[FQ_JUMP_JUMP_MIN_MSB:FQ_JUMP_JUMP_MIN_LSB];
                end
                FQ_ABGEN: begin
                    r_ab_sep <= reg_wdata[FQ_ABGEN_AB_SEP_MSB:FQ_ABGEN_AB_SEP_LSB];
                    r_ab_src <= reg_wdata[FQ_ABGEN_AB_SRC_LSB];
                end
                FQ_AB_BOUND:
                    r_ab_bound <= reg_wdata[FQ_AB_BOUND_AB_BOUND_MSB:FQ_AB_BOUND_AB_BOUND_LSB];
                FQ_CLIP: r_clip <= reg_wdata[FQ_CLIP_CLIP_MSB:FQ_CLIP_CLIP_LSB];
                FQ_RADIUS: begin
                    r_loss <= reg_wdata[FQ_RADIUS_LOSS_MSB:FQ_RADIUS_LOSS_LSB];
                    r_over <= reg_wdata[FQ_RADIUS_OVER_MSB:FQ_RADIUS_OVER_LSB];
                end
                FQ_MONITOR: begin
                    r_glitch_k <= reg_wdata[FQ_MONITOR_GLITCH_K_MSB:FQ_MONITOR_GLITCH_K_LSB];
                    r_stuck_n <= reg_wdata[FQ_MONITOR_STUCK_N_MSB:FQ_MONITOR_STUCK_N_LSB];
                    r_code_step <= reg_wdata[FQ_MONITOR_CODE_STEP_MSB:FQ_MONITOR_CODE_STEP_LSB];
                end
                FQ_COAST: begin
                    r_floor <= reg_wdata[FQ_COAST_FLOOR_MSB:FQ_COAST_FLOOR_LSB];
                    r_coast_acc <= reg_wdata[FQ_COAST_COAST_ACC_MSB:FQ_COAST_COAST_ACC_LSB];
                end
                default: ;
            endcase
        end
        // write 1 to clear; a fault arriving on the same edge stays set
        r_fault_sticky <= (r_fault_sticky & ~((wr_take && reg_addr == FQ_FAULT_STICKY) ?
                                              reg_wdata[FQ_FAULT_W-1:0] : {FQ_FAULT_W{1'b0}}))
                          | (m_valid ? m_fault : {FQ_FAULT_W{1'b0}});
        r_ref_sticky <= (r_ref_sticky & ~((wr_take && reg_addr == FQ_REF_STICKY) ?
                                          {reg_wdata[FQ_REF_STICKY_DC_ERR_LSB],
                                           reg_wdata[FQ_REF_STICKY_LOST_LSB],
                                           reg_wdata[FQ_REF_STICKY_LATCHED_LSB]} : 3'b000))
                        | {dc_err, rm_lost, rm_latch};
        if (rst) begin
            r_interp <= FQ_INTERP_INTERP_RESET;
            r_eps <= FQ_EPS_EPS_RESET;
            r_lambda_k <= FQ_LAMBDA_K_LAMBDA_K_RESET;
            r_kappa <= FQ_KAPPA_KAPPA_RESET;
            r_kappa5 <= KAPPA5_RESET;
            r_period <= FQ_PERIOD_PERIOD_RESET;
            r_settle <= FQ_SETTLE_SETTLE_RESET;
            r_gate <= FQ_GATE_GATE_RESET;
            r_jump_off <= FQ_JUMP_JUMP_OFF_RESET;
            r_jump_min <= FQ_JUMP_JUMP_MIN_RESET;
            r_fault_sticky <= 0;
            r_ref_sticky <= 3'b000;
            r_dc_spacing <= FQ_DCODE_DC_SPACING_RESET;
            r_dc_coded <= FQ_DCODE_DC_CODED_RESET;
            r_dc_confirm <= FQ_DCODE_DC_CONFIRM_RESET;
            req_dc_inval <= 1'b0;
            r_ref_q <= FQ_REF_REF_Q_RESET;
            r_ref_filt <= FQ_REF_REF_FILT_RESET;
            r_home <= FQ_HOME_HOME_COUNT_RESET;
            req_home <= 1'b0;
            req_inval <= 1'b0;
            req_cov_reset <= 1'b0;
            req_load <= 1'b0;
            req_capture <= 1'b0;
            r_count_mode <= FQ_CTRL_COUNT_MODE_RESET;
            r_clip <= FQ_CLIP_CLIP_RESET;
            r_loss <= FQ_RADIUS_LOSS_RESET;
            r_over <= FQ_RADIUS_OVER_RESET;
            r_glitch_k <= FQ_MONITOR_GLITCH_K_RESET;
            r_stuck_n <= FQ_MONITOR_STUCK_N_RESET;
            r_code_step <= FQ_MONITOR_CODE_STEP_RESET;
            r_floor <= FQ_COAST_FLOOR_RESET;
            r_coast_acc <= FQ_COAST_COAST_ACC_RESET;
            st_gain <= G_INIT;
            st_m1 <= FQ_M1_M1_RESET[15:0];
            st_m2 <= FQ_M2_M2_RESET[15:0];
            st_c1 <= FQ_C1_C1_RESET[15:0];
            st_c12 <= FQ_C12_C12_RESET[15:0];
            st_c2 <= FQ_C2_C2_RESET[15:0];
            r_harm_apply <= FQ_HARM_HARM_APPLY_RESET;
            r_harm_learn <= FQ_HARM_HARM_LEARN_RESET;
            r_harm_mu <= FQ_HARM_HARM_MU_RESET;
            r_harm_clear <= 1'b0;
            r_ab_sep <= FQ_ABGEN_AB_SEP_RESET;
            r_ab_src <= FQ_ABGEN_AB_SRC_RESET;
            r_ab_bound <= FQ_AB_BOUND_AB_BOUND_RESET;
        end
    end

    // ---- estimator and its bundle -------------------------------------------------------------
    wire [1:0] b_g;
    wire signed [15:0] b_m1, b_m2, b_c1, b_c12, b_c2;
    wire b_uncal, b_hold, b_loaded, b_ref, e_sat;
    wire [31:0] e_updates;
    wire [15:0] e_jumps;

    // ---- fast path: t .. t+2 -------------------------------------------------------------------
    wire c_v0, c_clip, c_nsat, c_dsat, c_valid, c_xn, c_yn, c_rsat;
    wire signed [15:0] c_raw1, c_raw2;
    wire [14:0] c_amax, c_ax, c_ay;
    wire [3:0]  c_zl;
    correct #(.ADC_W(ADC_W)) u_correct (
        .clk(clk), .valid_i(s_valid && !rst), .u1_i(s_u1), .u2_i(s_u2), .clip_i(r_clip),
        .g_i(b_g), .m1_i(b_m1), .m2_i(b_m2), .c1_i(b_c1), .c12_i(b_c12), .c2_i(b_c2),
        .valid0_o(c_v0), .raw1_o(c_raw1), .raw2_o(c_raw2), .amax_o(c_amax),
        .clip_o(c_clip), .nsat_o(c_nsat), .dsat_o(c_dsat),
        .valid_o(c_valid), .ax_o(c_ax), .ay_o(c_ay), .xn_o(c_xn), .yn_o(c_yn), .zl_o(c_zl),
        .rsat_o(c_rsat)
    );
    // ---- t+3 .. t+5: octant ---------------------------------------------------------------------
    wire o_valid, o_neg;
    wire [10:0] o_j;
    wire [11:0] o_t;
    wire [1:0] o_oct2;
    octant #(.TABLE_DIR(TABLE_DIR), .TABLE_EXACT(TABLE_EXACT), .OPT_ECP5_MULT(OPT_ECP5_MULT))
    u_octant (
        .clk(clk), .valid_i(c_valid), .ax_i(c_ax), .ay_i(c_ay), .xn_i(c_xn), .yn_i(c_yn),
        .zl_i(c_zl),
        .valid_o(o_valid), .j_o(o_j), .t_o(o_t), .oct2_o(o_oct2), .neg_o(o_neg)
    );
    // ---- t+5 .. t+6: phase table and the harmonic table, fine phase --------------------------
    wire [11:0] l_ph;
    wire h_valid;
    wire [12:0] h_phase, h_phase_c;
    generate
        if (OPT_HARMONIC) begin : g_harm
            harmonic #(.TABLE_EXACT(TABLE_EXACT), .OPT_DISTRAM(OPT_DISTRAM)) u_harmonic (
                .clk(clk), .valid_i(o_valid), .oct2_i(o_oct2), .neg_i(o_neg), .t_i(o_t),
                .ph_i(l_ph), .apply_i(r_harm_apply), .learn_i(r_harm_learn), .mu_i(r_harm_mu),
                .clear_i(r_harm_clear), .valid_o(h_valid), .phase_o(h_phase),
                .phase_c_o(h_phase_c)
            );
        end else begin : g_noharm
            phase u_phase (
                .clk(clk), .valid_i(o_valid), .oct2_i(o_oct2), .neg_i(o_neg), .ph_i(l_ph),
                .valid_o(h_valid), .phase_o(h_phase), .phase_c_o(h_phase_c)
            );
            wire unused_h = &{1'b0, r_harm_apply, r_harm_learn, r_harm_mu, r_harm_clear, 1'b0};
        end
    endgenerate
    // ---- signal monitor: faults, the counter's hold (stage t+6 .. t+7), the travel ------------
    wire mon_hold, mon_excl, mon_loss, mon_over, mon_stuck, mon_glitch, mon_coast, mon_lost;
    wire [12:0] mon_line;
    wire [19:0] mon_travel;
    monitor #(.OPT_MONITOR(OPT_MONITOR), .ADC_W(ADC_W)) u_monitor (
        .clk(clk), .rst(rst), .sv_i(s_valid && !rst), .g_i(b_g), .c1_i(b_c1), .c2_i(b_c2),
        .code_step_i(r_code_step), .valid0_i(c_v0), .raw1_i(c_raw1), .raw2_i(c_raw2),
        .clip_i(c_clip), .ref_i(b_ref), .ax_i(c_ax), .ay_i(c_ay), .xn_i(c_xn), .yn_i(c_yn), .pvalid_i(h_valid), .phase_i(h_phase),
        .loss_th_i(r_loss), .over_th_i(r_over), .glitch_k_i(r_glitch_k),
        .stuck_n_i(r_stuck_n), .floor_th_i(r_floor), .coast_acc_i(r_coast_acc),
        .coast_o(mon_coast), .line_o(mon_line), .lost_o(mon_lost),
        .hold_o(mon_hold), .excl_o(mon_excl), .loss_o(mon_loss),
        .over_o(mon_over), .stuck_o(mon_stuck), .glitch_o(mon_glitch),
        .travel_o(mon_travel)
    );
    // ---- t+7 .. t+8: n-th order phase and sines -------------------------------------------------
    wire n_valid, l_valid, l_cneg, l_sneg;
    wire [21:0] n_prod;
    wire [12:0] l_pn;
    wire [SIN_W-2:0] l_cmag, l_smag;
    wire [10:0] l_ck, l_sk;
    lut #(.TABLE_DIR(TABLE_DIR), .TABLE_EXACT(TABLE_EXACT), .SIN_W(SIN_W),
          .OPT_NTH_DSP(OPT_NTH_DSP), .OPT_PHASE_4K(OPT_PHASE_4K),
          .OPT_ECP5_MULT(OPT_ECP5_MULT)) u_lut (
        .clk(clk), .j_i(o_j), .t_i(o_t), .neg_i(o_neg), .ph_o(l_ph),
        .valid_i(h_valid), .phase_i(h_phase_c), .n_i(r_interp),
        .nth_valid_o(n_valid), .prod_o(n_prod),
        .valid_o(l_valid), .pn_o(l_pn), .cos_mag_o(l_cmag), .cos_neg_o(l_cneg),
        .sin_mag_o(l_smag), .sin_neg_o(l_sneg), .cos_k_o(l_ck), .sin_k_o(l_sk)
    );
    // ---- t+9: Eq. 12 pulses ------------------------------------------------------------------------
    wire p_valid, p_a, p_b;
    pulse #(.SIN_W(SIN_W), .OPT_TUNABLE(OPT_TUNABLE), .OPT_ADDR(OPT_PULSE_ADDR),
            .TABLE_DIR(TABLE_DIR)) u_pulse (
        .clk(clk), .rst(rst), .valid_i(l_valid),
        .cos_mag_i(l_cmag), .cos_neg_i(l_cneg), .cos_k_i(l_ck),
        .sin_mag_i(l_smag), .sin_neg_i(l_sneg), .sin_k_i(l_sk),
        .eps_i(r_eps), .valid_o(p_valid), .a_o(p_a), .b_o(p_b)
    );
    // ---- t+7 .. t+8: counter -----------------------------------------------------------------------
    wire k_ovs, k_ill, k_held;
    wire signed [COUNT_W-1:0] k_count;          // the count before the homing offset
    wire [15:0] k_ill_count;
    counter #(.COUNT_W(COUNT_W)) u_counter (
        .clk(clk), .rst(rst), .valid_i(h_valid), .hold_i(mon_hold), .coast_i(mon_coast),
        .line_i(mon_line), .phase_i(h_phase_c),
        .prod_i(n_prod),
        .n_i(r_interp), .mode_i(r_count_mode), .pv_i(p_valid), .a_i(p_a), .b_i(p_b),
        .valid_o(m_valid), .count_o(k_count), .ovs_o(k_ovs), .ill_o(k_ill),
        .ill_count_o(k_ill_count), .held_o(k_held)
    );
    // the monitor's verdict that a coast lost the travel (t + 7), beside the count (t + 8)
    reg k_lost = 1'b0;
    always @(posedge clk)
        k_lost <= mon_lost && !r_count_mode && !rst;
    // ---- t+9 .. t+10: reference marks ----------------------------------------------------------
    wire rm_pa, rm_pb, rm_zp;
    wire rm_z_en, rm_win, rm_homed, rm_pos_valid, rm_home_armed, rm_latch, rm_lost;
    wire signed [COUNT_W-1:0] rm_target, rm_z_at, rm_off, rm_ref_count, rm_x;
    wire rm_cross, rm_cdir, rm_mark, rm_inv;
    wire dc_en = OPT_DCODE && (r_dc_spacing != 0);
    wire dc_home, dc_err, dc_abs_valid;
    wire signed [COUNT_W-1:0] dc_off, dc_ref, dc_abs;
    wire signed [COUNT_W-1:0] g_pos;
    wire fl_ref;                                 // the sample's s_ref on t + 8
    refmark #(.COUNT_W(COUNT_W)) u_refmark (
        .clk(clk), .rst(rst), .nv_i(n_valid), .q_i(n_prod[21:11]), .n_i(r_interp),
        .ref_q_i(r_ref_q), .filt_i(r_ref_filt), .mode_i(r_count_mode),
        .cv_i(m_valid), .count_i(k_count), .held_i(k_held), .lost_i(k_lost), .ovs_i(k_ovs),
        .ref_i(fl_ref),
        .pv_i(p_valid), .pa_i(p_a), .pb_i(p_b), .pa_o(rm_pa), .pb_o(rm_pb), .zp_o(rm_zp),
        .pos_i(g_pos), .target_o(rm_target), .z_en_o(rm_z_en), .z_at_o(rm_z_at),
        .home_arm_i(req_home), .home_i(r_home[COUNT_W-1:0]), .inval_i(req_inval),
        .off_o(rm_off), .ref_count_o(rm_ref_count), .win_o(rm_win), .homed_o(rm_homed),
        .pos_valid_o(rm_pos_valid), .home_armed_o(rm_home_armed), .latch_o(rm_latch),
        .lost_o(rm_lost), .dc_en_i(dc_en), .dc_home_i(dc_home), .dc_off_i(dc_off),
        .dc_ref_i(dc_ref), .cross_o(rm_cross), .cdir_o(rm_cdir), .mark_o(rm_mark),
        .x_o(rm_x), .inv_o(rm_inv)
    );
    // distance-coded marks (rtl/dcode.v), on the latch's t + 10
    generate
        if (OPT_DCODE) begin : g_dcode
            dcode #(.COUNT_W(COUNT_W)) u_dcode (
                .clk(clk), .rst(rst), .a_i(r_dc_spacing), .b_i(r_dc_coded),
                .conf_i(r_dc_confirm), .n_i(r_interp), .home_i(r_home[COUNT_W-1:0]),
                .cross_i(rm_cross), .cdir_i(rm_cdir), .lat_i(rm_mark && dc_en), .x_i(rm_x),
                .inv_i(rm_inv || !dc_en || req_dc_inval), .abs_valid_o(dc_abs_valid), .abs_o(dc_abs),
                .home_o(dc_home), .off_o(dc_off), .ref_o(dc_ref), .err_o(dc_err)
            );
        end else begin : g_no_dcode
            assign dc_home = 1'b0;
            assign dc_err = 1'b0;
            assign dc_abs_valid = 1'b0;
            assign dc_off = 0;
            assign dc_ref = 0;
            assign dc_abs = 0;
            wire unused_dc = &{1'b0, rm_cross, rm_cdir, rm_mark, rm_x, rm_inv, r_dc_spacing,
                               r_dc_coded, r_dc_confirm, req_dc_inval, 1'b0};
        end
    endgenerate
    assign m_count = k_count + rm_off;
    assign m_ref_count = rm_ref_count;
    assign m_homed = rm_homed;
    assign m_pos_valid = rm_pos_valid;
    // ---- t+10: paced A/B and Z (the count before the homing offset, one edge later) ----------
    wire g_a, g_b, g_ovf, g_sticky, g_z;
    wire signed [15:0] g_backlog;
    abgen #(.COUNT_W(COUNT_W), .OPT_TUNABLE(OPT_TUNABLE)) u_abgen (
        .clk(clk), .rst(rst), .target_i(rm_target), .sep_i(r_ab_sep), .bound_i(r_ab_bound),
        .a_o(g_a), .b_o(g_b), .pos_o(g_pos), .backlog_o(g_backlog), .ovf_o(g_ovf),
        .ovf_sticky_o(g_sticky), .z_en_i(rm_z_en), .z_at_i(rm_z_at), .z_o(g_z)
    );
    // the Eq. 12 pulses on the pins one edge late, beside their Z (rtl/refmark.v)
    assign m_a = r_ab_src ? rm_pa : g_a;
    assign m_b = r_ab_src ? rm_pb : g_b;
    assign m_z = r_ab_src ? rm_zp : g_z;

    // ---- estimator: every sample on arrival (t), its fine phase PHASE_AT = 6 edges after (t+6) -----
    estimator #(.TABLE_DIR(TABLE_DIR), .G_INIT(G_INIT), .PH_DELAY(PHASE_AT),
                .ENGINE_LANES(ENGINE_LANES), .OPT_EXT_ENGINE(OPT_EXT_ENGINE),
                .EXT_PERIOD(EXT_PERIOD),
                .OPT_TUNABLE(OPT_TUNABLE)) u_est (
        .clk(clk), .rst(rst),
        .smp_valid_i(c_v0), .u1_i(c_raw1), .u2_i(c_raw2), .amax_i(c_amax),
        .ph_valid_i(h_valid), .phase_i(h_phase), .excl_i(mon_excl),
        .travel_i(mon_travel),
        .load_i(req_load), .ld_g_i(st_gain), .ld_m1_i(st_m1), .ld_m2_i(st_m2), .ld_c1_i(st_c1),
        .ld_c12_i(st_c12), .ld_c2_i(st_c2),
        .req_reset_i(req_cov_reset), .lambda_k_i(r_lambda_k), .kappa_i(r_kappa),
        .kappa5_i(r_kappa5),
        .period_i(r_period), .settle_i(r_settle), .gate_i(r_gate),
        .jump_on_i(OPT_JUMP && !r_jump_off), .jump_min_i(r_jump_min), .jumps_o(e_jumps),
        .g_o(b_g), .m1_o(b_m1), .m2_o(b_m2), .c1_o(b_c1), .c12_o(b_c12), .c2_o(b_c2),
        .uncal_o(b_uncal), .hold_o(b_hold), .loaded_o(b_loaded), .ref_o(b_ref),
        .updates_o(e_updates), .sat_o(e_sat),
        .tdm_ok_i(tdm_ok_i), .eng_cmd_o(eng_cmd_o), .eng_rsp_i(eng_rsp_i)
    );

    // ---- fault bits, carried with the sample -------------------------------------------------
    // The flags of edge t (clip, gain and offset saturation, and the bundle's uncal and
    // hold, sampled with the sample: uncal0, hold0) reach the output on edge t + LATENCY.
    // csat: the offset removal's saturation (edge t), joined by the correction's (rsat,
    // edge t + CORR_AT) at index CORR_AT of its delay line (index k: registered k + 1
    // edges after edge t), which is registered on the same edge as rsat.
    reg [LATENCY-1:0] csat_d = 0;
    reg uncal0 = 1'b1, hold0 = 1'b0, ref0 = 1'b0;
    always @(posedge clk) begin
        uncal0 <= b_uncal;
        hold0  <= b_hold;
        ref0   <= s_ref;
        csat_d <= {csat_d[LATENCY-2:CORR_AT], csat_d[CORR_AT-1] | c_rsat,
                   csat_d[CORR_AT-2:0], c_dsat};
    end
    // clip, nsat, uncal, hold: OPT_DISTRAM = 0 (iCE40: short of logic cells, and a
    // flip-flop of a shift register takes a whole one): in a block RAM of LATENCY = 8
    // words written on every edge at fl_wp (3 bits) and read at fl_wp + 1, so the word
    // written on edge t + 1 is read on edge t + LATENCY, into the RAM's output register;
    // OPT_DISTRAM = 1 (ECP5): flip-flops.
    wire [4:0] fl_in = {ref0, c_clip, c_nsat, uncal0, hold0};
    wire [4:0] fl_out;                           // {ref, clip, nsat, uncal, hold}
    generate
        if (OPT_DISTRAM) begin : g_flag_ff
            reg [4:0] fl_d [0:LATENCY-1];
            integer k;
            initial
                for (k = 0; k < LATENCY; k = k + 1)
                    fl_d[k] = 5'd0;
            always @(posedge clk) begin
                fl_d[0] <= fl_in;
                for (k = 1; k < LATENCY; k = k + 1)
                    fl_d[k] <= fl_d[k - 1];
            end
            assign fl_out = fl_d[LATENCY-1];
        end else begin : g_flag_ram
            (* ram_style = "block" *) reg [4:0] fl_mem [0:LATENCY-1];
            reg [2:0] fl_wp = 3'd0;
            wire [2:0] fl_rp = fl_wp + 3'd1;     // (3 bits: wraps)
            reg [4:0] fl_q = 5'd0;
            integer k;
            initial
                for (k = 0; k < LATENCY; k = k + 1)
                    fl_mem[k] = 5'd0;
            always @(posedge clk) begin
                fl_mem[fl_wp] <= fl_in;
                fl_q <= fl_mem[fl_rp];
                fl_wp <= fl_wp + 3'd1;
            end
            assign fl_out = fl_q;
        end
    endgenerate
    // the monitor's flags are registered on t + 7, one edge before the output
    reg [3:0] mon_q = 4'd0;                      // {glitch, stuck, over, loss}
    always @(posedge clk)
        mon_q <= {mon_glitch, mon_stuck, mon_over, mon_loss};
    // the fault word: its bits where FAULT_STICKY has them; csat: the offset removal (t)
    // or the correction's products (t + 2) saturated
    assign fl_ref = fl_out[4];
    assign m_fault[FQ_FAULT_STICKY_CLIP_LSB] = fl_out[3];
    assign m_fault[FQ_FAULT_STICKY_NSAT_LSB] = fl_out[2];
    assign m_fault[FQ_FAULT_STICKY_CSAT_LSB] = csat_d[LATENCY-1];
    assign m_fault[FQ_FAULT_STICKY_OVS_LSB] = k_ovs;
    assign m_fault[FQ_FAULT_STICKY_UNCAL_LSB] = fl_out[1];
    assign m_fault[FQ_FAULT_STICKY_HOLD_LSB] = fl_out[0];
    assign m_fault[FQ_FAULT_STICKY_ABOVF_LSB] = g_sticky;
    assign m_fault[FQ_FAULT_STICKY_LOSS_LSB] = mon_q[0];
    assign m_fault[FQ_FAULT_STICKY_OVER_LSB] = mon_q[1];
    assign m_fault[FQ_FAULT_STICKY_STUCK_LSB] = mon_q[2];
    assign m_fault[FQ_FAULT_STICKY_GLITCH_LSB] = mon_q[3];

    // CTRL.capture: the count captured (a coherent copy for a narrow or slow host link)
    reg signed [COUNT_W-1:0] r_capture = 0;
    always @(posedge clk) begin
        if (req_capture)
            r_capture <= m_count;
        if (rst)
            r_capture <= 0;
    end

    // ---- register read-back (registered): `FQ_RD_<REG>() places the fields by position
    // (signed fields sign-extended here; unmapped words read 0) ----------------------------
    always @(posedge clk) begin
        if (reg_re) begin
            case (reg_addr)
                FQ_STATUS: reg_rdata <= `FQ_RD_STATUS(b_uncal, b_hold, e_sat, r_count_mode,
                                                     b_loaded);
                FQ_INTERP: reg_rdata <= `FQ_RD_INTERP(r_interp);
                FQ_EPS: reg_rdata <= `FQ_RD_EPS(r_eps);
                FQ_LAMBDA_K: reg_rdata <= `FQ_RD_LAMBDA_K(r_lambda_k);
                FQ_KAPPA: reg_rdata <= `FQ_RD_KAPPA(r_kappa);
                FQ_PERIOD: reg_rdata <= `FQ_RD_PERIOD(r_period);
                FQ_SETTLE: reg_rdata <= `FQ_RD_SETTLE(r_settle);
                FQ_GATE: reg_rdata <= `FQ_RD_GATE(r_gate);
                FQ_COUNT: reg_rdata <= `FQ_RD_COUNT({{(32-COUNT_W+1){m_count[COUNT_W-1]}},
                                                    m_count[COUNT_W-2:0]});
                FQ_ILLEGAL: reg_rdata <= `FQ_RD_ILLEGAL(k_ill_count);
                FQ_FAULT_STICKY: reg_rdata <= {{(32-FQ_FAULT_W){1'b0}}, r_fault_sticky};
                FQ_GAIN: reg_rdata <= `FQ_RD_GAIN(b_g);
                FQ_M1: reg_rdata <= `FQ_RD_M1({{16{b_m1[15]}}, b_m1});
                FQ_M2: reg_rdata <= `FQ_RD_M2({{16{b_m2[15]}}, b_m2});
                FQ_C1: reg_rdata <= `FQ_RD_C1({{16{b_c1[15]}}, b_c1});
                FQ_C12: reg_rdata <= `FQ_RD_C12({{16{b_c12[15]}}, b_c12});
                FQ_C2: reg_rdata <= `FQ_RD_C2({{16{b_c2[15]}}, b_c2});
                FQ_UPDATES: reg_rdata <= `FQ_RD_UPDATES(e_updates);
                FQ_HARM: reg_rdata <= OPT_HARMONIC ?
                                      `FQ_RD_HARM(r_harm_apply, r_harm_learn, r_harm_mu) : 32'd0;
                FQ_JUMP: reg_rdata <= OPT_JUMP ? `FQ_RD_JUMP(r_jump_min, r_jump_off) :
                                      `FQ_RD_JUMP(11'd0, 1'b1);          // the detector off
                FQ_JUMPS: reg_rdata <= OPT_JUMP ? `FQ_RD_JUMPS(e_jumps) : 32'd0;
                FQ_ABGEN: reg_rdata <= `FQ_RD_ABGEN(r_ab_sep, r_ab_src);
                FQ_AB_BOUND: reg_rdata <= `FQ_RD_AB_BOUND(r_ab_bound);
                FQ_AB_BACKLOG: reg_rdata <= `FQ_RD_AB_BACKLOG({{16{g_backlog[15]}}, g_backlog});
                FQ_CLIP: reg_rdata <= `FQ_RD_CLIP(r_clip);
                FQ_RADIUS: reg_rdata <= OPT_MONITOR ? `FQ_RD_RADIUS(r_loss, r_over) : 32'd0;
                FQ_MONITOR: reg_rdata <= OPT_MONITOR ? `FQ_RD_MONITOR(r_glitch_k, r_code_step, r_stuck_n) :
                                         32'd0;
                FQ_COAST: reg_rdata <= OPT_MONITOR ? `FQ_RD_COAST(r_floor, r_coast_acc) : 32'd0;
                FQ_CAPTURE: reg_rdata <= `FQ_RD_CAPTURE({{(32-COUNT_W+1){r_capture[COUNT_W-1]}},
                                                        r_capture[COUNT_W-2:0]});
                FQ_TRAVEL: reg_rdata <= `FQ_RD_TRAVEL(mon_travel);
                FQ_REF: reg_rdata <= `FQ_RD_REF(r_ref_q, r_ref_filt);
                FQ_HOME: reg_rdata <= `FQ_RD_HOME(r_home);
                FQ_REF_COUNT: reg_rdata <= `FQ_RD_REF_COUNT({{(32-COUNT_W+1){rm_ref_count[COUNT_W-1]}},
                                                            rm_ref_count[COUNT_W-2:0]});
                FQ_REF_STATUS: reg_rdata <= `FQ_RD_REF_STATUS(rm_win, rm_homed, rm_pos_valid,
                                                             rm_home_armed, dc_abs_valid);
                FQ_REF_STICKY: reg_rdata <= `FQ_RD_REF_STICKY(r_ref_sticky[0], r_ref_sticky[1],
                                                             r_ref_sticky[2]);
                FQ_DCODE: reg_rdata <= `FQ_RD_DCODE(r_dc_spacing, r_dc_coded, r_dc_confirm);
                FQ_ABS_COUNT: reg_rdata <= `FQ_RD_ABS_COUNT({{(32-COUNT_W+1){dc_abs[COUNT_W-1]}},
                                                            dc_abs[COUNT_W-2:0]});
                FQ_ID: reg_rdata <= ID;
                default: reg_rdata <= 32'd0;
            endcase
        end
    end
    initial reg_rdata = 32'd0;
    wire unused = &{1'b0, reg_wdata[31:16], l_pn, k_ill, g_ovf, r_home, 1'b0};
endmodule
`resetall
