-- finequad_system: the board-independent design every board top instantiates (VHDL
-- edition of rtl/finequad_system.v, whose header gives the timing and the reasoning):
-- Pmod AD1 front end (adc_pmod_ad1) -> finequad_core; the core's registers on an
-- AXI4-Lite bus (axil_regs) mastered by the UART bridge (uart_axil); the reference input;
-- the A/B and Z pins; status for LEDs.
--
-- AXI byte address 4 k = core register k for k = 0 .. FQ_ADDR_TOP; above it SLVERR;
-- partial writes SLVERR. UART 8N1 at f_clk / BAUD_DIV (rtl/uart_axil.v, scripts/fqhost.py).
-- a_o, b_o, z_o: the core's m_a, m_b, m_z registered once more (pins from flip-flops).
-- ref_i (asynchronous): two synchronising flip-flops; the level they hold on the edge after
-- CS_N falls is the sample's s_ref.
-- status_o ([1..3] sticky until rst): (0) calibrated (the last sample's fault bit 4
-- clear), (1) a fault seen (bits 0..3), (2) an ADC frame with non-zero leading bits,
-- (3) a UART frame dropped, (4) position valid (REF_STATUS.pos_valid).
-- rst: synchronous, active high, to every block.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_regs_pkg.all;

entity finequad_system is
  generic (
    -- folder of the core's tables
    TABLE_DIR : string := "rtl/tables/";
    -- the core's options (finequad_core)
    OPT_NTH_DSP    : integer range 0 to 1 := 0;
    OPT_HARMONIC   : integer range 0 to 1 := 1;
    OPT_DISTRAM    : integer range 0 to 1 := 0;
    OPT_PHASE_4K   : integer range 0 to 1 := 0;
    OPT_ECP5_MULT  : integer range 0 to 1 := 0;
    OPT_PULSE_ADDR : integer range 0 to 1 := 0;
    OPT_MONITOR    : integer range 0 to 1 := 1;
    OPT_JUMP       : integer range 0 to 1 := 1;
    OPT_DCODE      : integer range 0 to 1 := 1;
    -- ADC front end: clocks per SCLK half period, CS_N to first SCLK falling, per sample
    ADC_SCLK_HALF : integer range 1 to 2047  := 1;
    ADC_CS_SETUP  : integer range 1 to 65535 := 1;
    ADC_PERIOD    : integer range 2 to 65536 := 34;
    -- clocks per UART bit (f_clk / baud)
    BAUD_DIV : integer range 8 to 65535 := 286;
    -- clocks between two bytes of a UART frame before it is abandoned
    UART_TIMEOUT : integer range 0 to 2 ** 20 - 1 := 262143;
    -- 1: the UART host link and the AXI4-Lite registers; 0: none (the core's registers
    -- keep their reset values; uart_tx_o idles high)
    OPT_HOSTLINK : integer range 0 to 1 := 1
  );
  port (
    clk : in    std_logic;
    rst : in    std_logic;                   -- sync, active high
    -- Pmod AD1
    adc_cs_n_o   : out   std_logic;
    adc_sclk_o   : out   std_logic;
    adc_sdata1_i : in    std_logic;
    adc_sdata2_i : in    std_logic;
    -- host link
    uart_rx_i : in    std_logic;
    uart_tx_o : out   std_logic;
    -- reference input (asynchronous)
    ref_i : in    std_logic;
    -- quadrature outputs and Z
    a_o : out   std_logic;
    b_o : out   std_logic;
    z_o : out   std_logic;
    -- status (see above)
    status_o : out   std_logic_vector(4 downto 0)
  );
end entity finequad_system;

architecture rtl of finequad_system is

  -- The core's register port.
  type reg_port_t is record
    we    : std_logic;
    re    : std_logic;
    addr  : fq_addr_t;
    wdata : fq_word_t;
  end record reg_port_t;

  constant REG_IDLE : reg_port_t :=
  (
    we    => '0',
    re    => '0',
    addr  => (others => '0'),
    wdata => (others => '0')
  );

  -- ---- ADC front end ---------------------------------------------------------------------
  signal s_valid : std_logic;
  signal s_u1    : signed(11 downto 0); -- s12 codes
  signal s_u2    : signed(11 downto 0);
  signal adc_err : std_logic;

  -- ---- host link -------------------------------------------------------------------------
  signal reg_port  : reg_port_t;
  signal reg_rdata : fq_word_t;
  signal reg_err   : std_logic;
  signal uart_drop : std_logic;

  -- ---- reference input -------------------------------------------------------------------
  signal ref_sync : std_logic_vector(1 downto 0) := "00"; -- ref_i, two flip-flops
  signal cs_n_q   : std_logic                    := '1';  -- CS_N one edge later
  signal s_ref    : std_logic                    := '0';  -- the conversion's reference level

  -- ---- the core --------------------------------------------------------------------------
  signal m_valid     : std_logic;
  signal m_count     : signed(31 downto 0);
  signal m_fault     : std_logic_vector(FQ_FAULT_W - 1 downto 0);
  signal m_a         : std_logic;
  signal m_b         : std_logic;
  signal m_z         : std_logic;
  signal m_ref_count : signed(31 downto 0);
  signal m_homed     : std_logic;
  signal m_pos_valid : std_logic;
  signal eng_cmd     : std_logic_vector(65 downto 0); -- unused: the engine is inside

  -- ---- pins and status -------------------------------------------------------------------
  signal a_q        : std_logic := '1';
  signal b_q        : std_logic := '1';
  signal z_q        : std_logic := '0';
  signal cal_q      : std_logic := '0';
  signal fault_q    : std_logic := '0';
  signal adc_err_q  : std_logic := '0';
  signal uart_err_q : std_logic := '0';

begin

  u_adc : entity work.adc_pmod_ad1
    generic map (
      sclk_half => ADC_SCLK_HALF,
      cs_setup  => ADC_CS_SETUP,
      period    => ADC_PERIOD,
      out_w     => 12
    )
    port map (
      clk      => clk,
      rst      => rst,
      cs_n_o   => adc_cs_n_o,
      sclk_o   => adc_sclk_o,
      sdata1_i => adc_sdata1_i,
      sdata2_i => adc_sdata2_i,
      m_valid  => s_valid,
      m_u1     => s_u1,
      m_u2     => s_u2,
      m_err    => adc_err
    );

  -- ---- host link: UART -> AXI4-Lite -> register port -------------------------------------

  g_host : if OPT_HOSTLINK = 1 generate

    -- The AXI4-Lite bus: the master's (uart_axil) signals, then the slave's (axil_regs).
    signal awaddr    : std_logic_vector(15 downto 0);
    signal awprot    : std_logic_vector(2 downto 0);
    signal awvalid   : std_logic;
    signal wdata     : std_logic_vector(31 downto 0);
    signal wstrb     : std_logic_vector(3 downto 0);
    signal wvalid    : std_logic;
    signal bready    : std_logic;
    signal araddr    : std_logic_vector(15 downto 0);
    signal arprot    : std_logic_vector(2 downto 0);
    signal arvalid   : std_logic;
    signal rready    : std_logic;
    signal awready   : std_logic;
    signal wready    : std_logic;
    signal bresp     : std_logic_vector(1 downto 0);
    signal bvalid    : std_logic;
    signal arready   : std_logic;
    signal rdata     : std_logic_vector(31 downto 0);
    signal rresp     : std_logic_vector(1 downto 0);
    signal rvalid    : std_logic;
    signal uart_ferr : std_logic;                     -- (unused: drop_o covers it)

  begin

    u_uart : entity work.uart_axil
      generic map (
        div     => BAUD_DIV,
        timeout => UART_TIMEOUT
      )
      port map (
        clk            => clk,
        rst            => rst,
        rxd_i          => uart_rx_i,
        txd_o          => uart_tx_o,
        m_axil_awaddr  => awaddr,
        m_axil_awprot  => awprot,
        m_axil_awvalid => awvalid,
        m_axil_awready => awready,
        m_axil_wdata   => wdata,
        m_axil_wstrb   => wstrb,
        m_axil_wvalid  => wvalid,
        m_axil_wready  => wready,
        m_axil_bresp   => bresp,
        m_axil_bvalid  => bvalid,
        m_axil_bready  => bready,
        m_axil_araddr  => araddr,
        m_axil_arprot  => arprot,
        m_axil_arvalid => arvalid,
        m_axil_arready => arready,
        m_axil_rdata   => rdata,
        m_axil_rresp   => rresp,
        m_axil_rvalid  => rvalid,
        m_axil_rready  => rready,
        frame_err_o    => uart_ferr,
        drop_o         => uart_drop
      );

    u_regs : entity work.axil_regs
      generic map (
        addr_w   => 16,
        addr_top => to_integer(FQ_ADDR_TOP)
      )
      port map (
        clk            => clk,
        rst            => rst,
        s_axil_awaddr  => awaddr,
        s_axil_awprot  => awprot,
        s_axil_awvalid => awvalid,
        s_axil_awready => awready,
        s_axil_wdata   => wdata,
        s_axil_wstrb   => wstrb,
        s_axil_wvalid  => wvalid,
        s_axil_wready  => wready,
        s_axil_bresp   => bresp,
        s_axil_bvalid  => bvalid,
        s_axil_bready  => bready,
        s_axil_araddr  => araddr,
        s_axil_arprot  => arprot,
        s_axil_arvalid => arvalid,
        s_axil_arready => arready,
        s_axil_rdata   => rdata,
        s_axil_rresp   => rresp,
        s_axil_rvalid  => rvalid,
        s_axil_rready  => rready,
        reg_we         => reg_port.we,
        reg_re         => reg_port.re,
        reg_addr       => reg_port.addr,
        reg_wdata      => reg_port.wdata,
        reg_rdata      => reg_rdata,
        reg_err        => reg_err
      );

  else generate

    reg_port  <= REG_IDLE;
    uart_tx_o <= '1';
    uart_drop <= '0';

  end generate g_host;

  -- ---- reference input: synchroniser, then held from the conversion's CS_N edge ----------
  ref_hold : process (clk) is
  begin

    if rising_edge(clk) then
      ref_sync <= ref_sync(0) & ref_i;
      cs_n_q   <= adc_cs_n_o;

      if cs_n_q = '1' and adc_cs_n_o = '0' then
        s_ref <= ref_sync(1);
      end if;

      if rst = '1' then
        cs_n_q <= '1';
        s_ref  <= '0';
      end if;
    end if;

  end process ref_hold;

  -- ---- the core --------------------------------------------------------------------------
  u_core : entity work.finequad_core
    generic map (
      table_dir      => TABLE_DIR,
      adc_w          => 12,
      opt_nth_dsp    => OPT_NTH_DSP,
      opt_harmonic   => OPT_HARMONIC,
      opt_distram    => OPT_DISTRAM,
      opt_phase_4k   => OPT_PHASE_4K,
      opt_ecp5_mult  => OPT_ECP5_MULT,
      opt_pulse_addr => OPT_PULSE_ADDR,
      opt_monitor    => OPT_MONITOR,
      opt_jump       => OPT_JUMP,
      opt_dcode      => OPT_DCODE
    )
    port map (
      clk         => clk,
      rst         => rst,
      s_valid     => s_valid,
      s_u1        => s_u1,
      s_u2        => s_u2,
      s_ref       => s_ref,
      reg_we      => reg_port.we,
      reg_re      => reg_port.re,
      reg_addr    => reg_port.addr,
      reg_wdata   => reg_port.wdata,
      reg_rdata   => reg_rdata,
      reg_err     => reg_err,
      m_valid     => m_valid,
      m_count     => m_count,
      m_fault     => m_fault,
      m_a         => m_a,
      m_b         => m_b,
      m_z         => m_z,
      m_ref_count => m_ref_count,
      m_homed     => m_homed,
      m_pos_valid => m_pos_valid,
      -- the engine inside
      tdm_ok_i  => '1',
      eng_cmd_o => eng_cmd,
      eng_rsp_i => (others => '0')
    );

  -- ---- pins and status -------------------------------------------------------------------
  pins : process (clk) is
  begin

    if rising_edge(clk) then
      a_q <= m_a;
      b_q <= m_b;
      z_q <= m_z;

      if m_valid = '1' then
        cal_q <= not m_fault(FQ_FAULT_STICKY_UNCAL_LSB);

        if m_fault(FQ_FAULT_STICKY_CLIP_LSB) = '1' or m_fault(FQ_FAULT_STICKY_NSAT_LSB) = '1'
           or m_fault(FQ_FAULT_STICKY_CSAT_LSB) = '1' or m_fault(FQ_FAULT_STICKY_OVS_LSB) = '1' then
          fault_q <= '1';
        end if;
      end if;

      if s_valid = '1' and adc_err = '1' then
        adc_err_q <= '1';
      end if;

      if uart_drop = '1' then
        uart_err_q <= '1';
      end if;

      if rst = '1' then
        cal_q      <= '0';
        fault_q    <= '0';
        adc_err_q  <= '0';
        uart_err_q <= '0';
      end if;
    end if;

  end process pins;

  a_o <= a_q;
  b_o <= b_q;
  z_o <= z_q;

  -- pos_valid: the core's register (refmark), straight to the LED
  status_o <= m_pos_valid & uart_err_q & adc_err_q & fault_q & cal_q;

end architecture rtl;
