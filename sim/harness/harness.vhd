-- harness: the `make rtlsim EDITION=vhdl` bench of the VHDL edition's finequad_core
-- (GHDL). The twin of sim/harness/harness.cpp (the Verilator harness), which describes
-- the contract; sim/run_vhdl.py is its front end (the options, the CSV input and its
-- errors, the settings' register writes: the code the model uses) and writes STIM.
--
-- STIM, a text file (sim/run_vhdl.py write_stim):
--   line 1          div n_writes n_reads      (decimal)
--   n_writes lines  index word                (decimal word index, 8 hex digits)
--   n_reads lines   index                     (read after the last sample: --dump-regs)
--   then per sample u1 u2 ref                 (decimal)
-- OUT_CSV gets the header 'count,a,b,fault,z,ref_count,homed,pos_valid' and one row per
-- sample; OUT_STATUS gets 'rdata <8 hex digits>' per read, or 'refused <k>' when the core
-- raised reg_err on write k (then the bench stops).
--
-- Timing: the harness's edges (registers written on edges 0, 1, ..., sample k strobed on
-- edge T0 + k * div, T0 = 32; count, a, b, fault, z taken after a sample's output edge,
-- ref_count, homed, pos_valid two edges later). Here the inputs of edge e change at
-- e * PERIOD, and clk rises half a period later, at e * PERIOD + PERIOD / 2, so no input
-- changes in the delta cycle of a clock edge: GHDL's VCD shows edge e half a period
-- later than the Verilator VCD (scripts/vcdcompare.py --rtl-edge0-ps).

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library std;
  use std.textio.all;
  use std.env.all;

entity harness is
  generic (
    STIM       : string;
    OUT_CSV    : string;
    OUT_STATUS : string;
    -- finequad_core's generics (make rtlsim's knobs)
    TABLE_DIR      : string                 := "rtl/tables/";
    ADC_W          : integer range 12 to 16 := 16;
    TABLE_EXACT    : integer range 0 to 1   := 1;
    ENGINE_LANES   : integer range 1 to 2   := 1;
    OPT_DISTRAM    : integer range 0 to 1   := 0;
    OPT_PHASE_4K   : integer range 0 to 1   := 0;
    OPT_PULSE_ADDR : integer range 0 to 1   := 0;
    OPT_HARMONIC   : integer range 0 to 1   := 1;
    OPT_NTH_DSP    : integer range 0 to 1   := 1;
    OPT_TUNABLE    : integer range 0 to 1   := 1;
    OPT_MONITOR    : integer range 0 to 1   := 1;
    OPT_JUMP       : integer range 0 to 1   := 1;
    OPT_DCODE      : integer range 0 to 1   := 1
  );
end entity harness;

architecture bench of harness is

  constant PERIOD  : time    := 27778 ps;     -- 36 MHz, as harness.cpp
  constant HALF    : time    := 13889 ps;
  constant T0      : integer := 32;
  constant REF_LAG : integer := 2;
  constant COUNT_W : integer := 32;

  signal clk         : std_logic                     := '0';
  signal s_valid     : std_logic                     := '0';
  signal s_u1        : signed(ADC_W - 1 downto 0)    := (others => '0');
  signal s_u2        : signed(ADC_W - 1 downto 0)    := (others => '0');
  signal s_ref       : std_logic                     := '0';
  signal reg_we      : std_logic                     := '0';
  signal reg_re      : std_logic                     := '0';
  signal reg_addr    : unsigned(5 downto 0)          := (others => '0');
  signal reg_wdata   : std_logic_vector(31 downto 0) := (others => '0');
  signal reg_rdata   : std_logic_vector(31 downto 0);
  signal reg_err     : std_logic;
  signal m_valid     : std_logic;
  signal m_count     : signed(COUNT_W - 1 downto 0);
  signal m_fault     : std_logic_vector(10 downto 0);
  signal m_a         : std_logic;
  signal m_b         : std_logic;
  signal m_z         : std_logic;
  signal m_ref_count : signed(COUNT_W - 1 downto 0);
  signal m_homed     : std_logic;
  signal m_pos_valid : std_logic;
  -- the core's other inputs, held (as harness.cpp leaves them), and its engine port
  signal rst       : std_logic                      := '0';
  signal tdm_ok_i  : std_logic                      := '0';
  signal eng_rsp_i : std_logic_vector(114 downto 0) := (others => '0');
  signal eng_cmd_o : std_logic_vector(65 downto 0);

  -- an output row waiting for its reference columns
  type row_t is record
    edge  : integer;
    count : integer;
    a     : integer;
    b     : integer;
    fault : integer;
    z     : integer;
  end record row_t;

  type rows_t is array (0 to 3) of row_t;

  type writes_t is array (0 to 63) of std_logic_vector(31 downto 0);

  type indices_t is array (0 to 63) of integer range 0 to 63;

  function bit_of (s : std_logic) return integer is
  begin

    if s = '1' then
      return 1;
    end if;

    return 0;

  end function bit_of;

begin

  finequad_core : entity work.finequad_core
    generic map (
      table_dir      => TABLE_DIR,
      adc_w          => ADC_W,
      table_exact    => TABLE_EXACT,
      engine_lanes   => ENGINE_LANES,
      opt_distram    => OPT_DISTRAM,
      opt_phase_4k   => OPT_PHASE_4K,
      opt_pulse_addr => OPT_PULSE_ADDR,
      opt_harmonic   => OPT_HARMONIC,
      opt_nth_dsp    => OPT_NTH_DSP,
      opt_tunable    => OPT_TUNABLE,
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
      reg_we      => reg_we,
      reg_re      => reg_re,
      reg_addr    => reg_addr,
      reg_wdata   => reg_wdata,
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
      tdm_ok_i    => tdm_ok_i,
      eng_cmd_o   => eng_cmd_o,
      eng_rsp_i   => eng_rsp_i
    );

  run : process is

    file     fi        : text;
    file     fo        : text;
    file     fs        : text;
    variable li        : line;
    variable lo        : line;
    variable div       : integer;
    variable n_writes  : integer;
    variable n_reads   : integer;
    variable w_index   : indices_t;
    variable w_word    : writes_t;
    variable r_index   : indices_t;
    variable a         : integer := 0;
    variable b         : integer := 0;
    variable rf        : integer := 0;
    variable have      : boolean;
    variable strobed   : integer := 0;
    variable written   : integer := 0;
    variable last_edge : integer := -1;
    variable e         : integer := 0;
    variable strobe    : boolean;
    variable pend      : rows_t;
    variable head      : integer := 0;
    variable tail      : integer := 0;

    -- the next sample of STIM (false at its end; blank lines skipped)

    procedure next_sample (
      ok : out boolean
    ) is
    begin

      ok := false;

      while not endfile(fi) loop

        readline(fi, li);

        if li'length > 0 then
          read(li, a);
          read(li, b);
          read(li, rf);
          ok := true;
          return;
        end if;

      end loop;

    end procedure next_sample;

    -- one clock: the inputs already set at the period's start, the rising edge half a
    -- period later; returns at the next period's start with the edge's outputs settled

    procedure clock is
    begin

      wait for HALF;
      clk <= '1';
      wait for HALF;
      clk <= '0';

    end procedure clock;

  begin

    file_open(fi, STIM, read_mode);
    file_open(fo, OUT_CSV, write_mode);
    file_open(fs, OUT_STATUS, write_mode);
    readline(fi, li);
    read(li, div);
    read(li, n_writes);
    read(li, n_reads);

    for k in 0 to n_writes - 1 loop

      readline(fi, li);
      read(li, w_index(k));
      hread(li, w_word(k));

    end loop;

    for k in 0 to n_reads - 1 loop

      readline(fi, li);
      read(li, r_index(k));

    end loop;

    write(lo, string'("count,a,b,fault,z,ref_count,homed,pos_valid"));
    writeline(fo, lo);
    next_sample(have);

    while last_edge < 0 or e <= last_edge loop

      -- the inputs of edge e
      if e < n_writes then
        reg_we    <= '1';
        reg_addr  <= to_unsigned(w_index(e), 6);
        reg_wdata <= w_word(e);
      else
        reg_we <= '0';
      end if;

      strobe := have and e = T0 + strobed * div;

      if strobe then
        s_valid <= '1';
        s_u1    <= to_signed(a, ADC_W);
        s_u2    <= to_signed(b, ADC_W);
        s_ref   <= '1' when rf = 1 else '0';
        strobed := strobed + 1;
        next_sample(have);
        if not have then
          last_edge := e + 12;
        end if;
      else
        s_valid <= '0';
        s_u1    <= (others => '0');
        s_u2    <= (others => '0');
        s_ref   <= '0';
      end if;

      clock;
      -- the outputs after edge e
      if m_valid = '1' then
        pend(tail mod 4) :=
        (
          edge  => e,
          count => to_integer(m_count),
          a     => bit_of(m_a),
          b     => bit_of(m_b),
          fault => to_integer(unsigned(m_fault)),
          z     => bit_of(m_z)
        );
        tail             := tail + 1;
        assert tail - head <= 4
          report "internal: more than 4 rows pending"
          severity failure;
      end if;

      if head /= tail and pend(head mod 4).edge + REF_LAG = e then
        write(lo, pend(head mod 4).count);
        write(lo, ',');
        write(lo, pend(head mod 4).a);
        write(lo, ',');
        write(lo, pend(head mod 4).b);
        write(lo, ',');
        write(lo, pend(head mod 4).fault);
        write(lo, ',');
        write(lo, pend(head mod 4).z);
        write(lo, ',');
        write(lo, to_integer(m_ref_count));
        write(lo, ',');
        write(lo, bit_of(m_homed));
        write(lo, ',');
        write(lo, bit_of(m_pos_valid));
        writeline(fo, lo);
        head    := head + 1;
        written := written + 1;
      end if;

      if e < n_writes and reg_err = '1' then
        write(lo, string'("refused "));
        write(lo, e);
        writeline(fs, lo);
        file_close(fo);
        file_close(fs);
        finish;
      end if;

      e := e + 1;

    end loop;

    -- --dump-regs: the registered read port, the address for one edge, the value after it
    reg_we  <= '0';
    s_valid <= '0';

    for k in 0 to n_reads - 1 loop

      reg_re   <= '1';
      reg_addr <= to_unsigned(r_index(k), 6);
      clock;
      write(lo, string'("rdata "));
      hwrite(lo, reg_rdata);
      writeline(fs, lo);

    end loop;

    reg_re <= '0';

    assert written = strobed
      report "wrote " & integer'image(written) & " rows for " & integer'image(strobed) &
             " samples"
      severity failure;
    file_close(fi);
    file_close(fo);
    file_close(fs);
    -- (the last falling edge and half a period after it into the VCD, as the Verilator
    -- VCD ends after the last edge's falling edge)
    wait for HALF;
    finish;
    wait;

  end process run;

end architecture bench;
