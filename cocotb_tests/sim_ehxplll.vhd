-- EHXPLLL (Lattice ECP5 PLL), behavioural stand-in for simulations of
-- rtl/vhdl/top_ulx3s.vhd on GHDL (cocotb_tests/test_system.py), the VHDL twin of
-- sim_ehxplll.v: CLKOP is CLKI (the test drives the board clock pin at the PLL's output
-- frequency), LOCK rises after 16 CLKI edges. The generics and ports are those of the
-- component top_ulx3s.vhd declares; the generics are accepted and ignored.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

-- the primitive's names in the vendor's case, as top_ulx3s.vhd declares them
-- vsg_off
entity EHXPLLL is
  generic (
    CLKI_DIV        : integer := 1;
    CLKFB_DIV       : integer := 1;
    CLKOP_DIV       : integer := 8;
    CLKOP_CPHASE    : integer := 0;
    CLKOP_FPHASE    : integer := 0;
    CLKOP_ENABLE    : string  := "ENABLED";
    FEEDBK_PATH     : string  := "CLKOP";
    OUTDIVIDER_MUXA : string  := "DIVA";
    OUTDIVIDER_MUXB : string  := "DIVB";
    OUTDIVIDER_MUXC : string  := "DIVC";
    OUTDIVIDER_MUXD : string  := "DIVD";
    PLLRST_ENA      : string  := "DISABLED";
    INTFB_WAKE      : string  := "DISABLED";
    STDBY_ENABLE    : string  := "DISABLED";
    DPHASE_SOURCE   : string  := "DISABLED"
  );
  port (
    CLKI         : in    std_logic;
    CLKFB        : in    std_logic;
    PHASESEL1    : in    std_logic;
    PHASESEL0    : in    std_logic;
    PHASEDIR     : in    std_logic;
    PHASESTEP    : in    std_logic;
    PHASELOADREG : in    std_logic;
    STDBY        : in    std_logic;
    PLLWAKESYNC  : in    std_logic;
    RST          : in    std_logic;
    ENCLKOP      : in    std_logic;
    CLKOP        : out   std_logic;
    LOCK         : out   std_logic
  );
end entity EHXPLLL;

architecture sim of EHXPLLL is

  signal cnt  : unsigned(4 downto 0) := (others => '0');
  signal lock_q : std_logic          := '0';

begin

  CLKOP <= CLKI;
  LOCK  <= lock_q;

  lock_count : process (CLKI) is
  begin

    if rising_edge(CLKI) then
      if cnt(4) = '0' then
        cnt <= cnt + 1;
      end if;
      lock_q <= cnt(4);
    end if;

  end process lock_count;

end architecture sim;
-- vsg_on
