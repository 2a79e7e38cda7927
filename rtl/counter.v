`timescale 1ns / 1ps
`default_nettype none
// counter: position count of the n-th order, two modes (sim/model/counter.py counter()).
// Counts up when the phase increases (u1 leads u2).
//
// Phase mode (mode_i = 0, the default): the count follows the unwrapped fine phase Phi
// (8192 units per signal period) exactly:
//     count = floor(4 n Phi / 8192) = B + q,   B = 4 n W,   q = floor(n f / 2048)
// with Phi = 8192 W + f, f the fine phase in [0, 8192) and W the signal periods, so no
// multiplier is needed here: q is the high part of the product n f that rtl/lut.v forms
// for the n-th order phase anyway, and B steps by -+4 n when the phase wraps. Per sample,
// with raw = f - f_prev (s14, f_prev = 0 after rst) and dph = wrap13(raw) in
// [-4096, 4095]: the phase moved by dph, and wrapped backwards when raw >= 4096
// (B -= 4 n) or forwards when raw < -4096 (B += 4 n). Nothing is lost at any speed below
// half a signal period per sample, whatever n. After rst, Phi starts at wrap13(f_0)
// (count aligned to the absolute phase, modulo 4 n counts). n is sampled with the sample
// on both stages: change it at standstill (B keeps the factor it was built with).
// Overspeed (ovs_o): |dph| >= 3072 (3/4 pi or more per sample; near pi the direction of
// the step, hence the position, becomes ambiguous); never on the first sample after rst.
// Hold (hold_i with valid_i, rtl/monitor.v: a signal below COAST.floor, a stuck channel, a
// glitch, a rail with over-range; the phase is not trusted): the sample's count is the one before (count_o stays; no
// overspeed). With coast_i the count follows the monitor's line through the fault: f_prev
// <- line_i and B steps by the line's wraps, so the next trusted sample steps from where
// the line has come (right while the line is within half a period of the stage: the
// monitor clears pos_valid at a quarter); without it B and f_prev stay, and the next
// trusted sample steps from the last trusted phase. The edge mode ignores hold_i.
//
// Edge mode (mode_i = 1, the paper's counter, Sec. 2.3, for comparison): an x4
// quadrature decoder of the Eq. 12 pulses A/B (rtl/pulse.v): +1 / -1 per single-channel
// step (quadrant step 1 / 3 modulo 4), 0 for none; a step where both A and B change is
// illegal: not counted (the count is lost), counted in ill_count_o. The decoder runs in
// both modes, from rst (ill_count_o counts the pulses' illegal steps either way; its
// count E starts at 0 with rst, so switch modes together with a reset). The pulses of a
// sample arrive two edges after its phase-mode count, so in edge mode count_o of a
// sample holds E as of its output edge: the steps of the samples strobed at least 3
// edges before it.
//
// Timing (e = the edge registering phase_i, t + 6 in the core):
//   e + 1  B, f_prev; the step dph and whether it may flag overspeed (a trusted sample
//          after a first one); prod_i = n * phase_i arrives registered (rtl/lut.v)
//   e + 2  count_o = mode ? E : B + prod_i[21:11]; valid_o, ovs_o (the step's test)
//   pulses: pv_i with a_i, b_i on edge p (t + 9); E and ill_count_o updated on p + 1
module counter #(
    // counter width (wraps), 16..32
    parameter COUNT_W = 32
) (
    input  wire                      clk,
    input  wire                      rst,
    input  wire                      valid_i,
    input  wire                      hold_i,     // with valid_i: do not count this sample
    input  wire                      coast_i,    // with hold_i: follow line_i instead
    input  wire [12:0]               line_i,     // u13 the monitor's line (rtl/monitor.v)
    input  wire [12:0]               phase_i,    // u13 fine phase (registered, edge e)
    input  wire [21:0]               prod_i,     // u22 n * phase_i, registered on e + 1
    input  wire [8:0]                n_i,        // u9 n, 1..511
    input  wire                      mode_i,     // 0 phase, 1 edge (x4 of A/B)
    input  wire                      pv_i,       // Eq. 12 pulses of a sample
    input  wire                      a_i,
    input  wire                      b_i,
    output reg                       valid_o,
    output reg  signed [COUNT_W-1:0] count_o,    // s(COUNT_W), wraps
    output reg                       ovs_o,      // overspeed (with valid_o)
    output reg                       ill_o,      // an illegal A/B step (pulse, edge p + 1)
    output reg  [15:0]               ill_count_o, // u16 illegal A/B steps since rst, wraps
    output reg                       held_o      // with valid_o: a held sample, phase mode
);
`include "geu.vh"                          // geu(a, b): a >= b, unsigned, bit by bit
    // parameter check (as rtl/finequad_core.v; rtl/vhdl/counter.vhd's range): an undefined
    // module named after the rule stops elaboration
    generate
        if (COUNT_W < 16 || COUNT_W > 32) begin : g_bad_count_w
            counter_COUNT_W_must_be_16_to_32 u_bad ();
        end
    endgenerate
    // ---- e + 1: wrap, B ------------------------------------------------------------------
    reg  [12:0] ph_prev = 13'd0;
    reg         primed = 1'b0;
    reg  signed [COUNT_W-1:0] b_acc = 0;         // B = 4 n W, s(COUNT_W), wraps
    // the step from the last phase taken: the sample's, or the line's on a coast (both
    // differences side by side; hold_i only selects)
    wire [13:0] raw_p = {1'b0, phase_i} - {1'b0, ph_prev};       // s14
    wire [13:0] raw_l = {1'b0, line_i} - {1'b0, ph_prev};
    wire [13:0] raw = hold_i ? raw_l : raw_p;
    wire        take = valid_i && (!hold_i || coast_i);
    wire        back = (raw[13:12] == 2'b01);   // raw >= 4096: wrapped backwards
    wire        fwd  = (raw[13:12] == 2'b10);   // raw < -4096: wrapped forwards
    wire [12:0] dph = raw[12:0];                 // wrap13, as u13
    // |wrap13| >= 3072, of a step registered on e + 1 (the test waits for the count's edge,
    // so no comparison follows the phase difference)
    function automatic ovs_of(input [12:0] d);
        ovs_of = geu({19'd0, d}, 32'd3072) && geu(32'd5120, {19'd0, d});
    endfunction
    wire signed [COUNT_W-1:0] n4 = {{(COUNT_W-11){1'b0}}, n_i, 2'b00};
    // B - 4n and B + 4n beside the phase difference (two adders from B and n, which do
    // not wait for the phase): the wrap test only chooses between them and B
    wire signed [COUNT_W-1:0] b_dn = b_acc - n4;
    wire signed [COUNT_W-1:0] b_up = b_acc + n4;
    reg         v1 = 1'b0, ovc1 = 1'b0, hold1 = 1'b0;
    reg  [12:0] dph1 = 13'd0;
    wire        ovs1 = ovc1 && ovs_of(dph1);     // the sample of v1 is at overspeed
    always @(posedge clk) begin
        v1 <= valid_i;
        ovc1 <= primed && !hold_i;
        dph1 <= dph;
        hold1 <= hold_i;
        if (valid_i && !hold_i)
            primed <= 1'b1;
        if (take) begin
            ph_prev <= hold_i ? line_i : phase_i;
            if (back)
                b_acc <= b_dn;
            else if (fwd)
                b_acc <= b_up;
        end
        if (rst) begin
            v1 <= 1'b0;
            ph_prev <= 13'd0;
            primed <= 1'b0;
            b_acc <= 0;
        end
    end

    // ---- edge decoder (pulses) -----------------------------------------------------------
    // quadrant code: (1,1) 0, (0,1) 1, (0,0) 2, (1,0) 3
    reg  signed [COUNT_W-1:0] e_acc = 0;         // E
    reg  [1:0]  qd_prev = 2'd0;
    reg         eprimed = 1'b0;
    wire [1:0]  qd = {~b_i, a_i ^ b_i};
    wire [1:0]  dq = qd - qd_prev;
    always @(posedge clk) begin
        ill_o <= 1'b0;
        if (pv_i) begin
            qd_prev <= qd;
            eprimed <= 1'b1;
            if (dq == 2'd2 && eprimed) begin
                ill_o <= 1'b1;
                ill_count_o <= ill_count_o + 1'b1;
            end
        end
        if (pv_i && dq[0])                       // dq 1: +1, 3: -1 (one adder)
            e_acc <= e_acc + {{(COUNT_W-1){dq[1]}}, 1'b1};
        if (rst) begin
            qd_prev <= 2'd0;
            eprimed <= 1'b0;
            ill_o <= 1'b0;
            ill_count_o <= 16'd0;
            e_acc <= 0;
        end
    end

    // ---- e + 2: the count -----------------------------------------------------------------
    wire signed [COUNT_W-1:0] q = {{(COUNT_W-11){1'b0}}, prod_i[21:11]};
    always @(posedge clk) begin
        valid_o <= v1;
        ovs_o <= v1 && ovs1;
        held_o <= v1 && hold1 && !mode_i;
        if (v1 && (mode_i || !hold1))
            count_o <= mode_i ? e_acc : b_acc + q;
        if (rst) begin
            valid_o <= 1'b0;
            ovs_o <= 1'b0;
            held_o <= 1'b0;
            count_o <= 0;
        end
    end
    initial begin
        valid_o = 1'b0; count_o = 0; ovs_o = 1'b0; ill_o = 1'b0; ill_count_o = 16'd0;
        held_o = 1'b0;
    end
    wire unused = &{1'b0, prod_i[10:0], 1'b0};
`ifdef FORMAL
    // ---- formal properties (sim/formal/counter.sby) -----------------------------------------
    // Every input is free on every clock but prod_i (the abstraction below). Ghost state f_*
    // is rebuilt from the inputs alone (the last phase taken, the last trusted sample, B by
    // the wrap rule, the net wraps coasted since the last trusted sample, the last pulse's
    // A/B); invariants I1..I4 tie it to the registers (k-induction). Stage 1 = the edge
    // sampling valid_i (B, f_prev), stage 2 = the next one (count_o, valid_o). A sample
    // (valid_i) is trusted without hold_i and coasted with hold_i && coast_i; both are
    // taken: the trusted sample's phase_i, the coasted one's line_i becomes the last phase
    // taken (f_prev, 0 after rst).
    //  C1 rst: count_o, valid_o, ovs_o, ill_o, ill_count_o, B, the last phase and E are 0.
    //  C2 valid_o two edges after valid_i (lost on a rst edge); count_o changes only on an
    //     edge that raises valid_o with a sample (it holds between samples).
    //  C3 phase mode: B moves only on a sample taken, by -4n (the phase taken wrapped
    //     backwards from the last one: raw >= 4096), +4n (raw < -4096) or 0, n of the
    //     sample; count_o of a trusted sample = B + prod >> 11.
    //  C4 phase mode, the step of a trusted sample's count from the previous trusted
    //     sample's, when it, the previous one and the samples coasted between them had the
    //     same n (see "n" below): it has the sign of the unwrapped travel along the phases
    //     taken, P = 8192 Wd + (phase - previous trusted phase) (Wd the net wraps of the
    //     phases taken since the previous trusted sample: the coasted lines, then the
    //     phase; 0 for P = 0), and it is at most 2n counts (half a period) when |P| <= 4096.
    //     With no coast between, P = wrap13(phase - previous trusted phase), in [-4096,
    //     4095]: at most 2n in the direction of the phase step. Claimed from the first
    //     trusted sample after rst on (coasts before it: not) while |Wd| stays <= 1 along
    //     the path (the step then stays within 8 n: no wrap of the count; B's steps on the
    //     coasts themselves, C3, are exact for any path); likewise for count_o when the
    //     previous one shown was a phase-mode count.
    //  C5 a held sample never flags overspeed and (phase mode) leaves count_o as it was;
    //     without coast_i it leaves B and the last phase taken as they were; with coast_i,
    //     line_i becomes the last phase and B steps by its wrap (C3).
    //  C6 ovs_o == |wrap13(phase - last phase taken)| >= 3072 of a trusted sample, only
    //     with valid_o, never before a first trusted sample after rst (coasts do not prime
    //     it).
    //  C7 edge mode: E moves only with a pulse, by +1 / -1 (a single-channel step, x4
    //     direction: A changed to != B, or B changed to == A, is up) or 0 (none, or both:
    //     illegal, never counted); an illegal step after the first pulse since rst raises
    //     ill_o on the next edge and adds 1 to ill_count_o (mod 2^16); count_o of an
    //     edge-mode sample is E.
    // n: B keeps the factors it was built with (the header: change n at standstill), so
    // across a change of n the count may jump; C4 is claimed for trusted samples (and the
    // coasts between them) with the same n only (n free otherwise, every other property
    // for any n).
    // prod_i: the counter trusts rtl/lut.v for prod = n * phase of the sample (registered
    // one edge after the phase, i.e. on stage 2; lut.v forms it on every edge from the same
    // n and phase nets, core wiring). An exact `*` in the proof leaves z3 on two 9x13
    // products for longer than 10 minutes, so the product is abstracted ZipCPU-style: only
    // what n * phase implies for two trusted samples with the same n > 0 is assumed, for
    // Y = prod - prod_last (= n * raw, raw = phase - phase_last, the previous trusted
    // sample's, whatever was coasted between; phase_last = prod_last = 0 after rst): Y
    // compares with n*c as raw compares with c, c in {0, +-4096, +-8192}; n = 0: Y = 0.
    // Nothing else about prod (single samples, n changes) is assumed.
`ifdef COUNTER
`define ASSUME assume
`else
`define ASSUME assert
`endif
    reg                      f_past_valid = 1'b0;
    always @(posedge clk)
        f_past_valid <= 1'b1;

    // ---- stage 1 ghosts: the last phase taken, the last trusted sample since rst, B by the
    // wrap rule, the net wraps since that sample ------------------------------------------
    reg        [12:0]         f_lph = 13'd0;    // the last phase taken (0 after rst)
    reg        [12:0]         f_tph = 13'd0;    // the last trusted sample's phase (0 after rst)
    reg        [8:0]          f_ln = 9'd0;      // its n
    reg                       f_lok = 1'b0;     // one was taken since rst
    reg signed [COUNT_W-1:0]  f_b = 0;          // B
    reg signed [COUNT_W-1:0]  f_bt = 0;         // B after the last trusted sample
    reg signed [2:0]          f_wd = 3'sd0;     // Wd of the coasts since it
    reg                       f_wok = 1'b1;     // they had its n, |Wd| <= 1 (after a trusted one)
    reg                       f_nc = 1'b1;      // no coast since it
    wire                      f_acc = valid_i && !hold_i;
    wire                      f_cst = valid_i && hold_i && coast_i;
    wire        [12:0]        f_tk = f_acc ? phase_i : line_i;     // the phase taken
    wire signed [14:0] f_raw = $signed({2'b00, f_tk}) - $signed({2'b00, f_lph});
    wire signed [14:0] f_dph = (f_raw >= 15'sd4096) ? f_raw - 15'sd8192
                             : (f_raw < -15'sd4096) ? f_raw + 15'sd8192 : f_raw;
    wire signed [14:0] f_rawt = $signed({2'b00, phase_i}) - $signed({2'b00, f_tph});
    wire signed [COUNT_W-1:0] f_n4 = $signed({{(COUNT_W-11){1'b0}}, n_i, 2'b00});
    wire signed [COUNT_W-1:0] f_bstep = (f_raw >= 15'sd4096) ? -f_n4
                                      : (f_raw < -15'sd4096) ? f_n4 : 0;
    wire signed [3:0]  f_wn = $signed({f_wd[2], f_wd}) + ((f_raw >= 15'sd4096) ? -4'sd1
                                                        : (f_raw < -15'sd4096) ? 4'sd1 : 4'sd0);
    wire               f_wokn = f_wok && (f_wn >= -4'sd1) && (f_wn <= 4'sd1);
    wire                      f_ovs = (f_dph >= 15'sd3072) || (f_dph <= -15'sd3072);
    // 4 n Wd for |Wd| <= 1
    function automatic signed [COUNT_W-1:0] f_nw(input [8:0] n, input signed [2:0] wd);
        reg signed [COUNT_W-1:0] n4;
        begin
            n4 = $signed({{(COUNT_W-11){1'b0}}, n, 2'b00});
            f_nw = (wd == 3'sd1) ? n4 : (wd == -3'sd1) ? -n4 : 0;
        end
    endfunction
    // stage 2 copies of the sample
    reg                       f_v1 = 1'b0, f_h1 = 1'b0, f_same1 = 1'b0, f_ovs1 = 1'b0;
    reg                       f_wok1 = 1'b0, f_nc1 = 1'b0;
    reg signed [2:0]          f_wd1 = 3'sd0;
    reg        [12:0]         f_ph1 = 13'd0;
    reg        [8:0]          f_n1 = 9'd0;
    reg signed [14:0]         f_rawt1 = 15'sd0;
    always @(posedge clk) begin
        if (f_acc || f_cst) begin
            f_lph <= f_tk;
            f_b   <= f_b + f_bstep;
        end
        if (f_acc) begin
            f_tph <= phase_i;
            f_ln  <= n_i;
            f_lok <= 1'b1;
            f_bt  <= f_b + f_bstep;
            f_wd  <= 3'sd0;
            f_wok <= 1'b1;
            f_nc  <= 1'b1;
        end else if (f_cst) begin
            f_wd  <= f_wn[2:0];
            f_wok <= f_wokn && f_lok && (n_i == f_ln);
            f_nc  <= 1'b0;
        end
        f_v1    <= valid_i && !rst;
        f_h1    <= hold_i;
        f_ph1   <= phase_i;
        f_n1    <= n_i;
        f_rawt1 <= f_rawt;
        f_wd1   <= f_wn[2:0];
        f_wok1  <= f_wokn;
        f_nc1   <= f_nc;
        f_same1 <= !f_lok || (n_i == f_ln);
        f_ovs1  <= f_acc && f_lok && f_ovs && !rst;
        if (rst) begin
            f_lph <= 13'd0;
            f_tph <= 13'd0;
            f_ln  <= 9'd0;
            f_lok <= 1'b0;
            f_b   <= 0;
            f_bt  <= 0;
            f_wd  <= 3'sd0;
            f_wok <= 1'b1;
            f_nc  <= 1'b1;
        end
    end

    // ---- stage 2 ghosts: the last trusted sample's product, B and phase-mode count --------
    reg        [21:0]         f_lp = 22'd0;
    reg        [12:0]         f_lph2 = 13'd0;
    reg signed [COUNT_W-1:0]  f_lb = 0, f_lc = 0;
    reg                       f_pm = 1'b1;      // count_o shows f_lc
    wire                      f_acc1 = f_v1 && !f_h1;
    wire signed [COUNT_W-1:0] f_q = $signed({{(COUNT_W-11){1'b0}}, prod_i[21:11]});
    wire signed [COUNT_W-1:0] f_c = f_b + f_q;  // the phase-mode count of the sample
    wire signed [COUNT_W-1:0] f_dc = f_c - f_lc;
    wire signed [COUNT_W-1:0] f_2n = $signed({{(COUNT_W-10){1'b0}}, f_n1, 1'b0});
    wire signed [14:0] f_dpt1 = (f_rawt1 >= 15'sd4096) ? f_rawt1 - 15'sd8192
                              : (f_rawt1 < -15'sd4096) ? f_rawt1 + 15'sd8192 : f_rawt1;
    // P = 8192 Wd + (phase - previous trusted phase) (s17)
    wire signed [16:0] f_p1 = $signed({f_wd1[2], f_wd1, 13'd0}) + $signed({{2{f_rawt1[14]}}, f_rawt1});
    always @(posedge clk) begin
        if (f_acc1) begin
            f_lp   <= prod_i;
            f_lph2 <= f_ph1;
            f_lb   <= f_b;
            f_lc   <= f_c;
        end
        if (f_v1)
            f_pm <= f_h1 ? (f_pm && !mode_i) : !mode_i;
        if (rst) begin
            f_lp   <= 22'd0;
            f_lph2 <= 13'd0;
            f_lb   <= 0;
            f_lc   <= 0;
            f_pm   <= 1'b1;
        end
    end

    // ---- the multiplier abstraction (see above) -------------------------------------------
    wire signed [22:0] f_y = $signed({1'b0, prod_i}) - $signed({1'b0, f_lp});
    wire signed [23:0] f_n12 = $signed({2'b00, f_n1, 13'd0} >> 1);   // n * 4096
    wire signed [23:0] f_n13 = $signed({2'b00, f_n1, 13'd0});        // n * 8192
    wire signed [23:0] f_y24 = {f_y[22], f_y};
    always @(*) if (f_acc1 && f_same1) begin
        if (f_n1 == 9'd0) begin
            `ASSUME(f_y == 0);
        end else begin
            `ASSUME((f_rawt1 >= 15'sd0)     == (f_y24 >= 24'sd0));
            `ASSUME((f_rawt1 <= 15'sd0)     == (f_y24 <= 24'sd0));
            `ASSUME((f_rawt1 >= 15'sd4096)  == (f_y24 >= f_n12));
            `ASSUME((f_rawt1 <= 15'sd4096)  == (f_y24 <= f_n12));
            `ASSUME((f_rawt1 >= -15'sd4096) == (f_y24 >= -f_n12));
            `ASSUME((f_rawt1 <= -15'sd4096) == (f_y24 <= -f_n12));
            `ASSUME((f_rawt1 >= 15'sd8192)  == (f_y24 >= f_n13));
            `ASSUME((f_rawt1 <= -15'sd8192) == (f_y24 <= -f_n13));
        end
    end

    // ---- edge mode ghosts: the last pulse's A/B ((1,1) after rst) ----------------------------
    reg  f_pa = 1'b1, f_pb = 1'b1, f_epr = 1'b0;
    wire f_ach = (a_i != f_pa), f_bch = (b_i != f_pb);
    wire signed [COUNT_W-1:0] f_estep =
        !pv_i ? 0 : (f_ach && !f_bch) ? ((a_i != b_i) ? 1 : -1)
                  : (f_bch && !f_ach) ? ((b_i == a_i) ? 1 : -1) : 0;
    wire f_ill = pv_i && f_ach && f_bch && f_epr;
    always @(posedge clk) begin
        if (pv_i) begin
            f_pa  <= a_i;
            f_pb  <= b_i;
            f_epr <= 1'b1;
        end
        if (rst) begin
            f_pa  <= 1'b1;
            f_pb  <= 1'b1;
            f_epr <= 1'b0;
        end
    end

    // ---- invariants (from the initial values on) ---------------------------------------------
    always @(*) begin
        assert (b_acc == f_b);                                           // I1, C3
        assert (ph_prev == f_lph && primed == f_lok);
        if (f_wok)
            assert (f_wd >= -3'sd1 && f_wd <= 3'sd1 && f_b == f_bt + f_nw(f_ln, f_wd));
        if (f_nc)
            assert (f_wok && f_wd == 3'sd0 && f_lph == f_tph);
        if (!f_lok)
            assert (f_tph == 13'd0 && f_ln == 9'd0 && f_bt == 0 && (!f_wok || f_wd == 3'sd0));
        assert (v1 == f_v1 && (v1 && ovs1) == f_ovs1);                   // I2
        if (v1)
            assert (hold1 == f_h1);
        if (f_ovs1)
            assert (f_v1 && !f_h1);
        if (f_acc1) begin                                                // I3
            assert (f_tph == f_ph1 && f_lph == f_ph1 && f_bt == f_b);
            assert (f_wok && f_nc && f_wd == 3'sd0);
            assert (f_rawt1 == $signed({2'b00, f_ph1}) - $signed({2'b00, f_lph2}));
            if (f_wok1 && f_same1)
                assert (f_b == f_lb + f_nw(f_n1, f_wd1));
        end else begin
            assert (f_tph == f_lph2 && f_bt == f_lb);
        end
        assert (f_lc == f_lb + $signed({{(COUNT_W-11){1'b0}}, f_lp[21:11]}));
        if (f_pm)
            assert (count_o == f_lc);
        assert (qd_prev == {~f_pb, f_pa ^ f_pb} && eprimed == f_epr);   // I4
    end

    // C4: the step of the phase-mode count between trusted samples with the same n, in
    // terms of the samples alone (4 n Wd + q - q_last, s15; no width dependence), and the
    // count's step is that (the ghost counts; count_o below)
    wire signed [COUNT_W-1:0] f_nw1 = f_nw(f_n1, f_wd1);
    wire signed [14:0] f_dcl = $signed({f_nw1[COUNT_W-1], f_nw1[13:0]})
                               + $signed({4'd0, prod_i[21:11]}) - $signed({4'd0, f_lp[21:11]});
    wire signed [14:0] f_2n15 = $signed({5'd0, f_n1, 1'b0});
    wire               f_half1 = (f_p1 <= 17'sd4096) && (f_p1 >= -17'sd4096);
    always @(*) if (f_acc1) begin
        if (f_nc1)                          // no coast between: the phase step
            assert (f_wok1 && f_p1 == {{2{f_dpt1[14]}}, f_dpt1});
        if (f_same1 && f_wok1) begin
            assert (f_dc == {{(COUNT_W-15){f_dcl[14]}}, f_dcl});
            if (f_p1 >= 0)
                assert (f_dcl >= 0);
            if (f_p1 <= 0)
                assert (f_dcl <= 0);
            if (f_half1)
                assert (f_dcl <= f_2n15 && f_dcl >= -f_2n15);
        end
    end

    // ---- per-edge properties -----------------------------------------------------------------
    reg  signed [COUNT_W-1:0] f_count = 0;     // count_o before the edge
    always @(posedge clk)
        f_count <= count_o;
    wire signed [COUNT_W-1:0] f_dcount = count_o - f_count;
    always @(posedge clk) if (f_past_valid) begin
        if ($past(rst)) begin                                            // C1
            assert (count_o == 0 && !valid_o && !ovs_o && !ill_o && ill_count_o == 16'd0);
            assert (b_acc == 0 && ph_prev == 13'd0 && e_acc == 0);
        end else begin
            // C2
            assert (valid_o == $past(f_v1));
            if (count_o != $past(count_o))
                assert (valid_o);
            // C3, C7: the count shown for a sample
            if ($past(f_acc1) && !$past(mode_i))
                assert (count_o == $past(f_c));
            if ($past(f_v1) && $past(mode_i))
                assert (count_o == $past(e_acc));
            // C4 on count_o: the step from the count shown before is the sample's step
            // (signed and bounded when n is the same)
            if ($past(f_acc1 && f_pm) && !$past(mode_i))
                assert (f_dcount == $past(f_dc));
            if ($past(f_acc1 && f_same1 && f_wok1 && f_pm) && !$past(mode_i)) begin
                if ($past(f_half1))
                    assert (f_dcount <= $past(f_2n) && f_dcount >= -$past(f_2n));
                if ($past(f_p1) >= 0)
                    assert (f_dcount >= 0);
                if ($past(f_p1) <= 0)
                    assert (f_dcount <= 0);
            end
            // C5
            if ($past(valid_i && hold_i && !coast_i))
                assert (b_acc == $past(b_acc) && ph_prev == $past(ph_prev));
            if ($past(valid_i && hold_i && coast_i))
                assert (b_acc == $past(b_acc + f_bstep) && ph_prev == $past(line_i));
            if ($past(f_v1 && f_h1)) begin
                assert (!ovs_o);
                if (!$past(mode_i))
                    assert (count_o == $past(count_o));
            end
            // C6
            assert (ovs_o == $past(f_ovs1));
            if (ovs_o)
                assert (valid_o);
            // C7
            assert (e_acc == $past(e_acc + f_estep));
            assert (ill_o == $past(f_ill));
            assert (ill_count_o == $past(ill_count_o) + {15'd0, $past(f_ill)});
        end
    end

    // ---- reachability ------------------------------------------------------------------------
    reg  f_cst1 = 1'b0;                         // the sample in stage 2 was coasted
    always @(posedge clk)
        f_cst1 <= f_cst && !rst;
    always @(posedge clk) if (f_past_valid && !$past(rst)) begin
        // a backward and a forward wrap counted, the step bound reached, in phase mode
        cover ($past(f_acc1 && !mode_i && f_nc1 && f_wd1 == -3'sd1) && f_dcount == -5);
        cover ($past(f_acc1 && !mode_i && f_nc1 && f_wd1 == 3'sd1) && f_dcount > 0);
        cover ($past(f_acc1 && f_same1 && f_pm && !mode_i && f_n1 == 9'd3)
               && f_dcount == 6);
        // overspeed on the first trusted sample after a held one, and after a coast
        cover (ovs_o && $past(f_lok) && $past(f_v1 && f_h1, 2));
        cover (ovs_o && $past(f_cst1, 2));
        // a held sample keeps a count; a trusted one after a held one moves it
        cover ($past(f_v1 && f_h1 && !mode_i) && $past(f_acc1 && !mode_i, 2)
               && valid_o && count_o != 0);
        cover ($past(f_acc1 && !mode_i) && $past(f_v1 && f_h1, 2) && f_dcount != 0);
        // a coast's line wraps B; the count goes on from the coasted wrap (P > 0 though
        // the phase is below the previous trusted one)
        cover ($past(f_cst && !mode_i) && b_acc != $past(b_acc));
        cover ($past(f_acc1 && f_same1 && f_wok1 && !f_nc1 && f_pm && !mode_i
                     && f_wd1 == 3'sd1 && f_rawt1 < 0) && f_dcount > 0);
        // illegal steps counted; the edge-mode count two steps down
        cover (ill_o && ill_count_o == 16'd2);
        cover ($past(f_v1 && mode_i) && count_o == -2 && $past(e_acc, 3) == -1);
    end
`undef ASSUME
`endif
endmodule
`resetall
