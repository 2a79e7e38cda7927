-- abgen: paced A/B quadrature output that follows the position count (VHDL edition of
-- rtl/abgen.v, which describes it in full, as does its model sim/model/abgen.py).
--
-- pos_o chases target_i by one count per edge, at least sep_i clocks (0 as 1) between
-- two A/B edges, the short way round modulo 2^COUNT_W; the pins show pos_o's quadrant
-- (finequad_util_pkg.to_ab), so one pin changes per step. backlog_o and ovf_o describe
-- the distance d = target_i - pos_o of the edge before; z_o is high while the pins show
-- z_at_i, armed by z_en_i. rst (sync): pos 0, A = B = 1, the flags and Z 0, the first
-- step allowed on the next edge. Latency 1: target_i on edge e can move pos_o after e.
-- Formats: target_i, pos_o, z_at_i s(COUNT_W).0 counts (x4 units); sep_i u8 clocks;
-- bound_i u16 counts; backlog_o s16.0 counts, saturated. Power-up values are those
-- after rst.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;

entity abgen is
  generic (
    -- counter width (wraps), >= 17
    COUNT_W : integer range 17 to integer'high := 32;
    -- 1: sep_i, bound_i are registers; 0: constants (finequad_core OPT_TUNABLE = 0),
    -- compared bit by bit, which synthesis folds into a few LUTs
    OPT_TUNABLE : integer range 0 to 1 := 1
  );
  port (
    clk          : in    std_logic;
    rst          : in    std_logic;                    -- sync, active high
    target_i     : in    signed(COUNT_W - 1 downto 0); -- s(COUNT_W).0 counts
    sep_i        : in    unsigned(7 downto 0);         -- u8 min clocks between edges
    bound_i      : in    unsigned(15 downto 0);        -- u16 counts, bound for ovf_o
    a_o          : out   std_logic;
    b_o          : out   std_logic;
    pos_o        : out   signed(COUNT_W - 1 downto 0); -- s(COUNT_W).0 counts
    backlog_o    : out   signed(15 downto 0);          -- s16.0 sat(target - pos)
    ovf_o        : out   std_logic;                    -- |target - pos| > bound
    ovf_sticky_o : out   std_logic;                    -- ovf_o seen since rst
    z_en_i       : in    std_logic;                    -- Z armed (rtl/refmark.v)
    z_at_i       : in    signed(COUNT_W - 1 downto 0); -- s(COUNT_W).0 the count Z marks
    z_o          : out   std_logic                     -- the pins at z_at_i, armed
  );
end entity abgen;

architecture rtl of abgen is

  subtype count_t is signed(COUNT_W - 1 downto 0);

  constant CNT_MAX : unsigned(7 downto 0) := x"FF";

  -- The registered state.
  signal pos        : count_t               := (others => '0');
  signal pins       : ab_t                  := (a => '1', b => '1');
  signal cnt        : unsigned(7 downto 0)  := CNT_MAX;     -- clocks since the last edge
  signal d_q        : count_t               := (others => '0');
  signal bound_q    : unsigned(15 downto 0) := (others => '0');
  signal backlog    : signed(15 downto 0)   := (others => '0');
  signal ovf        : std_logic             := '0';
  signal ovf_sticky : std_logic             := '0';
  signal z          : std_logic             := '0';

  -- d = target - pos (modular); neg its sign; a step toward the target
  signal d     : count_t;
  signal neg   : std_logic;
  signal step  : boolean;
  signal pos_n : count_t;
  signal ovf_n : std_logic;
  signal ze    : count_t;
  signal z_n   : std_logic;

begin

  d   <= target_i - pos;
  neg <= d(COUNT_W - 1);

  -- the target differs (an equality tree beside the subtraction) and the pacing allows
  step <= target_i /= pos and cnt >= sep_i when OPT_TUNABLE = 1 else
          target_i /= pos and geu(cnt, sep_i);

  -- pos + 1 or pos - 1 in one carry chain behind d's sign
  -- (one adder of +1 or -1: "01" or "11" sign-extended; a choice between pos - 1 and
  -- pos + 1 would be two)
  pos_n <= pos + resize(signed'(neg & '1'), COUNT_W);

  -- |d| > bound from d registered (one edge later: the subtraction and the comparison in
  -- one clock were the UP5K's critical path). With m = d xor its sign (d when d >= 0,
  -- |d| - 1 when d < 0): d >= 0: m > bound, d < 0: m >= bound.
  overflow : process (all) is

    variable m    : unsigned(COUNT_W - 1 downto 0);
    variable high : boolean;                            -- m >= 2^16
    variable cmp  : unsigned(16 downto 0);

  begin

    m    := unsigned(d_q) xor (m'range => d_q(COUNT_W - 1));
    high := m(COUNT_W - 1 downto 16) /= 0;

    if OPT_TUNABLE = 1 then
      -- the carry of m + not bound (+ 1 when d < 0)
      cmp   := ('0' & m(15 downto 0)) + ('0' & not bound_q) + d_q(COUNT_W - 1);
      ovf_n <= to_sl(high or cmp(16) = '1');
    elsif d_q(COUNT_W - 1) = '1' then
      ovf_n <= to_sl(high or geu(m(15 downto 0), bound_q));
    else
      ovf_n <= to_sl(high or geu(m(15 downto 0), ('0' & bound_q) + 1));
    end if;

  end process overflow;

  -- Z: the position after this edge is pos + sign(d) on a step, else pos; ze = z_at -
  -- pos beside d, so the choice waits only for d's sign (as pos_n does)
  ze  <= z_at_i - pos;
  z_n <= z_en_i and to_sl(ze = -1) when step and neg = '1' else
         z_en_i and to_sl(ze = 1) when step else
         z_en_i and to_sl(ze = 0);

  regs : process (clk) is
  begin

    if rising_edge(clk) then
      if step then
        pos  <= pos_n;
        pins <= to_ab(unsigned(pos_n(1 downto 0)));
        cnt  <= to_unsigned(1, cnt'length);
      elsif cnt /= CNT_MAX then
        cnt <= cnt + 1;
      end if;

      d_q        <= d;
      bound_q    <= bound_i;
      backlog    <= saturate(d_q, 16);
      ovf        <= ovf_n;
      ovf_sticky <= ovf_sticky or ovf_n;
      z          <= z_n;

      if rst = '1' then
        pos        <= (others => '0');
        pins       <= (a => '1', b => '1');
        cnt        <= CNT_MAX;
        d_q        <= (others => '0');
        backlog    <= (others => '0');
        ovf        <= '0';
        ovf_sticky <= '0';
        z          <= '0';
      end if;
    end if;

  end process regs;

  a_o          <= pins.a;
  b_o          <= pins.b;
  pos_o        <= pos;
  backlog_o    <= backlog;
  ovf_o        <= ovf;
  ovf_sticky_o <= ovf_sticky;
  z_o          <= z;

end architecture rtl;
