`timescale 1ns / 1ps
`default_nettype none
// finequad_core: adaptive quadrature interpolator (Ulu, Gecer Ulu, Cakmakci 2014, and
// beyond). Bit-true model: sim/model/core.py. One sample per clock on the fast path.
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
// m_count, m_fault after edge t + LATENCY (8); the paced A/B outputs follow the count one
// edge later (t + 9). Stages: t correct (offsets), t+1 products, t+2 magnitudes, t+3
// reciprocal, t+4 ratio, t+5 address and bin (block RAM reads), t+6 fine phase, t+7
// n * phase and the period count, t+8 count; Eq. 12 sines t+8, pulses t+9, the edge-mode
// count E t+10 (in edge mode m_count of a sample holds E as of its own output edge: the
// steps of the samples strobed on or before t-3; rtl/counter.v).
// Fault bits (m_fault): 0 clip (at or near a rail), 1 gain saturation, 2 correction
// saturation, 3 overspeed (|phase step| >= 3/4 pi per sample), 4 not calibrated,
// 5 estimate held (last theta invalid), 6 A/B backlog over its bound, 7 signal loss,
// 8 over-range, 9 stuck channel, 10 glitch (rtl/monitor.v). Bits 7, 9, 10, and 0 with 8,
// hold the counter (the sample's phase is not trusted); 0, 7, 9, 10 and a short bit 8
// keep the sample from the estimator. With OPT_MONITOR = 0 bits 7..10 stay 0 and
// nothing holds the counter; clipped samples are still kept from the estimator.
// Register port: reg_we writes reg_wdata to reg_addr on the edge; reg_re reads reg_addr,
// reg_rdata holds the value after that edge (registered; rtl/axil_regs.v puts an AXI4-Lite
// slave in front). The register map is in README.md.
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
    // 1: every setting is a register; 0: the tuning settings (EPS, LAMBDA_K, KAPPA,
    // PERIOD, SETTLE, GATE, HARM, JUMP, ABGEN, AB_BOUND, CLIP, RADIUS, MONITOR) keep their
    // reset values, which synthesis folds into the logic (writes are ignored, reads return
    // them, except as OPT_MONITOR and OPT_JUMP say below); CTRL, INTERP, the staged coefficients and FAULT_STICKY stay writable (for a
    // small device, e.g. the iCE40 UP5K)
    parameter [0:0] OPT_TUNABLE = 1'b1,
    // 1: the signal monitor's fault checks (loss, over-range, stuck channel, glitch:
    // rtl/monitor.v); 0: none (the counter never holds, those fault bits are 0, RADIUS and
    // MONITOR read 0; the travel that gates the estimator stays: for a small device)
    parameter [0:0] OPT_MONITOR = 1'b1,
    // 1: the estimator's jump detector (rtl/estimator.v); 0: none (JUMP reads 0x8000,
    // disabled, and JUMPS 0: for a small device)
    parameter [0:0] OPT_JUMP = 1'b1,
    // lanes of the estimator's RLS engine, 1 or 2 (2: four more DSP blocks, shorter
    // programs: rtl/rls_engine.v, sim/model/estimator.py CYCLES_BY_LANES)
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
    // register port
    input  wire                      reg_we,
    input  wire                      reg_re,
    input  wire [5:0]                reg_addr,
    input  wire [31:0]               reg_wdata,
    output reg  [31:0]               reg_rdata,
    // per-sample results
    output wire                      m_valid,
    output wire signed [COUNT_W-1:0] m_count,
    output wire [10:0]               m_fault,
    // A/B outputs (paced quadrature following m_count, or the Eq. 12 pulses)
    output wire                      m_a,
    output wire                      m_b,
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

    // ---- registers ------------------------------------------------------------------------
    localparam [31:0] ID = 32'h46510004;        // "FQ", version 0.4
    reg [8:0]  r_interp = 9'd100;               // n
    reg [15:0] r_eps = 16'd1638;                // u0.15 (0.05); a write on edge w (or rst)
                                                // decides the pulses from w + 3 (rtl/pulse.v)
    reg [4:0]  r_lam_k = 5'd8;                  // lambda = 1/(1 + 2**-k)
    reg [15:0] r_kappa = 16'h4000;              // u8.8 (64)
    // u11.4 5 max(kappa, 1/256) >> 4, the estimator's trace bound, formed with the write
    // (rtl/estimator.v; a register, so no adder lies between kappa and the comparison);
    // 5 * 255.996 = 1279.98 needs the 11 integer bits
    reg [14:0] r_kappa5 = 15'd5120;
    reg [15:0] r_period = 16'd0;                // updates between resets (0: never)
    reg [9:0]  r_settle = 10'd32;               // updates after a reset before a commit
    reg [12:0] r_gate = 13'd64;                 // u13 phase progress between updates
    reg        r_jump_off = 1'b0;               // JUMP bit 15: jump detector disabled
    reg [10:0] r_jump_min = 11'd41;             // JUMP [10:0]: its floor, s3.13 |e| units
    reg [10:0] r_sticky = 11'd0;                // sticky fault bits, write 1 to clear
    reg        r_cmode = 1'b0;                  // CTRL bit 3: counter mode, 0 phase, 1 edge
    reg        r_happly = 1'b1;                 // HARM bit 0: apply the harmonic correction
    reg        r_hlearn = 1'b1;                 // HARM bit 1: learn the harmonic table
    reg [1:0]  r_hmu = 2'd1;                    // HARM [5:4]: LMS step 2^-(3 + r_hmu)
    reg        r_hclear = 1'b0;                 // HARM bit 8 written 1: clear (pulse)
    reg [7:0]  r_absep = 8'd4;                  // ABGEN [7:0]: min clocks between A/B edges
    reg        r_absrc = 1'b0;                  // ABGEN bit 8: A/B = Eq. 12 pulses
    reg [15:0] r_abbound = 16'd1024;            // AB_BOUND: backlog bound (counts)
    reg [15:0] r_clip = 16'd32512;              // CLIP: u16 |u| at or above: clipped
    reg [15:0] r_loss = 16'd3277;               // RADIUS [15:0]: u16 radius, loss (0.2)
    reg [15:0] r_over = 16'd22118;              // RADIUS [31:16]: over-range (1.35)
    reg [3:0]  r_glitch = 4'd10;                // MONITOR [3:0]: max |phase accel.| 2^K
    reg [7:0]  r_stuckn = 8'd8;                 // MONITOR [23:16]: stuck after n samples
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
    // staged bundle (writes to 0x0b..0x10), handed to the fast path by a LOAD (CTRL 1)
    reg [1:0]  st_g = G_INIT;
    reg signed [15:0] st_m1 = 0, st_m2 = 0, st_c1 = 16'sd8192, st_c12 = 0, st_c2 = 16'sd8192;
    reg        req_reset = 1'b0;
    reg        req_load = 1'b0;                 // CTRL bit 1: LOAD (a pulse)
    reg        req_cap = 1'b0;                  // CTRL bit 2: capture the count (a pulse)
    always @(posedge clk) begin
        req_reset <= 1'b0;
        req_load <= 1'b0;
        req_cap <= 1'b0;
        r_hclear <= 1'b0;
        if (reg_we) begin
            case (reg_addr)
                6'h00: begin
                    req_reset <= reg_wdata[0];
                    req_load <= reg_wdata[1];
                    req_cap <= reg_wdata[2];
                    r_cmode <= reg_wdata[3];
                end
                6'h01: r_interp <= reg_wdata[8:0];
                6'h0b: st_g <= reg_wdata[1:0];
                6'h0c: st_m1 <= reg_wdata[15:0];
                6'h0d: st_m2 <= reg_wdata[15:0];
                6'h0e: st_c1 <= reg_wdata[15:0];
                6'h0f: st_c12 <= reg_wdata[15:0];
                6'h10: st_c2 <= reg_wdata[15:0];
                default: ;
            endcase
        end
        if (reg_we && OPT_TUNABLE) begin
            case (reg_addr)
                6'h02: r_eps <= reg_wdata[15:0];
                6'h03: r_lam_k <= reg_wdata[4:0];
                6'h04: begin
                    r_kappa <= reg_wdata[15:0];
                    r_kappa5 <= kappa5(reg_wdata[15:0]);
                end
                6'h05: r_period <= reg_wdata[15:0];
                6'h06: r_settle <= reg_wdata[9:0];
                6'h07: r_gate <= reg_wdata[12:0];
                6'h12: begin
                    r_happly <= reg_wdata[0];
                    r_hlearn <= reg_wdata[1];
                    r_hmu <= reg_wdata[5:4];
                    r_hclear <= reg_wdata[8];
                end
                6'h13: begin
                    r_jump_off <= reg_wdata[15];
                    r_jump_min <= reg_wdata[10:0];
                end
                6'h15: begin
                    r_absep <= reg_wdata[7:0];
                    r_absrc <= reg_wdata[8];
                end
                6'h16: r_abbound <= reg_wdata[15:0];
                6'h18: r_clip <= reg_wdata[15:0];
                6'h19: begin
                    r_loss <= reg_wdata[15:0];
                    r_over <= reg_wdata[31:16];
                end
                6'h1a: begin
                    r_glitch <= reg_wdata[3:0];
                    r_stuckn <= reg_wdata[23:16];
                end
                default: ;
            endcase
        end
        // write 1 to clear; a fault arriving on the same edge stays set
        r_sticky <= (r_sticky & ~((reg_we && reg_addr == 6'h0a) ? reg_wdata[10:0] : 11'd0))
                    | (m_valid ? m_fault : 11'd0);
        if (rst) begin
            r_interp <= 9'd100; r_eps <= 16'd1638; r_lam_k <= 5'd8; r_kappa <= 16'h4000;
            r_kappa5 <= 15'd5120;
            r_period <= 16'd0; r_settle <= 10'd32; r_gate <= 13'd64;
            r_jump_off <= 1'b0; r_jump_min <= 11'd41;
            r_sticky <= 11'd0; req_reset <= 1'b0; req_load <= 1'b0; req_cap <= 1'b0;
            r_cmode <= 1'b0;
            r_clip <= 16'd32512; r_loss <= 16'd3277; r_over <= 16'd22118;
            r_glitch <= 4'd10; r_stuckn <= 8'd8;
            st_g <= G_INIT; st_m1 <= 0; st_m2 <= 0; st_c1 <= 16'sd8192; st_c12 <= 0;
            st_c2 <= 16'sd8192;
            r_happly <= 1'b1; r_hlearn <= 1'b1; r_hmu <= 2'd1; r_hclear <= 1'b0;
            r_absep <= 8'd4; r_absrc <= 1'b0; r_abbound <= 16'd1024;
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
                .ph_i(l_ph), .apply_i(r_happly), .learn_i(r_hlearn), .mu_i(r_hmu),
                .clear_i(r_hclear), .valid_o(h_valid), .phase_o(h_phase),
                .phase_c_o(h_phase_c)
            );
        end else begin : g_noharm
            phase u_phase (
                .clk(clk), .valid_i(o_valid), .oct2_i(o_oct2), .neg_i(o_neg), .ph_i(l_ph),
                .valid_o(h_valid), .phase_o(h_phase), .phase_c_o(h_phase_c)
            );
            wire unused_h = &{1'b0, r_happly, r_hlearn, r_hmu, r_hclear, 1'b0};
        end
    endgenerate
    // ---- signal monitor: faults, the counter's hold (stage t+6 .. t+7), the travel ------------
    wire mon_hold, mon_excl, mon_loss, mon_over, mon_stuck, mon_glitch;
    wire [19:0] mon_travel;
    monitor #(.OPT_MONITOR(OPT_MONITOR)) u_monitor (
        .clk(clk), .rst(rst), .valid0_i(c_v0), .raw1_i(c_raw1), .raw2_i(c_raw2),
        .clip_i(c_clip), .ref_i(b_ref), .ax_i(c_ax), .ay_i(c_ay), .xn_i(c_xn), .yn_i(c_yn), .pvalid_i(h_valid), .phase_i(h_phase),
        .loss_th_i(r_loss), .over_th_i(r_over), .glitch_k_i(r_glitch),
        .stuck_n_i(r_stuckn), .hold_o(mon_hold), .excl_o(mon_excl), .loss_o(mon_loss),
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
    wire k_ovs, k_ill;
    wire [15:0] k_ill_count;
    counter #(.COUNT_W(COUNT_W)) u_counter (
        .clk(clk), .rst(rst), .valid_i(h_valid), .hold_i(mon_hold), .phase_i(h_phase_c),
        .prod_i(n_prod),
        .n_i(r_interp), .mode_i(r_cmode), .pv_i(p_valid), .a_i(p_a), .b_i(p_b),
        .valid_o(m_valid), .count_o(m_count), .ovs_o(k_ovs), .ill_o(k_ill),
        .ill_count_o(k_ill_count)
    );
    // ---- t+9: paced A/B ----------------------------------------------------------------------------
    wire g_a, g_b, g_ovf, g_sticky;
    wire signed [COUNT_W-1:0] g_pos;
    wire signed [15:0] g_backlog;
    abgen #(.COUNT_W(COUNT_W), .OPT_TUNABLE(OPT_TUNABLE)) u_abgen (
        .clk(clk), .rst(rst), .target_i(m_count), .sep_i(r_absep), .bound_i(r_abbound),
        .a_o(g_a), .b_o(g_b), .pos_o(g_pos), .backlog_o(g_backlog), .ovf_o(g_ovf),
        .ovf_sticky_o(g_sticky)
    );
    assign m_a = r_absrc ? p_a : g_a;
    assign m_b = r_absrc ? p_b : g_b;

    // ---- estimator: every sample on arrival (t), its fine phase PHASE_AT = 6 edges after (t+6) -----
    estimator #(.TABLE_DIR(TABLE_DIR), .G_INIT(G_INIT), .PH_DELAY(PHASE_AT),
                .ENGINE_LANES(ENGINE_LANES), .OPT_EXT_ENGINE(OPT_EXT_ENGINE),
                .EXT_PERIOD(EXT_PERIOD),
                .OPT_TUNABLE(OPT_TUNABLE)) u_est (
        .clk(clk), .rst(rst),
        .smp_valid_i(c_v0), .u1_i(c_raw1), .u2_i(c_raw2), .amax_i(c_amax),
        .ph_valid_i(h_valid), .phase_i(h_phase), .excl_i(mon_excl),
        .travel_i(mon_travel),
        .load_i(req_load), .ld_g_i(st_g), .ld_m1_i(st_m1), .ld_m2_i(st_m2), .ld_c1_i(st_c1),
        .ld_c12_i(st_c12), .ld_c2_i(st_c2),
        .req_reset_i(req_reset), .lam_k_i(r_lam_k), .kappa_i(r_kappa),
        .kappa5_i(r_kappa5),
        .period_i(r_period), .settle_i(r_settle), .gate_i(r_gate),
        .jump_on_i(OPT_JUMP && !r_jump_off), .jump_min_i(r_jump_min), .jumps_o(e_jumps),
        .g_o(b_g), .m1_o(b_m1), .m2_o(b_m2), .c1_o(b_c1), .c12_o(b_c12), .c2_o(b_c2),
        .uncal_o(b_uncal), .hold_o(b_hold), .loaded_o(b_loaded), .ref_o(b_ref),
        .updates_o(e_updates), .sat_o(e_sat),
        .tdm_ok_i(tdm_ok_i), .eng_cmd_o(eng_cmd_o), .eng_rsp_i(eng_rsp_i)
    );

    // ---- fault bits, carried with the sample -------------------------------------------------
    // Index k of each delay line holds the value registered k + 1 edges after the flag's
    // own edge: flags of edge t (clip, gain, offset saturation, and the bundle's uncal and
    // hold, sampled with the sample) reach index LATENCY - 1 on edge t + LATENCY, rsat
    // (edge t + 2) index LATENCY - 3.
    reg [LATENCY-1:0] clip_d = 0, nsat_d = 0, dsat_d = 0, uncal_d = 0, hold_d = 0;
    reg [LATENCY-CORR_AT-1:0] rsat_d = 0;
    reg uncal0 = 1'b1, hold0 = 1'b0;
    always @(posedge clk) begin
        uncal0 <= b_uncal;
        hold0  <= b_hold;
        clip_d  <= {clip_d[LATENCY-2:0], c_clip};
        nsat_d  <= {nsat_d[LATENCY-2:0], c_nsat};
        dsat_d  <= {dsat_d[LATENCY-2:0], c_dsat};
        uncal_d <= {uncal_d[LATENCY-2:0], uncal0};
        hold_d  <= {hold_d[LATENCY-2:0], hold0};
        rsat_d  <= {rsat_d[LATENCY-CORR_AT-2:0], c_rsat};
    end
    // the monitor's flags are registered on t + 7, one edge before the output
    reg [3:0] mon_q = 4'd0;                      // {glitch, stuck, over, loss}
    always @(posedge clk)
        mon_q <= {mon_glitch, mon_stuck, mon_over, mon_loss};
    assign m_fault = {mon_q, g_sticky, hold_d[LATENCY-1], uncal_d[LATENCY-1], k_ovs,
                      dsat_d[LATENCY-1] | rsat_d[LATENCY-CORR_AT-1], nsat_d[LATENCY-1],
                      clip_d[LATENCY-1]};

    // ---- register read-back (registered) ---------------------------------------------------------
    always @(posedge clk) begin
        if (reg_re) begin
            case (reg_addr)
                6'h00: reg_rdata <= {27'd0, b_loaded, r_cmode, e_sat, b_hold, b_uncal};
                6'h01: reg_rdata <= {23'd0, r_interp};
                6'h02: reg_rdata <= {16'd0, r_eps};
                6'h03: reg_rdata <= {27'd0, r_lam_k};
                6'h04: reg_rdata <= {16'd0, r_kappa};
                6'h05: reg_rdata <= {16'd0, r_period};
                6'h06: reg_rdata <= {22'd0, r_settle};
                6'h07: reg_rdata <= {19'd0, r_gate};
                6'h08: reg_rdata <= {{(32-COUNT_W+1){m_count[COUNT_W-1]}}, m_count[COUNT_W-2:0]};
                6'h09: reg_rdata <= {16'd0, k_ill_count};
                6'h0a: reg_rdata <= {21'd0, r_sticky};
                6'h0b: reg_rdata <= {30'd0, b_g};
                6'h0c: reg_rdata <= {{16{b_m1[15]}}, b_m1};
                6'h0d: reg_rdata <= {{16{b_m2[15]}}, b_m2};
                6'h0e: reg_rdata <= {{16{b_c1[15]}}, b_c1};
                6'h0f: reg_rdata <= {{16{b_c12[15]}}, b_c12};
                6'h10: reg_rdata <= {{16{b_c2[15]}}, b_c2};
                6'h11: reg_rdata <= e_updates;
                6'h12: reg_rdata <= OPT_HARMONIC ? {26'd0, r_hmu, 2'd0, r_hlearn, r_happly} : 32'd0;
                6'h13: reg_rdata <= OPT_JUMP ? {16'd0, r_jump_off, 4'd0, r_jump_min} : 32'h8000;
                6'h14: reg_rdata <= OPT_JUMP ? {16'd0, e_jumps} : 32'd0;
                6'h15: reg_rdata <= {23'd0, r_absrc, r_absep};
                6'h16: reg_rdata <= {16'd0, r_abbound};
                6'h17: reg_rdata <= {{16{g_backlog[15]}}, g_backlog};
                6'h18: reg_rdata <= {16'd0, r_clip};
                6'h19: reg_rdata <= OPT_MONITOR ? {r_over, r_loss} : 32'd0;
                6'h1a: reg_rdata <= OPT_MONITOR ? {8'd0, r_stuckn, 12'd0, r_glitch} : 32'd0;
                6'h1b: reg_rdata <= {{(32-COUNT_W+1){r_cap[COUNT_W-1]}}, r_cap[COUNT_W-2:0]};
                6'h1c: reg_rdata <= {12'd0, mon_travel};
                6'h1f: reg_rdata <= ID;
                default: reg_rdata <= 32'd0;
            endcase
        end
    end
    initial reg_rdata = 32'd0;
    // CTRL bit 2: the count captured (a coherent copy for a narrow or slow host link)
    reg signed [COUNT_W-1:0] r_cap = 0;
    always @(posedge clk) begin
        if (req_cap)
            r_cap <= m_count;
        if (rst)
            r_cap <= 0;
    end
    wire unused = &{1'b0, reg_wdata[31:16], l_pn, n_valid, k_ill, g_pos, g_ovf, 1'b0};
endmodule
`resetall
