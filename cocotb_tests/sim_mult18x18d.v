`timescale 1ns / 1ps
`default_nettype none
// MULT18X18D (Lattice ECP5 DSP multiplier), behavioural stand-in for simulations of the
// instances in rtl/octant.v and rtl/lut.v (OPT_ECP5_MULT = 1, compiled with SYNTHESIS
// defined: cocotb_tests/test_octant.py test_octant_mult18, cocotb_tests/test_lut.py
// test_lut_mult18). Only what those instances use is modelled:
// A and B either combinational (REG_INPUTx_CLK "NONE") or in input registers on CLK0 with
// clock enable CE0 (and synchronous reset RST0), signed or unsigned by SIGNEDA/SIGNEDB,
// P = A * B (36 bits), combinational or in the output register on CLK0 (CE0, RST0), no
// pipeline register, C unused. Any other setting stops the simulation with an error
// naming the parameter.
module MULT18X18D #(
    parameter REG_INPUTA_CLK = "NONE",
    parameter REG_INPUTA_CE = "CE0",
    parameter REG_INPUTA_RST = "RST0",
    parameter REG_INPUTB_CLK = "NONE",
    parameter REG_INPUTB_CE = "CE0",
    parameter REG_INPUTB_RST = "RST0",
    parameter REG_INPUTC_CLK = "NONE",
    parameter REG_PIPELINE_CLK = "NONE",
    parameter REG_OUTPUT_CLK = "NONE",
    parameter REG_OUTPUT_CE = "CE0",
    parameter REG_OUTPUT_RST = "RST0",
    parameter SOURCEB_MODE = "B_SHIFT",
    parameter MULT_BYPASS = "DISABLED",
    parameter RESETMODE = "SYNC",
    parameter GSR = "ENABLED"
) (
    input  wire A17, A16, A15, A14, A13, A12, A11, A10, A9, A8, A7, A6, A5, A4, A3, A2,
                A1, A0,
    input  wire B17, B16, B15, B14, B13, B12, B11, B10, B9, B8, B7, B6, B5, B4, B3, B2,
                B1, B0,
    input  wire C17, C16, C15, C14, C13, C12, C11, C10, C9, C8, C7, C6, C5, C4, C3, C2,
                C1, C0,
    input  wire SIGNEDA, SIGNEDB, SOURCEA, SOURCEB,
    input  wire CLK3, CLK2, CLK1, CLK0, CE3, CE2, CE1, CE0, RST3, RST2, RST1, RST0,
    output wire P35, P34, P33, P32, P31, P30, P29, P28, P27, P26, P25, P24, P23, P22, P21,
                P20, P19, P18, P17, P16, P15, P14, P13, P12, P11, P10, P9, P8, P7, P6, P5,
                P4, P3, P2, P1, P0
);
    initial begin
        if ((REG_INPUTA_CLK != "NONE" && REG_INPUTA_CLK != "CLK0") || REG_INPUTA_CE != "CE0"
            || REG_INPUTA_RST != "RST0")
            $fatal(1, "MULT18X18D stand-in: REG_INPUTA_* %0s/%0s/%0s not modelled",
                   REG_INPUTA_CLK, REG_INPUTA_CE, REG_INPUTA_RST);
        if ((REG_INPUTB_CLK != "NONE" && REG_INPUTB_CLK != "CLK0") || REG_INPUTB_CE != "CE0"
            || REG_INPUTB_RST != "RST0")
            $fatal(1, "MULT18X18D stand-in: REG_INPUTB_* %0s/%0s/%0s not modelled",
                   REG_INPUTB_CLK, REG_INPUTB_CE, REG_INPUTB_RST);
        if ((REG_OUTPUT_CLK != "NONE" && REG_OUTPUT_CLK != "CLK0") || REG_OUTPUT_CE != "CE0"
            || REG_OUTPUT_RST != "RST0")
            $fatal(1, "MULT18X18D stand-in: REG_OUTPUT_* %0s/%0s/%0s not modelled",
                   REG_OUTPUT_CLK, REG_OUTPUT_CE, REG_OUTPUT_RST);
        if (REG_INPUTC_CLK != "NONE" || REG_PIPELINE_CLK != "NONE")
            $fatal(1, "MULT18X18D stand-in: REG_INPUTC/PIPELINE_CLK not modelled");
        if (MULT_BYPASS != "DISABLED" || RESETMODE != "SYNC")
            $fatal(1, "MULT18X18D stand-in: MULT_BYPASS %0s, RESETMODE %0s not modelled",
                   MULT_BYPASS, RESETMODE);
    end
    wire [17:0] a = {A17, A16, A15, A14, A13, A12, A11, A10, A9, A8, A7, A6, A5, A4, A3,
            A2, A1, A0};
    wire [17:0] b = {B17, B16, B15, B14, B13, B12, B11, B10, B9, B8, B7, B6, B5, B4, B3,
            B2, B1, B0};
    reg  [17:0] a_q = 18'd0, b_q = 18'd0;
    always @(posedge CLK0) begin
        if (RST0) begin
            a_q <= 18'd0;
            b_q <= 18'd0;
        end else if (CE0) begin
            a_q <= a;
            b_q <= b;
        end
    end
    wire [17:0] ao = (REG_INPUTA_CLK == "CLK0") ? a_q : a;
    wire [17:0] bo = (REG_INPUTB_CLK == "CLK0") ? b_q : b;
    wire signed [36:0] sa = SIGNEDA ? {{19{ao[17]}}, ao} : {19'd0, ao};
    wire signed [36:0] sb = SIGNEDB ? {{19{bo[17]}}, bo} : {19'd0, bo};
    wire signed [36:0] prod = sa * sb;
    reg  [35:0] p_q = 36'd0;
    always @(posedge CLK0) begin
        if (RST0)
            p_q <= 36'd0;
        else if (CE0)
            p_q <= prod[35:0];
    end
    wire [35:0] po = (REG_OUTPUT_CLK == "CLK0") ? p_q : prod[35:0];
    assign {P35, P34, P33, P32, P31, P30, P29, P28, P27, P26, P25, P24, P23, P22, P21,
            P20, P19, P18, P17, P16, P15, P14, P13, P12, P11, P10, P9, P8, P7, P6, P5, P4, P3,
            P2, P1, P0} = po;
    wire unused = &{1'b0, C17, C16, C15, C14, C13, C12, C11, C10, C9, C8, C7, C6, C5,
            C4, C3, C2, C1, C0,
                     SOURCEA, SOURCEB, CLK3, CLK2, CLK1, CE3, CE2, CE1, RST3, RST2, RST1,
                     1'b0};
endmodule
`resetall
