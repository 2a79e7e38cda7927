-- counter: the position count of the n-th order (VHDL edition of rtl/counter.v, which
-- describes it in full, as does its model sim/model/counter.py). Counts up when the
-- phase increases (u1 leads u2).
--
-- Phase mode (mode_i = '0'): count = floor(4 n Phi / 8192) of the unwrapped fine phase
-- Phi = 8192 W + f, formed as B + floor(n f / 2048) with B = 4 n W stepped by -+4 n
-- when the phase wraps; a step of 3/4 pi or more flags ovs_o; a held sample (hold_i)
-- keeps the count, and with coast_i the last phase taken follows line_i.
-- Edge mode (mode_i = '1'): the x4 decoder E of the Eq. 12 pulses; a step of both A and
-- B is illegal (ill_o, ill_count_o) and not counted.
--
-- Timing (e = the edge that registered phase_i upstream, t + 6 in the core):
--   e + 1  B, the last phase taken, the step and its overspeed test; prod_i arrives
--   e + 2  count_o, valid_o, ovs_o, held_o
--   pulses: pv_i, a_i, b_i on edge p (t + 9); E, ill_o and ill_count_o on p + 1
-- Formats: phase_i, line_i u13 (8192 per signal period); prod_i u22 = n_i * phase_i;
-- n_i u9 (1..511); count_o s(COUNT_W) counts, 4 n per signal period, wraps;
-- ill_count_o u16, wraps. Power-up values are those after rst.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;

entity counter is
  generic (
    -- counter width (wraps), 16..32
    COUNT_W : integer range 16 to 32 := 32
  );
  port (
    clk         : in    std_logic;
    rst         : in    std_logic;                    -- sync, active high
    valid_i     : in    std_logic;
    hold_i      : in    std_logic;                    -- with valid_i: do not count
    coast_i     : in    std_logic;                    -- with hold_i: follow line_i
    line_i      : in    phase_t;                      -- u13 the monitor's line
    phase_i     : in    phase_t;                      -- u13 fine phase (edge e)
    prod_i      : in    prod_t;                       -- u22 n * phase_i (edge e + 1)
    n_i         : in    n_t;                          -- u9 n, 1..511
    mode_i      : in    std_logic;                    -- '0' phase, '1' edge
    pv_i        : in    std_logic;                    -- Eq. 12 pulses of a sample
    a_i         : in    std_logic;
    b_i         : in    std_logic;
    valid_o     : out   std_logic;
    count_o     : out   signed(COUNT_W - 1 downto 0); -- s(COUNT_W), wraps
    ovs_o       : out   std_logic;                    -- overspeed (with valid_o)
    ill_o       : out   std_logic;                    -- an illegal A/B step
    ill_count_o : out   unsigned(15 downto 0);        -- u16 illegal steps, wraps
    held_o      : out   std_logic                     -- a held sample, phase mode
  );
end entity counter;

architecture rtl of counter is

  subtype count_t is signed(COUNT_W - 1 downto 0);

  -- A sample as it stands on e + 1, its count formed on e + 2.
  type stage_t is record
    valid : std_logic;
    ovc   : std_logic; -- may flag overspeed
    hold  : std_logic;
    dph   : phase_t;   -- wrap13 of the step, as u13
  end record stage_t;

  -- |wrap13(d)| >= 3072 for the step d as u13: 3072 <= d <= 5120
  function overspeed (d : phase_t) return boolean is
  begin

    return geu(d, 3072) and geu(5120, d);

  end function overspeed;

  -- ---- e + 1: the last phase taken, B --------------------------------------------------
  signal ph_prev : phase_t   := (others => '0');
  signal primed  : std_logic := '0';             -- a trusted sample since rst
  signal b_acc   : count_t   := (others => '0'); -- B = 4 n W, wraps
  signal s1      : stage_t   := (valid => '0', ovc => '0', hold => '0', dph => (others => '0'));

  signal raw    : signed(PHASE_W downto 0); -- s14 step from the last phase
  signal take   : boolean;
  signal n4     : count_t;
  signal b_dn   : count_t;
  signal b_up   : count_t;
  signal b_next : count_t;

  -- ---- edge decoder ----------------------------------------------------------------------
  signal e_acc   : count_t    := (others => '0'); -- E
  signal qd_prev : quadrant_t := (others => '0');
  signal eprimed : std_logic  := '0';             -- a pulse since rst
  signal dq      : quadrant_t;
  signal e_next  : count_t;

  -- ---- e + 2: the outputs -------------------------------------------------------------
  signal valid_q     : std_logic             := '0';
  signal count_q     : count_t               := (others => '0');
  signal ovs_q       : std_logic             := '0';
  signal ill_q       : std_logic             := '0';
  signal ill_count_q : unsigned(15 downto 0) := (others => '0');
  signal held_q      : std_logic             := '0';

begin

  -- The step from the last phase taken: the sample's, or the line's on a coast (both
  -- differences side by side; hold_i only selects).
  raw <= signed('0' & line_i) - signed('0' & ph_prev) when hold_i = '1' else
         signed('0' & phase_i) - signed('0' & ph_prev);

  take <= valid_i = '1' and (hold_i = '0' or coast_i = '1');

  -- B - 4n and B + 4n beside the phase difference (two adders from B and n, which do not
  -- wait for the phase); the wrap test only chooses: raw >= 4096 wrapped backwards,
  -- raw < -4096 forwards
  n4   <= signed(resize(n_i & "00", COUNT_W));
  b_dn <= b_acc - n4;
  b_up <= b_acc + n4;

  b_next <= b_dn when take and raw(PHASE_W downto PHASE_W - 1) = "01" else
            b_up when take and raw(PHASE_W downto PHASE_W - 1) = "10" else
            b_acc;

  step_reg : process (clk) is
  begin

    if rising_edge(clk) then
      s1.valid <= valid_i;
      s1.ovc   <= primed and not hold_i;
      s1.dph   <= unsigned(raw(PHASE_W - 1 downto 0));
      s1.hold  <= hold_i;

      if valid_i = '1' and hold_i = '0' then
        primed <= '1';
      end if;

      if take then
        if hold_i = '1' then
          ph_prev <= line_i;
        else
          ph_prev <= phase_i;
        end if;
      end if;

      b_acc <= b_next;

      if rst = '1' then
        s1.valid <= '0';
        ph_prev  <= (others => '0');
        primed   <= '0';
        b_acc    <= (others => '0');
      end if;
    end if;

  end process step_reg;

  -- Quadrant step of the pulses: 1 up, 3 down, 2 illegal; E moves by +1 or -1 in one
  -- adder (dq(1) & '1' as s2)
  dq     <= quadrant(a_i, b_i) - qd_prev;
  e_next <= e_acc + signed'(dq(1) & '1') when pv_i = '1' and dq(0) = '1' else
            e_acc;

  edge_decoder : process (clk) is
  begin

    if rising_edge(clk) then
      ill_q <= '0';

      if pv_i = '1' then
        qd_prev <= quadrant(a_i, b_i);
        eprimed <= '1';

        if dq = 2 and eprimed = '1' then
          ill_q       <= '1';
          ill_count_q <= ill_count_q + 1;
        end if;
      end if;

      e_acc <= e_next;

      if rst = '1' then
        qd_prev     <= (others => '0');
        eprimed     <= '0';
        ill_q       <= '0';
        ill_count_q <= (others => '0');
        e_acc       <= (others => '0');
      end if;
    end if;

  end process edge_decoder;

  count_reg : process (clk) is
  begin

    if rising_edge(clk) then
      valid_q <= s1.valid;
      ovs_q   <= s1.valid and s1.ovc and to_sl(overspeed(s1.dph));
      held_q  <= s1.valid and s1.hold and not mode_i;

      if s1.valid = '1' and (mode_i = '1' or s1.hold = '0') then
        if mode_i = '1' then
          count_q <= e_acc;
        else
          count_q <= b_acc + signed(resize(prod_i(PROD_W - 1 downto 11), COUNT_W));
        end if;
      end if;

      if rst = '1' then
        valid_q <= '0';
        ovs_q   <= '0';
        held_q  <= '0';
        count_q <= (others => '0');
      end if;
    end if;

  end process count_reg;

  -- pragma translate_off
  -- Simulation only. A testbench's write to B or E (cocotb_tests/test_counter.py presets
  -- them after rst) is a deposit in Icarus and Verilator: the register goes on from the
  -- value written. GHDL 2.0's VPI forces the signal instead and never releases it (cocotb
  -- issue 4150), so the force is released on the next edge, where B and E take their
  -- next value from the one written (they are assigned on every edge for this).
  release_deposits : process (clk) is
  begin

    if rising_edge(clk) then
      b_acc <= release;
      e_acc <= release;
    end if;

  end process release_deposits;

  -- pragma translate_on

  valid_o     <= valid_q;
  count_o     <= count_q;
  ovs_o       <= ovs_q;
  ill_o       <= ill_q;
  ill_count_o <= ill_count_q;
  held_o      <= held_q;

end architecture rtl;
