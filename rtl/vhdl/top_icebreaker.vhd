-- top_icebreaker: board shell for the iCEBreaker (iCE40 UP5K-SG48): 12 MHz -> 20.25 MHz
-- PLL, reset synchroniser, pins; everything else is finequad_system. VHDL edition of
-- rtl/boards/top_icebreaker.v, which describes the pins, the LEDs and why this board
-- runs the core standalone (no host link: TX idles high).
-- The build's generics and PLL dividers: rtl/builds.toml [icebreaker], through the
-- generated builds_pkg (ICEBREAKER_SYSTEM, ICEBREAKER_PLL). SB_PLL40_PAD is a component
-- (a black box for ghdl --synth; the synthesis tool maps it).

library ieee;
  use ieee.std_logic_1164.all;

library work;
  use work.builds_pkg.all;

entity top_icebreaker is
  generic (
    -- folder of the core's tables
    TABLE_DIR : string := "rtl/tables/"
  );
  -- the pins by the names of constraints/icebreaker.pcf
  -- vsg_off port_010
  port (
    CLK    : in    std_logic; -- 12 MHz
    BTN_N  : in    std_logic; -- user button: reset
    LEDR_N : out   std_logic;
    LEDG_N : out   std_logic;
    -- Pmod AD1 on PMOD1A
    P1A1 : out   std_logic; -- CS_N
    P1A2 : in    std_logic; -- SDATA1 (u1)
    P1A3 : in    std_logic; -- SDATA2 (u2)
    P1A4 : out   std_logic; -- SCLK
    -- A/B/Z outputs and the reference input on PMOD1B
    P1B1 : out   std_logic; -- A
    P1B2 : out   std_logic; -- B
    P1B3 : out   std_logic; -- Z
    P1B4 : in    std_logic; -- reference input
    -- FTDI UART (idle: no host link on this board)
    RX : in    std_logic; -- from the host
    TX : out   std_logic  -- to the host (held high)
  );
-- vsg_on
end entity top_icebreaker;

architecture rtl of top_icebreaker is

  -- iCE40 PLL, pad input (the generics this top sets; the vendor's VHDL declaration
  -- gives the dividers as bit_vector)
  -- the primitive's names in the vendor's (and yosys') case
  -- vsg_off port_010 component_008 component_012 instantiation_008 instantiation_009
  -- vsg_off generic_map_002 port_map_002
  component SB_PLL40_PAD is
    generic (
      FEEDBACK_PATH : string                 := "SIMPLE";
      DIVR          : bit_vector(3 downto 0) := "0000";
      DIVF          : bit_vector(6 downto 0) := "0000000";
      DIVQ          : bit_vector(2 downto 0) := "000";
      FILTER_RANGE  : bit_vector(2 downto 0) := "000"
    );
    port (
      PACKAGEPIN   : in    std_logic;
      PLLOUTGLOBAL : out   std_logic;
      LOCK         : out   std_logic;
      RESETB       : in    std_logic;
      BYPASS       : in    std_logic
    );
  end component SB_PLL40_PAD;

  -- vsg_on

  signal sys_clk : std_logic;
  signal locked  : std_logic;
  -- reset synchroniser: held while the PLL is unlocked or the button is pressed
  signal rst_sync : std_logic_vector(3 downto 0) := (others => '1');
  signal rst      : std_logic;
  signal status   : std_logic_vector(4 downto 0);

begin

  -- 12 MHz * 54 = 648 MHz VCO, / 32 = 20.25 MHz
  -- the primitive's names in the vendor's (and yosys') case
  -- vsg_off port_010 component_008 component_012 instantiation_008 instantiation_009
  -- vsg_off generic_map_002 port_map_002
  u_pll : component SB_PLL40_PAD
    generic map (
      FEEDBACK_PATH => "SIMPLE",
      DIVR          => ICEBREAKER_PLL.DIVR,
      DIVF          => ICEBREAKER_PLL.DIVF,
      DIVQ          => ICEBREAKER_PLL.DIVQ,
      FILTER_RANGE  => ICEBREAKER_PLL.FILTER_RANGE
    )
    port map (
      PACKAGEPIN   => CLK,
      PLLOUTGLOBAL => sys_clk,
      LOCK         => locked,
      RESETB       => '1',
      BYPASS       => '0'
    );

  -- vsg_on

  reset_sync : process (sys_clk) is
  begin

    if rising_edge(sys_clk) then
      rst_sync <= rst_sync(2 downto 0) & (not locked or not BTN_N);
    end if;

  end process reset_sync;

  rst <= rst_sync(3);

  u_sys : entity work.finequad_system
    generic map (
      table_dir      => TABLE_DIR,
      opt_nth_dsp    => ICEBREAKER_SYSTEM.OPT_NTH_DSP,
      opt_harmonic   => ICEBREAKER_SYSTEM.OPT_HARMONIC,
      opt_distram    => ICEBREAKER_SYSTEM.OPT_DISTRAM,
      opt_phase_4k   => ICEBREAKER_SYSTEM.OPT_PHASE_4K,
      opt_ecp5_mult  => ICEBREAKER_SYSTEM.OPT_ECP5_MULT,
      opt_pulse_addr => ICEBREAKER_SYSTEM.OPT_PULSE_ADDR,
      opt_monitor    => ICEBREAKER_SYSTEM.OPT_MONITOR,
      opt_jump       => ICEBREAKER_SYSTEM.OPT_JUMP,
      opt_dcode      => ICEBREAKER_SYSTEM.OPT_DCODE,
      adc_sclk_half  => ICEBREAKER_SYSTEM.ADC_SCLK_HALF,
      adc_cs_setup   => ICEBREAKER_SYSTEM.ADC_CS_SETUP,
      adc_period     => ICEBREAKER_SYSTEM.ADC_PERIOD,
      baud_div       => ICEBREAKER_SYSTEM.BAUD_DIV,
      uart_timeout   => ICEBREAKER_SYSTEM.UART_TIMEOUT,
      opt_hostlink   => ICEBREAKER_SYSTEM.OPT_HOSTLINK
    )
    port map (
      clk          => sys_clk,
      rst          => rst,
      adc_cs_n_o   => P1A1,
      adc_sclk_o   => P1A4,
      adc_sdata1_i => P1A2,
      adc_sdata2_i => P1A3,
      uart_rx_i    => RX,
      uart_tx_o    => TX,
      ref_i        => P1B4,
      a_o          => P1B1,
      b_o          => P1B2,
      z_o          => P1B3,
      status_o     => status
    );

  -- green: calibrated; red: a fault seen (status(4..2) unconnected)
  LEDG_N <= not status(0);
  LEDR_N <= not status(1);

end architecture rtl;
