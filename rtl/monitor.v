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
//   t + 4  x_c = o_c - snap_c (s18); det_c = run_ok_c and x_c outside [-2048, 2047] (a
//          bit test: 1/8 of the calibrated radius); stk_c <= !chg_c and (stk_c or det_c);
//          snap_c <= o_c if chg_c; stuck = stk_1 or stk_2 (as updated)
//          r = max + min >> 2 + min >> 3           u16 radius (alpha-max-plus-beta-min)
//   t + 5  loss = ref and r < LOSS, over = ref and r > OVER
//   Every per-sample recurrence (run, stk, snap, and stage H below) is one carry chain
//   deep, so samples may come on every clock.
//   H = the clock from t + 6 to t + 7: phase_i (u13 fine phase, before the harmonic
//          correction) registered on t + 6 with pvalid_i
//          glitch = K > 0, chk == 2 and wrap13(phase - pred) outside [-2^K, 2^K - 1]
//                   (K = glitch_k_i: a bit test, no compare chain)
//          hold_o = pvalid and (loss or stuck or glitch or (clip and over))
//                   (combinational in H: the counter keeps its count and last phase,
//                   rtl/counter.v; a clipped code alone still counts)
//          excl_o = hold_o or clip or over while orun < 4095      (combinational in H:
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
    input  wire [3:0]         glitch_k_i,   // max |phase acceleration| 2^K (0: off)
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
    localparam [11:0] OVER_PERSIST = 12'd4095;

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
    // ---- t + 2 .. t + 4: the other channel's excursion, the stuck latch -----------------
    reg        v1 = 1'b0, v2 = 1'b0, v3 = 1'b0;
    reg        chg1_2 = 1'b0, chg2_2 = 1'b0, rok1_2 = 1'b0, rok2_2 = 1'b0;
    reg        chg1_3 = 1'b0, chg2_3 = 1'b0, rok1_3 = 1'b0, rok2_3 = 1'b0;
    reg signed [16:0] o1 = 0, o2 = 0;            // t + 3: the other channel, signed
    reg        stk1 = 1'b0, stk2 = 1'b0, stuck4 = 1'b0;
    reg signed [16:0] snap1 = 0, snap2 = 0;
    wire signed [17:0] x1 = {o1[16], o1} - {snap1[16], snap1};
    wire signed [17:0] x2 = {o2[16], o2} - {snap2[16], snap2};
    wire far1 = (x1[17:11] != {7{x1[17]}});      // x outside [-2048, 2047]
    wire far2 = (x2[17:11] != {7{x2[17]}});
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
            if (chg1_3)
                snap1 <= o1;
            if (chg2_3)
                snap2 <= o2;
        end
        if (rst) begin
            v1 <= 1'b0; v2 <= 1'b0; v3 <= 1'b0; stk1 <= 1'b0; stk2 <= 1'b0;
            snap1 <= 0; snap2 <= 0;
        end
    end
    // the stuck flag of edge t + 4, at t + 6
    reg [1:0] stuck_d = 0;
    always @(posedge clk)
        stuck_d <= {stuck_d[0], stuck4};
    wire stuck = stuck_d[1];
    // the clip flag of edge t, at t + 5 (into `early`, below)
    reg [4:0] clip_d = 0;
    always @(posedge clk)
        clip_d <= {clip_d[3:0], clip_i};

    // ---- t .. t + 5: the radius ---------------------------------------------------------
    reg        ref0 = 1'b0, ref1 = 1'b0, ref2 = 1'b0, ref3 = 1'b0, ref4 = 1'b0;
    reg [14:0] mx3 = 0, mn3 = 0;
    reg [15:0] r4 = 0;
    reg        loss5 = 1'b0, over5 = 1'b0, loss6 = 1'b0, over6 = 1'b0;
    always @(posedge clk) begin
        {ref0, ref1, ref2, ref3, ref4} <= {ref_i, ref0, ref1, ref2, ref3};
        mx3 <= (ay_i <= ax_i) ? ax_i : ay_i;
        mn3 <= (ay_i <= ax_i) ? ay_i : ax_i;
        r4 <= {1'b0, mx3} + {3'd0, mn3[14:2]} + {4'd0, mn3[14:3]};
        loss5 <= ref4 && (r4 < loss_th_i);
        over5 <= ref4 && (r4 > over_th_i);
        loss6 <= loss5;
        over6 <= over5;
    end
    wire loss = loss6, over = over6;
    // loss, stuck or clip with over-range of the sample in H, combined on the edge before
    // (t + 6); clip alone for the estimator
    reg early = 1'b0, clip6 = 1'b0;
    always @(posedge clk) begin
        early <= loss5 || stuck_d[0] || (clip_d[4] && over5);
        clip6 <= clip_d[4];
    end

    // ---- stage H ----------------------------------------------------------------------------
    reg [12:0] ph_a = 0, pred = 0;
    reg [1:0]  chk = 0;
    reg [19:0] u = 0;
    reg [24:0] s = 0;
    reg [11:0] orun = 0;
    wire [12:0] e = phase_i - pred;                             // s13 acceleration
    // e outside [-2^K, 2^K - 1] <=> a bit of e[11:K] differs from the sign e[12]
    wire [11:0] e_off = e[11:0] ^ {12{e[12]}};
    reg         big;
    integer     kb;
    always @* begin
        big = 1'b0;
        for (kb = 1; kb < 12; kb = kb + 1)
            if (kb >= glitch_k_i && e_off[kb])
                big = 1'b1;
    end
    wire        glitch = (glitch_k_i != 4'd0) && (glitch_k_i < 4'd12) && chk[1] && big;
    assign hold_o = pvalid_i && (early || glitch);
    assign excl_o = hold_o || (pvalid_i && (clip6 || (over && (orun != OVER_PERSIST))));
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
    wire unused = &{1'b0, mn3[1:0], sd[4:0], x1[10:0], x2[10:0], 1'b0};

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
