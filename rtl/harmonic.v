`timescale 1ns / 1ps
`default_nettype none
// harmonic: assembles the fine phase from the octant and the phase table, with the
// adaptive compensation of its periodic error (the residual harmonic distortion of the
// encoder signals, which no ellipse correction removes). Bit-true model and the
// reasoning: sim/model/harmonic.py. No multiplier; the table in two block RAMs (two
// copies, one per read, below) or in distributed RAM (OPT_DISTRAM).
//
// Per sample, with ph = PH[j] (rtl/lut.v), phase = (2048 oct2 +- ph) mod 8192 (u13, - when
// neg), b = phase >> 7 (64 bins of 128 units), A the table (s8.8 units) and R = sum(A) -
// 8192 (s23):
//   corr    = (A[b] - (R >>> 6)) >>> 8          s10 units, round(A[b] - mean(A)); 0 for
//                                               samples arriving during a clear
//   phase_o   = phase                            (u13: the estimator's and the bins' phase)
//   phase_c_o = apply ? phase - corr : phase     (u13, wraps: the counter's phase)
//   corr is not formed on its own: phase - corr = phase + ((~A + R' + 256) >> 8) (mod
//   2**13) with R' = R >>> 6; y = (~A + R' + 256) >> 8 (or 0) is registered with the
//   phase, and phase_c_o is their sum after the register (stage 3 below).
//   observer of pc = phase - corr (always, also while apply is off):
//     E = wrap18(pc * 32 - P);  P += (V >>> 8) + (E >>> KA);  V += E * 2^(8 - KB)
//     P u13.5 (wraps with the period), V s13.13 units/sample (wraps), E s13.5;
//     (KA, KB) = (2, 10) while C < 256, else (7, 15) (both: P and V step by E >>> KA);
//     C (u11, saturating at 2047) counts the samples since |E| >= 1024 units
//   Y = E * 4 - M;  M += Y >>> 10               M: running mean of E, s13.7 (s20)
//   learning candidates: one sample in 8..15 (after a candidate, 7 + lfsr[2:0] samples
//   are skipped; 8-bit Galois LFSR 0xB8, seed 0xE1, stepped per candidate). A candidate k
//   learns when learn_i, C == 2047, 16 <= |V| >> 13 < 512 (|V| one's complement; C, V
//   before this sample's update), -256 <= E >> 5 < 256, and no clear since it arrived:
//     x = sat12((Y >>> 2) - (R >>> 7))          E minus its mean, minus 4 mean(A), in
//                                                 E's units (1/32)
//     H = A[b] + (x >>> mu_i)                      H in 1/256 units: LMS step 2^-(3 + mu_i);
//                                                 not made if H would leave s16
//   and H is written to A[b] (and R updated) when sample k + 7 arrives: the correction
//   of sample j sees the updates of the candidates <= j - 7, whatever the strobe pattern.
//   Candidates are 8 or more samples apart, so at most one update is in flight and the
//   learning view is the table itself.
//
// The bin is found from the octant address's scale t_i (rtl/octant.v t_o) before the
// phase table is read (rtl/hbin.v): its two candidates b0, b1 need only t's bucket, so
// both words are read and the comparison inside the bucket (c) selects one afterwards.
//
// Timing, a = the edge on which valid_i is high (the sample's arrival; t + 4 in the core):
//   a      candidate decision; commit (RAM write and R) of the candidate k - 7
//   a + 1  t_i registered (it is combinational before this edge, the ratio multiply's
//          result); the phase sums' constant parts registered (apply_i sampled).
//          The candidates b0, b1 are formed from t_i before this edge (rtl/hbin.v).
//          OPT_DISTRAM = 0 (block RAM, e.g. iCE40): A[b0], A[b1] read on this edge;
//          OPT_DISTRAM = 1 (distributed RAM, e.g. ECP5): b0, b1 registered on this edge
//          and the RAM read asynchronously after it from the flip-flops (no logic
//          before its address; the report's ECP5 build keeps the multiplier's operand
//          registers in its DSP block, rtl/octant.v OPT_ECP5_MULT, to make room for hbin
//          in front of the register).
//          Either way the read sees the writes on edges <= a (as if read on this edge: a
//          commit on this edge is undone by lha below).
//   a + 2  phase_o, phase_c_o, valid_o (ph_i is the phase table's output, valid after
//          a + 1); a candidate's A[b] captured
//   a + 3  observer: E, P, V, C
//   a + 4  Y, M
//   a + 5  update (learn_i and mu_i sampled on this edge)
//   a + 6  new entry H (pending until sample k + 7 arrives)
// Every stage's registers take a sample only with its valid bit (a clock enable; between
// samples they hold the last one's values).
// clear_i high on edge w: R = -8192, a pending update is dropped and so are those of
// candidates that arrived before w; the RAM is swept to zero on edges w + 1 .. w + 64;
// samples arriving on edges w .. w + 64 are not corrected and not learned from. The
// observer and M keep running. No reset input: rst of the core leaves the table as it
// is (like the estimator's theta); the registers return to learning and applying.
module harmonic #(
    // the thresholds of the bins (rtl/tables/hbin.vh): 1 exact table, 0 the paper's
    parameter [0:0] TABLE_EXACT = 1'b1,
    // 1: the table is read asynchronously from the candidates' registered addresses
    // (distributed RAM: ECP5 and the like; the read starts at flip-flops, a shorter path at
    // high clock rates); 0: read on edge a + 1 (block RAM: iCE40). Either way the
    // addresses are formed from t_i before edge a + 1. The results are the same.
    parameter [0:0] OPT_DISTRAM = 1'b0
) (
    input  wire        clk,
    input  wire        valid_i,     // the sample's arrival (edge a)
    input  wire [1:0]  oct2_i,      // with valid_i: base phase 2048 oct2 (rtl/octant.v)
    input  wire        neg_i,       // with valid_i: phase = base - ph
    input  wire [11:0] t_i,         // combinational before edge a + 1: u12 address scale
    input  wire [11:0] ph_i,        // u12 PH[j], ~PH[j] for neg (rtl/lut.v), after a + 1
    input  wire        apply_i,     // apply the correction to phase_c_o
    input  wire        learn_i,     // update the table
    input  wire [1:0]  mu_i,        // LMS step 2^-mu, mu = 3 + mu_i
    input  wire        clear_i,     // one-clock pulse: empty the table
    output reg         valid_o = 1'b0,
    output reg  [12:0] phase_o = 13'd0,     // u13 uncorrected fine phase (edge a + 2)
    output wire [12:0] phase_c_o            // u13 corrected fine phase (edge a + 2; the
                                            // sum of two registers)
);
    localparam [22:0] R0 = -23'sd8192;
    // ---- table RAM -------------------------------------------------------------------------
    // Two copies written alike, one per candidate's read (b0 from mem0, b1 from mem1): two
    // block RAMs, or distributed RAM. (One memory with two read ports whose outputs are
    // multiplexed would let synthesis merge them into one port with a multiplexed address,
    // putting the comparison that selects back in front of the read.) A read and a write
    // of the same word on one edge happen (one sample per clock); the block RAM's result is
    // then undefined (iCE40), so the read is taken as the word before the write by
    // construction (stage 3): no collision logic from synthesis.
    (* no_rw_check *)
    reg [15:0] mem0 [0:63];
    (* no_rw_check *)
    reg [15:0] mem1 [0:63];
    integer mi;
    initial
        for (mi = 0; mi < 64; mi = mi + 1) begin
            mem0[mi] = 16'd0;
            mem1[mi] = 16'd0;
        end

    // ---- stage 1 (edge a): candidates, commit, sweep ------------------------------------
    reg  [6:0]  swp = 7'd0;         // clear sweep: words left
    wire        sweeping = (swp != 7'd0);
    reg  [3:0]  skip = 4'd0;
    reg  [7:0]  lfsr = 8'hE1;
    reg  [2:0]  cc = 3'd0;          // arrivals until the pending update is committed
    reg         pw = 1'b0;          // pending update valid
    reg  [15:0] hp = 16'd0;         // pending entry (zero while sweeping)
    reg  [11:0] pd = 12'd0;         // pending entry - old entry
    reg  [5:0]  lb = 6'd0;          // candidate's bin
    reg  [15:0] lha = 16'd0;        // candidate's A[b] (the entry before the update)
    reg  signed [22:0] r_sum = R0;  // R, updated with the commits and clears
    wire        cand = (skip == 4'd0);
    wire        commit = valid_i && cc == 3'd1 && pw && !clear_i;
    reg         v1 = 1'b0, cand1 = 1'b0, blk1 = 1'b0, neg1 = 1'b0;
    reg  [1:0]  oct1 = 2'd0;
    always @(posedge clk) begin
        v1 <= valid_i;
        if (valid_i) begin
            oct1 <= oct2_i;
            neg1 <= neg_i;
            cand1 <= cand;
            blk1 <= clear_i || sweeping;
            skip <= cand ? 4'd7 + {1'b0, lfsr[2:0]} : skip - 1'b1;
            if (cand)
                lfsr <= {1'b0, lfsr[7:1]} ^ (lfsr[0] ? 8'hB8 : 8'h00);
            cc <= cand ? 3'd7 : (cc != 3'd0) ? cc - 1'b1 : 3'd0;
        end
        swp <= clear_i ? 7'd64 : sweeping ? swp - 1'b1 : 7'd0;
        if (clear_i)
            r_sum <= R0;
        else if (commit)
            r_sum <= r_sum + {{11{pd[11]}}, pd};
    end

    // ---- stage 2 (edge a + 1): table reads; the constant parts of the phase sums: 256
    // (base + neg) (+ R' + 256 where the correction is used) ----------------------------------
    // a0, a1: A[b0], A[b1] as the writes on edges <= a left them (a commit writes on the
    // arrival edge of sample k + 7, a sweep on the edges after a clear):
    //   OPT_DISTRAM = 0: read on edge a + 1, when the commit of the next sample may write
    //     the same word (the block RAM's result is then undefined): such a read is taken
    //     as the word before the write, which is lha (the candidate's entry; nothing else
    //     writes that word while its update is pending). A sweep's write may hit the read
    //     too: the samples read during a sweep are not corrected and not learned from.
    //   OPT_DISTRAM = 1: read after edge a + 1 from copies whose writes come one edge late
    //     (registered), so that they hold the writes on edges <= a: no collision logic.
    reg  [11:0] t2 = 12'd0;                     // t_i
    reg  [1:0]  oct2q = 2'd0;                   // the octant of t2
    reg         cw2 = 1'b0;                     // a commit wrote lb on the read's edge
    wire [5:0]  swa = 6'd0 - swp[5:0];          // sweep address 0, 1, .., 63
    wire [5:0]  wa = sweeping ? swa : lb;       // (a named 6-bit wire: Icarus 11 indexes
    wire        we = sweeping || commit;        //  with a wider difference otherwise)
    wire [11:0] bc1;                            // {b1, b0} from t_i (the RAM's address)
    wire        c1_unused;
    wire [5:0]  bin1_unused;
    hbin #(.TABLE_EXACT(TABLE_EXACT)) u_bin1 (
        .oct2_i(oct1), .neg_i(neg1), .t_i(t_i), .b0_o(bc1[5:0]), .b1_o(bc1[11:6]),
        .c_o(c1_unused), .bin_o(bin1_unused)
    );
    reg         v2 = 1'b0, cand2 = 1'b0, blk2 = 1'b0, ok2 = 1'b0, neg2 = 1'b0;
    wire [11:0] bc;                             // {b1, b0} of the sample read
    wire        c2;                             // t reaches its bucket's threshold
    wire [5:0]  bin2;                           // the bin: c2 ? b1 : b0
    hbin #(.TABLE_EXACT(TABLE_EXACT)) u_bin2 (
        .oct2_i(oct2q), .neg_i(neg2), .t_i(t2), .b0_o(bc[5:0]), .b1_o(bc[11:6]),
        .c_o(c2), .bin_o(bin2)
    );
    wire [15:0] a0, a1;
    always @(posedge clk) begin
        if (v1) begin
            t2 <= t_i;
            oct2q <= oct1;
        end
        cw2 <= commit && !sweeping;
    end
    generate
        if (OPT_DISTRAM) begin : g_async
            reg        we_q = 1'b0;
            reg [5:0]  wa_q = 6'd0;
            reg [15:0] hp_q = 16'd0;
            reg [11:0] bc_q = 12'd0;            // {b1, b0} from t_i, registered: the
            always @(posedge clk) begin         // RAM's address straight from flip-flops
                if (v1)
                    bc_q <= bc1;
                we_q <= we;
                wa_q <= wa;
                hp_q <= hp;
                if (we_q) begin
                    mem0[wa_q] <= hp_q;
                    mem1[wa_q] <= hp_q;
                end
            end
            assign a0 = mem0[bc_q[5:0]];
            assign a1 = mem1[bc_q[11:6]];
            wire unused_a = &{1'b0, cw2, bc, 1'b0};
        end else begin : g_sync
            reg [15:0] rd0_q = 16'd0, rd1_q = 16'd0;
            always @(posedge clk) begin
                if (we) begin
                    mem0[wa] <= hp;
                    mem1[wa] <= hp;
                end
                if (v1) begin
`ifdef SYNTHESIS
                    rd0_q <= mem0[bc1[5:0]];
                    rd1_q <= mem1[bc1[11:6]];
`else
                    // simulation: the undefined read of a word written on the same edge
                    // returns the word inverted, so that a result relying on it differs
                    // from the model
                    rd0_q <= (we && wa == bc1[5:0]) ? ~mem0[bc1[5:0]] : mem0[bc1[5:0]];
                    rd1_q <= (we && wa == bc1[11:6]) ? ~mem1[bc1[11:6]] : mem1[bc1[11:6]];
`endif
                end
            end
            assign a0 = (cw2 && lb == bc[5:0]) ? lha : rd0_q;
            assign a1 = (cw2 && lb == bc[11:6]) ? lha : rd1_q;
        end
    endgenerate
    // (base1 and rq below as functions evaluated in the stage's clock enable's branch:
    // simulation computes them only for a sample)
    // 256 (base + neg) / 256: {oct2, 11'd0} + neg (u13)
    function automatic [12:0] h_base(input [1:0] oct, input neg);
        h_base = {oct, 11'd0} + {12'd0, neg};
    endfunction
    // R >>> 6, plus 256 (s21, R s23)
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [20:0] h_rq(input [22:0] r);
        h_rq = {{4{r[22]}}, r[22:6]} + 21'd256;
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    wire        ublk = !blk1;                          // the correction is used (pc)
    wire        uapl = ublk && apply_i;                // and applied (phase_c_o)
    reg         ub2 = 1'b0, ua2 = 1'b0;
    reg  [12:0] k0 = 13'd0;
    reg  [20:0] rq2 = 21'd0;
    always @(posedge clk) begin
        v2 <= v1;
        cand2 <= v1 && cand1;
        if (v1) begin
            blk2 <= blk1;
            ok2 <= !blk1 && !clear_i;
            neg2 <= neg1;
            k0 <= h_base(oct1, neg1);
            rq2 <= h_rq(r_sum);
            ub2 <= ublk;
            ua2 <= uapl;
        end
    end

    // ---- stage 3 (edge a + 2): the phases; a candidate's entry ------------------------------
    // phase - corr = phase - floor((A - R') / 256), R' = R >>> 6, is
    // floor((256 phase + ~A + R' + 256) / 256) = phase + y mod 2**13 with
    // y = (~A + R' + 256) >> 8 (mod 2**13; the low 8 bits of 256 phase are 0). Where the
    // correction is not used (pc) or not applied (phase_c_o), y is 0. y is formed from the
    // table's word while the phase table is read and registered with the phase; the sums
    // come after the registers (phase_c_o, pc3), so the phase table's output only meets
    // one 13-bit carry chain and the table's word one 21-bit chain before a register.
    // (lb is the committed word's address until the next candidate's stage 3, at least
    // eight arrivals after the commit)
    wire [15:0] rd_q = c2 ? a1 : a0;                     // A[b]
    // ~A (sign-extended) + R' + 256 for both candidates; c selects the sum and u gates it
    // (y, u13, or 0 where the correction is not used; a function evaluated in the stage's
    // clock enable's branch, like the phase's sum). The selection is an AND-OR behind both
    // adders, one LUT with the gate: a multiplexer would let synthesis share the two
    // adders behind a multiplexer of the words (ECP5: one more LUT level on the path from
    // the distributed RAM)
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [12:0] h_ysum(input [15:0] w0, input [15:0] w1, input c, input u,
                                     input [20:0] rq);
        reg [20:0] ys0, ys1;
        begin
            ys0 = ~{{5{w0[15]}}, w0} + rq;
            ys1 = ~{{5{w1[15]}}, w1} + rq;
            h_ysum = (ys1[20:8] & {13{c & u}}) | (ys0[20:8] & {13{!c & u}});
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    // 256 (base + neg) / 256 + ph, or - ph - 1 (neg): the uncorrected phase (u13, wraps);
    // the table gives ~ph for neg (rtl/lut.v), so - ph - 1 = {1, ~ph} is a concatenation
    function automatic [12:0] h_ph(input [12:0] k, input [11:0] ph, input neg);
        h_ph = k + {neg, ph};
    endfunction
    reg  [12:0] ya = 13'd0, yb = 13'd0;                 // y applied (phase_c_o), used (pc)
    reg         v3 = 1'b0, cand3 = 1'b0, lok = 1'b0;
    always @(posedge clk) begin
        valid_o <= v2;
        if (v2) begin
            phase_o <= h_ph(k0, ph_i, neg2);
            ya <= h_ysum(a0, a1, c2, ua2, rq2);
            yb <= h_ysum(a0, a1, c2, ub2, rq2);
        end
        v3 <= v2;
        cand3 <= v2 && cand2;
        if (v2 && cand2) begin
            lb <= bin2;
            lha <= rd_q;
            lok <= ok2 && !clear_i;
        end else if (clear_i)
            lok <= 1'b0;
    end
    assign phase_c_o = phase_o + ya;

    // ---- stage 4 (edge a + 3): observer -----------------------------------------------------
    reg  [17:0] p_st = 18'd0;                   // P, u13.5
    reg  [25:0] v_st = 26'd0;                   // V, s13.13
    reg  [10:0] c_st = 11'd0;                   // C, u11
    // (this stage's logic as functions evaluated in its clock enable's branch: simulation
    // computes it only for a sample)
    // E = 32 (phase + y) - P (s13.5, wraps): one carry-save step (-P = ~P + 1, the 1 in the
    // carry's free bit 0), then one carry chain
    function automatic [17:0] obs_e(input [12:0] ph, input [12:0] y, input [17:0] p);
        reg [17:0] ex, ey, ez;
        begin
            ex = {ph, 5'd0};
            ey = {y, 5'd0};
            ez = ~p;
            obs_e = (ex ^ ey ^ ez) + {(ex[16:0] & ey[16:0]) | (ex[16:0] & ez[16:0]) |
                                      (ey[16:0] & ez[16:0]), 1'b1};
        end
    endfunction
    // the observer's step, E >>> 2 or E >>> 7 (the gear), sign-extended to 26 bits
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [15:0] obs_de(input [17:0] e, input [10:0] c);
        obs_de = (c < 11'd256) ? e[17:2] : {{5{e[17]}}, e[17:7]};
    endfunction
    function automatic [17:0] obs_de18(input [17:0] e, input [10:0] c);
        reg [15:0] de;
        begin
            de = obs_de(e, c);
            obs_de18 = {{2{de[15]}}, de};
        end
    endfunction
    function automatic [25:0] obs_de26(input [17:0] e, input [10:0] c);
        reg [15:0] de;
        begin
            de = obs_de(e, c);
            obs_de26 = {{10{de[15]}}, de};
        end
    endfunction
    // the lock is lost: |E| >= 1024 units
    function automatic obs_lost(input [17:0] e);
        obs_lost = !((e[17:15] == 3'b000) || (e[17:15] == 3'b111));
    endfunction
    // the learning window: C == 2047 and 16 <= |V| >> 13 < 512 (|V| one's complement)
    function automatic obs_win(input [10:0] c, input [25:0] v);
        reg [25:0] av;
        begin
            av = v ^ {26{v[25]}};
            obs_win = (c == 11'd2047) && (av[25:22] == 4'd0) && (av[21:17] != 5'd0);
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    reg         v4 = 1'b0, cand4 = 1'b0, win4 = 1'b0;
    reg  [17:0] e4 = 18'd0;
    always @(posedge clk) begin
        if (v3) begin
            p_st <= p_st + v_st[25:8] + obs_de18(obs_e(phase_o, yb, p_st), c_st);
            v_st <= v_st + obs_de26(obs_e(phase_o, yb, p_st), c_st);
            c_st <= obs_lost(obs_e(phase_o, yb, p_st)) ? 11'd0
                  : (c_st == 11'd2047) ? c_st : c_st + 1'b1;
            win4 <= obs_win(c_st, v_st);
            e4 <= obs_e(phase_o, yb, p_st);
        end
        v4 <= v3;
        cand4 <= cand3;
    end

    // ---- stage 5 (edge a + 4): running mean of E, lock gate ---------------------------------
    reg  [19:0] m_st = 20'd0;                   // M, s13.7
    // Y = 4 E - M (s21), a function evaluated in the stage's clock enable's branch
    function automatic [20:0] h_y(input [17:0] e, input [19:0] m);
        h_y = {e[17], e, 2'd0} - {m[19], m};
    endfunction
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [19:0] h_m(input [17:0] e, input [19:0] m);   // M + Y >>> 10
        reg [20:0] y;
        begin
            y = h_y(e, m);
            h_m = m + {{9{y[20]}}, y[20:10]};
        end
    endfunction
    function automatic [18:0] h_y5(input [17:0] e, input [19:0] m);  // Y >>> 2
        reg [20:0] y;
        begin
            y = h_y(e, m);
            h_y5 = y[20:2];
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    reg         cand5 = 1'b0, win5 = 1'b0, lock5 = 1'b0;
    reg  [18:0] y5 = 19'd0;                     // Y >>> 2, s19
    always @(posedge clk) begin
        cand5 <= cand4;
        if (v4) begin
            m_st <= h_m(e4, m_st);
            win5 <= win4;
            lock5 <= (e4[17:13] == 5'b00000) || (e4[17:13] == 5'b11111);
            y5 <= h_y5(e4, m_st);
        end
    end

    // ---- stage 6 (edge a + 5): the update ---------------------------------------------------
    // the step (X = Y - R >>> 7, s20, clamped to s12) >>> mu: a function evaluated in the
    // stage's clock enable's branch
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [11:0] h_step(input [18:0] y, input [22:0] r, input [1:0] mu);
        reg [19:0] x_w;
        reg        x_hi, x_lo;
        reg signed [11:0] xc;
        begin
            x_w = {y[18], y} - {{4{r[22]}}, r[22:7]};
            x_hi = !x_w[19] && (x_w[18:11] != 8'd0);
            x_lo = x_w[19] && (x_w[18:11] != 8'hff);
            xc = x_hi ? 12'sh7ff : x_lo ? -12'sh800 : $signed(x_w[11:0]);
            h_step = xc >>> mu;
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    reg  [11:0] d6 = 12'd0;
    reg         g6 = 1'b0, cand6 = 1'b0;
    always @(posedge clk) begin
        if (cand5)
            d6 <= h_step(y5, r_sum, mu_i);
        g6 <= cand5 && learn_i && win5 && lock5;
        cand6 <= cand5;
    end

    // ---- stage 7 (edge a + 6): new entry, pending until sample k + 7 ------------------------
    // an update that would leave s16 is not made (the entry stays at most one step short
    // of the rail)
    // the new entry A + d (s17) and whether it leaves s16: functions evaluated in the
    // stage's clock enable's branch
    function automatic [16:0] h_sum(input [15:0] a, input [11:0] d);
        h_sum = {a[15], a} + {{5{d[11]}}, d};
    endfunction
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic h_ovf(input [15:0] a, input [11:0] d);
        reg [16:0] hs;
        begin
            hs = h_sum(a, d);
            h_ovf = (hs[16] != hs[15]);
        end
    endfunction
    function automatic [15:0] h_entry(input [15:0] a, input [11:0] d);
        reg [16:0] hs;
        begin
            hs = h_sum(a, d);
            h_entry = hs[15:0];
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    always @(posedge clk) begin
        if (clear_i) begin
            pw <= 1'b0;
            hp <= 16'd0;
        end else if (cand6) begin
            pw <= g6 && lok && !h_ovf(lha, d6);
            if (g6 && lok && !h_ovf(lha, d6)) begin
                hp <= h_entry(lha, d6);
                pd <= d6;
            end
        end
    end
    wire unused = &{1'b0, blk2, c1_unused, bin1_unused, 1'b0};
endmodule
`resetall
