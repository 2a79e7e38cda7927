-- top_ulx3s: board shell for the ULX3S (ECP5 LFE5U-25F-6BG381C, 25 MHz oscillator, FT231X
-- USB UART): 25 MHz -> 35.714 MHz PLL, reset synchroniser, pins; everything else is
-- finequad_system. VHDL edition of rtl/boards/top_ulx3s.v, which describes the pins
-- (constraints/ulx3s.lpf) and the LEDs: led(4..0) the system's status, led(7) PLL
-- locked.
-- The build's generics and PLL settings: rtl/builds.toml [ulx3s], through the generated
-- builds_pkg (ULX3S_SYSTEM, ULX3S_PLL, ULX3S_CLKI_MHZ, ULX3S_CLKOP_MHZ). EHXPLLL is a
-- component (a black box for ghdl --synth; the synthesis tool maps it).

library ieee;
  use ieee.std_logic_1164.all;

library work;
  use work.builds_pkg.all;

entity top_ulx3s is
  generic (
    -- folder of the core's tables
    TABLE_DIR : string := "rtl/tables/"
  );
  port (
    clk_25mhz : in    std_logic;
    btn       : in    std_logic_vector(1 downto 1);
    led       : out   std_logic_vector(7 downto 0);
    ftdi_txd  : in    std_logic; -- from the host (FT231X TXD)
    ftdi_rxd  : out   std_logic; -- to the host (FT231X RXD)
    -- Pmod AD1 on the GP row of J1
    adc_cs_n   : out   std_logic; -- gp[3]
    adc_sdata1 : in    std_logic; -- gp[2] (D0, u1)
    adc_sdata2 : in    std_logic; -- gp[1] (D1, u2)
    adc_sclk   : out   std_logic; -- gp[0]
    -- A/B/Z and the reference input on the GN row of J1
    quad_a : out   std_logic; -- gn[0]
    quad_b : out   std_logic; -- gn[1]
    quad_z : out   std_logic; -- gn[2]
    ref_in : in    std_logic  -- gn[3]
  );
end entity top_ulx3s;

architecture rtl of top_ulx3s is

  -- ECP5 PLL (the generics and ports this top uses, as the vendor's VHDL declares them)
  -- the primitive's names in the vendor's (and yosys') case
  -- vsg_off port_010 component_008 component_012 instantiation_008 instantiation_009
  -- vsg_off generic_map_002 port_map_002
  component EHXPLLL is
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
  end component EHXPLLL;

  -- vsg_on

  -- the PLL's settings for the place and route tool (Diamond's and nextpnr's names,
  -- in their case; ghdl --synth 2.0 does not pass them on)
  -- vsg_off
  attribute FREQUENCY_PIN_CLKI     : string;
  attribute FREQUENCY_PIN_CLKOP    : string;
  attribute ICP_CURRENT            : string;
  attribute LPF_RESISTOR           : string;
  attribute MFG_ENABLE_FILTEROPAMP : string;
  attribute MFG_GMCREF_SEL         : string;
  attribute FREQUENCY_PIN_CLKI of u_pll     : label is ULX3S_CLKI_MHZ;
  attribute FREQUENCY_PIN_CLKOP of u_pll    : label is ULX3S_CLKOP_MHZ;
  attribute ICP_CURRENT of u_pll            : label is "12";
  attribute LPF_RESISTOR of u_pll           : label is "8";
  attribute MFG_ENABLE_FILTEROPAMP of u_pll : label is "1";
  attribute MFG_GMCREF_SEL of u_pll         : label is "2";
  -- vsg_on

  signal sys_clk : std_logic;
  signal locked  : std_logic;
  -- reset synchroniser: held while the PLL is unlocked or FIRE1 is pressed
  signal rst_sync : std_logic_vector(3 downto 0) := (others => '1');
  signal rst      : std_logic;
  signal status   : std_logic_vector(4 downto 0);

begin

  -- 25 MHz / 7 * 10 = 35.714 MHz (feedback from CLKOP), VCO 607 MHz
  -- the primitive's names in the vendor's (and yosys') case
  -- vsg_off port_010 component_008 component_012 instantiation_008 instantiation_009
  -- vsg_off generic_map_002 port_map_002
  u_pll : component EHXPLLL
    generic map (
      CLKI_DIV        => ULX3S_PLL.CLKI_DIV,
      CLKFB_DIV       => ULX3S_PLL.CLKFB_DIV,
      CLKOP_DIV       => ULX3S_PLL.CLKOP_DIV,
      CLKOP_CPHASE    => ULX3S_PLL.CLKOP_CPHASE,
      CLKOP_FPHASE    => 0,
      CLKOP_ENABLE    => "ENABLED",
      FEEDBK_PATH     => "CLKOP",
      OUTDIVIDER_MUXA => "DIVA",
      OUTDIVIDER_MUXB => "DIVB",
      OUTDIVIDER_MUXC => "DIVC",
      OUTDIVIDER_MUXD => "DIVD",
      PLLRST_ENA      => "DISABLED",
      INTFB_WAKE      => "DISABLED",
      STDBY_ENABLE    => "DISABLED",
      DPHASE_SOURCE   => "DISABLED"
    )
    port map (
      CLKI         => clk_25mhz,
      CLKFB        => sys_clk,
      PHASESEL1    => '0',
      PHASESEL0    => '0',
      PHASEDIR     => '1',
      PHASESTEP    => '1',
      PHASELOADREG => '1',
      STDBY        => '0',
      PLLWAKESYNC  => '0',
      RST          => '0',
      ENCLKOP      => '0',
      CLKOP        => sys_clk,
      LOCK         => locked
    );

  -- vsg_on

  reset_sync : process (sys_clk) is
  begin

    if rising_edge(sys_clk) then
      rst_sync <= rst_sync(2 downto 0) & (not locked or btn(1));
    end if;

  end process reset_sync;

  rst <= rst_sync(3);

  u_sys : entity work.finequad_system
    generic map (
      table_dir      => TABLE_DIR,
      opt_nth_dsp    => ULX3S_SYSTEM.OPT_NTH_DSP,
      opt_harmonic   => ULX3S_SYSTEM.OPT_HARMONIC,
      opt_distram    => ULX3S_SYSTEM.OPT_DISTRAM,
      opt_phase_4k   => ULX3S_SYSTEM.OPT_PHASE_4K,
      opt_ecp5_mult  => ULX3S_SYSTEM.OPT_ECP5_MULT,
      opt_pulse_addr => ULX3S_SYSTEM.OPT_PULSE_ADDR,
      opt_monitor    => ULX3S_SYSTEM.OPT_MONITOR,
      opt_jump       => ULX3S_SYSTEM.OPT_JUMP,
      opt_dcode      => ULX3S_SYSTEM.OPT_DCODE,
      adc_sclk_half  => ULX3S_SYSTEM.ADC_SCLK_HALF,
      adc_cs_setup   => ULX3S_SYSTEM.ADC_CS_SETUP,
      adc_period     => ULX3S_SYSTEM.ADC_PERIOD,
      baud_div       => ULX3S_SYSTEM.BAUD_DIV,
      uart_timeout   => ULX3S_SYSTEM.UART_TIMEOUT,
      opt_hostlink   => ULX3S_SYSTEM.OPT_HOSTLINK
    )
    port map (
      clk          => sys_clk,
      rst          => rst,
      adc_cs_n_o   => adc_cs_n,
      adc_sclk_o   => adc_sclk,
      adc_sdata1_i => adc_sdata1,
      adc_sdata2_i => adc_sdata2,
      uart_rx_i    => ftdi_txd,
      uart_tx_o    => ftdi_rxd,
      ref_i        => ref_in,
      a_o          => quad_a,
      b_o          => quad_b,
      z_o          => quad_z,
      status_o     => status
    );

  led <= locked & "00" & status;

end architecture rtl;
