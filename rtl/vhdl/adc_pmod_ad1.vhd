-- adc_pmod_ad1: front end for Digilent's Pmod AD1 (two AD7476A, 12 bit, straight
-- binary; CS_N and SCLK shared, one SDATA line per converter). VHDL edition of
-- rtl/adc_pmod_ad1.v, which has the converter's timing, the requirements on the
-- generics and the board values.
--
-- Timing (all outputs registered; p = phase counter after an edge, one conversion every
-- PERIOD clocks; H = SCLK_HALF, S = CS_SETUP):
--   p = 0                  CS_N falls (SCLK idles high)
--   p = S + 2H(k-1)        SCLK falls for the k-th time (k = 1..16), SDATA sampled
--   p = S + 2H(k-1) + H    SCLK rises
--   p = S + 31H            SCLK rises after the 16th falling edge, CS_N rises
--   p = S + 30H + 1        m_valid high for one clock with both samples
-- Requirements (rtl/adc_pmod_ad1.v): 2H / f_clk >= 50 ns, S / f_clk >= 22 ns + I/O
-- delays, PERIOD >= S + 31H + 1 (checked here), (PERIOD - S - 30H) / f_clk >= 86 ns.
-- Formats: m_u1, m_u2 s(OUT_W).0, the 12-bit code MSB-aligned, u = (code - 2048) *
-- 2^(OUT_W - 12); m_err: a leading zero of either line was 1. Valid strobe only.
-- rst (sync): CS_N and SCLK high, the next CS_N falling edge PERIOD - S - 31H clocks
-- later. Power-up values are those after rst.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

entity adc_pmod_ad1 is
  generic (
    -- clocks per SCLK half period (SCLK = f_clk / (2 SCLK_HALF))
    SCLK_HALF : integer range 1 to 2047 := 1;
    -- clocks from CS_N falling to the first SCLK falling edge (>= 1)
    CS_SETUP : integer range 1 to 65535 := 1;
    -- clocks per conversion (the sample period)
    PERIOD : integer range 2 to 65536 := 34;
    -- output word width (>= 12); the 12-bit code is MSB-aligned
    OUT_W : integer range 12 to integer'high := 12
  );
  port (
    clk : in    std_logic;
    rst : in    std_logic; -- sync, active high
    -- Pmod AD1 pins (J1: 1 CS, 2 D0, 3 D1, 4 SCLK)
    cs_n_o   : out   std_logic;
    sclk_o   : out   std_logic;
    sdata1_i : in    std_logic; -- D0: converter 1 (u1)
    sdata2_i : in    std_logic; -- D1: converter 2 (u2)
    -- sample stream
    m_valid : out   std_logic;
    m_u1    : out   signed(OUT_W - 1 downto 0); -- s(OUT_W).0
    m_u2    : out   signed(OUT_W - 1 downto 0); -- s(OUT_W).0
    m_err   : out   std_logic
  );
end entity adc_pmod_ad1;

architecture rtl of adc_pmod_ad1 is

  -- the phase counter and the SCLK half counter: u16
  subtype phase_t is unsigned(15 downto 0);

  constant P_END   : phase_t := to_unsigned(CS_SETUP + 31 * SCLK_HALF, 16); -- CS_N rises
  constant P_LAST  : phase_t := to_unsigned(PERIOD - 1, 16);                -- last p
  constant P_FIRST : phase_t := to_unsigned(CS_SETUP, 16);                  -- first fall
  constant H_LAST  : phase_t := to_unsigned(SCLK_HALF - 1, 16);             -- clocks - 1

  -- The bits of one frame of a converter: 4 leading zeros, then DB11..DB0.
  subtype frame_t is std_logic_vector(15 downto 0);

  -- The frame's 12-bit code (straight binary) as s(OUT_W).0, MSB-aligned.
  function to_sample (f : frame_t) return signed is

    variable u : signed(OUT_W - 1 downto 0) := (others => '0');

  begin

    u(OUT_W - 1 downto OUT_W - 12) := signed((not f(11)) & f(10 downto 0));
    return u;

  end function to_sample;

  signal p       : phase_t                    := P_END;
  signal hc      : phase_t                    := (others => '0'); -- clocks left in this half
  signal tog_n   : unsigned(5 downto 0)       := (others => '0'); -- SCLK edges in this frame
  signal run     : std_logic                  := '0';             -- SCLK running
  signal done    : std_logic                  := '0';             -- the 16th bit was sampled
  signal sh1     : frame_t                    := (others => '0');
  signal sh2     : frame_t                    := (others => '0');
  signal cs_n_q  : std_logic                  := '1';
  signal sclk_q  : std_logic                  := '1';
  signal valid_q : std_logic                  := '0';
  signal u1_q    : signed(OUT_W - 1 downto 0) := (others => '0');
  signal u2_q    : signed(OUT_W - 1 downto 0) := (others => '0');
  signal err_q   : std_logic                  := '0';

  signal p_n : phase_t;
  signal tog : boolean; -- SCLK toggles this edge

begin

  assert PERIOD >= CS_SETUP + 31 * SCLK_HALF + 1
    report "adc_pmod_ad1: PERIOD must be at least CS_SETUP + 31 SCLK_HALF + 1"
    severity failure;

  p_n <= (others => '0') when p = P_LAST else
         p + 1;
  tog <= run = '1' and hc = 0;

  regs : process (clk) is
  begin

    if rising_edge(clk) then
      p       <= p_n;
      valid_q <= '0';
      done    <= '0';

      -- the pins: each assigned once per edge (rst included), so that no simulator
      -- shows a zero-width pulse on them while rst holds them high
      if rst = '1' then
        cs_n_q <= '1';
      elsif p_n = 0 then
        cs_n_q <= '0';
      elsif tog and tog_n = 31 then
        cs_n_q <= '1';
      end if;

      if rst = '1' then
        sclk_q <= '1';
      elsif p_n = P_FIRST then
        sclk_q <= '0';
      elsif tog then
        sclk_q <= not sclk_q;
      end if;

      if p_n = P_FIRST then
        -- the first SCLK falling edge: sample the first leading zero
        run   <= '1';
        hc    <= H_LAST;
        tog_n <= to_unsigned(1, 6);
        sh1   <= sh1(14 downto 0) & sdata1_i;
        sh2   <= sh2(14 downto 0) & sdata2_i;
      elsif run = '1' then
        if hc /= 0 then
          hc <= hc - 1;
        else
          hc    <= H_LAST;
          tog_n <= tog_n + 1;

          -- SCLK falls: sample the previous bit
          if sclk_q = '1' then
            sh1 <= sh1(14 downto 0) & sdata1_i;
            sh2 <= sh2(14 downto 0) & sdata2_i;

            if tog_n = 30 then
              done <= '1';
            end if;
          end if;

          -- SCLK rises after the 16th bit, CS_N rises
          if tog_n = 31 then
            run <= '0';
          end if;
        end if;
      end if;

      if done = '1' then
        valid_q <= '1';
        u1_q    <= to_sample(sh1);
        u2_q    <= to_sample(sh2);
        err_q   <= or (sh1(15 downto 12) & sh2(15 downto 12));
      end if;

      if rst = '1' then
        p       <= P_END;
        run     <= '0';
        done    <= '0';
        valid_q <= '0';
      end if;
    end if;

  end process regs;

  cs_n_o  <= cs_n_q;
  sclk_o  <= sclk_q;
  m_valid <= valid_q;
  m_u1    <= u1_q;
  m_u2    <= u2_q;
  m_err   <= err_q;

end architecture rtl;
