-- top_report: finequad_core with every port kept, for resource and timing reports of the
-- VHDL edition (`make report EDITION=vhdl`: ghdl --synth of this entity, then Yosys and
-- nextpnr as for the Verilog edition). The VHDL edition of ../boards/top_report.v, which
-- says why it is built so: every core input comes from a flip-flop of a serial scan
-- chain (sdi), every output goes, four bits per register, into an XOR reduction (sdo),
-- so nothing of the core is optimised away and every core path runs from flip-flop to
-- flip-flop. Not a design to load: the pins carry no protocol.
--
-- The core is a component (bound to the entity finequad_core at elaboration), so this
-- file is analysed on its own.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

entity top_report is
  generic (
    -- forwarded to finequad_core
    OPT_NTH_DSP    : integer range 0 to 1 := 1;
    OPT_HARMONIC   : integer range 0 to 1 := 1;
    OPT_DISTRAM    : integer range 0 to 1 := 0;
    OPT_PHASE_4K   : integer range 0 to 1 := 0;
    OPT_ECP5_MULT  : integer range 0 to 1 := 0;
    OPT_PULSE_ADDR : integer range 0 to 1 := 0;
    OPT_TUNABLE    : integer range 0 to 1 := 1;
    OPT_MONITOR    : integer range 0 to 1 := 1;
    OPT_JUMP       : integer range 0 to 1 := 1;
    OPT_DCODE      : integer range 0 to 1 := 1;
    ENGINE_LANES   : integer range 1 to 2 := 1;
    -- 1: reg_rdata is observed; 0: reg_re tied low, the read-back removed
    OPT_READBACK : integer range 0 to 1 := 1;
    -- 1: the register port is driven from the scan chain; 0: reg_we and reg_re tied low
    OPT_REGPORT : integer range 0 to 1 := 1;
    -- the tables' folder (the Verilog top leaves the core's default; ghdl --synth is
    -- given it)
    TABLE_DIR : string := "rtl/tables/"
  );
  port (
    clk : in    std_logic;
    sdi : in    std_logic; -- scan chain in
    sdo : out   std_logic  -- XOR of the registered outputs
  );
end entity top_report;

architecture rtl of top_report is

  component finequad_core is
    generic (
      TABLE_DIR      : string;
      OPT_NTH_DSP    : integer range 0 to 1;
      OPT_HARMONIC   : integer range 0 to 1;
      OPT_DISTRAM    : integer range 0 to 1;
      OPT_PHASE_4K   : integer range 0 to 1;
      OPT_ECP5_MULT  : integer range 0 to 1;
      OPT_PULSE_ADDR : integer range 0 to 1;
      OPT_TUNABLE    : integer range 0 to 1;
      OPT_MONITOR    : integer range 0 to 1;
      OPT_JUMP       : integer range 0 to 1;
      OPT_DCODE      : integer range 0 to 1;
      ENGINE_LANES   : integer range 1 to 2
    );
    port (
      clk         : in    std_logic;
      rst         : in    std_logic;
      s_valid     : in    std_logic;
      s_u1        : in    signed(15 downto 0);
      s_u2        : in    signed(15 downto 0);
      s_ref       : in    std_logic;
      reg_we      : in    std_logic;
      reg_re      : in    std_logic;
      reg_addr    : in    unsigned(5 downto 0);
      reg_wdata   : in    std_logic_vector(31 downto 0);
      reg_rdata   : out   std_logic_vector(31 downto 0);
      reg_err     : out   std_logic;
      m_valid     : out   std_logic;
      m_count     : out   signed(31 downto 0);
      m_fault     : out   std_logic_vector(10 downto 0);
      m_a         : out   std_logic;
      m_b         : out   std_logic;
      m_z         : out   std_logic;
      m_ref_count : out   signed(31 downto 0);
      m_homed     : out   std_logic;
      m_pos_valid : out   std_logic;
      tdm_ok_i    : in    std_logic;
      eng_cmd_o   : out   std_logic_vector(65 downto 0);
      eng_rsp_i   : in    std_logic_vector(114 downto 0)
    );
  end component finequad_core;

  -- rst, s_valid, s_u1, s_u2, reg_we, reg_re, reg_addr, reg_wdata, s_ref
  constant IN_W : integer := 1 + 1 + 16 + 16 + 1 + 1 + 6 + 32 + 1;
  -- reg_err, reg_rdata, m_count, m_fault, m_valid, m_a, m_b, m_ref_count, m_z, m_homed,
  -- m_pos_valid; in groups of four
  constant OUT_W : integer := 32 + 32 + 11 + 3 + 1 + 32 + 3;
  constant OUT_G : integer := (OUT_W + 3) / 4;

  signal chain       : std_logic_vector(IN_W - 1 downto 0)  := (others => '0');
  signal reg_we      : std_logic;
  signal reg_re      : std_logic;
  signal reg_rdata   : std_logic_vector(31 downto 0);
  signal reg_err     : std_logic;
  signal m_valid     : std_logic;
  signal m_count     : signed(31 downto 0);
  signal m_fault     : std_logic_vector(10 downto 0);
  signal m_a         : std_logic;
  signal m_b         : std_logic;
  signal m_z         : std_logic;
  signal m_ref_count : signed(31 downto 0);
  signal m_homed     : std_logic;
  signal m_pos_valid : std_logic;
  signal eng_cmd     : std_logic_vector(65 downto 0);       -- 0: the engine is inside
  signal outs        : std_logic_vector(4 * OUT_G - 1 downto 0);
  signal outs_q      : std_logic_vector(OUT_G - 1 downto 0) := (others => '0');
  signal sdo_q       : std_logic                            := '0';

begin

  scan : process (clk) is
  begin

    if rising_edge(clk) then
      chain <= chain(IN_W - 2 downto 0) & sdi;
    end if;

  end process scan;

  reg_we <= chain(34) when OPT_REGPORT = 1 else
            '0';
  reg_re <= chain(35) when OPT_REGPORT = 1 and OPT_READBACK = 1 else
            '0';

  u_core : component finequad_core
    generic map (
      table_dir      => TABLE_DIR,
      opt_nth_dsp    => OPT_NTH_DSP,
      opt_harmonic   => OPT_HARMONIC,
      opt_distram    => OPT_DISTRAM,
      opt_phase_4k   => OPT_PHASE_4K,
      opt_ecp5_mult  => OPT_ECP5_MULT,
      opt_pulse_addr => OPT_PULSE_ADDR,
      opt_tunable    => OPT_TUNABLE,
      opt_monitor    => OPT_MONITOR,
      opt_jump       => OPT_JUMP,
      opt_dcode      => OPT_DCODE,
      engine_lanes   => ENGINE_LANES
    )
    port map (
      clk         => clk,
      rst         => chain(0),
      s_valid     => chain(1),
      s_u1        => signed(chain(17 downto 2)),
      s_u2        => signed(chain(33 downto 18)),
      s_ref       => chain(74),
      reg_we      => reg_we,
      reg_re      => reg_re,
      reg_addr    => unsigned(chain(41 downto 36)),
      reg_wdata   => chain(73 downto 42),
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
      tdm_ok_i    => '1',
      eng_cmd_o   => eng_cmd,
      eng_rsp_i   => (others => '0')
    );

  outs <=
  (
    4 * OUT_G - 1 downto OUT_W => '0'
  ) & reg_err & reg_rdata &
    std_logic_vector(m_count) & m_fault & m_valid & m_a & m_b &
    std_logic_vector(m_ref_count
                    ) & m_z & m_homed & m_pos_valid;

  -- outputs, four to a register (one LUT4 and its flip-flop), then one XOR tree
  reduce : process (clk) is
  begin

    if rising_edge(clk) then

      for i in 0 to OUT_G - 1 loop

        outs_q(i) <= xor outs(4 * i + 3 downto 4 * i);

      end loop;

      sdo_q <= xor outs_q;
    end if;

  end process reduce;

  sdo <= sdo_q;

end architecture rtl;
