-- monitor: signal faults, the counter's hold and coast, and the travel along the scale
-- (VHDL edition of rtl/monitor.v, whose header gives the timing, the formats and the
-- reasoning of every check; the model sim/model/monitor.py argues each one).
--
-- Per sample strobed on edge t: the radius checks (loss, dead = below FLOOR, over) from
-- the magnitudes, the stuck channels (a channel's code unchanged STUCK_N samples while
-- the other channel moved beyond the span of its snapshot, the span from the bundle's
-- c1, c2, gain and code step), and in stage H (t + 6 to t + 7) the line of the accepted
-- phases: the glitch test against it, the hold and the coast along it (a stuck channel's
-- coast starts from its shadow line; a parted shadow line loses the travel), the coast's
-- uncertainty (lost_o), and the travel U, S.
--
-- Timing: the edge after the strobe edge t that samples each input (rtl/monitor.v's
-- header numbers the edges that register them upstream, one earlier): sv_i, g_i, c1_i,
-- c2_i, code_step_i and ref_i on t; valid0_i, raw1_i, raw2_i, clip_i on t + 1; ax_i,
-- ay_i, xn_i, yn_i on t + 3; glitch_k_i on t + 6; pvalid_i, phase_i on t + 7, with
-- hold_o, excl_o, coast_o combinational while pvalid_i is high before that edge (stage
-- H); loss_o, over_o, stuck_o, glitch_o, lost_o, travel_o after it. Samples may come on
-- every clock.
-- Formats: raw s1.15 codes; c1, c2 s4.12; ax, ay u15 (s2.14 units, calibrated circle
-- 16384); thresholds u16 radius; phase_i, line_o u13 (8192 per period); coast_acc_i
-- u0.12; travel_o u20 phase units (wraps); the internal formats beside each signal.
-- Power-up values are the Verilog's initial values: rst restores them, except in the
-- pipeline stages that rtl/monitor.v's rst leaves alone too.
-- OPT_MONITOR = 0: no checks (hold_o, coast_o, lost_o never, line_o 0, excl_o = pvalid_i
-- and clip), every sample accepted.
-- Not carried over: rtl/monitor.v's formal code (`ifdef FORMAL: the properties, the
-- ghost delay lines f_* and the mdev wire, mdev_r with its pending update); formal
-- stays on the Verilog.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;

entity monitor is
  generic (
    -- 1: the fault checks; 0: none (a small device)
    OPT_MONITOR : integer range 0 to 1 := 1;
    -- the ADC port's width (rtl/correct.v), 12..16
    ADC_W : integer range 12 to 16 := 16
  );
  port (
    clk         : in    std_logic;
    rst         : in    std_logic;             -- sync, active high
    sv_i        : in    std_logic;             -- (t) the sample's strobe
    g_i         : in    unsigned(1 downto 0);  -- (t) the bundle's input gain 2^g
    c1_i        : in    signed(15 downto 0);   -- (t) s4.12 the bundle's c1 and c2
    c2_i        : in    signed(15 downto 0);
    code_step_i : in    unsigned(3 downto 0);  -- (t) u4 the code step 2^k port LSBs, 0..8
    valid0_i    : in    std_logic;             -- (t + 1)
    raw1_i      : in    signed(15 downto 0);   -- (t + 1) s1.15 aligned codes
    raw2_i      : in    signed(15 downto 0);
    clip_i      : in    std_logic;             -- (t + 1) a code at or near a rail
    ref_i       : in    std_logic;             -- (t) the radius checks are armed
    ax_i        : in    unsigned(14 downto 0); -- (t + 3) u15 |u1c|, s2.14 units
    ay_i        : in    unsigned(14 downto 0); -- (t + 3) u15 |u2c|
    xn_i        : in    std_logic;             -- (t + 3) u1c < 0
    yn_i        : in    std_logic;             -- (t + 3) u2c < 0
    pvalid_i    : in    std_logic;             -- (t + 7)
    phase_i     : in    phase_t;               -- (t + 7) u13 fine phase (uncorrected)
    loss_th_i   : in    unsigned(15 downto 0); -- u16 radius below it: loss
    over_th_i   : in    unsigned(15 downto 0); -- u16 radius above it: over-range
    glitch_k_i  : in    unsigned(3 downto 0);  -- (t + 6) max |phase accel.| 2^K (0: off)
    stuck_n_i   : in    unsigned(7 downto 0);  -- u8 unchanged codes before stuck (0: off)
    floor_th_i  : in    unsigned(15 downto 0); -- u16 radius below it: the phase untrusted
    coast_acc_i : in    unsigned(11 downto 0); -- u0.12 the coast's acceleration bound
    hold_o      : out   std_logic;             -- (H) the counter does not take the phase
    excl_o      : out   std_logic;             -- (H) the estimator does not take it
    coast_o     : out   std_logic;             -- (H) with hold_o: the count follows line_o
    line_o      : out   phase_t;               -- u13 the line at this sample (registered)
    loss_o      : out   std_logic;             -- (after t + 7) the sample's fault bits
    over_o      : out   std_logic;
    stuck_o     : out   std_logic;
    glitch_o    : out   std_logic;
    lost_o      : out   std_logic;             -- the coast's uncertainty reached 1/4 period
    travel_o    : out   unsigned(19 downto 0)  -- u20 integer part of S
  );
end entity monitor;

architecture rtl of monitor is

  constant OPT : std_logic := to_sl(OPT_MONITOR = 1);

  constant OVER_PERSIST : unsigned(11 downto 0) := to_unsigned(4095, 12);
  -- glitches coasted in a row before an unclipped sample re-anchors the line
  constant COAST_MAX : unsigned(4 downto 0) := to_unsigned(16, 5);
  -- unc: a quarter period in 2^-12 phase units (the travel is lost)
  constant UNC_LOST : unsigned(23 downto 0) := x"800000";
  -- the port's LSB in s1.15 LSBs, 2^SH0
  constant SH0 : unsigned(4 downto 0) := to_unsigned(16 - ADC_W, 5);
  -- the least span (u15)
  constant SPAN_MIN : unsigned(14 downto 0) := to_unsigned(2048, 15);

  subtype code_t is signed(15 downto 0); -- s1.15 a code; s4.12 a coefficient

  subtype other_t is signed(16 downto 0); -- s17 the other channel, s2.14 units

  subtype span_t is unsigned(14 downto 0); -- u15 a stuck span, s2.14 units

  subtype line_pos_t is unsigned(15 downto 0); -- u13.3 a line (wraps)

  subtype line_vel_t is signed(15 downto 0); -- s13.3 its velocity

  -- The channels: channel 1 watches the other channel's magnitude ay_i (sign yn_i),
  -- channel 2 ax_i (xn_i). Indices of the delay lines and t + k: the edge after t that
  -- registers them.
  type chan_t is record
    prev : code_t;                   -- s1.15 the code of the sample before
    run  : unsigned(7 downto 0);     -- u8 unchanged codes (saturates)
    chg  : std_logic_vector(1 to 6); -- the code changed
    rok  : std_logic_vector(1 to 3); -- STUCK_N > 0 and run >= STUCK_N
    sx   : unsigned(7 downto 0);     -- t + 1: span_exp {zero, E, m}
    sv   : unsigned(18 downto 0);    -- t + 2: span_shift (u19)
    sp3  : span_t;                   -- t + 3: the sample's span
    o    : other_t;                  -- t + 3: the other channel, signed
    snap : other_t;                  -- the other channel at the last change
    sp   : span_t;                   -- the span stored with the snapshot
    stk  : std_logic;                -- the stuck latch
    st   : std_logic_vector(5 to 6); -- the latch beside the sample
    osg  : std_logic_vector(3 to 6); -- the other channel's sign
  end record chan_t;

  constant CHAN_INIT : chan_t :=
  (
    prev => (others => '0'),
    run  => (others => '0'),
    chg  => (others => '0'),
    rok  => (others => '0'),
    sx   => (others => '0'),
    sv   => (others => '0'),
    sp3  => SPAN_MIN,
    o    => (others => '0'),
    snap => (others => '0'),
    sp   => SPAN_MIN,
    stk  => '0',
    st   => (others => '0'),
    osg  => (others => '0')
  );

  type chan_arr_t is array (1 to 2) of chan_t;

  -- Stage H per channel: the shadow line (the line as it would have coasted from the
  -- channel's last code change) and what the sample before saw.
  type shadow_t is record
    sl   : line_pos_t; -- u13.3 the shadow line
    sv   : line_vel_t; -- s13.3 its velocity
    prt  : std_logic;  -- parted from the line since the change
    pst  : std_logic;  -- the stuck latch of the sample before
    posg : std_logic;  -- the other channel's sign before
  end record shadow_t;

  constant SHADOW_INIT : shadow_t :=
  (
    sl   => (others => '0'),
    sv   => (others => '0'),
    prt  => '0',
    pst  => '0',
    posg => '0'
  );

  type shadow_arr_t is array (1 to 2) of shadow_t;

  type code_arr_t is array (1 to 2) of code_t;

  type mag_arr_t is array (1 to 2) of unsigned(14 downto 0);

  -- A sample's bundle as the spans see it: the gain and the coefficients c1, c2.
  type bundle_t is record
    g : unsigned(1 downto 0);
    c : code_arr_t; -- s4.12
  end record bundle_t;

  constant BUNDLE_INIT : bundle_t := (g => "00", c => (others => (others => '0')));

  -- Stage H: the line of the accepted phases.
  type line_t is record
    ph_a : phase_t;              -- u13 the last phase accepted
    pf   : line_pos_t;           -- u13.3 the line: this sample's prediction
    v    : line_vel_t;           -- s13.3 its velocity
    chk  : unsigned(1 downto 0); -- accepted since re-anchoring (2: lok)
    acc  : std_logic;            -- the sample before was accepted
    rc   : std_logic;            -- a coast through a fault: no glitch test
    grun : unsigned(4 downto 0); -- u5 glitches coasted (saturates)
  end record line_t;

  constant LINE_INIT : line_t :=
  (
    ph_a => (others => '0'),
    pf   => (others => '0'),
    v    => (others => '0'),
    chk  => "00",
    acc  => '0',
    rc   => '0',
    grun => (others => '0')
  );

  -- The coast's uncertainty and its growth w, retimed (rtl/monitor.v: w_r and mdev_r run
  -- one sample behind, with the sample before's update pending).
  type coast_t is record
    unc    : unsigned(23 downto 0); -- u24 2^-12 units (2^23: lost)
    w_r    : unsigned(25 downto 0); -- u26 w before the sample before
    wacc   : std_logic;             -- the sample before was accepted
    wadd   : unsigned(11 downto 0); -- u0.12 coast_acc if it coasted, else 0
    mdev_r : unsigned(19 downto 0); -- u20 mdev before the sample before (2^-7)
    padv   : unsigned(15 downto 0); -- u16 |8 d - v| of the sample before
    pupd   : std_logic;             -- it updates mdev
  end record coast_t;

  constant COAST_INIT : coast_t :=
  (
    unc    => (others => '0'),
    w_r    => (others => '0'),
    wacc   => '0',
    wadd   => (others => '0'),
    mdev_r => (others => '0'),
    padv   => (others => '0'),
    pupd   => '0'
  );

  -- The travel: U u20 (wraps), S u20.5 (wraps) following it.
  type travel_t is record
    u : unsigned(19 downto 0);
    s : unsigned(24 downto 0);
  end record travel_t;

  -- The sample's fault bits (t + 7).
  type flags_t is record
    loss   : std_logic;
    over   : std_logic;
    stuck  : std_logic;
    glitch : std_logic;
    lost   : std_logic;
  end record flags_t;

  constant FLAGS_INIT : flags_t := (others => '0');

  constant TRAVEL_INIT : travel_t := (u => (others => '0'), s => (others => '0'));

  -- SPAN_K of the model, by {E & 1, m}
  -- (descending: GHDL addresses an ascending table at the index's complement)
  type span_k_t is array (7 downto 0) of natural range 0 to 255;

  constant SPAN_K : span_k_t := (192, 180, 167, 152, 136, 127, 118, 108);

  -- {zero, E, m} of |c| with the code step 2^sh: E = msb(|c|) + sh, m the two bits below
  -- the msb (u1, u5, u2)
  function span_exp (c : code_t; sh : unsigned(4 downto 0)) return unsigned is

    variable a  : unsigned(15 downto 0); -- |c|: |-32768| is bit 15
    variable e  : natural range 0 to 15;
    variable am : unsigned(17 downto 0);

  begin

    if c(15) = '1' then
      a := unsigned(-c);
    else
      a := unsigned(c);
    end if;

    e := 0;

    for k in 1 to 15 loop

      if a(k) = '1' then
        e := k;
      end if;

    end loop;

    -- the leading one at bit 2
    am := shift_right(a & "00", e);
    return to_sl(a = 0) & (to_unsigned(e, 5) + sh) & am(1 downto 0);

  end function span_exp;

  -- SPAN_K[E & 1][m] 2^(E >> 1) / 16, 0 for c = 0 (u19)
  function span_shift (x : unsigned(7 downto 0)) return unsigned is

    variable t : unsigned(22 downto 0);

  begin

    t := shift_left(to_unsigned(SPAN_K(to_integer(x(2 downto 0))), 23),
                    to_integer(x(6 downto 3)));

    if x(7) = '1' then
      return to_unsigned(0, 19);
    end if;

    return t(22 downto 4);

  end function span_shift;

  -- v clamped to [2048, 32767]: two bit tests
  function span_clamp (v : unsigned(18 downto 0)) return span_t is
  begin

    if v(18 downto 11) = 0 then
      return SPAN_MIN;
    elsif v(18 downto 15) /= 0 then
      return (others => '1');
    end if;

    return v(14 downto 0);

  end function span_clamp;

  -- a phase (u13) or a step (s13) in the line's eighths: u13.3, s13.3
  function x8 (p : phase_t) return line_pos_t is
  begin

    return p & "000";

  end function x8;

  -- a saturating count: n + 1 up to top
  function sat_inc (n : unsigned; top : unsigned) return unsigned is
  begin

    if n = top then
      return n;
    end if;

    return n + 1;

  end function sat_inc;

  -- ---- t .. t + 6: the channels, the bundles, the radius -------------------------------

  signal ch     : chan_arr_t               := (others => CHAN_INIT);
  signal raw    : code_arr_t;
  signal oth    : mag_arr_t;                               -- the other channel's magnitude
  signal oth_n  : std_logic_vector(1 to 2);                -- its sign
  signal smp    : bundle_t                 := BUNDLE_INIT; -- the sample's bundle (sv_i)
  signal prv    : bundle_t                 := BUNDLE_INIT; -- the sample before's
  signal sst    : unsigned(3 downto 0)     := (others => '0');
  signal sh     : unsigned(4 downto 0);                    -- the code step in s1.15 LSBs, 2^sh
  signal vld    : std_logic_vector(1 to 3) := (others => '0');
  signal reb    : std_logic_vector(1 to 3) := (others => '0');
  signal stk_p  : std_logic_vector(4 to 6) := (others => '0');
  signal clip_p : std_logic_vector(1 to 6) := (others => '0');

  signal ref_p : std_logic_vector(0 to 4) := (others => '0');
  signal mx3   : unsigned(14 downto 0)    := (others => '0');
  signal mn3   : unsigned(14 downto 0)    := (others => '0');
  signal r4    : unsigned(15 downto 0)    := (others => '0'); -- u16 the radius
  signal loss5 : std_logic                := '0';
  signal dead5 : std_logic                := '0';
  signal over5 : std_logic                := '0';
  signal loss6 : std_logic                := '0';
  signal dead6 : std_logic                := '0';
  signal over6 : std_logic                := '0';
  -- dead, stuck or clip with over-range of the sample in H, combined on t + 6
  signal early : std_logic := '0';

  -- ---- stage H ------------------------------------------------------------------------

  signal ln    : line_t                := LINE_INIT;
  signal cst   : coast_t               := COAST_INIT;
  signal trv   : travel_t              := TRAVEL_INIT;
  signal orun  : unsigned(11 downto 0) := (others => '0'); -- u12 over-range run
  signal flags : flags_t               := FLAGS_INIT;
  signal shd   : shadow_arr_t          := (others => SHADOW_INIT);
  -- the glitch test's bits K..11 (t + 6: K sampled there)
  signal gmask : unsigned(11 downto 1) := (others => '0');

  signal loss   : std_logic;
  signal over   : std_logic;
  signal stuck  : std_logic;
  signal pred   : phase_t;                  -- u13 the line
  signal e      : phase_t;                  -- s13 off the line (wraps)
  signal big    : std_logic;                -- e outside [-2^K, 2^K - 1]
  signal glitch : std_logic;
  signal hold   : std_logic;
  signal coast  : std_logic;
  signal acc_ok : std_logic;
  signal d      : phase_t;                  -- s13 the step (wraps)
  signal dv     : signed(16 downto 0);      -- s14.3 8 d - v
  signal adv    : unsigned(15 downto 0);    -- u16 |8 d - v|
  signal mdd    : signed(20 downto 0);      -- s21 16 padv - mdev_r
  signal w      : unsigned(25 downto 0);    -- u26 w after the sample before
  signal sd     : unsigned(24 downto 0);    -- s25 (U << 5) - S
  signal part   : std_logic_vector(1 to 2); -- the shadow line parted
  signal sel    : integer range 1 to 2;     -- the stuck channel, when one is
  signal one    : std_logic;                -- one channel stuck
  signal rise   : std_logic;                -- its latch's first sample
  signal anchor : std_logic;                -- the working channel's sign changed
  signal rlost  : std_logic;                -- a rise with a parted shadow line
  signal p2k    : phase_t;                  -- u13 pred + 2048
  signal cand   : phase_t;                  -- u13 the crossing nearest the line
  signal usum   : unsigned(26 downto 0);    -- u27 unc + w
  signal pf_n   : line_pos_t;               -- the line after the sample
  signal v_n    : line_vel_t;

begin

  raw   <= (1 => raw1_i, 2 => raw2_i);
  oth   <= (1 => ay_i, 2 => ax_i);
  oth_n <= (1 => yn_i, 2 => xn_i);

  -- ---- the bundles: the sample's and the one before (on sv_i) -------------------------
  bundles : process (clk) is
  begin

    if rising_edge(clk) then
      if sv_i = '1' then
        smp <= (g => g_i, c => (1 => c1_i, 2 => c2_i));
        sst <= code_step_i;
        prv <= smp;
      end if;

      if rst = '1' then
        smp <= BUNDLE_INIT;
        prv <= BUNDLE_INIT;
        sst <= (others => '0');
      end if;
    end if;

  end process bundles;

  sh <= SH0 + sst + smp.g;

  -- ---- t + 1 .. t + 6: runs, spans, snapshots, the stuck latches ----------------------
  channels : process (clk) is

    variable eq    : boolean;
    variable x     : signed(17 downto 0);    -- s18 o - snap
    variable sp    : signed(17 downto 0);
    variable far   : boolean;
    variable stk_n : std_logic;
    variable any_n : std_logic;

  begin

    if rising_edge(clk) then
      any_n := '0';

      for c in 1 to 2 loop

        -- t + 1: the run of unchanged codes; run_n >= N (N > 0) <=> the code is
        -- unchanged and run >= N - 1
        eq := raw(c) = ch(c).prev;

        if valid0_i = '1' then
          ch(c).prev <= raw(c);

          if not eq then
            ch(c).run <= (others => '0');
          else
            ch(c).run <= sat_inc(ch(c).run, x"FF");
          end if;
        end if;

        ch(c).chg(1)      <= to_sl(not eq);
        ch(c).rok(1)      <= to_sl(stuck_n_i /= 0 and eq and ch(c).run >= stuck_n_i - 1);
        ch(c).chg(2 to 6) <= ch(c).chg(1 to 5);
        ch(c).rok(2 to 3) <= ch(c).rok(1 to 2);

        -- t + 1 .. t + 3: the sample's span, stage by stage (clock enables)
        if valid0_i = '1' then
          ch(c).sx <= span_exp(smp.c(c), sh);
        end if;

        if vld(1) = '1' then
          ch(c).sv <= span_shift(ch(c).sx);
        end if;

        if vld(2) = '1' then
          ch(c).sp3 <= span_clamp(ch(c).sv);
        end if;

        -- t + 3: the other channel, signed; t + 4: outside [-sp, sp - 1] of the
        -- snapshot (not on a rebase), the latch and the snapshot updated
        if oth_n(c) = '1' then
          ch(c).o <= -signed(unsigned'("00" & oth(c)));
        else
          ch(c).o <= signed(unsigned'("00" & oth(c)));
        end if;

        x     := resize(ch(c).o, 18) - resize(ch(c).snap, 18);
        sp    := signed(unsigned'("000" & ch(c).sp));
        far   := reb(3) = '0' and (x >= sp or x < -sp);
        stk_n := not ch(c).chg(3) and (ch(c).stk or (ch(c).rok(3) and to_sl(far)));
        any_n := any_n or stk_n;

        if vld(3) = '1' then
          ch(c).stk <= stk_n;

          if ch(c).chg(3) = '1' or reb(3) = '1' then
            ch(c).snap <= ch(c).o;
            ch(c).sp   <= ch(c).sp3;
          end if;
        end if;

        -- beside the sample to H: the latch, the other channel's sign
        ch(c).st  <= ch(c).stk & ch(c).st(5);
        ch(c).osg <= oth_n(c) & ch(c).osg(3 to 5);

        if rst = '1' then
          ch(c).prev <= (others => '0');
          ch(c).run  <= (others => '0');
          ch(c).stk  <= '0';
          ch(c).snap <= (others => '0');
          ch(c).sp   <= SPAN_MIN;
        end if;

      end loop;

      vld <= valid0_i & vld(1 to 2);

      if valid0_i = '1' then
        reb(1) <= to_sl(smp /= prv);
      end if;

      if vld(1) = '1' then
        reb(2) <= reb(1);
      end if;

      if vld(2) = '1' then
        reb(3) <= reb(2);
      end if;

      -- the stuck flag of edge t + 4, carried to t + 6; clip from t + 1
      stk_p  <= any_n & stk_p(4 to 5);
      clip_p <= clip_i & clip_p(1 to 5);

      if rst = '1' then
        vld <= (others => '0');
      end if;
    end if;

  end process channels;

  stuck <= OPT and stk_p(6);

  -- ---- t .. t + 6: the radius (alpha-max-plus-beta-min) -------------------------------
  radius : process (clk) is
  begin

    if rising_edge(clk) then
      ref_p <= ref_i & ref_p(0 to 3);

      if ay_i <= ax_i then
        mx3 <= ax_i;
        mn3 <= ay_i;
      else
        mx3 <= ay_i;
        mn3 <= ax_i;
      end if;

      r4    <= ('0' & mx3) + mn3(14 downto 2) + mn3(14 downto 3);
      loss5 <= ref_p(4) and to_sl(r4 < loss_th_i);
      dead5 <= ref_p(4) and to_sl(r4 < floor_th_i);
      over5 <= ref_p(4) and to_sl(r4 > over_th_i);
      loss6 <= loss5;
      dead6 <= dead5;
      over6 <= over5;
      early <= OPT and (dead5 or stk_p(5) or (clip_p(5) and over5));
    end if;

  end process radius;

  loss <= OPT and loss6;
  over <= OPT and over6;

  -- ---- stage H: the glitch test, the hold and the coast -------------------------------
  -- e outside [-2^K, 2^K - 1] <=> a bit of e[11:K] differs from the sign e[12]
  glitch_mask : process (clk) is
  begin

    if rising_edge(clk) then

      for kb in gmask'range loop

        gmask(kb) <= to_sl(glitch_k_i /= 0 and kb >= to_integer(glitch_k_i));

      end loop;

    end if;

  end process glitch_mask;

  pred <= ln.pf(15 downto 3);
  e    <= phase_i - pred;

  -- a clear bit under the mask (e < 0) or a set one (e >= 0), side by side; the sign
  -- selects
  big    <= to_sl((not e(11 downto 1) and gmask) /= 0) when e(12) = '1' else
            to_sl((e(11 downto 1) and gmask) /= 0);
  glitch <= OPT and ln.chk(1) and not ln.rc and big;

  hold   <= pvalid_i and (early or glitch);
  acc_ok <= not hold;

  -- a coast along the known line: through dead, stuck, clip with over, or a glitch
  -- (COAST_MAX glitch coasts, unless clipped)
  coast <= OPT and ln.chk(1) and
           (early or (glitch and not (to_sl(ln.grun = COAST_MAX) and not clip_p(6))));

  hold_o  <= hold;
  coast_o <= hold and coast;
  line_o  <= pred when OPT = '1' else
             (others => '0');
  excl_o  <= hold or (pvalid_i and (loss or clip_p(6) or
                                    (over and to_sl(orun /= OVER_PERSIST))));

  d   <= phase_i - ln.ph_a;
  dv  <= resize(signed(x8(d)), 17) - resize(ln.v, 17);
  adv <= unsigned(-dv(15 downto 0)) when dv(16) = '1' else
         unsigned(dv(15 downto 0));
  mdd <= signed(unsigned'('0' & cst.padv & "0000")) - signed(unsigned'('0' & cst.mdev_r));

  -- w after the sample before: an accept starts it from mdev before that accept's update,
  -- a coast grows it by coast_acc below 2^23
  w <= (resize(cst.mdev_r(19 downto 4), 17) + 1) & "000000000" when cst.wacc = '1' else
       cst.w_r + cst.wadd when cst.w_r(25 downto 23) = 0 else
       cst.w_r;

  usum <= ("000" & cst.unc) + ('0' & w);
  sd   <= (trv.u & "00000") - trv.s;

  -- per channel: the shadow line a quarter period or more off the line (s16 outside
  -- [-2^14, 2^14 - 1]), now or since the channel's code last changed

  g_part : for c in 1 to 2 generate
    signal dl : unsigned(15 downto 0);
  begin

    dl      <= shd(c).sl - ln.pf;
    part(c) <= shd(c).prt or (dl(15) xor dl(14));

  end generate g_part;

  -- one stuck channel: its shadow line on its latch's first sample, else the working
  -- channel's zero crossing nearest the line (channel 2's 0 or 4096 when channel 1 is
  -- stuck, channel 1's 2048 or 6144 when channel 2 is)
  one    <= ch(1).st(6) xor ch(2).st(6);
  sel    <= 1 when ch(1).st(6) = '1' else
            2;
  rise   <= one and not shd(sel).pst;
  anchor <= one and not dead6 and (ch(sel).osg(6) xor shd(sel).posg);
  rlost  <= rise and part(sel);
  p2k    <= pred + 2048;
  cand   <= p2k(12) & x"000" when sel = 1 else
            pred(12) & '1' & "00000000000";

  -- the line and its velocity after the sample (the shadow lines start from them)
  line_next : process (all) is
  begin

    pf_n <= ln.pf;
    v_n  <= ln.v;

    if acc_ok = '1' then
      if ln.chk(1) = '0' then
        v_n  <= signed(x8(d));
        pf_n <= x8(phase_i) + x8(d);
      else
        if ln.acc = '1' then
          v_n <= ln.v + resize(asr(dv, 3), 16);
        end if;
        pf_n <= x8(phase_i) + unsigned(ln.v);
      end if;
    elsif coast = '1' then
      if rise = '1' then
        pf_n <= shd(sel).sl + unsigned(shd(sel).sv);
        v_n  <= shd(sel).sv;
      elsif anchor = '1' then
        pf_n <= x8(cand) + unsigned(ln.v);
      else
        pf_n <= ln.pf + unsigned(ln.v);
      end if;
    end if;

  end process line_next;

  stage_h : process (clk) is
  begin

    if rising_edge(clk) then
      if pvalid_i = '1' then
        flags.loss   <= loss;
        flags.over   <= over;
        flags.stuck  <= stuck;
        flags.glitch <= glitch;

        if over = '0' then
          orun <= (others => '0');
        else
          orun <= sat_inc(orun, OVER_PERSIST);
        end if;

        ln.pf <= pf_n;
        ln.v  <= v_n;

        for c in 1 to 2 loop

          shd(c).pst  <= ch(c).st(6);
          shd(c).posg <= ch(c).osg(6);
          shd(c).prt  <= not ch(c).chg(6) and part(c);

          if ch(c).chg(6) = '1' then
            shd(c).sl <= pf_n;
            shd(c).sv <= v_n;
          else
            shd(c).sl <= shd(c).sl + unsigned(shd(c).sv);
          end if;

        end loop;

        -- the retimed w and mdev
        cst.w_r  <= w;
        cst.wacc <= acc_ok;

        if acc_ok = '0' and coast = '1' then
          cst.wadd <= coast_acc_i;
        else
          cst.wadd <= (others => '0');
        end if;

        if cst.pupd = '1' then
          cst.mdev_r <= cst.mdev_r + unsigned(resize(asr(mdd, 4), 20));
        end if;

        cst.padv <= adv;
        cst.pupd <= acc_ok and ln.chk(1) and ln.acc;

        if acc_ok = '1' then
          ln.ph_a <= phase_i;
          if ln.chk(1) = '0' then
            ln.chk <= ln.chk + 1;
          end if;

          ln.rc <= '0';
          trv.s <= trv.s + unsigned(asr(signed(sd), 5));
          trv.u <= trv.u + unsigned(resize(signed(d), 20));

          -- two in a row: the line holds
          if ln.acc = '1' then
            ln.grun <= (others => '0');
          end if;

          ln.acc     <= '1';
          cst.unc    <= (others => '0');
          flags.lost <= '0';
        elsif coast = '1' then
          if anchor = '1' and rise = '0' then
            cst.unc    <= (others => '0');
            flags.lost <= '0';
          elsif rlost = '1' or usum(26 downto 23) /= 0 then
            cst.unc    <= UNC_LOST;
            flags.lost <= '1';
          else
            cst.unc    <= usum(23 downto 0);
            flags.lost <= '0';
          end if;

          if early = '1' then
            ln.rc <= '1';
          else
            ln.grun <= sat_inc(ln.grun, COAST_MAX);
          end if;

          ln.acc <= '0';
        else
          -- no line to coast along: the travel is lost
          ln.chk     <= "00";
          ln.grun    <= (others => '0');
          ln.acc     <= '0';
          ln.rc      <= '0';
          cst.unc    <= UNC_LOST;
          flags.lost <= OPT;
        end if;
      end if;

      if rst = '1' then
        flags <= FLAGS_INIT;
        orun  <= (others => '0');
        ln    <= LINE_INIT;
        cst   <= COAST_INIT;
        trv   <= TRAVEL_INIT;
        shd   <= (others => SHADOW_INIT);
      end if;
    end if;

  end process stage_h;

  loss_o   <= flags.loss;
  over_o   <= flags.over;
  stuck_o  <= flags.stuck;
  glitch_o <= flags.glitch;
  lost_o   <= flags.lost;
  travel_o <= trv.s(24 downto 5);

end architecture rtl;
