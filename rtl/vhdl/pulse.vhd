-- pulse: the Eq. 12 pulses, comparators with hysteresis (VHDL edition of rtl/pulse.v,
-- which gives the reasoning of both comparison forms; model sim/model/pulse.py).
--
-- A = '1' if cos(n a) >= eps, '0' if cos(n a) <= -eps, else unchanged; B likewise from
-- sin(n a). A value is a sign and a magnitude m (the sine table's word, u0.(SIN_W-1)),
-- compared in u0.15 units with eps; one unsigned comparison m >= eps decides both sides:
--   v >= eps   <=>  (not neg and m >= eps) or (m = 0 and eps = 0)
--   v <= -eps  <=>  neg and m >= eps                     (taken when not v >= eps)
-- The comparison's two forms (OPT_ADDR with OPT_TUNABLE; rtl/pulse.v):
--   the word:    m itself (cos_mag_i, sin_mag_i) against eps_i;
--   the address: the table address k (cos_k_i, sin_k_i) against the inverse threshold
--                K[E] of E = ceil(eps / 2**(16 - SIN_W)), read from eq12_k_<SIN_W>.hex
--                (SIN_W 8, 10 or 12; any other width stops elaboration).
-- A constant eps (OPT_TUNABLE = 0) is always compared in the word form.
--
-- Timing: latency 1 (valid_o, a_o, b_o after the edge that takes valid_i). eps_i is taken
-- two edges before the pulses it decides (a pulse formed on edge p compares with eps_i as
-- of edge p - 2) in both forms; a constant eps is the same on every edge.
-- Formats: cos_mag_i, sin_mag_i u0.(SIN_W-1) magnitudes; cos_k_i, sin_k_i u11 quarter-wave
-- table addresses; eps_i u0.15. rst (sync): valid_o '0', A = B = '1'. Power-up values
-- are those after rst.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;

entity pulse is
  generic (
    -- sine word width (magnitude SIN_W - 1 bits; rtl/lut.v has 8, 10, 12 and 16)
    SIN_W : integer range 2 to 16 := 10;
    -- 1: eps_i is a register; 0: a constant (finequad_core OPT_TUNABLE = 0), compared
    -- bit by bit in the word form, which synthesis folds into a few LUTs
    OPT_TUNABLE : integer range 0 to 1 := 1;
    -- the comparison's form with OPT_TUNABLE: 1 the address side (for clock rates near
    -- 100 MHz, e.g. ECP5), 0 the table's word
    OPT_ADDR : integer range 0 to 1 := 0;
    -- where eq12_k_<SIN_W>.hex is (OPT_ADDR)
    TABLE_DIR : string := "rtl/tables/"
  );
  port (
    clk       : in    std_logic;
    rst       : in    std_logic;                    -- sync, active high
    valid_i   : in    std_logic;
    cos_mag_i : in    unsigned(SIN_W - 2 downto 0); -- u0.(SIN_W-1) |cos(n a)|
    cos_neg_i : in    std_logic;
    cos_k_i   : in    unsigned(10 downto 0);        -- u11 its table address (OPT_ADDR)
    sin_mag_i : in    unsigned(SIN_W - 2 downto 0); -- u0.(SIN_W-1) |sin(n a)|
    sin_neg_i : in    std_logic;
    sin_k_i   : in    unsigned(10 downto 0);        -- u11
    eps_i     : in    unsigned(15 downto 0);        -- u0.15 hysteresis threshold
    valid_o   : out   std_logic;
    a_o       : out   std_logic;
    b_o       : out   std_logic
  );
end entity pulse;

architecture rtl of pulse is

  -- the address form (a constant eps is compared as a word)
  constant ADDR : boolean := OPT_ADDR = 1 and OPT_TUNABLE = 1;
  -- u0.(SIN_W-1) to u0.15: the shift
  constant SH : natural := 16 - SIN_W;

  -- One channel's comparison with eps: m >= eps, and m = 0.
  type cmp_t is record
    ge   : boolean;
    zero : boolean;
  end record cmp_t;

  -- The magnitude m in u0.15.
  function to_u15 (m : unsigned) return unsigned is
  begin

    return resize(m & (SH - 1 downto 0 => '0'), 16);

  end function to_u15;

  -- Eq. 12 with hysteresis for one channel: the pin after a sample of sign neg whose
  -- magnitude compares as c, with zero_eps (eps = 0).
  function hysteresis (pin : std_logic; neg : std_logic; c : cmp_t; zero_eps : boolean) return std_logic is
  begin

    if (neg = '0' and c.ge) or (zero_eps and c.zero) then
      return '1';
    elsif neg = '1' and c.ge then
      return '0';
    end if;

    return pin;

  end function hysteresis;

  signal c        : cmp_t; -- the cosine channel (A)
  signal s        : cmp_t; -- the sine channel (B)
  signal zero_eps : boolean;

  signal valid_q : std_logic := '0';
  signal a_q     : std_logic := '1';
  signal b_q     : std_logic := '1';

begin

  g_form : if ADDR generate

    -- the threshold table's rows: E = 0 .. 2**KW - 1
    constant KW : natural := SIN_W - 1;

    -- eq12_k_<SIN_W>.hex, or a failure naming the rule for a width with no table
    function k_table_name return string is
    begin

      assert SIN_W = 8 or SIN_W = 10 or SIN_W = 12
        report "pulse: OPT_ADDR needs SIN_W 8, 10 or 12 (no eq12_k table for SIN_W = "
               & integer'image(SIN_W) & ")"
        severity failure;
      return TABLE_DIR & "eq12_k_" & integer'image(SIN_W) & ".hex";

    end function k_table_name;

    -- K[E] = #{k : T[k] < E}, u12 (sim/model/tables.py eq12_k_table)
    constant KROM : hex_table_t := read_hex(k_table_name, 2 ** KW, 12);

    signal e   : unsigned(SIN_W downto 0); -- u(SIN_W+1) E = ceil(eps / 2**SH)
    signal row : unsigned(KW - 1 downto 0);

    -- for the pulses of edge p: the row of eps_i read on edge p - 2 (block RAM), the
    -- threshold K and the flags registered on edge p - 1
    signal kb    : unsigned(11 downto 0) := (others => '0');
    signal e0_1  : std_logic             := '1';
    signal far_1 : std_logic             := '0';
    signal kth   : unsigned(11 downto 0) := (others => '0');
    signal e0_2  : std_logic             := '1';

  begin

    e <= resize(eps_i(15 downto SH), SIN_W + 1) + to_sl(eps_i(SH - 1 downto 0) /= 0);

    -- E = 0 reads row 1 (K[1] tells m = 0; m >= 0 always)
    row <= to_unsigned(1, KW) when e = 0 else
           e(KW - 1 downto 0);

    threshold : process (clk) is
    begin

      if rising_edge(clk) then
        kb   <= unsigned(KROM(to_integer(row)));
        e0_1 <= to_sl(e = 0);
        -- E beyond the rows: no k reaches it
        far_1 <= to_sl(e(SIN_W downto KW) /= 0);
        e0_2  <= e0_1;

        if far_1 = '1' then
          kth <= to_unsigned(2048, 12);
        else
          kth <= kb;
        end if;
      end if;

    end process threshold;

    zero_eps <= e0_2 = '1';
    -- m >= eps <=> k >= K[E]; m = 0 <=> k < K[1] (with E = 0)
    c <= (ge => e0_2 = '1' or resize(cos_k_i, 12) >= kth, zero => resize(cos_k_i, 12) < kth);
    s <= (ge => e0_2 = '1' or resize(sin_k_i, 12) >= kth, zero => resize(sin_k_i, 12) < kth);

  else generate

    -- eps_i of edge p - 2 (a constant eps needs no delay)
    signal eps_1 : unsigned(15 downto 0) := (others => '0');
    signal eps_q : unsigned(15 downto 0) := (others => '0');
    signal eps_2 : unsigned(15 downto 0);

  begin

    eps_delay : process (clk) is
    begin

      if rising_edge(clk) then
        eps_1 <= eps_i;
        eps_q <= eps_1;
      end if;

    end process eps_delay;

    eps_2 <= eps_q when OPT_TUNABLE = 1 else
             eps_i;

    zero_eps <= eps_2 = 0;
    -- a constant eps bit by bit (geu), which folds into a few LUTs
    c <= (ge => to_u15(cos_mag_i) >= eps_2, zero => cos_mag_i = 0) when OPT_TUNABLE = 1 else
         (ge => geu(to_u15(cos_mag_i), eps_2), zero => cos_mag_i = 0);
    s <= (ge => to_u15(sin_mag_i) >= eps_2, zero => sin_mag_i = 0) when OPT_TUNABLE = 1 else
         (ge => geu(to_u15(sin_mag_i), eps_2), zero => sin_mag_i = 0);

  end generate g_form;

  pins : process (clk) is
  begin

    if rising_edge(clk) then
      valid_q <= valid_i;

      if valid_i = '1' then
        a_q <= hysteresis(a_q, cos_neg_i, c, zero_eps);
        b_q <= hysteresis(b_q, sin_neg_i, s, zero_eps);
      end if;

      if rst = '1' then
        valid_q <= '0';
        a_q     <= '1';
        b_q     <= '1';
      end if;
    end if;

  end process pins;

  valid_o <= valid_q;
  a_o     <= a_q;
  b_o     <= b_q;

end architecture rtl;
