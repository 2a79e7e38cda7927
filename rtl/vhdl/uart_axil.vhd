-- uart_axil: UART (8N1) to AXI4-Lite master bridge, so that a PC can read and write the
-- registers (VHDL edition of rtl/uart_axil.v, which describes the protocol, its
-- robustness and the timing in full; host side: scripts/fqhost.py, FqProtocol).
--
-- Frames: FLAG (x"7E") opens and closes each; x"7E" and x"7D" inside are sent as x"7D"
-- and the byte xor x"20". Content, multi-byte fields big-endian:
--   read:   host 'R' A1 A0 C1 C0               FPGA ST E1 E0 D3 D2 D1 D0 C1 C0
--   write:  host 'W' A1 A0 D3 D2 D1 D0 C1 C0   FPGA ST E1 E0 C1 C0
-- C1 C0: CRC-16/CCITT-FALSE of the frame's bytes before it; E1 E0: the request's C1 C0;
-- ST: x"50" + the AXI response, or x"54" for a wrong CRC (not executed, D = 0).
-- A frame is executed only on its closing FLAG, with a known command, its length and a
-- CRC of residue 0; any other frame is dropped (drop_o, one clock), as is a frame with a
-- framing error or a break or more than TIMEOUT clocks between two bytes. Bytes outside
-- a frame, or while a command executes or its answer goes out, are ignored.
-- AXI4-Lite master: one transaction at a time; AWVALID and WVALID rise together (WSTRB
-- "1111", AWPROT/ARPROT 0) and each drops on its own handshake; BREADY/RREADY high
-- while the response is awaited; valids are registers. The transaction starts on the
-- edge after the closing FLAG is received; the answer's opening FLAG follows the
-- response handshake by 2 clocks.
-- rst (sync): idle, bus valids dropped. Power-up values are those after rst.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;

entity uart_axil is
  generic (
    -- clocks per UART bit (f_clk / baud)
    DIV : integer range 8 to 65535 := 286;
    -- clocks allowed between two bytes of a frame before it is dropped (< 2^20)
    TIMEOUT : integer range 0 to 2 ** 20 - 1 := 262143
  );
  port (
    clk   : in    std_logic;
    rst   : in    std_logic; -- sync, active high
    rxd_i : in    std_logic; -- from the host (asynchronous)
    txd_o : out   std_logic; -- to the host
    -- AXI4-Lite master
    m_axil_awaddr  : out   std_logic_vector(15 downto 0);
    m_axil_awprot  : out   std_logic_vector(2 downto 0);
    m_axil_awvalid : out   std_logic;
    m_axil_awready : in    std_logic;
    m_axil_wdata   : out   std_logic_vector(31 downto 0);
    m_axil_wstrb   : out   std_logic_vector(3 downto 0);
    m_axil_wvalid  : out   std_logic;
    m_axil_wready  : in    std_logic;
    m_axil_bresp   : in    std_logic_vector(1 downto 0);
    m_axil_bvalid  : in    std_logic;
    m_axil_bready  : out   std_logic;
    m_axil_araddr  : out   std_logic_vector(15 downto 0);
    m_axil_arprot  : out   std_logic_vector(2 downto 0);
    m_axil_arvalid : out   std_logic;
    m_axil_arready : in    std_logic;
    m_axil_rdata   : in    std_logic_vector(31 downto 0);
    m_axil_rresp   : in    std_logic_vector(1 downto 0);
    m_axil_rvalid  : in    std_logic;
    m_axil_rready  : out   std_logic;
    -- diagnostics (one-clock pulses)
    frame_err_o : out   std_logic; -- UART framing error or break
    drop_o      : out   std_logic  -- a frame dropped
  );
end entity uart_axil;

architecture rtl of uart_axil is

  subtype byte_t is std_logic_vector(7 downto 0);

  subtype crc_t is std_logic_vector(15 downto 0);

  constant CMD_R  : byte_t                       := x"52";
  constant CMD_W  : byte_t                       := x"57";
  constant FLAG   : byte_t                       := x"7E";
  constant ESC    : byte_t                       := x"7D";
  constant ST_CRC : byte_t                       := x"54";
  constant ST_BUS : std_logic_vector(5 downto 0) := "010100"; -- x"50" + the response
  constant CRC_0  : crc_t                        := x"FFFF";

  -- s_hunt waiting for a FLAG; s_rx receiving a frame; s_bus the AXI transaction;
  -- s_tx sending the answer
  type state_t is (s_hunt, s_rx, s_bus, s_tx);

  -- The frame being received: its first byte (the command), the last 8 bytes after it.
  type rx_frame_t is record
    cmd     : byte_t;
    sh      : std_logic_vector(63 downto 0);
    n       : unsigned(3 downto 0);  -- bytes of the frame so far (saturates at 10)
    escaped : std_logic;             -- the last byte was ESC
    crc     : crc_t;                 -- CRC over the frame's bytes so far
    idle    : unsigned(19 downto 0); -- clocks since the frame's last byte
  end record rx_frame_t;

  -- The answer going out: byte k (0 the opening FLAG, then ST E1 E0 [D3..D0] C1 C0,
  -- then the closing FLAG), an escape pending, the CRC of the bytes sent.
  type tx_frame_t is record
    k        : unsigned(3 downto 0);
    escaping : std_logic; -- ESC sent, the byte xor x"20" is next
    crc      : crc_t;
  end record tx_frame_t;

  -- The AXI master's registered outputs (awaddr also the read address).
  type axil_m_t is record
    awaddr  : std_logic_vector(15 downto 0);
    awvalid : std_logic;
    wdata   : std_logic_vector(31 downto 0);
    wvalid  : std_logic;
    bready  : std_logic;
    arvalid : std_logic;
    rready  : std_logic;
  end record axil_m_t;

  -- CRC-16/CCITT-FALSE (polynomial x"1021", not reflected) of one more byte, MSB first.
  function crc_step (c : crc_t; b : byte_t) return crc_t is

    variable r : crc_t;

  begin

    r := c xor (b & x"00");

    for i in 0 to 7 loop

      if r(15) = '1' then
        r := (r(14 downto 0) & '0') xor x"1021";
      else
        r := r(14 downto 0) & '0';
      end if;

    end loop;

    return r;

  end function crc_step;

  signal state  : state_t    := s_hunt;
  signal rxf    : rx_frame_t := (cmd => (others => '0'), sh => (others => '0'),
                                 n => (others => '0'), escaped => '0', crc => CRC_0,
                                 idle => (others => '0'));
  signal txf    : tx_frame_t := (k => (others => '0'), escaping => '0', crc => CRC_0);
  signal axm    : axil_m_t   := (awaddr => (others => '0'), awvalid => '0',
                                 wdata => (others => '0'), wvalid => '0', bready => '0',
                                 arvalid => '0', rready => '0');
  signal is_wr  : std_logic  := '0';             -- the request served is a write
  signal echo   : crc_t      := (others => '0'); -- the request's C1 C0
  signal st     : byte_t     := x"50";
  signal drop_q : std_logic  := '0';

  -- the UART
  signal rx_data    : byte_t;
  signal rx_valid   : std_logic;
  signal rx_overrun : std_logic; -- unused: rx_valid is always taken
  signal frame_err  : std_logic;
  signal tx_data    : byte_t    := (others => '0');
  signal tx_valid   : std_logic := '0';
  signal tx_ready   : std_logic;

  signal rx_byte  : byte_t;               -- the received byte, unescaped
  signal is_wr_n  : boolean;              -- the frame closing is a write
  signal len_ok   : boolean;              -- a command with its length
  signal n_ans    : unsigned(3 downto 0); -- content bytes of the answer
  signal ans_byte : byte_t;               -- content byte k - 1
  signal special  : boolean;              -- ans_byte needs an escape

begin

  u_rx : entity work.uart_rx
    generic map (
      div => DIV
    )
    port map (
      clk           => clk,
      rst           => rst,
      rxd_i         => rxd_i,
      m_axis_tdata  => rx_data,
      m_axis_tvalid => rx_valid,
      m_axis_tready => '1',
      frame_err_o   => frame_err,
      overrun_o     => rx_overrun
    );

  u_tx : entity work.uart_tx
    generic map (
      div => DIV
    )
    port map (
      clk           => clk,
      rst           => rst,
      s_axis_tdata  => tx_data,
      s_axis_tvalid => tx_valid,
      s_axis_tready => tx_ready,
      txd_o         => txd_o
    );

  rx_byte <= rx_data xor x"20" when rxf.escaped = '1' else
             rx_data;
  is_wr_n <= rxf.cmd = CMD_W;
  len_ok  <= (rxf.cmd = CMD_R and rxf.n = 5) or (rxf.cmd = CMD_W and rxf.n = 9);

  -- the answer's bytes: ST E1 E0 [D3..D0] C1 C0 (D3..D0 shifted out of wdata)
  n_ans <= to_unsigned(5, 4) when is_wr = '1' else
           to_unsigned(9, 4);

  answer : process (all) is
  begin

    if txf.k >= 4 and txf.k < n_ans - 1 then
      ans_byte <= axm.wdata(31 downto 24);
    elsif txf.k = n_ans - 1 then
      ans_byte <= txf.crc(15 downto 8);
    elsif txf.k = n_ans then
      ans_byte <= txf.crc(7 downto 0);
    elsif txf.k = 1 then
      ans_byte <= st;
    elsif txf.k = 2 then
      ans_byte <= echo(15 downto 8);
    elsif txf.k = 3 then
      ans_byte <= echo(7 downto 0);
    else
      ans_byte <= x"00";
    end if;

  end process answer;

  special <= ans_byte = FLAG or ans_byte = ESC;

  fsm : process (clk) is
  begin

    if rising_edge(clk) then
      drop_q <= '0';

      -- (if, not case: Yosys reads GHDL 2.0's case as a latch, README.md)
      if state = s_hunt then
        if rx_valid = '1' and rx_data = FLAG then
          state       <= s_rx;
          rxf.n       <= (others => '0');
          rxf.escaped <= '0';
          rxf.crc     <= CRC_0;
          rxf.idle    <= (others => '0');
        end if;
      elsif state = s_rx then
        -- the answer starts afresh
        txf <= (k => (others => '0'), escaping => '0', crc => CRC_0);

        if rx_valid = '1' then
          rxf.idle <= (others => '0');

          if rx_data = FLAG then
            -- the frame closes (and the FLAG opens the next one)
            rxf.n       <= (others => '0');
            rxf.escaped <= '0';
            rxf.crc     <= CRC_0;

            if rxf.n /= 0 and rxf.escaped = '0' and len_ok then
              is_wr <= to_sl(is_wr_n);
              echo  <= rxf.sh(15 downto 0);

              if is_wr_n then
                axm.awaddr <= rxf.sh(63 downto 48);
                axm.wdata  <= rxf.sh(47 downto 16);
              else
                axm.awaddr <= rxf.sh(31 downto 16);
              end if;

              if rxf.crc = x"0000" then
                state       <= s_bus;
                axm.awvalid <= to_sl(is_wr_n);
                axm.wvalid  <= to_sl(is_wr_n);
                axm.bready  <= to_sl(is_wr_n);
                axm.arvalid <= to_sl(not is_wr_n);
                axm.rready  <= to_sl(not is_wr_n);
              else
                st        <= ST_CRC;
                axm.wdata <= (others => '0');
                state     <= s_tx;
              end if;
            elsif rxf.n /= 0 or rxf.escaped = '1' then
              drop_q <= '1';
            end if;
          elsif rx_data = ESC and rxf.escaped = '0' then
            rxf.escaped <= '1';
          else
            rxf.escaped <= '0';

            if rxf.n = 0 then
              rxf.cmd <= rx_byte;
            else
              rxf.sh <= rxf.sh(55 downto 0) & rx_byte;
            end if;

            if rxf.n /= 10 then
              rxf.n <= rxf.n + 1;
            end if;

            rxf.crc <= crc_step(rxf.crc, rx_byte);
          end if;
        elsif rxf.n /= 0 or rxf.escaped = '1' then
          if rxf.idle = TIMEOUT then
            state  <= s_hunt;
            drop_q <= '1';
          else
            rxf.idle <= rxf.idle + 1;
          end if;
        end if;

        if frame_err = '1' then
          state  <= s_hunt;
          drop_q <= to_sl(rxf.n /= 0 or rxf.escaped = '1');
        end if;
      elsif state = s_bus then
        if m_axil_awready = '1' then
          axm.awvalid <= '0';
        end if;

        if m_axil_wready = '1' then
          axm.wvalid <= '0';
        end if;

        if m_axil_arready = '1' then
          axm.arvalid <= '0';
        end if;

        if axm.bready = '1' and m_axil_bvalid = '1' then
          axm.bready <= '0';
          st         <= ST_BUS & m_axil_bresp;
          state      <= s_tx;
        end if;

        if axm.rready = '1' and m_axil_rvalid = '1' then
          axm.rready <= '0';
          st         <= ST_BUS & m_axil_rresp;
          axm.wdata  <= m_axil_rdata;
          state      <= s_tx;
        end if;
      else
        -- s_tx
        if tx_valid = '0' then
          tx_valid <= '1';

          if txf.k = 0 or txf.k > n_ans then
            tx_data <= FLAG;
          elsif txf.escaping = '1' then
            tx_data <= ans_byte xor x"20";
          elsif special then
            tx_data <= ESC;
          else
            tx_data <= ans_byte;
          end if;
        elsif tx_ready = '1' then
          tx_valid <= '0';

          if txf.k /= 0 and txf.k <= n_ans and special and txf.escaping = '0' then
            -- the escaped byte follows
            txf.escaping <= '1';
          else
            txf.escaping <= '0';

            if txf.k > n_ans then
              -- the closing FLAG went out
              state <= s_hunt;
            else
              txf.k <= txf.k + 1;

              if txf.k /= 0 and txf.k < n_ans - 1 then
                txf.crc <= crc_step(txf.crc, ans_byte);
              end if;

              if txf.k >= 4 and txf.k < n_ans - 1 then
                axm.wdata <= axm.wdata(23 downto 0) & x"00";
              end if;
            end if;
          end if;
        end if;
      end if;

      if rst = '1' then
        state       <= s_hunt;
        tx_valid    <= '0';
        axm.awvalid <= '0';
        axm.wvalid  <= '0';
        axm.bready  <= '0';
        axm.arvalid <= '0';
        axm.rready  <= '0';
        drop_q      <= '0';
      end if;
    end if;

  end process fsm;

  m_axil_awaddr  <= axm.awaddr;
  m_axil_awprot  <= (others => '0');
  m_axil_awvalid <= axm.awvalid;
  m_axil_wdata   <= axm.wdata;
  m_axil_wstrb   <= (others => '1');
  m_axil_wvalid  <= axm.wvalid;
  m_axil_bready  <= axm.bready;
  m_axil_araddr  <= axm.awaddr;
  m_axil_arprot  <= (others => '0');
  m_axil_arvalid <= axm.arvalid;
  m_axil_rready  <= axm.rready;
  frame_err_o    <= frame_err;
  drop_o         <= drop_q;

end architecture rtl;
