-- tb_axil_core: test bench top of cocotb_tests/test_axil_regs.py (axil_core) on GHDL, the
-- VHDL twin of tb_axil_core.v (same generic and ports): axil_regs (ADDR_TOP the core's
-- top word, as in rtl/vhdl/finequad_system.vhd) in front of finequad_core, no samples.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_regs_pkg.all;

entity tb_axil_core is
  generic (
    -- folder of the core's tables
    TABLE_DIR : string := "rtl/tables/"
  );
  port (
    clk            : in    std_logic;
    rst            : in    std_logic;
    s_axil_awaddr  : in    std_logic_vector(15 downto 0);
    s_axil_awprot  : in    std_logic_vector(2 downto 0);
    s_axil_awvalid : in    std_logic;
    s_axil_awready : out   std_logic;
    s_axil_wdata   : in    std_logic_vector(31 downto 0);
    s_axil_wstrb   : in    std_logic_vector(3 downto 0);
    s_axil_wvalid  : in    std_logic;
    s_axil_wready  : out   std_logic;
    s_axil_bresp   : out   std_logic_vector(1 downto 0);
    s_axil_bvalid  : out   std_logic;
    s_axil_bready  : in    std_logic;
    s_axil_araddr  : in    std_logic_vector(15 downto 0);
    s_axil_arprot  : in    std_logic_vector(2 downto 0);
    s_axil_arvalid : in    std_logic;
    s_axil_arready : out   std_logic;
    s_axil_rdata   : out   std_logic_vector(31 downto 0);
    s_axil_rresp   : out   std_logic_vector(1 downto 0);
    s_axil_rvalid  : out   std_logic;
    s_axil_rready  : in    std_logic
  );
end entity tb_axil_core;

architecture bench of tb_axil_core is

  -- no samples, the engine inside (its response port unused)
  constant NO_CODE : signed(11 downto 0)            := (others => '0');
  constant NO_RSP  : std_logic_vector(114 downto 0) := (others => '0');

  signal reg_we    : std_logic;
  signal reg_re    : std_logic;
  signal reg_err   : std_logic;
  signal reg_addr  : fq_addr_t;
  signal reg_wdata : fq_word_t;
  signal reg_rdata : fq_word_t;

begin

  u_regs : entity work.axil_regs
    generic map (
      addr_w   => 16,
      addr_top => to_integer(FQ_ADDR_TOP)
    )
    port map (
      clk            => clk,
      rst            => rst,
      s_axil_awaddr  => s_axil_awaddr,
      s_axil_awprot  => s_axil_awprot,
      s_axil_awvalid => s_axil_awvalid,
      s_axil_awready => s_axil_awready,
      s_axil_wdata   => s_axil_wdata,
      s_axil_wstrb   => s_axil_wstrb,
      s_axil_wvalid  => s_axil_wvalid,
      s_axil_wready  => s_axil_wready,
      s_axil_bresp   => s_axil_bresp,
      s_axil_bvalid  => s_axil_bvalid,
      s_axil_bready  => s_axil_bready,
      s_axil_araddr  => s_axil_araddr,
      s_axil_arprot  => s_axil_arprot,
      s_axil_arvalid => s_axil_arvalid,
      s_axil_arready => s_axil_arready,
      s_axil_rdata   => s_axil_rdata,
      s_axil_rresp   => s_axil_rresp,
      s_axil_rvalid  => s_axil_rvalid,
      s_axil_rready  => s_axil_rready,
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
