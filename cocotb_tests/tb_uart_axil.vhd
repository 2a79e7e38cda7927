-- tb_uart_axil: test bench top of cocotb_tests/test_uart_axil.py on GHDL, the VHDL twin
-- of tb_uart_axil.v (same generics and ports): the UART bridge (uart_axil) driving
-- axil_regs (ADDR_TOP 0x2f); the test's register-file model serves the register port.

library ieee;
  use ieee.std_logic_1164.all;

library work;
  use work.finequad_regs_pkg.all;

entity tb_uart_axil is
  generic (
    -- clocks per UART bit
    DIV : integer range 8 to 65535 := 16;
    -- clocks between two bytes of a frame before it is abandoned
    TIMEOUT : integer range 0 to 2 ** 20 - 1 := 2000
  );
  port (
    clk         : in    std_logic;
    rst         : in    std_logic;
    rxd_i       : in    std_logic;
    txd_o       : out   std_logic;
    frame_err_o : out   std_logic;
    drop_o      : out   std_logic;
    reg_we      : out   std_logic;
    reg_re      : out   std_logic;
    reg_addr    : out   fq_addr_t;
    reg_wdata   : out   fq_word_t;
    reg_rdata   : in    fq_word_t;
    reg_err     : in    std_logic
  );
end entity tb_uart_axil;

architecture bench of tb_uart_axil is

  signal awaddr  : std_logic_vector(15 downto 0);
  signal araddr  : std_logic_vector(15 downto 0);
  signal awprot  : std_logic_vector(2 downto 0);
  signal arprot  : std_logic_vector(2 downto 0);
  signal wdata   : std_logic_vector(31 downto 0);
  signal rdata   : std_logic_vector(31 downto 0);
  signal wstrb   : std_logic_vector(3 downto 0);
  signal bresp   : std_logic_vector(1 downto 0);
  signal rresp   : std_logic_vector(1 downto 0);
  signal awvalid : std_logic;
  signal awready : std_logic;
  signal wvalid  : std_logic;
  signal wready  : std_logic;
  signal bvalid  : std_logic;
  signal bready  : std_logic;
  signal arvalid : std_logic;
  signal arready : std_logic;
  signal rvalid  : std_logic;
  signal rready  : std_logic;

begin

  u_bridge : entity work.uart_axil
    generic map (
      DIV     => DIV,
      TIMEOUT => TIMEOUT
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
      frame_err_o    => frame_err_o,
      drop_o         => drop_o
    );

  u_regs : entity work.axil_regs
    generic map (
      ADDR_W   => 16,
      ADDR_TOP => 16#2f#
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

end architecture bench;
