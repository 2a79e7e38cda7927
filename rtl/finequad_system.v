`timescale 1ns / 1ps
`default_nettype none
// finequad_system: the board-independent design that every board top instantiates
// (verilog-ethernet's fpga_core.v): Pmod AD1 front end -> finequad_core, the core's
// registers on an AXI4-Lite bus (axil_regs) mastered by the UART bridge (uart_axil), the
// reference input, the A/B and Z outputs, status for LEDs.
//
//   adc pins -> adc_pmod_ad1 -> m_valid/m_u1/m_u2 --> finequad_core -> m_a/m_b/m_z -> a_o/b_o/z_o
//   ref_i -> synchroniser -> s_ref (from CS_N falling) -'
//   uart_rx_i -> uart_axil (AXI4-Lite master) -> axil_regs -> core register port
//   (OPT_HOSTLINK = 0: no host link, the registers at their reset values)
//   uart_tx_o <-'
//
// AXI address map (byte addresses, 32-bit words): 0x0000 + 4 k = finequad_core register k
// for k = 0 .. FQ_ADDR_TOP (rtl/regs/finequad.rdl; e.g. 0x7C = ID, 0x20 = COUNT); words
// above it answer SLVERR; partial writes (WSTRB != 4'hF) SLVERR.
// UART: 8N1 at f_clk / BAUD_DIV, protocol in rtl/uart_axil.v and scripts/fqhost.py.
//
// Timing: a conversion every ADC_PERIOD clocks; the core takes sample k on the edge
// ADC_CS_SETUP + 30 ADC_SCLK_HALF + 2 clocks after its CS_N falling edge (see
// rtl/adc_pmod_ad1.v); a_o/b_o/z_o are the core's m_a/m_b/m_z registered once more (one
// clock later than the core's ports; pins straight from flip-flops).
// Reference input ref_i (a reference-mark comparator's output, asynchronous): two
// flip-flops synchronise it, and the level they hold on the edge after CS_N falls (ref_i
// one clock before that edge, the converters' sampling instant) is held and given to the
// core as s_ref with the sample that conversion makes (the core takes it
// ADC_CS_SETUP + 30 ADC_SCLK_HALF + 1 clocks later, before the next conversion replaces
// it), so the reference level and the codes describe the same instant. Z, the
// reference count, homing and pos_valid: rtl/refmark.v (REF, HOME, REF_COUNT, REF_STATUS,
// REF_STICKY).
// status_o (for LEDs; [1..3] sticky until rst): [0] calibrated (the last sample's fault
// bit 4 clear), [1] a fault seen (fault bits 0..3: clip, saturations, overspeed), [2] an
// ADC frame with non-zero leading bits seen (no Pmod, wrong pins), [3] a UART frame
// dropped (timeout, framing error or break), [4] position valid (the core's
// REF_STATUS.pos_valid: a reference latched and the count not lost since).
// rst: synchronous, active high, to every block.
module finequad_system #(
    // folder of the core's $readmemh tables
    parameter TABLE_DIR = "rtl/tables/",
    // the core's n * phase product: 1 DSP block, 0 logic (iCE40 UP5K: DSPs are taken)
    parameter [0:0] OPT_NTH_DSP = 1'b0,
    // the core's harmonic compensation (rtl/harmonic.v)
    parameter [0:0] OPT_HARMONIC = 1'b1,
    // the core's harmonic table in distributed RAM, its exact phase table in 4096 rows per sign
    // (rtl/finequad_core.v; 1 on the ECP5, 0 on the iCE40)
    parameter [0:0] OPT_DISTRAM = 1'b0,
    parameter [0:0] OPT_PHASE_4K = 1'b0,
    // the ratio multiply's operand registers and the n-th order product's register in
    // ECP5 DSP blocks (rtl/finequad_core.v)
    parameter [0:0] OPT_ECP5_MULT = 1'b0,
    // Eq. 12 on the sine table's address side (rtl/finequad_core.v)
    parameter [0:0] OPT_PULSE_ADDR = 1'b0,
    // the core's signal monitor and jump detector (rtl/finequad_core.v OPT_MONITOR,
    // OPT_JUMP)
    parameter [0:0] OPT_MONITOR = 1'b1,
    parameter [0:0] OPT_JUMP = 1'b1,
    // distance-coded reference marks (rtl/finequad_core.v OPT_DCODE)
    parameter [0:0] OPT_DCODE = 1'b1,
    // ADC front end: clocks per SCLK half period, CS_N to first SCLK falling, per sample
    parameter ADC_SCLK_HALF = 1,
    parameter ADC_CS_SETUP = 1,
    parameter ADC_PERIOD = 34,
    // clocks per UART bit (f_clk / baud)
    parameter BAUD_DIV = 286,
    // clocks between two bytes of a UART frame before it is abandoned
    parameter [19:0] UART_TIMEOUT = 20'd262143,
    // 1: the UART host link and the AXI4-Lite registers; 0: none (the core's registers
    // keep their reset values, which synthesis folds into the logic; uart_tx_o idles
    // high): for a device the core with a live register port does not fit (the UP5K)
    parameter [0:0] OPT_HOSTLINK = 1'b1
) (
    input  wire       clk,
    input  wire       rst,
    // Pmod AD1
    output wire       adc_cs_n_o,
    output wire       adc_sclk_o,
    input  wire       adc_sdata1_i,
    input  wire       adc_sdata2_i,
    // host link
    input  wire       uart_rx_i,
    output wire       uart_tx_o,
    // reference input (asynchronous, see above)
    input  wire       ref_i,
    // quadrature outputs and Z
    output reg        a_o,
    output reg        b_o,
    output reg        z_o,
    // status (see above)
    output wire [4:0] status_o
);
    // the core's register map (FQ_ADDR_TOP, the fault bits): rtl/regs/finequad.rdl
    `include "finequad_regs.vh"

    // ---- ADC front end ---------------------------------------------------------------------
    wire               s_valid, adc_err;
    wire signed [11:0] s_u1, s_u2;
    adc_pmod_ad1 #(.SCLK_HALF(ADC_SCLK_HALF), .CS_SETUP(ADC_CS_SETUP),
                   .PERIOD(ADC_PERIOD), .OUT_W(12)) u_adc (
        .clk(clk), .rst(rst), .cs_n_o(adc_cs_n_o), .sclk_o(adc_sclk_o),
        .sdata1_i(adc_sdata1_i), .sdata2_i(adc_sdata2_i),
        .m_valid(s_valid), .m_u1(s_u1), .m_u2(s_u2), .m_err(adc_err)
    );

    // ---- host link: UART -> AXI4-Lite -> register port -------------------------------------
    wire        reg_we, reg_re;
    wire [5:0]  reg_addr;
    wire [31:0] reg_wdata, reg_rdata;
    wire        reg_err;
    wire        uart_drop;
    generate
        if (OPT_HOSTLINK) begin : g_host
            wire [15:0] awaddr, araddr;
            wire [2:0]  awprot, arprot;
            wire        awvalid, awready, wvalid, wready, bvalid, bready;
            wire        arvalid, arready, rvalid, rready;
            wire [31:0] wdata, rdata;
            wire [3:0]  wstrb;
            wire [1:0]  bresp, rresp;
            wire        uart_ferr;
            uart_axil #(.DIV(BAUD_DIV), .TIMEOUT(UART_TIMEOUT)) u_uart (
                .clk(clk), .rst(rst), .rxd_i(uart_rx_i), .txd_o(uart_tx_o),
                .m_axil_awaddr(awaddr), .m_axil_awprot(awprot), .m_axil_awvalid(awvalid),
                .m_axil_awready(awready), .m_axil_wdata(wdata), .m_axil_wstrb(wstrb),
                .m_axil_wvalid(wvalid), .m_axil_wready(wready), .m_axil_bresp(bresp),
                .m_axil_bvalid(bvalid), .m_axil_bready(bready), .m_axil_araddr(araddr),
                .m_axil_arprot(arprot), .m_axil_arvalid(arvalid), .m_axil_arready(arready),
                .m_axil_rdata(rdata), .m_axil_rresp(rresp), .m_axil_rvalid(rvalid),
                .m_axil_rready(rready), .frame_err_o(uart_ferr), .drop_o(uart_drop)
            );
            axil_regs #(.ADDR_W(16), .ADDR_TOP(FQ_ADDR_TOP)) u_regs (
                .clk(clk), .rst(rst),
                .s_axil_awaddr(awaddr), .s_axil_awprot(awprot), .s_axil_awvalid(awvalid),
                .s_axil_awready(awready), .s_axil_wdata(wdata), .s_axil_wstrb(wstrb),
                .s_axil_wvalid(wvalid), .s_axil_wready(wready), .s_axil_bresp(bresp),
                .s_axil_bvalid(bvalid), .s_axil_bready(bready), .s_axil_araddr(araddr),
                .s_axil_arprot(arprot), .s_axil_arvalid(arvalid), .s_axil_arready(arready),
                .s_axil_rdata(rdata), .s_axil_rresp(rresp), .s_axil_rvalid(rvalid),
                .s_axil_rready(rready),
                .reg_we(reg_we), .reg_re(reg_re), .reg_addr(reg_addr), .reg_wdata(reg_wdata),
                .reg_rdata(reg_rdata), .reg_err(reg_err)
            );
            wire unused_host = &{1'b0, uart_ferr, 1'b0};
        end else begin : g_nohost
            assign reg_we = 1'b0;
            assign reg_re = 1'b0;
            assign reg_addr = 6'd0;
            assign reg_wdata = 32'd0;
            assign uart_tx_o = 1'b1;
            assign uart_drop = 1'b0;
            wire unused_host = &{1'b0, uart_rx_i, reg_rdata, reg_err, 1'b0};
        end
    endgenerate

    // ---- reference input: synchroniser, then held from the conversion's CS_N edge ----------
    reg [1:0] ref_sync = 2'b00;              // ref_i, two flip-flops
    reg       cs_n_q = 1'b1;                 // CS_N one edge later: its falling edge
    reg       s_ref = 1'b0;                  // the conversion's reference level
    always @(posedge clk) begin
        ref_sync <= {ref_sync[0], ref_i};
        cs_n_q <= adc_cs_n_o;
        if (cs_n_q && !adc_cs_n_o)
            s_ref <= ref_sync[1];
        if (rst) begin
            cs_n_q <= 1'b1;
            s_ref <= 1'b0;
        end
    end

    // ---- the core ---------------------------------------------------------------------------
    wire        m_valid, m_a, m_b, m_z, m_homed, m_pos_valid;
    wire [31:0] m_count, m_ref_count;
    wire [FQ_FAULT_W-1:0] m_fault;   // finequad_core: FAULT_STICKY's bits
    wire [65:0] eng_cmd;                 // 0: the core's engine is inside
    finequad_core #(.TABLE_DIR(TABLE_DIR), .ADC_W(12), .OPT_NTH_DSP(OPT_NTH_DSP),
                    .OPT_HARMONIC(OPT_HARMONIC), .OPT_DISTRAM(OPT_DISTRAM),
                    .OPT_PHASE_4K(OPT_PHASE_4K), .OPT_ECP5_MULT(OPT_ECP5_MULT),
                    .OPT_PULSE_ADDR(OPT_PULSE_ADDR),
                    .OPT_MONITOR(OPT_MONITOR), .OPT_JUMP(OPT_JUMP), .OPT_DCODE(OPT_DCODE)) u_core (
        .clk(clk), .rst(rst),
        .s_valid(s_valid), .s_u1(s_u1), .s_u2(s_u2), .s_ref(s_ref),
        .reg_we(reg_we), .reg_re(reg_re), .reg_addr(reg_addr), .reg_wdata(reg_wdata),
        .reg_rdata(reg_rdata), .reg_err(reg_err),
        .m_fault(m_fault),
        .m_valid(m_valid), .m_count(m_count), .m_a(m_a), .m_b(m_b),
        .m_z(m_z), .m_ref_count(m_ref_count), .m_homed(m_homed), .m_pos_valid(m_pos_valid),
        .tdm_ok_i(1'b1), .eng_cmd_o(eng_cmd), .eng_rsp_i(115'd0)   // the engine inside
    );
    wire unused_eng = &{1'b0, eng_cmd, 1'b0};

    // ---- pins and status ----------------------------------------------------------------------
    reg cal_q = 1'b0, fault_q = 1'b0, adc_err_q = 1'b0, uart_err_q = 1'b0;
    initial begin
        a_o = 1'b1;
        b_o = 1'b1;
        z_o = 1'b0;
    end
    always @(posedge clk) begin
        a_o <= m_a;
        b_o <= m_b;
        z_o <= m_z;
        if (m_valid) begin
            cal_q <= !m_fault[FQ_FAULT_STICKY_UNCAL_LSB];
            if (m_fault[FQ_FAULT_STICKY_CLIP_LSB] || m_fault[FQ_FAULT_STICKY_NSAT_LSB] ||
                m_fault[FQ_FAULT_STICKY_CSAT_LSB] || m_fault[FQ_FAULT_STICKY_OVS_LSB])
                fault_q <= 1'b1;
        end
        if (s_valid && adc_err)
            adc_err_q <= 1'b1;
        if (uart_drop)
            uart_err_q <= 1'b1;
        if (rst) begin
            cal_q <= 1'b0;
            fault_q <= 1'b0;
            adc_err_q <= 1'b0;
            uart_err_q <= 1'b0;
        end
    end
    // pos_valid: the core's register (rtl/refmark.v), straight to the LED
    assign status_o = {m_pos_valid, uart_err_q, adc_err_q, fault_q, cal_q};
    wire unused = &{1'b0, m_count, m_fault, m_ref_count, m_homed, 1'b0};
endmodule
`resetall
