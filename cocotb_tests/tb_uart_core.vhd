-- tb_uart_core: test bench top of cocotb_tests/test_uart_axil.py (uart_core) on GHDL, the
-- VHDL twin of tb_uart_core.v (same generics and ports): the UART bridge (uart_axil) and
-- axil_regs (ADDR_TOP the core's top word, as in rtl/vhdl/finequad_system.vhd) in front of
-- the real finequad_core, no samples.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_regs_pkg.all;

entity tb_uart_core is
  generic (
    -- folder of the core's tables
    TABLE_DIR : string := "rtl/tables/";
    -- clocks per UART bit
    DIV : integer range 8 to 65535 := 16;
    -- clocks between two bytes of a frame before it is dropped
    TIMEOUT : integer range 0 to 2 ** 20 - 1 := 2000
  );
  port (
    clk    : in    std_logic;
    rst    : in    std_logic;
    rxd_i  : in    std_logic;
    txd_o  : out   std_logic;
    drop_o : out   std_logic
  );
end entity tb_uart_core;

architecture bench of tb_uart_core is

  -- no samples, the engine inside (its response port unused)
  constant NO_CODE : signed(11 downto 0)            := (others => '0');
  constant NO_RSP  : std_logic_vector(114 downto 0) := (others => '0');

  signal awaddr    : std_logic_vector(15 downto 0);
  signal araddr    : std_logic_vector(15 downto 0);
  signal awprot    : std_logic_vector(2 downto 0);
  signal arprot    : std_logic_vector(2 downto 0);
  signal wdata     : std_logic_vector(31 downto 0);
  signal rdata     : std_logic_vector(31 downto 0);
  signal wstrb     : std_logic_vector(3 downto 0);
  signal bresp     : std_logic_vector(1 downto 0);
  signal rresp     : std_logic_vector(1 downto 0);
  signal awvalid   : std_logic;
  signal awready   : std_logic;
  signal wvalid    : std_logic;
  signal wready    : std_logic;
  signal bvalid    : std_logic;
  signal bready    : std_logic;
  signal arvalid   : std_logic;
  signal arready   : std_logic;
  signal rvalid    : std_logic;
  signal rready    : std_logic;
  signal reg_we    : std_logic;
  signal reg_re    : std_logic;
  signal reg_err   : std_logic;
  signal reg_addr  : fq_addr_t;
  signal reg_wdata : fq_word_t;
  signal reg_rdata : fq_word_t;

begin

  u_bridge : entity work.uart_axil
    generic map (
      div     => DIV,
      timeout => TIMEOUT
    )
    port map (
      clk            => clk,
      rst            => rst,
      rxd_i          => rxd_i,
      txd_o          => txd_o,
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
      frame_err_o    => open,
      drop_o         => drop_o
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
      reg_we         => reg_we,
      reg_re         => reg_re,
      reg_addr       => reg_addr,
      reg_wdata      => reg_wdata,
      reg_rdata      => reg_rdata,
      reg_err        => reg_err
    );

  u_core : entity work.finequad_core
    generic map (
      table_dir => TABLE_DIR,
      adc_w     => 12
    )
    port map (
      clk         => clk,
      rst         => rst,
      s_valid     => '0',
      s_u1        => NO_CODE,
      s_u2        => NO_CODE,
      s_ref       => '0',
      reg_we      => reg_we,
      reg_re      => reg_re,
      reg_addr    => reg_addr,
      reg_wdata   => reg_wdata,
      reg_rdata   => reg_rdata,
      reg_err     => reg_err,
      m_valid     => open,
      m_count     => open,
      m_fault     => open,
      m_a         => open,
      m_b         => open,
      m_z         => open,
      m_ref_count => open,
      m_homed     => open,
      m_pos_valid => open,
      tdm_ok_i    => '1',
      eng_cmd_o   => open,
      eng_rsp_i   => NO_RSP
    );

end architecture bench;
