-- octant: Table 2 of the paper, the octant and the phase-table address from the corrected
-- magnitudes and signs (VHDL edition of rtl/octant.v, which gives the design reasoning;
-- model sim/model/octant.py octant(), ratio() and scale()).
--
--   TABLE_EXACT = 1: j = round(2048 |small| / |large|) through a reciprocal of the
--     normalised |large| (recip.hex, 512 words) and one multiply; the table holds atan.
--   TABLE_EXACT = 0: j = min(2047, (|small| + 4) >> 3), the paper's linear address.
-- Timing, inputs registered on edge e (t + 2 in the core):
--   e+1  valid_o, oct2_o (base phase 2048 oct2), neg_o (phase = base - PH[j]); inside:
--        rcp (u0.14 RECIP[ln(13 downto 5)], ln = large << zl), sn (u14 (small << zl) >> 1),
--        jp (u11 the paper's address)
--   e+2  rcp_q, sn_q (the multiply's operand registers; with OPT_ECP5_MULT the DSP
--        block's own), jp_q
--   e+3  combinational from e+2: p = sn_q rcp_q (u28 = t 2**27), j_o (u11), t_o (u12
--        the address's scale: exact min(4095, floor(p / 2**15)), paper 2 jp)
-- The stages' registers take a sample only with its valid bit (a clock enable); no reset.
-- Power-up values 0.
-- OPT_ECP5_MULT = 1 instantiates the ECP5 MULT18X18D (finequad_util_pkg) in simulation
-- as in synthesis (VHDL has no `SYNTHESIS` define): a simulation binds it to a model of
-- the primitive (cocotb_tests/sim_mult18x18d.vhd). rtl/octant.v simulates the inferred
-- form instead; the ports behave the same.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;

entity octant is
  generic (
    TABLE_DIR : string := "rtl/tables/";
    -- 1: ratio address (atan table); 0: the paper's linear address
    TABLE_EXACT : integer range 0 to 1 := 1;
    -- 1: the ratio multiply in an ECP5 MULT18X18D whose input registers hold rcp_q and
    -- sn_q; 0: inferred (any device)
    OPT_ECP5_MULT : integer range 0 to 1 := 0
  );
  port (
    clk     : in    std_logic;
    valid_i : in    std_logic;
    ax_i    : in    unsigned(14 downto 0); -- u15 |u1c|, s2.14 units
    ay_i    : in    unsigned(14 downto 0); -- u15 |u2c|
    xn_i    : in    std_logic;             -- u1c < 0
    yn_i    : in    std_logic;             -- u2c < 0
    zl_i    : in    unsigned(3 downto 0);  -- u4 lzc15(ax_i | ay_i) (rtl/correct.v)
    valid_o : out   std_logic;             -- e+1
    j_o     : out   unsigned(10 downto 0); -- u11 phase-table address (e+3, comb.)
    t_o     : out   unsigned(11 downto 0); -- u12 its scale (e+3, comb.)
    oct2_o  : out   unsigned(1 downto 0);  -- u2 base phase 2048 oct2 (e+1)
    neg_o   : out   std_logic              -- phase = base - PH[j] (e+1)
  );
end entity octant;

architecture rtl of octant is

  subtype mag_t is unsigned(14 downto 0);

  subtype u14_t is unsigned(13 downto 0);

  subtype u11_t is unsigned(10 downto 0);

  -- the reciprocal table: RECIP[i] ~ 2**14 / (1 + i / 512), u0.14
  constant RCP_ROM : hex_table_t := read_hex(TABLE_DIR & "recip.hex", 512, 14);

  -- One normalising shift (zl) for both magnitudes; the comparison low = |u2c| <= |u1c|
  -- beside it only selects, by AND-OR (a multiplexer would let synthesis put the shifters
  -- behind the comparison): large << zl, or small << zl for want_small.
  function norm (
    ax         : mag_t;
    ay         : mag_t;
    zl         : unsigned(3 downto 0);
    want_small : std_logic
  ) return mag_t is

    variable sel : mag_t;

  begin

    sel := (others => to_sl(ay <= ax) xor want_small);
    return (shift_left(ax, to_integer(zl)) and sel)
           or (shift_left(ay, to_integer(zl)) and not sel);

  end function norm;

  -- the paper's address min(2047, (|small| + 4) >> 3)
  function paddr (ax : mag_t; ay : mag_t) return u11_t is

    variable jq : unsigned(15 downto 0);

  begin

    if ay <= ax then
      jq := shift_right(resize(ay, 16) + 4, 3);
    else
      jq := shift_right(resize(ax, 16) + 4, 3);
    end if;

    if jq(15 downto 11) /= 0 then
      return (others => '1');
    end if;

    return jq(10 downto 0);

  end function paddr;

  -- ---- e+1 ---------------------------------------------------------------------------------
  signal ln     : mag_t;                                   -- the reciprocal's address
  signal v1     : std_logic            := '0';
  signal rcp    : u14_t                := (others => '0'); -- u0.14
  signal sn     : u14_t                := (others => '0'); -- u14
  signal jp     : u11_t                := (others => '0');
  signal oct2_q : unsigned(1 downto 0) := (others => '0');
  signal neg_q  : std_logic            := '0';

  -- ---- e+2 ---------------------------------------------------------------------------------
  signal jp_q : u11_t := (others => '0');

  -- ---- e+3 (combinational) -----------------------------------------------------------------
  signal p    : unsigned(27 downto 0); -- u28 sn_q * rcp_q
  signal psum : unsigned(28 downto 0);
  signal jr   : u11_t;

begin

  ln <= norm(ax_i, ay_i, zl_i, '0');

  stage_e1 : process (clk) is

    variable low : boolean;
    variable ns  : mag_t;

  begin

    if rising_edge(clk) then
      if valid_i = '1' then
        low := ay_i <= ax_i;
        ns  := norm(ax_i, ay_i, zl_i, '1');

        rcp <= unsigned(RCP_ROM(to_integer(ln(13 downto 5))));
        sn  <= ns(14 downto 1);
        jp  <= paddr(ax_i, ay_i);

        if low then
          oct2_q <= xn_i & '0';
          neg_q  <= xn_i xor yn_i;
        else
          oct2_q <= yn_i & '1';
          neg_q  <= not (xn_i xor yn_i);
        end if;
      end if;

      v1 <= valid_i;
    end if;

  end process stage_e1;

  stage_e2 : process (clk) is
  begin

    if rising_edge(clk) then
      if v1 = '1' then
        jp_q <= jp;
      end if;
    end if;

  end process stage_e2;

  -- the ratio p = sn_q rcp_q: the operand registers and the multiply inferred

  g_mult : if OPT_ECP5_MULT = 0 generate

    signal rcp_q : u14_t := (others => '0'); -- u0.14 rcp
    signal sn_q  : u14_t := (others => '0'); -- u14 sn

  begin

    operands : process (clk) is
    begin

      if rising_edge(clk) then
        if v1 = '1' then
          rcp_q <= rcp;
          sn_q  <= sn;
        end if;
      end if;

    end process operands;

    p <= sn_q * rcp_q;

  end generate g_mult;

  -- or in an ECP5 MULT18X18D: rcp_q and sn_q in its input registers A and B (CLK0 = clk,
  -- CE0 = v1), unsigned, no output or pipeline register

  g_mult18 : if OPT_ECP5_MULT = 1 generate

    signal mult_a  : std_logic_vector(17 downto 0);
    signal mult_b  : std_logic_vector(17 downto 0);
    signal mult_c  : std_logic_vector(17 downto 0);
    signal mult_ce : std_logic;
    signal mult_p  : std_logic_vector(35 downto 0);

  begin

    mult_a  <= std_logic_vector(resize(rcp, 18));
    mult_b  <= std_logic_vector(resize(sn, 18));
    mult_c  <= (others => '0');
    mult_ce <= v1;

    u_mult : component mult18x18d
      generic map (
        reg_inputa_clk => "CLK0",
        reg_inputa_ce  => "CE0",
        reg_inputa_rst => "RST0",
        reg_inputb_clk => "CLK0",
        reg_inputb_ce  => "CE0",
        reg_inputb_rst => "RST0"
      )
      port map (
        a17     => mult_a(17),
        a16     => mult_a(16),
        a15     => mult_a(15),
        a14     => mult_a(14),
        a13     => mult_a(13),
        a12     => mult_a(12),
        a11     => mult_a(11),
        a10     => mult_a(10),
        a9      => mult_a(9),
        a8      => mult_a(8),
        a7      => mult_a(7),
        a6      => mult_a(6),
        a5      => mult_a(5),
        a4      => mult_a(4),
        a3      => mult_a(3),
        a2      => mult_a(2),
        a1      => mult_a(1),
        a0      => mult_a(0),
        b17     => mult_b(17),
        b16     => mult_b(16),
        b15     => mult_b(15),
        b14     => mult_b(14),
        b13     => mult_b(13),
        b12     => mult_b(12),
        b11     => mult_b(11),
        b10     => mult_b(10),
        b9      => mult_b(9),
        b8      => mult_b(8),
        b7      => mult_b(7),
        b6      => mult_b(6),
        b5      => mult_b(5),
        b4      => mult_b(4),
        b3      => mult_b(3),
        b2      => mult_b(2),
        b1      => mult_b(1),
        b0      => mult_b(0),
        c17     => mult_c(17),
        c16     => mult_c(16),
        c15     => mult_c(15),
        c14     => mult_c(14),
        c13     => mult_c(13),
        c12     => mult_c(12),
        c11     => mult_c(11),
        c10     => mult_c(10),
        c9      => mult_c(9),
        c8      => mult_c(8),
        c7      => mult_c(7),
        c6      => mult_c(6),
        c5      => mult_c(5),
        c4      => mult_c(4),
        c3      => mult_c(3),
        c2      => mult_c(2),
        c1      => mult_c(1),
        c0      => mult_c(0),
        signeda => '0',
        signedb => '0',
        sourcea => '0',
        sourceb => '0',
        clk0    => clk,
        clk1    => '0',
        clk2    => '0',
        clk3    => '0',
        ce0     => mult_ce,
        ce1     => '0',
        ce2     => '0',
        ce3     => '0',
        rst0    => '0',
        rst1    => '0',
        rst2    => '0',
        rst3    => '0',
        p35     => mult_p(35),
        p34     => mult_p(34),
        p33     => mult_p(33),
        p32     => mult_p(32),
        p31     => mult_p(31),
        p30     => mult_p(30),
        p29     => mult_p(29),
        p28     => mult_p(28),
        p27     => mult_p(27),
        p26     => mult_p(26),
        p25     => mult_p(25),
        p24     => mult_p(24),
        p23     => mult_p(23),
        p22     => mult_p(22),
        p21     => mult_p(21),
        p20     => mult_p(20),
        p19     => mult_p(19),
        p18     => mult_p(18),
        p17     => mult_p(17),
        p16     => mult_p(16),
        p15     => mult_p(15),
        p14     => mult_p(14),
        p13     => mult_p(13),
        p12     => mult_p(12),
        p11     => mult_p(11),
        p10     => mult_p(10),
        p9      => mult_p(9),
        p8      => mult_p(8),
        p7      => mult_p(7),
        p6      => mult_p(6),
        p5      => mult_p(5),
        p4      => mult_p(4),
        p3      => mult_p(3),
        p2      => mult_p(2),
        p1      => mult_p(1),
        p0      => mult_p(0)
      );

    p <= unsigned(mult_p(27 downto 0));

  end generate g_mult18;

  -- exact: j = round(2048 t) clipped at 2047, t_o = floor(p / 2**15) clipped at 4095
  psum <= resize(p, 29) + 16#8000#;
  jr   <= (others => '1') when psum(28 downto 27) /= 0 else
          psum(26 downto 16);

  j_o <= jr when TABLE_EXACT = 1 else
         jp_q;
  t_o <= (others => '1') when TABLE_EXACT = 1 and p(27) = '1' else
         p(26 downto 15) when TABLE_EXACT = 1 else
         jp_q & '0';

  valid_o <= v1;
  oct2_o  <= oct2_q;
  neg_o   <= neg_q;

end architecture rtl;
