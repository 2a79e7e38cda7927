`timescale 1ns / 1ps
`default_nettype none
// pulse: Eq. 12, comparators with hysteresis (sim/model/pulse.py pulse()).
//   A = 1 if cos(n a) >= eps, 0 if cos(n a) <= -eps, else unchanged (B likewise from sin).
// The table values (u0.(SIN_W-1) with sign) are compared in u0.15 units with eps.
// Latency 1; A and B start at 1. eps_i is taken two edges before the pulses it decides
// (a pulse formed on edge p compares with eps_i as of edge p - 2: the threshold index of
// OPT_ADDR is read from a table; both forms keep the same timing; a constant eps,
// OPT_TUNABLE = 0, is the same on every edge). In the core a write of EPS on edge w (or
// its reset by rst) thus decides the pulses formed from edge w + 3 on.
//
// Two forms of the comparison m >= eps (m = the magnitude in u0.15):
//   OPT_ADDR = 0: m itself, the sine table's word (cos_mag_i, sin_mag_i).
//   OPT_ADDR = 1: the sine table's address k (cos_k_i, sin_k_i: m = T[k], T the
//     quarter wave, non-decreasing in k), so that no comparison waits for the table's
//     block RAM: with E = ceil(eps / 2**(16 - SIN_W)) (m >= eps <=> T[k] >= E),
//     T[k] >= E <=> k >= K[E], K[E] = #{k : T[k] < E} (eq12_k_<SIN_W>.hex, rows
//     E = 0 .. 2**(SIN_W-1) - 1, sim/model/tables.py eq12_k_table; E beyond them: no
//     k), and m = 0 <=> k < K[1]. For SIN_W 8, 10 or 12 (the tables generated; any
//     other width stops elaboration); one block RAM (ECP5: 512 x 12 at SIN_W = 10).
module pulse #(
    // sine word width (magnitude SIN_W-1 bits, rtl/lut.v)
    parameter SIN_W = 10,
    // 1: eps_i is a register; 0: a constant (rtl/finequad_core.v OPT_TUNABLE = 0): compared
    // bit by bit in the word form, which synthesis folds into a few LUTs
    parameter [0:0] OPT_TUNABLE = 1'b1,
    // the comparison's form (above) with OPT_TUNABLE: 1 address side (for clock rates
    // near 100 MHz, e.g. ECP5), 0 the table's word
    parameter [0:0] OPT_ADDR = 1'b0,
    // where eq12_k_<SIN_W>.hex is (OPT_ADDR)
    parameter TABLE_DIR = "rtl/tables/"
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             valid_i,
    input  wire [SIN_W-2:0] cos_mag_i,
    input  wire             cos_neg_i,
    input  wire [10:0]      cos_k_i,      // u11 its quarter-wave table address (OPT_ADDR)
    input  wire [SIN_W-2:0] sin_mag_i,
    input  wire             sin_neg_i,
    input  wire [10:0]      sin_k_i,      // u11
    input  wire [15:0]      eps_i,        // u0.15 hysteresis threshold
    output reg              valid_o,
    output reg              a_o,
    output reg              b_o
);
    // With v = +-m (m the magnitude in u0.15) one unsigned comparison m >= eps decides:
    //   v >= eps   <=>  (!neg && m >= eps) || (m == 0 && eps == 0)
    //   v <= -eps  <=>  ( neg && m >= eps) || (m == 0 && eps == 0)   (used when not v >= eps)
    wire [15:0] cm = {1'b0, cos_mag_i, {(16-SIN_W){1'b0}}};
    wire [15:0] sm = {1'b0, sin_mag_i, {(16-SIN_W){1'b0}}};
`include "geu.vh"                          // geu(a, b): a >= b, unsigned, bit by bit
    wire c_ge, s_ge, c_zero, s_zero, zero_eps;
    // (a constant eps, OPT_TUNABLE = 0, is compared in the word form: it folds into a few
    // LUTs, and it cannot change, so it needs no delay)
    localparam [0:0] ADDR = OPT_ADDR && OPT_TUNABLE;
    generate
        if (ADDR) begin : g_addr
            // E (u(SIN_W+1)) and the table row read: E, or 1 for E = 0 (then K[1] tells
            // m = 0; m >= 0 always); beyond the rows no k reaches E
            localparam SH = 16 - SIN_W;
            localparam KW = SIN_W - 1;                   // row address width
            reg  [11:0] krom [0:(1 << KW) - 1];
            // one branch per file (Icarus 11 empties a ?: between strings of different
            // lengths: rtl/lut.v)
            if (SIN_W == 8) begin : g_k8
                initial
                    $readmemh({TABLE_DIR, "eq12_k_8.hex"}, krom);
            end else if (SIN_W == 10) begin : g_k10
                initial
                    $readmemh({TABLE_DIR, "eq12_k_10.hex"}, krom);
            end else if (SIN_W == 12) begin : g_k12
                initial
                    $readmemh({TABLE_DIR, "eq12_k_12.hex"}, krom);
            end else begin : g_kbad
                // no threshold table for this width: an undefined module stops every
                // tool's elaboration with this name
                pulse_OPT_ADDR_needs_SIN_W_8_10_or_12 u_bad ();
            end
            wire [16-SH:0] e = {1'b0, eps_i[15:SH]} + {{(16-SH){1'b0}}, |eps_i[SH-1:0]};
            wire        e0 = (e == 0);
            wire        far = (e >= (1 << KW));
            wire [KW-1:0] row = e0 ? {{(KW-1){1'b0}}, 1'b1} : e[KW-1:0];
            // for the pulses of edge p: the row of eps_i read on edge p - 2 (block RAM),
            // K and the flags in flip-flops on edge p - 1
            reg  [11:0] kb = 12'd0, kth = 12'd0;
            reg         e0_1 = 1'b1, far_1 = 1'b0, e0_2 = 1'b1;
            always @(posedge clk) begin
                kb <= krom[row];
                e0_1 <= e0;
                far_1 <= far;
                kth <= far_1 ? 12'd2048 : kb;
                e0_2 <= e0_1;
            end
            assign zero_eps = e0_2;
            assign c_ge = e0_2 || ({1'b0, cos_k_i} >= kth);
            assign s_ge = e0_2 || ({1'b0, sin_k_i} >= kth);
            assign c_zero = ({1'b0, cos_k_i} < kth);     // with e0_2: m = 0
            assign s_zero = ({1'b0, sin_k_i} < kth);
            wire unused_m = &{1'b0, cm, sm, 1'b0};
        end else begin : g_mag
            reg [15:0] eps_1 = 16'd0, eps_q = 16'd0;
            always @(posedge clk) begin
                eps_1 <= eps_i;
                eps_q <= eps_1;
            end
            wire [15:0] eps_2 = OPT_TUNABLE ? eps_q : eps_i;
            assign c_ge = OPT_TUNABLE ? cm >= eps_2 : geu({16'd0, cm}, {16'd0, eps_2});
            assign s_ge = OPT_TUNABLE ? sm >= eps_2 : geu({16'd0, sm}, {16'd0, eps_2});
            assign zero_eps = (eps_2 == 16'd0);
            assign c_zero = (cm == 16'd0);
            assign s_zero = (sm == 16'd0);
            wire unused_k = &{1'b0, cos_k_i, sin_k_i, 1'b0};
        end
    endgenerate
    wire c_pos = (!cos_neg_i && c_ge) || (zero_eps && c_zero);
    wire c_neg = cos_neg_i && c_ge;
    wire s_pos = (!sin_neg_i && s_ge) || (zero_eps && s_zero);
    wire s_neg = sin_neg_i && s_ge;
    always @(posedge clk) begin
        valid_o <= valid_i;
        if (valid_i) begin
            if (c_pos)
                a_o <= 1'b1;
            else if (c_neg)
                a_o <= 1'b0;
            if (s_pos)
                b_o <= 1'b1;
            else if (s_neg)
                b_o <= 1'b0;
        end
        if (rst) begin
            valid_o <= 1'b0;
            a_o <= 1'b1;
            b_o <= 1'b1;
        end
    end
    initial begin
        valid_o = 1'b0; a_o = 1'b1; b_o = 1'b1;
    end
`ifdef FORMAL
    // ---- formal properties (sim/formal/pulse.sby; every input free on every clock) ----------
    // With c = +-(cos magnitude in u0.15) and s likewise, as signed integers (independent of
    // the single-comparison form above):
    //  P1 rst: a_o = b_o = 1, valid_o = 0.
    //  P2 valid_o is valid_i one edge later; a_o and b_o change only on an edge with valid_i.
    //  P3 on such an edge a_o <= 1 if c >= eps, else 0 if c <= -eps, else a_o (Eq. 12);
    //     so a_o becomes 1 only if c >= eps and 0 only if c <= -eps. b_o likewise with s.
    //     eps is eps_i two edges before (f_e2; eps_i itself with OPT_TUNABLE = 0).
    //  OPT_ADDR (task prf_a): the same properties, with the magnitudes and the addresses
    //     related as the sine table and the threshold table relate them (assumed here;
    //     proved for every row and address in sim/tests/test_tables.py). Invariants: the
    //     registered row and threshold are those of eps_i one and two edges before.
    //  (OPT_ADDR: from the third edge after power-up, when the threshold registers hold
    //  their first table words; no sample reaches the pulses that early in the core)
    reg f_past_valid = 1'b0;
    reg [1:0] f_age = 2'd0;                 // edges since power-up, saturating at 3
    reg [15:0] f_e1 = 16'd0, f_e2 = 16'd0;
    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_age <= (f_age == 2'd3) ? f_age : f_age + 1'b1;
        f_e1 <= eps_i;
        f_e2 <= f_e1;
    end
    wire f_spec = !ADDR || f_age == 2'd3;   // the pulses of the edge before are specified
    wire signed [17:0] f_cm = $signed({2'b00, cos_mag_i, {(16-SIN_W){1'b0}}});
    wire signed [17:0] f_sm = $signed({2'b00, sin_mag_i, {(16-SIN_W){1'b0}}});
    wire signed [17:0] f_c = cos_neg_i ? -f_cm : f_cm;
    wire signed [17:0] f_s = sin_neg_i ? -f_sm : f_sm;
    wire signed [17:0] f_eps = $signed({2'b00, OPT_TUNABLE ? f_e2 : eps_i});
    generate
        if (ADDR) begin : f_addr
            // the registers behind eps_i: the row and the threshold of eps_i one and two
            // edges before
            localparam SH = g_addr.SH, KW = g_addr.KW;
            wire [16-SH:0] f_x1 = {1'b0, f_e1[15:SH]} + {{(16-SH){1'b0}}, |f_e1[SH-1:0]};
            wire [16-SH:0] f_x2 = {1'b0, f_e2[15:SH]} + {{(16-SH){1'b0}}, |f_e2[SH-1:0]};
            wire [KW-1:0]  f_r1 = (f_x1 == 0) ? 1 : f_x1[KW-1:0];
            wire [KW-1:0]  f_r2 = (f_x2 == 0) ? 1 : f_x2[KW-1:0];
            wire           f_far2 = (f_x2 >= (1 << KW));
            wire [11:0]    f_k2 = f_far2 ? 12'd2048 : g_addr.krom[f_r2];
            always @(*) if (f_age >= 2'd2) begin
                assert (g_addr.e0_1 == (f_x1 == 0) && g_addr.far_1 == (f_x1 >= (1 << KW)));
                assert (g_addr.kb == g_addr.krom[f_r1]);
                assert (g_addr.e0_2 == (f_x2 == 0) && g_addr.kth == f_k2);
            end
            // the tables' contract (the address k of the magnitude m = T[k]; proved for
            // every row and address by sim/tests/test_tables.py test_eq12_k_table):
            // m = 0 <=> k < K[1], and m >= E <=> k >= K[E] for the E = ceil(eps / 2**SH)
            // in use (no k for E beyond the rows)
            always @(*) begin
                assume ((cos_mag_i == 0) == (cos_k_i < g_addr.krom[1]));
                assume ((sin_mag_i == 0) == (sin_k_i < g_addr.krom[1]));
                if (f_x2 != 0) begin
                    assume (({1'b0, cos_mag_i} >= f_x2) == ({1'b0, cos_k_i} >= f_k2));
                    assume (({1'b0, sin_mag_i} >= f_x2) == ({1'b0, sin_k_i} >= f_k2));
                end
            end
        end
    endgenerate
    wire f_a = (f_c >= f_eps) ? 1'b1 : (f_c <= -f_eps) ? 1'b0 : a_o;
    wire f_b = (f_s >= f_eps) ? 1'b1 : (f_s <= -f_eps) ? 1'b0 : b_o;
    always @(posedge clk) if (f_past_valid) begin
        if ($past(rst)) begin
            assert (a_o && b_o && !valid_o);                              // P1
        end else begin
            assert (valid_o == $past(valid_i));                           // P2
            if (!$past(valid_i))
                assert (a_o == $past(a_o) && b_o == $past(b_o));
            else if (f_spec)
                assert (a_o == $past(f_a) && b_o == $past(f_b));          // P3
            if (f_spec) begin
                if (a_o && !$past(a_o))
                    assert ($past(f_c >= f_eps));
                if (!a_o && $past(a_o))
                    assert ($past(f_c <= -f_eps));
                if (b_o && !$past(b_o))
                    assert ($past(f_s >= f_eps));
                if (!b_o && $past(b_o))
                    assert ($past(f_s <= -f_eps));
            end
        end
    end
    // reachability: a falls and b rises with a threshold, a holds inside the band after a
    // fall, both set by a zero value at eps = 0
    always @(posedge clk) if (f_past_valid && !$past(rst)) begin
        cover (!a_o && $past(a_o) && b_o && !$past(b_o) && $past(f_eps) > 18'sd100);
        cover (!a_o && $past(valid_i) && $past(f_c > -f_eps && f_c < f_eps)
               && $past(f_c) != 0);
        cover (a_o && !$past(a_o) && $past(f_eps == 18'sd0 && f_c == 0 && cos_neg_i));
    end
`endif
endmodule
`resetall
