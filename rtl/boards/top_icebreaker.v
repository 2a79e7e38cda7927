`timescale 1ns / 1ps
`default_nettype none
// top_icebreaker: board shell for the iCEBreaker (iCE40 UP5K). 12 MHz -> 33 MHz PLL,
// reset synchroniser, a Digilent Pmod AD1 on PMOD1A (two AD7476A, 12 bit, 1 MS/s),
// A/B outputs on PMOD1B, LEDs: green = calibrated, red = a fault was seen.
// The core (finequad_core) is what the simulations and proofs cover; this shell only
// adds clocks and pins. The ADC reader here is a bring-up version (conversion every
// 34 clocks = 0.97 MS/s, SCLK = 16.5 MHz, CS high for 60 ns); the verified front end and
// the host link to the register bus come with the integration work. 33 MHz rather than
// 36: the core meets 33 MHz on every nextpnr seed tried, 36 MHz on some only.
module top_icebreaker (
    input  wire CLK,         // 12 MHz
    input  wire BTN_N,       // user button: reset
    output wire LEDR_N,
    output wire LEDG_N,
    // Pmod AD1 on PMOD1A
    output wire P1A1,        // CS_N
    input  wire P1A2,        // SDATA1 (u1)
    input  wire P1A3,        // SDATA2 (u2)
    output wire P1A4,        // SCLK
    // A/B outputs on PMOD1B
    output wire P1B1,        // A
    output wire P1B2         // B
);
    wire clk, locked;
    SB_PLL40_PAD #(
        // 12 MHz * 88 = 1056 MHz VCO, / 32 = 33 MHz
        .FEEDBACK_PATH("SIMPLE"), .DIVR(4'd0), .DIVF(7'd87), .DIVQ(3'd5),
        .FILTER_RANGE(3'd1)
    ) u_pll (
        .PACKAGEPIN(CLK), .PLLOUTGLOBAL(clk), .LOCK(locked),
        .RESETB(1'b1), .BYPASS(1'b0)
    );

    // reset synchroniser: held while the PLL is unlocked or the button is pressed
    reg [3:0] rst_sync = 4'hf;
    always @(posedge clk)
        rst_sync <= {rst_sync[2:0], !locked || !BTN_N};
    wire rst = rst_sync[3];

    // Pmod AD1 reader: 16 SCLK cycles per conversion (4 zeros + 12 data bits, MSB first)
    reg [5:0]  phase = 0;
    reg [15:0] sh1 = 0, sh2 = 0;
    reg        s_valid = 1'b0;
    reg signed [11:0] s_u1 = 0, s_u2 = 0;
    always @(posedge clk) begin
        s_valid <= 1'b0;
        phase <= (phase == 6'd33) ? 6'd0 : phase + 1'b1;
        if (phase < 6'd32 && phase[0]) begin      // rising SCLK: sample the data lines
            sh1 <= {sh1[14:0], P1A2};
            sh2 <= {sh2[14:0], P1A3};
        end
        if (phase == 6'd33) begin                // straight binary -> two's complement
            s_u1 <= {~sh1[11], sh1[10:0]};
            s_u2 <= {~sh2[11], sh2[10:0]};
            s_valid <= 1'b1;
        end
        if (rst)
            phase <= 0;
    end
    assign P1A1 = (phase >= 6'd32);               // CS_N high between conversions
    assign P1A4 = (phase < 6'd32) ? phase[0] : 1'b1;

    wire        m_valid, m_a, m_b;
    wire [31:0] m_count;
    wire [6:0]  m_fault;
    wire [31:0] reg_rdata;
    // the UP5K's 8 DSP blocks are taken (correction 3, estimator 4, octant 1): the n-th
    // order product in logic
    finequad_core #(.ADC_W(12), .OPT_NTH_DSP(1'b0)) u_core (
        .clk(clk), .rst(rst),
        .s_valid(s_valid), .s_u1(s_u1), .s_u2(s_u2),
        .reg_we(1'b0), .reg_re(1'b1), .reg_addr(6'h00), .reg_wdata(32'd0),
        .reg_rdata(reg_rdata),
        .m_valid(m_valid), .m_count(m_count), .m_a(m_a), .m_b(m_b), .m_fault(m_fault)
    );
    assign P1B1 = m_a;
    assign P1B2 = m_b;
    reg seen_fault = 1'b0;
    always @(posedge clk)
        if (m_valid && |m_fault[3:0])
            seen_fault <= 1'b1;
    assign LEDR_N = !seen_fault;
    assign LEDG_N = reg_rdata[0];                 // status bit 0: not calibrated
    wire unused = &{1'b0, m_count, reg_rdata[31:1], m_fault[6:4], 1'b0};
endmodule
`resetall
