`default_nettype none
// Formal wrapper for rtl/counter.v: what one sample may do to the outputs, both modes.
// Run by scripts/formal.py (proof "counter_steps"): BMC from the initial values, and
// k-induction from an arbitrary state (unbounded).
//
// Every input is free on every clock: valid_i, rst, a_i, b_i, phase_i, n_i (0..511, so
// n may change between samples) and mode_i (the mode may change per sample: the RTL
// carries it with the sample). COUNT_W = 16 keeps the arithmetic small; the properties
// do not depend on the width (2n <= 1022 fits in any COUNT_W >= 12).
//
// The wrapper keeps its own record of the last sample (ghost, independent of the RTL's
// encodings): its phase, its A/B and whether a sample was seen since rst. For each sample
// it computes the expected outcome and carries it down a 3-stage ghost pipeline (the
// counter's latency: a sample on edge e is on the outputs after edge e + 2, n_i is read
// on edge e + 1), where it is compared with the outputs.
//
// Properties (cycle after the output edge, unless that edge saw rst):
//  P1 valid_o marks exactly the samples that were not cut by rst (no output without a
//     sample, no sample lost in the pipeline).
//  P2 no valid sample: the count does not change.
//  P3 phase mode: |count - count_prev| <= 2 n (mod 2^COUNT_W). Why: the step adds
//     4 n dph units of S, dph = wrap13(phase - phase_prev) in [-4096, 4095], i.e. at most
//     2 n counts of 8192 units; floor(x + y) - floor(x) lies in [floor(y), ceil(y)], so
//     the count moves by at most 2 n (the brief's bound 2 n + 1 follows).
//  P4 phase mode: illegal_o (overspeed) == |wrap13(phase - phase_prev)| >= 3072, except on
//     the first sample after rst (its step is from the reset state, not from a sample).
//  P5 edge mode: the count changes by exactly +1 when exactly one of A, B toggled in the
//     up direction of (1,1) -> (0,1) -> (0,0) -> (1,0) -> (1,1), by -1 in the other
//     direction, else by 0: in particular a sample where both toggled is not counted.
//  P6 edge mode: illegal_o == both A and B toggled (again not on the first sample).
//  P7 illegal_count_o increments by 1 exactly on a flagged sample (both modes), else holds.
//  P8 rst (previous edge): count 0, no valid, no flag, illegal count 0.
// Invariants for the induction (they tie the RTL's long-lived state to the ghost, read
// through probes that scripts/formal.py connects to u_dut's internal registers):
//  I1 ph_prev == ghost phase, I2 qd_prev == the RTL's code {~B, A^B} of the ghost A/B,
//  I3 primed == ghost "sample seen since rst". Without them an arbitrary start state could
//  hold a phase_prev the ghost does not know, and no depth of induction would help.
module fv_counter_steps (
    input wire        clk,
    input wire        rst,
    input wire        valid_i,
    input wire        a_i,
    input wire        b_i,
    input wire [12:0] phase_i,
    input wire [8:0]  n_i,
    input wire        mode_i
);
    localparam CW = 16;
    wire                 valid_o, a_o, b_o, illegal_o;
    wire signed [CW-1:0] count_o;
    wire [31:0]          illegal_count_o;
    counter #(.COUNT_W(CW)) u_dut (
        .clk(clk), .rst(rst), .valid_i(valid_i), .a_i(a_i), .b_i(b_i), .phase_i(phase_i),
        .n_i(n_i), .mode_i(mode_i), .valid_o(valid_o), .count_o(count_o), .a_o(a_o),
        .b_o(b_o), .illegal_o(illegal_o), .illegal_count_o(illegal_count_o)
    );
    // probes (connected by scripts/formal.py to u_dut's registers)
    (* fv_probe = "u_dut.ph_prev" *) wire [12:0] p_ph_prev;
    (* fv_probe = "u_dut.qd_prev" *) wire [1:0]  p_qd_prev;
    (* fv_probe = "u_dut.primed" *)  wire        p_primed;

    reg f_past = 1'b0;
    always @(posedge clk) f_past <= 1'b1;

    // ---- ghost: the last sample since rst (reset state: phase 0, A = B = 1) --------------
    reg [12:0] g_prev = 13'd0;
    reg        g_a = 1'b1, g_b = 1'b1, g_primed = 1'b0;
    always @(posedge clk) begin
        if (valid_i) begin
            g_prev <= phase_i;
            g_a <= a_i;
            g_b <= b_i;
            g_primed <= 1'b1;
        end
        if (rst) begin
            g_prev <= 13'd0;
            g_a <= 1'b1;
            g_b <= 1'b1;
            g_primed <= 1'b0;
        end
    end
    // expected outcome of the sample now at the inputs
    // wrap13 written out: the difference in [-8191, 8191] brought into [-4096, 4095]
    wire signed [15:0] d_raw = $signed({3'd0, phase_i}) - $signed({3'd0, g_prev});
    wire signed [15:0] g_dph = (d_raw >= 16'sd4096) ? d_raw - 16'sd8192 :
                               (d_raw < -16'sd4096) ? d_raw + 16'sd8192 : d_raw;
    wire        x_ovs = (g_dph >= 16'sd3072) || (g_dph <= -16'sd3072);
    wire [3:0]  tr = {g_a, g_b, a_i, b_i};          // transition (A, B)prev -> (A, B)now
    wire        x_up = (tr == 4'b11_01) || (tr == 4'b01_00) || (tr == 4'b00_10) || (tr == 4'b10_11);
    wire        x_dn = (tr == 4'b01_11) || (tr == 4'b00_01) || (tr == 4'b10_00) || (tr == 4'b11_10);
    wire        x_both = (a_i != g_a) && (b_i != g_b);
    wire        x_flag = g_primed && (mode_i ? x_both : x_ovs);
    // ---- ghost pipeline (stage k holds the sample registered k edges ago) ---------------
    reg       q1_v = 1'b0, q1_m = 1'b0, q1_f = 1'b0, q1_up = 1'b0, q1_dn = 1'b0;
    reg       q2_v = 1'b0, q2_m = 1'b0, q2_f = 1'b0, q2_up = 1'b0, q2_dn = 1'b0;
    reg       q3_v = 1'b0, q3_m = 1'b0, q3_f = 1'b0, q3_up = 1'b0, q3_dn = 1'b0;
    reg [8:0] q2_n = 9'd0, q3_n = 9'd0;
    always @(posedge clk) begin
        {q1_v, q1_m, q1_f, q1_up, q1_dn} <= {valid_i && !rst, mode_i, x_flag, x_up, x_dn};
        {q2_v, q2_m, q2_f, q2_up, q2_dn} <= {q1_v && !rst, q1_m, q1_f, q1_up, q1_dn};
        q2_n <= n_i;                                 // the counter reads n on edge e + 1
        {q3_v, q3_m, q3_f, q3_up, q3_dn} <= {q2_v && !rst, q2_m, q2_f, q2_up, q2_dn};
        q3_n <= q2_n;
    end

    reg  signed [CW-1:0] f_count = 0;              // count_o one clock ago
    reg  [31:0]          f_ill = 32'd0;            // illegal_count_o one clock ago
    always @(posedge clk) begin
        f_count <= count_o;
        f_ill <= illegal_count_o;
    end
    wire signed [CW-1:0] delta = count_o - f_count;   // mod 2^CW
    wire signed [CW-1:0] lim = $signed({{(CW-10){1'b0}}, q3_n, 1'b0});   // 2 n
    always @(posedge clk) begin
        // I1..I3: the RTL's record of the last sample is the ghost's
        assert (p_ph_prev == g_prev);
        assert (p_qd_prev == {~g_b, g_a ^ g_b});
        assert (p_primed == g_primed);
        if (f_past) begin
            if ($past(rst)) begin
                // P8
                assert (count_o == 0);
                assert (!valid_o && !illegal_o);
                assert (illegal_count_o == 32'd0);
            end else begin
                assert (valid_o == q3_v);                                      // P1
                assert (illegal_o == (q3_v && q3_f));                          // P4, P6
                assert (illegal_count_o == f_ill + illegal_o);                  // P7
                if (!valid_o)
                    assert (delta == 0);                                       // P2
                else if (q3_m)
                    assert (delta == (q3_up ? 1 : q3_dn ? -1 : 0));            // P5
                else
                    assert (delta <= lim && delta >= -lim);                    // P3
            end
        end
    end
    // non-vacuity (cover mode): the extreme phase steps and every edge-mode outcome
    always @(posedge clk) begin
        if (f_past && !$past(rst) && valid_o) begin
            cover (!q3_m && q3_n == 9'd511 && delta == lim);
            cover (!q3_m && q3_n == 9'd511 && delta == -lim);
            cover (!q3_m && illegal_o);
            cover (q3_m && delta == 1);
            cover (q3_m && delta == -1);
            cover (q3_m && illegal_o && delta == 0);
        end
    end
endmodule
`resetall
