-- correct: input gain, offsets and Eq. 9 as three products, ending in the magnitudes and
-- signs of the corrected signals that the octant logic needs (VHDL edition of
-- rtl/correct.v, which gives the design reasoning; model sim/model/correct.py).
--
-- One sample per clock, strobed on edge t by valid_i, with its coefficient bundle:
--   t    u_r = u << (16 - ADC_W) (s1.15, raw*_o); x = u_r 2**g (s4.15, exact);
--        d = sat16(x - m) (s1.15); d and the coefficients registered (the DSP blocks'
--        input registers); flags clip_o, nsat_o, dsat_o and amax_o
--   t+1  p1 = d1 c1, p12 = d1 c12, p2 = d2 c2 (s5.27, three DSP products)
--   t+2  v1 = p1, v2 = p12 + p2 (s6.27); ax_o, ay_o = min(32767, (v ^ sign) >> 13) (u15
--        magnitudes, s2.14 units), xn_o, yn_o the signs, rsat_o (|u| >= 2), zl_o =
--        lzc15(ax_o | ay_o)
-- Every stage's registers take a sample only with its valid bit (a clock enable); no
-- reset. Power-up values 0.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;

entity correct is
  generic (
    -- ADC word width, 12..16, two's complement
    ADC_W : integer range 12 to 16 := 16
  );
  port (
    clk     : in    std_logic;
    valid_i : in    std_logic;
    u1_i    : in    signed(ADC_W - 1 downto 0); -- ADC codes
    u2_i    : in    signed(ADC_W - 1 downto 0);
    clip_i  : in    unsigned(15 downto 0);      -- u16 clip level (s1.15 magnitude)
    g_i     : in    unsigned(1 downto 0);       -- input gain 2**g
    m1_i    : in    signed(15 downto 0);        -- s1.15 offsets (normalised units)
    m2_i    : in    signed(15 downto 0);
    c1_i    : in    signed(15 downto 0);        -- s4.12 coefficients
    c12_i   : in    signed(15 downto 0);
    c2_i    : in    signed(15 downto 0);
    -- edge t
    valid0_o : out   std_logic;
    raw1_o   : out   signed(15 downto 0);   -- s1.15 aligned codes (for the estimator)
    raw2_o   : out   signed(15 downto 0);
    amax_o   : out   unsigned(14 downto 0); -- u15 max(|raw1|, |raw2|), 32768 as 32767
    clip_o   : out   std_logic;             -- |raw1| or |raw2| >= clip_i
    nsat_o   : out   std_logic;             -- x leaves s1.15 (the gain saturates)
    dsat_o   : out   std_logic;             -- x - m leaves s1.15 (d saturated)
    -- edge t+2
    valid_o : out   std_logic;
    ax_o    : out   unsigned(14 downto 0); -- u15 |u1c|, s2.14 units, saturated
    ay_o    : out   unsigned(14 downto 0); -- u15 |u2c|
    xn_o    : out   std_logic;             -- u1c < 0
    yn_o    : out   std_logic;             -- u2c < 0
    zl_o    : out   unsigned(3 downto 0);  -- lzc15(ax_o | ay_o): 0..14 (14 for 0, 1)
    rsat_o  : out   std_logic              -- a magnitude reaches 2 (saturated)
  );
end entity correct;

architecture rtl of correct is

  subtype s16_t is signed(15 downto 0);

  subtype u15_t is unsigned(14 downto 0);

  subtype dsp_t is signed(31 downto 0); -- s5.27 products

  subtype vhi_t is unsigned(19 downto 0); -- s20 v >> 13, as bits

  subtype lz2_t is unsigned(1 downto 0);

  subtype lz4_t is unsigned(3 downto 0);

  -- ---- t: align, gain, offsets ------------------------------------------------------------

  -- u_r = u << (16 - ADC_W), s1.15
  function align (u : signed) return s16_t is
  begin

    return shift_left(resize(u, 16), 16 - u'length);

  end function align;

  -- v fits s1.15: its bits above bit 15 copy bit 15
  function fits16 (v : signed) return boolean is
  begin

    return resize(resize(v, 16), v'length) = v;

  end function fits16;

  -- x = u_r 2**g, s4.15 (exact)
  function gain (ur : s16_t; g : unsigned(1 downto 0)) return signed is
  begin

    return shift_left(resize(ur, 19), to_integer(g));

  end function gain;

  -- e = x - m, s5.15
  function offset (ur : s16_t; g : unsigned(1 downto 0); m : s16_t) return signed is
  begin

    return resize(gain(ur, g), 20) - resize(m, 20);

  end function offset;

  -- max(|u1|, |u2|) saturated to 32767; |u1| >= |u2| is decided from the codes beside the
  -- magnitudes (by the signs: u1 - u2 or u1 + u2), ties pick either
  function amax (u1 : s16_t; u2 : s16_t) return u15_t is

    -- |u| as u16 (|-32768| = 32768), saturated to u15
    function mag15 (u : s16_t) return u15_t is

      variable a : signed(16 downto 0);

    begin

      -- (an if, not abs: GHDL 2.0's Verilog writer prints abs of a signed as VHDL text)
      if u(u'high) = '1' then -- (the sign bit: Yosys makes u < 0 a carry chain)
        a := -resize(u, 17);
      else
        a := resize(u, 17);
      end if;

      if a(15) = '1' then
        return (others => '1');
      end if;

      return unsigned(a(14 downto 0));

    end function mag15;

    variable dif : signed(16 downto 0);
    variable smu : signed(16 downto 0);
    variable lt  : std_logic;

  begin

    dif := resize(u1, 17) - resize(u2, 17);
    smu := resize(u1, 17) + resize(u2, 17);

    if u1(15) = u2(15) then
      lt := dif(16);
    else
      lt := smu(16);
    end if;

    -- lt xor (u1 >= 0): |u1| >= |u2|
    if (lt xor not u1(15)) = '1' then
      return mag15(u1);
    end if;

    return mag15(u2);

  end function amax;

  -- |u| >= clip with no negation in front of the comparison: u >= clip for u >= 0;
  -- not u >= clip - 1 for u < 0 (every u < 0 when clip = 0)
  function clipped (u : s16_t; clip : unsigned(15 downto 0)) return boolean is

    variable cm : unsigned(16 downto 0);

  begin

    cm := resize(clip, 17) - 1;

    if u(15) = '1' then
      return cm(16) = '1' or resize(unsigned(not u), 17) >= cm;
    end if;

    return unsigned(u) >= clip;

  end function clipped;

  -- ---- t+2: magnitudes and signs -----------------------------------------------------------

  -- (a + b) >> 13 as s20, by carry select: both values of the upper 20 bits (carry in 0
  -- and 1) beside the carry out of the low 13, chosen by AND-OR (rtl/correct.v sum_hi)
  function sum_hi (a : dsp_t; b : dsp_t) return vhi_t is

    -- the upper parts a >> 13, b >> 13 as s20
    constant AH : unsigned(19 downto 0) := unsigned(resize(a(31 downto 13), 20));
    constant BH : unsigned(19 downto 0) := unsigned(resize(b(31 downto 13), 20));

    variable lo   : unsigned(13 downto 0);
    variable hi0  : unsigned(19 downto 0);
    variable hi1  : unsigned(20 downto 0);
    variable csel : unsigned(19 downto 0);

  begin

    lo   := resize(unsigned(a(12 downto 0)), 14) + resize(unsigned(b(12 downto 0)), 14);
    hi0  := AH + BH;
    hi1  := (AH & '1') + (BH & '1'); -- AH + BH + 1 in bits 20 downto 1
    csel := (others => lo(13));
    return (hi1(20 downto 1) and csel) or (hi0 and not csel);

  end function sum_hi;

  -- |u| = vh ^ sign (u20): floor((|v| - 1) / 2**13) for v < 0, no carry chain
  function umag20 (vh : vhi_t) return vhi_t is
  begin

    return vh xor (vh'range => vh(19));

  end function umag20;

  -- |u| >= 2: the magnitude saturates
  function usat (vh : vhi_t) return boolean is
  begin

    return umag20(vh)(19 downto 15) /= 0;

  end function usat;

  -- |u| saturated to 32767
  function umag (vh : vhi_t) return u15_t is
  begin

    if usat(vh) then
      return (others => '1');
    end if;

    return umag20(vh)(14 downto 0);

  end function umag;

  -- leading zeros of 4 bits (3 for 0001 and 0000)
  function lzc4 (v : unsigned(3 downto 0)) return lz2_t is
  begin

    if v(3) = '1' then
      return "00";
    elsif v(2) = '1' then
      return "01";
    elsif v(1) = '1' then
      return "10";
    end if;

    return "11";

  end function lzc4;

  -- leading zeros in 15 bits, 14 for 0 and 1: those of the 16 bits v(14 downto 1) & "11",
  -- a two-level tree (nibble priority beside the nibbles' own counts)
  function lzc15 (v : u15_t) return lz4_t is

    variable w : unsigned(15 downto 0);

  begin

    w := v(14 downto 1) & "11";

    if w(15 downto 12) /= 0 then
      return "00" & lzc4(w(15 downto 12));
    elsif w(11 downto 8) /= 0 then
      return "01" & lzc4(w(11 downto 8));
    elsif w(7 downto 4) /= 0 then
      return "10" & lzc4(w(7 downto 4));
    end if;

    return "11" & lzc4(w(3 downto 0));

  end function lzc15;

  -- ---- registers ---------------------------------------------------------------------------
  -- t: d and the coefficients (the DSP blocks' input registers), s1.15 and s4.12
  signal d1   : s16_t := (others => '0');
  signal d2   : s16_t := (others => '0');
  signal c1q  : s16_t := (others => '0');
  signal c12q : s16_t := (others => '0');
  signal c2q  : s16_t := (others => '0');

  signal valid0_q : std_logic := '0';
  signal raw1_q   : s16_t     := (others => '0');
  signal raw2_q   : s16_t     := (others => '0');
  signal amax_q   : u15_t     := (others => '0');
  signal clip_q   : std_logic := '0';
  signal nsat_q   : std_logic := '0';
  signal dsat_q   : std_logic := '0';

  -- t+1: the products, s5.27
  signal p1  : dsp_t     := (others => '0');
  signal p12 : dsp_t     := (others => '0');
  signal p2  : dsp_t     := (others => '0');
  signal v1q : std_logic := '0';

  -- t+2
  signal valid_q : std_logic := '0';
  signal ax_q    : u15_t     := (others => '0');
  signal ay_q    : u15_t     := (others => '0');
  signal xn_q    : std_logic := '0';
  signal yn_q    : std_logic := '0';
  signal zl_q    : lz4_t     := (others => '0');
  signal rsat_q  : std_logic := '0';

begin

  -- (the stages' logic as variables inside their clock enables: simulation evaluates it
  -- only for a sample)
  stage_t : process (clk) is

    variable ur1 : s16_t;
    variable ur2 : s16_t;
    variable e1  : signed(19 downto 0);
    variable e2  : signed(19 downto 0);

  begin

    if rising_edge(clk) then
      valid0_q <= valid_i;

      if valid_i = '1' then
        ur1 := align(u1_i);
        ur2 := align(u2_i);
        e1  := offset(ur1, g_i, m1_i);
        e2  := offset(ur2, g_i, m2_i);

        d1     <= saturate(e1, 16);
        d2     <= saturate(e2, 16);
        c1q    <= c1_i;
        c12q   <= c12_i;
        c2q    <= c2_i;
        raw1_q <= ur1;
        raw2_q <= ur2;
        amax_q <= amax(ur1, ur2);
        clip_q <= to_sl(clipped(ur1, clip_i) or clipped(ur2, clip_i));
        nsat_q <= to_sl(not (fits16(gain(ur1, g_i)) and fits16(gain(ur2, g_i))));
        dsat_q <= to_sl(not (fits16(e1) and fits16(e2)));
      end if;
    end if;

  end process stage_t;

  stage_t1 : process (clk) is
  begin

    if rising_edge(clk) then
      if valid0_q = '1' then
        p1  <= d1 * c1q;
        p12 <= d1 * c12q;
        p2  <= d2 * c2q;
      end if;

      v1q <= valid0_q;
    end if;

  end process stage_t1;

  stage_t2 : process (clk) is

    -- v >> 13 (s20) of v1 = p1 and of v2 = p12 + p2
    variable v1h : vhi_t;
    variable v2h : vhi_t;

  begin

    if rising_edge(clk) then
      if v1q = '1' then
        v1h := unsigned(resize(p1(31 downto 13), 20));
        v2h := sum_hi(p12, p2);

        ax_q <= umag(v1h);
        ay_q <= umag(v2h);

        -- (a saturated magnitude, 32767, has no leading zero: the count does not wait
        -- for the saturation's multiplexer)
        if usat(v1h) or usat(v2h) then
          zl_q <= (others => '0');
        else
          zl_q <= lzc15(umag20(v1h)(14 downto 0) or umag20(v2h)(14 downto 0));
        end if;

        xn_q   <= p1(31);
        yn_q   <= v2h(19);
        rsat_q <= to_sl(usat(v1h) or usat(v2h));
      end if;

      valid_q <= v1q;
    end if;

  end process stage_t2;

  valid0_o <= valid0_q;
  raw1_o   <= raw1_q;
  raw2_o   <= raw2_q;
  amax_o   <= amax_q;
  clip_o   <= clip_q;
  nsat_o   <= nsat_q;
  dsat_o   <= dsat_q;

  valid_o <= valid_q;
  ax_o    <= ax_q;
  ay_o    <= ay_q;
  xn_o    <= xn_q;
  yn_o    <= yn_q;
  zl_o    <= zl_q;
  rsat_o  <= rsat_q;

end architecture rtl;
