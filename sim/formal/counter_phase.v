`default_nettype none
// Formal wrapper for rtl/counter.v, phase mode: the counter never loses or invents a count.
// Run by scripts/formal.py (proof "counter_phase"): BMC from the initial values and
// k-induction from an arbitrary state, so the property holds for all time.
//
// Assumptions: mode_i = 0 (phase mode) always; n_i constant (INTERP is changed at
// standstill only, README) but otherwise any value 0..511; every other input (rst,
// valid_i, phase_i, a_i, b_i) free on every clock. COUNT_W = 16 keeps the solver fast;
// nothing in the argument depends on the width.
//
// Ghost: the unwrapped fine phase Phi, kept by the wrapper independently of the RTL: after
// rst Phi = 0 and the previous phase is 0 (the RTL's reset state); each valid sample moves
// Phi to the nearest value congruent to the new phase modulo 8192 (a step of
// wrap13(phase - phase_prev) in [-4096, 4095]). Phi is kept modulo 2^27: the count modulo
// 2^16 is floor(4 n Phi / 8192) mod 2^16 = ((4 n Phi) mod 2^29) >> 13, and (4 n Phi) mod
// 2^29 = 4 ((n Phi) mod 2^27) depends on Phi mod 2^27 only. Phi2 is Phi delayed by the
// counter's latency (a sample on edge e is in the count after edge e + 2); rst empties
// the pipeline, so it clears the delayed copies too.
//
// Properties:
//  C1 count_o == floor(4 n Phi2 / 8192) mod 2^16, every clock (the claim).
//  C2 the whole accumulator S (count and its 13 fraction bits) == 4 n Phi2 mod 2^29: this
//     is what makes C1 inductive (the fraction carries into later counts), read through a
//     probe of u_dut.s_acc.
//  C3 the RTL's previous phase == the ghost's (probe u_dut.ph_prev): an arbitrary start
//     state could otherwise hold a phase_prev the ghost does not know.
//  C4 (ghost sanity) Phi mod 8192 == the last sample's phase: Phi unwraps the phase.
module fv_counter_phase (
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
    (* fv_probe = "u_dut.s_acc" *)   wire [CW+12:0] p_s_acc;
    (* fv_probe = "u_dut.ph_prev" *) wire [12:0]    p_ph_prev;
    (* fv_probe = "u_dut.v1" *)      wire           p_v1;
    (* fv_probe = "u_dut.dph1" *)    wire [12:0]    p_dph1;
    (* fv_probe = "u_dut.v2" *)      wire           p_v2;
    (* fv_probe = "u_dut.d2" *)      wire signed [22:0] p_d2;
    (* fv_probe = "u_dut.m1" *)      wire           p_m1;
    (* fv_probe = "u_dut.m2" *)      wire           p_m2;

    // n: one value, chosen by the solver, for the whole trace
    (* anyconst *) wire [8:0] f_n;
    always @* begin
        assume (!mode_i);
        assume (n_i == f_n);
    end

    // ---- ghost: unwrapped phase --------------------------------------------------------
    reg [12:0] g_prev = 13'd0;
    reg [26:0] g_phi = 27'd0, g_phi1 = 27'd0, g_phi2 = 27'd0;
    wire signed [15:0] d_raw = $signed({3'd0, phase_i}) - $signed({3'd0, g_prev});
    wire signed [15:0] g_dph = (d_raw >= 16'sd4096) ? d_raw - 16'sd8192 :
                               (d_raw < -16'sd4096) ? d_raw + 16'sd8192 : d_raw;
    // the step of the sample in each pipeline stage (0 for none)
    reg signed [15:0] g_d1 = 16'sd0, g_d2 = 16'sd0;
    always @(posedge clk) begin
        g_phi1 <= g_phi;
        g_phi2 <= g_phi1;
        g_d1 <= (valid_i && !rst) ? g_dph : 16'sd0;
        g_d2 <= rst ? 16'sd0 : g_d1;
        if (valid_i) begin
            g_phi <= g_phi + {{11{g_dph[15]}}, g_dph};
            g_prev <= phase_i;
        end
        if (rst) begin
            g_phi <= 27'd0;
            g_phi1 <= 27'd0;
            g_phi2 <= 27'd0;
            g_prev <= 13'd0;
        end
    end
    wire [26:0] g_nphi = g_phi2 * {18'd0, n_i};          // n Phi2 mod 2^27
    // Assertions on the current state (always @*: checked in every step, including the
    // first step of an induction; a clocked assert would check registered copies).
    always @* begin
        assert (count_o == g_nphi[26:11]);                // C1
        assert (p_s_acc == {g_nphi, 2'b00});              // C2
        assert (p_ph_prev == g_prev);                     // C3
        assert (g_phi[12:0] == g_prev);                   // C4
        // C5: the samples in flight (steps of a sample are in [-4096, 4095])
        assert (g_d1 >= -16'sd4096 && g_d1 <= 16'sd4095);
        assert (g_d2 >= -16'sd4096 && g_d2 <= 16'sd4095);
        assert (g_phi == g_phi1 + {{11{g_d1[15]}}, g_d1});
        assert (g_phi1 == g_phi2 + {{11{g_d2[15]}}, g_d2});
        assert (p_v1 ? (p_dph1 == g_d1[12:0]) : (g_d1 == 16'sd0));
        assert (!p_m1 && !p_m2);                          // phase mode in flight too
        assert (p_v2 ? (p_d2 == g_d2 * $signed({1'b0, n_i})) : (g_d2 == 16'sd0));
    end
    // non-vacuity: counts far from 0 both ways at the largest n, and past the wrap
    always @* begin
        cover (n_i == 9'd511 && count_o == 16'sd2044);
        cover (n_i == 9'd511 && count_o == -16'sd2044);
        cover (n_i == 9'd3 && count_o == -16'sd7 && valid_o);
    end
endmodule
`resetall
