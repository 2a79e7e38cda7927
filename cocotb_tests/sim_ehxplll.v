`timescale 1ns / 1ps
`default_nettype none
// EHXPLLL (Lattice ECP5 PLL), behavioural stand-in for simulations of
// rtl/boards/top_ulx3s.v (cocotb_tests/test_system.py): CLKOP is CLKI (the test drives
// the board clock pin at the PLL's output frequency), LOCK rises after 16 CLKI edges.
// The parameters of the real cell are accepted and ignored.
module EHXPLLL #(
    parameter PLLRST_ENA = "DISABLED",
    parameter INTFB_WAKE = "DISABLED",
    parameter STDBY_ENABLE = "DISABLED",
    parameter DPHASE_SOURCE = "DISABLED",
    parameter OUTDIVIDER_MUXA = "DIVA",
    parameter OUTDIVIDER_MUXB = "DIVB",
    parameter OUTDIVIDER_MUXC = "DIVC",
    parameter OUTDIVIDER_MUXD = "DIVD",
    parameter CLKI_DIV = 1,
    parameter CLKOP_ENABLE = "ENABLED",
    parameter CLKOP_DIV = 8,
    parameter CLKOP_CPHASE = 0,
    parameter CLKOP_FPHASE = 0,
    parameter FEEDBK_PATH = "CLKOP",
    parameter CLKFB_DIV = 1
) (
    input  wire RST,
    input  wire STDBY,
    input  wire CLKI,
    output wire CLKOP,
    input  wire CLKFB,
    input  wire PHASESEL0,
    input  wire PHASESEL1,
    input  wire PHASEDIR,
    input  wire PHASESTEP,
    input  wire PHASELOADREG,
    input  wire PLLWAKESYNC,
    input  wire ENCLKOP,
    output reg  LOCK
);
    reg [4:0] cnt = 5'd0;
    initial LOCK = 1'b0;
    assign CLKOP = CLKI;
    always @(posedge CLKI) begin
        if (!cnt[4])
            cnt <= cnt + 1'b1;
        LOCK <= cnt[4];
    end
    wire unused = &{1'b0, RST, STDBY, CLKFB, PHASESEL0, PHASESEL1, PHASEDIR, PHASESTEP,
                    PHASELOADREG, PLLWAKESYNC, ENCLKOP, 1'b0};
endmodule
`resetall
