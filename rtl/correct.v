`timescale 1ns / 1ps
`default_nettype none
// correct: input gain, offsets and Eq. 9 as three products, ending in the magnitudes and
// signs of the corrected signals that the octant logic needs (sim/model/correct.py
// correct()). One sample per clock; the sample is strobed on edge t (valid_i high before
// t) and the coefficient bundle is sampled on the same edge, so a sample never mixes two
// bundles.
//   t    u_r  = u << (16 - ADC_W)                            s1.15 aligned code (raw_o)
//        x    = u_r * 2**g                                    s4.15 (exact)
//        d    = sat16(x - m)                                  s1.15
//        d and c1, c12, c2 registered: the DSP blocks' input registers (iCE40: A_REG and
//        B_REG of each SB_MAC16, d1 in two of them; nextpnr-ice40 times an SB_MAC16 only
//        at its pins, so an input without its register would leave the multiplier's
//        delay out of the reported Fmax; scripts/report.py lists such stages)
//   t+1  p1 = d1 c1, p12 = d1 c12, p2 = d2 c2                 s5.27 (three DSP products)
//   t+2  v1 = p1, v2 = p12 + p2                               s6.27
//        ax = min(32767, (v1 ^ s1) >> 13), xn = s1 = v1 < 0    u15 magnitude (s2.14
//        ay, yn likewise from v2                              units: unit circle 16384)
//        zl = lzc15(ax | ay)                                  u4 leading zeros of the larger
//                                                             magnitude (for rtl/octant.v)
// Every stage's registers take a sample only with its valid bit (a clock enable, as the
// valid strobe of a fixed-rate sample chain): between samples they hold the last one's
// values, which nothing reads, and simulation skips their logic (make rtlsim runs a
// sample every 36 clocks).
// Flags (registered with the values they describe):
//   clip_o (t)   a code is at or near an ADC rail: |u_r| >= clip_i (|-32768| = 32768)
//   nsat_o (t)   x leaves s1.15: the input gain saturates (the estimator excludes the
//                sample and resets; the fast path still uses d)
//   dsat_o (t)   x - m leaves s1.15 (d saturated)
//   rsat_o (t+2) a magnitude reaches 2 (the corrected signal saturates)
module correct #(
    // ADC word width, 12..16, two's complement
    parameter ADC_W = 16
) (
    input  wire                    clk,
    input  wire                    valid_i,
    input  wire signed [ADC_W-1:0] u1_i,    // ADC codes
    input  wire signed [ADC_W-1:0] u2_i,
    input  wire [15:0]             clip_i,  // u16 clip level (s1.15 magnitude)
    input  wire [1:0]              g_i,     // input gain 2**g
    input  wire signed [15:0]      m1_i,    // s1.15 offsets (normalised units)
    input  wire signed [15:0]      m2_i,
    input  wire signed [15:0]      c1_i,    // s4.12 coefficients
    input  wire signed [15:0]      c12_i,
    input  wire signed [15:0]      c2_i,
    // edge t
    output reg                     valid0_o,
    output reg  signed [15:0]      raw1_o,  // s1.15 aligned codes (for the estimator)
    output reg  signed [15:0]      raw2_o,
    output reg  [14:0]             amax_o,  // u15 max(|raw1|, |raw2|), 32768 as 32767
    output reg                     clip_o,
    output reg                     nsat_o,
    output reg                     dsat_o,
    // edge t+2
    output reg                     valid_o,
    output reg  [14:0]             ax_o,    // u15 |u1c|, s2.14 units, saturated
    output reg  [14:0]             ay_o,    // u15 |u2c|
    output reg                     xn_o,    // u1c < 0
    output reg                     yn_o,    // u2c < 0
    output reg  [3:0]              zl_o,    // lzc15(ax_o | ay_o): 0..14 (14 for 0 and 1)
    output reg                     rsat_o
);
    // parameter check (as rtl/finequad_core.v; rtl/vhdl/correct.vhd's range): an
    // undefined module named after the rule stops elaboration
    generate
        if (ADC_W < 12 || ADC_W > 16) begin : g_bad_adc_w
            correct_ADC_W_must_be_12_to_16 u_bad ();
        end
    endgenerate
    // ---- t: align, gain, offsets ------------------------------------------------------------
    // (as functions evaluated in the clock enable's branch: the ports feed nothing else, so
    // simulation computes this logic only when a sample arrives)
    function automatic signed [15:0] align(input [ADC_W-1:0] u);       // s1.15
        align = {u, {(16-ADC_W){1'b0}}};
    endfunction
    // a value fits s1.15 when its bits above bit 15 are copies of bit 15
    function automatic fits16(input [19:0] v, input integer w);
        integer k;
        begin
            fits16 = 1'b1;
            for (k = 16; k < 20; k = k + 1)
                if (k < w && v[k] != v[15])
                    fits16 = 1'b0;
        end
    endfunction
    // x = u << g (s4.15, exact) and e = x - m (s5.15)
    function automatic signed [18:0] gain(input signed [15:0] ua, input [1:0] g);
        gain = $signed({{3{ua[15]}}, ua}) <<< g;
    endfunction
    function automatic signed [19:0] offset(input signed [15:0] ua, input [1:0] g,
                                            input signed [15:0] m);
        reg signed [18:0] x;
        begin
            x = gain(ua, g);
            offset = {x[18], x} - {{4{m[15]}}, m};
        end
    endfunction
    // x fits s1.15 (the input gain does not saturate)
    function automatic gfits(input signed [15:0] ua, input [1:0] g);
        reg signed [18:0] x;
        begin
            x = gain(ua, g);
            gfits = fits16({x[18], x}, 19);
        end
    endfunction
    // d = sat16(e)
    function automatic signed [15:0] sat16(input signed [19:0] e);
        sat16 = fits16(e, 20) ? e[15:0] : (e[19] ? 16'sh8000 : 16'sh7fff);
    endfunction
    // max(|u1|, |u2|), saturated to 32767: |u1| >= |u2| from the codes, beside the
    // magnitudes (not behind their carry chains): by the signs, u1 >= u2 (both >= 0),
    // u1 < u2 (both < 0), u1 + u2 >= 0 (u1 >= 0 > u2) or u1 + u2 < 0 (u1 < 0 <= u2); ties
    // pick either (the same magnitude)
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [14:0] amax(input signed [15:0] ua1, input signed [15:0] ua2);
        reg [15:0] ab1, ab2;
        reg signed [16:0] dif, smu;
        reg        gt1;
        begin
            ab1 = ua1[15] ? -ua1 : ua1;           // |-32768| = 32768: bit 15
            ab2 = ua2[15] ? -ua2 : ua2;
            dif = {ua1[15], ua1} - {ua2[15], ua2};
            smu = {ua1[15], ua1} + {ua2[15], ua2};
            gt1 = ((ua1[15] == ua2[15]) ? dif[16] : smu[16]) ^ !ua1[15];
            amax = gt1 ? (ab1[15] ? 15'h7fff : ab1[14:0]) : (ab2[15] ? 15'h7fff : ab2[14:0]);
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    // |u| >= clip: u >= clip for u >= 0; -u >= clip <=> ~u >= clip - 1 for u < 0 (every
    // u < 0 when clip = 0), so no negation lies in front of the comparison
    function automatic clipped(input [15:0] u, input [15:0] clip);
        reg [16:0] cm;
        begin
            cm = {1'b0, clip} - 17'd1;
            clipped = u[15] ? (cm[16] || ({1'b0, ~u} >= cm)) : (u >= clip);
        end
    endfunction
    reg signed [15:0] d1 = 0, d2 = 0;
    reg signed [15:0] c1q = 0, c12q = 0, c2q = 0;
    always @(posedge clk) begin
        valid0_o <= valid_i;
        if (valid_i) begin
            d1 <= sat16(offset(align(u1_i), g_i, m1_i));
            d2 <= sat16(offset(align(u2_i), g_i, m2_i));
            c1q <= c1_i; c12q <= c12_i; c2q <= c2_i;
            raw1_o <= align(u1_i);
            raw2_o <= align(u2_i);
            amax_o <= amax(align(u1_i), align(u2_i));
            clip_o <= clipped(align(u1_i), clip_i) || clipped(align(u2_i), clip_i);
            nsat_o <= !(gfits(align(u1_i), g_i) && gfits(align(u2_i), g_i));
            dsat_o <= !(fits16(offset(align(u1_i), g_i, m1_i), 20) &&
                        fits16(offset(align(u2_i), g_i, m2_i), 20));
        end
    end

    // ---- t+1: products (DSP blocks with input and output registers) ----------------------
    reg signed [31:0] p1 = 0, p12 = 0, p2 = 0;
    reg v1q = 1'b0;
    always @(posedge clk) begin
        if (valid0_o) begin
            p1  <= d1 * c1q;
            p12 <= d1 * c12q;
            p2  <= d2 * c2q;
        end
        v1q <= valid0_o;
    end

    // ---- t+2: magnitudes and signs ---------------------------------------------------------
    // v = p1 or p12 + p2 (s6.27); the octant logic takes |u| = floor(|v| / 2**13) as
    // (v ^ sign) >> 13, so no carry chain follows the sum: for v < 0 this is
    // floor((|v| - 1) / 2**13), 1 / 2**27 of a unit below |v|'s, and u is truncated, not
    // rounded (a bias of half an LSB of the unit circle, 3e-5: 0.01 nm on a 4 um scale).
    // The sum's bits [32:13] by carry select: both values of the upper 20 bits (carry in 0
    // and 1) beside the carry out of the low 13, chosen by AND-OR (a multiplexer would let
    // synthesis share the two adders again).
    // of vh = v >> 13 (s20): |u| = vh ^ sign (u20), saturated to 32767 (umag), and whether
    // it saturates, |u| >= 2 (usat)
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic usat(input [19:0] vh);
        reg [19:0] q;
        begin
            q = vh ^ {20{vh[19]}};
            usat = (q[19:15] != 5'd0);
        end
    endfunction
    function automatic [14:0] uraw(input [19:0] vh);             // |u| mod 2**15
        reg [19:0] q;
        begin
            q = vh ^ {20{vh[19]}};
            uraw = q[14:0];
        end
    endfunction
    function automatic [14:0] umag(input [19:0] vh);
        reg [19:0] q;
        begin
            q = vh ^ {20{vh[19]}};
            umag = usat(vh) ? 15'h7fff : q[14:0];
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    // (p12 + p2) >> 13 by carry select: both values of the upper 20 bits (carry in 0 and
    // 1) beside the carry out of the low 13, chosen by AND-OR (a multiplexer would let
    // synthesis share the two adders again)
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [19:0] sum_hi(input [31:0] a, input [31:0] b);     // s20
        reg [13:0] lo2;
        reg [19:0] hi20, hi21, csel;
        reg [20:0] hi21c;
        begin
            lo2   = {1'b0, a[12:0]} + {1'b0, b[12:0]};
            hi20  = {a[31], a[31:13]} + {b[31], b[31:13]};
            hi21c = {a[31], a[31:13], 1'b1} + {b[31], b[31:13], 1'b1};   // + 1
            hi21  = hi21c[20:1];
            csel  = {20{lo2[13]}};
            sum_hi = (hi21 & csel) | (hi20 & ~csel);
        end
    endfunction
    function automatic sum_neg(input [31:0] a, input [31:0] b);         // p12 + p2 < 0
        reg [19:0] h;
        begin
            h = sum_hi(a, b);
            sum_neg = h[19];
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    // leading zeros in 15 bits, 14 for 0 and 1: those of the 16 bits {v[14:1], 1, 1}, as
    // a two-level tree (nibble priority beside the nibbles' own counts)
    function automatic [1:0] lzc4(input [3:0] v);
        casez (v)
            4'b1???: lzc4 = 2'd0;
            4'b01??: lzc4 = 2'd1;
            4'b001?: lzc4 = 2'd2;
            default: lzc4 = 2'd3;
        endcase
    endfunction
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [3:0] lzc15(input [14:0] v);     // v[0] does not matter
        reg [15:0] w;
        begin
            w = {v[14:1], 2'b11};
            casez ({|w[15:12], |w[11:8], |w[7:4]})
                3'b1??:  lzc15 = {2'd0, lzc4(w[15:12])};
                3'b01?:  lzc15 = {2'd1, lzc4(w[11:8])};
                3'b001:  lzc15 = {2'd2, lzc4(w[7:4])};
                default: lzc15 = {2'd3, lzc4(w[3:0])};
            endcase
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */

    // (evaluated in the clock enable's branch, as stage t's; v1 = p1, whose bits [32:13]
    // are p1[31:13] sign-extended)
    wire [19:0] v1h = {p1[31], p1[31:13]};
    always @(posedge clk) begin
        if (v1q) begin
            ax_o <= umag(v1h);
            ay_o <= umag(sum_hi(p12, p2));
            // (a saturated magnitude, 32767, has no leading zero: the count does not wait
            // for the saturation's multiplexer)
            zl_o <= (usat(v1h) || usat(sum_hi(p12, p2))) ? 4'd0
                  : lzc15(uraw(v1h) | uraw(sum_hi(p12, p2)));
            xn_o <= p1[31];
            yn_o <= sum_neg(p12, p2);
            rsat_o <= usat(v1h) || usat(sum_hi(p12, p2));         // |u| >= 2 (32768)
        end
        valid_o <= v1q;
    end

    initial begin
        valid0_o = 1'b0; raw1_o = 0; raw2_o = 0; amax_o = 0; clip_o = 1'b0; nsat_o = 1'b0;
        dsat_o = 1'b0; valid_o = 1'b0; ax_o = 0; ay_o = 0; xn_o = 1'b0; yn_o = 1'b0; zl_o = 0;
        rsat_o = 1'b0;
    end
    wire unused = &{1'b0, p1[12:0], 1'b0};
endmodule
`resetall
