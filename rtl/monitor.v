`timescale 1ns / 1ps
`default_nettype none
// monitor: signal faults, the counter's hold and the travel along the scale (beyond the
// paper). Bit-true model: sim/model/monitor.py, where each check is argued.
//
// Per sample strobed on edge t (fixed latencies from t; samples may come every clock):
//   t      raw1_i, raw2_i, valid0_i   s1.15 aligned codes (rtl/correct.v, registered on t)
//          ref_i is sampled like the bundle (the value before edge t is the sample's)
//   t + 1  run_c = consecutive unchanged codes of channel c (u8, saturating); chg_c = the
//          code changed; run_ok_c = STUCK_N > 0 and run_c >= STUCK_N
//   t + 2  ax_i, ay_i, xn_i, yn_i     u15 |u1c|, |u2c| (s2.14: calibrated circle 16384),
//          their signs
//   t + 3  o_1 = u2c, o_2 = u1c (the other channel, s17); max, min of ax, ay
//   t      sv_i strobes the sample's bundle (g, c1, c2, as rtl/correct.v samples it) and
//          the code step: sc_c, sg, sst registered; the previous sample's pc_c, pg
//   t + 1  rebase = (g, c1, c2) differ from the previous sample's; per channel E =
//          msb(|c_c|) + 16 - ADC_W + code_step + g, m = the 2 bits below the msb
//   t + 2  SPAN_K[E & 1][m] 2^(E >> 1) / 16 (u19; 0 for c = 0)
//   t + 3  span_c = that clamped to [2048, 32767] (u15: sim/model/monitor.py
//          stuck_span(), where the bound is argued)
//   t + 4  x_c = o_c - snap_c (s18); det_c = run_ok_c and x_c outside [-sp_c, sp_c - 1]
//          and not rebase (sp_c: the span stored with the snapshot); stk_c <= !chg_c and
//          (stk_c or det_c); snap_c <= o_c, sp_c <= span_c if chg_c or rebase; stuck =
//          stk_1 or stk_2 (as updated)
//          r = max + min >> 2 + min >> 3           u16 radius (alpha-max-plus-beta-min)
//   t + 5  loss = ref and r < LOSS, dead = ref and r < FLOOR, over = ref and r > OVER
//   t + 6  per channel: the stuck latch, the code change (t + 3) and the signs (t + 2)
//   Every per-sample recurrence (run, stk, snap, and stage H below) is one carry chain
//   deep, so samples may come on every clock.
//   H = the clock from t + 6 to t + 7: phase_i (u13 fine phase, before the harmonic
//          correction) registered on t + 6 with pvalid_i; pred = pf >> 3 (the line)
//          glitch = K > 0, chk == 2, not rc and wrap13(phase - pred) outside
//                   [-2^K, 2^K - 1] (K = glitch_k_i sampled on t + 5, the edge before
//                   H: a bit test, no compare chain)
//          hold_o = pvalid and (dead or stuck or glitch or (clip and over))
//                   (combinational in H: the counter does not take the phase,
//                   rtl/counter.v; a clipped code alone still counts, and so does a
//                   weak signal between FLOOR and LOSS)
//          coast_o = hold_o and lok and (dead or stuck or (clip and over) or a glitch
//                   coast: grun < COAST_MAX or clipped); line_o = pred: the counter
//                   follows the line instead of the phase
//          excl_o = hold_o or loss or clip or over while orun < 4095  (combinational in
//                   H: the estimator does not take the sample)
//   t + 7  loss_o, over_o, stuck_o, glitch_o (the sample's fault bits), lost_o;
//          orun <= over ? min(orun + 1, 4095) : 0; if accepted
//          (not hold), with d = wrap13(phase - ph_a): ph_a <= phase; while chk < 2 (the
//          line re-anchors) v <= 8 d, pf <= 8 phase + 8 d; else pf <= 8 phase + v
//          (v as before the sample) and, if the sample before was accepted too (acc),
//          v <= v + ((8 d - v) >>> 3) (s13.3, a running mean of the steps: one outlier
//          under the threshold moves it by 1/8 of its error) and mdev <= mdev +
//          ((16 |8 d - v| - mdev) >>> 4) (their spread); chk <= min(chk + 1, 2) (lok =
//          chk == 2: the line is known), rc <= 0, unc <= 0, w <= ((mdev >> 4) + 1) << 9 (mdev as before),
//          S <= S + ((U << 5) - S) >>> 5, U <= U + d, grun <= 0 only if acc (an accept
//          right after a coast keeps the count: a wrong line that meets the phase now
//          and then, coasting in between, still reaches COAST_MAX), acc <= 1;
//          coasting (coast_o): pf <= pf + v (the line goes on; ph_a and v stay; on the
//          first sample of one stuck channel pf <= its shadow line + its velocity, v <=
//          that velocity, and if that shadow line has parted from the line (prt_c, below)
//          unc <= 2^23, lost; else, while one channel is stuck and the signal is not dead,
//          a sign change of the working channel re-anchors: pf <= 8 cand + v, cand the
//          crossing (0 or 4096 for channel 2's, 2048 or 6144 for channel 1's) nearest
//          pred, and unc <= 0), unc <= min(unc + w, 2^23), w <= w + coast_acc (below
//          2^23), lost_o <= unc reached 2^23; a glitch coast: grun <= min(grun + 1,
//          COAST_MAX); a coast through dead, stuck or clip with over: rc <= 1 (the next
//          accepted sample is not tested against the line: the line may be off by up to
//          the uncertainty), chk kept, acc <= 0; otherwise held (no line: lok = 0, or
//          a glitch coast past COAST_MAX unclipped, the wrong line): chk <= 0, grun <= 0,
//          acc <= 0, rc <= 0, unc <= 2^23, lost_o <= 1 (the next two samples
//          re-anchor the line).
//          Per channel (the shadow lines sl_c, sv_c, u13.3 and s13.3): a sample whose
//          code changed sets them to the line and velocity after it, any other moves
//          sl_c by sv_c: the line as it would have coasted from the channel's last
//          change, so the coast of a stuck channel starts clear of the samples distorted
//          before the check caught it (sim/model/monitor.py). prt_c: the shadow line
//          and the line (both as after the sample before) were a quarter period or more
//          apart (s16 sl_c - pf outside [-2^14, 2^14 - 1]) on some sample since the
//          channel's code last changed; cleared by a change.
//          travel_o = S[24:5] (u20 phase units, wraps; the estimator's gate).
// Formats: U u20 (wraps), S u20.5 (wraps; the difference (U << 5) - S is taken as s25,
// and |U - S| stays below 2^19 at any speed below half a period per sample: 32 x 4096),
// snap s17 (|o| <= 32767, the difference s18), orun u12, run u8 and grun u5 saturate,
// ph_a u13 and pf, sl_c u13.3 wrap; unc u24 (2^-12 phase units, saturates at 2^23, a
// quarter period), w u26 (2^-12 units per sample; at most 2^25 from mdev, stops at 2^23
// + 4095 from coast_acc), mdev u20 (2^-7 units, at most 16 x 65535). w and mdev as stated
// here are wires: their registers (w_r, mdev_r) run one sample behind with the sample
// before's update pending, so the ECP5's longest paths (the phase through |8 d - v| into
// mdev, the hold into w) end in a register first; the values per sample are the same.
// Nothing overflows
// (the formal properties below and sim/formal/monitor.sby, for OPT_MONITOR = 1).
// OPT_MONITOR = 0 (a small device, e.g. the iCE40 UP5K): no fault checks: loss, over,
// stuck and glitch are 0, hold_o never, excl_o = pvalid_i and clip (a clipped sample is
// still not estimated); every sample is accepted, so U and S (the travel, the
// estimator's gate) follow every sample. The checks' logic drives nothing and synthesis
// removes it. sim/model/monitor.py Monitor(enabled=False) is the same.
module monitor #(
    parameter [0:0] OPT_MONITOR = 1'b1,
    parameter       ADC_W = 16              // the ADC port's width (rtl/correct.v)
) (
    input  wire               clk,
    input  wire               rst,
    // before edge t (sampled on t, as rtl/correct.v samples them)
    input  wire               sv_i,         // the sample's strobe
    input  wire [1:0]         g_i,          // the bundle's input gain 2^g
    input  wire signed [15:0] c1_i,         // s4.12 the bundle's c1 and c2
    input  wire signed [15:0] c2_i,
    input  wire [3:0]         code_step_i,  // u4 the converter's code step, 2^k port LSBs,
                                            // 0..8 (MONITOR.code_step's legal range)
    // edge t
    input  wire               valid0_i,
    input  wire signed [15:0] raw1_i,       // s1.15 aligned codes
    input  wire signed [15:0] raw2_i,
    input  wire               clip_i,       // a code at or near a rail (rtl/correct.v)
    input  wire               ref_i,        // the bundle is a calibration (handed over or
                                            // loaded): the radius checks are armed
    // edge t + 2
    input  wire [14:0]        ax_i,         // u15 |u1c|, s2.14 units
    input  wire [14:0]        ay_i,
    input  wire               xn_i,         // u1c < 0
    input  wire               yn_i,         // u2c < 0
    // edge t + 6
    input  wire               pvalid_i,
    input  wire [12:0]        phase_i,      // u13 fine phase (uncorrected)
    // registers
    input  wire [15:0]        loss_th_i,    // u16 radius (s2.14 units) below it: loss
    input  wire [15:0]        over_th_i,    // u16 radius above it: over-range
    input  wire [3:0]         glitch_k_i,   // max |phase acceleration| 2^K (0: off)
    input  wire [7:0]         stuck_n_i,    // u8 unchanged codes before stuck (0: off)
    input  wire [15:0]        floor_th_i,   // u16 radius below it: the phase not trusted
    input  wire [11:0]        coast_acc_i,  // u0.12 the coast's acceleration bound
    // stage H (combinational)
    output wire               hold_o,
    output wire               excl_o,
    output wire               coast_o,      // with hold_o: the count follows line_o
    output wire [12:0]        line_o,       // u13 the line at this sample (a register)
    // edge t + 7
    output reg                loss_o = 1'b0,
    output reg                over_o = 1'b0,
    output reg                stuck_o = 1'b0,
    output reg                glitch_o = 1'b0,
    output reg                lost_o = 1'b0, // the coast's uncertainty reached 1/4 period
    output wire [19:0]        travel_o      // u20 integer part of S
);
    localparam [11:0] OVER_PERSIST = 12'd4095;
    // glitches coasted in a row before an unclipped sample re-anchors the line: a burst
    // of interference is shorter; a line still off after 16 samples is the wrong line
    localparam [4:0]  COAST_MAX = 5'd16;

    // ---- t + 1: runs of unchanged codes ------------------------------------------------
    reg signed [15:0] prev1 = 0, prev2 = 0;
    reg [7:0] run1 = 0, run2 = 0;
    wire      eq1 = (raw1_i == prev1), eq2 = (raw2_i == prev2);
    wire [7:0] run1n = eq1 ? ((run1 == 8'hff) ? run1 : run1 + 1'b1) : 8'd0;
    wire [7:0] run2n = eq2 ? ((run2 == 8'hff) ? run2 : run2 + 1'b1) : 8'd0;
    // run_n >= N (N > 0) <=> the code is unchanged and run >= N - 1 (run saturates at 255)
    wire [7:0] n_m1 = stuck_n_i - 1'b1;
    reg       chg1_1 = 1'b0, chg2_1 = 1'b0, rok1_1 = 1'b0, rok2_1 = 1'b0;
    always @(posedge clk) begin
        if (valid0_i) begin
            prev1 <= raw1_i;
            prev2 <= raw2_i;
            run1 <= run1n;
            run2 <= run2n;
        end
        chg1_1 <= !eq1;
        chg2_1 <= !eq2;
        rok1_1 <= (stuck_n_i != 8'd0) && eq1 && (run1 >= n_m1);
        rok2_1 <= (stuck_n_i != 8'd0) && eq2 && (run2 >= n_m1);
        if (rst) begin
            prev1 <= 0; prev2 <= 0; run1 <= 0; run2 <= 0;
        end
    end
    // ---- t .. t + 3: the stuck spans of the sample's bundle ------------------------------
    reg [1:0]         sg = 2'd0, pg = 2'd0;
    reg signed [15:0] sc1 = 0, sc2 = 0, pc1 = 0, pc2 = 0;
    reg [3:0]         sst = 4'd0;
    always @(posedge clk) begin
        if (sv_i) begin
            {sg, sc1, sc2, sst} <= {g_i, c1_i, c2_i, code_step_i};
            {pg, pc1, pc2} <= {sg, sc1, sc2};
        end
        if (rst) begin
            sg <= 2'd0; sc1 <= 0; sc2 <= 0; sst <= 4'd0; pg <= 2'd0; pc1 <= 0; pc2 <= 0;
        end
    end
    // {zero, E, m} of |c| with the code step 2^sh (sh <= 15, E <= 30)
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [7:0] span_exp(input signed [15:0] c, input [4:0] sh);
        reg [15:0] a;
        reg [3:0]  e;
        reg [17:0] am;
        integer    k;
        begin
            a = c[15] ? -c : c;                   // |-32768| = 32768: bit 15
            e = 4'd0;
            for (k = 1; k < 16; k = k + 1)
                if (a[k])
                    e = k[3:0];
            am = {a, 2'b00} >> e;                 // the leading one at bit 2
            span_exp = {a == 16'd0, {1'b0, e} + sh, am[1:0]};
        end
    endfunction
    // K 2^(E >> 1) / 16 (exact where it reaches 2048: E >> 1 >= 4), 0 for c = 0 (u19)
    function automatic [18:0] span_shift(input [7:0] x);
        reg [7:0]  kk;
        reg [22:0] t;
        begin
            case ({x[2], x[1:0]})                // E & 1, m: SPAN_K of the model
                3'd0: kk = 8'd108; 3'd1: kk = 8'd118; 3'd2: kk = 8'd127; 3'd3: kk = 8'd136;
                3'd4: kk = 8'd152; 3'd5: kk = 8'd167; 3'd6: kk = 8'd180; default: kk = 8'd192;
            endcase
            t = {15'd0, kk} << x[6:3];
            span_shift = x[7] ? 19'd0 : t[22:4];
        end
    endfunction
    // clamped to [2048, 32767]: two bit tests
    function automatic [14:0] span_clamp(input [18:0] v);
        span_clamp = (v[18:11] == 8'd0) ? 15'd2048 : (|v[18:15]) ? 15'h7fff : v[14:0];
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    localparam integer SH0I = 16 - ADC_W;      // the port's LSB in s1.15 LSBs, 2^SH0
    localparam [4:0]   SH0 = SH0I[4:0];
    wire [4:0] sh = SH0 + {1'b0, sst} + {3'b000, sg};
    // ---- t + 2 .. t + 4: the other channel's excursion, the stuck latch -----------------
    reg        v1 = 1'b0, v2 = 1'b0, v3 = 1'b0;
    // the spans, stage by stage with the sample (clock enables: simulation skips them
    // between samples)
    reg  [7:0]  sx1_1 = 8'd0, sx2_1 = 8'd0;
    reg  [18:0] sv1_2 = 19'd0, sv2_2 = 19'd0;
    reg         reb_1 = 1'b0, reb_2 = 1'b0, reb_3 = 1'b0;
    reg  [14:0] sp1_3 = 15'd2048, sp2_3 = 15'd2048;
    always @(posedge clk) begin
        if (valid0_i) begin
            sx1_1 <= span_exp(sc1, sh);
            sx2_1 <= span_exp(sc2, sh);
            reb_1 <= {sg, sc1, sc2} != {pg, pc1, pc2};
        end
        if (v1) begin
            sv1_2 <= span_shift(sx1_1);
            sv2_2 <= span_shift(sx2_1);
            reb_2 <= reb_1;
        end
        if (v2) begin
            sp1_3 <= span_clamp(sv1_2);
            sp2_3 <= span_clamp(sv2_2);
            reb_3 <= reb_2;
        end
    end
    reg        chg1_2 = 1'b0, chg2_2 = 1'b0, rok1_2 = 1'b0, rok2_2 = 1'b0;
    reg        chg1_3 = 1'b0, chg2_3 = 1'b0, rok1_3 = 1'b0, rok2_3 = 1'b0;
    reg signed [16:0] o1 = 0, o2 = 0;            // t + 3: the other channel, signed
    reg        stk1 = 1'b0, stk2 = 1'b0, stuck4 = 1'b0;
    reg signed [16:0] snap1 = 0, snap2 = 0;
    wire signed [17:0] x1 = {o1[16], o1} - {snap1[16], snap1};
    wire signed [17:0] x2 = {o2[16], o2} - {snap2[16], snap2};
    reg [14:0] sp1 = 15'd2048, sp2 = 15'd2048;  // the spans stored with the snapshots
    wire far1 = !reb_3 && ((x1 >= $signed({3'b000, sp1})) || (x1 < -$signed({3'b000, sp1})));
    wire far2 = !reb_3 && ((x2 >= $signed({3'b000, sp2})) || (x2 < -$signed({3'b000, sp2})));
    wire stk1n = !chg1_3 && (stk1 || (rok1_3 && far1));
    wire stk2n = !chg2_3 && (stk2 || (rok2_3 && far2));
    always @(posedge clk) begin
        v1 <= valid0_i;
        v2 <= v1;
        v3 <= v2;
        {chg1_2, chg2_2, rok1_2, rok2_2} <= {chg1_1, chg2_1, rok1_1, rok2_1};
        {chg1_3, chg2_3, rok1_3, rok2_3} <= {chg1_2, chg2_2, rok1_2, rok2_2};
        o1 <= yn_i ? -$signed({2'b00, ay_i}) : $signed({2'b00, ay_i});
        o2 <= xn_i ? -$signed({2'b00, ax_i}) : $signed({2'b00, ax_i});
        stuck4 <= stk1n || stk2n;
        if (v3) begin
            stk1 <= stk1n;
            stk2 <= stk2n;
            if (chg1_3 || reb_3) begin
                snap1 <= o1;
                sp1 <= sp1_3;
            end
            if (chg2_3 || reb_3) begin
                snap2 <= o2;
                sp2 <= sp2_3;
            end
        end
        if (rst) begin
            v1 <= 1'b0; v2 <= 1'b0; v3 <= 1'b0; stk1 <= 1'b0; stk2 <= 1'b0;
            snap1 <= 0; snap2 <= 0; sp1 <= 15'd2048; sp2 <= 15'd2048;
        end
    end
    // the stuck flag of edge t + 4, at t + 6; per channel, the latches, the code changes
    // (t + 3) and the signs (t + 2) beside it, for the coast in H
    reg [1:0] stuck_d = 0;
    reg [1:0] st_5 = 0, st_6 = 0, chg_4 = 0, chg_5 = 0, chg_6 = 0;
    reg [1:0] sg_3 = 0, sg_4 = 0, sg_5 = 0, sg_6 = 0;       // {yn, xn}
    always @(posedge clk) begin
        stuck_d <= {stuck_d[0], stuck4};
        st_5 <= {stk2, stk1};
        st_6 <= st_5;
        {chg_4, chg_5, chg_6} <= {chg2_3, chg1_3, chg_4, chg_5};
        {sg_3, sg_4, sg_5, sg_6} <= {yn_i, xn_i, sg_3, sg_4, sg_5};
    end
    wire stuck = OPT_MONITOR && stuck_d[1];
    // the clip flag of edge t, at t + 5 (into `early`, below)
    reg [4:0] clip_d = 0;
    always @(posedge clk)
        clip_d <= {clip_d[3:0], clip_i};

    // ---- t .. t + 5: the radius ---------------------------------------------------------
    reg        ref0 = 1'b0, ref1 = 1'b0, ref2 = 1'b0, ref3 = 1'b0, ref4 = 1'b0;
    reg [14:0] mx3 = 0, mn3 = 0;
    reg [15:0] r4 = 0;
    reg        loss5 = 1'b0, over5 = 1'b0, loss6 = 1'b0, over6 = 1'b0;
    reg        dead5 = 1'b0, dead6 = 1'b0;
    always @(posedge clk) begin
        {ref0, ref1, ref2, ref3, ref4} <= {ref_i, ref0, ref1, ref2, ref3};
        mx3 <= (ay_i <= ax_i) ? ax_i : ay_i;
        mn3 <= (ay_i <= ax_i) ? ay_i : ax_i;
        r4 <= {1'b0, mx3} + {3'd0, mn3[14:2]} + {4'd0, mn3[14:3]};
        loss5 <= ref4 && (r4 < loss_th_i);
        dead5 <= ref4 && (r4 < floor_th_i);
        dead6 <= dead5;
        over5 <= ref4 && (r4 > over_th_i);
        loss6 <= loss5;
        over6 <= over5;
    end
    wire loss = OPT_MONITOR && loss6, over = OPT_MONITOR && over6;
    // dead, stuck or clip with over-range of the sample in H, combined on the edge before
    // (t + 6); clip alone for the estimator
    reg early = 1'b0, clip6 = 1'b0;
    always @(posedge clk) begin
        early <= OPT_MONITOR && (dead5 || stuck_d[0] || (clip_d[4] && over5));
        clip6 <= clip_d[4];
    end

    // ---- stage H ----------------------------------------------------------------------------
    reg [12:0] ph_a = 0;
    reg [15:0] pf = 0;          // u13.3 the line: the prediction of this sample's phase
    reg [1:0]  chk = 0;
    reg [19:0] u = 0;
    reg [24:0] s = 0;
    reg [11:0] orun = 0;
    reg [4:0]  grun = 0;        // glitches coasted since two samples in a row were accepted
    reg        acc = 1'b0;                                      // the sample before was accepted
    wire       lok = chk[1];    // the line is known (anchored): held samples coast along it
    reg        rc = 1'b0;       // a coast through dead, stuck or a rail: no glitch test next
    reg [23:0] unc = 0;         // u24 the coast's uncertainty, 2^-12 units (2^23: lost)
    // w, the coast's growth per sample, and mdev, the mean |8 d - v| it starts from,
    // retimed: the registers hold them one sample behind (w_r, mdev_r), with what the
    // sample before did to them (wacc, wadd; padv, pupd), so no path runs from the phase
    // through |8 d - v| into mdev, or from the hold into w
    reg [25:0] w_r = 0;         // u26 w before the sample before
    reg        wacc = 1'b0;     // the sample before was accepted
    reg [11:0] wadd = 12'd0;    // u0.12 coast_acc if the sample before coasted, else 0
    reg [19:0] mdev_r = 0;      // u20 mdev before the sample before (2^-7 units)
    reg [15:0] padv = 0;        // u16 |8 d - v| of the sample before
    reg        pupd = 1'b0;     // it updates mdev (accepted, chk == 2, acc)
    reg [15:0] sl1 = 0, sl2 = 0, sv1 = 0, sv2 = 0;   // the shadow lines and their velocities
    reg [1:0]  pst = 0, psg = 0;                     // the stuck latches, signs before
    reg        prt1 = 1'b0, prt2 = 1'b0;             // the shadow lines have parted
    wire [12:0] pred = pf[15:3];
    wire [12:0] e = phase_i - pred;                             // s13 off the line
    // e outside [-2^K, 2^K - 1] <=> a bit of e[11:K] differs from the sign e[12]; the
    // bits K..11 as a mask (all clear for K = 0, off, or K >= 12), registered from K on the
    // edge before (t + 5: K is sampled there); a set bit under the mask (e >= 0) and a
    // clear one (e < 0) are looked for side by side, and the sign only selects
    reg  [11:1] gmask = 11'd0;
    integer     kb;
    always @(posedge clk)
        for (kb = 1; kb < 12; kb = kb + 1)
            gmask[kb] <= (glitch_k_i != 4'd0) && (kb >= glitch_k_i);
    wire        big_p = |(e[11:1] & gmask);
    wire        big_n = |(~e[11:1] & gmask);
    wire        glitch = OPT_MONITOR && chk[1] && !rc && (e[12] ? big_n : big_p);
    assign hold_o = pvalid_i && (early || glitch);
    // a glitch alone coasts along the line (COAST_MAX coasts since two samples in a row
    // were accepted; a clipped sample, a channel on a rail, coasts on for as long as it lasts)
    wire        gco = glitch && !early && !(grun == COAST_MAX && !clip6);
    wire        coast = OPT_MONITOR && lok && (early || gco);
    assign coast_o = hold_o && coast;
    assign line_o = OPT_MONITOR ? pred : 13'd0;
    reg  signed [15:0] v = 0;                                   // s13.3 the line's velocity
    assign excl_o = hold_o || (pvalid_i && (loss || clip6 ||
                                            (over && (orun != OVER_PERSIST))));
    wire [12:0] d = phase_i - ph_a;                             // s13 step
    wire signed [16:0] dv = $signed({d, 3'b000}) - v;            // s14.3 8 d - v
    wire [15:0] adv = dv[16] ? -dv[15:0] : dv[15:0];             // |8 d - v| <= 65535
    wire signed [20:0] mdd = $signed({1'b0, padv, 4'b0000}) - $signed({1'b0, mdev_r});
    // u26 w after the sample before: an accept starts it from mdev before that accept's
    // update (mdev_r), a coast grows it by coast_acc below 2^23
    wire [25:0] w = wacc ? {mdev_r[19:4] + 17'd1, 9'd0}
                  : (w_r[25:23] == 3'd0) ? w_r + {14'd0, wadd} : w_r;
    wire [24:0] sd = {u, 5'd0} - s;                             // s25
    // one stuck channel (st_6[0]: channel 1): its shadow line on the latch's first sample,
    // else the working channel's zero crossing nearest the line
    wire        one = st_6[0] ^ st_6[1];
    wire        rise = one && (st_6[0] ? !pst[0] : !pst[1]);
    wire        sgch = st_6[0] ? (sg_6[1] != psg[1]) : (sg_6[0] != psg[0]);
    wire        anchor = one && !dead6 && sgch;
    wire [12:0] p2k = pred + 13'd2048;
    wire [12:0] cand = st_6[0] ? {p2k[12], 12'd0} : {pred[12], 1'b1, 11'd0};
    wire [26:0] usum = {3'b000, unc} + {1'b0, w};
    // the shadow lines against the line (both as after the sample before): a quarter
    // period or more apart (s16 outside [-2^14, 2^14 - 1]: the two top bits differ), or
    // so since the channel's code last changed
    wire [15:0] dl1 = sl1 - pf, dl2 = sl2 - pf;
    wire        part1 = prt1 || (dl1[15] != dl1[14]);
    wire        part2 = prt2 || (dl2[15] != dl2[14]);
    // the first sample of one stuck channel whose shadow line parted from the line: the
    // count may have followed the distorted phase across a period boundary
    wire        rlost = rise && (st_6[0] ? part1 : part2);
    wire        acc_ok = !hold_o;
    // the line and its velocity after the sample (the shadow lines start from them)
    reg  [15:0] pf_n;
    reg  signed [15:0] v_n;
    always @(*) begin
        pf_n = pf;
        v_n = v;
        if (acc_ok) begin
            if (!chk[1])
                v_n = {d, 3'b000};
            else if (acc)
                v_n = v + {{3{dv[16]}}, dv[15:3]};
            pf_n = {phase_i, 3'b000} + (chk[1] ? v : {d, 3'b000});
        end else if (coast) begin
            if (rise) begin
                pf_n = st_6[0] ? sl1 + sv1 : sl2 + sv2;
                v_n = st_6[0] ? sv1 : sv2;
            end else if (anchor)
                pf_n = {cand, 3'b000} + v;
            else
                pf_n = pf + v;
        end
    end
    always @(posedge clk) begin
        if (pvalid_i) begin
            loss_o <= loss;
            over_o <= over;
            stuck_o <= stuck;
            glitch_o <= glitch;
            orun <= !over ? 12'd0 : (orun == OVER_PERSIST) ? orun : orun + 1'b1;
            pf <= pf_n;
            v <= v_n;
            pst <= st_6;
            psg <= sg_6;
            prt1 <= !chg_6[0] && part1;
            prt2 <= !chg_6[1] && part2;
            sl1 <= chg_6[0] ? pf_n : sl1 + sv1;
            sv1 <= chg_6[0] ? v_n : sv1;
            sl2 <= chg_6[1] ? pf_n : sl2 + sv2;
            sv2 <= chg_6[1] ? v_n : sv2;
            w_r <= w;
            wacc <= acc_ok;
            wadd <= (!acc_ok && coast) ? coast_acc_i : 12'd0;
            if (pupd)
                mdev_r <= mdev_r + {{3{mdd[20]}}, mdd[20:4]};
            padv <= adv;
            pupd <= acc_ok && chk[1] && acc;
            if (acc_ok) begin
                ph_a <= phase_i;
                chk <= chk[1] ? chk : chk + 1'b1;
                rc <= 1'b0;
                s <= s + {{5{sd[24]}}, sd[24:5]};
                u <= u + {{7{d[12]}}, d};
                if (acc)                       // two in a row: the line holds
                    grun <= 5'd0;
                acc <= 1'b1;
                unc <= 24'd0;
                lost_o <= 1'b0;
            end else if (coast) begin
                unc <= (anchor && !rise) ? 24'd0 : (rlost || (|usum[26:23])) ? 24'h800000
                                                                             : usum[23:0];
                lost_o <= !(anchor && !rise) && (rlost || (|usum[26:23]));
                if (early)
                    rc <= 1'b1;
                else
                    grun <= (grun == COAST_MAX) ? grun : grun + 1'b1;
                acc <= 1'b0;
            end else begin                     // no line to coast along: the travel is lost
                chk <= 2'd0;
                grun <= 5'd0;
                acc <= 1'b0;
                rc <= 1'b0;
                unc <= 24'h800000;
                lost_o <= OPT_MONITOR;
            end
        end
        if (rst) begin
            loss_o <= 1'b0; over_o <= 1'b0; stuck_o <= 1'b0; glitch_o <= 1'b0;
            orun <= 0;
            ph_a <= 0; pf <= 0; chk <= 0; s <= 0; u <= 0; grun <= 0; v <= 0; acc <= 1'b0;
            rc <= 1'b0; unc <= 0; lost_o <= 1'b0;
            w_r <= 0; wacc <= 1'b0; wadd <= 12'd0; mdev_r <= 0; padv <= 0; pupd <= 1'b0;
            sl1 <= 0; sl2 <= 0; sv1 <= 0; sv2 <= 0; pst <= 0; psg <= 0;
            prt1 <= 1'b0; prt2 <= 1'b0;
        end
    end
    assign travel_o = s[24:5];
    wire unused = &{1'b0, mn3[1:0], sd[4:0], x1[10:0], x2[10:0], dv[2:0], e[0], mdd[3:0], p2k[11:0],
                      dl1[13:0], dl2[13:0], 1'b0};

`ifdef FORMAL
    // ---- formal properties (sim/formal/monitor.sby; every input free on every clock) --------
    // Stated per edge for any inputs: a sample's values are its inputs on the edges the
    // header gives (no assumption ties the stages of one sample together; ghost delay lines
    // f_* carry them to stage H). With E the edge sampling pvalid_i (t + 7 of the header):
    //  M1 loss (in H, loss_o after E) == ref && r < LOSS, dead == ref && r < FLOOR, over ==
    //     ref && r > OVER for ref sampled on E - 7, r = max + (min >> 2) + (min >> 3) of
    //     ax_i, ay_i sampled on E - 4 (computed here in 17 bits), the thresholds sampled on
    //     E - 2; the 16-bit radius register holds the exact sum (it never passes 16 bits).
    //  M2 stuck: a channel's latch, on each sample's update (v3), becomes !chg && (latch ||
    //     (run >= N > 0 && !rebase && the other channel outside [-sp, sp - 1] of its
    //     snapshot)), chg = the code changed from the previous sample, run its run of
    //     unchanged codes as updated by the sample (the spec run >= N, not the run >= N -
    //     1 shortcut), the difference o - snap taken exactly (19 bits: o and snap stay in
    //     [-32767, 32767], so the s18 x never wraps); the snapshot and its span sp follow
    //     the other channel and the sample's span on a change or a rebase; stuck (in H,
    //     stuck_o after E) == the latch (either channel) right after the update on E - 3.
    //     The spans' pipeline: the sample's (g, c1, c2, code step) registered on sv_i, its
    //     predecessor's beside it; rebase and span_exp() with the sample one edge later,
    //     span_shift() the next, span_clamp() the next; every span in [2048, 32767]. (The
    //     functions' values are held to the model's stuck_span() by
    //     cocotb_tests/test_monitor.py, whose stimulus makes wrong spans and a missing
    //     rebase visible; not here.) Assumed: code_step_i <= 8 (the register's legal
    //     range; with ADC_W >= 12, E <= 30 fits its 5 bits). Per channel, beside the
    //     sample in H: its latch as it stood after E - 3, its code change (chg) and its
    //     signs (xn_i, yn_i sampled on E - 4, with ax_i and ay_i).
    //  M3 glitch_o == K > 0 && chk == 2 && !rc && wrap13(phase - pred) outside [-2^K,
    //     2^K - 1], pred = pf >> 3 (the line; signed compares; off for K >= 12 as the
    //     range then covers every s13); hold_o == pvalid && (dead || stuck || (clip &&
    //     over) || glitch) of the sample (clip sampled on E - 6; loss alone does not hold);
    //     coast_o == hold_o && lok && (dead || stuck || (clip && over) || (glitch && (grun
    //     < 16 || clip))); line_o == pred; excl_o == hold_o || (pvalid && (loss || clip ||
    //     over && orun < 4095)): so hold_o and excl_o only with pvalid_i, excl_o whenever
    //     hold_o, coast_o only with hold_o.
    //  M4 No pvalid_i: nothing in H moves, the fault bits and lost_o hold. A held sample
    //     moves neither U, S, ph_a nor mdev (orun and the flags follow the sample).
    //     Coasting (coast_o): chk and lok kept, acc <= 0; the line: on the first sample
    //     of one stuck channel (its latch set, clear for the sample before: rise) pf <=
    //     sl + sv, v <= sv of that channel, and unc <= 2^23 if that channel's shadow
    //     line has parted (prt, or sl - pf now outside [-2^14, 2^14 - 1] as s16); else,
    //     with one stuck channel, the signal not
    //     dead and the working channel's sign changed from the sample before (anchor):
    //     pf <= 8 cand + v, cand the working channel's zero crossing (0 or 4096 for
    //     channel 2, 2048 or 6144 for channel 1) with wrap13(pred - cand) in [-2048,
    //     2047] (the nearest), v kept; else pf <= pf + v, v kept; unc <= 0 on an anchor
    //     (not rise), else (no parted rise) min(unc + w, 2^23); w <= w + coast_acc while w < 2^23, else
    //     kept; a coast through dead, stuck or clip with over: rc <= 1, grun kept; a
    //     glitch coast: grun <= min(grun + 1, 16), rc stays 0.
    //     Any other held one (no line: lok = 0, or the 17th glitch coast unclipped): pf,
    //     v, w kept; chk, grun, acc, lok, rc <= 0; unc <= 2^23 (lost_o).
    //     An accepted one: ph_a <= phase; re-anchoring (chk < 2) pf <= 8 phase + 8 d, v
    //     <= 8 d; else pf <= 8 phase + v and, if the sample before was accepted (acc),
    //     v <= v + floor((8 d - v) / 8) and mdev <= mdev + floor((16 |8 d - v| - mdev) /
    //     16) (both exact, d = wrap13(phase - ph_a): in 20 and 23 bits they never leave
    //     s16 and [0, 16 x 65535]), else v and mdev kept; w <= (floor(mdev / 16) + 1) 2^9
    //     (mdev before the sample); chk <= min(chk + 1, 2), lok <= chk >= 1, rc <= 0, unc
    //     <= 0; grun <= 0 only if acc (else kept), acc <= 1; U <= U + d.
    //     Every sample (pvalid_i): pst, psg <= its latches and signs; per channel the
    //     shadow line: sl <= pf, sv <= v (as updated by the sample) if the channel's code
    //     changed, else sl <= sl + sv, sv kept; prt <= 0 if the channel's code changed,
    //     else prt or sl - pf (before the sample) outside [-2^14, 2^14 - 1].
    //  M5 saturating counters never wrap: run 0..255 (+1 while unchanged, 0 on a change),
    //     orun 0..4095 (+1 while over, 0 otherwise), chk 0..2, grun 0..16 (+1 per glitch
    //     coast, 0 on two accepted in a row or a re-anchor); lok == (chk == 2) (the line
    //     is known exactly while it is anchored), rc only with lok.
    //  M6 S: the difference (U << 5) - S (s25) stays within +-2^22 (|U - S| <= 32 x 4096
    //     in U units, at any phase steps: wrap13 bounds them), so S's step never sees a
    //     wrapped difference.
    //  M7 rst: the flags and lost_o, orun, chk, U, S, ph_a, pf, v, grun, acc, lok, rc,
    //     unc, w, mdev, the shadow lines, prt, pst, psg, the runs, latches and snapshots 0, the
    //     spans 2048, the sampled bundles 0.
    //  M8 OPT_MONITOR = 0 (sby task prf_m): M1..M7, M9 with loss, dead, over, stuck and
    //     glitch as specified replaced by 0: hold_o, coast_o and lost_o never, line_o ==
    //     0, excl_o == pvalid && clip, every sample accepted (M4's accepted branch: U and
    //     S follow every sample).
    //  M9 the coast's bounds: lost_o == (unc == 2^23) (after a sample: its uncertainty as
    //     updated reached a quarter period), unc <= 2^23, w <= 2^25 (max(2^25 from mdev,
    //     2^23 + 4094 from coast_acc): neither w (u26) nor unc + w (u27) wraps), mdev <=
    //     16 x 65535.
    // The pipeline invariants (the RTL's stage registers against the ghost delay lines) make
    // every property inductive in two steps.
    reg f_past_valid = 1'b0;
    always @(posedge clk)
        f_past_valid <= 1'b1;
    always @(*)
        assume (code_step_i <= 4'd8);

    // the radius as specified, in 17 bits (used in continuous assignments only)
    function [16:0] f_radius(input [14:0] a, input [14:0] b);
        reg [14:0] mx, mn;
        begin
            mx = (a >= b) ? a : b;
            mn = (a >= b) ? b : a;
            f_radius = {2'b00, mx} + {4'd0, mn[14:2]} + {5'd0, mn[14:3]};
        end
    endfunction

    // ghost delay lines: ax, ay (4 samples), the thresholds (2), ref (7), clip (6), the
    // latch's next value (3), the latches (2), the signs (4)
    reg [119:0] f_axy = 120'd0;
    reg [63:0]  f_th = 64'd0;
    reg [31:0]  f_fl = 32'd0;
    reg [6:0]   f_ref = 7'd0;
    reg [5:0]   f_clip = 6'd0;
    reg [2:0]   f_stkp = 3'd0;
    reg [3:0]   f_st = 4'd0;                                    // {stk2, stk1}
    reg [7:0]   f_sg = 8'd0;                                    // {yn, xn}
    wire        f_stk1n, f_stk2n;
    always @(posedge clk) begin
        f_axy  <= {f_axy[89:0], ax_i, ay_i};
        f_th   <= {f_th[31:0], loss_th_i, over_th_i};
        f_fl   <= {f_fl[15:0], floor_th_i};
        f_ref  <= {f_ref[5:0], ref_i};
        f_clip <= {f_clip[4:0], clip_i};
        f_stkp <= {f_stkp[1:0], f_stk1n || f_stk2n};
        f_st   <= {f_st[1:0], stk2, stk1};
        f_sg   <= {f_sg[5:0], yn_i, xn_i};
    end
    wire [16:0] f_r   = f_radius(f_axy[119:105], f_axy[104:90]);   // sampled on E - 4
    wire [16:0] f_r5  = f_radius(f_axy[89:75], f_axy[74:60]);      // one sample later
    wire [16:0] f_r4  = f_radius(f_axy[59:45], f_axy[44:30]);
    wire [16:0] f_rin = f_radius(ax_i, ay_i);
    // (the fault bits as specified exist only with OPT_MONITOR; 0 without: M8)
    wire        f_deadr = f_ref[6] && ({1'b0, f_fl[31:16]} > f_r);
    wire        f_loss  = OPT_MONITOR && f_ref[6] && ({1'b0, f_th[63:48]} > f_r);
    wire        f_dead  = OPT_MONITOR && f_deadr;
    wire        f_over  = OPT_MONITOR && f_ref[6] && ({1'b0, f_th[47:32]} < f_r);
    wire        f_loss5 = f_ref[5] && ({1'b0, f_th[31:16]} > f_r5);
    wire        f_dead5 = f_ref[5] && ({1'b0, f_fl[15:0]} > f_r5);
    wire        f_over5 = f_ref[5] && ({1'b0, f_th[15:0]} < f_r5);
    wire        f_lowa  = (f_axy[29:15] >= f_axy[14:0]);
    wire        f_stuck = OPT_MONITOR && f_stkp[2];
    wire        f_early = f_dead || f_stuck || (f_clip[5] && f_over);

    // the other channel (s17) and wrap13 of the phase error / step, as integers
    wire signed [17:0] f_o1 = yn_i ? -$signed({3'b000, ay_i}) : $signed({3'b000, ay_i});
    wire signed [17:0] f_o2 = xn_i ? -$signed({3'b000, ax_i}) : $signed({3'b000, ax_i});
    wire signed [13:0] f_e  = $signed({1'b0, phase_i}) - $signed({1'b0, pf[15:3]});
    wire signed [13:0] f_ew = (f_e >= 14'sd4096) ? f_e - 14'sd8192
                            : (f_e < -14'sd4096) ? f_e + 14'sd8192 : f_e;
    wire signed [13:0] f_d  = $signed({1'b0, phase_i}) - $signed({1'b0, ph_a});
    wire signed [13:0] f_dw = (f_d >= 14'sd4096) ? f_d - 14'sd8192
                            : (f_d < -14'sd4096) ? f_d + 14'sd8192 : f_d;
    reg  [3:0] f_k = 4'd0;                                      // K of the edge before
    always @(posedge clk)
        f_k <= glitch_k_i;
    // the registered mask is K's (an invariant for the induction)
    integer fk;
    always @(*)
        for (fk = 1; fk < 12; fk = fk + 1)
            assert (gmask[fk] == ((f_k != 4'd0) && (fk >= f_k)));
    wire signed [17:0] f_lim = $signed(18'd1 << f_k);           // 2^K
    wire signed [17:0] f_ew18 = f_ew;
    wire f_off = (f_ew18 < -f_lim) || (f_ew18 > f_lim - 18'sd1);
    wire f_glitch = OPT_MONITOR && (f_k != 4'd0) && (chk == 2'd2) && !rc && f_off;
    wire f_hold = pvalid_i && (f_early || f_glitch);
    wire f_coast = OPT_MONITOR && lok
                   && (f_early || (f_glitch && !(grun == 5'd16 && !f_clip[5])));
    // mdev after the sample before (the retimed register with its pending update)
    wire [19:0] mdev = pupd ? mdev_r + {{3{mdd[20]}}, mdd[20:4]} : mdev_r;
    always @(*) begin
        assert (w_r <= 26'h2000000 && mdev_r <= 20'd1048560 && !(wacc && wadd != 12'd0));
        assert (mdd >= -21'sd1048560);
    end
    // v's running mean and the spread's in exact arithmetic (20 and 23 bits), their ranges
    wire signed [19:0] f_vn = $signed(v) + (($signed(f_dw) * 20'sd8 - $signed(v)) >>> 3);
    wire signed [17:0] f_dv = $signed(f_dw) * 18'sd8 - $signed(v);
    wire        [16:0] f_adv = f_dv[17] ? 17'd0 - f_dv[16:0] : f_dv[16:0];
    wire signed [22:0] f_md0 = $signed({3'b000, mdev});
    wire signed [22:0] f_mdn = f_md0 + (($signed({2'b00, f_adv, 4'b0000}) - f_md0) >>> 4);
    always @(*) begin
        assert (f_vn >= -20'sd32768 && f_vn <= 20'sd32767);
        assert (f_mdn >= 23'sd0 && f_mdn <= 23'sd1048560);
    end
    // one stuck channel (f_st[2]: channel 1), the first sample of its latch (rise), the
    // working channel's sign change (anchor), as the header gives them
    wire        f_one = f_st[2] != f_st[3];
    wire        f_rise = f_one && (f_st[2] ? !pst[0] : !pst[1]);
    wire        f_anchor = f_one && !f_deadr
                           && (f_st[2] ? (f_sg[7] != psg[1]) : (f_sg[6] != psg[0]));
    wire [26:0] f_us = {3'b000, unc} + {1'b0, w};               // exact
    // a shadow line a quarter period or more off the line (s16 compare), or so since its
    // channel's code last changed; on the rise of its latch the travel is lost
    wire signed [15:0] f_dl1 = $signed(sl1 - pf), f_dl2 = $signed(sl2 - pf);
    wire        f_part1 = prt1 || f_dl1 < -16'sd16384 || f_dl1 >= 16'sd16384;
    wire        f_part2 = prt2 || f_dl2 < -16'sd16384 || f_dl2 >= 16'sd16384;
    wire        f_rlost = f_rise && (f_st[2] ? f_part1 : f_part2);

    // stuck: the spec's chg and run >= N of the sample, carried to the latch's update edge
    // (chg on to H)
    wire [7:0] f_run1n = (raw1_i != prev1) ? 8'd0 : (run1 == 8'hff) ? 8'hff : run1 + 1'b1;
    wire [7:0] f_run2n = (raw2_i != prev2) ? 8'd0 : (run2 == 8'hff) ? 8'hff : run2 + 1'b1;
    reg  [5:0] f_chg1 = 6'd0, f_chg2 = 6'd0;
    reg  [2:0] f_rok1 = 3'd0, f_rok2 = 3'd0;
    always @(posedge clk) begin
        f_chg1 <= {f_chg1[4:0], raw1_i != prev1};
        f_chg2 <= {f_chg2[4:0], raw2_i != prev2};
        f_rok1 <= {f_rok1[1:0], (stuck_n_i != 8'd0) && (f_run1n >= stuck_n_i)};
        f_rok2 <= {f_rok2[1:0], (stuck_n_i != 8'd0) && (f_run2n >= stuck_n_i)};
    end
    wire signed [18:0] f_x1 = $signed({{2{o1[16]}}, o1}) - $signed({{2{snap1[16]}}, snap1});
    wire signed [18:0] f_x2 = $signed({{2{o2[16]}}, o2}) - $signed({{2{snap2[16]}}, snap2});
    wire signed [18:0] f_sp1 = $signed({4'd0, sp1}), f_sp2 = $signed({4'd0, sp2});
    wire f_far1 = !reb_3 && ((f_x1 < -f_sp1) || (f_x1 > f_sp1 - 19'sd1));
    wire f_far2 = !reb_3 && ((f_x2 < -f_sp2) || (f_x2 > f_sp2 - 19'sd1));
    assign f_stk1n = !f_chg1[2] && (stk1 || (f_rok1[2] && f_far1));
    assign f_stk2n = !f_chg2[2] && (stk2 || (f_rok2[2] && f_far2));

    // ---- properties and invariants on every clock ---------------------------------------------
    wire signed [24:0] f_sd = sd;
    always @(*) begin
        assert (chk <= 2'd2 && grun <= 5'd16);                                          // M5
        assert (lok == (chk == 2'd2));
        if (rc)
            assert (lok);
        assert (orun <= OVER_PERSIST);
        assert (f_sd <= 25'sd4194304 && f_sd >= -25'sd4194304);          // M6
        assert (snap1 <= 17'sd32767 && snap1 >= -17'sd32767);            // M2
        assert (snap2 <= 17'sd32767 && snap2 >= -17'sd32767);
        assert (o1 <= 17'sd32767 && o1 >= -17'sd32767);
        assert (o2 <= 17'sd32767 && o2 >= -17'sd32767);
        assert (x1 == f_x1[17:0] && x2 == f_x2[17:0]);                  // s18 exact
        assert (stk1n == f_stk1n && stk2n == f_stk2n);
        assert (sp1 >= 15'd2048 && sp2 >= 15'd2048 && sp1_3 >= 15'd2048 && sp2_3 >= 15'd2048);
        assert (stuck == f_stuck);
        assert (f_rin < 17'h10000);                                      // M1
        assert ({1'b0, r4} == f_r4);
        assert (loss == f_loss && over == f_over && dead6 == f_deadr);
        assert (glitch == f_glitch);                                     // M3
        assert (hold_o == f_hold);
        assert (coast_o == (f_hold && f_coast));
        assert (line_o == (OPT_MONITOR ? pf[15:3] : 13'd0));
        assert (excl_o == (hold_o || (pvalid_i && (f_loss || f_clip[5]
                                                   || (f_over && orun != OVER_PERSIST)))));
        if (!pvalid_i)
            assert (!hold_o && !excl_o && !coast_o);
        if (hold_o)
            assert (excl_o);
        if (coast_o)
            assert (hold_o);
        assert (lost_o == (unc == 24'h800000));                          // M9
        assert (unc <= 24'h800000);
        assert (w <= 26'h2000000);
        assert (mdev <= 20'd1048560);
        if (!OPT_MONITOR)                                                // M8
            assert (!hold_o && !coast_o && !lost_o && line_o == 13'd0
                    && excl_o == (pvalid_i && f_clip[5]));
        // pipeline invariants
        assert (ref0 == f_ref[0] && ref1 == f_ref[1] && ref2 == f_ref[2]
                && ref3 == f_ref[3] && ref4 == f_ref[4]);
        assert (mx3 == (f_lowa ? f_axy[29:15] : f_axy[14:0]));
        assert (mn3 == (f_lowa ? f_axy[14:0] : f_axy[29:15]));
        assert (loss5 == f_loss5 && over5 == f_over5 && dead5 == f_dead5);
        assert (clip_d == f_clip[4:0] && clip6 == f_clip[5]);
        assert ({stuck_d, stuck4} == f_stkp);
        assert (early == f_early);
        assert ({chg1_3, chg1_2, chg1_1} == f_chg1[2:0] && {chg2_3, chg2_2, chg2_1} == f_chg2[2:0]);
        assert ({chg_6, chg_5, chg_4} == {f_chg2[5], f_chg1[5], f_chg2[4], f_chg1[4],
                                          f_chg2[3], f_chg1[3]});
        assert ({rok1_3, rok1_2, rok1_1} == f_rok1 && {rok2_3, rok2_2, rok2_1} == f_rok2);
        assert ({st_6, st_5} == f_st);
        assert ({sg_6, sg_5, sg_4, sg_3} == f_sg);
    end

    // the anchor's crossing (the line less its velocity) and its distance from pred
    wire [15:0]        f_cpf = pf - v;
    reg  [12:0]        f_pred = 13'd0;                          // pred before the edge
    always @(posedge clk)
        f_pred <= pf[15:3];
    wire signed [13:0] f_ce = $signed({1'b0, f_pred}) - $signed({1'b0, f_cpf[15:3]});
    wire signed [13:0] f_cwe = (f_ce >= 14'sd4096) ? f_ce - 14'sd8192
                             : (f_ce < -14'sd4096) ? f_ce + 14'sd8192 : f_ce;

    // ---- per edge ----------------------------------------------------------------------------
    always @(posedge clk) if (f_past_valid) begin
        if ($past(rst)) begin                                            // M7
            assert (!loss_o && !over_o && !stuck_o && !glitch_o && !lost_o);
            assert (orun == 12'd0 && chk == 2'd0 && u == 20'd0 && s == 25'd0);
            assert (ph_a == 13'd0 && pf == 16'd0 && grun == 5'd0 && !acc && v == 16'sd0);
            assert (!lok && !rc && unc == 24'd0 && w == 26'd0 && mdev == 20'd0);
            assert (sl1 == 16'd0 && sl2 == 16'd0 && sv1 == 16'd0 && sv2 == 16'd0);
            assert (pst == 2'd0 && psg == 2'd0 && !prt1 && !prt2);
            assert (run1 == 8'd0 && run2 == 8'd0 && prev1 == 0 && prev2 == 0);
            assert (!stk1 && !stk2 && snap1 == 0 && snap2 == 0 && !v1 && !v2 && !v3);
            assert (sp1 == 15'd2048 && sp2 == 15'd2048 && sc1 == 0 && sc2 == 0 && sg == 2'd0);
            assert (pc1 == 0 && pc2 == 0 && pg == 2'd0 && sst == 4'd0);
        end else begin
            // M2: the spans' pipeline
            if ($past(sv_i)) begin
                assert ({sg, sc1, sc2, sst} == $past({g_i, c1_i, c2_i, code_step_i}));
                assert ({pg, pc1, pc2} == $past({sg, sc1, sc2}));
            end else begin
                assert ({sg, sc1, sc2, sst, pg, pc1, pc2}
                        == $past({sg, sc1, sc2, sst, pg, pc1, pc2}));
            end
            // M5: the runs
            if ($past(valid0_i)) begin
                assert (run1 == $past(f_run1n) && run2 == $past(f_run2n));
                assert (prev1 == $past(raw1_i) && prev2 == $past(raw2_i));
            end else begin
                assert (run1 == $past(run1) && run2 == $past(run2));
                assert (prev1 == $past(prev1) && prev2 == $past(prev2));
            end
            // M2: the latch and the snapshot move only on a sample's update; stuck in H is
            // the latch right after the update (f_stkp[0] -> f_stkp[2])
            if ($past(v3)) begin
                assert (stk1 == $past(f_stk1n) && stk2 == $past(f_stk2n));
                assert ((stk1 || stk2) == f_stkp[0]);
                assert (snap1 == ($past(f_chg1[2] || reb_3) ? $past(o1) : $past(snap1)));
                assert (snap2 == ($past(f_chg2[2] || reb_3) ? $past(o2) : $past(snap2)));
                assert (sp1 == ($past(f_chg1[2] || reb_3) ? $past(sp1_3) : $past(sp1)));
                assert (sp2 == ($past(f_chg2[2] || reb_3) ? $past(sp2_3) : $past(sp2)));
            end else begin
                assert (stk1 == $past(stk1) && stk2 == $past(stk2));
                assert (snap1 == $past(snap1) && snap2 == $past(snap2));
                assert (sp1 == $past(sp1) && sp2 == $past(sp2));
            end
        end
        if (!$past(rst)) begin
            if ($past(valid0_i)) begin
                assert (sx1_1 == span_exp($past(sc1), $past(sh)));
                assert (sx2_1 == span_exp($past(sc2), $past(sh)));
                assert (reb_1 == ($past({sg, sc1, sc2}) != $past({pg, pc1, pc2})));
            end else
                assert ({sx1_1, sx2_1, reb_1} == $past({sx1_1, sx2_1, reb_1}));
            if ($past(v1))
                assert (sv1_2 == span_shift($past(sx1_1)) && sv2_2 == span_shift($past(sx2_1))
                        && reb_2 == $past(reb_1));
            else
                assert ({sv1_2, sv2_2, reb_2} == $past({sv1_2, sv2_2, reb_2}));
            if ($past(v2))
                assert (sp1_3 == span_clamp($past(sv1_2)) && sp2_3 == span_clamp($past(sv2_2))
                        && reb_3 == $past(reb_2));
            else
                assert ({sp1_3, sp2_3, reb_3} == $past({sp1_3, sp2_3, reb_3}));
            assert (o1 == $past(f_o1[16:0]) && o2 == $past(f_o2[16:0]));
            // the stage H state
            if (!$past(pvalid_i)) begin
                assert (ph_a == $past(ph_a) && pf == $past(pf) && chk == $past(chk));
                assert (v == $past(v) && acc == $past(acc) && grun == $past(grun));
                assert (lok == $past(lok) && rc == $past(rc) && unc == $past(unc));
                assert (w == $past(w) && mdev == $past(mdev));
                assert (sl1 == $past(sl1) && sl2 == $past(sl2));
                assert (prt1 == $past(prt1) && prt2 == $past(prt2));
                assert (sv1 == $past(sv1) && sv2 == $past(sv2));
                assert (pst == $past(pst) && psg == $past(psg));
                assert (u == $past(u) && s == $past(s) && orun == $past(orun));
                assert (loss_o == $past(loss_o) && over_o == $past(over_o));
                assert (stuck_o == $past(stuck_o) && glitch_o == $past(glitch_o));
                assert (lost_o == $past(lost_o));
            end else begin
                // M1..M3: the fault bits of the sample
                assert (loss_o == $past(f_loss) && over_o == $past(f_over));
                assert (stuck_o == $past(f_stuck));
                assert (glitch_o == $past(f_glitch));
                // M5: the over-range run
                if (!$past(f_over))
                    assert (orun == 12'd0);
                else if ($past(orun) != OVER_PERSIST)
                    assert (orun == $past(orun) + 1'b1);
                else
                    assert (orun == OVER_PERSIST);
                // M4: every sample, its latches and signs, the shadow lines
                assert (pst == $past(f_st[3:2]) && psg == $past(f_sg[7:6]));
                assert (sl1 == ($past(f_chg1[5]) ? pf : $past(sl1 + sv1)));
                assert (sv1 == ($past(f_chg1[5]) ? v : $past(sv1)));
                assert (sl2 == ($past(f_chg2[5]) ? pf : $past(sl2 + sv2)));
                assert (sv2 == ($past(f_chg2[5]) ? v : $past(sv2)));
                assert (prt1 == $past(!f_chg1[5] && f_part1));
                assert (prt2 == $past(!f_chg2[5] && f_part2));
                // M9: the travel is lost after the sample
                assert (lost_o == (unc >= 24'h800000));
                // M4
                if ($past(f_hold)) begin
                    assert (u == $past(u) && s == $past(s));
                    assert (ph_a == $past(ph_a) && mdev == $past(mdev));
                    assert (!acc);
                    if ($past(f_coast)) begin
                        assert (chk == $past(chk) && lok == $past(lok));
                        if ($past(f_rise)) begin
                            assert (pf == $past(f_st[2] ? sl1 + sv1 : sl2 + sv2));
                            assert (v == $past(f_st[2] ? sv1 : sv2));
                        end else if ($past(f_anchor)) begin
                            assert (v == $past(v));
                            assert (f_cpf[2:0] == 3'd0);
                            assert (f_cpf[14:3] == ($past(f_st[2]) ? 12'd0 : 12'd2048));
                            assert (f_cwe >= -14'sd2048 && f_cwe <= 14'sd2047);
                        end else begin
                            assert (pf == $past(pf + v) && v == $past(v));
                        end
                        if ($past(f_anchor && !f_rise))
                            assert (unc == 24'd0);
                        else if ($past(f_rlost))
                            assert (unc == 24'h800000);
                        else
                            assert (unc == (($past(f_us) >= 27'h800000) ? 24'h800000
                                                                          : $past(f_us[23:0])));
                        if ($past(w) < 26'h800000)
                            assert (w == $past(w) + $past({14'd0, coast_acc_i}));
                        else
                            assert (w == $past(w));
                        if ($past(f_early)) begin
                            assert (rc && grun == $past(grun));
                        end else begin
                            assert (!rc);
                            assert (grun == (($past(grun) == 5'd16) ? 5'd16
                                                                    : $past(grun) + 1'b1));
                        end
                    end else begin
                        assert (pf == $past(pf) && v == $past(v) && w == $past(w));
                        assert (chk == 2'd0 && grun == 5'd0 && !lok && !rc);
                        assert (unc == 24'h800000);
                    end
                end else begin
                    // two accepted in a row clear the coast count; one after a coast keeps it
                    assert (grun == ($past(acc) ? 5'd0 : $past(grun)) && acc);
                    assert (ph_a == $past(phase_i));
                    if (!$past(chk[1])) begin
                        assert (pf == $past({phase_i, 3'b000} + {phase_i - ph_a, 3'b000}));
                        assert (v == $past({phase_i - ph_a, 3'b000}));
                    end else begin
                        assert (pf == $past({phase_i, 3'b000} + v));
                        if ($past(acc))
                            assert ($signed(v) == $past(f_vn));
                        else
                            assert (v == $past(v));
                    end
                    if ($past(chk[1] && acc))
                        assert ($signed({3'b000, mdev}) == $past(f_mdn));
                    else
                        assert (mdev == $past(mdev));
                    assert (w == ((({6'd0, $past(mdev)} >> 4) + 26'd1) << 9));
                    assert (chk == (($past(chk) == 2'd2) ? 2'd2 : $past(chk) + 1'b1));
                    assert (lok == ($past(chk) != 2'd0) && !rc && unc == 24'd0);
                    assert (u == $past(u + {{6{f_dw[13]}}, f_dw}));
                end
            end
        end
    end

    // ---- reachability ------------------------------------------------------------------------
    always @(posedge clk) if (f_past_valid && !$past(rst)) begin
        cover (loss_o);
        cover (over_o && !$past(hold_o) && $past(excl_o));
        cover (stuck_o && $past(pvalid_i) && $past(v3, 4));
        cover (glitch_o && $past(f_k) == 4'd3);
        cover ($past(pvalid_i && !hold_o) && $past(pvalid_i && hold_o, 2) && chk == 2'd1);
        cover (run1 == 8'd5 && stk2);
        cover (stk1 && sp1 > 15'd8192);
        cover ($past(hold_o) && $past(f_clip[5] && over && !f_dead && !stuck && !f_glitch));
        cover (grun == 5'd3);
        cover ($past(pvalid_i && !hold_o && !acc) && grun == 5'd2);
        // a weak signal (loss, not dead) still counted; a coast through a dead signal
        cover (loss_o && !$past(hold_o) && $past(excl_o));
        cover ($past(coast_o && f_dead) && $past(pvalid_i && !hold_o, 2));
        // the coast's uncertainty reaches a quarter period; the blind hold loses the travel
        cover (lost_o && $past(coast_o) && !$past(lost_o));
        cover (lost_o && $past(hold_o && !coast_o));
        // a stuck channel's coast from its shadow line; a sign change re-anchors it
        cover ($past(coast_o && f_rise) && sl1 != 16'd0);
        cover ($past(coast_o && f_rlost) && $past(prt1 || prt2) && lost_o);
        cover ($past(coast_o && f_anchor && !f_rise) && $past(unc) != 24'd0);
        // the sample after a coast through a fault is not tested against the line
        cover ($past(pvalid_i && !hold_o && rc && f_k != 4'd0 && chk == 2'd2 && f_off));
    end
`endif
endmodule
`resetall
