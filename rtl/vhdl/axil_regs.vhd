-- axil_regs: AXI4-Lite slave in front of finequad_core's register port (VHDL edition of
-- rtl/axil_regs.v, which gives the reasons, the address map and the timing in full).
--
-- Word index = address / 4 (address bits 1..0 ignored). Words 0 .. ADDR_TOP go to the
-- core: a write it refuses (reg_err with reg_we) answers SLVERR; words above ADDR_TOP
-- answer SLVERR without touching the core (reads 0). Only full-word writes (WSTRB =
-- "1111") are performed; any other WSTRB answers SLVERR and writes nothing.
-- AWREADY, WREADY, ARREADY are high while that channel's holding register is empty;
-- BVALID, RVALID and their payloads are registers. One operation at a time on the core
-- port; a write and a read ready together alternate.
-- Timing: AW and W held before edge e -> reg_we after e, BVALID after e + 1; AR held
-- before e -> reg_re after e, RVALID after e + 1 with RDATA = reg_rdata.
-- rst (sync): the holding registers emptied, BVALID and RVALID dropped. Power-up values
-- are those after rst.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;
  use work.finequad_regs_pkg.all;

entity axil_regs is
  generic (
    -- AXI address width (bits); at least 8 (64 words of the core's port)
    ADDR_W : integer range 8 to integer'high := 16;
    -- highest word index that is mapped to the core (<= 63)
    ADDR_TOP : integer range 0 to 63 := 63
  );
  port (
    clk : in    std_logic;
    rst : in    std_logic; -- sync, active high
    -- AXI4-Lite slave: write address, write data, write response
    s_axil_awaddr  : in    std_logic_vector(ADDR_W - 1 downto 0);
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
    -- read address, read data
    s_axil_araddr  : in    std_logic_vector(ADDR_W - 1 downto 0);
    s_axil_arprot  : in    std_logic_vector(2 downto 0);
    s_axil_arvalid : in    std_logic;
    s_axil_arready : out   std_logic;
    s_axil_rdata   : out   std_logic_vector(31 downto 0);
    s_axil_rresp   : out   std_logic_vector(1 downto 0);
    s_axil_rvalid  : out   std_logic;
    s_axil_rready  : in    std_logic;
    -- finequad_core register port (reg_rdata registered: valid the edge after reg_re)
    reg_we    : out   std_logic;
    reg_re    : out   std_logic;
    reg_addr  : out   fq_addr_t; -- u6 word index
    reg_wdata : out   fq_word_t;
    reg_rdata : in    fq_word_t;
    -- the core refuses the write on the register port (combinational, with reg_we)
    reg_err : in    std_logic
  );
end entity axil_regs;

architecture rtl of axil_regs is

  constant RESP_OKAY   : std_logic_vector(1 downto 0) := "00";
  constant RESP_SLVERR : std_logic_vector(1 downto 0) := "10";

  subtype word_t is unsigned(ADDR_W - 3 downto 0); -- u(ADDR_W - 2) word index

  -- A channel's holding register: full, and the word index it holds.
  type hold_t is record
    full : std_logic;
    word : word_t;
  end record hold_t;

  constant HOLD_EMPTY : hold_t := (full => '0', word => (others => '0'));

  -- The word index of a byte address.
  function word_of (a : std_logic_vector) return word_t is
  begin

    return unsigned(a(a'high downto a'low + 2));

  end function word_of;

  -- ---- holding registers -------------------------------------------------------------
  signal aw     : hold_t                       := HOLD_EMPTY;
  signal ar     : hold_t                       := HOLD_EMPTY;
  signal w_full : std_logic                    := '0';
  signal w_data : fq_word_t                    := (others => '0');
  signal w_strb : std_logic_vector(3 downto 0) := (others => '0');

  -- ---- responses ---------------------------------------------------------------------
  signal bvalid  : std_logic                    := '0';
  signal wr_wait : std_logic                    := '0'; -- reg_we issued: verdict
  signal bresp   : std_logic_vector(1 downto 0) := RESP_OKAY;
  signal rd_wait : std_logic                    := '0'; -- reg_re issued
  signal rvalid  : std_logic                    := '0';
  signal rerr    : std_logic                    := '0'; -- SLVERR read: RDATA 0
  signal last_wr : std_logic                    := '0'; -- the last one a write

  -- ---- register port -----------------------------------------------------------------
  signal we_q    : std_logic := '0';
  signal re_q    : std_logic := '0';
  signal addr_q  : fq_addr_t := (others => '0');
  signal wdata_q : fq_word_t := (others => '0');

  -- ---- decisions (from registered state only) ----------------------------------------
  signal wr_ready  : boolean;
  signal rd_ready  : boolean;
  signal do_wr     : boolean;
  signal do_rd     : boolean;
  signal wr_ok     : boolean;
  signal rd_mapped : boolean;

begin

  wr_ready <= aw.full = '1' and w_full = '1' and bvalid = '0' and wr_wait = '0';
  rd_ready <= ar.full = '1' and rvalid = '0' and rd_wait = '0';

  -- both ready: alternate (the one that did not go last)
  do_wr <= wr_ready and not (rd_ready and last_wr = '1');
  do_rd <= rd_ready and not (wr_ready and last_wr = '0');

  wr_ok     <= aw.word <= ADDR_TOP and w_strb = "1111";
  rd_mapped <= ar.word <= ADDR_TOP;

  regs : process (clk) is
  begin

    if rising_edge(clk) then
      -- channel captures
      if s_axil_awvalid = '1' and aw.full = '0' then
        aw <= (full => '1', word => word_of(s_axil_awaddr));
      end if;

      if s_axil_wvalid = '1' and w_full = '0' then
        w_full <= '1';
        w_data <= s_axil_wdata;
        w_strb <= s_axil_wstrb;
      end if;

      if s_axil_arvalid = '1' and ar.full = '0' then
        ar <= (full => '1', word => word_of(s_axil_araddr));
      end if;

      -- responses accepted
      if bvalid = '1' and s_axil_bready = '1' then
        bvalid <= '0';
      end if;

      if rvalid = '1' and s_axil_rready = '1' then
        rvalid <= '0';
      end if;

      -- register port: one operation per edge at most
      we_q <= '0';
      re_q <= '0';

      if do_wr then
        aw.full <= '0';
        w_full  <= '0';
        we_q    <= to_sl(wr_ok);
        addr_q  <= aw.word(5 downto 0);
        wdata_q <= w_data;
        bresp   <= RESP_OKAY when wr_ok else RESP_SLVERR;
        last_wr <= '1';
      end if;

      -- the response after the core's verdict (reg_we's clock)
      wr_wait <= to_sl(do_wr);

      if wr_wait = '1' then
        bvalid <= '1';

        if we_q = '1' and reg_err = '1' then
          bresp <= RESP_SLVERR;
        end if;
      end if;

      if do_rd then
        ar.full <= '0';
        re_q    <= to_sl(rd_mapped);
        addr_q  <= ar.word(5 downto 0);
        rerr    <= to_sl(not rd_mapped);
        last_wr <= '0';
      end if;

      rd_wait <= to_sl(do_rd);

      if rd_wait = '1' then
        rvalid <= '1';
      end if;

      if rst = '1' then
        aw.full <= '0';
        w_full  <= '0';
        ar.full <= '0';
        bvalid  <= '0';
        wr_wait <= '0';
        rvalid  <= '0';
        rd_wait <= '0';
        we_q    <= '0';
        re_q    <= '0';
        last_wr <= '0';
      end if;
    end if;

  end process regs;

  s_axil_awready <= not aw.full;
  s_axil_wready  <= not w_full;
  s_axil_arready <= not ar.full;
  s_axil_bvalid  <= bvalid;
  s_axil_bresp   <= bresp;
  s_axil_rvalid  <= rvalid;
  s_axil_rresp   <= RESP_SLVERR when rerr = '1' else
                    RESP_OKAY;
  s_axil_rdata   <= (others => '0') when rerr = '1' else
                    reg_rdata;

  reg_we    <= we_q;
  reg_re    <= re_q;
  reg_addr  <= addr_q;
  reg_wdata <= wdata_q;

end architecture rtl;
