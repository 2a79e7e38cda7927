`timescale 1ns / 1ps
`default_nettype none
// pulse: Eq. 12, comparators with hysteresis (sim/model/fastpath.py pulse()).
//   A = 1 if cos(n a) >= eps, 0 if cos(n a) <= -eps, else unchanged (B likewise from sin).
// The table values (u0.(SIN_W-1) with sign) are compared in u0.15 units with eps.
// Latency 1; A and B start at 1.
module pulse #(
    parameter SIN_W = 10,
    // 1: eps_i is a register; 0: a constant (rtl/finequad_core.v OPT_TUNABLE = 0): compared
    // bit by bit, which synthesis folds into a few LUTs
    parameter [0:0] OPT_TUNABLE = 1'b1
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             valid_i,
    input  wire [SIN_W-2:0] cos_mag_i,
    input  wire             cos_neg_i,
    input  wire [SIN_W-2:0] sin_mag_i,
    input  wire             sin_neg_i,
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
    // a >= b (unsigned, up to 32 bits), bit by bit from the LSB: with b constant it folds
    // to an AND/OR chain that synthesis maps to a few LUTs (yosys maps a comparison with a
    // constant to a whole carry chain)
    function automatic geu(input [31:0] a, input [31:0] b);
        integer i;
        reg r;
        begin
            r = 1'b1;
            for (i = 0; i < 32; i = i + 1)
                r = (a[i] & ~b[i]) | (~(a[i] ^ b[i]) & r);
            geu = r;
        end
    endfunction
    wire c_ge = OPT_TUNABLE ? cm >= eps_i : geu({16'd0, cm}, {16'd0, eps_i});
    wire s_ge = OPT_TUNABLE ? sm >= eps_i : geu({16'd0, sm}, {16'd0, eps_i});
    wire zero_eps = (eps_i == 16'd0);
    wire c_pos = (!cos_neg_i && c_ge) || (zero_eps && cm == 16'd0);
    wire c_neg = cos_neg_i && c_ge;
    wire s_pos = (!sin_neg_i && s_ge) || (zero_eps && sm == 16'd0);
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
    reg f_past_valid = 1'b0;
    always @(posedge clk)
        f_past_valid <= 1'b1;
    wire signed [17:0] f_cm = $signed({2'b00, cos_mag_i, {(16-SIN_W){1'b0}}});
    wire signed [17:0] f_sm = $signed({2'b00, sin_mag_i, {(16-SIN_W){1'b0}}});
    wire signed [17:0] f_c = cos_neg_i ? -f_cm : f_cm;
    wire signed [17:0] f_s = sin_neg_i ? -f_sm : f_sm;
    wire signed [17:0] f_eps = $signed({2'b00, eps_i});
    wire f_a = (f_c >= f_eps) ? 1'b1 : (f_c <= -f_eps) ? 1'b0 : a_o;
    wire f_b = (f_s >= f_eps) ? 1'b1 : (f_s <= -f_eps) ? 1'b0 : b_o;
    always @(posedge clk) if (f_past_valid) begin
        if ($past(rst)) begin
            assert (a_o && b_o && !valid_o);                              // P1
        end else begin
            assert (valid_o == $past(valid_i));                           // P2
            if (!$past(valid_i))
                assert (a_o == $past(a_o) && b_o == $past(b_o));
            else
                assert (a_o == $past(f_a) && b_o == $past(f_b));          // P3
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
    // reachability: a falls and b rises with a threshold, a holds inside the band after a
    // fall, both set by a zero value at eps = 0
    always @(posedge clk) if (f_past_valid && !$past(rst)) begin
        cover (!a_o && $past(a_o) && b_o && !$past(b_o) && $past(eps_i) > 16'd100);
        cover (!a_o && $past(valid_i) && $past(f_c > -f_eps && f_c < f_eps)
               && $past(f_c) != 0);
        cover (a_o && !$past(a_o) && $past(eps_i == 16'd0 && f_c == 0 && cos_neg_i));
    end
`endif
endmodule
`resetall
