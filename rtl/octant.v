`timescale 1ns / 1ps
`default_nettype none
// octant: Table 2 of the paper. The octant comes from the signs of u1c, u2c and the
// comparison of their magnitudes (as the paper, for both tables); the table address from
// the magnitudes. Mirrors sim/model/fastpath.py octant() and ratio().
//   TABLE_EXACT = 1: the ratio t = |small| / |large| in [0, 1], the tangent of the
//     octant-local angle (so both signals contribute: the angle noise is sigma/A at every
//     angle, the Cramer-Rao bound, where the small signal alone gives sigma/(A cos a));
//     the phase table holds atan. No divider: a reciprocal of the normalised |large| from
//     a 512-word table (2 block RAMs), one multiply |small| * recip (a DSP block).
//   TABLE_EXACT = 0: the smaller magnitude, linear (Eq. 10), bit for bit the paper's.
// Latency 3: inputs registered on edge e; valid_o, oct2_o, neg_o registered on edge e+2,
// j_o formed combinationally from registers of edge e+2 (TABLE_EXACT = 1: the rounding
// add and the clip on the product; it feeds the phase table's address in lut.v
// directly) or a register of edge e+2 (TABLE_EXACT = 0).
//   +1 ax, ay  u15   |u1c|, |u2c| in s2.14 units, saturated (|-32768| -> 32767)
//      low     u1    ay <= ax: octants 0, 3, 4, 7; small = low ? ay : ax, large the other
//      zx, zy  u4    leading zeros in 15 bits (0..14; 14 for 0) of the one's complement
//                    magnitude (u1c < 0 ? ~u1c : u1c), formed beside the negation's carry
//                    chain: lzc(ax), or lzc(ax) + 1 when u1c = -2**p (|u1c| - 1 = 2**p - 1)
//   +2 zl      u4    zx or zy of the large magnitude (combinational)
//      jp      u11   paper address min(2047, (small + 4) >> 3): small in steps of 1/2048
//      ln      u16   large << zl: in [2**14, 2**15), or exactly 2**15 (the case above)
//      rcp     u0.14 RECIP[ln[15] ? 511 : ln[13:5]] ~ 2**14 / m, m = ln / 2**14 in [1, 2]
//                    (m = 2 takes the last bin, 1/1.999); always in [2**13, 2**14)
//                    (recip.hex, sim/model/tables.py)
//      sn      u14   min(2**14 - 1, (small << zl) >> 1): small on the normalised scale,
//                    t = 2 sn / ln
//   +3 p       u28   sn * rcp = t * 2**27 (1 + O(2**-10)), below 2**28 for every input
//      j_o     u11   min(2047, (p + 2**15) >> 16) = round(2048 t), clipped
//      oct2    u2    base phase oct2 * 2048 (u13 units, 8192 per period)
//      neg     u1    phase = base - PH[j] (else base + PH[j])
// Ties |u1c| == |u2c| take the low octant (t = 1, PH = 1024: the same phase either way).
module octant #(
    parameter TABLE_DIR = "rtl/tables/",
    parameter [0:0] TABLE_EXACT = 1'b1
) (
    input  wire               clk,
    input  wire               valid_i,
    input  wire signed [15:0] u1c_i,   // s2.14
    input  wire signed [15:0] u2c_i,   // s2.14
    output reg                valid_o,
    output wire [10:0]        j_o,
    output reg  [1:0]         oct2_o,
    output reg                neg_o
);
    reg [13:0] rcp_rom [0:511];
    initial
        $readmemh({TABLE_DIR, "recip.hex"}, rcp_rom);

    function [3:0] lzc15;               // leading zeros in 15 bits, 14 for 0
        input [14:0] v;
        integer b;
        begin
            lzc15 = 4'd14;
            for (b = 0; b < 15; b = b + 1)
                if (v[b])
                    lzc15 = 4'd14 - b[3:0];
        end
    endfunction

    // +1: magnitudes (saturated to 15 bits), their comparison, signs, leading zeros
    wire [15:0] ax_f = u1c_i[15] ? -u1c_i : u1c_i;
    wire [15:0] ay_f = u2c_i[15] ? -u2c_i : u2c_i;
    wire [14:0] ax_s = ax_f[15] ? 15'h7fff : ax_f[14:0];
    wire [14:0] ay_s = ay_f[15] ? 15'h7fff : ay_f[14:0];
    wire [14:0] ox = u1c_i[14:0] ^ {15{u1c_i[15]}};    // one's complement magnitude
    wire [14:0] oy = u2c_i[14:0] ^ {15{u2c_i[15]}};
    // ay_s <= ax_s without waiting for the saturation: sat(b) <= sat(a) exactly when
    // b <= a or a >= 32767 (u1c in {32767, -32767, -32768}, decoded from the input)
    wire        xbig = (u1c_i == 16'sh7fff) || (u1c_i == -16'sh7fff) || (u1c_i == -16'sh8000);
    wire [16:0] dxy = {1'b0, ax_f} - {1'b0, ay_f};       // sign: ay_f > ax_f
    reg  [14:0] ax = 0, ay = 0;
    reg  [3:0]  zx = 0, zy = 0;
    reg         low = 1'b0;         // |u2c| <= |u1c|: octants 0, 3, 4, 7
    reg         xn = 1'b0, yn = 1'b0, v1 = 1'b0;
    always @(posedge clk) begin
        ax  <= ax_s;
        ay  <= ay_s;
        low <= !dxy[16] || xbig;
        zx  <= lzc15(ox);
        zy  <= lzc15(oy);
        xn  <= u1c_i[15];
        yn  <= u2c_i[15];
        v1  <= valid_i;
    end

    // +2: octant; paper address; reciprocal look-up and the normalised small magnitude
    wire [14:0] sm = low ? ay : ax;     // small
    wire [14:0] lg = low ? ax : ay;     // large
    wire [3:0]  zl = low ? zx : zy;
    wire [15:0] jq = ({1'b0, sm} + 16'd4) >> 3;
    wire [15:0] ln = {1'b0, lg} << zl;  // [2**14, 2**15] unless 0
    wire [15:0] ns = {1'b0, sm} << zl;  // <= ln
    wire [8:0]  ridx = ln[15] ? 9'h1ff : ln[13:5];
    reg  [13:0] rcp = 0;
    reg  [13:0] sn = 0;
    reg  [10:0] jp = 0;
    reg  [1:0]  oct2_q = 0;
    reg         neg_q = 1'b0, v2 = 1'b0;
    always @(posedge clk) begin
        rcp    <= rcp_rom[ridx];
        sn     <= ns[15] ? 14'h3fff : ns[14:1];
        jp     <= (jq[15:11] != 5'd0) ? 11'd2047 : jq[10:0];
        oct2_q <= low ? (xn ? 2'd2 : 2'd0) : (yn ? 2'd3 : 2'd1);
        neg_q  <= low ? (xn ^ yn) : !(xn ^ yn);
        v2     <= v1;
    end

    // +3: p = sn * rcp, the full u28 product (one DSP block: the counter's step multiply
    // is shift-and-add in logic, so the octant's wider one gets the multiplier)
    reg [27:0] p = 0;
    reg [10:0] jp_q = 0;
    always @(posedge clk) begin
        p       <= sn * rcp;
        jp_q    <= jp;
        oct2_o  <= oct2_q;
        neg_o   <= neg_q;
        valid_o <= v2;
    end
    // j: round to 1/2048 and clip at 2047 (t >= 2047.5 / 2048)
    wire [28:0] psum = {1'b0, p} + 29'h8000;
    wire [10:0] jr = (psum[28:27] != 2'b00) ? 11'd2047 : psum[26:16];
    assign j_o = TABLE_EXACT ? jr : jp_q;

    initial begin
        valid_o = 1'b0; oct2_o = 0; neg_o = 1'b0;
    end
    wire unused = &{1'b0, psum[15:0], ln[14], ln[4:0], ns[0], dxy[15:0], 1'b0};
endmodule
`resetall
