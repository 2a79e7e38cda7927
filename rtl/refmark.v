`timescale 1ns / 1ps
`default_nettype none
// refmark: reference marks (sim/model/refmark.py). The reference input's window, the
// count at which the fine phase passes the reference phase inside it, Z at the paced A/B
// pins, REF_COUNT latched once per pass, homing, and pos_valid.
//
// The reference point. The count (phase mode) is c = B + q, B stepping by 4 n per signal
// period and q = floor(n phase / 2048) in 0 .. 4 n - 1 the count within the period, so the
// counts where q = ref_q are where the fine phase passes 2048 ref_q / n: once per signal
// period. A sample's count step from the previous count c' to c crosses one when, with
// kf = (q - ref_q) mod 4 n and kr = (ref_q - q) mod 4 n:
//     c > c' and kf < c - c'    (forward: the crossed count is x = c - kf)
//     c < c' and kr < c' - c    (reverse: x = c + kr)
// i.e. x lies in (c', c] or [c, c'), so the pins pass x whichever way they move (a
// decoder sees Z in the same A/B state in both directions). No crossing is taken on the
// first trusted sample after rst or inval_i (there is no step before it), on a held
// sample (its count does not move) or the sample after it (its step may span a coast
// through a fault: rtl/monitor.v), on an overspeed sample (its step is ambiguous), in
// edge mode (count_mode = 1: the count is not B + q) or with ref_q >= 4 n (no count is
// ever at it).
//
// The window. The reference input ref_i of each sample, glitch-filtered: the window takes
// a new level once the input has shown it on filt_i + 1 consecutive samples (filt_i = 0:
// at once). A crossing counts only inside the window. The reference mark, with ref_q,
// should put exactly one reference point inside the window (a window narrower than a
// signal period, the point near its middle: then every pass finds the same x). The
// sample that crosses the point must lie inside the window as filtered, which opens
// filt_i samples after the input: the stage must move less than w / 2 / max(1, filt_i)
// per sample (w the window's width; faster passes find no reference).
//
// Z. A crossing inside the window arms Z at x (z_en_o, z_at_o; rtl/abgen.v raises Z while
// the pins stand at x). Z is disarmed once the window is closed and the pins and their
// target are both strictly on one side of x (no passage over x is pending): the pins
// still reach x when they lag the count (at speed, with a backlog), and a stage dithering
// on the mark gives Z each time the pins are at x.
//
// The latch. One per pass: the window's rise arms it, the first crossing inside the
// window takes it: REF_COUNT = x + off (the count at the reference), homed = 1 (a
// reference latched since rst). A stage at rest or dithering on the mark therefore
// latches once, and every latch of the same mark gives the same count. Homing
// (home_arm_i, REF.home): the next latch sets off = HOME - x first, so the count
// (m_count = raw count + off) reads HOME at the reference, REF_COUNT = HOME, and
// pos_valid = 1; the pins keep counting as before (a controller homes its own count on
// Z). m_count changes with off on t + 10 of the homing sample, without m_valid. With
// distance-coded marks (dc_en_i, rtl/dcode.v) a latch does not home: the decode that sets
// abs_valid does (dc_home_i, off = HOME + ABS_COUNT - x, REF_COUNT = HOME + ABS_COUNT),
// on its last edge. cross_o, cdir_o, mark_o, x_o and inv_o feed the decoder.
//
// Z with the Eq. 12 pulses on the pins (ABGEN.ab_src = 1): the pins are the pulses one
// edge late (pa_o, pb_o: registered on t + 10 like the paced pins), and zp_o is high while
// they show the reference count's A/B state in the reference count's n-th order period.
// The pulses lag the phase by their hysteresis, so the count they show is
// qp = q - delta (mod 4 n), delta = (q - pq) mod 4 taken as -1, 0, 1 or 2 (pq their
// quadrant code, rtl/counter.v), which is ref_q exactly when kf = delta (mod 4 n). Z rises
// on a sample inside the window whose pulses show that count, and stays high while the
// pulses stay in that state (a window closing does not cut it): one A/B state wide.
//
// pos_valid: 0 after rst; 1 from homing (a homing latch, or the homing decode: dc_home_i);
// 0 again on a sample whose count may be off by a period: lost_i (a held sample on which
// the monitor's coast through a fault reached a quarter period of uncertainty, or one with
// no line to coast along: rtl/monitor.v) or an overspeed sample; and on inval_i (the core: a
// write that changes INTERP, whose counts then mix two scales, or count_mode = 1; it
// also disarms Z and takes no crossing on the next sample).
// lost_o pulses when pos_valid falls (REF_STICKY.lost).
//
// Timing (t = the sample's strobe edge; the core's count is registered on t + 8):
//   t + 8  kf, kr, zok from q_i (registered with the n-th order product on t + 7)
//   t + 9  the window, the crossing and x; Z armed; target_o (the pins follow from t + 10)
//   t + 10 REF_COUNT, off, homed, pos_valid, home_armed_o; latch_o, lost_o pulses; the
//          Eq. 12 pins and their Z (the pulses registered on t + 9)
// Cost: COUNT_W registers for the previous count, the pins' target, z_at, x, off, REF_COUNT;
// three COUNT_W adders (x, HOME - x, x + off), two COUNT_W subtracts (the disarm sides),
// 12-bit arithmetic for kf, kr and the step. No multipliers.
module refmark #(
    parameter COUNT_W = 32                       // 17..32
) (
    input  wire                      clk,
    input  wire                      rst,
    // t + 7: the sample's n-th order product (rtl/lut.v prod_o), its count part
    input  wire                      nv_i,       // valid on t + 7
    input  wire [10:0]               q_i,        // u11 floor(n phase / 2048), 0 .. 4 n - 1
    input  wire [8:0]                n_i,        // u9 n
    input  wire [10:0]               ref_q_i,    // u11 REF.ref_q
    input  wire [3:0]                filt_i,     // u4 REF.ref_filt
    input  wire                      mode_i,     // count mode: 1 edge (no reference)
    // t + 8: the sample's count (rtl/counter.v) and its reference input
    input  wire                      cv_i,
    input  wire signed [COUNT_W-1:0] count_i,    // the counter's count (before off)
    input  wire                      held_i,     // the count held (not edge mode)
    input  wire                      lost_i,     // with cv_i: the travel lost (rtl/monitor.v)
    input  wire                      ovs_i,
    input  wire                      ref_i,
    // t + 9: the sample's Eq. 12 pulses (rtl/pulse.v)
    input  wire                      pv_i,
    input  wire                      pa_i,
    input  wire                      pb_i,
    output reg                       pa_o,       // the pulses one edge later (the pins)
    output reg                       pb_o,
    output reg                       zp_o,       // Z beside them
    // the pins (rtl/abgen.v)
    input  wire signed [COUNT_W-1:0] pos_i,      // the count the pins show
    output reg  signed [COUNT_W-1:0] target_o,   // count_i one edge later: the pins' target
    output reg                       z_en_o,
    output reg  signed [COUNT_W-1:0] z_at_o,
    // settings and status
    input  wire                      home_arm_i, // a pulse: home at the next latch
    input  wire signed [COUNT_W-1:0] home_i,     // HOME
    input  wire                      inval_i,    // a pulse: the count lost its scale
    // distance-coded marks (rtl/dcode.v)
    input  wire                      dc_en_i,    // DCODE on: homing waits for dc_home_i
    input  wire                      dc_home_i,  // the decode sets abs_valid: home now
    input  wire signed [COUNT_W-1:0] dc_off_i,   // with it: HOME + ABS_COUNT - x
    input  wire signed [COUNT_W-1:0] dc_ref_i,   // with it: HOME + ABS_COUNT
    output reg                       cross_o,    // t + 9: the sample crossed a reference point
    output reg                       cdir_o,     // (1: back)
    output wire                      mark_o,     // t + 9: the sample latches (latch_o's source)
    output wire signed [COUNT_W-1:0] x_o,        // its count
    output wire                      inv_o,      // t + 9: the count lost its scale
    output reg  signed [COUNT_W-1:0] off_o,      // the homing offset (m_count = count + off)
    output reg  signed [COUNT_W-1:0] ref_count_o,
    output reg                       win_o,      // the window (the filtered reference)
    output reg                       homed_o,    // a reference latched since rst
    output reg                       pos_valid_o,
    output reg                       home_armed_o,
    output reg                       latch_o,    // a pulse: a reference latched
    output reg                       lost_o      // a pulse: pos_valid fell
);
    // parameter check (as rtl/finequad_core.v; rtl/vhdl/refmark.vhd's range): an
    // undefined module named after the rule stops elaboration
    generate
        if (COUNT_W < 17 || COUNT_W > 32) begin : g_bad_count_w
            refmark_COUNT_W_must_be_17_to_32 u_bad ();
        end
    endgenerate
    // ---- t + 8: kf, kr (12-bit two's complement, then + 4 n when negative) -----------------
    wire [11:0] n4 = {1'b0, n_i, 2'b00};
    wire [11:0] kf0 = {1'b0, q_i} - {1'b0, ref_q_i};
    wire [11:0] kr0 = {1'b0, ref_q_i} - {1'b0, q_i};
    reg  [11:0] kf = 12'd0, kr = 12'd0;
    reg         zok = 1'b0;
    reg  [1:0]  qlo = 2'd0;                      // q mod 4 (the phase's quadrant)
    always @(posedge clk) begin
        if (nv_i) begin
            kf <= kf0[11] ? kf0 + n4 : kf0;
            kr <= kr0[11] ? kr0 + n4 : kr0;
            zok <= ({1'b0, ref_q_i} < n4);
            qlo <= q_i[1:0];
        end
        if (rst) begin
            kf <= 12'd0;
            kr <= 12'd0;
            zok <= 1'b0;
            qlo <= 2'd0;
        end
    end

    // ---- t + 9: the window, the crossing, Z --------------------------------------------------
    reg  [11:0] cp = 12'd0;                      // the previous sample's count, low bits
    reg         primed = 1'b0;                   // cp holds a trusted phase-mode count
    reg  [3:0]  fc = 4'd0;                       // samples the input has differed
    reg         arm = 1'b0;                      // the latch is armed (this pass)
    reg         lat1 = 1'b0, inv1 = 1'b0;
    reg  signed [COUNT_W-1:0] x_q = 0;
    reg  [11:0] kf1 = 12'd0;                     // kf, qlo, zok of the sample in stage 1
    reg  [1:0]  qlo1 = 2'd0;
    reg         zok1 = 1'b0;
    // the step c - c' in 12 bits: |step| <= 2 n <= 1022 on a sample without overspeed
    wire [11:0] dc = count_i[11:0] - cp;
    wire        fwd = !dc[11] && (dc != 12'd0);
    wire        rev = dc[11];
    /* verilator lint_off UNUSEDSIGNAL */
    wire [12:0] rsum = {1'b0, kr} + {dc[11], dc};          // kr + (c - c') < 0: kr < c' - c
    /* verilator lint_on UNUSEDSIGNAL */
    wire        hit = primed && !mode_i && zok && !held_i && !ovs_i &&
                      ((fwd && kf < dc) || (rev && rsum[12]));
    wire        flip = (ref_i != win_o) && (fc >= filt_i);
    wire        win_n = flip ? ref_i : win_o;
    wire        xc = cv_i && hit && win_n;
    wire        arm_n = arm || (win_n && !win_o);
    wire        lat_n = xc && arm_n;
    wire signed [COUNT_W-1:0] x = count_i + (fwd ? -{{(COUNT_W-12){1'b0}}, kf}
                                                 : {{(COUNT_W-12){1'b0}}, kr});
    // disarm: the window closed, the pins and their target strictly on one side of z_at
    wire signed [COUNT_W-1:0] sp = pos_i - z_at_o;
    wire signed [COUNT_W-1:0] st = target_o - z_at_o;
    wire        off_side = !win_o && (sp != 0) && (st != 0) && (sp[COUNT_W-1] == st[COUNT_W-1]);
    always @(posedge clk) begin
        target_o <= count_i;
        lat1 <= 1'b0;
        inv1 <= 1'b0;
        cross_o <= 1'b0;
        if (cv_i) begin
            cp <= count_i[11:0];
            primed <= !held_i && !mode_i;
            win_o <= win_n;
            fc <= (ref_i == win_o || flip) ? 4'd0 : fc + 4'd1;
            arm <= arm_n && win_n && !lat_n;
            lat1 <= lat_n;
            inv1 <= lost_i || ovs_i;
            x_q <= x;
            cross_o <= hit;
            cdir_o <= rev;
            kf1 <= kf;
            qlo1 <= qlo;
            zok1 <= zok;
        end
        if (xc) begin
            z_en_o <= 1'b1;
            z_at_o <= x;
        end else if (off_side)
            z_en_o <= 1'b0;
        if (inval_i) begin
            primed <= 1'b0;
            z_en_o <= 1'b0;
        end
        if (rst) begin
            target_o <= 0;
            cp <= 12'd0;
            primed <= 1'b0;
            win_o <= 1'b0;
            fc <= 4'd0;
            arm <= 1'b0;
            lat1 <= 1'b0;
            inv1 <= 1'b0;
            x_q <= 0;
            cross_o <= 1'b0;
            cdir_o <= 1'b0;
            kf1 <= 12'd0;
            qlo1 <= 2'd0;
            zok1 <= 1'b0;
            z_en_o <= 1'b0;
            z_at_o <= 0;
        end
    end

    assign mark_o = lat1;
    assign x_o = x_q;
    assign inv_o = inv1 || inval_i;

    // ---- t + 10: the Eq. 12 pins and their Z ------------------------------------------------------
    wire [1:0]  pq = {~pb_i, pa_i ^ pb_i};       // quadrant codes (rtl/counter.v)
    wire [1:0]  pq_d = {~pb_o, pa_o ^ pb_o};
    wire [1:0]  dl = qlo1 - pq;                  // delta mod 4: 3 is -1
    wire [11:0] n4m1 = n4 - 12'd1;
    wire        at_ref = (dl == 2'd3) ? (kf1 == n4m1) : (kf1 == {10'd0, dl});
    always @(posedge clk) begin
        if (pv_i) begin
            pa_o <= pa_i;
            pb_o <= pb_i;
            zp_o <= (win_o && zok1 && at_ref) || (zp_o && pq == pq_d);
        end
        if (rst) begin
            pa_o <= 1'b1;
            pb_o <= 1'b1;
            zp_o <= 1'b0;
        end
    end

    // ---- t + 10: the latch, homing, pos_valid --------------------------------------------------
    always @(posedge clk) begin
        latch_o <= lat1;
        lost_o <= pos_valid_o && (inv1 || inval_i);
        if (lat1) begin
            homed_o <= 1'b1;
            if (home_armed_o && !dc_en_i) begin
                pos_valid_o <= 1'b1;
                off_o <= home_i - x_q;
                ref_count_o <= home_i;
            end else
                ref_count_o <= x_q + off_o;
        end
        if (lat1 && home_armed_o && !dc_en_i)
            home_armed_o <= 1'b0;
        // distance-coded homing (never with lat1 or an invalidation: rtl/dcode.v)
        if (dc_home_i && home_armed_o) begin
            off_o <= dc_off_i;
            ref_count_o <= dc_ref_i;
            pos_valid_o <= 1'b1;
            home_armed_o <= 1'b0;
        end
        if (home_arm_i)
            home_armed_o <= 1'b1;
        if (inv1 || inval_i)
            pos_valid_o <= 1'b0;
        if (rst) begin
            latch_o <= 1'b0;
            lost_o <= 1'b0;
            homed_o <= 1'b0;
            pos_valid_o <= 1'b0;
            home_armed_o <= 1'b0;
            off_o <= 0;
            ref_count_o <= 0;
        end
    end
    initial begin
        target_o = 0; z_en_o = 1'b0; z_at_o = 0; off_o = 0; ref_count_o = 0; win_o = 1'b0;
        homed_o = 1'b0; pos_valid_o = 1'b0; home_armed_o = 1'b0; latch_o = 1'b0;
        lost_o = 1'b0; pa_o = 1'b1; pb_o = 1'b1; zp_o = 1'b0; cross_o = 1'b0; cdir_o = 1'b0;
    end

`ifdef FORMAL
    // ---- formal properties (sim/formal/refmark.sby; every input free on every clock) --------
    //  R1 at most one latch per pass: between two latches the window was closed (f_lip: a
    //     latch since the window last was closed, as registered on the edge before).
    //  R2 a latch only inside the window, with a crossing of the sample's count step.
    //  R3 Z is armed only at a crossing inside the window, at its count x; z_at changes
    //     only then (inval_i disarms it).
    //  R4 pos_valid rises only with homing: a homing latch, or with distance-coded marks
    //     the decode that sets abs_valid; a sample with lost_i or overspeed (inv1, the edge
    //     after it) or inval_i clears it on the next edge, and lost_o pulses if it was set;
    //     nothing else clears it (a held sample whose coast kept the travel does not).
    //  R5 a crossing (cross_o, hence a latch or Z armed) only on a sample that is not held,
    //     not at overspeed, in phase mode, with ref_q < 4 n, whose previous sample since rst
    //     and inval_i was counted (not held, phase mode): its step may span a coast.
    reg f_past_valid = 1'b0, f_rst = 1'b0, f_lip = 1'b0, f_prv = 1'b0;
    reg f_xc = 1'b0, f_lat = 1'b0, f_inv = 1'b0, f_pv = 1'b0, f_inval = 1'b0;
    reg signed [COUNT_W-1:0] f_x = 0, f_zat = 0;
    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst <= rst;
        f_xc <= xc;
        f_lat <= lat_n;
        f_x <= x;
        f_zat <= z_at_o;
        f_inv <= cv_i && (lost_i || ovs_i);
        f_inval <= inval_i;
        f_pv <= pos_valid_o;
        if (rst || inval_i)
            f_prv <= 1'b0;
        else if (cv_i)
            f_prv <= !held_i && !mode_i;
        if (rst || !win_o)
            f_lip <= 1'b0;
        else if (lat1)
            f_lip <= 1'b1;
    end
    always @(*) begin
        if (f_past_valid && !f_rst) begin
            if (lat1)
                assert (!f_lip && win_o && f_xc);                            // R1, R2
            assert (lat1 == f_lat);
            if (f_xc)
                assert (z_en_o == !f_inval && z_at_o == f_x);                // R3
            else
                assert (z_at_o == f_zat);
            // induction: a latch in this pass disarms the latch until the window closes
            if (f_lip)
                assert (!arm);
            if (arm)
                assert (win_o);
            assert (inv1 == f_inv);                                          // R4
        end
        assert (primed == f_prv);                                            // R5
    end
    always @(posedge clk) begin
        if (f_past_valid && !rst && !f_rst) begin
            if (pos_valid_o && !$past(pos_valid_o))
                assert ($past(home_armed_o) &&                               // R4
                        (($past(lat1) && !$past(dc_en_i)) || $past(dc_home_i)));
            if ($past(inv1) || $past(inval_i))
                assert (!pos_valid_o && lost_o == $past(pos_valid_o));
            if ($past(pos_valid_o) && !pos_valid_o)
                assert ($past(inv1 || inval_i));
        end
        if (f_past_valid && !f_rst && cross_o)                               // R5
            assert ($past(cv_i && !held_i && !ovs_i && !mode_i && zok && f_prv));
    end
    always @(posedge clk) begin
        if (f_past_valid && !f_rst) begin
            cover (lat1 && homed_o);                 // a second pass latches again
            cover (z_en_o && !win_o && off_side);    // Z disarmed after the window
            // a held sample keeps pos_valid (its coast kept the travel); lost_i clears it
            cover (pos_valid_o && $past(cv_i && held_i && !lost_i));
            cover (lost_o && $past(cv_i && lost_i && !ovs_i, 2) && !$past(inval_i));
        end
    end
`endif
endmodule
`resetall
