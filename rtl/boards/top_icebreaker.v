`timescale 1ns / 1ps
`default_nettype none
// top_icebreaker: board shell for the iCEBreaker (iCE40 UP5K-SG48): 12 MHz -> 20.25 MHz PLL,
// reset synchroniser, pins; everything else is rtl/finequad_system.v.
//   PMOD1A: Digilent Pmod AD1 (pin 1 CS_N, 2 D0 = u1, 3 D1 = u2, 4 SCLK); 20.25 MHz,
//           SCLK 10.1 MHz, a conversion every 33 clocks (0.614 MS/s)
//   PMOD1B: pin 1 A, pin 2 B (paced quadrature, 3.3 V), pin 3 Z (out), pin 4 the
//           reference input (a reference-mark comparator's 3.3 V output, high inside
//           the mark's window; no pull-down on the iCE40: tie it low when no reference
//           is wired). Without the host link REF keeps its reset value (ref_q = 0: Z at
//           the count 0 mod 4 n inside the window) and there is no homing.
//   FTDI channel B UART (RX pin 6 into the FPGA, TX pin 9 out): idle (see below)
//   LEDs: green = calibrated, red = a fault (clip, saturation, overspeed) seen (the
//         board has two: the system's position-valid status is left unconnected)
//   BTN_N (user button): reset while pressed
// The UP5K does not hold the core with a live register port: with the host link
// (OPT_HOSTLINK = 1) the system needs more logic cells than the part's 5280. So this board
// runs the core standalone: no host link (the registers at their reset values, which
// synthesis folds into the logic; TX idles high), no harmonic compensation
// (OPT_HARMONIC = 0); the ULX3S build (rtl/boards/top_ulx3s.v) has everything. The cells
// and Fmax of this build: make bitstream. The PLL makes 20.25 MHz, below the roughly
// 30 MHz nextpnr reports, because three of the core's DSP blocks have a stage the open
// tools do not time (scripts/README.md, make report): the MHz to spare are its margin.
// A faster clock: DIVF, with ADC_PERIOD for the ADC's quiet time; scripts/bitstream.sh
// fails when a build misses the PLL's clock.
// The build's parameters and PLL dividers: rtl/builds.toml [icebreaker], through the
// generated rtl/boards/builds.vh (rtl/boards on the include path).
`include "builds.vh"
module top_icebreaker #(
    // folder of the core's $readmemh tables
    parameter TABLE_DIR = "rtl/tables/"
) (
    input  wire CLK,         // 12 MHz
    input  wire BTN_N,       // user button: reset
    output wire LEDR_N,
    output wire LEDG_N,
    // Pmod AD1 on PMOD1A
    output wire P1A1,        // CS_N
    input  wire P1A2,        // SDATA1 (u1)
    input  wire P1A3,        // SDATA2 (u2)
    output wire P1A4,        // SCLK
    // A/B/Z outputs and the reference input on PMOD1B
    output wire P1B1,        // A
    output wire P1B2,        // B
    output wire P1B3,        // Z
    input  wire P1B4,        // reference input
    // FTDI UART (idle: no host link on this board, see above)
    input  wire RX,          // from the host
    output wire TX           // to the host (held high)
);
    wire clk, locked;
    SB_PLL40_PAD #(
        // 12 MHz * 54 = 648 MHz VCO, / 32 = 20.25 MHz (DIVR, DIVF, DIVQ, FILTER_RANGE)
        .FEEDBACK_PATH("SIMPLE"), `FQ_ICEBREAKER_PLL
    ) u_pll (
        .PACKAGEPIN(CLK), .PLLOUTGLOBAL(clk), .LOCK(locked),
        .RESETB(1'b1), .BYPASS(1'b0)
    );

    // reset synchroniser: held while the PLL is unlocked or the button is pressed
    reg [3:0] rst_sync = 4'hf;
    always @(posedge clk)
        rst_sync <= {rst_sync[2:0], !locked || !BTN_N};
    wire rst = rst_sync[3];

    wire [4:0] status;
    finequad_system #(.TABLE_DIR(TABLE_DIR), `FQ_ICEBREAKER_PARAMS) u_sys (
        .clk(clk), .rst(rst),
        .adc_cs_n_o(P1A1), .adc_sclk_o(P1A4), .adc_sdata1_i(P1A2), .adc_sdata2_i(P1A3),
        .uart_rx_i(RX), .uart_tx_o(TX), .ref_i(P1B4), .a_o(P1B1), .b_o(P1B2), .z_o(P1B3),
        .status_o(status)
    );
    assign LEDG_N = !status[0];
    assign LEDR_N = !status[1];
    wire unused = &{1'b0, status[4:2], 1'b0};
endmodule
`resetall
