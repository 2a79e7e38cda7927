-- finequad_multi: AXES encoder axes, each a finequad_core, sharing one RLS engine in time
-- division (VHDL edition of rtl/finequad_multi.v, whose header gives the window rule and
-- its reasoning; bit-true model: each axis is sim/model/finequad_core.py's Core with
-- Config.tdm = (AXES, i, TDM_L, TDM_W) on its own samples).
--
-- Axis i may decide an engine program only on an edge e with
--   i TDM_L <= e mod (AXES TDM_L) < i TDM_L + TDM_W,
-- edges counted from power-up or the last rst; TDM_L = TDM_W + 1 + the UPDATE's and the
-- EXTRACT's cycles (rls_pkg, for ENGINE_LANES). AXES = 1: one finequad_core with its own
-- engine (no windows).
-- Register port: the core registers of axis reg_axis; reg_err: that core refuses the
-- write, or reg_axis >= AXES (nothing written); reg_rdata: the axis read last (0 for
-- reg_axis >= AXES).
-- Formats per axis as finequad_core; the buses hold axis i at bits W i + W - 1 .. W i:
-- s_u1, s_u2 s(ADC_W) codes, m_count s(COUNT_W) counts, m_fault 11 bits. The count latched
-- at a reference is read as the axis's REF_COUNT register (no port).

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;
  use work.finequad_regs_pkg.all;
  use work.rls_pkg.all;

entity finequad_multi is
  generic (
    TABLE_DIR : string := "rtl/tables/";
    -- axes sharing the RLS engine
    AXES : integer range 1 to 8 := 2;
    -- window (edges) in which an axis may start an engine program (>= the longest gap
    -- between an axis's strobes)
    TDM_W : integer range 1 to 65535 := 64;
    -- ADC word width (every axis)
    ADC_W : integer range 12 to 16 := 16;
    -- sine table word width: 8, 10, 12 or 16
    SIN_W : integer range 8 to 16 := 10;
    -- counter width
    COUNT_W : integer range 17 to 32 := 32;
    -- the core's options (finequad_core)
    TABLE_EXACT    : integer range 0 to 1 := 1;
    G_INIT         : integer range 0 to 3 := 0;
    OPT_NTH_DSP    : integer range 0 to 1 := 1;
    OPT_HARMONIC   : integer range 0 to 1 := 1;
    OPT_DISTRAM    : integer range 0 to 1 := 0;
    OPT_PHASE_4K   : integer range 0 to 1 := 0;
    OPT_ECP5_MULT  : integer range 0 to 1 := 0;
    OPT_PULSE_ADDR : integer range 0 to 1 := 0;
    OPT_TUNABLE    : integer range 0 to 1 := 1;
    OPT_MONITOR    : integer range 0 to 1 := 1;
    OPT_JUMP       : integer range 0 to 1 := 1;
    OPT_DCODE      : integer range 0 to 1 := 1;
    -- lanes of the shared RLS engine
    ENGINE_LANES : integer range 1 to 2 := 1
  );
  port (
    clk : in    std_logic;
    rst : in    std_logic; -- sync, active high
    -- sample streams: axis i strobes s_valid(i) with its words of s_u1, s_u2
    s_valid : in    std_logic_vector(AXES - 1 downto 0);
    s_u1    : in    std_logic_vector(AXES * ADC_W - 1 downto 0); -- s(ADC_W) each
    s_u2    : in    std_logic_vector(AXES * ADC_W - 1 downto 0);
    -- reference input of axis i (sampled with s_valid(i))
    s_ref : in    std_logic_vector(AXES - 1 downto 0);
    -- register port of axis reg_axis (ceil(log2(AXES)) bits, at least 1)
    reg_we    : in    std_logic;
    reg_re    : in    std_logic;
    reg_axis  : in    unsigned(boolean'pos(AXES > 2) + boolean'pos(AXES > 4) downto 0);
    reg_addr  : in    unsigned(5 downto 0);
    reg_wdata : in    std_logic_vector(31 downto 0);
    reg_rdata : out   std_logic_vector(31 downto 0);
    -- the write is refused (combinational)
    reg_err : out   std_logic;
    -- per-sample results of axis i
    m_valid : out   std_logic_vector(AXES - 1 downto 0);
    m_count : out   std_logic_vector(AXES * COUNT_W - 1 downto 0); -- s(COUNT_W) each
    m_fault : out   std_logic_vector(AXES * 11 - 1 downto 0);
    -- A/B outputs of axis i
    m_a : out   std_logic_vector(AXES - 1 downto 0);
    m_b : out   std_logic_vector(AXES - 1 downto 0);
    -- reference marks of axis i: Z, homed, position valid
    m_z         : out   std_logic_vector(AXES - 1 downto 0);
    m_homed     : out   std_logic_vector(AXES - 1 downto 0);
    m_pos_valid : out   std_logic_vector(AXES - 1 downto 0)
  );
end entity finequad_multi;

architecture rtl of finequad_multi is

  -- window spacing (sim/model/finequad_core.py tdm_period)
  function tdm_period return positive is
  begin

    if ENGINE_LANES = 2 then
      return TDM_W + 1 + CYCLES_UPDATE_2 + CYCLES_EXTRACT_2;
    end if;

    return TDM_W + 1 + CYCLES_UPDATE_1 + CYCLES_EXTRACT_1;

  end function tdm_period;

  constant TDM_L         : positive := tdm_period;
  constant SHARED_ENGINE : boolean  := AXES > 1;

  subtype axis_t is unsigned(reg_axis'range);

  -- the engine's command of an axis (rtl/estimator.v eng_cmd_o)
  subtype cmd_word_t is std_logic_vector(65 downto 0);

  -- the engine's response to an axis (rtl/estimator.v eng_rsp_i)
  subtype rsp_word_t is std_logic_vector(114 downto 0);

  type cmd_words_t is array (0 to AXES - 1) of cmd_word_t;

  type rsp_words_t is array (0 to AXES - 1) of rsp_word_t;

  type rdata_words_t is array (0 to AXES - 1) of fq_word_t;

  -- the fields of a command word
  type eng_cmd_t is record
    start    : std_logic;
    entry    : unsigned(7 downto 0);  -- program entry address
    x1       : signed(15 downto 0);   -- s1.15
    x2       : signed(15 downto 0);   -- s1.15
    lambda_k : unsigned(4 downto 0);
    freeze   : std_logic;
    kappa    : unsigned(15 downto 0); -- u8.8
    dg       : signed(2 downto 0);
  end record eng_cmd_t;

  function to_cmd (w : cmd_word_t) return eng_cmd_t is
  begin

    return (start    => w(65),
            entry    => unsigned(w(64 downto 57)),
            x1       => signed(w(56 downto 41)),
            x2       => signed(w(40 downto 25)),
            lambda_k => unsigned(w(24 downto 20)),
            freeze   => w(19),
            kappa    => unsigned(w(18 downto 3)),
            dg       => signed(w(2 downto 0)));

  end function to_cmd;

  function to_axis (i : natural) return axis_t is
  begin

    return to_unsigned(i, axis_t'length);

  end function to_axis;

  signal tdm_ok    : std_logic_vector(AXES - 1 downto 0); -- axis i may decide on the coming edge
  signal cmd_all   : cmd_words_t;
  signal rsp_all   : rsp_words_t;
  signal rdata_all : rdata_words_t;
  signal err_all   : std_logic_vector(AXES - 1 downto 0); -- axis i refuses the write
  signal axis_ok   : std_logic;                           -- reg_axis names an axis
  signal rd_axis   : axis_t := (others => '0');           -- the axis read last

begin

  -- ---- the axes --------------------------------------------------------------------------

  g_axis : for i in 0 to AXES - 1 generate

    -- this axis's registers
    signal sel   : std_logic;
    signal we    : std_logic;
    signal re    : std_logic;
    signal count : signed(COUNT_W - 1 downto 0);
    signal fault : std_logic_vector(10 downto 0);
    -- REF_COUNT reads it (no port)
    signal ref_count : signed(COUNT_W - 1 downto 0);

  begin

    sel <= '1' when AXES = 1 or reg_axis = to_axis(i) else
           '0';
    we  <= reg_we and sel;
    re  <= reg_re and sel;

    u_core : entity work.finequad_core
      generic map (
        table_dir      => TABLE_DIR,
        adc_w          => ADC_W,
        sin_w          => SIN_W,
        count_w        => COUNT_W,
        table_exact    => TABLE_EXACT,
        g_init         => G_INIT,
        opt_nth_dsp    => OPT_NTH_DSP,
        opt_harmonic   => OPT_HARMONIC,
        opt_distram    => OPT_DISTRAM,
        opt_phase_4k   => OPT_PHASE_4K,
        opt_ecp5_mult  => OPT_ECP5_MULT,
        opt_pulse_addr => OPT_PULSE_ADDR,
        opt_tunable    => OPT_TUNABLE,
        opt_monitor    => OPT_MONITOR,
        opt_jump       => OPT_JUMP,
        opt_dcode      => OPT_DCODE,
        engine_lanes   => ENGINE_LANES,
        opt_ext_engine => boolean'pos(SHARED_ENGINE),
        ext_period     => boolean'pos(SHARED_ENGINE) * AXES * TDM_L
      )
      port map (
        clk         => clk,
        rst         => rst,
        s_valid     => s_valid(i),
        s_u1        => signed(s_u1(ADC_W * i + ADC_W - 1 downto ADC_W * i)),
        s_u2        => signed(s_u2(ADC_W * i + ADC_W - 1 downto ADC_W * i)),
        s_ref       => s_ref(i),
        reg_we      => we,
        reg_re      => re,
        reg_addr    => reg_addr,
        reg_wdata   => reg_wdata,
        reg_rdata   => rdata_all(i),
        reg_err     => err_all(i),
        m_valid     => m_valid(i),
        m_count     => count,
        m_fault     => fault,
        m_a         => m_a(i),
        m_b         => m_b(i),
        m_z         => m_z(i),
        m_ref_count => ref_count,
        m_homed     => m_homed(i),
        m_pos_valid => m_pos_valid(i),
        tdm_ok_i    => tdm_ok(i),
        eng_cmd_o   => cmd_all(i),
        eng_rsp_i   => rsp_all(i)
      );

    m_count(COUNT_W * i + COUNT_W - 1 downto COUNT_W * i) <= std_logic_vector(count);
    m_fault(11 * i + 10 downto 11 * i)                    <= fault;

  end generate g_axis;

  -- a write to a reg_axis beyond the axes reaches no core: refused too (an integer
  -- compare: GHDL 2.0's synthesis cuts AXES to reg_axis's width, README.md)
  axis_ok <= '1' when AXES = 1 or to_integer(reg_axis) < AXES else
             '0';
  reg_err <= or err_all or (reg_we and not axis_ok);

  -- ---- register read-back: the axis read last --------------------------------------------
  read_axis : process (clk) is
  begin

    if rising_edge(clk) then
      if reg_re = '1' then
        rd_axis <= reg_axis;
      end if;
    end if;

  end process read_axis;

  read_mux : process (all) is
  begin

    reg_rdata <= (others => '0');

    for j in 0 to AXES - 1 loop

      if AXES = 1 or rd_axis = to_axis(j) then
        reg_rdata <= rdata_all(j);
      end if;

    end loop;

  end process read_mux;

  -- ---- the shared engine and its windows -------------------------------------------------

  g_engine : if SHARED_ENGINE generate

    -- before edge e: wl = e mod TDM_L, wi = the axis whose window span holds e, in_w =
    -- wl < TDM_W; own = wi one edge earlier: the axis whose programs start or end on e
    signal wl   : natural range 0 to TDM_L - 1 := 0;
    signal wi   : natural range 0 to AXES - 1  := 0;
    signal in_w : std_logic                    := '1';
    signal own  : natural range 0 to AXES - 1  := AXES - 1;
    -- own as the engine's axis_i (a signal: GHDL 2.0's synthesis fails on a function of a
    -- signal as a port's actual)
    signal own_axis : axis_t;

    -- the owner's command (the other axes' start bits are low: they are outside their
    -- windows and their programs have ended)
    signal cmd   : eng_cmd_t;
    signal busy  : std_logic;
    signal done  : std_logic;
    signal valid : std_logic;
    signal outs  : std_logic_vector(111 downto 0); -- OUT registers (rls_engine)
    signal sat   : std_logic_vector(AXES - 1 downto 0);

  begin

    windows : process (clk) is
    begin

      if rising_edge(clk) then
        if wl = TDM_L - 1 then
          wl   <= 0;
          in_w <= '1';

          if wi = AXES - 1 then
            wi <= 0;
          else
            wi <= wi + 1;
          end if;
        else
          wl <= wl + 1;

          if wl = TDM_W - 1 then
            in_w <= '0';
          end if;
        end if;

        own <= wi;

        if rst = '1' then
          wl   <= 0;
          wi   <= 0;
          in_w <= '1';
          own  <= AXES - 1;
        end if;
      end if;

    end process windows;

    g_ok : for a in 0 to AXES - 1 generate
      tdm_ok(a) <= in_w when wi = a else
                   '0';
    end generate g_ok;

    cmd      <= to_cmd(cmd_all(own));
    own_axis <= to_axis(own);

    u_engine : entity work.rls_engine
      generic map (
        table_dir => TABLE_DIR,
        lanes     => ENGINE_LANES,
        axes      => AXES
      )
      port map (
        clk        => clk,
        rst        => rst,
        start_i    => cmd.start,
        entry_i    => cmd.entry,
        x1_i       => cmd.x1,
        x2_i       => cmd.x2,
        lambda_k_i => cmd.lambda_k,
        freeze_i   => cmd.freeze,
        kappa_i    => cmd.kappa,
        dg_i       => cmd.dg,
        axis_i     => own_axis,
        busy_o     => busy,
        done_o     => done,
        valid_o    => valid,
        out_o      => outs,
        sat_o      => sat
      );

    -- {sat of the axis, done (for its owner only), valid, OUT}

    g_rsp : for a in 0 to AXES - 1 generate
      rsp_all(a) <= sat(a) & (done and to_sl(own = a)) & valid & outs;
    end generate g_rsp;

  else generate

    tdm_ok  <= (others => '1');
    rsp_all <= (others => (others => '0'));

  end generate g_engine;

end architecture rtl;
