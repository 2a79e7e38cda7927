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
//   t + 3  o_1 = u2c, o_2 = u1c (the other channel, s17); det_c = run_ok_c and |o_c -
//          snap_c| >= 2048; stk_c <= !chg_c and (stk_c or det_c); snap_c <= o_c if chg_c;
//          stuck = stk_1 or stk_2 (as updated)
//          r = max + min >> 2 + min >> 3           u16 radius (alpha-max-plus-beta-min)
//   t + 4  loss = ref and r < LOSS, over = ref and r > OVER
//   H = the clock from t + 6 to t + 7: phase_i (u13 fine phase, before the harmonic
//          correction) registered on t + 6 with pvalid_i
//          glitch = GLITCH > 0, chk == 2 and |wrap13(phase - pred)| > GLITCH
//          hold_o = pvalid and (loss or stuck or glitch or clip)  (combinational in H:
//                   the counter keeps its count and last phase, rtl/counter.v)
//          excl_o = hold_o or over while orun < 4095              (combinational in H:
//                   the estimator does not take the sample)
//   t + 7  loss_o, over_o, stuck_o, glitch_o (the sample's fault bits);
//          orun <= over ? min(orun + 1, 4095) : 0; if accepted
//          (not hold): ph_a <= phase, pred <= 2 phase - ph_a (mod 8192), chk <= min(chk +
//          1, 2), S <= S + ((U << 5) - S) >>> 5, U <= U + wrap13(phase - ph_a); held:
//          chk <= 0. travel_o = S[24:5] (u20 phase units, wraps; the estimator's gate).
// Formats: U u20 (wraps), S u20.5 (wraps; the difference (U << 5) - S is taken as s25,
// and |U - S| stays below 2^19 at any speed below half a period per sample: 32 x 4096),
// snap s17 (|o| <= 32767, the difference s18), orun u12 and run u8 saturate, pred and
// ph_a u13 wrap. Nothing overflows
// (the formal properties below and sim/formal/monitor.sby).
module monitor (
    input  wire               clk,
    input  wire               rst,
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
    input  wire [12:0]        glitch_th_i,  // u13 max |phase acceleration| (0: off)
    input  wire [7:0]         stuck_n_i,    // u8 unchanged codes before stuck (0: off)
    // stage H (combinational)
    output wire               hold_o,
    output wire               excl_o,
    // edge t + 7
    output reg                loss_o = 1'b0,
    output reg                over_o = 1'b0,
    output reg                stuck_o = 1'b0,
    output reg                glitch_o = 1'b0,
    output wire [19:0]        travel_o      // u20 integer part of S
);
    localparam [17:0] STUCK_SPAN = 18'd2048;     // 1/8 of the calibrated radius
    localparam [11:0] OVER_PERSIST = 12'd4095;

    // ---- t + 1: runs of unchanged codes ------------------------------------------------
    reg signed [15:0] prev1 = 0, prev2 = 0;
    reg [7:0] run1 = 0, run2 = 0;
    wire      eq1 = (raw1_i == prev1), eq2 = (raw2_i == prev2);
    wire [7:0] run1n = eq1 ? ((run1 == 8'hff) ? run1 : run1 + 1'b1) : 8'd0;
    wire [7:0] run2n = eq2 ? ((run2 == 8'hff) ? run2 : run2 + 1'b1) : 8'd0;
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
        rok1_1 <= (stuck_n_i != 8'd0) && (run1n >= stuck_n_i);
        rok2_1 <= (stuck_n_i != 8'd0) && (run2n >= stuck_n_i);
        if (rst) begin
            prev1 <= 0; prev2 <= 0; run1 <= 0; run2 <= 0;
        end
    end
    // ---- t + 2 .. t + 3: the other channel's excursion, the stuck latch -----------------
    reg        v1 = 1'b0, v2 = 1'b0;
    reg        chg1_2 = 1'b0, chg2_2 = 1'b0, rok1_2 = 1'b0, rok2_2 = 1'b0;
    reg        stk1 = 1'b0, stk2 = 1'b0, stuck3 = 1'b0;
    reg signed [16:0] snap1 = 0, snap2 = 0;
    wire signed [16:0] o1 = yn_i ? -$signed({2'b00, ay_i}) : $signed({2'b00, ay_i});
    wire signed [16:0] o2 = xn_i ? -$signed({2'b00, ax_i}) : $signed({2'b00, ax_i});
    wire signed [17:0] x1 = {o1[16], o1} - {snap1[16], snap1};
    wire signed [17:0] x2 = {o2[16], o2} - {snap2[16], snap2};
    wire far1 = (x1 >= $signed(STUCK_SPAN)) || (x1 <= -$signed(STUCK_SPAN));
    wire far2 = (x2 >= $signed(STUCK_SPAN)) || (x2 <= -$signed(STUCK_SPAN));
    wire stk1n = !chg1_2 && (stk1 || (rok1_2 && far1));
    wire stk2n = !chg2_2 && (stk2 || (rok2_2 && far2));
    always @(posedge clk) begin
        v1 <= valid0_i;
        v2 <= v1;
        chg1_2 <= chg1_1;
        chg2_2 <= chg2_1;
        rok1_2 <= rok1_1;
        rok2_2 <= rok2_1;
        stuck3 <= stk1n || stk2n;
        if (v2) begin
            stk1 <= stk1n;
            stk2 <= stk2n;
            if (chg1_2)
                snap1 <= o1;
            if (chg2_2)
                snap2 <= o2;
        end
        if (rst) begin
            v1 <= 1'b0; v2 <= 1'b0; stk1 <= 1'b0; stk2 <= 1'b0; snap1 <= 0; snap2 <= 0;
        end
    end
    // the stuck flag of edge t + 3, at t + 6
    reg [2:0] stuck_d = 0;
    always @(posedge clk)
        stuck_d <= {stuck_d[1:0], stuck3};
    wire stuck = stuck_d[2];
    // the clip flag of edge t, at t + 6
    reg [5:0] clip_d = 0;
    always @(posedge clk)
        clip_d <= {clip_d[4:0], clip_i};
    wire clip = clip_d[5];

    // ---- t .. t + 4: the radius ---------------------------------------------------------
    reg        ref0 = 1'b0, ref1 = 1'b0, ref2 = 1'b0, ref3 = 1'b0;
    reg [15:0] r3 = 0;
    reg        loss4 = 1'b0, over4 = 1'b0;
    reg [1:0]  loss_d = 0, over_d = 0;
    wire       low = (ay_i <= ax_i);
    wire [14:0] mx = low ? ax_i : ay_i;
    wire [14:0] mn = low ? ay_i : ax_i;
    always @(posedge clk) begin
        ref0 <= ref_i;
        ref1 <= ref0;
        ref2 <= ref1;
        ref3 <= ref2;
        r3 <= {1'b0, mx} + {3'd0, mn[14:2]} + {4'd0, mn[14:3]};
        loss4 <= ref3 && (r3 < loss_th_i);
        over4 <= ref3 && (r3 > over_th_i);
        loss_d <= {loss_d[0], loss4};
        over_d <= {over_d[0], over4};
    end
    wire loss = loss_d[1], over = over_d[1];

    // ---- stage H ----------------------------------------------------------------------------
    reg [12:0] ph_a = 0, pred = 0;
    reg [1:0]  chk = 0;
    reg [19:0] u = 0;
    reg [24:0] s = 0;
    reg [11:0] orun = 0;
    wire [12:0] e = phase_i - pred;                             // s13 acceleration
    wire        glitch = (glitch_th_i != 13'd0) && chk[1] &&
                         (($signed({e[12], e}) > $signed({1'b0, glitch_th_i})) ||
                          ($signed({e[12], e}) < -$signed({1'b0, glitch_th_i})));
    assign hold_o = pvalid_i && (loss || stuck || glitch || clip);
    assign excl_o = hold_o || (pvalid_i && over && (orun != OVER_PERSIST));
    wire [12:0] d = phase_i - ph_a;                             // s13 step
    wire [24:0] sd = {u, 5'd0} - s;                             // s25
    always @(posedge clk) begin
        if (pvalid_i) begin
            loss_o <= loss;
            over_o <= over;
            stuck_o <= stuck;
            glitch_o <= glitch;
            orun <= !over ? 12'd0 : (orun == OVER_PERSIST) ? orun : orun + 1'b1;
            if (!hold_o) begin
                ph_a <= phase_i;
                pred <= phase_i + d;
                chk <= chk[1] ? chk : chk + 1'b1;
                s <= s + {{5{sd[24]}}, sd[24:5]};
                u <= u + {{7{d[12]}}, d};
            end else begin
                chk <= 2'd0;
            end
        end
        if (rst) begin
            loss_o <= 1'b0; over_o <= 1'b0; stuck_o <= 1'b0; glitch_o <= 1'b0;
            orun <= 0;
            ph_a <= 0; pred <= 0; chk <= 0; s <= 0; u <= 0;
        end
    end
    assign travel_o = s[24:5];
    wire unused = &{1'b0, mn[1:0], sd[4:0], 1'b0};

`ifdef FORMAL
    // the saturating counters stay in range; chk never passes 2; the flags are raised
    // exactly when their conditions hold (registered with the sample)
    reg f_past_valid = 1'b0;
    always @(posedge clk)
        f_past_valid <= 1'b1;
    always @(*) begin
        assert(chk <= 2'd2);
        assert(orun <= OVER_PERSIST);
        if (!pvalid_i)
            assert(!hold_o && !excl_o);
        if (hold_o)
            assert(excl_o);
    end
    always @(posedge clk) if (f_past_valid && !$past(rst) && $past(pvalid_i)) begin
        assert(loss_o == $past(loss));
        assert(over_o == $past(over));
        assert(stuck_o == $past(stuck));
        assert(glitch_o == $past(glitch));
        // a held sample moves nothing but chk (to 0)
        if ($past(hold_o)) begin
            assert(ph_a == $past(ph_a) && pred == $past(pred));
            assert(u == $past(u) && s == $past(s));
            assert(chk == 2'd0);
        end
        // the over-range run
        if (!$past(over))
            assert(orun == 12'd0);
        else if ($past(orun) != OVER_PERSIST)
            assert(orun == $past(orun) + 1'b1);
        else
            assert(orun == OVER_PERSIST);
    end
    always @(posedge clk) if (f_past_valid && !$past(rst) && $past(valid0_i)) begin
        // runs saturate at 255 and restart at 0 on a change
        if ($past(raw1_i) != $past(prev1))
            assert(run1 == 8'd0);
        else if ($past(run1) != 8'hff)
            assert(run1 == $past(run1) + 1'b1);
        else
            assert(run1 == 8'hff);
    end
`endif
endmodule
`resetall
