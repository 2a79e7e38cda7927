`timescale 1ns / 1ps
`default_nettype none
// top_ulx3s: board shell for the ULX3S (ECP5 LFE5U-25F-6BG381C, 25 MHz oscillator,
// FT231X USB UART): 25 MHz -> 35.714 MHz PLL (EHXPLLL: 25 MHz / 7 * 10, VCO 607 MHz;
// values from ecppll), reset synchroniser, pins; everything else is
// rtl/finequad_system.v.
//   J1 GPIO, GP row (gp[0..3], next to the header's GND and 3.3 V pins): a Digilent
//       Pmod AD1 plugged with its GND/VCC on the board's GND/3.3 V: gp[3] CS_N (Pmod pin
//       1), gp[2] D0 = u1 (pin 2), gp[1] D1 = u2 (pin 3), gp[0] SCLK (pin 4); 35.714 MHz,
//       SCLK 17.9 MHz, a conversion every 36 clocks (0.992 MS/s)
//   J1 GPIO, GN row: gn[0] A, gn[1] B, gn[2] Z, gn[3] the reference input (a
//       reference-mark comparator's 3.3 V output; pulled down: no reference when open)
//   FT231X UART (ftdi_txd into the FPGA, ftdi_rxd out): 115 207 baud (35.714 MHz / 310)
//   LEDs: led[0] calibrated, led[1] a fault seen, led[2] ADC leading bits not zero (no
//       Pmod), led[3] a UART frame dropped, led[4] position valid (a reference latched,
//       the count not lost since: REF_STATUS.pos_valid), led[7] PLL locked
//   btn[1] (FIRE1, active high): reset while pressed
// Pins from the board's ulx3s_v20.lpf (constraints/ulx3s.lpf); the Pmod-to-header
// orientation follows the header's layout (3.3 V, GND, then pairs 0..3): check it
// against your board before plugging the Pmod in.
// The build's parameters and PLL settings: rtl/builds.toml [ulx3s], through the generated
// rtl/boards/builds.vh (rtl/boards on the include path).
`include "builds.vh"
module top_ulx3s #(
    // folder of the core's $readmemh tables
    parameter TABLE_DIR = "rtl/tables/"
) (
    input  wire       clk_25mhz,
    input  wire [1:1] btn,
    output wire [7:0] led,
    input  wire       ftdi_txd,     // from the host (FT231X TXD)
    output wire       ftdi_rxd,     // to the host (FT231X RXD)
    // Pmod AD1 on the GP row of J1
    output wire       adc_cs_n,     // gp[3]
    input  wire       adc_sdata1,   // gp[2] (D0, u1)
    input  wire       adc_sdata2,   // gp[1] (D1, u2)
    output wire       adc_sclk,     // gp[0]
    // A/B/Z and the reference input on the GN row of J1
    output wire       quad_a,       // gn[0]
    output wire       quad_b,       // gn[1]
    output wire       quad_z,       // gn[2]
    input  wire       ref_in        // gn[3]
);
    wire clk, locked;
    (* FREQUENCY_PIN_CLKI=`FQ_ULX3S_CLKI_MHZ *)
    (* FREQUENCY_PIN_CLKOP=`FQ_ULX3S_CLKOP_MHZ *)
    (* ICP_CURRENT="12" *) (* LPF_RESISTOR="8" *) (* MFG_ENABLE_FILTEROPAMP="1" *)
    (* MFG_GMCREF_SEL="2" *)
    EHXPLLL #(
        .PLLRST_ENA("DISABLED"), .INTFB_WAKE("DISABLED"), .STDBY_ENABLE("DISABLED"),
        .DPHASE_SOURCE("DISABLED"), .OUTDIVIDER_MUXA("DIVA"), .OUTDIVIDER_MUXB("DIVB"),
        .OUTDIVIDER_MUXC("DIVC"), .OUTDIVIDER_MUXD("DIVD"),
        .CLKOP_ENABLE("ENABLED"), .CLKOP_FPHASE(0), .FEEDBK_PATH("CLKOP"),
        // CLKI_DIV, CLKFB_DIV, CLKOP_DIV, CLKOP_CPHASE
        `FQ_ULX3S_PLL
    ) u_pll (
        .RST(1'b0), .STDBY(1'b0), .CLKI(clk_25mhz), .CLKOP(clk), .CLKFB(clk),
        .PHASESEL0(1'b0), .PHASESEL1(1'b0), .PHASEDIR(1'b1),
        .PHASESTEP(1'b1), .PHASELOADREG(1'b1), .PLLWAKESYNC(1'b0), .ENCLKOP(1'b0),
        .LOCK(locked)
    );

    reg [3:0] rst_sync = 4'hf;
    always @(posedge clk)
        rst_sync <= {rst_sync[2:0], !locked || btn[1]};
    wire rst = rst_sync[3];

    wire [4:0] status;
    finequad_system #(.TABLE_DIR(TABLE_DIR), `FQ_ULX3S_PARAMS) u_sys (
        .clk(clk), .rst(rst),
        .adc_cs_n_o(adc_cs_n), .adc_sclk_o(adc_sclk), .adc_sdata1_i(adc_sdata1),
        .adc_sdata2_i(adc_sdata2), .uart_rx_i(ftdi_txd), .uart_tx_o(ftdi_rxd),
        .ref_i(ref_in), .a_o(quad_a), .b_o(quad_b), .z_o(quad_z), .status_o(status)
    );
    assign led = {locked, 2'b00, status};
endmodule
`resetall
