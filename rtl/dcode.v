`timescale 1ns / 1ps
`default_nettype none
// dcode: distance-coded reference marks (sim/model/dcode.py). The absolute position on the
// scale from the distance between two reference marks, with no multiplier and no divider.
//
// The layout (DCODE; in signal periods, A = dc_spacing, even, B = dc_coded > A, d = B - A):
// fixed marks at a_j = j A and coded marks at b_j = j A + A / 2 + d (j + 1), j = 0, 1, ..
// (A = 1000, B = 1001: marks at 0, 501, 1000, 1502, 2000, 2503, ..). Two neighbouring marks
// lie m = A / 2 + d k (a_j, b_j) or A / 2 - d k (b_j, a_(j+1)) apart, k = j + 1, and each
// such distance occurs once: so two marks crossed one after the other give k, hence where
// both lie. With e = m - A / 2 and k = |e| / d, crossing forwards (fwd):
//     e > 0: a_(k-1), b_(k-1): the second at k B - A / 2    e < 0: b_(k-1), a_k: at k A
// and crossing back:
//     e > 0: b_(k-1), a_(k-1): the second at k A - A        e < 0: a_k, b_(k-1): at k B - A / 2
// The first mark lies m before the second (after it, crossing back). A distance is valid
// when 0 < |e| < A / 2 (so m < A) and d divides e exactly; A odd or B <= A: none is.
//
// The distance. refmark.v's crossings (cross_i, one per signal period travelled over its
// reference point, +1 forwards, -1 back) are counted from the last latch: the latch's
// count dp is the signed number of signal periods between the two marks (their counts
// differ by 4 n dp exactly, both at the reference point). |dp| reaching 4095 marks the
// distance as too far (not a neighbour). dp = 0 (the same mark crossed again) decodes
// nothing and keeps the chain.
//
// The decision, when a decode ends: an invalid distance clears abs_valid and the chain's
// position (err_o). A valid one gives the second mark's position xa and the first's, fa;
// if the previous decode gave the first mark's position (ap) and fa differs, the marks
// contradict each other: err_o, abs_valid = 0, and xa is kept for the next mark to check.
// Otherwise abs_valid = 1 (with conf_i, DCODE.dc_confirm: only once two decodes in a row,
// in one direction, have agreed, or it was 1 already), ABS_COUNT = 4 n xa. A missing mark
// always gives a distance of A or more (invalid); a spurious one gives a valid distance
// by chance (with d = 1 almost every distance is valid), which the next mark contradicts;
// with conf_i no single extra mark gives a wrong position (its two distances cannot both
// agree with a real neighbour's in one direction).
//
// Events: a latch starts a decode on its edge E (refmark.v's t + 10) if a mark has been
// latched since rst or inv (the chain's start) and dp != 0; the decode ends on E + 27.
// A latch on E + 1 .. E + 27 abandons it (err_o: an overrun, the chain restarts at that
// mark); inv_i (a coast that lost the travel, an overspeed sample, an INTERP change, edge
// mode) abandons it and clears the chain and abs_valid. home_o (to refmark.v, on the decode's last edge): the
// decode leaves abs_valid 1; with homing armed the count becomes HOME + the absolute count
// (off_o), REF_COUNT HOME + ABS_COUNT, and pos_valid = 1. HOME and x are taken on E. A
// write that changes DCODE's layout is an inv_i (rtl/finequad_core.v).
//
// ABS_COUNT and REF_COUNT: REF_COUNT takes a mark on its latch (E), ABS_COUNT on the end of
// its decode (E + 27): in between they belong to two marks. The scale's length: coded
// marks exist while d (j + 1) < A / 2, so a layout covers about A^2 / (2 d) periods
// (1000 / 1001: 500 000 periods, 10 m at 20 um).
//
// Steps (st, the edge E + st; E takes dp, x and HOME): 1 m = |dp|; 2 e = m - A / 2; 3 |e|,
// the divisor and the product's factor; 4..15 restoring division of |e| by d, adding B or
// A << i to xa with each quotient bit (k B or k A); 16 xa less A / 2, 0 or A, the
// remainder's test; 17 fa; 18..26 4 n xa (shift-add over n's 9 bits); 27 the decision.
// Cost: a 13-bit distance counter, 24-bit shift registers and accumulator, a COUNT_W
// shift-add product, three COUNT_W adders (HOME - x, the offset, HOME + ABS_COUNT).
module dcode #(
    parameter COUNT_W = 32                       // 17..32
) (
    input  wire                      clk,
    input  wire                      rst,
    input  wire [11:0]               a_i,        // u12 DCODE.dc_spacing (0: off)
    input  wire [11:0]               b_i,        // u12 DCODE.dc_coded
    input  wire                      conf_i,     // DCODE.dc_confirm
    input  wire [8:0]                n_i,        // u9 n
    input  wire signed [COUNT_W-1:0] home_i,     // HOME
    // on a sample's t + 10 edge (refmark.v, registered on t + 9)
    input  wire                      cross_i,    // a reference point crossed
    input  wire                      cdir_i,     // 1: back
    input  wire                      lat_i,      // a reference latched
    input  wire signed [COUNT_W-1:0] x_i,        // its count (before the offset)
    input  wire                      inv_i,      // the count lost its scale
    output reg                       abs_valid_o,
    output reg  signed [COUNT_W-1:0] abs_o,      // ABS_COUNT
    output wire                      home_o,     // on the decode's last edge: abs_valid = 1
    output wire signed [COUNT_W-1:0] off_o,      // with home_o: HOME + ABS - x
    output wire signed [COUNT_W-1:0] ref_o,      // with home_o: HOME + ABS
    output reg                       err_o       // a pulse: REF_STICKY.dc_err
);
    // parameter check (as rtl/finequad_core.v; rtl/vhdl/dcode.vhd's range): an
    // undefined module named after the rule stops elaboration
    generate
        if (COUNT_W < 17 || COUNT_W > 32) begin : g_bad_count_w
            dcode_COUNT_W_must_be_17_to_32 u_bad ();
        end
    endgenerate
    localparam LAST = 27;

    // ---- the distance since the last latch ---------------------------------------------------
    reg  signed [12:0] dr = 13'sd0;
    reg         far = 1'b0;
    wire signed [12:0] dr_n = dr + (!cross_i ? 13'sd0 : cdir_i ? -13'sd1 : 13'sd1);
    wire        far_n = far || dr_n == 13'sd4095 || dr_n == -13'sd4095;

    // ---- the decode ----------------------------------------------------------------------------
    reg  [4:0]  st = 5'd0;
    wire        busy = st != 5'd0;
    reg         have = 1'b0, pv = 1'b0, sp = 1'b0;
    reg  [23:0] ap = 24'd0;
    reg  [12:0] m = 13'd0;
    reg  [12:0] dp = 13'd0;                      // the latch's distance (two's complement)
    reg         fwd = 1'b0, far_q = 1'b0, ok = 1'b0, selb = 1'b0;
    reg  signed [13:0] e = 14'sd0;
    reg  [12:0] rem = 13'd0;
    reg  [23:0] dsh = 24'd0, msh = 24'd0, acc = 24'd0, xa = 24'd0, fa = 24'd0;
    reg  [8:0]  nsh = 9'd0;
    reg  [COUNT_W-1:0] xsh = 0, prod = 0;
    reg  signed [COUNT_W-1:0] hx = 0, hs = 0;   // HOME - x, HOME
    wire [11:0] d = b_i - a_i;
    wire [12:0] ae = e[13] ? 13'd0 - e[12:0] : e[12:0];
    wire        ep = !e[13] && (e != 14'sd0);
    wire        ge = (dsh[23:13] == 11'd0) && (rem >= dsh[12:0]);
    wire        cons = pv && fa == ap;
    wire        fin = (st == LAST) && !lat_i && !inv_i;
    wire        good = ok && !(pv && !cons);
    wire        nv = good && (!conf_i || abs_valid_o || (pv && fwd == sp));
    wire [COUNT_W-1:0] abs_n = {prod[COUNT_W-3:0], 2'b00};
    wire [31:0] xa32 = {8'd0, xa};
    assign home_o = fin && nv;
    assign off_o = hx + abs_n;
    assign ref_o = hs + abs_n;
    always @(posedge clk) begin
        err_o <= 1'b0;
        dr <= lat_i ? 13'sd0 : dr_n;
        far <= !lat_i && far_n;
        if (busy)
            st <= (st == LAST) ? 5'd0 : st + 5'd1;
        case (st)
            5'd1: m <= dp[12] ? 13'd0 - dp : dp;
            5'd2: begin
                e <= $signed({1'b0, m}) - $signed({3'b000, a_i[11:1]});
                ok <= !far_q && !a_i[0] && (a_i != 12'd0) && (b_i > a_i) &&
                      ({1'b0, m} < {2'b00, a_i});
            end
            5'd3: begin
                rem <= ae;
                ok <= ok && (e != 14'sd0);
                selb <= (fwd == ep);
                dsh <= {1'b0, d, 11'd0};
                msh <= {1'b0, (fwd == ep) ? b_i : a_i, 11'd0};
                acc <= 24'd0;
            end
            5'd16: begin
                ok <= ok && (rem == 13'd0);
                xa <= acc - (selb ? {13'd0, a_i[11:1]} : fwd ? 24'd0 : {12'd0, a_i});
            end
            5'd17: begin
                fa <= fwd ? xa - {11'd0, m} : xa + {11'd0, m};
                prod <= 0;
                xsh <= xa32[COUNT_W-1:0];
                nsh <= n_i;
            end
            default: ;
        endcase
        if (st >= 5'd4 && st <= 5'd15) begin
            if (ge) begin
                rem <= rem - dsh[12:0];
                acc <= acc + msh;
            end
            dsh <= dsh >> 1;
            msh <= msh >> 1;
        end
        if (st >= 5'd18 && st <= 5'd26) begin
            if (nsh[0])
                prod <= prod + xsh;
            xsh <= xsh << 1;
            nsh <= nsh >> 1;
        end
        if (fin) begin
            if (!ok) begin
                err_o <= 1'b1;
                abs_valid_o <= 1'b0;
                pv <= 1'b0;
            end else begin
                if (!good) begin
                    err_o <= 1'b1;
                    abs_valid_o <= 1'b0;
                end else if (nv) begin
                    abs_valid_o <= 1'b1;
                    abs_o <= abs_n;
                end
                pv <= 1'b1;
                ap <= xa;
                sp <= fwd;
            end
        end
        if (inv_i) begin
            st <= 5'd0;
            have <= 1'b0;
            pv <= 1'b0;
            abs_valid_o <= 1'b0;
        end else if (lat_i && busy) begin
            st <= 5'd0;
            err_o <= 1'b1;
            have <= 1'b1;
            pv <= 1'b0;
            abs_valid_o <= 1'b0;
        end else if (lat_i) begin
            have <= 1'b1;
            if (have && dr_n != 13'sd0)
                st <= 5'd1;
        end
        // the latch's operands, taken on every latch not during a decode
        if (lat_i && !busy) begin
            dp <= dr_n;
            fwd <= !dr_n[12];
            far_q <= far_n;
            hx <= home_i - x_i;
            hs <= home_i;
        end
        if (rst) begin
            err_o <= 1'b0;
            dr <= 13'sd0;
            far <= 1'b0;
            st <= 5'd0;
            have <= 1'b0;
            pv <= 1'b0;
            abs_valid_o <= 1'b0;
            abs_o <= 0;
        end
    end
    initial begin
        abs_valid_o = 1'b0; abs_o = 0; err_o = 1'b0;
    end

`ifdef FORMAL
    // ---- formal properties (sim/formal/dcode.sby; every input free on every clock) ------------
    //  D1 a decode starts only on a latch, after a mark since rst / inv, with dp != 0
    //  D2 abs_valid rises only on a decode's last edge with no latch or inv on it and a valid
    //     distance; inv_i clears it, the chain and the decode
    //  D3 a decode runs its LAST steps in order: st counts 1 .. LAST from a latch, and a
    //     latch during it abandons it with err_o
    //  D4 err_o only from a decode's last edge or a latch during one
    reg f_past_valid = 1'b0;
    always @(posedge clk)
        f_past_valid <= 1'b1;
    always @(*) begin
        assert (st <= LAST);
    end
    always @(posedge clk) begin
        if (f_past_valid && !$past(rst)) begin
            if (st == 5'd1)
                assert ($past(st) == 0 && $past(lat_i) && !$past(inv_i) &&       // D1
                        $past(have) && $past(dr_n) != 13'sd0);
            if (abs_valid_o && !$past(abs_valid_o))
                assert ($past(st) == LAST && !$past(lat_i) && !$past(inv_i) &&   // D2
                        $past(ok));
            if ($past(inv_i))
                assert (!abs_valid_o && !have && !pv && st == 0);
            if ($past(st) != 0 && $past(st) != LAST && !$past(lat_i) && !$past(inv_i))
                assert (st == $past(st) + 5'd1);                                 // D3
            if ($past(st) != 0 && $past(lat_i) && !$past(inv_i))
                assert (st == 0 && err_o);
            if (err_o)
                assert ($past(st) == LAST || ($past(st) != 0 && $past(lat_i)));   // D4
        end
    end
    always @(posedge clk) begin
        if (f_past_valid && !rst) begin
            cover (home_o);                      // a decode homes
        end
    end
`endif
endmodule
`resetall
