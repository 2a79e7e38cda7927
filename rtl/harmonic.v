`timescale 1ns / 1ps
`default_nettype none
// harmonic: adaptive compensation of the fine phase's periodic error (the residual
// harmonic distortion of the encoder signals, which no ellipse correction removes).
// Bit-true model and the algorithm: sim/model/harmonic.py. No multiplier, one block RAM.
//
// Per sample, with b = phase[12:7] (64 bins of 128 units):
//   corr    = (64 A[b] - R) >>> 14        s10 phase units, R = sum(A) - 8192 (s23), i.e.
//                                         round(A[b] - mean(A)): zero-mean over the table
//   phase_o = apply ? phase - corr : phase          (u13, wraps)
//   observer of pc = phase - corr (always, also while apply is off):
//     E = wrap21(pc * 256 - P);  P += (V >>> 8) + (E >>> KA);  V += E * 2^(8 - KB)
//     P u13.8 (wraps with the period), V s13.16 units/sample (wraps), E s13.8; gears
//     (KA, KB) = (2, 5), (4, 10), (7, 15) by C, the samples since |E| >= 1024 units
//     (C < 64, < 512, else; u11, saturating)
//   Y = E * 256 - M;  M += Y >>> 10                 M: running mean of E, s13.16 (s30)
//   x = (Y >>> 8) - (R >>> 4)                       s24, E minus its mean minus 4 mean(A)
//   learn when learn_i, C == 2047, 16 <= |V| >> 16 < 512 (|V| as one's complement; C
//   and V before this sample's update) and -256 <= E >> 8 < 256:
//     H[b] = sat16(H[b] + sat12((x + (2^mu >> 1)) >>> mu))     H, A entries s8.8 units
// A is H delayed by D = 7 samples: the update of sample j is written to the table RAM
// (A) when sample j + 7 arrives, so the correction of sample k sees the updates of
// samples <= k - 7 whatever the strobe pattern. The learning view H (updates <= k - 1)
// is A plus the last updates, kept in a 7-entry history (newest first).
//
// Timing, a = the edge on which valid_i is high (the sample's arrival):
//   a      stage 1: RAM read of A[b]; commit of sample k - 7 (RAM write, valid bit, R)
//   a + 1  corr (apply_i sampled on this edge)
//   a + 2  phase_o, valid_o                             (latency 3 from phase_i)
//   a + 3  observer: E, P, V
//   a + 4  Y, M, lock gate
//   a + 5  update d (learn_i and mu_i sampled on this edge); learning view precomputed
//   a + 6  H[b] + d, pushed into the history
// clear_i high on edge w: the samples arriving on edges >= w see empty tables (A = H = 0,
// R = -8192); updates of samples that arrived before w are dropped. The observer and M
// keep running. Clearing is instant: each bin has a valid bit (cleared together), the
// RAM is not swept.
// The in-flight count c (samples arrived, not yet pushed) is at most 6, so the update of
// sample k - 7 sits at history position 6 - c when sample k arrives.
module harmonic (
    input  wire        clk,
    input  wire        valid_i,
    input  wire [12:0] phase_i,     // u13 fine phase (registered, lut phase_o)
    input  wire        apply_i,     // apply the correction to phase_o
    input  wire        learn_i,     // update the table
    input  wire [3:0]  mu_i,        // LMS step 2^-mu
    input  wire        clear_i,     // one-clock pulse: empty the tables
    output reg         valid_o = 1'b0,
    output reg  [12:0] phase_o = 13'd0,
    output reg  [15:0] updates_o = 16'd0    // updates computed (gate open; wraps)
);
    localparam D = 7;               // samples between an update and the correction using it
    localparam VMIN_LOG2 = 4;       // learning window: 2^4 <= |V| < 2^9 units/sample
    localparam VMAX_LOG2 = 9;
    localparam [22:0] R0 = -23'sd8192;

    // ---- table RAM (A) and its valid bits ---------------------------------------------------
    reg [15:0] mem [0:63];
    reg [63:0] vb = 64'd0;
    integer mi;
    initial
        for (mi = 0; mi < 64; mi = mi + 1)
            mem[mi] = 16'd0;

    // ---- history of the last D updates: position 0 newest ---------------------------------
    reg        hw [0:D-1];          // a table write (learning gate open, not cleared)
    reg [5:0]  hb [0:D-1];
    reg [15:0] hh [0:D-1];          // new entry, s8.8
    reg [11:0] hd [0:D-1];          // new - old, s12
    integer hi;
    initial
        for (hi = 0; hi < D; hi = hi + 1) begin
            hw[hi] = 1'b0; hb[hi] = 6'd0; hh[hi] = 16'd0; hd[hi] = 12'd0;
        end
    reg [2:0] inflight = 3'd0;      // samples arrived and not yet pushed (0..6)

    // ---- stage 1 (edge a): read, commit ----------------------------------------------------
    wire [5:0]  bin_i = phase_i[12:7];
    wire [2:0]  cpos = 3'd6 - inflight;
    wire        cw = valid_i && hw[cpos] && !clear_i;
    wire [5:0]  cb = hb[cpos];
    wire [15:0] ch = hh[cpos];
    wire [11:0] cd = hd[cpos];
    reg  signed [22:0] r_sum = R0;  // R = sum(A) - 8192
    reg         v1 = 1'b0, ok1 = 1'b0, vbq = 1'b0, c1_we = 1'b0;
    reg  [12:0] ph1 = 13'd0;
    reg  [5:0]  b1 = 6'd0, c1_b = 6'd0;
    reg  [15:0] rd_q = 16'd0, c1_h = 16'd0;
    always @(posedge clk) begin
        rd_q <= mem[bin_i];
        if (cw)
            mem[cb] <= ch;
    end
    always @(posedge clk) begin
        v1 <= valid_i;
        ok1 <= 1'b1;
        ph1 <= phase_i;
        b1 <= bin_i;
        vbq <= !clear_i && vb[bin_i];
        c1_we <= cw;
        c1_b <= cb;
        c1_h <= ch;
        if (clear_i) begin
            vb <= 64'd0;
            r_sum <= R0;
        end else if (cw) begin
            vb[cb] <= 1'b1;
            r_sum <= r_sum + {{11{cd[11]}}, cd};
        end
    end

    // ---- stage 2 (edge a + 1): correction --------------------------------------------------
    wire [15:0] ha = (c1_we && c1_b == b1) ? c1_h : (vbq ? rd_q : 16'd0);
    wire signed [23:0] cfull = $signed({{2{ha[15]}}, ha, 6'd0}) - $signed({r_sum[22], r_sum});
    reg         v2 = 1'b0, ok2 = 1'b0, ap2 = 1'b0;
    reg  [12:0] ph2 = 13'd0;
    reg  [9:0]  corr2 = 10'd0;      // s10
    reg  [5:0]  b2 = 6'd0;
    reg  [15:0] ha2 = 16'd0;
    reg  [18:0] u2 = 19'd0;         // R >>> 4, s19
    always @(posedge clk) begin
        v2 <= v1;
        ok2 <= ok1 && !clear_i;
        ap2 <= apply_i;
        ph2 <= ph1;
        corr2 <= cfull[23:14];
        b2 <= b1;
        ha2 <= ha;
        u2 <= r_sum[22:4];
    end

    // ---- stage 3 (edge a + 2): output -------------------------------------------------------
    wire [12:0] pc = ph2 - {{3{corr2[9]}}, corr2};
    reg         v3 = 1'b0, ok3 = 1'b0;
    reg  [12:0] pc3 = 13'd0;
    reg  [5:0]  b3 = 6'd0;
    reg  [15:0] ha3 = 16'd0;
    reg  [18:0] u3 = 19'd0;
    always @(posedge clk) begin
        valid_o <= v2;
        phase_o <= ap2 ? pc : ph2;
        v3 <= v2;
        ok3 <= ok2 && !clear_i;
        pc3 <= pc;
        b3 <= b2;
        ha3 <= ha2;
        u3 <= u2;
    end

    // ---- stage 4 (edge a + 3): observer -----------------------------------------------------
    // gains by C (samples in track): C < 64: P += E >>> 2, V += E << 3 (KA 2, KB 5);
    // C < 512: E >>> 4, E >>> 2 (KA 4, KB 10); else E >>> 7, E >>> 7 (KA 7, KB 15)
    reg  [20:0] p_st = 21'd0;                   // P, u13.8
    reg  signed [28:0] v_st = 29'sd0;           // V, s13.16
    reg  [10:0] c_st = 11'd0;                   // C, u11
    wire [20:0] e_w = {pc3, 8'd0} - p_st;       // E, s13.8 (wraps)
    wire        g0 = (c_st < 11'd64);
    wire        g1 = !g0 && (c_st < 11'd512);
    wire [20:0] dp = g0 ? {{2{e_w[20]}}, e_w[20:2]} :
                     g1 ? {{4{e_w[20]}}, e_w[20:4]} : {{7{e_w[20]}}, e_w[20:7]};
    wire [28:0] dv = g0 ? {{5{e_w[20]}}, e_w, 3'd0} :
                     g1 ? {{10{e_w[20]}}, e_w[20:2]} : {{15{e_w[20]}}, e_w[20:7]};
    wire [20:0] q_w = p_st + v_st[28:8];        // P + (V >>> 8)
    wire        lost = !((e_w[20:18] == 3'b000) || (e_w[20:18] == 3'b111));
    wire [28:0] av = v_st[28] ? ~v_st : v_st;   // |V| (one's complement)
    wire        win = (c_st == 11'd2047) && (av[28:VMAX_LOG2+16] == 0) &&
                      (av[VMAX_LOG2+15:VMIN_LOG2+16] != 0);
    reg         v4 = 1'b0, ok4 = 1'b0, win4 = 1'b0;
    reg  [20:0] e4 = 21'd0;
    reg  [5:0]  b4 = 6'd0;
    reg  [15:0] ha4 = 16'd0;
    reg  [18:0] u4 = 19'd0;
    always @(posedge clk) begin
        if (v3) begin
            p_st <= q_w + dp;
            v_st <= v_st + dv;
            c_st <= lost ? 11'd0 : (c_st == 11'd2047) ? c_st : c_st + 1'b1;
        end
        v4 <= v3;
        ok4 <= ok3 && !clear_i;
        win4 <= win;
        e4 <= e_w;
        b4 <= b3;
        ha4 <= ha3;
        u4 <= u3;
    end

    // ---- stage 5 (edge a + 4): running mean of E, lock gate ---------------------------------
    reg  signed [29:0] m_st = 30'sd0;           // M, s13.16
    wire signed [30:0] y_w = $signed({{2{e4[20]}}, e4, 8'd0}) - $signed({m_st[29], m_st});
    reg         v5 = 1'b0, ok5 = 1'b0, win5 = 1'b0, lock5 = 1'b0;
    reg  [22:0] y5 = 23'd0;                     // Y >>> 8, s23
    reg  [5:0]  b5 = 6'd0;
    reg  [15:0] ha5 = 16'd0;
    reg  [18:0] u5 = 19'd0;
    always @(posedge clk) begin
        if (v4)
            m_st <= m_st + {{9{y_w[30]}}, y_w[30:10]};
        v5 <= v4;
        ok5 <= ok4 && !clear_i;
        win5 <= win4;
        lock5 <= (e4[20:16] == 5'b00000) || (e4[20:16] == 5'b11111);
        y5 <= y_w[30:8];
        b5 <= b4;
        ha5 <= ha4;
        u5 <= u4;
    end

    // ---- stage 6 (edge a + 5): update, learning view ----------------------------------------
    wire signed [23:0] x_w = $signed({y5[22], y5}) - $signed({{5{u5[18]}}, u5});
    wire signed [24:0] xr = $signed({x_w[23], x_w}) + $signed({9'd0, 16'd1 << mu_i >> 1});
    wire signed [24:0] xs = xr >>> mu_i;
    wire [11:0] d_w = (xs > 25'sd2047) ? 12'h7ff : (xs < -25'sd2048) ? 12'h800 : xs[11:0];
    // newest matching history entry among positions 0..D-2 (older ones are in A)
    reg  [15:0] pre;
    integer pi;
    always @* begin
        pre = ha5;
        for (pi = D - 2; pi >= 0; pi = pi - 1)
            if (hw[pi] && hb[pi] == b5)
                pre = hh[pi];
    end
    reg         v6 = 1'b0, ok6 = 1'b0, g6 = 1'b0;
    reg  [11:0] d6 = 12'd0;
    reg  [5:0]  b6 = 6'd0;
    reg  [15:0] pre6 = 16'd0;
    always @(posedge clk) begin
        v6 <= v5;
        ok6 <= ok5 && !clear_i;
        g6 <= v5 && learn_i && win5 && lock5;
        d6 <= d_w;
        b6 <= b5;
        pre6 <= pre;
    end

    // ---- stage 7 (edge a + 6): learning, history push --------------------------------------
    reg  pushed = 1'b0;             // a push on the previous edge (its entry is position 0)
    wire [15:0] hf = (pushed && hw[0] && hb[0] == b6) ? hh[0] : pre6;
    wire signed [16:0] hsum = $signed({hf[15], hf}) + $signed({{5{d6[11]}}, d6});
    wire        hi_sat = (hsum > 17'sd32767);
    wire        lo_sat = (hsum < -17'sd32768);
    wire [15:0] hn = hi_sat ? 16'h7fff : lo_sat ? 16'h8000 : hsum[15:0];
    wire [15:0] dhi = 16'h7fff - hf;            // new - old when saturated
    wire [15:0] dlo = 16'h8000 - hf;
    wire [11:0] dn = hi_sat ? dhi[11:0] : lo_sat ? dlo[11:0] : d6;
    wire        wr = g6 && ok6 && !clear_i;
    integer si;
    always @(posedge clk) begin
        pushed <= v6;
        if (v6) begin
            for (si = D - 1; si > 0; si = si - 1) begin
                hw[si] <= hw[si-1] && !clear_i;
                hb[si] <= hb[si-1];
                hh[si] <= hh[si-1];
                hd[si] <= hd[si-1];
            end
            hw[0] <= wr;
            hb[0] <= b6;
            hh[0] <= hn;
            hd[0] <= dn;
            if (g6)
                updates_o <= updates_o + 1'b1;
        end else if (clear_i) begin
            for (si = 0; si < D; si = si + 1)
                hw[si] <= 1'b0;
        end
        inflight <= inflight + {2'd0, valid_i} - {2'd0, v6};
    end
    wire unused = &{1'b0, cfull[13:0], av[19:0], y_w[7:0], dhi[15:12], dlo[15:12], 1'b0};
endmodule
`resetall
