`timescale 1ns / 1ps
`default_nettype none
// finequad_core: adaptive quadrature interpolator (Ulu, Gecer Ulu, Cakmakci 2014, and
// beyond). Bit-true model: sim/model/core.py. One sample per clock on the fast path.
//
//   s_u1/s_u2 --> align --> correct (gain, Eq. 9) --> octant (Table 2) --> lut (Table 1)
//        |                                                  | phase            |
//        |                                                  v                  v
//        +---------- raw sample, delayed --------> estimator (Eqs. 3-8)   pulse (Eq. 12)
//                                                  coefficient bundle ^       |
//                                                                        counter (x4)
// Latency: a sample strobed on edge t appears on m_* after edge t + LATENCY (16).
// Fault bits (m_fault): 0 clip, 1 gain saturation, 2 correction saturation,
// 3 counter (phase mode: overspeed, |phase step| >= 3/4 pi per sample; edge mode: both
// A and B changed, step lost), 4 not calibrated, 5 estimate held (last theta invalid).
// CTRL (0x00) write: bit 0 request a covariance reset (pulse), bit 3 counter mode
// (0 phase: count = 4 n phase, 1 edge: the paper's x4 decoder of A/B; reset 0).
// A CTRL write always writes bit 3: give the mode in use with a reset request.
// STATUS (0x00) read: bit 0 uncal, 1 hold, 2 estimator saturated, 3 counter mode.
// HARM (0x12): bit 0 apply, bit 1 learn, [5:4] mu - 3 (LMS step 2^-mu; reset 1, 1, 1:
// mu 4); writing bit 8 = 1 clears the harmonic table (a 64-clock RAM sweep) for the
// samples strobed on edges >= w - PHASE_AT (w the write edge). See rtl/harmonic.v.
module finequad_core #(
    parameter TABLE_DIR = "rtl/tables/",
    // ADC word width, 12..16, two's complement, MSB-aligned to s1.15 internally
    parameter ADC_W = 16,
    // sine table word width: 8, 10, 12 or 16
    parameter SIN_W = 10,
    // counter width
    parameter COUNT_W = 32,
    // 1: exact table (address |small|/|large|, atan rows), 0: the paper's uniform table
    parameter [0:0] TABLE_EXACT = 1'b1,
    // input gain after power-up
    parameter [1:0] G_INIT = 2'd0
) (
    input  wire                      clk,
    input  wire                      rst,
    // sample stream
    input  wire                      s_valid,
    input  wire signed [ADC_W-1:0]   s_u1,
    input  wire signed [ADC_W-1:0]   s_u2,
    // register interface (writes take effect on the edge; reads are combinational)
    input  wire                      reg_we,
    input  wire [4:0]                reg_addr,
    input  wire [31:0]               reg_wdata,
    output reg  [31:0]               reg_rdata,
    // per-sample results
    output wire                      m_valid,
    output wire signed [COUNT_W-1:0] m_count,
    output wire                      m_a,
    output wire                      m_b,
    output wire [5:0]                m_fault
);
    // pipeline: stage 0 (edge t), correct t+1..t+5, octant t+6..t+8, lut phase t+10
    // (estimator decision t+12), lut sines t+12, pulse t+13, counter t+14..t+16
    localparam LATENCY = 16;
    localparam PHASE_AT = 10;     // fine phase registered on edge t + PHASE_AT
    localparam CORR_AT = 5;       // correct outputs registered on edge t + CORR_AT
    localparam AB_AT = 13;        // pulse outputs registered on edge t + AB_AT

    // ---- registers ------------------------------------------------------------------------
    localparam [31:0] ID = 32'h46510001;        // "FQ", version 0.1
    reg [8:0]  r_interp = 9'd100;               // n
    reg [15:0] r_eps = 16'd1638;                // u0.15 (0.05)
    reg [4:0]  r_lam_k = 5'd8;                  // lambda = 1/(1 + 2**-k)
    reg [15:0] r_kappa = 16'h4000;              // u8.8 (64)
    reg [15:0] r_period = 16'd0;                // updates between resets (0: never)
    reg [9:0]  r_settle = 10'd32;               // updates after a reset before a commit
    reg [12:0] r_gate = 13'd64;                 // u13 phase progress between updates
    reg        r_jump_off = 1'b0;               // JUMP bit 15: jump detector disabled
    reg [10:0] r_jump_min = 11'd41;             // JUMP [10:0]: its floor, s3.13 |e| units
    reg [5:0]  r_sticky = 6'd0;                 // sticky fault bits, write 1 to clear
    reg        r_cmode = 1'b0;                  // CTRL bit 3: counter mode, 0 phase, 1 edge
    reg        r_happly = 1'b1;                 // HARM bit 0: apply the harmonic correction
    reg        r_hlearn = 1'b1;                 // HARM bit 1: learn the harmonic table
    reg [1:0]  r_hmu = 2'd1;                    // HARM [5:4]: LMS step 2^-(3 + r_hmu)
    reg        r_hclear = 1'b0;                 // HARM bit 8 written 1: clear (pulse)
    reg        req_reset = 1'b0;
    always @(posedge clk) begin
        req_reset <= 1'b0;
        r_hclear <= 1'b0;
        if (reg_we) begin
            case (reg_addr)
                5'h00: begin
                    req_reset <= reg_wdata[0];
                    r_cmode <= reg_wdata[3];
                end
                5'h01: r_interp <= reg_wdata[8:0];
                5'h02: r_eps <= reg_wdata[15:0];
                5'h03: r_lam_k <= reg_wdata[4:0];
                5'h04: r_kappa <= reg_wdata[15:0];
                5'h05: r_period <= reg_wdata[15:0];
                5'h06: r_settle <= reg_wdata[9:0];
                5'h07: r_gate <= reg_wdata[12:0];
                5'h12: begin
                    r_happly <= reg_wdata[0];
                    r_hlearn <= reg_wdata[1];
                    r_hmu <= reg_wdata[5:4];
                    r_hclear <= reg_wdata[8];
                end
                5'h13: begin
                    r_jump_off <= reg_wdata[15];
                    r_jump_min <= reg_wdata[10:0];
                end
                default: ;
            endcase
        end
        // write 1 to clear; a fault arriving on the same edge stays set
        r_sticky <= (r_sticky & ~((reg_we && reg_addr == 5'h0a) ? reg_wdata[5:0] : 6'd0))
                    | (m_valid ? m_fault : 6'd0);
        if (rst) begin
            r_interp <= 9'd100; r_eps <= 16'd1638; r_lam_k <= 5'd8; r_kappa <= 16'h4000;
            r_period <= 16'd0; r_settle <= 10'd32; r_gate <= 13'd64;
            r_jump_off <= 1'b0; r_jump_min <= 11'd41;
            r_sticky <= 6'd0; req_reset <= 1'b0; r_cmode <= 1'b0;
            r_happly <= 1'b1; r_hlearn <= 1'b1; r_hmu <= 2'd1; r_hclear <= 1'b0;
        end
    end

    // ---- stage 0: align ---------------------------------------------------------------------
    reg signed [15:0] u1r = 0, u2r = 0;
    reg v0 = 1'b0, clip0 = 1'b0;
    wire signed [ADC_W-1:0] rail_hi = {1'b0, {(ADC_W-1){1'b1}}};
    wire signed [ADC_W-1:0] rail_lo = {1'b1, {(ADC_W-1){1'b0}}};
    always @(posedge clk) begin
        u1r <= $signed({s_u1, {(16-ADC_W){1'b0}}});
        u2r <= $signed({s_u2, {(16-ADC_W){1'b0}}});
        clip0 <= (s_u1 == rail_hi) || (s_u1 == rail_lo) || (s_u2 == rail_hi) || (s_u2 == rail_lo);
        v0 <= s_valid;
        if (rst)
            v0 <= 1'b0;
    end

    // ---- estimator and its bundle -------------------------------------------------------------
    wire [1:0] b_g;
    wire signed [15:0] b_m1, b_m2, b_c1, b_c12, b_c2;
    wire b_uncal, b_hold, e_sat;
    wire [31:0] e_updates;
    wire [15:0] e_jumps;
    wire ph_valid;
    wire [12:0] phase;
    // raw sample delayed to the phase stage (edge t + PHASE_AT)
    reg signed [15:0] u1d [0:PHASE_AT-1];
    reg signed [15:0] u2d [0:PHASE_AT-1];
    integer di;
    always @(posedge clk) begin
        u1d[0] <= u1r;
        u2d[0] <= u2r;
        for (di = 1; di < PHASE_AT; di = di + 1) begin
            u1d[di] <= u1d[di-1];
            u2d[di] <= u2d[di-1];
        end
    end
    // max(|u1|, |u2|) (saturated to 15 bits) for the estimator's peak detector, formed in
    // two registered steps alongside the delay line so it arrives with the sample
    wire [15:0] ab1 = u1d[PHASE_AT-3][15] ? -u1d[PHASE_AT-3] : u1d[PHASE_AT-3];
    wire [15:0] ab2 = u2d[PHASE_AT-3][15] ? -u2d[PHASE_AT-3] : u2d[PHASE_AT-3];
    reg  [14:0] abs1 = 0, abs2 = 0, amax = 0;
    always @(posedge clk) begin
        abs1 <= ab1[15] ? 15'h7fff : ab1[14:0];
        abs2 <= ab2[15] ? 15'h7fff : ab2[14:0];
        amax <= (abs1 > abs2) ? abs1 : abs2;
    end
    estimator #(.TABLE_DIR(TABLE_DIR), .G_INIT(G_INIT)) u_est (
        .clk(clk), .rst(rst),
        .smp_valid_i(ph_valid), .u1_i(u1d[PHASE_AT-1]), .u2_i(u2d[PHASE_AT-1]),
        .amax_i(amax), .phase_i(phase),
        .req_reset_i(req_reset), .lam_k_i(r_lam_k), .kappa_i(r_kappa),
        .period_i(r_period), .settle_i(r_settle), .gate_i(r_gate),
        .jump_on_i(!r_jump_off), .jump_min_i(r_jump_min), .jumps_o(e_jumps),
        .g_o(b_g), .m1_o(b_m1), .m2_o(b_m2), .c1_o(b_c1), .c12_o(b_c12), .c2_o(b_c2),
        .uncal_o(b_uncal), .hold_o(b_hold), .updates_o(e_updates), .sat_o(e_sat)
    );

    // ---- fast path ------------------------------------------------------------------------
    wire c_valid, c_nsat, c_csat;
    wire signed [15:0] u1c, u2c;
    correct u_correct (
        .clk(clk), .valid_i(v0), .u1_i(u1r), .u2_i(u2r),
        .g_i(b_g), .m1_i(b_m1), .m2_i(b_m2), .c1_i(b_c1), .c12_i(b_c12), .c2_i(b_c2),
        .valid_o(c_valid), .u1c_o(u1c), .u2c_o(u2c), .nsat_o(c_nsat), .csat_o(c_csat)
    );
    wire o_valid, o_neg;
    wire [10:0] o_j;
    wire [1:0] o_oct2;
    octant #(.TABLE_DIR(TABLE_DIR), .TABLE_EXACT(TABLE_EXACT)) u_octant (
        .clk(clk), .valid_i(c_valid), .u1c_i(u1c), .u2c_i(u2c),
        .valid_o(o_valid), .j_o(o_j), .oct2_o(o_oct2), .neg_o(o_neg)
    );
    wire l_valid, l_cneg, l_sneg;
    wire [12:0] l_pn;
    wire [SIN_W-2:0] l_cmag, l_smag;
    lut #(.TABLE_DIR(TABLE_DIR), .TABLE_EXACT(TABLE_EXACT), .SIN_W(SIN_W)) u_lut (
        .clk(clk), .valid_i(o_valid), .j_i(o_j), .oct2_i(o_oct2), .neg_i(o_neg),
        .n_i(r_interp), .phase_valid_o(ph_valid), .phase_o(phase),
        .valid_o(l_valid), .pn_o(l_pn), .cos_mag_o(l_cmag), .cos_neg_o(l_cneg),
        .sin_mag_o(l_smag), .sin_neg_o(l_sneg)
    );
    wire p_valid, p_a, p_b;
    pulse #(.SIN_W(SIN_W)) u_pulse (
        .clk(clk), .rst(rst), .valid_i(l_valid),
        .cos_mag_i(l_cmag), .cos_neg_i(l_cneg), .sin_mag_i(l_smag), .sin_neg_i(l_sneg),
        .eps_i(r_eps), .valid_o(p_valid), .a_o(p_a), .b_o(p_b)
    );
    // harmonic compensation of the fine phase (rtl/harmonic.v, latency 3), from edge
    // t + PHASE_AT to t + AB_AT (aligned with A/B); a longer gap is padded after it
    localparam HARM_PAD = AB_AT - PHASE_AT - 3;
    wire        h_valid;
    wire [12:0] h_phase;
    harmonic u_harmonic (
        .clk(clk), .valid_i(ph_valid), .phase_i(phase),
        .apply_i(r_happly), .learn_i(r_hlearn), .mu_i(r_hmu), .clear_i(r_hclear),
        .valid_o(h_valid), .phase_o(h_phase)
    );
    wire [12:0] k_phase;
    generate
        if (HARM_PAD == 0) begin : g_nopad
            assign k_phase = h_phase;
        end else begin : g_pad
            reg [12:0] phd [0:HARM_PAD-1];
            integer pi;
            always @(posedge clk) begin
                phd[0] <= h_phase;
                for (pi = 1; pi < HARM_PAD; pi = pi + 1)
                    phd[pi] <= phd[pi-1];
            end
            assign k_phase = phd[HARM_PAD-1];
        end
    endgenerate
    wire k_illegal;
    wire [31:0] k_ill_count;
    counter #(.COUNT_W(COUNT_W)) u_counter (
        .clk(clk), .rst(rst), .valid_i(p_valid), .a_i(p_a), .b_i(p_b),
        .phase_i(k_phase),
        .n_i(r_interp), .mode_i(r_cmode),
        .valid_o(m_valid), .count_o(m_count), .a_o(m_a), .b_o(m_b),
        .illegal_o(k_illegal), .illegal_count_o(k_ill_count)
    );

    // ---- fault bits, carried with the sample -------------------------------------------------
    // clip: registered on edge t; bundle flags: sampled on edge t+1 with the bundle;
    // saturations from correct (edge t + CORR_AT); illegal from the counter (t + LATENCY).
    // Index k of each delay line holds the value registered k+1 edges later.
    reg [LATENCY-1:0] clip_d = 0, uncal_d = 0, hold_d = 0;
    reg [LATENCY-CORR_AT-1:0] nsat_d = 0, csat_d = 0;
    always @(posedge clk) begin
        clip_d  <= {clip_d[LATENCY-2:0], clip0};
        uncal_d <= {uncal_d[LATENCY-2:0], b_uncal};
        hold_d  <= {hold_d[LATENCY-2:0], b_hold};
        nsat_d  <= {nsat_d[LATENCY-CORR_AT-2:0], c_nsat};
        csat_d  <= {csat_d[LATENCY-CORR_AT-2:0], c_csat};
    end
    wire unused = &{1'b0, reg_wdata[31:16], l_pn, h_valid, 1'b0};
    assign m_fault = {hold_d[LATENCY-1], uncal_d[LATENCY-1], k_illegal,
                      csat_d[LATENCY-CORR_AT-1], nsat_d[LATENCY-CORR_AT-1], clip_d[LATENCY-1]};

    // ---- register read-back --------------------------------------------------------------------
    always @* begin
        case (reg_addr)
            5'h00: reg_rdata = {28'd0, r_cmode, e_sat, b_hold, b_uncal};
            5'h01: reg_rdata = {23'd0, r_interp};
            5'h02: reg_rdata = {16'd0, r_eps};
            5'h03: reg_rdata = {27'd0, r_lam_k};
            5'h04: reg_rdata = {16'd0, r_kappa};
            5'h05: reg_rdata = {16'd0, r_period};
            5'h06: reg_rdata = {22'd0, r_settle};
            5'h07: reg_rdata = {19'd0, r_gate};
            5'h08: reg_rdata = {{(32-COUNT_W+1){m_count[COUNT_W-1]}}, m_count[COUNT_W-2:0]};
            5'h09: reg_rdata = k_ill_count;
            5'h0a: reg_rdata = {26'd0, r_sticky};
            5'h0b: reg_rdata = {30'd0, b_g};
            5'h0c: reg_rdata = {{16{b_m1[15]}}, b_m1};
            5'h0d: reg_rdata = {{16{b_m2[15]}}, b_m2};
            5'h0e: reg_rdata = {{16{b_c1[15]}}, b_c1};
            5'h0f: reg_rdata = {{16{b_c12[15]}}, b_c12};
            5'h10: reg_rdata = {{16{b_c2[15]}}, b_c2};
            5'h11: reg_rdata = e_updates;
            5'h12: reg_rdata = {26'd0, r_hmu, 2'd0, r_hlearn, r_happly};
            5'h13: reg_rdata = {16'd0, r_jump_off, 4'd0, r_jump_min};
            5'h14: reg_rdata = {16'd0, e_jumps};
            5'h1f: reg_rdata = ID;
            default: reg_rdata = 32'd0;
        endcase
    end
endmodule
`resetall
