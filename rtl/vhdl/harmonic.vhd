-- harmonic: assembles the fine phase from the octant and the phase table, with the
-- adaptive compensation of its periodic error (VHDL edition of rtl/harmonic.v, whose
-- header states the arithmetic, the observer, the learning rule and the timing in full;
-- bit-true model and reasoning: sim/model/harmonic.py).
--
-- phase = (2048 oct2 +- PH[j]) mod 8192, its bin b = phase >> 7 (rtl/vhdl/hbin.vhd, from
-- the address's scale t_i before the phase table is read), A the table of 64 entries,
-- R = sum(A) - 8192:
--   phase_o   = phase
--   phase_c_o = phase - ((A[b] - (R >>> 6)) >>> 8) while apply_i and the table is
--               significant (sig), else phase
-- An observer of the corrected phase, in gears of blocks of 2**g samples, tells which
-- samples may teach the table (LMS step 2^-(3 + mu_i + ...)); an update is written when
-- the sample 9 arrivals later arrives. clear_i empties the table (a 64-edge sweep).
--
-- Timing, a = the edge on which valid_i is high:
--   a      tick, gear and candidate decisions; the commit of the candidate k - 9
--   a + 1  t_i registered (b0, b1 formed before it); table read (OPT_DISTRAM = 0) or its
--          addresses registered (OPT_DISTRAM = 1); apply_i sampled
--   a + 2  phase_o, phase_c_o, valid_o (ph_i valid after a + 1)
--   a + 3 .. a + 6  the block's sum and mean, the observer, the learning error
--   a + 7  the update (learn_i, mu_i sampled)
--   a + 8  the new entry, pending until sample k + 9 arrives
-- Formats: oct2_i u2; t_i u12; ph_i u12 (PH[j], ~PH[j] for neg, rtl/lut.v); mu_i u2;
-- phase_o, phase_c_o u13 (8192 per signal period); entries s8.8 units (1/256 unit),
-- R s23, N u21, P u13.5, V s13.13 units/tick, C u11 ticks, M s13.17, E s13.5.
-- No reset input: the table and the registers start from their power-up values.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;

entity harmonic is
  generic (
    -- the thresholds of the bins (hbin_pkg): 1 exact table, 0 the paper's
    TABLE_EXACT : integer range 0 to 1 := 1;
    -- 1: the table read asynchronously from the candidates' registered addresses
    -- (distributed RAM); 0: read on edge a + 1 (block RAM). The results are the same.
    OPT_DISTRAM : integer range 0 to 1 := 0;
    -- the observer's gears 0..GEARS (blocks of 2**g samples)
    GEARS : integer range 0 to 11 := 11;
    -- sig: the table is shown once N - |R + 8192| > SHOW, hidden again at SHOW / 2 or
    -- below; 0: always shown
    SHOW : integer range 0 to 2097151 := 32768
  );
  port (
    clk       : in    std_logic;
    valid_i   : in    std_logic;             -- the sample's arrival (edge a)
    oct2_i    : in    unsigned(1 downto 0);  -- with valid_i: base phase 2048 oct2
    neg_i     : in    std_logic;             -- with valid_i: phase = base - ph
    t_i       : in    unsigned(11 downto 0); -- u12 address scale, before edge a + 1
    ph_i      : in    unsigned(11 downto 0); -- u12 PH[j], ~PH[j] for neg, after a + 1
    apply_i   : in    std_logic;             -- apply the correction to phase_c_o
    learn_i   : in    std_logic;             -- update the table
    mu_i      : in    unsigned(1 downto 0);  -- LMS step 2^-(3 + mu_i) in gear 0
    clear_i   : in    std_logic;             -- one-clock pulse: empty the table
    valid_o   : out   std_logic;
    phase_o   : out   phase_t;               -- u13 uncorrected fine phase (edge a + 2)
    phase_c_o : out   phase_t                -- u13 corrected fine phase (edge a + 2)
  );
end entity harmonic;

architecture rtl of harmonic is

  -- ---- formats -------------------------------------------------------------------------
  -- A[b], s8.8 units
  subtype entry_t is signed(15 downto 0);

  -- R = sum(A) - 8192, s23
  subtype rsum_t is signed(22 downto 0);

  -- N = sum(|A|) and |R + 8192|, u21
  subtype nsum_t is unsigned(20 downto 0);

  -- a bin, u6
  subtype bin_t is unsigned(5 downto 0);

  -- an observer gear, 0..GEARS
  subtype gear_t is unsigned(3 downto 0);

  -- an update of an entry, s12 (1/256 units)
  subtype step_t is signed(11 downto 0);

  -- E, s13.5
  subtype err_t is signed(17 downto 0);

  -- P and the block's mean, u13.5 (wrap with the period)
  subtype fix18_t is unsigned(17 downto 0);

  -- Y = 4096 E - M, s31
  subtype ymean_t is signed(30 downto 0);

  type table_t is array (0 to 63) of entry_t;

  -- A gear request (the observer's, per sample) and a gear change (on a tick): keep, one
  -- up, one down, back to gear 0 (the lock is lost).
  type gear_move_t is (g_keep, g_up, g_down, g_zero);

  type ring_t is array (0 to 7) of gear_move_t;

  -- What travels with a sample from its arrival to the observer's stage.
  type tag_t is record
    tick : std_logic;   -- it ends a block
    conv : gear_move_t; -- the gear change decided on its tick
    gear : gear_t;      -- the gear of the block it belongs to
  end record tag_t;

  constant TAG_0 : tag_t := (tick => '0', conv => g_keep, gear => (others => '0'));

  -- The observer's state, changed on ticks.
  type observer_t is record
    p : fix18_t;               -- P, u13.5 (wraps with the period)
    v : signed(25 downto 0);   -- V, s13.13 units/tick (wraps)
    c : unsigned(10 downto 0); -- C, u11 ticks since |E| >= 1024 units (saturating)
    m : signed(29 downto 0);   -- M, s13.17: running mean of E
  end record observer_t;

  constant OBS_0 : observer_t :=
  (
    p => (others => '0'),
    v => (others => '0'),
    c => (others => '0'),
    m => (others => '0')
  );

  constant R0      : rsum_t              := to_signed(-8192, 23);
  constant SIG_ON  : signed(21 downto 0) := to_signed(SHOW, 22);
  constant SIG_OFF : signed(21 downto 0) := to_signed(SHOW / 2, 22);

  -- ---- arithmetic ----------------------------------------------------------------------

  -- 0 or 1: a rounding bit as an addend
  function bit_val (b : std_logic) return natural is
  begin

    if b = '1' then
      return 1;
    end if;

    return 0;

  end function bit_val;

  -- v = 0 or v = -1 (all bits equal)
  function all_sign (v : signed) return boolean is
  begin

    return v = 0 or v = -1;

  end function all_sign;

  -- |a| of an entry (one's complement: a xor its sign)
  function mag (a : entry_t) return nsum_t is
  begin

    return resize(unsigned(a xor (a'range => a(a'high))), nsum_t'length);

  end function mag;

  -- |R + 8192| = |sum(A)| (one's complement; |sum A| < 2**21)
  function smag (r : rsum_t) return nsum_t is

    variable sa : rsum_t;

  begin

    sa := r + 8192;
    return unsigned(sa(20 downto 0) xor (20 downto 0 => sa(22)));

  end function smag;

  function next_gear (g : gear_t; mv : gear_move_t) return gear_t is
  begin

    -- (if, not case: GHDL 2.0's netlist leaves Yosys a latch for a case, README.md)
    if mv = g_zero then
      return (others => '0');
    elsif mv = g_up then
      return g + 1;
    elsif mv = g_down then
      return g - 1;
    end if;

    return g;

  end function next_gear;

  -- y = (~A + R' + 256) >> 8 (u13, mod 2**13) of the word c selects, 0 unless u: phase
  -- + y = phase - floor((A - R') / 256). Both sums, then an AND-OR behind them (a
  -- multiplexer would let synthesis share one adder behind a multiplexer of the words:
  -- rtl/harmonic.v)
  function ysum (
    w0 : entry_t;
    w1 : entry_t;
    c : std_logic;
    u : std_logic;
    rq : signed(20 downto 0)
  ) return phase_t is

    variable ys0 : signed(20 downto 0);
    variable ys1 : signed(20 downto 0);

  begin

    ys0 := not resize(w0, 21) + rq;
    ys1 := not resize(w1, 21) + rq;
    return (unsigned(ys1(20 downto 8)) and (12 downto 0 => c and u))
           or (unsigned(ys0(20 downto 8)) and (12 downto 0 => not c and u));

  end function ysum;

  -- the block's mean, 32 base + (32 S >>> g) (u13.5, wraps)
  function block_mean (base : phase_t; s : signed(23 downto 0); g : gear_t) return fix18_t is

    variable sh : signed(28 downto 0);

  begin

    sh := asr(s & "00000", to_integer(g));
    return (base & "00000") + unsigned(sh(17 downto 0));

  end function block_mean;

  -- ---- the observer (stage 6) ----------------------------------------------------------

  -- the step, round(E / 4) while C < 256, else round(E / 128): E >>> 2 or E >>> 7 here,
  -- the rounding bit (obs_round) joins the adders' carry
  function obs_de (e : err_t; c : unsigned(10 downto 0)) return signed is
  begin

    if c < 256 then
      return e(17 downto 2);
    end if;

    return resize(e(17 downto 7), 16);

  end function obs_de;

  function obs_round (e : err_t; c : unsigned(10 downto 0)) return natural is
  begin

    if c < 256 then
      return bit_val(e(1));
    end if;

    return bit_val(e(6));

  end function obs_round;

  -- the lock is lost: |E| >= 1024 units
  function obs_lost (e : err_t) return boolean is
  begin

    return not all_sign(e(17 downto 15));

  end function obs_lost;

  -- |V| (one's complement)
  function obs_av (v : signed(25 downto 0)) return unsigned is
  begin

    return unsigned(v xor (v'range => v(25)));

  end function obs_av;

  -- the lag is small: |M| < 2 units
  function obs_quiet (m : signed(29 downto 0)) return boolean is
  begin

    return m(29 downto 18) = 0 or (m(29 downto 18) = -1 and m(17 downto 0) /= 0);

  end function obs_quiet;

  -- the learning window: C = 2047, 16 <= |V| >> 13 < 512, and above gear 0 |M| < 2
  -- units and |E| < 64 units
  function obs_win (o : observer_t; g : gear_t; e : err_t) return boolean is

    variable av : unsigned(25 downto 0);

  begin

    av := obs_av(o.v);
    return o.c = 2047 and av(25 downto 22) = 0 and av(21 downto 17) /= 0
           and (g = 0 or (obs_quiet(o.m) and all_sign(e(17 downto 11))));

  end function obs_win;

  -- the gear request as the sample finds the observer: lost (C = 0), up (locked, |M| < 2
  -- units, |V| < 16 units/tick), down (|V| >= 64 units/tick)
  function obs_req (o : observer_t) return gear_move_t is

    variable av : unsigned(25 downto 0);

  begin

    av := obs_av(o.v);

    if o.c = 0 then
      return g_zero;
    elsif o.c = 2047 and obs_quiet(o.m) and av(25 downto 17) = 0 then
      return g_up;
    elsif av(25 downto 19) /= 0 then
      return g_down;
    end if;

    return g_keep;

  end function obs_req;

  -- the prediction's step W >>> 8 (mod 2**18) as converted for the next block: 1.5 V
  -- (up), 0.75 V (down), 0 (to gear 0), V
  function obs_w8 (v : signed(25 downto 0); cv : gear_move_t) return fix18_t is

    variable w : signed(25 downto 0);

  begin

    -- (if, not case: GHDL 2.0's netlist leaves Yosys a latch for a case, README.md)
    if cv = g_up then
      w := v + asr(v, 1);
    elsif cv = g_down then
      w := v - asr(v, 2);
    elsif cv = g_zero then
      w := (others => '0');
    else
      w := v;
    end if;

    return unsigned(w(25 downto 8));

  end function obs_w8;

  -- V as converted for the next block: 2 V, V / 2, 0, V
  function obs_vc (v : signed(25 downto 0); cv : gear_move_t) return signed is
  begin

    -- (if, not case: GHDL 2.0's netlist leaves Yosys a latch for a case, README.md)
    if cv = g_up then
      return shift_left(v, 1);
    elsif cv = g_down then
      return asr(v, 1);
    elsif cv = g_zero then
      return to_signed(0, v'length);
    end if;

    return v;

  end function obs_vc;

  -- C: 0 when the lock is lost, else one more (saturating at 2047); at most 1791 after a
  -- gear change
  function obs_c (c : unsigned(10 downto 0); e : err_t; cv : gear_move_t) return unsigned is
  begin

    if obs_lost(e) then
      return to_unsigned(0, c'length);
    elsif cv /= g_keep and c >= 1791 then
      return to_unsigned(1791, c'length);
    elsif c = 2047 then
      return c;
    end if;

    return c + 1;

  end function obs_c;

  -- Y = 4096 E - M (s31)
  function ymean (e : err_t; m : signed(29 downto 0)) return ymean_t is
  begin

    return (resize(e, 19) & x"000") - resize(m, 31);

  end function ymean;

  -- M + round(Y / 1024); 0 after a gear change
  function obs_m (e : err_t; m : signed(29 downto 0); cv : gear_move_t) return signed is

    variable y : ymean_t;

  begin

    y := ymean(e, m);

    if cv /= g_keep then
      return to_signed(0, m'length);
    end if;

    return m + resize(y(30 downto 10), 30) + bit_val(y(9));

  end function obs_m;

  -- The observer on a tick with E = e and the gear change cv.
  function observe (o : observer_t; e : err_t; cv : gear_move_t) return observer_t is

    variable r : observer_t;

  begin

    r.p := o.p + obs_w8(o.v, cv) + unsigned(resize(obs_de(e, o.c), 18)) + obs_round(e, o.c);
    r.v := obs_vc(o.v, cv) + resize(obs_de(e, o.c), 26) + obs_round(e, o.c);
    r.c := obs_c(o.c, e, cv);
    r.m := obs_m(e, o.m, cv);
    return r;

  end function observe;

  -- ext = ((V >>> 1) - (V >>> (g + 1))) >>> 8: the block's mean moved to its last sample
  function obs_ext (v : signed(25 downto 0); g : gear_t) return signed is

    variable vh  : signed(25 downto 0);
    variable ext : signed(25 downto 0);

  begin

    vh  := asr(v, 1);
    ext := vh - asr(vh, to_integer(g));
    return ext(25 downto 8);

  end function obs_ext;

  -- E = meas + ext - P (s13.5, wraps): one carry-save step (-P = ~P + 1, the 1 in the
  -- carry's free bit 0), then one carry chain
  function obs_e (meas : fix18_t; x : fix18_t; p : fix18_t) return err_t is

    variable ez : fix18_t;
    variable cy : fix18_t;

  begin

    ez := not p;
    cy := (meas and x) or (meas and ez) or (x and ez);
    return signed((meas xor x xor ez) + (cy(16 downto 0) & '1'));

  end function obs_e;

  -- ---- the update (stages 8 and 9) -----------------------------------------------------

  -- the step: X = Y - R >>> 7 (s20) saturated to s12, >>> (mu_i + gshift + anneal)
  function lms_step (y : signed(18 downto 0); r : rsum_t; mu : natural) return step_t is
  begin

    return asr(saturate(resize(y, 20) - resize(r(22 downto 7), 20), 12), mu);

  end function lms_step;

  -- the new entry A + d (s17): made only if it stays in s16
  function entry_sum (a : entry_t; d : step_t) return signed is
  begin

    return resize(a, 17) + resize(d, 17);

  end function entry_sum;

  function entry_ovf (a : entry_t; d : step_t) return boolean is

    variable hs : signed(16 downto 0);

  begin

    hs := entry_sum(a, d);
    return hs(16) /= hs(15);

  end function entry_ovf;

  -- ---- stage 1 (edge a): candidates, commit, sweep, sig --------------------------------
  signal swp   : unsigned(6 downto 0)  := (others => '0');    -- clear sweep: words left
  signal skip  : unsigned(4 downto 0)  := (others => '0');
  signal lfsr  : unsigned(7 downto 0)  := x"E1";
  signal cc    : unsigned(3 downto 0)  := (others => '0');    -- arrivals until the commit
  signal r_sum : rsum_t                := R0;
  signal n_sum : nsum_t                := (others => '0');
  signal n_q   : nsum_t                := (others => '0');    -- N on the last arrival
  signal s_q   : nsum_t                := (others => '0');    -- |R + 8192| on it
  signal d_q   : signed(21 downto 0)   := (others => '0');    -- N - |R + 8192| before
  signal sig   : std_logic             := '0';
  signal gear  : gear_t                := (others => '0');    -- the block being collected
  signal tcnt  : unsigned(10 downto 0) := (others => '0');    -- arrivals until the tick
  signal hold  : unsigned(2 downto 0)  := "111";              -- arrivals since a change
  signal n1    : unsigned(2 downto 0)  := (others => '0');    -- arrivals mod 8
  signal ring  : ring_t                := (others => g_keep); -- requests by sample
  signal v1    : std_logic             := '0';
  signal cand1 : std_logic             := '0';
  signal blk1  : std_logic             := '0';
  signal neg1  : std_logic             := '0';
  signal oct1  : unsigned(1 downto 0)  := (others => '0');
  signal tag1  : tag_t                 := TAG_0;

  signal sweeping : boolean;
  signal tick     : boolean;
  signal req      : gear_move_t;
  signal conv     : gear_move_t;
  signal g_new    : gear_t;
  signal cand     : boolean;
  signal commit   : boolean;

  -- ---- the pending update (stages 3, 9) ------------------------------------------------
  signal pw  : std_logic := '0';             -- valid
  signal hp  : entry_t   := (others => '0'); -- the entry (0 while sweeping)
  signal pd  : step_t    := (others => '0'); -- the entry - the old entry
  signal lb  : bin_t     := (others => '0'); -- the candidate's bin
  signal lha : entry_t   := (others => '0'); -- the candidate's A[b] before it
  signal lok : std_logic := '0';             -- no clear since it arrived

  -- ---- stage 2 (edge a + 1): table reads -----------------------------------------------
  signal mem0 : table_t := (others => (others => '0')); -- b0's copy
  signal mem1 : table_t := (others => (others => '0')); -- b1's copy

  signal t2    : unsigned(11 downto 0) := (others => '0');
  signal oct2q : unsigned(1 downto 0)  := (others => '0');
  signal cw2   : std_logic             := '0';             -- a commit wrote lb on the read's edge
  signal v2    : std_logic             := '0';
  signal cand2 : std_logic             := '0';
  signal ok2   : std_logic             := '0';
  signal neg2  : std_logic             := '0';
  signal tag2  : tag_t                 := TAG_0;
  signal k0    : phase_t               := (others => '0'); -- 2048 oct2 + neg
  signal rq2   : signed(20 downto 0)   := (others => '0'); -- R >>> 6, plus 256
  signal ub2   : std_logic             := '0';             -- the correction is used (pc)
  signal ua2   : std_logic             := '0';             -- and applied (phase_c_o)

  signal wa   : bin_t;
  signal we   : boolean;
  signal rb0  : bin_t;     -- the candidates from t_i (the read's addresses)
  signal rb1  : bin_t;
  signal sb0  : bin_t;     -- the candidates of the sample read (from t2)
  signal sb1  : bin_t;
  signal c2   : std_logic; -- t reaches its bucket's threshold
  signal bin2 : bin_t;
  signal a0   : entry_t;   -- A[b0], A[b1] as the writes on edges <= a left them
  signal a1   : entry_t;

  -- ---- stage 3 (edge a + 2): the phases ------------------------------------------------
  signal valid_q : std_logic := '0';
  signal phase_q : phase_t   := (others => '0');
  signal ya      : phase_t   := (others => '0'); -- y applied (phase_c_o)
  signal yb      : phase_t   := (others => '0'); -- y used (pc)
  signal v3      : std_logic := '0';
  signal cand3   : std_logic := '0';
  signal tag3    : tag_t     := TAG_0;

  -- ---- stage 4 (edge a + 3): the block's sum -------------------------------------------
  signal v4    : std_logic           := '0';
  signal cand4 : std_logic           := '0';
  signal tag4  : tag_t               := TAG_0;
  signal first : std_logic           := '1';             -- the block's first sample
  signal base  : phase_t             := (others => '0'); -- its pc
  signal s_sum : signed(23 downto 0) := (others => '0'); -- S, sum of pc - base

  -- ---- stage 5 (edge a + 4): the block's mean ------------------------------------------
  signal v5    : std_logic := '0';
  signal cand5 : std_logic := '0';
  signal tag5  : tag_t     := TAG_0;
  signal meas5 : fix18_t   := (others => '0');

  -- ---- stage 6 (edge a + 5): the observer ----------------------------------------------
  signal obs   : observer_t           := OBS_0;
  signal n6    : unsigned(2 downto 0) := (others => '0'); -- the ring's write index
  signal g_nxt : gear_t               := (others => '0'); -- the block after the last tick
  signal ext_q : signed(17 downto 0)  := (others => '0');
  signal cand6 : std_logic            := '0';
  signal tick6 : std_logic            := '0';
  signal win6  : std_logic            := '0';
  signal g0_6  : std_logic            := '0';
  signal gs6   : std_logic            := '0';
  signal e6    : err_t                := (others => '0');
  signal y6    : ymean_t              := (others => '0');
  signal e6w   : err_t;

  -- ---- stages 7 to 9 (edges a + 6 .. a + 8): the update --------------------------------
  signal cand7 : std_logic             := '0';
  signal win7  : std_logic             := '0';
  signal lock7 : std_logic             := '0';
  signal gs7   : std_logic             := '0';
  signal g0_7  : std_logic             := '0';
  signal y7    : signed(18 downto 0)   := (others => '0');
  signal d8    : step_t                := (others => '0');
  signal g8    : std_logic             := '0';
  signal cand8 : std_logic             := '0';
  signal nup   : unsigned(13 downto 0) := (others => '0'); -- updates since a clear (sat.)
  signal gsh   : natural range 0 to 2;
  signal anl   : natural range 0 to 3;

begin

  -- ---- stage 1 ---------------------------------------------------------------------------
  sweeping <= swp /= 0;
  tick     <= tcnt = 0;

  -- the request the observer made for the sample 6 arrivals before, if after a change
  req <= ring(to_integer(n1 + 2)) when hold = 7 else
         g_keep;

  conv <= g_keep when not tick else
          g_zero when req = g_zero and gear /= 0 else
          g_up when req = g_up and gear < GEARS else
          g_down when req = g_down and gear /= 0 else
          g_keep;

  g_new  <= next_gear(gear, conv);
  cand   <= skip = 0 and tick;
  commit <= valid_i = '1' and cc = 1 and pw = '1' and clear_i = '0';

  -- The tick schedule, the gear, the candidates (the first tick after 10..17 samples), the
  -- commit of the pending update, the clear's sweep, R, N and sig.
  arrival : process (clk) is
  begin

    if rising_edge(clk) then
      v1 <= valid_i;

      if valid_i = '1' then
        oct1      <= oct2_i;
        neg1      <= neg_i;
        cand1     <= to_sl(cand);
        tag1.tick <= to_sl(tick);
        tag1.conv <= conv;
        tag1.gear <= gear;
        blk1      <= clear_i or to_sl(sweeping);
        n1        <= n1 + 1;

        -- a tick ends the block: the next one is 2**g_new samples long
        if tick then
          gear <= g_new;
          tcnt <= not shift_left(to_unsigned(16#7FF#, 11), to_integer(g_new));
        else
          tcnt <= tcnt - 1;
        end if;

        if conv /= g_keep then
          hold <= to_unsigned(1, 3);
        elsif hold /= 7 then
          hold <= hold + 1;
        end if;

        if cand then
          skip <= 9 + resize(lfsr(2 downto 0), 5);
          -- the Galois LFSR 0xB8, one step per candidate
          if lfsr(0) = '1' then
            lfsr <= shift_right(lfsr, 1) xor x"B8";
          else
            lfsr <= shift_right(lfsr, 1);
          end if;
          cc <= to_unsigned(9, 4);
        else
          if skip /= 0 then
            skip <= skip - 1;
          end if;
          if cc /= 0 then
            cc <= cc - 1;
          end if;
        end if;
      end if;

      if clear_i = '1' then
        swp <= to_unsigned(64, 7);
      elsif sweeping then
        swp <= swp - 1;
      end if;

      if clear_i = '1' then
        r_sum <= R0;
        n_sum <= (others => '0');
        n_q   <= (others => '0');
        s_q   <= (others => '0');
        d_q   <= (others => '0');
        sig   <= '0';
      else
        if commit then
          r_sum <= r_sum + pd;
          n_sum <= n_sum + mag(hp) - mag(lha);
        end if;

        if valid_i = '1' then
          n_q <= n_sum;
          s_q <= smag(r_sum);
          d_q <= signed('0' & n_q) - signed('0' & s_q);

          if sig = '1' then
            sig <= to_sl(d_q > SIG_OFF);
          else
            sig <= to_sl(d_q > SIG_ON);
          end if;
        end if;
      end if;
    end if;

  end process arrival;

  -- ---- stage 2 ---------------------------------------------------------------------------
  -- the sweep writes 0 (hp) to 0, 1, .., 63; a commit writes hp to lb
  wa <= 0 - swp(5 downto 0) when sweeping else
        lb;
  we <= sweeping or commit;

  -- the candidates of the arriving sample, from t_i (the RAM's addresses)
  u_bin1 : entity work.hbin
    generic map (
      table_exact => TABLE_EXACT
    )
    port map (
      oct2_i => oct1,
      neg_i  => neg1,
      t_i    => t_i,
      b0_o   => rb0,
      b1_o   => rb1,
      c_o    => open,
      bin_o  => open
    );

  -- the same from t registered: the choice between the words read, and the bin
  u_bin2 : entity work.hbin
    generic map (
      table_exact => TABLE_EXACT
    )
    port map (
      oct2_i => oct2q,
      neg_i  => neg2,
      t_i    => t2,
      b0_o   => sb0,
      b1_o   => sb1,
      c_o    => c2,
      bin_o  => bin2
    );

  g_async : if OPT_DISTRAM = 1 generate

    -- Distributed RAM: the addresses registered, the copies written one edge late (so
    -- that the asynchronous read after a + 1 holds the writes on edges <= a).
    signal we_q  : boolean := false;
    signal wa_q  : bin_t   := (others => '0');
    signal hp_q  : entry_t := (others => '0');
    signal rb0_q : bin_t   := (others => '0');
    signal rb1_q : bin_t   := (others => '0');

  begin

    ram : process (clk) is
    begin

      if rising_edge(clk) then
        if v1 = '1' then
          rb0_q <= rb0;
          rb1_q <= rb1;
        end if;

        we_q <= we;
        wa_q <= wa;
        hp_q <= hp;

        if we_q then
          mem0(to_integer(wa_q)) <= hp_q;
          mem1(to_integer(wa_q)) <= hp_q;
        end if;
      end if;

    end process ram;

    a0 <= mem0(to_integer(rb0_q));
    a1 <= mem1(to_integer(rb1_q));

  end generate g_async;

  g_sync : if OPT_DISTRAM = 0 generate

    -- Block RAM: read on a + 1, when a commit may write the same word: the result is then
    -- undefined on the FPGA and taken as the word before the write, lha (the candidate's
    -- entry). (A sweep's write may hit it too; those samples are blocked.)
    signal rd0_q : entry_t := (others => '0');
    signal rd1_q : entry_t := (others => '0');

  begin

    ram : process (clk) is

      variable rd0 : entry_t;
      variable rd1 : entry_t;

    begin

      if rising_edge(clk) then
        if we then
          mem0(to_integer(wa)) <= hp;
          mem1(to_integer(wa)) <= hp;
        end if;

        if v1 = '1' then
          rd0 := mem0(to_integer(rb0));
          rd1 := mem1(to_integer(rb1));
          -- pragma translate_off
          -- simulation: a word written on the read's edge reads inverted, so that a
          -- result relying on the undefined read differs from the model
          if we and wa = rb0 then
            rd0 := not rd0;
          end if;
          if we and wa = rb1 then
            rd1 := not rd1;
          end if;
          -- pragma translate_on
          rd0_q <= rd0;
          rd1_q <= rd1;
        end if;
      end if;

    end process ram;

    a0 <= lha when cw2 = '1' and lb = sb0 else
          rd0_q;
    a1 <= lha when cw2 = '1' and lb = sb1 else
          rd1_q;

  end generate g_sync;

  read_stage : process (clk) is
  begin

    if rising_edge(clk) then
      v2    <= v1;
      cand2 <= v1 and cand1;
      cw2   <= to_sl(commit and not sweeping);

      if v1 = '1' then
        t2    <= t_i;
        oct2q <= oct1;
        tag2  <= tag1;
        ok2   <= not blk1 and not clear_i;
        neg2  <= neg1;
        k0    <= (oct1 & 11x"000") + bit_val(neg1);
        rq2   <= resize(r_sum(22 downto 6), 21) + 256;
        ub2   <= not blk1;
        ua2   <= not blk1 and apply_i and (sig or to_sl(SHOW = 0));
      end if;
    end if;

  end process read_stage;

  -- ---- stage 3 ---------------------------------------------------------------------------
  -- phase = 2048 oct2 + neg + {neg, ph} (- ph - 1 = {1, ~ph} for neg)
  phase_stage : process (clk) is
  begin

    if rising_edge(clk) then
      valid_q <= v2;
      v3      <= v2;
      cand3   <= v2 and cand2;

      if v2 = '1' then
        tag3    <= tag2;
        phase_q <= k0 + (neg2 & ph_i);
        ya      <= ysum(a0, a1, c2, ua2, rq2);
        yb      <= ysum(a0, a1, c2, ub2, rq2);
      end if;

      if v2 = '1' and cand2 = '1' then
        lb  <= bin2;
        lha <= a1 when c2 = '1' else a0;
        lok <= ok2 and not clear_i;
      elsif clear_i = '1' then
        lok <= '0';
      end if;
    end if;

  end process phase_stage;

  -- ---- stage 4: the block's first pc is its base, the others add pc - base (s13) to S ----
  sum_stage : process (clk) is
  begin

    if rising_edge(clk) then
      v4    <= v3;
      cand4 <= cand3;

      if v3 = '1' then
        tag4  <= tag3;
        first <= tag3.tick;

        if first = '1' then
          base  <= phase_q + yb;
          s_sum <= (others => '0');
        else
          s_sum <= s_sum + resize(signed(phase_q + yb - base), 24);
        end if;
      end if;
    end if;

  end process sum_stage;

  -- ---- stage 5 ---------------------------------------------------------------------------
  mean_stage : process (clk) is
  begin

    if rising_edge(clk) then
      v5    <= v4;
      cand5 <= cand4;

      if v4 = '1' then
        tag5  <= tag4;
        meas5 <= block_mean(base, s_sum, tag4.gear);
      end if;
    end if;

  end process mean_stage;

  -- ---- stage 6 ---------------------------------------------------------------------------
  -- ext from V and the gear after every tick (ready before the next tick's observer when
  -- that tick ends a block above gear 0); used only above gear 0
  e6w <= obs_e(meas5, unsigned(ext_q) and (17 downto 0 => to_sl(tag5.gear /= 0)), obs.p);

  observer : process (clk) is
  begin

    if rising_edge(clk) then
      ext_q <= obs_ext(obs.v, g_nxt);

      if v5 = '1' then
        ring(to_integer(n6)) <= obs_req(obs);
        n6                   <= n6 + 1;
      end if;

      if v5 = '1' and tag5.tick = '1' then
        obs   <= observe(obs, e6w, tag5.conv);
        g_nxt <= next_gear(tag5.gear, tag5.conv);
        win6  <= to_sl(obs_win(obs, tag5.gear, e6w));
        e6    <= e6w;
        y6    <= ymean(e6w, obs.m);
        g0_6  <= to_sl(tag5.gear = 0);
        gs6   <= to_sl(tag5.gear >= 4);
      end if;

      tick6 <= v5 and tag5.tick;
      cand6 <= cand5;
    end if;

  end process observer;

  -- ---- stage 7: the learning error (E minus its mean in gear 0, E above), the lock -------
  error_stage : process (clk) is
  begin

    if rising_edge(clk) then
      cand7 <= cand6;

      if tick6 = '1' then
        win7  <= win6;
        lock7 <= to_sl(all_sign(e6(17 downto 13)));
        gs7   <= gs6;
        g0_7  <= g0_6;

        if g0_6 = '1' then
          y7 <= y6(30 downto 12);
        else
          y7 <= resize(e6, 19);
        end if;
      end if;
    end if;

  end process error_stage;

  -- ---- stage 8: the step 2^-(mu_i + gshift + anneal) ------------------------------------
  -- gshift: 0 in gear 0, 1 in gears 1..3, 2 from gear 4; anneal: 1, 2, 3 from 2048, 4096,
  -- 8192 updates since a clear
  gsh <= 2 when gs7 = '1' else
         0 when g0_7 = '1' else
         1;
  anl <= 3 when nup(13) = '1' else
         2 when nup(12) = '1' else
         1 when nup(11) = '1' else
         0;

  update_stage : process (clk) is
  begin

    if rising_edge(clk) then
      if cand7 = '1' then
        d8 <= lms_step(y7, r_sum, to_integer(mu_i) + gsh + anl);
      end if;

      g8    <= cand7 and learn_i and win7 and lock7;
      cand8 <= cand7;
    end if;

  end process update_stage;

  -- ---- stage 9: the new entry, pending until sample k + 9 arrives ----------------------
  entry_stage : process (clk) is

    variable made : boolean;

  begin

    if rising_edge(clk) then
      made := g8 = '1' and lok = '1' and not entry_ovf(lha, d8);

      if clear_i = '1' then
        pw  <= '0';
        hp  <= (others => '0');
        nup <= (others => '0');
      elsif cand8 = '1' then
        pw <= to_sl(made);

        if made then
          hp <= entry_sum(lha, d8)(15 downto 0);
          pd <= d8;

          if nup(13) = '0' then
            nup <= nup + 1;
          end if;
        end if;
      end if;
    end if;

  end process entry_stage;

  valid_o   <= valid_q;
  phase_o   <= phase_q;
  phase_c_o <= phase_q + ya;

end architecture rtl;
