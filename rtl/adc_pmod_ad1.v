`timescale 1ns / 1ps
`default_nettype none
// adc_pmod_ad1: front end for Digilent's Pmod AD1 (two AD7476A, 12 bit, 1 MS/s, straight
// binary; CS_N and SCLK shared, one SDATA line per converter).
//
// AD7476A serial interface (Analog Devices AD7476A/AD7477A/AD7478A data sheet, Rev. F,
// Table 4 and Figures 3/4): the falling edge of CS_N samples the input and starts the
// conversion and clocks out the first of 4 leading zeros; each SCLK falling edge clocks
// out the next bit (4 zeros, then DB11..DB0 MSB first), so the master reads bit k - 1 at
// the k-th SCLK falling edge (k = 1..16) and DB0 at the 16th; SDATA goes three-state after
// the 16th falling edge. fSCLK <= 20 MHz, SCLK high and low >= 0.4 tSCLK; t2 (CS_N falling
// to SCLK falling) >= 10 ns; t4 (data access after SCLK falling) <= 40 ns; t7 (data hold
// after SCLK falling) >= 10 ns (VDD <= 3.3 V); t8 (SCLK falling to three-state) <= 36 ns;
// tQUIET (bus relinquish to the next CS_N falling) >= 50 ns; t1 (CS_N pulse) >= 10 ns.
//
// Timing generated here (all outputs registered; p = phase counter after an edge, one
// conversion every PERIOD clocks; H = SCLK_HALF, S = CS_SETUP):
//   p = 0                  CS_N falls (SCLK high: idle high)
//   p = S + 2H(k-1)        SCLK falls for the k-th time (k = 1..16); on that same edge the
//                          SDATA lines are sampled: the bit the ADC put out one SCLK period
//                          earlier (t4 <= 40 ns < 2H clocks minus I/O delays), held until
//                          t7 >= 10 ns after this falling edge, so sampling at the edge
//                          that makes SCLK fall is the latest safe point; with a
//                          35.714 MHz clock (ULX3S) and H = 1 the margin is 56 - 40 = 16 ns
//                          for the round trip through pads and board
//   p = S + 2H(k-1) + H    SCLK rises
//   p = S + 31H            SCLK rises after the 16th falling edge, CS_N rises
//   p = S + 30H + 1        m_valid high for one clock with both samples (m_u1, m_u2)
// so the core, fed m_valid as its s_valid, takes the sample on the edge p = S + 30H + 2
// (mod PERIOD), S + 30H + 2 clocks after CS_N fell (the analog sampling instant).
// Requirements on the parameters (checked by the AD7476A model of the tests):
//   2H / f_clk >= 50 ns (fSCLK <= 20 MHz); 2H / f_clk - 40 ns covers the I/O delays;
//   S / f_clk >= 22 ns + I/O delays (t2 >= 10 ns, and the first leading zero, which
//   m_err checks, is only out t3 <= 22 ns after CS_N falls); PERIOD >= S + 31H + 1 (CS_N high >= 1 clock >= t1) and
//   (PERIOD - S - 30H) / f_clk >= t8 + tQUIET = 86 ns.
// Board values: iCEBreaker 20.25 MHz, H = 1, S = 1, PERIOD = 33: SCLK 10.1 MHz, t2
// 49.4 ns, quiet 98.8 ns, 0.614 MS/s. ULX3S 35.714 MHz, H = 1, S = 1, PERIOD = 36: SCLK 17.9 MHz,
// t2 28 ns, quiet 140 ns, 0.992 MS/s.
//
// Output samples: m_u1/m_u2 signed two's complement, s(OUT_W).0 with the 12-bit code
// MSB-aligned (u = code - 2048, times 2^(OUT_W - 12)): 0x000 -> -2048, 0x800 -> 0,
// 0xFFF -> 2047 for OUT_W = 12 (finequad_core's ADC_W = 12). m_err is high with a sample
// whose leading zeros were not all zero on either line (no converter, a line stuck high,
// or broken timing). Valid strobe only, no back-pressure (a fixed-rate sample chain).
// rst: synchronous, active high: CS_N and SCLK high, the next CS_N falling edge comes
// PERIOD - S - 31H clocks after rst (the normal quiet time).
module adc_pmod_ad1 #(
    // clocks per SCLK half period (SCLK = f_clk / (2 SCLK_HALF))
    parameter SCLK_HALF = 1,
    // clocks from CS_N falling to the first SCLK falling edge (>= 1)
    parameter CS_SETUP = 1,
    // clocks per conversion (the sample period)
    parameter PERIOD = 34,
    // output word width (>= 12); the 12-bit code is MSB-aligned
    parameter OUT_W = 12
) (
    input  wire                    clk,
    input  wire                    rst,
    // Pmod AD1 pins (J1: 1 CS, 2 D0, 3 D1, 4 SCLK)
    output reg                     cs_n_o,
    output reg                     sclk_o,
    input  wire                    sdata1_i,     // D0: converter 1 (u1)
    input  wire                    sdata2_i,     // D1: converter 2 (u2)
    // sample stream
    output reg                     m_valid,
    output reg  signed [OUT_W-1:0] m_u1,
    output reg  signed [OUT_W-1:0] m_u2,
    output reg                     m_err
);
    localparam CW = 16;                           // phase counter width
    localparam [31:0] END32 = CS_SETUP + 31 * SCLK_HALF;
    localparam [31:0] PLAST32 = PERIOD - 1;
    localparam [31:0] FIRST32 = CS_SETUP;
    localparam [31:0] HLAST32 = SCLK_HALF - 1;
    localparam [CW-1:0] END = END32[CW-1:0];      // p of CS_N rising
    localparam [CW-1:0] PLAST = PLAST32[CW-1:0];  // last p of a period
    localparam [CW-1:0] FIRST = FIRST32[CW-1:0];  // p of the first SCLK falling edge
    localparam [CW-1:0] HLAST = HLAST32[CW-1:0];  // clocks per SCLK half, - 1
    localparam PAD = OUT_W - 12;

    reg [CW-1:0] p_q = END;
    reg [CW-1:0] hc_q = {CW{1'b0}};               // clocks left in this SCLK half
    reg [5:0]    tog_q = 6'd0;                    // SCLK edges so far in this frame
    reg          run_q = 1'b0;                    // SCLK running
    reg          done_q = 1'b0;                   // the 16th bit was sampled
    reg [15:0]   sh1_q = 16'd0, sh2_q = 16'd0;

    wire [CW-1:0] p_d = (p_q == PLAST) ? {CW{1'b0}} : p_q + 1'b1;

    wire [11:0] code1 = sh1_q[11:0];
    wire [11:0] code2 = sh2_q[11:0];
    wire [11:0] u1 = {~code1[11], code1[10:0]};   // straight binary -> two's complement
    wire [11:0] u2 = {~code2[11], code2[10:0]};
    wire [OUT_W-1:0] a1, a2;                      // MSB-aligned
    generate
        if (PAD == 0) begin : g_w12
            assign a1 = u1;
            assign a2 = u2;
        end else begin : g_wide
            assign a1 = {u1, {PAD{1'b0}}};
            assign a2 = {u2, {PAD{1'b0}}};
        end
    endgenerate

    initial begin
        cs_n_o = 1'b1;
        sclk_o = 1'b1;
        m_valid = 1'b0;
        m_u1 = {OUT_W{1'b0}};
        m_u2 = {OUT_W{1'b0}};
        m_err = 1'b0;
    end

    // the pins' next values, each assigned once per edge (rst included), so that a
    // simulator shows no zero-width pulse on them while rst holds them high
    wire tog = run_q && (hc_q == {CW{1'b0}});     // SCLK toggles on this edge
    wire cs_n_d = rst ? 1'b1 :
                  (p_d == {CW{1'b0}}) ? 1'b0 :
                  (tog && tog_q == 6'd31) ? 1'b1 : cs_n_o;
    wire sclk_d = rst ? 1'b1 :
                  (p_d == FIRST) ? 1'b0 :
                  tog ? !sclk_o : sclk_o;

    always @(posedge clk) begin
        p_q <= p_d;
        m_valid <= 1'b0;
        done_q <= 1'b0;
        cs_n_o <= cs_n_d;
        sclk_o <= sclk_d;
        if (p_d == FIRST) begin
            // first SCLK falling edge; sample the first leading zero
            run_q <= 1'b1;
            hc_q <= HLAST;
            tog_q <= 6'd1;
            sh1_q <= {sh1_q[14:0], sdata1_i};
            sh2_q <= {sh2_q[14:0], sdata2_i};
        end else if (run_q) begin
            if (hc_q != {CW{1'b0}}) begin
                hc_q <= hc_q - 1'b1;
            end else begin
                hc_q <= HLAST;
                tog_q <= tog_q + 1'b1;
                if (sclk_o) begin                 // SCLK falls: sample the previous bit
                    sh1_q <= {sh1_q[14:0], sdata1_i};
                    sh2_q <= {sh2_q[14:0], sdata2_i};
                    if (tog_q == 6'd30)
                        done_q <= 1'b1;
                end
                if (tog_q == 6'd31)               // SCLK rises after the 16th bit,
                    run_q <= 1'b0;                // CS_N rises (cs_n_d)
            end
        end
        if (done_q) begin
            m_valid <= 1'b1;
            m_u1 <= a1;
            m_u2 <= a2;
            m_err <= |{sh1_q[15:12], sh2_q[15:12]};
        end
        if (rst) begin
            p_q <= END;
            run_q <= 1'b0;
            done_q <= 1'b0;
            m_valid <= 1'b0;
        end
    end
endmodule
`resetall
