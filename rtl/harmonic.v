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
//   phase_c_o = apply && sig ? phase - corr : phase   (u13, wraps: the counter's phase;
//                                               sig: the table is significant, below)
//   corr is not formed on its own: phase - corr = phase + ((~A + R' + 256) >> 8) (mod
//   2**13) with R' = R >>> 6; y = (~A + R' + 256) >> 8 (or 0) is registered with the
//   phase, and phase_c_o is their sum after the register (stage 3 below).
//   the observer (of pc = phase - corr, always, also while apply is off) runs on ticks,
//   in gears g = 0..GEARS: a tick ends a block of 2**g samples (every sample in gear 0);
//   the tick's decision (stage 1) reads the request the observer left for the sample six
//   arrivals before (a ring of 8 by arrival): up (locked, |M| < 2, |V| < 16 units/tick),
//   down (|V| >= 64), back to 0 (lost), only if that sample arrived after the last gear
//   change (seven arrivals or more since it).
//     meas = 32 base + (32 S >>> g) + ((V >>> 1) - (V >>> (g + 1))) >>> 8   the block's
//            mean at its last sample; base its first pc, S the sum of pc - base (s24)
//     E = wrap18(meas - P);  P += (W >>> 8) + round(E / 2^KA);  V = V' + round(E / 2^KA)
//     P u13.5 (wraps with the period), V s13.13 units/tick (wraps), E s13.5; a gear
//     change converts V' = 2V, V/2 or 0 and W = 1.5V, 0.75V or 0 (else V' = W = V);
//     KA = 2 while C < 256, else 7; C (u11, saturating at 2047) counts the ticks since
//     |E| >= 1024 units, at most 1791 after a gear change
//   Y = E * 4096 - M;  M += round(Y / 1024), 0 after a gear change   M: running mean
//   of E, s13.17 (fine enough for the |M| < 2 units gate: a dead band of 2^-8 units)
//   learning candidates: the first tick after 10..17 samples (after a candidate,
//   9 + lfsr[2:0] samples are skipped; 8-bit Galois LFSR 0xB8, seed 0xE1, stepped per
//   candidate). A candidate k learns when learn_i, C == 2047, 16 <= |V| >> 13 < 512
//   (|V| one's complement; C, V, M before this tick's update), -256 <= E >> 5 < 256, in
//   gears above 0 |M| < 2 units and |E| < 64 units, and no clear since it arrived:
//     x = sat12(X - (R >>> 7))                   X = Y >>> 12 (E minus its mean) in gear
//                                                 0, E above; minus 4 mean(A); 1/32 units
//     H = A[b] + (x >>> (mu_i + s + n))            H in 1/256 units: LMS step
//                                                 2^-(3 + mu_i + s + n), s = 0 in gear 0,
//                                                 1 in gears 1..3, 2 from gear 4; n = 1,
//                                                 2, 3 from 2048, 4096, 8192 updates
//                                                 since a clear; not made if H would
//                                                 leave s16
//   and H is written to A[b] (and R updated) when sample k + 9 arrives: the correction
//   of sample j sees the updates of the candidates <= j - 9, whatever the strobe pattern.
//   Candidates are 10 or more samples apart, so at most one update is in flight and the
//   learning view is the table itself.
//   sig = (N - |R + 8192|) > (sig ? 2**14 : 2**15), N = sum(|A|) (|x| = x ^ sign), with N
//   and R as after the commits of the samples <= k - 3: the table is shown once its mean
//   deviation exceeds 2 units (a table learned from noise alone stays below).
//
// The bin is found from the octant address's scale t_i (rtl/octant.v t_o) before the
// phase table is read (rtl/hbin.v): its two candidates b0, b1 need only t's bucket, so
// both words are read and the comparison inside the bucket (c) selects one afterwards.
//
// Timing, a = the edge on which valid_i is high (the sample's arrival; t + 4 in the core):
//   a      tick, gear and candidate decisions; commit (RAM write and R) of the
//          candidate k - 9
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
//   a + 3  the block's base and sum
//   a + 4  the block's mean (meas; its move to the block's last sample, ext, is formed
//          from V after the last tick and joins E)
//   a + 5  observer on ticks: E, P, V, C, M; the gear request (every sample)
//   a + 6  the learning error
//   a + 7  update (learn_i and mu_i sampled on this edge)
//   a + 8  new entry H (pending until sample k + 9 arrives)
// Every stage's registers take a sample only with its valid bit (a clock enable; between
// samples they hold the last one's values).
// clear_i high on edge w: R = -8192, N = 0, sig = 0, a pending update is dropped and
// those of candidates that arrived before w; the RAM is swept to zero on edges w + 1 ..
// w + 64; samples arriving on edges w .. w + 64 are not corrected and not learned from.
// The observer and M keep running. No reset input: rst of the core leaves the table as
// it is (like the estimator's theta); the registers return to learning and applying.
module harmonic #(
    // the thresholds of the bins (rtl/tables/hbin.vh): 1 exact table, 0 the paper's
    parameter [0:0] TABLE_EXACT = 1'b1,
    // 1: the table is read asynchronously from the candidates' registered addresses
    // (distributed RAM: ECP5 and the like; the read starts at flip-flops, a shorter path at
    // high clock rates); 0: read on edge a + 1 (block RAM: iCE40). Either way the
    // addresses are formed from t_i before edge a + 1. The results are the same.
    parameter [0:0] OPT_DISTRAM = 1'b0,
    // the observer's gears 0..GEARS: in gear g it sees the mean of blocks of 2**g samples
    // (GEARS = 0: every sample; the table then learns from 16 units/sample up); 0..11
    parameter integer GEARS = 11,
    // sig: the table is shown once N - |R + 8192| > SHOW and hidden again at SHOW / 2 or
    // below (2**15: a mean deviation of 2 units); 0: always shown (block tests)
    parameter integer SHOW = 32768
) (
    input  wire        clk,
    input  wire        valid_i,     // the sample's arrival (edge a)
    input  wire [1:0]  oct2_i,      // with valid_i: base phase 2048 oct2 (rtl/octant.v)
    input  wire        neg_i,       // with valid_i: phase = base - ph
    input  wire [11:0] t_i,         // combinational before edge a + 1: u12 address scale
    input  wire [11:0] ph_i,        // u12 PH[j], ~PH[j] for neg (rtl/lut.v), after a + 1
    input  wire        apply_i,     // apply the correction to phase_c_o
    input  wire        learn_i,     // update the table
    input  wire [1:0]  mu_i,        // LMS step 2^-mu in gear 0, mu = 3 + mu_i (header)
    input  wire        clear_i,     // one-clock pulse: empty the table
    output reg         valid_o = 1'b0,
    output reg  [12:0] phase_o = 13'd0,     // u13 uncorrected fine phase (edge a + 2)
    output wire [12:0] phase_c_o            // u13 corrected fine phase (edge a + 2; the
                                            // sum of two registers)
);
    localparam [22:0] R0 = -23'sd8192;
    localparam signed [21:0] SIG_ON = $signed(SHOW[21:0]);
    localparam signed [21:0] SIG_OFF = $signed(SHOW[22:1]);
    generate
        if (SHOW < 0 || SHOW >= (1 << 21)) begin : g_bad_show
            harmonic_SHOW_must_be_0_to_2097151 u_bad ();  // an elaboration error
        end
    endgenerate
    // |a| (one's complement) of an entry, and of R + 8192 = sum(A) (|sum A| < 2**21)
    function automatic [20:0] h_mag(input [15:0] a);
        h_mag = {5'd0, a ^ {16{a[15]}}};
    endfunction
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [20:0] h_smag(input [22:0] r);
        reg [22:0] sa;
        begin
            sa = r + 23'd8192;
            h_smag = sa[20:0] ^ {21{sa[22]}};
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
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
    reg  [4:0]  skip = 5'd0;
    reg  [7:0]  lfsr = 8'hE1;
    reg  [3:0]  cc = 4'd0;          // arrivals until the pending update is committed
    reg         pw = 1'b0;          // pending update valid
    reg  [15:0] hp = 16'd0;         // pending entry (zero while sweeping)
    reg  [11:0] pd = 12'd0;         // pending entry - old entry
    reg  [5:0]  lb = 6'd0;          // candidate's bin
    reg  [15:0] lha = 16'd0;        // candidate's A[b] (the entry before the update)
    reg  signed [22:0] r_sum = R0;  // R, updated with the commits and clears
    // sig: the table is shown (phase_c_o) while N - |R + 8192| > SHOW (SHOW / 2 once
    // shown); N = sum(|A|); |.| one's complement (x ^ sign). Formed in three registers clocked by
    // the arrivals: sig on the arrival of sample k sees N and R as after the commits of
    // the samples <= k - 3.
    reg  [20:0] n_sum = 21'd0;      // N (u21: 64 entries of at most 32767)
    reg  [20:0] n_q = 21'd0;        // N, |R + 8192| on the last arrival
    reg  [20:0] s_q = 21'd0;
    reg  signed [21:0] d_q = 22'sd0;    // N - |R + 8192| on the arrival before
    reg         sig = 1'b0;
    // gears: the tick schedule (the observer's samples), the gear of the next block; a
    // tick's decision reads the request the observer (stage 6) wrote for the sample 6
    // arrivals before (ring, by arrival mod 8), unless the gear changed within them
    reg  [3:0]  gear = 4'd0;        // the gear of the block being collected
    reg  [10:0] tcnt = 11'd0;       // arrivals until the next tick
    reg  [2:0]  hold = 3'd7;        // arrivals since the last gear change (saturating)
    reg  [2:0]  n1 = 3'd0;          // arrivals mod 8
    reg  [1:0]  ring [0:7];         // the observer's gear request by sample (stage 6)
    integer     ri;
    initial
        for (ri = 0; ri < 8; ri = ri + 1)
            ring[ri] = 2'd0;
    wire        tick = (tcnt == 11'd0);
    wire [2:0]  n1r = n1 + 3'd2;                         // arrival - 6, mod 8
    wire [1:0]  req = (hold == 3'd7) ? ring[n1r] : 2'd0;   // a request made after it
    wire        g_rst = (req == 2'd3) && (gear != 4'd0);
    localparam [3:0] GMAX = GEARS[3:0];
    generate
        if (GEARS < 0 || GEARS > 11) begin : g_bad
            harmonic_GEARS_must_be_0_to_11 u_bad ();     // an elaboration error
        end
    endgenerate
    wire        g_up = (req == 2'd1) && (gear < GMAX);
    wire        g_dn = (req == 2'd2) && (gear != 4'd0);
    wire [1:0]  conv = !tick ? 2'd0 : g_rst ? 2'd3 : g_up ? 2'd1 : g_dn ? 2'd2 : 2'd0;
    wire [3:0]  g_new = (conv == 2'd3) ? 4'd0 : (conv == 2'd1) ? gear + 1'b1
                      : (conv == 2'd2) ? gear - 1'b1 : gear;
    wire        cand = (skip == 5'd0) && tick;
    wire        commit = valid_i && cc == 4'd1 && pw && !clear_i;
    reg         v1 = 1'b0, cand1 = 1'b0, blk1 = 1'b0, neg1 = 1'b0, tick1 = 1'b0;
    reg  [1:0]  oct1 = 2'd0, conv1 = 2'd0;
    reg  [3:0]  gb1 = 4'd0;         // the gear of the block this sample ends or belongs to
    always @(posedge clk) begin
        v1 <= valid_i;
        if (valid_i) begin
            oct1 <= oct2_i;
            neg1 <= neg_i;
            cand1 <= cand;
            tick1 <= tick;
            conv1 <= conv;
            gb1 <= gear;
            blk1 <= clear_i || sweeping;
            n1 <= n1 + 1'b1;
            if (tick) begin
                gear <= g_new;
                tcnt <= ~(11'h7ff << g_new);
            end else
                tcnt <= tcnt - 1'b1;
            hold <= (conv != 2'd0) ? 3'd1 : (hold == 3'd7) ? hold : hold + 1'b1;
            skip <= cand ? 5'd9 + {2'd0, lfsr[2:0]} : (skip != 5'd0) ? skip - 1'b1 : skip;
            if (cand)
                lfsr <= {1'b0, lfsr[7:1]} ^ (lfsr[0] ? 8'hB8 : 8'h00);
            cc <= cand ? 4'd9 : (cc != 4'd0) ? cc - 1'b1 : 4'd0;
        end
        swp <= clear_i ? 7'd64 : sweeping ? swp - 1'b1 : 7'd0;
        if (clear_i)
            r_sum <= R0;
        else if (commit)
            r_sum <= r_sum + {{11{pd[11]}}, pd};
        if (clear_i) begin
            n_sum <= 21'd0;
            n_q <= 21'd0;
            s_q <= 21'd0;
            d_q <= 22'sd0;
            sig <= 1'b0;
        end else begin
            if (commit)
                n_sum <= n_sum + h_mag(hp) - h_mag(lha);
            if (valid_i) begin
                n_q <= n_sum;
                s_q <= h_smag(r_sum);
                d_q <= $signed({1'b0, n_q}) - $signed({1'b0, s_q});
                sig <= d_q > (sig ? SIG_OFF : SIG_ON);
            end
        end
    end

    // ---- stage 2 (edge a + 1): table reads; the constant parts of the phase sums: 256
    // (base + neg) (+ R' + 256 where the correction is used) ----------------------------------
    // a0, a1: A[b0], A[b1] as the writes on edges <= a left them (a commit writes on the
    // arrival edge of sample k + 9, a sweep on the edges after a clear):
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
    reg         v2 = 1'b0, cand2 = 1'b0, blk2 = 1'b0, ok2 = 1'b0, neg2 = 1'b0, tick2 = 1'b0;
    reg  [1:0]  conv2 = 2'd0;
    reg  [3:0]  gb2 = 4'd0;
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
    wire        uapl = ublk && apply_i && (sig || SHOW == 0);   // and applied (phase_c_o)
    reg         ub2 = 1'b0, ua2 = 1'b0;
    reg  [12:0] k0 = 13'd0;
    reg  [20:0] rq2 = 21'd0;
    always @(posedge clk) begin
        v2 <= v1;
        cand2 <= v1 && cand1;
        if (v1) begin
            tick2 <= tick1;
            conv2 <= conv1;
            gb2 <= gb1;
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
    // one arrival after the commit)
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
    reg         v3 = 1'b0, cand3 = 1'b0, lok = 1'b0, tick3 = 1'b0;
    reg  [1:0]  conv3 = 2'd0;
    reg  [3:0]  gb3 = 4'd0;
    always @(posedge clk) begin
        valid_o <= v2;
        if (v2) begin
            tick3 <= tick2;
            conv3 <= conv2;
            gb3 <= gb2;
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

    // ---- stage 4 (edge a + 3): the block's sum ----------------------------------------------
    // pc = phase + y (the corrected phase); a block's first sample (the one after a tick)
    // is its base, the others add pc - base (s13, wrapped) to S (s24: 2048 samples of at
    // most half a period)
    reg         v4 = 1'b0, cand4 = 1'b0, tick4 = 1'b0, first = 1'b1;
    reg  [1:0]  conv4 = 2'd0;
    reg  [3:0]  gb4 = 4'd0;
    reg  [12:0] base = 13'd0;
    reg  [23:0] s_sum = 24'd0;
    // S + (phase + y - base) (a function evaluated in the stage's clock enable's branch)
    function automatic [23:0] h_sum24(input [23:0] s_in, input [12:0] ph, input [12:0] y,
                                      input [12:0] b);
        reg [12:0] dd;
        begin
            dd = ph + y - b;
            h_sum24 = s_in + {{11{dd[12]}}, dd};
        end
    endfunction
    always @(posedge clk) begin
        v4 <= v3;
        cand4 <= cand3;
        if (v3) begin
            tick4 <= tick3;
            conv4 <= conv3;
            gb4 <= gb3;
            first <= tick3;
            if (first) begin
                base <= phase_o + yb;
                s_sum <= 24'd0;
            end else
                s_sum <= h_sum24(s_sum, phase_o, yb, base);
        end
    end

    // the observer's state (stage 6; V is read by stage 5 too)
    reg  [17:0] p_st = 18'd0;                   // P, u13.5
    reg  [25:0] v_st = 26'd0;                   // V, s13.13 units/tick
    reg  [10:0] c_st = 11'd0;                   // C, u11 (ticks)
    reg  [29:0] m_st = 30'd0;                   // M, s13.17: running mean of E (ticks)
    reg  [2:0]  n6 = 3'd0;                      // samples mod 8 (the ring's write index)

    // ---- stage 5 (edge a + 4): the block's mean -------------------------------------------
    // meas = 32 base + (32 S >>> gear) (u13.5, wraps): the mean phase of the block's
    // 2**gear samples (the sample itself at gear 0)
    reg         v5 = 1'b0, cand5 = 1'b0, tick5 = 1'b0;
    reg  [1:0]  conv5 = 2'd0;
    reg  [3:0]  gb5 = 4'd0;
    reg  [17:0] meas5 = 18'd0;
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [17:0] h_meas(input [12:0] b, input [23:0] s_in, input [3:0] g);
        reg [28:0] sh;
        begin
            sh = $signed({s_in, 5'd0}) >>> g;
            h_meas = {b, 5'd0} + sh[17:0];
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    always @(posedge clk) begin
        v5 <= v4;
        cand5 <= cand4;
        if (v4) begin
            tick5 <= tick4;
            conv5 <= conv4;
            gb5 <= gb4;
            meas5 <= h_meas(base, s_sum, gb4);
        end
    end

    // ---- stage 6 (edge a + 5): observer and running mean of E (on ticks); the gear request
    // (this stage's logic as functions evaluated in its clock enable's branch: simulation
    // computes it only for a sample)
    // the observer's step, round(E / 4) or round(E / 128) (the loop's gear), sign-extended:
    // E >>> 2 + E[1] or E >>> 7 + E[6] (the rounding bit joins the adders' carry)
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [15:0] obs_de(input [17:0] e, input [10:0] c);
        obs_de = (c < 11'd256) ? e[17:2] : {{5{e[17]}}, e[17:7]};
    endfunction
    function automatic obs_rb(input [17:0] e, input [10:0] c);
        obs_rb = (c < 11'd256) ? e[1] : e[6];
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
    // |V| one's complement
    function automatic [25:0] obs_av(input [25:0] v);
        obs_av = v ^ {26{v[25]}};
    endfunction
    // the lag is small: |M| < 2 units (M s13.17)
    function automatic obs_quiet(input [29:0] m);
        obs_quiet = (m[29:18] == 12'd0) || ((m[29:18] == 12'hfff) && (m[17:0] != 18'd0));
    endfunction
    // the learning window: C == 2047, 16 <= |V| >> 13 < 512, and at gears above 0
    // |M| < 2 units and |E| < 64 units
    function automatic obs_win(input [10:0] c, input [25:0] v, input [3:0] g,
                               input [29:0] m, input [17:0] e);
        reg [25:0] av;
        begin
            av = obs_av(v);
            obs_win = (c == 11'd2047) && (av[25:22] == 4'd0) && (av[21:17] != 5'd0)
                   && ((g == 4'd0) || (obs_quiet(m)
                                && ((e[17:11] == 7'd0) || (e[17:11] == 7'h7f))));
        end
    endfunction
    // the gear request as the sample finds the observer: 3 lost (C == 0), 1 up (locked,
    // |M| < 2 units, |V| < 16 units/tick), 2 down (|V| >= 64 units/tick), else 0
    function automatic [1:0] obs_req(input [10:0] c, input [29:0] m, input [25:0] v);
        reg [25:0] av;
        begin
            av = obs_av(v);
            obs_req = (c == 11'd0) ? 2'd3
                    : ((c == 11'd2047) && obs_quiet(m) && (av[25:17] == 9'd0)) ? 2'd1
                    : (av[25:19] != 7'd0) ? 2'd2 : 2'd0;
        end
    endfunction
    // the prediction's step as converted for the next block: 0 as it is, 1 doubled (the
    // next mean 1.5 V ahead), 2 halved (0.75 V ahead), 3 zeroed; w >>> 8 (mod 2**18)
    function automatic [17:0] obs_w8(input [25:0] v, input [1:0] cv);
        reg [25:0] w;
        begin
            case (cv)
                2'd1: w = v + {v[25], v[25:1]};
                2'd2: w = v - {{2{v[25]}}, v[25:2]};
                2'd3: w = 26'd0;
                default: w = v;
            endcase
            obs_w8 = w[25:8];
        end
    endfunction
    // V as converted for the next block
    function automatic [25:0] obs_vc(input [25:0] v, input [1:0] cv);
        case (cv)
            2'd1: obs_vc = {v[24:0], 1'b0};
            2'd2: obs_vc = {v[25], v[25:1]};
            2'd3: obs_vc = 26'd0;
            default: obs_vc = v;
        endcase
    endfunction
    // C: 0 when the lock is lost, else one more (saturating at 2047); at most 1791 after
    // a gear change (256 ticks of settling before learning or another shift up)
    function automatic [10:0] obs_c(input [10:0] c, input [17:0] e, input [1:0] cv);
        obs_c = obs_lost(e) ? 11'd0
              : ((cv != 2'd0) && (c >= 11'd1791)) ? 11'd1791
              : (c == 11'd2047) ? c : c + 1'b1;
    endfunction
    // Y = 4096 E - M (s31)
    function automatic [30:0] h_y(input [17:0] e, input [29:0] m);
        h_y = {e[17], e, 12'd0} - {m[29], m};
    endfunction
    // M + round(Y / 1024): Y >>> 10 + Y[9]; 0 after a gear change (the lag measured
    // afresh)
    function automatic [29:0] h_m(input [17:0] e, input [29:0] m, input [1:0] cv);
        reg [30:0] y;
        begin
            y = h_y(e, m);
            h_m = (cv != 2'd0) ? 30'd0 : m + {{9{y[30]}}, y[30:10]} + {29'd0, y[9]};
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    // ext = ((V >>> 1) - (V >>> (g + 1))) >>> 8 moves the block's mean to its last sample,
    // (D - 1) / 2 samples later (0 in gear 0): formed from the registers V and the gear of
    // the next block after every tick, so it is ready one edge before the next tick's
    // observer when that tick ends a block above gear 0 (two or more samples later)
    reg  [3:0]  g_nxt = 4'd0;                   // the gear of the block after the last tick
    reg  [17:0] ext_q = 18'd0;
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [17:0] h_ext(input [25:0] v, input [3:0] g);
        reg [25:0] vh, vg, ext;
        begin
            vh = $signed(v) >>> 1;
            vg = $signed(vh) >>> g;         // (on its own: an unsigned operand beside it
            ext = vh - vg;                  //  would make the shift logical)
            h_ext = ext[25:8];
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    always @(posedge clk)
        ext_q <= h_ext(v_st, g_nxt);
    // E = meas + ext - P (s13.5, wraps): one carry-save step (-P = ~P + 1, the 1 in the
    // carry's free bit 0), then one carry chain
    function automatic [17:0] obs_e(input [17:0] m, input [17:0] x, input [17:0] p);
        reg [17:0] ez;
        begin
            ez = ~p;
            obs_e = (m ^ x ^ ez) + {(m[16:0] & x[16:0]) | (m[16:0] & ez[16:0]) |
                                    (x[16:0] & ez[16:0]), 1'b1};
        end
    endfunction
    // (ext is used only above gear 0: a tick right after a shift down to gear 0 comes
    // before ext is formed for it)
    wire [17:0] e6w = obs_e(meas5, ext_q & {18{gb5 != 4'd0}}, p_st);
    reg         cand6 = 1'b0, tick6 = 1'b0, win6 = 1'b0, g0_6 = 1'b0, gs6 = 1'b0;
    reg  [17:0] e6 = 18'd0;
    reg  [30:0] y6 = 31'd0;
    always @(posedge clk) begin
        if (v5) begin
            ring[n6] <= obs_req(c_st, m_st, v_st);
            n6 <= n6 + 1'b1;
        end
        if (v5 && tick5) begin
            p_st <= p_st + obs_w8(v_st, conv5) + obs_de18(e6w, c_st)
                  + {17'd0, obs_rb(e6w, c_st)};
            v_st <= obs_vc(v_st, conv5) + obs_de26(e6w, c_st) + {25'd0, obs_rb(e6w, c_st)};
            c_st <= obs_c(c_st, e6w, conv5);
            m_st <= h_m(e6w, m_st, conv5);
            g_nxt <= (conv5 == 2'd3) ? 4'd0 : (conv5 == 2'd1) ? gb5 + 1'b1
                   : (conv5 == 2'd2) ? gb5 - 1'b1 : gb5;
            win6 <= obs_win(c_st, v_st, gb5, m_st, e6w);
            e6 <= e6w;
            y6 <= h_y(e6w, m_st);
            g0_6 <= (gb5 == 4'd0);
            gs6 <= (gb5 >= 4'd4);
        end
        tick6 <= v5 && tick5;
        cand6 <= cand5;
    end

    // ---- stage 7 (edge a + 6): the learning error, lock gate --------------------------------
    // Y >>> 12 (E minus its mean) at gear 0, E at the others (s19)
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [18:0] h_y5(input [30:0] y, input [17:0] e, input g0);
        h_y5 = g0 ? y[30:12] : {e[17], e};
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    reg         cand7 = 1'b0, win7 = 1'b0, lock7 = 1'b0, gs7 = 1'b0, g0_7 = 1'b0;
    reg  [18:0] y7 = 19'd0;
    always @(posedge clk) begin
        cand7 <= cand6;
        if (tick6) begin
            win7 <= win6;
            lock7 <= (e6[17:13] == 5'b00000) || (e6[17:13] == 5'b11111);
            y7 <= h_y5(y6, e6, g0_6);
            gs7 <= gs6;
            g0_7 <= g0_6;
        end
    end

    // ---- stage 8 (edge a + 7): the update ---------------------------------------------------
    // the step (X = Y - R >>> 7, s20, clamped to s12) >>> (mu_i + gshift + anneal): a
    // function evaluated in the stage's clock enable's branch
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [11:0] h_step(input [18:0] y, input [22:0] r, input [3:0] mu);
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
    reg  [11:0] d8 = 12'd0;
    reg         g8 = 1'b0, cand8 = 1'b0;
    reg  [13:0] nup = 14'd0;        // updates made since the last clear, saturating at 8192
    // the step's halvings: 1, 2, 3 from 2048, 4096, 8192 updates; by gear: 0 in gear 0,
    // 1 in gears 1..3, 2 from gear 4
    wire [1:0]  anneal = nup[13] ? 2'd3 : nup[12] ? 2'd2 : nup[11] ? 2'd1 : 2'd0;
    wire [1:0]  gshift = gs7 ? 2'd2 : g0_7 ? 2'd0 : 2'd1;
    always @(posedge clk) begin
        if (cand7)
            d8 <= h_step(y7, r_sum, {2'd0, mu_i} + {2'd0, gshift} + {2'd0, anneal});
        g8 <= cand7 && learn_i && win7 && lock7;
        cand8 <= cand7;
    end

    // ---- stage 9 (edge a + 8): new entry, pending until sample k + 9 ------------------------
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
            nup <= 14'd0;
        end else if (cand8) begin
            pw <= g8 && lok && !h_ovf(lha, d8);
            if (g8 && lok && !h_ovf(lha, d8) && !nup[13])
                nup <= nup + 1'b1;
            if (g8 && lok && !h_ovf(lha, d8)) begin
                hp <= h_entry(lha, d8);
                pd <= d8;
            end
        end
    end
    wire unused = &{1'b0, blk2, c1_unused, bin1_unused, 1'b0};
endmodule
`resetall
