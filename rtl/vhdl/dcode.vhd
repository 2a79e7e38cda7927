-- dcode: distance-coded reference marks (VHDL edition of rtl/dcode.v, which describes the
-- layout, the decision and the events in full; model sim/model/dcode.py).
--
-- The absolute position on the scale from the distance between two reference marks:
-- refmark's crossings (cross_i, cdir_i) count the signal periods dp since the last latch;
-- the next latch (lat_i) decodes |dp| = A / 2 +- d k (A = a_i, B = b_i, d = B - A) into
-- the second mark's position xa in signal periods (restoring division of |dp| - A / 2 by
-- d, accumulating k B or k A), checks it against the previous decode (fa, the first
-- mark's position, = ap) and ends with ABS_COUNT = 4 n xa (a shift-add product over n's
-- 9 bits). No multiplier, no divider.
--
-- Timing: a latch on edge E (refmark's t + 10) takes dp, HOME and x_i and starts a
-- decode, st = 1 .. LAST on E + 1 .. E + LAST; the decision on edge E + LAST
-- (abs_valid_o, abs_o, err_o; home_o, off_o and ref_o before it). A latch during a decode
-- abandons it (err_o); inv_i abandons it and clears the chain and abs_valid_o.
-- Steps: 1 m = |dp|; 2 e = m - A / 2; 3 |e|, the divisor, the factor; 4 .. 15 the
-- division; 16 xa, the remainder's test; 17 fa; 18 .. 26 the product; 27 the decision.
-- Formats: a_i, b_i u12 signal periods; n_i u9; home_i, x_i, abs_o, off_o, ref_o
-- s(COUNT_W).0 counts (wrap); the distance s13 periods; xa, fa, ap u24 periods. Power-up
-- values are those after rst.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;

entity dcode is
  generic (
    -- counter width (wraps), 17..32
    COUNT_W : integer range 17 to 32 := 32
  );
  port (
    clk    : in    std_logic;
    rst    : in    std_logic;                    -- sync, active high
    a_i    : in    unsigned(11 downto 0);        -- u12 DCODE.dc_spacing (0: off)
    b_i    : in    unsigned(11 downto 0);        -- u12 DCODE.dc_coded
    conf_i : in    std_logic;                    -- DCODE.dc_confirm
    n_i    : in    n_t;                          -- u9 n
    home_i : in    signed(COUNT_W - 1 downto 0); -- HOME
    -- on a sample's t + 10 edge (refmark, registered on t + 9)
    cross_i     : in    std_logic;                    -- a reference point crossed
    cdir_i      : in    std_logic;                    -- '1': back
    lat_i       : in    std_logic;                    -- a reference latched
    x_i         : in    signed(COUNT_W - 1 downto 0); -- its count (before the offset)
    inv_i       : in    std_logic;                    -- the count lost its scale
    abs_valid_o : out   std_logic;
    abs_o       : out   signed(COUNT_W - 1 downto 0); -- ABS_COUNT
    home_o      : out   std_logic;                    -- the decode's last edge: abs_valid
    off_o       : out   signed(COUNT_W - 1 downto 0); -- with home_o: HOME + ABS - x
    ref_o       : out   signed(COUNT_W - 1 downto 0); -- with home_o: HOME + ABS
    err_o       : out   std_logic                     -- a pulse: REF_STICKY.dc_err
  );
end entity dcode;

architecture rtl of dcode is

  subtype count_t is signed(COUNT_W - 1 downto 0);

  -- positions on the scale, u24 signal periods
  subtype period_t is unsigned(23 downto 0);

  -- the distance between two marks, s13 signal periods (|dp| < 4096)
  subtype dist_t is signed(12 downto 0);

  -- the decode's steps: st = 0 idle, 1 .. LAST
  constant LAST : natural := 27;

  subtype step_t is natural range 0 to LAST;

  -- The restoring division of |e| by d, accumulating k B or k A (steps 4 .. 15): the
  -- remainder, the divisor and the factor shifted right by one per step, the sum.
  type division_t is record
    rmd : unsigned(12 downto 0);
    dsh : period_t;
    msh : period_t;
    acc : period_t;
  end record division_t;

  -- The shift-add product 4 n xa (steps 18 .. 26): xa shifted left, n shifted right.
  type product_t is record
    xsh : unsigned(COUNT_W - 1 downto 0);
    nsh : n_t;
    sum : unsigned(COUNT_W - 1 downto 0);
  end record product_t;

  -- The operands a latch takes (outside a decode).
  type operands_t is record
    dp  : dist_t;  -- the distance
    fwd : boolean; -- dp >= 0: crossed forwards
    far : boolean; -- |dp| reached 4095
    hx  : count_t; -- HOME - x
    hs  : count_t; -- HOME
  end record operands_t;

  -- {0, v, 11 zeros}: the u12 divisor or factor lined up with the first quotient bit (2**11)
  function top (v : unsigned) return period_t is
  begin

    return resize(v & (10 downto 0 => '0'), period_t'length);

  end function top;

  -- ---- the distance since the last latch ------------------------------------------------
  signal dr    : dist_t  := (others => '0');
  signal far   : boolean := false;
  signal dr_n  : dist_t;
  signal far_n : boolean;

  -- ---- the decode ------------------------------------------------------------------------
  signal st   : step_t     := 0;
  signal busy : boolean;
  signal have : boolean    := false; -- a mark latched since rst or inv_i
  signal op   : operands_t := (dp => (others => '0'), fwd => false, far => false,
                               hx => (others => '0'), hs => (others => '0'));

  signal m    : unsigned(12 downto 0) := (others => '0'); -- |dp|
  signal e    : signed(13 downto 0)   := (others => '0'); -- m - A / 2
  signal ok   : boolean               := false;           -- a valid distance so far
  signal selb : boolean               := false;           -- the quotient counts B
  signal div  : division_t            := (rmd => (others => '0'), dsh => (others => '0'),
                                          msh => (others => '0'), acc => (others => '0'));
  signal xa   : period_t              := (others => '0'); -- the second mark's position
  signal fa   : period_t              := (others => '0'); -- the first mark's
  signal mul  : product_t             := (xsh => (others => '0'), nsh => (others => '0'),
                                          sum => (others => '0'));

  -- ---- the decision ----------------------------------------------------------------------
  signal pv        : boolean   := false; -- ap holds the last decode's position
  signal ap        : period_t  := (others => '0');
  signal sp        : boolean   := false; -- its direction (forwards)
  signal abs_valid : std_logic := '0';
  signal abs_q     : count_t   := (others => '0');
  signal err       : std_logic := '0';

  signal d     : unsigned(11 downto 0); -- B - A
  signal ae    : unsigned(12 downto 0); -- |e|
  signal ep    : boolean;               -- e > 0
  signal ge    : boolean;               -- the quotient bit
  signal fin   : boolean;               -- the decode ends on this edge
  signal good  : boolean;               -- valid, and consistent with the last decode
  signal nv    : boolean;               -- the decode sets abs_valid
  signal abs_n : count_t;               -- 4 n xa

begin

  -- ---- the distance: +1 per crossing forwards, -1 back; |dr| reaching 4095 is too far ------
  dr_n  <= dr - 1 when cross_i = '1' and cdir_i = '1' else
           dr + 1 when cross_i = '1' else
           dr;
  far_n <= far or dr_n = 4095 or dr_n = -4095;

  distance : process (clk) is
  begin

    if rising_edge(clk) then
      if lat_i = '1' then
        dr  <= (others => '0');
        far <= false;
      else
        dr  <= dr_n;
        far <= far_n;
      end if;

      if rst = '1' then
        dr  <= (others => '0');
        far <= false;
      end if;
    end if;

  end process distance;

  -- ---- the sequencer: a latch after a mark (the chain's start) with dp /= 0 starts a decode;
  -- a latch during one abandons it, inv_i abandons it and the chain ---------------------------
  busy <= st /= 0;

  sequencer : process (clk) is
  begin

    if rising_edge(clk) then
      if st = LAST then
        st <= 0;
      elsif busy then
        st <= st + 1;
      end if;

      if inv_i = '1' then
        st   <= 0;
        have <= false;
      elsif lat_i = '1' then
        have <= true;

        if busy then
          st <= 0;
        elsif have and dr_n /= 0 then
          st <= 1;
        end if;
      end if;

      -- the latch's operands, taken on every latch not during a decode
      if lat_i = '1' and not busy then
        op <= (dp => dr_n, fwd => dr_n >= 0, far => far_n, hx => home_i - x_i, hs => home_i);
      end if;

      if rst = '1' then
        st   <= 0;
        have <= false;
      end if;
    end if;

  end process sequencer;

  -- ---- the steps ------------------------------------------------------------------------------
  d  <= b_i - a_i;
  ae <= unsigned(-e(12 downto 0)) when e(13) = '1' else
        unsigned(e(12 downto 0));
  ep <= e > 0;
  ge <= div.dsh(23 downto 13) = 0 and div.rmd >= div.dsh(12 downto 0);

  steps : process (clk) is
  begin

    -- (an if chain and no abs: GHDL 2.0's Verilog output writes a case's multiplexer
    -- without its default, and cannot write abs)
    if rising_edge(clk) then
      if st = 1 then
        if op.dp < 0 then
          m <= unsigned(-op.dp);
        else
          m <= unsigned(op.dp);
        end if;
      elsif st = 2 then
        e  <= signed(resize(m, 14)) - signed(resize(a_i(11 downto 1), 14));
        ok <= not op.far and a_i(0) = '0' and a_i /= 0 and b_i > a_i and m < a_i;
      elsif st = 3 then
        -- e > 0 forwards or e < 0 back: the quotient counts B (k B - A / 2), else A
        ok   <= ok and e /= 0;
        selb <= op.fwd = ep;
        div  <= (rmd => ae, dsh => top(d), msh => top(a_i), acc => (others => '0'));

        if op.fwd = ep then
          div.msh <= top(b_i);
        end if;
      elsif st >= 4 and st <= 15 then
        if ge then
          div.rmd <= div.rmd - div.dsh(12 downto 0);
          div.acc <= div.acc + div.msh;
        end if;

        div.dsh <= shift_right(div.dsh, 1);
        div.msh <= shift_right(div.msh, 1);
      elsif st = 16 then
        -- d divides e exactly; xa: k B - A / 2, k A or (back) k A - A
        ok <= ok and div.rmd = 0;

        if selb then
          xa <= div.acc - a_i(11 downto 1);
        elsif op.fwd then
          xa <= div.acc;
        else
          xa <= div.acc - a_i;
        end if;
      elsif st = 17 then
        -- the first mark lies m before the second (after it, crossing back)
        if op.fwd then
          fa <= xa - m;
        else
          fa <= xa + m;
        end if;

        mul <= (xsh => resize(xa, COUNT_W), nsh => n_i, sum => (others => '0'));
      elsif st >= 18 and st <= 26 then
        if mul.nsh(0) = '1' then
          mul.sum <= mul.sum + mul.xsh;
        end if;

        mul.xsh <= shift_left(mul.xsh, 1);
        mul.nsh <= shift_right(mul.nsh, 1);
      end if;
    end if;

  end process steps;

  -- ---- the decision ---------------------------------------------------------------------------
  fin   <= st = LAST and lat_i = '0' and inv_i = '0';
  good  <= ok and not (pv and fa /= ap);
  nv    <= good and (conf_i = '0' or abs_valid = '1' or (pv and op.fwd = sp));
  abs_n <= signed(shift_left(mul.sum, 2));

  decision : process (clk) is
  begin

    if rising_edge(clk) then
      err <= '0';

      if fin then
        if not ok then
          err       <= '1';
          abs_valid <= '0';
          pv        <= false;
        else
          if not good then
            err       <= '1';
            abs_valid <= '0';
          elsif nv then
            abs_valid <= '1';
            abs_q     <= abs_n;
          end if;

          pv <= true;
          ap <= xa;
          sp <= op.fwd;
        end if;
      end if;

      if inv_i = '1' then
        pv        <= false;
        abs_valid <= '0';
      elsif lat_i = '1' and busy then
        err       <= '1';
        pv        <= false;
        abs_valid <= '0';
      end if;

      if rst = '1' then
        err       <= '0';
        pv        <= false;
        abs_valid <= '0';
        abs_q     <= (others => '0');
      end if;
    end if;

  end process decision;

  abs_valid_o <= abs_valid;
  abs_o       <= abs_q;
  home_o      <= to_sl(fin and nv);
  off_o       <= op.hx + abs_n;
  ref_o       <= op.hs + abs_n;
  err_o       <= err;

end architecture rtl;
