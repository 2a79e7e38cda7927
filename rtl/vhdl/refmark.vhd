-- refmark: reference marks (VHDL edition of rtl/refmark.v, which describes the reference
-- point, the window, Z, the latch, homing and pos_valid in full; model
-- sim/model/refmark.py).
--
-- A sample whose count step crosses a reference point (the count c = B + q at which
-- q = ref_q_i, once per signal period) inside the window (ref_i glitch-filtered over
-- filt_i + 1 samples) arms Z at the crossed count x (z_en_o, z_at_o, for rtl/abgen.v) and,
-- once per pass, latches: REF_COUNT = x + off, homed_o; with homing armed (home_arm_i)
-- the latch (or, with distance-coded marks, the decode: dc_home_i) sets off and
-- pos_valid_o. A sample that lost the travel (lost_i) or at overspeed, or inval_i, clears
-- pos_valid_o (lost_o pulses). The Eq. 12 pins (pa_o, pb_o) and their Z (zp_o) for
-- ABGEN.ab_src = 1. cross_o, cdir_o, mark_o, x_o and inv_o feed rtl/dcode.v.
--
-- Timing (t = the sample's strobe edge in the core):
--   t + 8  kf, kr, zok from q_i (nv_i, registered with the n-th order product on t + 7)
--   t + 9  the window, the crossing and x; Z armed; target_o
--   t + 10 REF_COUNT, off, homed, pos_valid, home_armed_o; latch_o, lost_o; pa_o, pb_o, zp_o
-- Formats: q_i, ref_q_i u11 counts within the signal period (0 .. 4 n - 1); n_i u9;
-- filt_i u4 samples; count_i, pos_i, target_o, z_at_o, x_o, off_o, ref_count_o, home_i,
-- dc_off_i, dc_ref_i s(COUNT_W).0 counts (wrap). Power-up values are those after rst.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;

entity refmark is
  generic (
    -- counter width (wraps), 17..32
    COUNT_W : integer range 17 to 32 := 32
  );
  port (
    clk : in    std_logic;
    rst : in    std_logic; -- sync, active high
    -- t + 7: the sample's n-th order product (rtl/lut.v prod_o), its count part
    nv_i    : in    std_logic;             -- valid on t + 7
    q_i     : in    unsigned(10 downto 0); -- u11 floor(n phase / 2048)
    n_i     : in    n_t;                   -- u9 n
    ref_q_i : in    unsigned(10 downto 0); -- u11 REF.ref_q
    filt_i  : in    unsigned(3 downto 0);  -- u4 REF.ref_filt
    mode_i  : in    std_logic;             -- count mode: '1' edge
    -- t + 8: the sample's count (rtl/counter.v) and its reference input
    cv_i    : in    std_logic;
    count_i : in    signed(COUNT_W - 1 downto 0); -- the count before off
    held_i  : in    std_logic;                    -- the count held
    lost_i  : in    std_logic;                    -- with cv_i: the travel lost
    ovs_i   : in    std_logic;
    ref_i   : in    std_logic;
    -- t + 9: the sample's Eq. 12 pulses (rtl/pulse.v)
    pv_i : in    std_logic;
    pa_i : in    std_logic;
    pb_i : in    std_logic;
    pa_o : out   std_logic; -- the pulses one edge later
    pb_o : out   std_logic;
    zp_o : out   std_logic; -- Z beside them
    -- the pins (rtl/abgen.v)
    pos_i    : in    signed(COUNT_W - 1 downto 0); -- the count the pins show
    target_o : out   signed(COUNT_W - 1 downto 0); -- count_i one edge later
    z_en_o   : out   std_logic;
    z_at_o   : out   signed(COUNT_W - 1 downto 0);
    -- settings and status
    home_arm_i : in    std_logic;                    -- a pulse: home at the next latch
    home_i     : in    signed(COUNT_W - 1 downto 0); -- HOME
    inval_i    : in    std_logic;                    -- a pulse: the count lost its scale
    -- distance-coded marks (rtl/dcode.v)
    dc_en_i      : in    std_logic;                    -- DCODE on: homing waits for dc_home_i
    dc_home_i    : in    std_logic;                    -- the decode sets abs_valid: home now
    dc_off_i     : in    signed(COUNT_W - 1 downto 0); -- with it: HOME + ABS_COUNT - x
    dc_ref_i     : in    signed(COUNT_W - 1 downto 0); -- with it: HOME + ABS_COUNT
    cross_o      : out   std_logic;                    -- t + 9: a reference point crossed
    cdir_o       : out   std_logic;                    -- ('1': back)
    mark_o       : out   std_logic;                    -- t + 9: the sample latches
    x_o          : out   signed(COUNT_W - 1 downto 0); -- its count
    inv_o        : out   std_logic;                    -- t + 9: the count lost its scale
    off_o        : out   signed(COUNT_W - 1 downto 0); -- the homing offset
    ref_count_o  : out   signed(COUNT_W - 1 downto 0);
    win_o        : out   std_logic;                    -- the window (filtered reference)
    homed_o      : out   std_logic;                    -- a reference latched since rst
    pos_valid_o  : out   std_logic;
    home_armed_o : out   std_logic;
    latch_o      : out   std_logic;                    -- a pulse: a reference latched
    lost_o       : out   std_logic                     -- a pulse: pos_valid fell
  );
end entity refmark;

architecture rtl of refmark is

  subtype count_t is signed(COUNT_W - 1 downto 0);

  -- 12-bit count arithmetic (the step, kf, kr: |step| <= 2 n <= 1022 without overspeed)
  subtype k_t is unsigned(11 downto 0);

  -- Where a sample stands against the reference point: kf = (q - ref_q) mod 4 n, the
  -- phase's quadrant q mod 4, and zok = ref_q < 4 n (a count is ever at it).
  type place_t is record
    kf  : k_t;
    qlo : quadrant_t;
    zok : std_logic;
  end record place_t;

  constant PLACE_0 : place_t := (kf => (others => '0'), qlo => (others => '0'), zok => '0');

  -- (a - b) mod 4 n for a, b in 0 .. 4 n - 1: the 12-bit difference, + 4 n when negative
  function mod_n4 (a : unsigned; b : unsigned; n4 : k_t) return k_t is

    variable d : k_t;

  begin

    d := resize(a, 12) - resize(b, 12);

    if d(11) = '1' then
      return d + n4;
    end if;

    return d;

  end function mod_n4;

  -- where the count part q stands against ref_q
  function place_of (q : unsigned; ref_q : unsigned; n4 : k_t) return place_t is
  begin

    return (kf => mod_n4(q, ref_q, n4), qlo => resize(q, 2), zok => to_sl(resize(ref_q, 12) < n4));

  end function place_of;

  signal n4 : k_t; -- 4 n

  -- ---- t + 8 -----------------------------------------------------------------------------
  signal place : place_t := PLACE_0;
  signal kr    : k_t     := (others => '0'); -- (ref_q - q) mod 4 n

  -- ---- t + 9: the window, the crossing, Z ---------------------------------------------
  signal cp      : k_t                  := (others => '0'); -- the previous count, low bits
  signal primed  : std_logic            := '0';             -- cp holds a trusted count
  signal fc      : unsigned(3 downto 0) := (others => '0'); -- samples the input differed
  signal arm     : std_logic            := '0';             -- the latch armed (this pass)
  signal lat1    : std_logic            := '0';
  signal inv1    : std_logic            := '0';
  signal x_q     : count_t              := (others => '0');
  signal place1  : place_t              := PLACE_0;         -- the sample in stage 1
  signal win     : std_logic            := '0';
  signal target  : count_t              := (others => '0');
  signal cross_q : std_logic            := '0';
  signal cdir_q  : std_logic            := '0';
  signal z_en    : std_logic            := '0';
  signal z_at    : count_t              := (others => '0');

  signal dc       : k_t;     -- the step c - c' in 12 bits
  signal fwd      : boolean;
  signal rev      : boolean;
  signal hit      : boolean; -- the step crosses a reference point
  signal flip     : boolean; -- the window takes ref_i
  signal win_n    : std_logic;
  signal xc       : boolean; -- a crossing inside the window
  signal arm_n    : std_logic;
  signal lat_n    : boolean;
  signal xd       : count_t; -- the crossed count's offset from count_i
  signal x        : count_t; -- the crossed count
  signal off_side : boolean; -- Z may be disarmed

  -- ---- t + 10 ----------------------------------------------------------------------------
  signal pins       : ab_t      := (a => '1', b => '1');
  signal zp         : std_logic := '0';
  signal at_ref     : boolean; -- the pulses show the reference count
  signal off        : count_t   := (others => '0');
  signal ref_count  : count_t   := (others => '0');
  signal homed      : std_logic := '0';
  signal pos_valid  : std_logic := '0';
  signal home_armed : std_logic := '0';
  signal latch_q    : std_logic := '0';
  signal lost       : std_logic := '0';

begin

  n4 <= resize(n_i & "00", 12);

  -- ---- t + 8: kf, kr, zok ------------------------------------------------------------------
  place_reg : process (clk) is
  begin

    if rising_edge(clk) then
      if nv_i = '1' then
        place <= place_of(q_i, ref_q_i, n4);
        kr    <= mod_n4(ref_q_i, q_i, n4);
      end if;

      if rst = '1' then
        place <= PLACE_0;
        kr    <= (others => '0');
      end if;
    end if;

  end process place_reg;

  -- ---- t + 9: the crossing of c' -> c: forward kf < c - c', back kr < c' - c ----------
  dc  <= unsigned(count_i(11 downto 0)) - cp;
  fwd <= dc(11) = '0' and dc /= 0;
  rev <= dc(11) = '1';

  crossing : process (all) is

    -- kr + (c - c') < 0 (13 bits): kr < c' - c
    variable rsum : unsigned(12 downto 0);

  begin

    rsum := ('0' & kr) + unsigned(dc(11) & dc);
    hit  <= primed = '1' and mode_i = '0' and place.zok = '1' and held_i = '0' and ovs_i = '0'
            and ((fwd and place.kf < dc) or (rev and rsum(12) = '1'));

  end process crossing;

  flip  <= ref_i /= win and fc >= filt_i;
  win_n <= ref_i when flip else
           win;
  xc    <= cv_i = '1' and hit and win_n = '1';
  arm_n <= arm or (win_n and not win);
  lat_n <= xc and arm_n = '1';
  -- (one adder behind a choice of its operand; a choice between two sums would be two)
  xd <= -signed(resize(place.kf, COUNT_W)) when fwd else
        signed(resize(kr, COUNT_W));
  x  <= count_i + xd;

  -- disarm: the window closed, the pins and their target strictly on one side of z_at
  disarm : process (all) is

    variable sp : count_t;
    variable st : count_t;

  begin

    sp       := pos_i - z_at;
    st       := target - z_at;
    off_side <= win = '0' and sp /= 0 and st /= 0 and sp(COUNT_W - 1) = st(COUNT_W - 1);

  end process disarm;

  window : process (clk) is
  begin

    if rising_edge(clk) then
      target  <= count_i;
      lat1    <= '0';
      inv1    <= '0';
      cross_q <= '0';

      if cv_i = '1' then
        cp     <= unsigned(count_i(11 downto 0));
        primed <= not held_i and not mode_i;
        win    <= win_n;

        if ref_i = win or flip then
          fc <= (others => '0');
        else
          fc <= fc + 1;
        end if;

        arm     <= arm_n and win_n and not to_sl(lat_n);
        lat1    <= to_sl(lat_n);
        inv1    <= lost_i or ovs_i;
        x_q     <= x;
        cross_q <= to_sl(hit);
        cdir_q  <= to_sl(rev);
        place1  <= place;
      end if;

      if xc then
        z_en <= '1';
        z_at <= x;
      elsif off_side then
        z_en <= '0';
      end if;

      if inval_i = '1' then
        primed <= '0';
        z_en   <= '0';
      end if;

      if rst = '1' then
        target  <= (others => '0');
        cp      <= (others => '0');
        primed  <= '0';
        win     <= '0';
        fc      <= (others => '0');
        arm     <= '0';
        lat1    <= '0';
        inv1    <= '0';
        x_q     <= (others => '0');
        cross_q <= '0';
        cdir_q  <= '0';
        place1  <= PLACE_0;
        z_en    <= '0';
        z_at    <= (others => '0');
      end if;
    end if;

  end process window;

  -- ---- t + 10: the Eq. 12 pins and their Z ------------------------------------------------
  -- the pulses show count qp = q - delta (delta = (q - pq) mod 4, 3 as -1): the reference
  -- count when kf = delta (mod 4 n)
  pins_ref : process (all) is

    variable dl : quadrant_t;

  begin

    dl := place1.qlo - quadrant(pa_i, pb_i);

    if dl = 3 then
      at_ref <= place1.kf = n4 - 1;
    else
      at_ref <= place1.kf = resize(dl, 12);
    end if;

  end process pins_ref;

  eq12_pins : process (clk) is
  begin

    if rising_edge(clk) then
      if pv_i = '1' then
        pins <= (a => pa_i, b => pb_i);
        zp   <= to_sl((win = '1' and place1.zok = '1' and at_ref)
                      or (zp = '1' and quadrant(pa_i, pb_i) = quadrant(pins.a, pins.b)));
      end if;

      if rst = '1' then
        pins <= (a => '1', b => '1');
        zp   <= '0';
      end if;
    end if;

  end process eq12_pins;

  -- ---- t + 10: the latch, homing, pos_valid -------------------------------------------------
  homing : process (clk) is
  begin

    if rising_edge(clk) then
      latch_q <= lat1;
      lost    <= pos_valid and (inv1 or inval_i);

      if lat1 = '1' then
        homed <= '1';

        if home_armed = '1' and dc_en_i = '0' then
          pos_valid  <= '1';
          off        <= home_i - x_q;
          ref_count  <= home_i;
          home_armed <= '0';
        else
          ref_count <= x_q + off;
        end if;
      end if;

      -- distance-coded homing (never with lat1 or an invalidation: rtl/dcode.v)
      if dc_home_i = '1' and home_armed = '1' then
        off        <= dc_off_i;
        ref_count  <= dc_ref_i;
        pos_valid  <= '1';
        home_armed <= '0';
      end if;

      if home_arm_i = '1' then
        home_armed <= '1';
      end if;

      if inv1 = '1' or inval_i = '1' then
        pos_valid <= '0';
      end if;

      if rst = '1' then
        latch_q    <= '0';
        lost       <= '0';
        homed      <= '0';
        pos_valid  <= '0';
        home_armed <= '0';
        off        <= (others => '0');
        ref_count  <= (others => '0');
      end if;
    end if;

  end process homing;

  pa_o         <= pins.a;
  pb_o         <= pins.b;
  zp_o         <= zp;
  target_o     <= target;
  z_en_o       <= z_en;
  z_at_o       <= z_at;
  cross_o      <= cross_q;
  cdir_o       <= cdir_q;
  mark_o       <= lat1;
  x_o          <= x_q;
  inv_o        <= inv1 or inval_i;
  off_o        <= off;
  ref_count_o  <= ref_count;
  win_o        <= win;
  homed_o      <= homed;
  pos_valid_o  <= pos_valid;
  home_armed_o <= home_armed;
  latch_o      <= latch_q;
  lost_o       <= lost;

end architecture rtl;
