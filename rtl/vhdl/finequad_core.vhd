-- finequad_core: the single-axis adaptive quadrature interpolator (VHDL edition of
-- rtl/finequad_core.v, whose header gives the data flow, the latencies and the fault
-- bits in full; bit-true model sim/model/finequad_core.py). One sample per clock.
--
-- Blocks, by the edge after the strobe edge t that registers their output:
--   t .. t+2 correct, t+3 .. t+5 octant, t+5 .. t+6 lut's phase table with harmonic (or
--   phase), t+6 .. t+7 monitor, t+7 .. t+8 lut's n * phase and counter (m_count,
--   m_valid, m_fault after t + 8), t+9 pulse, t+9 .. t+10 refmark, dcode and abgen (A/B,
--   Z, m_ref_count, m_homed, m_pos_valid after t + 10); the estimator beside them.
-- Register port: reg_we writes reg_wdata to word reg_addr on the edge unless reg_err (a
-- combinational verdict, fq_write_ok of finequad_regs_pkg) refuses it; reg_re reads
-- reg_addr into reg_rdata on the edge. Map: rtl/regs/finequad.rdl.
-- Formats: s_u1, s_u2 s(ADC_W) codes, MSB-aligned to s1.15; m_count, m_ref_count
-- s(COUNT_W) counts (4 n per signal period, wraps); m_fault the FAULT_STICKY bits;
-- eng_cmd_o, eng_rsp_i the shared engine's command and response (rtl/estimator.v).
-- Power-up values are those after rst.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;
  use work.finequad_regs_pkg.all;

entity finequad_core is
  generic (
    TABLE_DIR : string := "rtl/tables/";
    -- ADC word width, two's complement, MSB-aligned to s1.15 internally
    ADC_W : integer range 12 to 16 := 16;
    -- sine table word width: 8, 10, 12 or 16
    SIN_W : integer range 8 to 16 := 10;
    -- counter width
    COUNT_W : integer range 17 to 32 := 32;
    -- 1: exact table, 0: the paper's uniform table
    TABLE_EXACT : integer range 0 to 1 := 1;
    -- input gain after power-up
    G_INIT : integer range 0 to 3 := 0;
    -- 1: the n * phase product in a DSP block; 0: in logic
    OPT_NTH_DSP : integer range 0 to 1 := 1;
    -- 1: adaptive harmonic compensation (harmonic); 0: none (phase; HARM reads 0)
    OPT_HARMONIC : integer range 0 to 1 := 1;
    -- 1: the harmonic table and the fault flags' delay in flip-flops / distributed RAM;
    -- 0: block RAM
    OPT_DISTRAM : integer range 0 to 1 := 0;
    -- 1: the exact phase table in 4096 rows per octant sign (lut)
    OPT_PHASE_4K : integer range 0 to 1 := 0;
    -- 1: ECP5 MULT18X18D blocks in octant and lut (synthesis only)
    OPT_ECP5_MULT : integer range 0 to 1 := 0;
    -- 1: Eq. 12 on the sine table's address side (pulse OPT_ADDR)
    OPT_PULSE_ADDR : integer range 0 to 1 := 0;
    -- 1: every setting is a register; 0: the tuning registers keep their reset values
    OPT_TUNABLE : integer range 0 to 1 := 1;
    -- 1: the signal monitor's fault checks; 0: none (RADIUS, MONITOR, COAST read 0)
    OPT_MONITOR : integer range 0 to 1 := 1;
    -- 1: the estimator's jump detector; 0: none (JUMP reads disabled, JUMPS 0)
    OPT_JUMP : integer range 0 to 1 := 1;
    -- 1: distance-coded reference marks (dcode); 0: none
    OPT_DCODE : integer range 0 to 1 := 1;
    -- lanes of the estimator's RLS engine
    ENGINE_LANES : integer range 1 to 2 := 1;
    -- 1: the RLS engine outside, shared (finequad_multi); 0: inside
    OPT_EXT_ENGINE : integer range 0 to 1 := 0;
    -- with OPT_EXT_ENGINE: the axis's window period in clocks; 0: one axis
    EXT_PERIOD : integer range 0 to integer'high := 0
  );
  port (
    clk : in    std_logic;
    rst : in    std_logic; -- sync, active high
    -- sample stream
    s_valid : in    std_logic;
    s_u1    : in    signed(ADC_W - 1 downto 0); -- s(ADC_W) codes
    s_u2    : in    signed(ADC_W - 1 downto 0);
    s_ref   : in    std_logic;                  -- the reference input
    -- register port
    reg_we    : in    std_logic;
    reg_re    : in    std_logic;
    reg_addr  : in    unsigned(5 downto 0);          -- word index
    reg_wdata : in    std_logic_vector(31 downto 0);
    reg_rdata : out   std_logic_vector(31 downto 0); -- registered
    reg_err   : out   std_logic;                     -- the write is refused
    -- per-sample results
    m_valid : out   std_logic;
    m_count : out   signed(COUNT_W - 1 downto 0);  -- s(COUNT_W) counts
    m_fault : out   std_logic_vector(10 downto 0); -- FAULT_STICKY's bits
    -- A/B outputs (paced quadrature or the Eq. 12 pulses)
    m_a : out   std_logic;
    m_b : out   std_logic;
    -- reference marks (REF_COUNT, REF_STATUS.homed, REF_STATUS.pos_valid)
    m_z         : out   std_logic;
    m_ref_count : out   signed(COUNT_W - 1 downto 0);
    m_homed     : out   std_logic;
    m_pos_valid : out   std_logic;
    -- shared RLS engine (OPT_EXT_ENGINE = 1; formats: rtl/estimator.v)
    tdm_ok_i  : in    std_logic;
    eng_cmd_o : out   std_logic_vector(65 downto 0);
    eng_rsp_i : in    std_logic_vector(114 downto 0)
  );
end entity finequad_core;

architecture rtl of finequad_core is

  constant LATENCY : positive := 8;
  -- magnitudes registered on edge t + CORR_AT
  constant CORR_AT : positive := 2;
  -- fine phase registered on edge t + PHASE_AT
  constant PHASE_AT : positive := 6;

  subtype count_t is signed(COUNT_W - 1 downto 0);

  subtype fault_t is std_logic_vector(FQ_FAULT_W - 1 downto 0);

  -- u11.4 5 max(kappa, 1/256) >> 4: the estimator's trace bound, formed with the write
  -- (u19 5 kappa needs 19 bits: 5 * 65535 = 327675)
  function kappa5 (k : unsigned(15 downto 0)) return unsigned is

    variable kk : unsigned(18 downto 0);

  begin

    kk := resize(k, 19);

    if k = 0 then
      kk := to_unsigned(1, 19);
    end if;

    return resize(shift_right(kk + shift_left(kk, 2), 4), 15);

  end function kappa5;

  -- the bits lsb + w - 1 .. lsb of a written word
  function field (d : fq_word_t; lsb : natural; w : positive) return unsigned is
  begin

    return unsigned(d(lsb + w - 1 downto lsb));

  end function field;

  function to_bool (i : integer) return boolean is
  begin

    return i /= 0;

  end function to_bool;

  constant OPTIONS : fq_options_t :=
  (
    OPT_DCODE    => to_bool(OPT_DCODE),
    OPT_HARMONIC => to_bool(OPT_HARMONIC),
    OPT_JUMP     => to_bool(OPT_JUMP),
    OPT_MONITOR  => to_bool(OPT_MONITOR),
    OPT_TUNABLE  => to_bool(OPT_TUNABLE)
  );

  -- The settings: every register a write sets (widths and resets from the map).
  type settings_t is record
    interp     : n_t;                                           -- n
    eps        : unsigned(FQ_EPS_EPS_W - 1 downto 0);           -- u0.15 Eq. 12
    lambda_k   : unsigned(FQ_LAMBDA_K_LAMBDA_K_W - 1 downto 0); -- 1/(1 + 2**-k)
    kappa      : unsigned(FQ_KAPPA_KAPPA_W - 1 downto 0);       -- u8.8
    kappa5     : unsigned(14 downto 0);                         -- u11.4 kappa5(kappa)
    period     : unsigned(FQ_PERIOD_PERIOD_W - 1 downto 0);     -- updates per reset
    settle     : unsigned(FQ_SETTLE_SETTLE_W - 1 downto 0);     -- before a hand-over
    gate       : unsigned(FQ_GATE_GATE_W - 1 downto 0);         -- u13 travel gate
    jump_off   : std_logic;
    jump_min   : unsigned(FQ_JUMP_JUMP_MIN_W - 1 downto 0);     -- u0.13 of |e|
    count_mode : std_logic;                                     -- 0 phase, 1 edge
    harm_apply : std_logic;
    harm_learn : std_logic;
    harm_mu    : unsigned(FQ_HARM_HARM_MU_W - 1 downto 0);      -- 2^-(3 + mu), gear 0
    ab_sep     : unsigned(FQ_ABGEN_AB_SEP_W - 1 downto 0);      -- clocks per edge
    ab_src     : std_logic;                                     -- 1: Eq. 12 pulses
    ab_bound   : unsigned(FQ_AB_BOUND_AB_BOUND_W - 1 downto 0); -- counts
    clip       : unsigned(FQ_CLIP_CLIP_W - 1 downto 0);         -- |u| clipped at
    loss       : unsigned(FQ_RADIUS_LOSS_W - 1 downto 0);       -- s2.14 radius
    over       : unsigned(FQ_RADIUS_OVER_W - 1 downto 0);       -- s2.14 radius
    glitch_k   : unsigned(FQ_MONITOR_GLITCH_K_W - 1 downto 0);  -- 2^K
    stuck_n    : unsigned(FQ_MONITOR_STUCK_N_W - 1 downto 0);   -- samples
    code_step  : unsigned(FQ_MONITOR_CODE_STEP_W - 1 downto 0); -- 2^k LSBs
    floor      : unsigned(FQ_COAST_FLOOR_W - 1 downto 0);       -- s2.14 radius
    coast_acc  : unsigned(FQ_COAST_COAST_ACC_W - 1 downto 0);   -- u0.12
    ref_q      : unsigned(FQ_REF_REF_Q_W - 1 downto 0);         -- counts, 0 .. 4n - 1
    ref_filt   : unsigned(FQ_REF_REF_FILT_W - 1 downto 0);      -- samples
    home       : signed(FQ_HOME_HOME_COUNT_W - 1 downto 0);     -- s32
    dc_spacing : unsigned(FQ_DCODE_DC_SPACING_W - 1 downto 0);  -- periods
    dc_coded   : unsigned(FQ_DCODE_DC_CODED_W - 1 downto 0);    -- periods
    dc_confirm : std_logic;
  end record settings_t;

  constant SETTINGS_RESET : settings_t :=
  (
    interp     => FQ_INTERP_INTERP_RESET,
    eps        => FQ_EPS_EPS_RESET,
    lambda_k   => FQ_LAMBDA_K_LAMBDA_K_RESET,
    kappa      => FQ_KAPPA_KAPPA_RESET,
    kappa5     => kappa5(FQ_KAPPA_KAPPA_RESET),
    period     => FQ_PERIOD_PERIOD_RESET,
    settle     => FQ_SETTLE_SETTLE_RESET,
    gate       => FQ_GATE_GATE_RESET,
    jump_off   => FQ_JUMP_JUMP_OFF_RESET,
    jump_min   => FQ_JUMP_JUMP_MIN_RESET,
    count_mode => FQ_CTRL_COUNT_MODE_RESET,
    harm_apply => FQ_HARM_HARM_APPLY_RESET,
    harm_learn => FQ_HARM_HARM_LEARN_RESET,
    harm_mu    => FQ_HARM_HARM_MU_RESET,
    ab_sep     => FQ_ABGEN_AB_SEP_RESET,
    ab_src     => FQ_ABGEN_AB_SRC_RESET,
    ab_bound   => FQ_AB_BOUND_AB_BOUND_RESET,
    clip       => FQ_CLIP_CLIP_RESET,
    loss       => FQ_RADIUS_LOSS_RESET,
    over       => FQ_RADIUS_OVER_RESET,
    glitch_k   => FQ_MONITOR_GLITCH_K_RESET,
    stuck_n    => FQ_MONITOR_STUCK_N_RESET,
    code_step  => FQ_MONITOR_CODE_STEP_RESET,
    floor      => FQ_COAST_FLOOR_RESET,
    coast_acc  => FQ_COAST_COAST_ACC_RESET,
    ref_q      => FQ_REF_REF_Q_RESET,
    ref_filt   => FQ_REF_REF_FILT_RESET,
    home       => FQ_HOME_HOME_COUNT_RESET,
    dc_spacing => FQ_DCODE_DC_SPACING_RESET,
    dc_coded   => FQ_DCODE_DC_CODED_RESET,
    dc_confirm => FQ_DCODE_DC_CONFIRM_RESET
  );

  -- The correction bundle: gain 2**g, s1.15 offsets, s4.12 coefficients (Eq. 9).
  type bundle_t is record
    g   : unsigned(1 downto 0);
    m1  : signed(15 downto 0);
    m2  : signed(15 downto 0);
    c1  : signed(15 downto 0);
    c12 : signed(15 downto 0);
    c2  : signed(15 downto 0);
  end record bundle_t;

  constant STAGED_RESET : bundle_t :=
  (
    g   => to_unsigned(G_INIT, 2),
    m1  => FQ_M1_M1_RESET(15 downto 0),
    m2  => FQ_M2_M2_RESET(15 downto 0),
    c1  => FQ_C1_C1_RESET(15 downto 0),
    c12 => FQ_C12_C12_RESET(15 downto 0),
    c2  => FQ_C2_C2_RESET(15 downto 0)
  );

  -- One-edge pulses a write makes.
  type requests_t is record
    cov_reset  : std_logic; -- CTRL.cov_reset
    load       : std_logic; -- CTRL.load: the staged bundle to the fast path
    capture    : std_logic; -- CTRL.capture
    harm_clear : std_logic; -- HARM.harm_clear
    home       : std_logic; -- REF.home
    inval      : std_logic; -- the count loses its scale: INTERP changed, or edge mode
    dc_inval   : std_logic; -- a DCODE write changed the layout
  end record requests_t;

  constant NO_REQUESTS : requests_t := (others => '0');

  -- correct's outputs: the aligned sample (t) and the magnitudes (t + CORR_AT)
  type corrected_t is record
    v0    : std_logic;
    raw1  : signed(15 downto 0);   -- s1.15 aligned codes
    raw2  : signed(15 downto 0);
    amax  : unsigned(14 downto 0); -- u15 max(|raw1|, |raw2|)
    clip  : std_logic;
    nsat  : std_logic;
    dsat  : std_logic;
    valid : std_logic;
    ax    : unsigned(14 downto 0); -- u15 |u1c|, s2.14 units
    ay    : unsigned(14 downto 0);
    xn    : std_logic;
    yn    : std_logic;
    zl    : unsigned(3 downto 0);
    rsat  : std_logic;
  end record corrected_t;

  -- octant's outputs (t + 5)
  type octant_out_t is record
    valid : std_logic;
    j     : unsigned(10 downto 0); -- u11 octant-local address
    t     : unsigned(11 downto 0); -- u12 its scale
    oct2  : unsigned(1 downto 0);
    neg   : std_logic;
  end record octant_out_t;

  -- lut's n-th order outputs: the product (t + 7), the sines (t + 8)
  type nth_t is record
    n_valid : std_logic;
    prod    : prod_t;                -- u22 n * phase
    valid   : std_logic;
    pn      : phase_t;               -- u13 n-th order phase
    cmag    : unsigned(SIN_W - 2 downto 0);
    cneg    : std_logic;
    smag    : unsigned(SIN_W - 2 downto 0);
    sneg    : std_logic;
    ck      : unsigned(10 downto 0); -- u11 table addresses
    sk      : unsigned(10 downto 0);
  end record nth_t;

  -- monitor's outputs
  type monitor_out_t is record
    hold   : std_logic;
    excl   : std_logic;
    coast  : std_logic;
    line   : phase_t;               -- u13
    loss   : std_logic;
    over   : std_logic;
    stuck  : std_logic;
    glitch : std_logic;
    lost   : std_logic;
    travel : unsigned(19 downto 0); -- u20
  end record monitor_out_t;

  -- counter's outputs (t + 8)
  type counter_out_t is record
    valid     : std_logic;
    count     : count_t; -- before the homing offset
    ovs       : std_logic;
    ill       : std_logic;
    ill_count : unsigned(15 downto 0);
    held      : std_logic;
  end record counter_out_t;

  -- refmark's outputs
  type refmark_out_t is record
    pa         : std_logic;
    pb         : std_logic;
    zp         : std_logic;
    target     : count_t;
    z_en       : std_logic;
    z_at       : count_t;
    cross      : std_logic;
    cdir       : std_logic;
    mark       : std_logic;
    x          : count_t;
    inv        : std_logic;
    off        : count_t;
    ref_count  : count_t;
    win        : std_logic;
    homed      : std_logic;
    pos_valid  : std_logic;
    home_armed : std_logic;
    latch      : std_logic;
    lost       : std_logic;
  end record refmark_out_t;

  -- dcode's outputs
  type dcode_out_t is record
    home      : std_logic;
    err       : std_logic;
    abs_valid : std_logic;
    off       : count_t;
    ref       : count_t;
    abs_count : count_t;
  end record dcode_out_t;

  -- abgen's outputs
  type abgen_out_t is record
    a       : std_logic;
    b       : std_logic;
    pos     : count_t;
    backlog : signed(15 downto 0);
    ovf     : std_logic;
    sticky  : std_logic;
    z       : std_logic;
  end record abgen_out_t;

  -- ---- registers -------------------------------------------------------------------------
  signal cfg       : settings_t                   := SETTINGS_RESET;
  signal staged    : bundle_t                     := STAGED_RESET;
  signal req       : requests_t                   := NO_REQUESTS;
  signal fault_stk : fault_t                      := (others => '0'); -- write 1 to clear
  signal ref_stk   : std_logic_vector(2 downto 0) := "000";           -- {dc_err, lost, latched}
  signal capture   : count_t                      := (others => '0'); -- CTRL.capture's count
  signal rdata_q   : fq_word_t                    := (others => '0');
  signal wr_take   : boolean;                                         -- the write is taken

  -- ---- the blocks' outputs ---------------------------------------------------------------
  signal bundle    : bundle_t;              -- the estimator's, on the fast path
  signal b_uncal   : std_logic;
  signal b_hold    : std_logic;
  signal b_loaded  : std_logic;
  signal b_ref     : std_logic;
  signal e_sat     : std_logic;
  signal e_upd     : unsigned(31 downto 0);
  signal e_jumps   : unsigned(15 downto 0);
  signal c         : corrected_t;
  signal o         : octant_out_t;
  signal l_ph      : unsigned(11 downto 0); -- u12 PH[j]
  signal h_valid   : std_logic;
  signal h_phase   : phase_t;               -- u13 fine phase (t + 6)
  signal h_phase_c : phase_t;               -- u13 corrected fine phase
  signal mon       : monitor_out_t;
  signal nth       : nth_t;
  signal p_valid   : std_logic;             -- Eq. 12 pulses (t + 9)
  signal p_a       : std_logic;
  signal p_b       : std_logic;
  signal k         : counter_out_t;
  signal rm        : refmark_out_t;
  signal dc        : dcode_out_t;
  signal ab        : abgen_out_t;
  signal dc_en     : std_logic;
  signal sv        : std_logic;             -- s_valid and not rst
  signal jump_on   : std_logic;
  signal count     : count_t;               -- m_count
  signal fault     : fault_t;               -- m_fault

  -- the monitor's verdict that a coast lost the travel (t + 7), beside the count (t + 8)
  signal k_lost : std_logic := '0';

  -- ---- fault bits carried with the sample ------------------------------------------------
  -- csat: the offset removal's saturation (t), joined by the correction's (t + CORR_AT)
  signal csat_d : std_logic_vector(LATENCY - 1 downto 0) := (others => '0');
  signal uncal0 : std_logic                              := '1';
  signal hold0  : std_logic                              := '0';
  signal ref0   : std_logic                              := '0';

  -- {ref, clip, nsat, uncal, hold} of edge t + 1, delayed to t + LATENCY
  subtype flags_t is std_logic_vector(4 downto 0);

  signal fl_in  : flags_t;
  signal fl_out : flags_t;
  signal fl_ref : std_logic; -- the sample's s_ref on t + 8
  -- the monitor's flags registered on t + 7: {glitch, stuck, over, loss}
  signal mon_q : std_logic_vector(3 downto 0) := (others => '0');

begin

  assert SIN_W = 8 or SIN_W = 10 or SIN_W = 12 or SIN_W = 16
    report "finequad_core: SIN_W must be 8, 10, 12 or 16"
    severity failure;

  assert FQ_FAULT_W = m_fault'length
    report "finequad_core: m_fault's width differs from FAULT_STICKY"
    severity failure;

  -- ---- register writes -------------------------------------------------------------------
  wr_take <= reg_we = '1' and fq_write_ok(reg_addr, reg_wdata, OPTIONS);
  reg_err <= reg_we and not to_sl(wr_take);

  reg_write : process (clk) is

    variable d         : fq_word_t;
    variable fault_clr : fault_t;
    variable ref_clr   : std_logic_vector(2 downto 0);

  begin

    if rising_edge(clk) then
      d   := reg_wdata;
      req <= NO_REQUESTS;

      if wr_take then
        -- (if, not case: GHDL 2.0's Verilog writer drops a case's others, README.md)
        if reg_addr = FQ_CTRL then
          req.cov_reset  <= d(FQ_CTRL_COV_RESET_LSB);
          req.load       <= d(FQ_CTRL_LOAD_LSB);
          req.capture    <= d(FQ_CTRL_CAPTURE_LSB);
          cfg.count_mode <= d(FQ_CTRL_COUNT_MODE_LSB);
          req.inval      <= d(FQ_CTRL_COUNT_MODE_LSB);
        elsif reg_addr = FQ_INTERP then
          cfg.interp <= field(d, FQ_INTERP_INTERP_LSB, FQ_INTERP_INTERP_W);
          req.inval  <= to_sl(field(d, FQ_INTERP_INTERP_LSB, FQ_INTERP_INTERP_W) /= cfg.interp);
        elsif reg_addr = FQ_REF then
          cfg.ref_q    <= field(d, FQ_REF_REF_Q_LSB, FQ_REF_REF_Q_W);
          cfg.ref_filt <= field(d, FQ_REF_REF_FILT_LSB, FQ_REF_REF_FILT_W);
          req.home     <= d(FQ_REF_HOME_LSB);
        elsif reg_addr = FQ_HOME then
          cfg.home <= signed(field(d, FQ_HOME_HOME_COUNT_LSB, FQ_HOME_HOME_COUNT_W));
        elsif reg_addr = FQ_DCODE then
          if OPT_DCODE = 1 then
            req.dc_inval   <= to_sl(field(d, FQ_DCODE_DC_SPACING_LSB, FQ_DCODE_DC_SPACING_W)
                                    /= cfg.dc_spacing or
                                    field(d, FQ_DCODE_DC_CODED_LSB, FQ_DCODE_DC_CODED_W)
                                    /= cfg.dc_coded);
            cfg.dc_spacing <= field(d, FQ_DCODE_DC_SPACING_LSB, FQ_DCODE_DC_SPACING_W);
            cfg.dc_coded   <= field(d, FQ_DCODE_DC_CODED_LSB, FQ_DCODE_DC_CODED_W);
            cfg.dc_confirm <= d(FQ_DCODE_DC_CONFIRM_LSB);
          end if;
        elsif reg_addr = FQ_GAIN then
          -- the staged bundle (the low 16 bits of the signed fields)
          staged.g <= field(d, FQ_GAIN_GAIN_LSB, FQ_GAIN_GAIN_W);
        elsif reg_addr = FQ_M1 then
          staged.m1 <= signed(field(d, FQ_M1_M1_LSB, 16));
        elsif reg_addr = FQ_M2 then
          staged.m2 <= signed(field(d, FQ_M2_M2_LSB, 16));
        elsif reg_addr = FQ_C1 then
          staged.c1 <= signed(field(d, FQ_C1_C1_LSB, 16));
        elsif reg_addr = FQ_C12 then
          staged.c12 <= signed(field(d, FQ_C12_C12_LSB, 16));
        elsif reg_addr = FQ_C2 then
          staged.c2 <= signed(field(d, FQ_C2_C2_LSB, 16));
        end if;
      end if;

      -- the tuning registers: constant with OPT_TUNABLE = 0 (fq_write_ok refuses their
      -- writes too; the generic here lets synthesis fold them)
      if wr_take and OPT_TUNABLE = 1 then
        -- (if, not case: GHDL 2.0's Verilog writer drops a case's others, README.md)
        if reg_addr = FQ_EPS then
          cfg.eps <= field(d, FQ_EPS_EPS_LSB, FQ_EPS_EPS_W);
        elsif reg_addr = FQ_LAMBDA_K then
          cfg.lambda_k <= field(d, FQ_LAMBDA_K_LAMBDA_K_LSB, FQ_LAMBDA_K_LAMBDA_K_W);
        elsif reg_addr = FQ_KAPPA then
          cfg.kappa  <= field(d, FQ_KAPPA_KAPPA_LSB, FQ_KAPPA_KAPPA_W);
          cfg.kappa5 <= kappa5(field(d, FQ_KAPPA_KAPPA_LSB, FQ_KAPPA_KAPPA_W));
        elsif reg_addr = FQ_PERIOD then
          cfg.period <= field(d, FQ_PERIOD_PERIOD_LSB, FQ_PERIOD_PERIOD_W);
        elsif reg_addr = FQ_SETTLE then
          cfg.settle <= field(d, FQ_SETTLE_SETTLE_LSB, FQ_SETTLE_SETTLE_W);
        elsif reg_addr = FQ_GATE then
          cfg.gate <= field(d, FQ_GATE_GATE_LSB, FQ_GATE_GATE_W);
        elsif reg_addr = FQ_HARM then
          cfg.harm_apply <= d(FQ_HARM_HARM_APPLY_LSB);
          cfg.harm_learn <= d(FQ_HARM_HARM_LEARN_LSB);
          cfg.harm_mu    <= field(d, FQ_HARM_HARM_MU_LSB, FQ_HARM_HARM_MU_W);
          req.harm_clear <= d(FQ_HARM_HARM_CLEAR_LSB);
        elsif reg_addr = FQ_JUMP then
          cfg.jump_off <= d(FQ_JUMP_JUMP_OFF_LSB);
          cfg.jump_min <= field(d, FQ_JUMP_JUMP_MIN_LSB, FQ_JUMP_JUMP_MIN_W);
        elsif reg_addr = FQ_ABGEN then
          cfg.ab_sep <= field(d, FQ_ABGEN_AB_SEP_LSB, FQ_ABGEN_AB_SEP_W);
          cfg.ab_src <= d(FQ_ABGEN_AB_SRC_LSB);
        elsif reg_addr = FQ_AB_BOUND then
          cfg.ab_bound <= field(d, FQ_AB_BOUND_AB_BOUND_LSB, FQ_AB_BOUND_AB_BOUND_W);
        elsif reg_addr = FQ_CLIP then
          cfg.clip <= field(d, FQ_CLIP_CLIP_LSB, FQ_CLIP_CLIP_W);
        elsif reg_addr = FQ_RADIUS then
          cfg.loss <= field(d, FQ_RADIUS_LOSS_LSB, FQ_RADIUS_LOSS_W);
          cfg.over <= field(d, FQ_RADIUS_OVER_LSB, FQ_RADIUS_OVER_W);
        elsif reg_addr = FQ_MONITOR then
          cfg.glitch_k  <= field(d, FQ_MONITOR_GLITCH_K_LSB, FQ_MONITOR_GLITCH_K_W);
          cfg.stuck_n   <= field(d, FQ_MONITOR_STUCK_N_LSB, FQ_MONITOR_STUCK_N_W);
          cfg.code_step <= field(d, FQ_MONITOR_CODE_STEP_LSB, FQ_MONITOR_CODE_STEP_W);
        elsif reg_addr = FQ_COAST then
          cfg.floor     <= field(d, FQ_COAST_FLOOR_LSB, FQ_COAST_FLOOR_W);
          cfg.coast_acc <= field(d, FQ_COAST_COAST_ACC_LSB, FQ_COAST_COAST_ACC_W);
        end if;
      end if;

      -- write 1 to clear; a fault arriving on the same edge stays set
      fault_clr := (others => '0');
      ref_clr   := "000";

      if wr_take and reg_addr = FQ_FAULT_STICKY then
        fault_clr := d(FQ_FAULT_W - 1 downto 0);
      end if;

      if wr_take and reg_addr = FQ_REF_STICKY then
        ref_clr := d(FQ_REF_STICKY_DC_ERR_LSB) & d(FQ_REF_STICKY_LOST_LSB) &
                   d(FQ_REF_STICKY_LATCHED_LSB);
      end if;

      fault_stk <= (fault_stk and not fault_clr) or (fault and (fault'range => k.valid));
      ref_stk   <= (ref_stk and not ref_clr) or (dc.err & rm.lost & rm.latch);

      if rst = '1' then
        cfg       <= SETTINGS_RESET;
        staged    <= STAGED_RESET;
        req       <= NO_REQUESTS;
        fault_stk <= (others => '0');
        ref_stk   <= "000";
      end if;
    end if;

  end process reg_write;

  -- ---- estimator: every sample on arrival (t), its fine phase PHASE_AT edges after -------
  jump_on <= to_sl(OPT_JUMP = 1) and not cfg.jump_off;

  u_est : entity work.estimator
    generic map (
      table_dir      => TABLE_DIR,
      g_init         => G_INIT,
      ph_delay       => PHASE_AT,
      engine_lanes   => ENGINE_LANES,
      opt_ext_engine => OPT_EXT_ENGINE,
      ext_period     => EXT_PERIOD,
      opt_tunable    => OPT_TUNABLE
    )
    port map (
      clk         => clk,
      rst         => rst,
      smp_valid_i => c.v0,
      u1_i        => c.raw1,
      u2_i        => c.raw2,
      amax_i      => c.amax,
      ph_valid_i  => h_valid,
      phase_i     => h_phase,
      excl_i      => mon.excl,
      travel_i    => mon.travel,
      load_i      => req.load,
      ld_g_i      => staged.g,
      ld_m1_i     => staged.m1,
      ld_m2_i     => staged.m2,
      ld_c1_i     => staged.c1,
      ld_c12_i    => staged.c12,
      ld_c2_i     => staged.c2,
      req_reset_i => req.cov_reset,
      lambda_k_i  => cfg.lambda_k,
      kappa_i     => cfg.kappa,
      kappa5_i    => cfg.kappa5,
      period_i    => cfg.period,
      settle_i    => cfg.settle,
      gate_i      => cfg.gate,
      jump_on_i   => jump_on,
      jump_min_i  => cfg.jump_min,
      g_o         => bundle.g,
      m1_o        => bundle.m1,
      m2_o        => bundle.m2,
      c1_o        => bundle.c1,
      c12_o       => bundle.c12,
      c2_o        => bundle.c2,
      uncal_o     => b_uncal,
      hold_o      => b_hold,
      loaded_o    => b_loaded,
      ref_o       => b_ref,
      updates_o   => e_upd,
      jumps_o     => e_jumps,
      sat_o       => e_sat,
      tdm_ok_i    => tdm_ok_i,
      eng_cmd_o   => eng_cmd_o,
      eng_rsp_i   => eng_rsp_i
    );

  -- ---- fast path: t .. t + 2 -------------------------------------------------------------
  sv <= s_valid and not rst;

  u_correct : entity work.correct
    generic map (
      adc_w => ADC_W
    )
    port map (
      clk      => clk,
      valid_i  => sv,
      u1_i     => s_u1,
      u2_i     => s_u2,
      clip_i   => cfg.clip,
      g_i      => bundle.g,
      m1_i     => bundle.m1,
      m2_i     => bundle.m2,
      c1_i     => bundle.c1,
      c12_i    => bundle.c12,
      c2_i     => bundle.c2,
      valid0_o => c.v0,
      raw1_o   => c.raw1,
      raw2_o   => c.raw2,
      amax_o   => c.amax,
      clip_o   => c.clip,
      nsat_o   => c.nsat,
      dsat_o   => c.dsat,
      valid_o  => c.valid,
      ax_o     => c.ax,
      ay_o     => c.ay,
      xn_o     => c.xn,
      yn_o     => c.yn,
      zl_o     => c.zl,
      rsat_o   => c.rsat
    );

  -- ---- t + 3 .. t + 5: octant ------------------------------------------------------------
  u_octant : entity work.octant
    generic map (
      table_dir     => TABLE_DIR,
      table_exact   => TABLE_EXACT,
      opt_ecp5_mult => OPT_ECP5_MULT
    )
    port map (
      clk     => clk,
      valid_i => c.valid,
      ax_i    => c.ax,
      ay_i    => c.ay,
      xn_i    => c.xn,
      yn_i    => c.yn,
      zl_i    => c.zl,
      valid_o => o.valid,
      j_o     => o.j,
      t_o     => o.t,
      oct2_o  => o.oct2,
      neg_o   => o.neg
    );

  -- ---- t + 5 .. t + 6: phase table and harmonic table, fine phase ------------------------

  g_harm : if OPT_HARMONIC = 1 generate

    u_harmonic : entity work.harmonic
      generic map (
        table_exact => TABLE_EXACT,
        opt_distram => OPT_DISTRAM
      )
      port map (
        clk       => clk,
        valid_i   => o.valid,
        oct2_i    => o.oct2,
        neg_i     => o.neg,
        t_i       => o.t,
        ph_i      => l_ph,
        apply_i   => cfg.harm_apply,
        learn_i   => cfg.harm_learn,
        mu_i      => cfg.harm_mu,
        clear_i   => req.harm_clear,
        valid_o   => h_valid,
        phase_o   => h_phase,
        phase_c_o => h_phase_c
      );

  else generate

    u_phase : entity work.phase
      port map (
        clk       => clk,
        valid_i   => o.valid,
        oct2_i    => o.oct2,
        neg_i     => o.neg,
        ph_i      => l_ph,
        valid_o   => h_valid,
        phase_o   => h_phase,
        phase_c_o => h_phase_c
      );

  end generate g_harm;

  -- ---- signal monitor: faults, the counter's hold (t + 6 .. t + 7), the travel -----------
  u_monitor : entity work.monitor
    generic map (
      opt_monitor => OPT_MONITOR,
      adc_w       => ADC_W
    )
    port map (
      clk         => clk,
      rst         => rst,
      sv_i        => sv,
      g_i         => bundle.g,
      c1_i        => bundle.c1,
      c2_i        => bundle.c2,
      code_step_i => cfg.code_step,
      valid0_i    => c.v0,
      raw1_i      => c.raw1,
      raw2_i      => c.raw2,
      clip_i      => c.clip,
      ref_i       => b_ref,
      ax_i        => c.ax,
      ay_i        => c.ay,
      xn_i        => c.xn,
      yn_i        => c.yn,
      pvalid_i    => h_valid,
      phase_i     => h_phase,
      loss_th_i   => cfg.loss,
      over_th_i   => cfg.over,
      glitch_k_i  => cfg.glitch_k,
      stuck_n_i   => cfg.stuck_n,
      floor_th_i  => cfg.floor,
      coast_acc_i => cfg.coast_acc,
      hold_o      => mon.hold,
      excl_o      => mon.excl,
      coast_o     => mon.coast,
      line_o      => mon.line,
      loss_o      => mon.loss,
      over_o      => mon.over,
      stuck_o     => mon.stuck,
      glitch_o    => mon.glitch,
      lost_o      => mon.lost,
      travel_o    => mon.travel
    );

  -- ---- t + 7 .. t + 8: n-th order phase and sines ----------------------------------------
  u_lut : entity work.lut
    generic map (
      table_dir     => TABLE_DIR,
      table_exact   => TABLE_EXACT,
      sin_w         => SIN_W,
      opt_nth_dsp   => OPT_NTH_DSP,
      opt_phase_4k  => OPT_PHASE_4K,
      opt_ecp5_mult => OPT_ECP5_MULT
    )
    port map (
      clk         => clk,
      j_i         => o.j,
      t_i         => o.t,
      neg_i       => o.neg,
      ph_o        => l_ph,
      valid_i     => h_valid,
      phase_i     => h_phase_c,
      n_i         => cfg.interp,
      nth_valid_o => nth.n_valid,
      prod_o      => nth.prod,
      valid_o     => nth.valid,
      pn_o        => nth.pn,
      cos_mag_o   => nth.cmag,
      cos_neg_o   => nth.cneg,
      sin_mag_o   => nth.smag,
      sin_neg_o   => nth.sneg,
      cos_k_o     => nth.ck,
      sin_k_o     => nth.sk
    );

  -- ---- t + 9: Eq. 12 pulses --------------------------------------------------------------
  u_pulse : entity work.pulse
    generic map (
      sin_w       => SIN_W,
      opt_tunable => OPT_TUNABLE,
      opt_addr    => OPT_PULSE_ADDR,
      table_dir   => TABLE_DIR
    )
    port map (
      clk       => clk,
      rst       => rst,
      valid_i   => nth.valid,
      cos_mag_i => nth.cmag,
      cos_neg_i => nth.cneg,
      cos_k_i   => nth.ck,
      sin_mag_i => nth.smag,
      sin_neg_i => nth.sneg,
      sin_k_i   => nth.sk,
      eps_i     => cfg.eps,
      valid_o   => p_valid,
      a_o       => p_a,
      b_o       => p_b
    );

  -- ---- t + 7 .. t + 8: counter -----------------------------------------------------------
  u_counter : entity work.counter
    generic map (
      count_w => COUNT_W
    )
    port map (
      clk         => clk,
      rst         => rst,
      valid_i     => h_valid,
      hold_i      => mon.hold,
      coast_i     => mon.coast,
      line_i      => mon.line,
      phase_i     => h_phase_c,
      prod_i      => nth.prod,
      n_i         => cfg.interp,
      mode_i      => cfg.count_mode,
      pv_i        => p_valid,
      a_i         => p_a,
      b_i         => p_b,
      valid_o     => k.valid,
      count_o     => k.count,
      ovs_o       => k.ovs,
      ill_o       => k.ill,
      ill_count_o => k.ill_count,
      held_o      => k.held
    );

  lost_reg : process (clk) is
  begin

    if rising_edge(clk) then
      k_lost <= mon.lost and not cfg.count_mode and not rst;
    end if;

  end process lost_reg;

  -- ---- t + 9 .. t + 10: reference marks --------------------------------------------------
  dc_en <= to_sl(OPT_DCODE = 1 and cfg.dc_spacing /= 0);

  u_refmark : entity work.refmark
    generic map (
      count_w => COUNT_W
    )
    port map (
      clk          => clk,
      rst          => rst,
      nv_i         => nth.n_valid,
      q_i          => nth.prod(PROD_W - 1 downto 11),
      n_i          => cfg.interp,
      ref_q_i      => cfg.ref_q,
      filt_i       => cfg.ref_filt,
      mode_i       => cfg.count_mode,
      cv_i         => k.valid,
      count_i      => k.count,
      held_i       => k.held,
      lost_i       => k_lost,
      ovs_i        => k.ovs,
      ref_i        => fl_ref,
      pv_i         => p_valid,
      pa_i         => p_a,
      pb_i         => p_b,
      pa_o         => rm.pa,
      pb_o         => rm.pb,
      zp_o         => rm.zp,
      pos_i        => ab.pos,
      target_o     => rm.target,
      z_en_o       => rm.z_en,
      z_at_o       => rm.z_at,
      home_arm_i   => req.home,
      home_i       => cfg.home(COUNT_W - 1 downto 0),
      inval_i      => req.inval,
      dc_en_i      => dc_en,
      dc_home_i    => dc.home,
      dc_off_i     => dc.off,
      dc_ref_i     => dc.ref,
      cross_o      => rm.cross,
      cdir_o       => rm.cdir,
      mark_o       => rm.mark,
      x_o          => rm.x,
      inv_o        => rm.inv,
      off_o        => rm.off,
      ref_count_o  => rm.ref_count,
      win_o        => rm.win,
      homed_o      => rm.homed,
      pos_valid_o  => rm.pos_valid,
      home_armed_o => rm.home_armed,
      latch_o      => rm.latch,
      lost_o       => rm.lost
    );

  -- distance-coded marks, on the latch's t + 10

  g_dcode : if OPT_DCODE = 1 generate

    signal lat : std_logic;
    signal inv : std_logic;

  begin

    lat <= rm.mark and dc_en;
    inv <= rm.inv or not dc_en or req.dc_inval;

    u_dcode : entity work.dcode
      generic map (
        count_w => COUNT_W
      )
      port map (
        clk         => clk,
        rst         => rst,
        a_i         => cfg.dc_spacing,
        b_i         => cfg.dc_coded,
        conf_i      => cfg.dc_confirm,
        n_i         => cfg.interp,
        home_i      => cfg.home(COUNT_W - 1 downto 0),
        cross_i     => rm.cross,
        cdir_i      => rm.cdir,
        lat_i       => lat,
        x_i         => rm.x,
        inv_i       => inv,
        abs_valid_o => dc.abs_valid,
        abs_o       => dc.abs_count,
        home_o      => dc.home,
        off_o       => dc.off,
        ref_o       => dc.ref,
        err_o       => dc.err
      );

  else generate

    dc <= (home => '0', err => '0', abs_valid => '0', others => (others => '0'));

  end generate g_dcode;

  count       <= k.count + rm.off;
  m_count     <= count;
  m_valid     <= k.valid;
  m_ref_count <= rm.ref_count;
  m_homed     <= rm.homed;
  m_pos_valid <= rm.pos_valid;

  -- ---- t + 10: paced A/B and Z (the count before the homing offset, one edge later) ------
  u_abgen : entity work.abgen
    generic map (
      count_w     => COUNT_W,
      opt_tunable => OPT_TUNABLE
    )
    port map (
      clk          => clk,
      rst          => rst,
      target_i     => rm.target,
      sep_i        => cfg.ab_sep,
      bound_i      => cfg.ab_bound,
      a_o          => ab.a,
      b_o          => ab.b,
      pos_o        => ab.pos,
      backlog_o    => ab.backlog,
      ovf_o        => ab.ovf,
      ovf_sticky_o => ab.sticky,
      z_en_i       => rm.z_en,
      z_at_i       => rm.z_at,
      z_o          => ab.z
    );

  -- the Eq. 12 pulses on the pins one edge late, beside their Z (rtl/refmark.v)
  m_a <= rm.pa when cfg.ab_src = '1' else
         ab.a;
  m_b <= rm.pb when cfg.ab_src = '1' else
         ab.b;
  m_z <= rm.zp when cfg.ab_src = '1' else
         ab.z;

  -- ---- fault bits, carried with the sample -----------------------------------------------
  -- The flags of edge t (clip, gain and offset saturation, the bundle's uncal and hold
  -- sampled with the sample) reach the output on edge t + LATENCY. csat_d(k) is
  -- registered k + 1 edges after edge t; the correction's rsat joins at index CORR_AT.
  flag_regs : process (clk) is

    variable next_csat : std_logic_vector(LATENCY - 1 downto 0);

  begin

    if rising_edge(clk) then
      uncal0 <= b_uncal;
      hold0  <= b_hold;
      ref0   <= s_ref;

      next_csat          := csat_d(LATENCY - 2 downto 0) & c.dsat;
      next_csat(CORR_AT) := csat_d(CORR_AT - 1) or c.rsat;
      csat_d             <= next_csat;

      mon_q <= mon.glitch & mon.stuck & mon.over & mon.loss;
    end if;

  end process flag_regs;

  fl_in <= ref0 & c.clip & c.nsat & uncal0 & hold0;

  -- OPT_DISTRAM = 1 (ECP5): flip-flops

  g_flag_delay : if OPT_DISTRAM = 1 generate

    type flag_line_t is array (0 to LATENCY - 1) of flags_t;

    signal fl_d : flag_line_t := (others => (others => '0'));

  begin

    flag_ff : process (clk) is
    begin

      if rising_edge(clk) then
        fl_d <= fl_in & fl_d(0 to LATENCY - 2);
      end if;

    end process flag_ff;

    fl_out <= fl_d(LATENCY - 1);

  -- OPT_DISTRAM = 0 (iCE40): a RAM of LATENCY words (ghdl --synth infers it) written on
  -- every edge at fl_wp and read at fl_wp + 1, so the word written on edge t + 1 is read
  -- on edge t + LATENCY, into the RAM's output register
  else generate

    -- (descending: GHDL addresses an ascending memory at the index's complement)
    type flag_ram_t is array (LATENCY - 1 downto 0) of flags_t;

    signal fl_mem : flag_ram_t           := (others => (others => '0'));
    signal fl_wp  : unsigned(2 downto 0) := (others => '0');
    signal fl_q   : flags_t              := (others => '0');

    -- (block RAM as in rtl/finequad_core.v; written onto the netlist by
    -- ../../scripts/ghdl_netlist.py: GHDL's writer drops attributes)
    attribute ram_style : string;
    attribute ram_style of fl_mem : signal is "block";

  begin

    flag_ram : process (clk) is
    begin

      if rising_edge(clk) then
        fl_mem(to_integer(fl_wp)) <= fl_in;
        fl_q                      <= fl_mem(to_integer(fl_wp + 1));
        fl_wp                     <= fl_wp + 1;
      end if;

    end process flag_ram;

    fl_out <= fl_q;

  end generate g_flag_delay;

  -- the fault word: its bits where FAULT_STICKY has them
  fl_ref                            <= fl_out(4);
  fault(FQ_FAULT_STICKY_CLIP_LSB)   <= fl_out(3);
  fault(FQ_FAULT_STICKY_NSAT_LSB)   <= fl_out(2);
  fault(FQ_FAULT_STICKY_CSAT_LSB)   <= csat_d(LATENCY - 1);
  fault(FQ_FAULT_STICKY_OVS_LSB)    <= k.ovs;
  fault(FQ_FAULT_STICKY_UNCAL_LSB)  <= fl_out(1);
  fault(FQ_FAULT_STICKY_HOLD_LSB)   <= fl_out(0);
  fault(FQ_FAULT_STICKY_ABOVF_LSB)  <= ab.sticky;
  fault(FQ_FAULT_STICKY_LOSS_LSB)   <= mon_q(0);
  fault(FQ_FAULT_STICKY_OVER_LSB)   <= mon_q(1);
  fault(FQ_FAULT_STICKY_STUCK_LSB)  <= mon_q(2);
  fault(FQ_FAULT_STICKY_GLITCH_LSB) <= mon_q(3);
  m_fault                           <= fault;

  -- CTRL.capture: the count captured (a coherent copy for a narrow or slow host link)
  capture_reg : process (clk) is
  begin

    if rising_edge(clk) then
      if req.capture = '1' then
        capture <= count;
      end if;

      if rst = '1' then
        capture <= (others => '0');
      end if;
    end if;

  end process capture_reg;

  -- ---- register read-back (registered, no reset): fq_rd_<reg>() places the fields;
  -- signed fields sign-extended to 32 bits; unmapped words read 0 -------------------------
  reg_read : process (clk) is
  begin

    if rising_edge(clk) then
      if reg_re = '1' then
        -- (if, not case: GHDL 2.0's Verilog writer drops a case's others, README.md)
        if reg_addr = FQ_STATUS then
          rdata_q <= fq_rd_status(b_uncal, b_hold, e_sat, cfg.count_mode, b_loaded);
        elsif reg_addr = FQ_INTERP then
          rdata_q <= fq_rd_interp(cfg.interp);
        elsif reg_addr = FQ_EPS then
          rdata_q <= fq_rd_eps(cfg.eps);
        elsif reg_addr = FQ_LAMBDA_K then
          rdata_q <= fq_rd_lambda_k(cfg.lambda_k);
        elsif reg_addr = FQ_KAPPA then
          rdata_q <= fq_rd_kappa(cfg.kappa);
        elsif reg_addr = FQ_PERIOD then
          rdata_q <= fq_rd_period(cfg.period);
        elsif reg_addr = FQ_SETTLE then
          rdata_q <= fq_rd_settle(cfg.settle);
        elsif reg_addr = FQ_GATE then
          rdata_q <= fq_rd_gate(cfg.gate);
        elsif reg_addr = FQ_COUNT then
          rdata_q <= fq_rd_count(resize(count, FQ_COUNT_COUNT_W));
        elsif reg_addr = FQ_ILLEGAL then
          rdata_q <= fq_rd_illegal(k.ill_count);
        elsif reg_addr = FQ_FAULT_STICKY then
          rdata_q <= fq_rd_fault_sticky(clip   => fault_stk(FQ_FAULT_STICKY_CLIP_LSB),
                                        nsat   => fault_stk(FQ_FAULT_STICKY_NSAT_LSB),
                                        csat   => fault_stk(FQ_FAULT_STICKY_CSAT_LSB),
                                        ovs    => fault_stk(FQ_FAULT_STICKY_OVS_LSB),
                                        uncal  => fault_stk(FQ_FAULT_STICKY_UNCAL_LSB),
                                        hold   => fault_stk(FQ_FAULT_STICKY_HOLD_LSB),
                                        abovf  => fault_stk(FQ_FAULT_STICKY_ABOVF_LSB),
                                        loss   => fault_stk(FQ_FAULT_STICKY_LOSS_LSB),
                                        over   => fault_stk(FQ_FAULT_STICKY_OVER_LSB),
                                        stuck  => fault_stk(FQ_FAULT_STICKY_STUCK_LSB),
                                        glitch => fault_stk(FQ_FAULT_STICKY_GLITCH_LSB));
        elsif reg_addr = FQ_GAIN then
          rdata_q <= fq_rd_gain(bundle.g);
        elsif reg_addr = FQ_M1 then
          rdata_q <= fq_rd_m1(resize(bundle.m1, FQ_M1_M1_W));
        elsif reg_addr = FQ_M2 then
          rdata_q <= fq_rd_m2(resize(bundle.m2, FQ_M2_M2_W));
        elsif reg_addr = FQ_C1 then
          rdata_q <= fq_rd_c1(resize(bundle.c1, FQ_C1_C1_W));
        elsif reg_addr = FQ_C12 then
          rdata_q <= fq_rd_c12(resize(bundle.c12, FQ_C12_C12_W));
        elsif reg_addr = FQ_C2 then
          rdata_q <= fq_rd_c2(resize(bundle.c2, FQ_C2_C2_W));
        elsif reg_addr = FQ_UPDATES then
          rdata_q <= fq_rd_updates(e_upd);
        elsif reg_addr = FQ_HARM then
          if OPT_HARMONIC = 1 then
            rdata_q <= fq_rd_harm(cfg.harm_apply, cfg.harm_learn, cfg.harm_mu);
          else
            rdata_q <= (others => '0');
          end if;
        elsif reg_addr = FQ_JUMP then
          if OPT_JUMP = 1 then
            rdata_q <= fq_rd_jump(cfg.jump_min, cfg.jump_off);
          else
            -- the detector off
            rdata_q <= fq_rd_jump(to_unsigned(0, FQ_JUMP_JUMP_MIN_W), '1');
          end if;
        elsif reg_addr = FQ_JUMPS then
          if OPT_JUMP = 1 then
            rdata_q <= fq_rd_jumps(e_jumps);
          else
            rdata_q <= (others => '0');
          end if;
        elsif reg_addr = FQ_ABGEN then
          rdata_q <= fq_rd_abgen(cfg.ab_sep, cfg.ab_src);
        elsif reg_addr = FQ_AB_BOUND then
          rdata_q <= fq_rd_ab_bound(cfg.ab_bound);
        elsif reg_addr = FQ_AB_BACKLOG then
          rdata_q <= fq_rd_ab_backlog(resize(ab.backlog, FQ_AB_BACKLOG_AB_BACKLOG_W));
        elsif reg_addr = FQ_CLIP then
          rdata_q <= fq_rd_clip(cfg.clip);
        elsif reg_addr = FQ_RADIUS then
          if OPT_MONITOR = 1 then
            rdata_q <= fq_rd_radius(cfg.loss, cfg.over);
          else
            rdata_q <= (others => '0');
          end if;
        elsif reg_addr = FQ_MONITOR then
          if OPT_MONITOR = 1 then
            rdata_q <= fq_rd_monitor(cfg.glitch_k, cfg.code_step, cfg.stuck_n);
          else
            rdata_q <= (others => '0');
          end if;
        elsif reg_addr = FQ_COAST then
          if OPT_MONITOR = 1 then
            rdata_q <= fq_rd_coast(cfg.floor, cfg.coast_acc);
          else
            rdata_q <= (others => '0');
          end if;
        elsif reg_addr = FQ_CAPTURE then
          rdata_q <= fq_rd_capture(resize(capture, FQ_CAPTURE_CAPTURE_W));
        elsif reg_addr = FQ_TRAVEL then
          rdata_q <= fq_rd_travel(mon.travel);
        elsif reg_addr = FQ_REF then
          rdata_q <= fq_rd_ref(cfg.ref_q, cfg.ref_filt);
        elsif reg_addr = FQ_HOME then
          rdata_q <= fq_rd_home(cfg.home);
        elsif reg_addr = FQ_REF_COUNT then
          rdata_q <= fq_rd_ref_count(resize(rm.ref_count, FQ_REF_COUNT_REF_COUNT_W));
        elsif reg_addr = FQ_REF_STATUS then
          rdata_q <= fq_rd_ref_status(rm.win, rm.homed, rm.pos_valid, rm.home_armed,
                                      dc.abs_valid);
        elsif reg_addr = FQ_REF_STICKY then
          rdata_q <= fq_rd_ref_sticky(ref_stk(0), ref_stk(1), ref_stk(2));
        elsif reg_addr = FQ_DCODE then
          rdata_q <= fq_rd_dcode(cfg.dc_spacing, cfg.dc_coded, cfg.dc_confirm);
        elsif reg_addr = FQ_ABS_COUNT then
          rdata_q <= fq_rd_abs_count(resize(dc.abs_count, FQ_ABS_COUNT_ABS_COUNT_W));
        elsif reg_addr = FQ_ID then
          rdata_q <= std_logic_vector(FQ_ID_ID_RESET);
        else
          rdata_q <= (others => '0');
        end if;
      end if;
    end if;

  end process reg_read;

  reg_rdata <= rdata_q;

end architecture rtl;
