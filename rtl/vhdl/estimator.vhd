-- estimator: decides which samples the RLS engine takes, manages covariance resets and
-- the input gain, and hands the correction coefficients over to the fast path (VHDL
-- edition of rtl/estimator.v; the edge-exact specification is sim/model/estimator.py,
-- the reasoning sim/README.md, "The estimator").
--
-- A sample arriving on edge t (smp_valid_i) may start a RESET program (t + 1) or become
-- the candidate; its fine phase arrives PH_DELAY edges later (ph_valid_i, excl_i,
-- travel_i), and the candidate is checked on the edge after (trusted, no saturation at
-- the gain in use, enough travel). A checked candidate starts an UPDATE when the engine
-- is free, else waits in the slot; the next candidate may come a dither of 0..DSPAN
-- clocks (an LFSR) after the UPDATE's decision. An UPDATE that ends valid with the
-- covariance settled, all eight octants covered and no jump detected is followed by an
-- EXTRACT, whose valid end hands the bundle over. Periodic resets (period_i), the
-- warm-up's gain check (WARMUP), the trace bound (kappa5_i: no forgetting) and the jump
-- detector (two running means of |e|) request resets. load_i replaces the bundle with
-- ld_*_i unless a hand-over happens on the same edge. OPT_EXT_ENGINE = 1: the engine is
-- outside (eng_cmd_o, eng_rsp_i; a program is decided only with tdm_ok_i).
--
-- Formats: u1_i, u2_i s1.15; amax_i u15; phase_i u13 (unused); travel_i u20; m1, m2
-- s1.15; c1, c12, c2 s4.12; kappa_i u8.8; kappa5_i u11.4; gate_i u13; jump_min_i u0.13
-- (of |e| s3.13); updates_o, jumps_o counts (wrap). rst (sync) restarts the control
-- state and the outputs as at power-up; it keeps g_eng, the gain theta is expressed in
-- (the engine's register file survives rst too), and the data registers.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;
  use work.rls_pkg.all;

entity estimator is
  generic (
    TABLE_DIR : string := "rtl/tables/";
    -- input gain after power-up, 0..3
    G_INIT : integer range 0 to 3 := 0;
    -- updates after power-up before the input gain is checked (reset if it changes)
    WARMUP : integer range 1 to 65535 := 64;
    -- edges from a sample's arrival (smp_valid_i) to its fine phase (ph_valid_i)
    PH_DELAY : integer range 2 to 64 := 6;
    -- lanes of the RLS engine (rls_engine LANES): 1 or 2
    ENGINE_LANES : integer range 1 to 2 := 1;
    -- 0: the RLS engine inside; 1: an engine outside (rtl/finequad_multi.v), driven
    -- through eng_cmd_o / eng_rsp_i, a RESET or UPDATE decided only with tdm_ok_i
    OPT_EXT_ENGINE : integer range 0 to 1 := 0;
    -- with OPT_EXT_ENGINE: the axis's window period in clocks, over which the dither
    -- spreads the candidates; 0: one axis
    EXT_PERIOD : integer range 0 to 65535 := 0;
    -- 1: the tuning inputs are registers; 0: constants, compared bit by bit (geu), and
    -- period_i unused (no periodic resets)
    OPT_TUNABLE : integer range 0 to 1 := 1
  );
  port (
    clk : in    std_logic;
    rst : in    std_logic; -- sync, active high
    -- every sample, on its arrival (edge t)
    smp_valid_i : in    std_logic;
    u1_i        : in    signed(15 downto 0);   -- s1.15 raw (aligned) sample
    u2_i        : in    signed(15 downto 0);
    amax_i      : in    unsigned(14 downto 0); -- max(|u1|, |u2|), saturated
    -- the fine phase of the sample that arrived PH_DELAY edges earlier
    ph_valid_i : in    std_logic;
    phase_i    : in    phase_t;               -- u13 (unused: timing only)
    excl_i     : in    std_logic;             -- the monitor excludes it
    travel_i   : in    unsigned(19 downto 0); -- u20 smoothed travel
    -- a LOAD: the staged bundle replaces the one in use
    load_i      : in    std_logic;
    ld_g_i      : in    unsigned(1 downto 0);
    ld_m1_i     : in    signed(15 downto 0);
    ld_m2_i     : in    signed(15 downto 0);
    ld_c1_i     : in    signed(15 downto 0);
    ld_c12_i    : in    signed(15 downto 0);
    ld_c2_i     : in    signed(15 downto 0);
    req_reset_i : in    std_logic;             -- reset P before the next update
    lambda_k_i  : in    unsigned(4 downto 0);  -- lambda = 1/(1 + 2**-k)
    kappa_i     : in    unsigned(15 downto 0); -- u8.8 (0 is taken as 1/256)
    kappa5_i    : in    unsigned(14 downto 0); -- u11.4 5 max(kappa, 1/256) >> 4
    period_i    : in    unsigned(15 downto 0); -- updates between resets, 0 never
    settle_i    : in    unsigned(9 downto 0);  -- updates after a reset to commit
    gate_i      : in    unsigned(12 downto 0); -- u13 phase progress per update
    jump_on_i   : in    std_logic;             -- jump detector enabled
    jump_min_i  : in    unsigned(10 downto 0); -- its floor, u0.13
    -- the committed bundle
    g_o       : out   unsigned(1 downto 0);  -- input gain 2**g
    m1_o      : out   signed(15 downto 0);   -- s1.15 offsets
    m2_o      : out   signed(15 downto 0);
    c1_o      : out   signed(15 downto 0);   -- s4.12 coefficients (Eq. 9)
    c12_o     : out   signed(15 downto 0);
    c2_o      : out   signed(15 downto 0);
    uncal_o   : out   std_logic;             -- no estimate committed yet
    hold_o    : out   std_logic;             -- the last estimate was invalid
    loaded_o  : out   std_logic;             -- the bundle was loaded
    ref_o     : out   std_logic;             -- the bundle is a calibration
    updates_o : out   unsigned(31 downto 0); -- updates run (wraps)
    jumps_o   : out   unsigned(15 downto 0); -- jumps detected (wraps)
    sat_o     : out   std_logic;             -- engine saturated (sticky)
    -- OPT_EXT_ENGINE = 1: the shared engine (see eng_cmd_t, eng_rsp_t below)
    tdm_ok_i  : in    std_logic; -- a program may be decided now
    eng_cmd_o : out   std_logic_vector(65 downto 0);
    eng_rsp_i : in    std_logic_vector(114 downto 0)
  );
end entity estimator;

architecture rtl of estimator is

  -- ---- the bundle and the engine's command and response ------------------------------------
  type bundle_t is record
    g   : unsigned(1 downto 0);
    m1  : signed(15 downto 0);
    m2  : signed(15 downto 0);
    c1  : signed(15 downto 0);
    c12 : signed(15 downto 0);
    c2  : signed(15 downto 0);
  end record bundle_t;

  constant BUNDLE_INIT : bundle_t :=
  (
    g   => to_unsigned(G_INIT, 2),
    m1  => (others => '0'),
    m2  => (others => '0'),
    c1  => to_signed(8192, 16),
    c12 => (others => '0'),
    c2  => to_signed(8192, 16)
  );

  -- The command (eng_cmd_o, registered; the engine starts on the edge after the
  -- decision and latches the rest with start): {start, entry, x1, x2, lambda_k, freeze,
  -- kappa, dg}.
  type eng_cmd_t is record
    start    : std_logic;
    entry    : rls_entry_t;
    x1       : signed(15 downto 0);   -- s1.15
    x2       : signed(15 downto 0);   -- s1.15
    lambda_k : unsigned(4 downto 0);
    freeze   : std_logic;
    kappa    : unsigned(15 downto 0); -- u8.8
    dg       : signed(2 downto 0);
  end record eng_cmd_t;

  function pack (c : eng_cmd_t) return std_logic_vector is
  begin

    return c.start & std_logic_vector(c.entry) & std_logic_vector(c.x1)
           & std_logic_vector(c.x2) & std_logic_vector(c.lambda_k) & c.freeze
           & std_logic_vector(c.kappa) & std_logic_vector(c.dg);

  end function pack;

  -- The response (eng_rsp_i): {sat (this axis's sticky bit), done, valid, out}; out
  -- (the OUT registers {tr, e, c2, c12, c1, m2, m1}) is read only on this axis's done.
  type eng_rsp_t is record
    sat   : std_logic;
    done  : std_logic;
    valid : std_logic;
    outs  : std_logic_vector(111 downto 0);
  end record eng_rsp_t;

  -- the engine's OUT m1 .. c2 as a bundle of gain g
  function to_bundle (outs : std_logic_vector(111 downto 0); g : unsigned(1 downto 0))
    return bundle_t is
  begin

    return (g   => g,
            m1  => signed(outs(15 downto 0)),
            m2  => signed(outs(31 downto 16)),
            c1  => signed(outs(47 downto 32)),
            c12 => signed(outs(63 downto 48)),
            c2  => signed(outs(79 downto 64)));

  end function to_bundle;

  -- ---- the dither's span (rtl/estimator.v, "the dither") --------------------------------
  function dither_span return integer is

    variable span : integer;

  begin

    if OPT_EXT_ENGINE = 1 and EXT_PERIOD /= 0 then
      span := EXT_PERIOD;
    elsif ENGINE_LANES = 2 then
      span := CYCLES_UPDATE_2 + 1;
    else
      span := CYCLES_UPDATE_1 + 1;
    end if;

    span := span - (PH_DELAY + 2);
    assert span >= 1 and span <= 32767
      report "estimator: the dither span " & integer'image(span) & " is not in 1..32767"
      severity failure;
    return span;

  end function dither_span;

  constant DSPAN_I  : positive                      := dither_span;
  constant SKIP_W   : positive                      := clog2(DSPAN_I + 1);
  constant DSPAN    : unsigned(SKIP_W - 1 downto 0) := to_unsigned(DSPAN_I, SKIP_W);
  constant SKIP_TOP : unsigned(SKIP_W - 1 downto 0) := to_unsigned(2 ** (SKIP_W - 1), SKIP_W);
  constant LFSR_0   : unsigned(15 downto 0)         := x"ACE1";

  -- the update count's width: with constant tuning it only needs to reach WARMUP
  function upd_width return positive is
  begin

    if OPT_TUNABLE = 1 then
      return 16;
    end if;

    return clog2(WARMUP + 1);

  end function upd_width;

  constant UPD_W     : positive             := upd_width;
  constant COVER_WIN : unsigned(7 downto 0) := x"FF";

  -- ---- the candidate's checks -----------------------------------------------------------
  -- u << g leaves 16 bits exactly when the top g + 1 bits of u differ (top = u(15..12))
  function ovf (top : signed(3 downto 0); g : unsigned(1 downto 0)) return boolean is
  begin

    -- (if, not case: GHDL 2.0's Verilog writer drops a case's others, README.md)
    if g = "00" then
      return false;
    elsif g = "01" then
      return top(3) /= top(2);
    elsif g = "10" then
      return top(3 downto 1) /= "111" and top(3 downto 1) /= "000";
    end if;

    return top /= "1111" and top /= "0000";

  end function ovf;

  -- The travel gate: |dtr| >= gate with dtr = travel - last (s20, the travel since the
  -- last update), gate u13: dtr >= gate or dtr <= -gate (two compares side by side; with
  -- a constant gate on offset-binary values, bit by bit).
  function gate_chk (
    travel : unsigned(19 downto 0);
    last : unsigned(19 downto 0);
    gate : unsigned(12 downto 0)
  ) return boolean is

    constant OFS    : unsigned(19 downto 0) := x"80000";
    variable dtr    : unsigned(19 downto 0);
    variable gate20 : unsigned(19 downto 0);
    variable ngate  : unsigned(19 downto 0);

  begin

    dtr    := travel - last;
    gate20 := resize(gate, 20);
    ngate  := 0 - gate20;

    if OPT_TUNABLE = 1 then
      return signed(dtr) >= signed(gate20) or signed(dtr) <= -signed(gate20);
    end if;

    return geu(dtr xor OFS, gate20 xor OFS) or geu(ngate xor OFS, dtr xor OFS);

  end function gate_chk;

  -- |v| (-2**(w-1) stays as it is: read it as unsigned)
  function magnitude (v : signed) return signed is
  begin

    if v(v'high) = '1' then
      return -v;
    end if;

    return v;

  end function magnitude;

  -- The coverage octant of the candidate's raw codes: {u2 < 0, u1 < 0, |u1| < |u2|}.
  function octant (u1 : signed(15 downto 0); u2 : signed(15 downto 0)) return unsigned is

    variable m1 : unsigned(16 downto 0); -- u17 |u1|, |u2| (-32768 -> 32768)
    variable m2 : unsigned(16 downto 0);

  begin

    m1 := unsigned(magnitude(resize(u1, 17)));
    m2 := unsigned(magnitude(resize(u2, 17)));
    return u2(15) & u1(15) & to_sl(m1 < m2);

  end function octant;

  -- Gain for the next reset: the largest g <= 3 with peak << g < 2**14 (2x headroom); g
  -- when no sample was seen.
  function gsel (pk : unsigned(14 downto 0); g : unsigned(1 downto 0)) return unsigned is
  begin

    if pk = 0 then
      return g;
    elsif pk(14 downto 11) = 0 then
      return "11";
    elsif pk(14 downto 12) = 0 then
      return "10";
    elsif pk(14 downto 13) = 0 then
      return "01";
    end if;

    return "00";

  end function gsel;

  -- ---- the sample bookkeeping and the control state ----------------------------------------
  signal g_eng           : unsigned(1 downto 0)         := to_unsigned(G_INIT, 2);
  signal peak            : unsigned(14 downto 0)        := (others => '0');
  signal reset_pend      : std_logic                    := '1';
  signal first           : std_logic                    := '1';
  signal upd             : unsigned(UPD_W - 1 downto 0) := (others => '0'); -- since a reset
  signal upd1            : unsigned(16 downto 0);
  signal settle          : unsigned(9 downto 0)         := (others => '0');
  signal s_last          : unsigned(19 downto 0)        := (others => '0'); -- travel then
  signal running_update  : std_logic                    := '0';
  signal running_extract : std_logic                    := '0';
  signal freeze          : std_logic                    := '0';             -- trace bound
  signal busy            : std_logic                    := '0';             -- a program runs
  signal slot_pend       : std_logic                    := '0';             -- awaits check
  signal slot_rdy        : std_logic                    := '0';             -- awaits engine

  -- ---- the dither ---------------------------------------------------------------------------
  signal lfsr : unsigned(15 downto 0)         := LFSR_0; -- Galois, x^16+x^14+x^13+x^11+1
  signal dith : unsigned(SKIP_W - 1 downto 0);
  signal skip : unsigned(SKIP_W - 1 downto 0) := (others => '0');

  -- ---- arrival ------------------------------------------------------------------------------
  signal pend     : std_logic;
  signal tdm_ok   : std_logic;
  signal do_reset : std_logic;
  signal do_cand  : std_logic;
  signal cu1      : signed(15 downto 0)                     := (others => '0'); -- the candidate
  signal cu2      : signed(15 downto 0)                     := (others => '0');
  signal g_chk    : unsigned(1 downto 0)                    := to_unsigned(G_INIT, 2);
  signal cwait    : std_logic_vector(PH_DELAY - 1 downto 0) := (others => '0');
  signal ph_cand  : std_logic;

  -- ---- the check, registered one edge before the decision ----------------------------------
  signal pre_valid : std_logic             := '0';
  signal pre_xsat  : std_logic             := '0';
  signal pre_gate  : std_logic             := '0';
  signal pre_bad   : std_logic             := '0';
  signal pre_oct   : unsigned(2 downto 0)  := (others => '0');
  signal cand_s    : unsigned(19 downto 0) := (others => '0');
  signal pre_pass  : std_logic;

  -- ---- the decisions and the engine ---------------------------------------------------------
  signal x1w         : signed(15 downto 0);                     -- s1.15 the candidate << g_eng
  signal x2w         : signed(15 downto 0);
  signal lambda_k    : unsigned(4 downto 0);                    -- 1..23
  signal kappa       : unsigned(15 downto 0);
  signal cmd         : eng_cmd_t;
  signal rsp         : eng_rsp_t;
  signal start_q     : std_logic            := '0';
  signal entry_q     : rls_entry_t          := (others => '0');
  signal dg_q        : signed(2 downto 0)   := (others => '0');
  signal oct_seen    : unsigned(7 downto 0) := (others => '0'); -- since the last commit
  signal cwin        : unsigned(7 downto 0) := (others => '0'); -- updates in the window
  signal gain_pend   : std_logic            := '0';
  signal settled     : std_logic            := '0';
  signal do_update   : std_logic;
  signal do_extract  : std_logic;
  signal eng_free    : std_logic;
  signal cov_restart : std_logic;
  signal tr_hi       : std_logic;

  -- ---- the jump detector: u15.5 |e|, its fast and slow means ---------------------------------
  signal eabs    : unsigned(19 downto 0) := (others => '0');
  signal jf      : unsigned(19 downto 0) := (others => '0');
  signal jl      : unsigned(19 downto 0) := (others => '0');
  signal jf_next : unsigned(19 downto 0) := (others => '0');
  signal jl_next : unsigned(19 downto 0) := (others => '0');
  signal jthr    : unsigned(22 downto 0) := (others => '0'); -- u18.5 4 jl + jump_min
  signal armed   : std_logic             := '0';
  signal trig    : std_logic             := '0';

  -- ---- the outputs --------------------------------------------------------------------------
  -- the bundle's registers, one per field (GHDL 2.0's --out=verilog writes a non-zero
  -- value wider than 64 bits as a string)
  signal g_q       : unsigned(1 downto 0)  := BUNDLE_INIT.g;
  signal m1_q      : signed(15 downto 0)   := BUNDLE_INIT.m1;
  signal m2_q      : signed(15 downto 0)   := BUNDLE_INIT.m2;
  signal c1_q      : signed(15 downto 0)   := BUNDLE_INIT.c1;
  signal c12_q     : signed(15 downto 0)   := BUNDLE_INIT.c12;
  signal c2_q      : signed(15 downto 0)   := BUNDLE_INIT.c2;
  signal uncal     : std_logic             := '1';
  signal hold      : std_logic             := '0';
  signal loaded    : std_logic             := '0';
  signal updates_q : unsigned(31 downto 0) := (others => '0');
  signal jumps_q   : unsigned(15 downto 0) := (others => '0');

begin

  -- ---- arrival: a RESET program, the dither, or the sample becomes the candidate ---------
  pend     <= reset_pend or req_reset_i;
  tdm_ok   <= tdm_ok_i when OPT_EXT_ENGINE = 1 else
              '1';
  do_reset <= smp_valid_i and not busy and not slot_pend and not slot_rdy and pend and tdm_ok;
  do_cand  <= smp_valid_i and not slot_pend and not slot_rdy and not pend and to_sl(skip = 0);
  ph_cand  <= ph_valid_i and cwait(PH_DELAY - 1);
  dith     <= lfsr(SKIP_W - 1 downto 0) xor SKIP_TOP when lfsr(SKIP_W - 1 downto 0) > DSPAN else
              lfsr(SKIP_W - 1 downto 0);

  candidate : process (clk) is
  begin

    if rising_edge(clk) then
      cwait <= cwait(PH_DELAY - 2 downto 0) & do_cand;

      if do_cand = '1' then
        cu1   <= u1_i;
        cu2   <= u2_i;
        g_chk <= gsel(peak, g_eng);
      end if;

      -- the check's inputs, with the candidate's fine phase
      pre_valid <= ph_cand;

      if ph_cand = '1' then
        pre_oct  <= octant(cu1, cu2);
        cand_s   <= travel_i;
        pre_bad  <= excl_i;
        pre_xsat <= to_sl(ovf(cu1(15 downto 12), g_eng) or ovf(cu2(15 downto 12), g_eng));
        pre_gate <= to_sl(gate_chk(travel_i, s_last, gate_i));
      end if;

      if rst = '1' then
        cwait     <= (others => '0');
        pre_valid <= '0';
      end if;
    end if;

  end process candidate;

  -- ---- the decisions ----------------------------------------------------------------------
  pre_pass <= pre_valid and not pre_bad and not pre_xsat and pre_gate;
  eng_free <= not busy or (rsp.done and not do_extract);

  do_update  <= eng_free and (slot_rdy or pre_pass) and tdm_ok;
  do_extract <= rsp.done and running_update and rsp.valid and settled
                and to_sl(oct_seen = x"FF") and not trig;

  cov_restart <= do_reset or (rsp.done and running_update and trig)
                 or (rsp.done and running_extract and rsp.valid)
                 or (do_update and to_sl(cwin = COVER_WIN));

  lambda_k <= to_unsigned(1, 5) when lambda_k_i = 0 else
              to_unsigned(23, 5) when lambda_k_i > 23 else
              lambda_k_i;
  kappa    <= to_unsigned(1, 16) when kappa_i = 0 else
              kappa_i;
  x1w      <= shift_left(cu1, to_integer(g_eng));
  x2w      <= shift_left(cu2, to_integer(g_eng));

  -- settled: registered (settle and gain_pend hold for two edges before a decision;
  -- settle_i is taken one edge before it)
  decide : process (clk) is
  begin

    if rising_edge(clk) then
      if OPT_TUNABLE = 1 then
        settled <= to_sl(settle >= settle_i) and not gain_pend;
      else
        settled <= to_sl(geu(settle, settle_i)) and not gain_pend;
      end if;

      start_q <= do_reset or do_update or do_extract;

      if do_reset = '1' then
        entry_q <= ENTRY_RESET;
      elsif do_update = '1' then
        entry_q <= ENTRY_UPDATE;
      else
        entry_q <= ENTRY_EXTRACT;
      end if;

      if (do_reset or do_update or do_extract) = '1' then
        dg_q <= signed('0' & gsel(peak, g_eng)) - signed('0' & g_eng);
      end if;

      if (do_reset or do_update) = '1' then
        busy <= '1';
      elsif (rsp.done and not do_extract) = '1' then
        busy <= '0';
      end if;

      if do_cand = '1' then
        slot_pend <= '1';
      elsif pre_valid = '1' then
        slot_pend <= '0';
      end if;

      if (pre_pass and not do_update) = '1' then
        slot_rdy <= '1';
      elsif do_update = '1' then
        slot_rdy <= '0';
      end if;

      if rst = '1' then
        start_q   <= '0';
        busy      <= '0';
        slot_pend <= '0';
        slot_rdy  <= '0';
      end if;
    end if;

  end process decide;

  -- ---- the engine: inside, or outside through eng_cmd_o / eng_rsp_i -----------------------
  cmd.start    <= start_q;
  cmd.entry    <= entry_q;
  cmd.lambda_k <= lambda_k;
  cmd.freeze   <= freeze;
  cmd.kappa    <= kappa;
  cmd.dg       <= dg_q;

  g_ext : if OPT_EXT_ENGINE = 1 generate

    -- the shared engine starts one edge after the command: the sample registered
    signal x1_q : signed(15 downto 0) := (others => '0');
    signal x2_q : signed(15 downto 0) := (others => '0');

  begin

    sample_reg : process (clk) is
    begin

      if rising_edge(clk) then
        x1_q <= x1w;
        x2_q <= x2w;
      end if;

    end process sample_reg;

    cmd.x1 <= x1_q;
    cmd.x2 <= x2_q;

    eng_cmd_o <= pack(cmd);
    rsp       <=
    (
      sat   => eng_rsp_i(114),
      done  => eng_rsp_i(113),
      valid => eng_rsp_i(112),
      outs  => eng_rsp_i(111 downto 0)
    );

  end generate g_ext;

  g_int : if OPT_EXT_ENGINE = 0 generate

    signal sat : std_logic_vector(0 downto 0);

  begin

    -- the sample: the engine latches it with start_q, on the edge after the decision;
    -- the candidate and g_eng do not change on the decision edge, so it is the decided one
    cmd.x1 <= x1w;
    cmd.x2 <= x2w;

    u_engine : entity work.rls_engine(rtl)
      generic map (
        table_dir => TABLE_DIR,
        lanes     => ENGINE_LANES
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
        axis_i     => "0",
        busy_o     => open,
        done_o     => rsp.done,
        valid_o    => rsp.valid,
        out_o      => rsp.outs,
        sat_o      => sat
      );

    rsp.sat   <= sat(0);
    eng_cmd_o <= (others => '0');

  end generate g_int;

  sat_o <= rsp.sat;

  -- the trace bound: P's trace (OUT TR, s12.4) at or above 5 kappa holds the forgetting
  -- off for the next update
  trace_bound : process (all) is

    variable tr : signed(15 downto 0);

  begin

    tr := signed(rsp.outs(111 downto 96));

    if OPT_TUNABLE = 1 then
      tr_hi <= not tr(15) and to_sl(unsigned(tr(14 downto 0)) >= kappa5_i);
    else
      tr_hi <= not tr(15) and to_sl(geu(unsigned(tr(14 downto 0)), kappa5_i));
    end if;

  end process trace_bound;

  -- ---- the jump detector (sim/model/finequad_core.py), pipelined over three edges: OUT e
  -- is written long before the UPDATE's END, and jf, jl, armed change only on done ------
  jump_detector : process (clk) is

    variable e_mag : signed(15 downto 0);
    variable df    : signed(20 downto 0);
    variable dl    : signed(20 downto 0);

  begin

    if rising_edge(clk) then
      e_mag := magnitude(signed(rsp.outs(95 downto 80)));   -- -32768: 0x8000, saturated
      df    := signed('0' & eabs) - signed('0' & jf);
      dl    := signed('0' & eabs) - signed('0' & jl);

      if e_mag(15) = '1' then
        eabs <= x"FFFE0";
      else
        eabs <= unsigned(e_mag(14 downto 0)) & "00000";
      end if;

      jf_next <= jf + unsigned(resize(df(20 downto 2), 20));
      jl_next <= jl + unsigned(resize(dl(20 downto 6), 20));
      jthr    <= ('0' & jl & "00") + resize(jump_min_i & "00000", 23);
      trig    <= armed and jump_on_i and to_sl(resize(jf_next, 23) > jthr);
    end if;

  end process jump_detector;

  -- ---- the bookkeeping, the coverage, the programs' ends and the hand-over -----------------
  upd1 <= resize(upd, 17) + 1;

  control : process (clk) is

    variable seen : unsigned(7 downto 0);
    variable bnd  : bundle_t;

  begin

    if rising_edge(clk) then
      -- sample bookkeeping
      if smp_valid_i = '1' and amax_i > peak then
        peak <= amax_i;
      end if;

      reset_pend <= pend;

      if do_reset = '1' then
        g_eng      <= gsel(peak, g_eng);
        peak       <= (others => '0');
        reset_pend <= '0';
        upd        <= (others => '0');
        settle     <= (others => '0');
      end if;

      -- the octants covered: restarted by a reset, a jump, a hand-over, or an update
      -- finding the window full; an update starting on this edge adds its own
      if cov_restart = '1' then
        seen := (others => '0');
        cwin <= "0000000" & do_update;
      else
        seen := oct_seen;

        if do_update = '1' then
          cwin <= cwin + 1;
        end if;
      end if;

      if do_update = '1' then
        seen := seen or shift_left(to_unsigned(1, 8), to_integer(pre_oct));
      end if;

      oct_seen <= seen;

      -- an update runs from its decision to its END
      if do_update = '1' then
        running_update <= '1';
      elsif (rsp.done and running_update) = '1' then
        running_update <= '0';
      end if;

      if (pre_valid and not pre_bad and pre_xsat) = '1' then
        reset_pend <= '1';
      end if;

      if skip /= 0 then
        skip <= skip - 1;
      end if;

      if do_update = '1' then
        gain_pend <= first and to_sl(g_chk /= g_eng);
        s_last    <= cand_s;
        skip      <= dith;
        lfsr      <= ('0' & lfsr(15 downto 1)) xor (x"B400" and (15 downto 0 => lfsr(0)));
        upd       <= upd + 1;
        updates_q <= updates_q + 1;

        -- the warm-up's gain check after WARMUP updates, then every period_i updates
        if first = '1' and geu(upd1, WARMUP) then
          if g_chk /= g_eng then
            reset_pend <= '1';
          end if;

          first <= '0';
        elsif OPT_TUNABLE = 1 and first = '0' and period_i /= 0 and upd1 >= period_i then
          reset_pend <= '1';
        end if;
      end if;

      -- the end of an update: the trace bound, the jump detector, an invalid update
      if (rsp.done and (running_update or not running_extract)) = '1' then
        freeze <= tr_hi;
      end if;

      if (rsp.done and running_update) = '1' then
        if trig = '1' then
          reset_pend <= '1';
          armed      <= '0';
          jf         <= jl;
          jumps_q    <= jumps_q + 1;
        else
          jf <= jf_next;

          if (armed or uncal) = '1' then
            jl <= jl_next;
          end if;
        end if;

        if rsp.valid = '0' then
          reset_pend <= '1';
        end if;

        running_extract <= do_extract;

        if settle /= 16#3FF# then
          settle <= settle + 1;
        end if;
      end if;

      -- the bundle (bnd: its next value): a LOAD, a hand-over on the same edge overrides it
      bnd := (g => g_q, m1 => m1_q, m2 => m2_q, c1 => c1_q, c12 => c12_q, c2 => c2_q);

      if load_i = '1' then
        bnd    :=
        (
          g => ld_g_i,
          m1 => ld_m1_i,
          m2 => ld_m2_i,
          c1 => ld_c1_i,
          c12 => ld_c12_i,
          c2 => ld_c2_i
        );
        loaded <= '1';
      end if;

      -- the end of an extraction: the hand-over if theta was an ellipse
      if (rsp.done and running_extract) = '1' then
        if rsp.valid = '1' then
          bnd    := to_bundle(rsp.outs, g_eng);
          uncal  <= '0';
          loaded <= '0';
          armed  <= '1';
        end if;

        hold            <= not rsp.valid;
        running_extract <= '0';
      end if;

      g_q   <= bnd.g;
      m1_q  <= bnd.m1;
      m2_q  <= bnd.m2;
      c1_q  <= bnd.c1;
      c12_q <= bnd.c12;
      c2_q  <= bnd.c2;

      -- rst restarts the control state; theta in the engine and g_eng survive it
      if rst = '1' then
        peak            <= (others => '0');
        reset_pend      <= '1';
        first           <= '1';
        gain_pend       <= '0';
        upd             <= (others => '0');
        settle          <= (others => '0');
        s_last          <= (others => '0');
        skip            <= (others => '0');
        lfsr            <= LFSR_0;
        oct_seen        <= (others => '0');
        cwin            <= (others => '0');
        running_update  <= '0';
        running_extract <= '0';
        freeze          <= '0';
        jf              <= (others => '0');
        jl              <= (others => '0');
        armed           <= '0';
        jumps_q         <= (others => '0');
        g_q             <= BUNDLE_INIT.g;
        m1_q            <= BUNDLE_INIT.m1;
        m2_q            <= BUNDLE_INIT.m2;
        c1_q            <= BUNDLE_INIT.c1;
        c12_q           <= BUNDLE_INIT.c12;
        c2_q            <= BUNDLE_INIT.c2;
        uncal           <= '1';
        hold            <= '0';
        loaded          <= '0';
        updates_q       <= (others => '0');
      end if;
    end if;

  end process control;

  g_o       <= g_q;
  m1_o      <= m1_q;
  m2_o      <= m2_q;
  c1_o      <= c1_q;
  c12_o     <= c12_q;
  c2_o      <= c2_q;
  uncal_o   <= uncal;
  hold_o    <= hold;
  loaded_o  <= loaded;
  ref_o     <= not uncal or loaded;
  updates_o <= updates_q;
  jumps_o   <= jumps_q;

end architecture rtl;
