`timescale 1ns / 1ps
`default_nettype none
// tb_finequad_core: a self-checking testbench of finequad_core (the default build of
// rtl/builds.toml), plain Verilog for Icarus: FuseSoC's sim target (finequad.core;
// make fusesoc). Run from a folder that holds rtl/tables/ (TABLE_DIR), with rtl and
// rtl/tables on the include path.
//   1. After reset every register is read: ID and each register's reset value (the
//      register map's, rtl/finequad_regs.vh: FQ_<REG>_RESET; the counters, the status,
//      REF_COUNT and REF_STATUS as at power-up).
//   2. A slightly distorted circle of ADC codes ($cos/$sin: amplitudes 0.40 and 0.37 of
//      full scale, offsets 1.2 % and -0.8 %, a phase error of 0.05 rad) turns PERIODS
//      signal periods forward, then as many back, SPP samples per period, a sample every
//      DIV clocks. The codes of a phase are the same in every period, so from any sample
//      to the one a period later the count must rise by exactly 4 n (n = INTERP) going
//      forward and fall by 4 n going back, and end where it started; every sample must
//      give a result, LATENCY clocks after its strobe, without a clip, saturation or
//      overspeed bit. (The estimator hands over no coefficients in so few updates, so
//      the phase of a code pair does not change during the run.) The reference input
//      s_ref stays 0, so Z never rises and nothing is latched: m_z, m_homed and
//      m_pos_valid stay 0 (checked with every result).
//   3. COUNT reads the last result's count; REF_COUNT, REF_STATUS and REF_STICKY still
//      read 0.
// The first failed check stops the run with $fatal (a nonzero exit); the last line is
// "tb_finequad_core: PASS" and the number of checks.
module tb_finequad_core #(
    // folder of the core's $readmemh tables (relative to the simulator's folder)
    parameter TABLE_DIR = "rtl/tables/",
    // samples per signal period, periods forward (then as many back), clocks per sample
    parameter SPP = 64,
    parameter PERIODS = 4,
    parameter DIV = 8
);
`include "finequad_regs.vh"
    localparam ADC_W = 16;
    localparam LATENCY = 8;                  // strobe edge to m_valid (rtl/finequad_core.v)
    localparam N = 2 * PERIODS * SPP + 1;    // samples: forward to the turn, back to 0
    localparam real FULL = 32767.0;
    localparam real TWO_PI = 6.283185307179586;

    reg clk = 1'b0;
    always #5 clk = !clk;

    reg                    rst = 1'b1;
    reg                    s_valid = 1'b0;
    reg signed [ADC_W-1:0] s_u1 = 0, s_u2 = 0;
    reg                    reg_we = 1'b0, reg_re = 1'b0;
    reg [5:0]              reg_addr = 6'd0;
    reg [31:0]             reg_wdata = 32'd0;
    wire [31:0]            reg_rdata;
    wire                   m_valid, m_a, m_b, m_z, m_homed, m_pos_valid;
    wire signed [31:0]     m_count, m_ref_count;
    wire [10:0]            m_fault;
    wire [65:0]            eng_cmd;

    finequad_core #(.TABLE_DIR(TABLE_DIR)) dut (
        .clk(clk), .rst(rst),
        .s_valid(s_valid), .s_u1(s_u1), .s_u2(s_u2), .s_ref(1'b0),
        .reg_we(reg_we), .reg_re(reg_re), .reg_addr(reg_addr), .reg_wdata(reg_wdata),
        .reg_rdata(reg_rdata),
        .m_valid(m_valid), .m_count(m_count), .m_fault(m_fault), .m_a(m_a), .m_b(m_b),
        .m_z(m_z), .m_ref_count(m_ref_count), .m_homed(m_homed), .m_pos_valid(m_pos_valid),
        .tdm_ok_i(1'b1), .eng_cmd_o(eng_cmd), .eng_rsp_i(115'd0)
    );

    integer checks = 0;
    integer cycle = 0;
    always @(posedge clk)
        cycle <= cycle + 1;

    // ---- register reads: set on a falling edge, reg_rdata valid after the next rise
    reg [31:0] rd_data;
    task rd(input [5:0] addr);
        begin
            @(negedge clk);
            reg_re = 1'b1;
            reg_addr = addr;
            @(negedge clk);
            reg_re = 1'b0;
            rd_data = reg_rdata;
        end
    endtask

    task expect_reg(input [5:0] addr, input [31:0] want, input [8*16-1:0] name);
        begin
            rd(addr);
            if (rd_data !== want)
                $fatal(1, "tb_finequad_core: %0s (word 0x%02h) reads 0x%08h, expected 0x%08h",
                       name, addr, rd_data, want);
            checks = checks + 1;
        end
    endtask

    // ---- the circle: codes of phase index p (0 .. SPP-1)
    function integer code(input real x);
        begin
            code = (x >= 0.0) ? $rtoi(x + 0.5) : -$rtoi(0.5 - x);
        end
    endfunction

    function integer phase_of(input integer k);     // sample k's phase index
        begin
            phase_of = ((k <= PERIODS * SPP) ? k : 2 * PERIODS * SPP - k) % SPP;
        end
    endfunction

    // ---- results, in order
    integer            nres = 0;
    reg signed [31:0]  counts [0:N-1];
    integer            strobe_at [0:N-1];
    always @(posedge clk) begin
        if (m_valid) begin
            if (nres >= N)
                $fatal(1, "tb_finequad_core: result %0d for %0d samples", nres + 1, N);
            if (cycle - strobe_at[nres] != LATENCY)
                $fatal(1, "tb_finequad_core: sample %0d's result %0d clocks after its strobe, expected %0d",
                       nres, cycle - strobe_at[nres], LATENCY);
            if (m_fault[3:0] != 4'd0)
                $fatal(1, "tb_finequad_core: sample %0d: fault bits 0x%03h (clip, saturation or overspeed)",
                       nres, m_fault);
            if (m_z !== 1'b0 || m_homed !== 1'b0 || m_pos_valid !== 1'b0 || m_ref_count !== 0)
                $fatal(1, "tb_finequad_core: sample %0d without a reference input: Z %b, homed %b, pos_valid %b, ref_count %0d",
                       nres, m_z, m_homed, m_pos_valid, m_ref_count);
            counts[nres] <= m_count;
            nres <= nres + 1;
        end
    end

    integer k, p, n, step;
    real    th;
    initial begin
        // a run that never ends is a failure too
        #(10 * (N * DIV + 2000)) $fatal(1, "tb_finequad_core: timeout with %0d of %0d results",
                                        nres, N);
    end

    initial begin
        repeat (4) @(negedge clk);
        rst = 1'b0;
        repeat (2) @(negedge clk);

        // 1. identification and reset values
        expect_reg(FQ_ID, FQ_ID_ID_RESET, "ID");
        expect_reg(FQ_STATUS, 32'd1 << FQ_STATUS_UNCAL_LSB, "STATUS");
        expect_reg(FQ_INTERP, FQ_INTERP_RESET, "INTERP");
        expect_reg(FQ_EPS, FQ_EPS_RESET, "EPS");
        expect_reg(FQ_LAMBDA_K, FQ_LAMBDA_K_RESET, "LAMBDA_K");
        expect_reg(FQ_KAPPA, FQ_KAPPA_RESET, "KAPPA");
        expect_reg(FQ_PERIOD, FQ_PERIOD_RESET, "PERIOD");
        expect_reg(FQ_SETTLE, FQ_SETTLE_RESET, "SETTLE");
        expect_reg(FQ_GATE, FQ_GATE_RESET, "GATE");
        expect_reg(FQ_COUNT, 32'd0, "COUNT");
        expect_reg(FQ_ILLEGAL, 32'd0, "ILLEGAL");
        expect_reg(FQ_FAULT_STICKY, FQ_FAULT_STICKY_RESET, "FAULT_STICKY");
        expect_reg(FQ_GAIN, FQ_GAIN_RESET, "GAIN");
        expect_reg(FQ_M1, FQ_M1_RESET, "M1");
        expect_reg(FQ_M2, FQ_M2_RESET, "M2");
        expect_reg(FQ_C1, FQ_C1_RESET, "C1");
        expect_reg(FQ_C12, FQ_C12_RESET, "C12");
        expect_reg(FQ_C2, FQ_C2_RESET, "C2");
        expect_reg(FQ_UPDATES, 32'd0, "UPDATES");
        expect_reg(FQ_HARM, FQ_HARM_RESET, "HARM");
        expect_reg(FQ_JUMP, FQ_JUMP_RESET, "JUMP");
        expect_reg(FQ_JUMPS, 32'd0, "JUMPS");
        expect_reg(FQ_ABGEN, FQ_ABGEN_RESET, "ABGEN");
        expect_reg(FQ_AB_BOUND, FQ_AB_BOUND_RESET, "AB_BOUND");
        expect_reg(FQ_AB_BACKLOG, 32'd0, "AB_BACKLOG");
        expect_reg(FQ_CLIP, FQ_CLIP_RESET, "CLIP");
        expect_reg(FQ_RADIUS, FQ_RADIUS_RESET, "RADIUS");
        expect_reg(FQ_MONITOR, FQ_MONITOR_RESET, "MONITOR");
        expect_reg(FQ_CAPTURE, 32'd0, "CAPTURE");
        expect_reg(FQ_TRAVEL, 32'd0, "TRAVEL");
        expect_reg(FQ_REF, FQ_REF_RESET, "REF");
        expect_reg(FQ_HOME, FQ_HOME_RESET, "HOME");
        expect_reg(FQ_REF_COUNT, 32'd0, "REF_COUNT");
        expect_reg(FQ_REF_STATUS, 32'd0, "REF_STATUS");
        expect_reg(FQ_REF_STICKY, FQ_REF_STICKY_RESET, "REF_STICKY");
        n = FQ_INTERP_RESET;

        // 2. the circle, forward then back: a strobe every DIV clocks (inputs set on the
        // falling edge before the strobe edge)
        for (k = 0; k < N; k = k + 1) begin
            p = phase_of(k);
            th = TWO_PI * p / SPP;
            s_u1 = code(FULL * (0.40 * $cos(th) + 0.012));
            s_u2 = code(FULL * (0.37 * $sin(th - 0.05) - 0.008));
            s_valid = 1'b1;
            strobe_at[k] = cycle + 1;
            @(negedge clk);
            s_valid = 1'b0;
            repeat (DIV - 1) @(negedge clk);
        end
        repeat (LATENCY + 4) @(negedge clk);
        if (nres != N)
            $fatal(1, "tb_finequad_core: %0d results for %0d samples", nres, N);
        checks = checks + 1;
        // (samples a period apart on the same side of the turn, sample PERIODS * SPP)
        for (k = 0; k + SPP < N; k = k + 1) begin
            if (k + SPP <= PERIODS * SPP || k >= PERIODS * SPP) begin
                step = (k < PERIODS * SPP) ? 4 * n : -4 * n;
                if (counts[k + SPP] - counts[k] != step)
                    $fatal(1, "tb_finequad_core: count %0d at sample %0d, %0d at %0d a period later: a step of %0d, expected %0d",
                           counts[k], k, counts[k + SPP], k + SPP,
                           counts[k + SPP] - counts[k], step);
                checks = checks + 1;
            end
        end
        if (counts[N - 1] != counts[0])
            $fatal(1, "tb_finequad_core: the count ends at %0d, it started at %0d",
                   counts[N - 1], counts[0]);
        checks = checks + 1;

        // 3. COUNT is the last result's count; no reference was latched
        expect_reg(FQ_COUNT, counts[N - 1], "COUNT (end)");
        expect_reg(FQ_REF_COUNT, 32'd0, "REF_COUNT (end)");
        expect_reg(FQ_REF_STATUS, 32'd0, "REF_STATUS (end)");
        expect_reg(FQ_REF_STICKY, 32'd0, "REF_STICKY (end)");
        $display("tb_finequad_core: PASS (%0d checks; %0d samples, count %0d at the turn, 4 n = %0d per period)", checks, N, counts[PERIODS * SPP], 4 * n);
        $finish;
    end
    wire unused = &{1'b0, m_a, m_b, eng_cmd, 1'b0};
endmodule
`resetall
