-- phase: the fine phase from the octant and the phase table, without the harmonic
-- compensation (VHDL edition of rtl/phase.v; finequad_core with OPT_HARMONIC = 0,
-- rtl/harmonic.v assembles the same phase with the correction).
--
-- Timing, a = the edge on which valid_i is high (t + 4 in the core):
--   a      oct2_i, neg_i taken
--   a + 1  the constant part k0 = 2048 oct2 + neg registered; ph_i (PH[j], ~PH[j] for
--          neg: rtl/lut.v) is the phase table's output after this edge
--   a + 2  phase_o = phase_c_o = (2048 oct2 +- ph) mod 8192, valid_o
-- The subtraction needs no inversion: - ph = ~ph + 1, and ph_i is ~PH already, so
-- phase = k0 + (neg & ph_i) mod 8192. Every stage's registers take a sample only with
-- its valid bit (a clock enable); no reset. Power-up values 0.
-- Formats: oct2_i u2 (base phase 2048 oct2); ph_i u12; phase_o u13 (8192 per period).

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;

entity phase is
  port (
    clk       : in    std_logic;
    valid_i   : in    std_logic;
    oct2_i    : in    unsigned(1 downto 0);  -- with valid_i: base phase 2048 oct2
    neg_i     : in    std_logic;             -- with valid_i: phase = base - ph
    ph_i      : in    unsigned(11 downto 0); -- u12 PH[j], ~PH[j] for neg, after a + 1
    valid_o   : out   std_logic;
    phase_o   : out   phase_t;               -- u13 fine phase
    phase_c_o : out   phase_t                -- u13 the same (no harmonic correction)
  );
end entity phase;

architecture rtl of phase is

  -- a: the sample's octant
  signal v1   : std_logic            := '0';
  signal oct1 : unsigned(1 downto 0) := (others => '0');
  signal neg1 : std_logic            := '0';

  -- a + 1: k0 = 2048 oct2 + neg (u13)
  signal v2   : std_logic := '0';
  signal k0   : phase_t   := (others => '0');
  signal neg2 : std_logic := '0';

  -- a + 2
  signal valid_q : std_logic := '0';
  signal phase_q : phase_t   := (others => '0');

begin

  stages : process (clk) is
  begin

    if rising_edge(clk) then
      v1      <= valid_i;
      v2      <= v1;
      valid_q <= v2;

      if valid_i = '1' then
        oct1 <= oct2_i;
        neg1 <= neg_i;
      end if;

      if v1 = '1' then
        k0   <= (oct1 & to_unsigned(0, 11)) + neg1;
        neg2 <= neg1;
      end if;

      if v2 = '1' then
        phase_q <= k0 + (neg2 & ph_i);
      end if;
    end if;

  end process stages;

  valid_o   <= valid_q;
  phase_o   <= phase_q;
  phase_c_o <= phase_q;

end architecture rtl;
