-- uart_rx: UART receiver, 8N1, line idle high, DIV clocks per bit (VHDL edition of
-- rtl/uart_rx.v, which describes it in full).
--
-- rxd_i (asynchronous) passes two flip-flops; a low level starts a frame, checked again
-- half a bit later (a shorter glitch is no start bit); each data bit and the stop bit
-- are sampled once, mid-bit. m_axis_tdata/m_axis_tvalid after the edge that sampled
-- the stop bit, held until m_axis_tready; a byte that completes while the previous one
-- is held is dropped (overrun_o, one clock). A stop bit of 0 (framing error or break)
-- drops the byte (frame_err_o, one clock) and the receiver waits for the line to return
-- high. rst (sync): idle, nothing held. Power-up values are those after rst.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

entity uart_rx is
  generic (
    -- clocks per bit (f_clk / baud), 8 .. 65535
    DIV : integer range 8 to 65535 := 286
  );
  port (
    clk           : in    std_logic;
    rst           : in    std_logic; -- sync, active high
    rxd_i         : in    std_logic; -- serial input, asynchronous
    m_axis_tdata  : out   std_logic_vector(7 downto 0);
    m_axis_tvalid : out   std_logic;
    m_axis_tready : in    std_logic;
    frame_err_o   : out   std_logic; -- pulse: stop bit 0 (byte dropped)
    overrun_o     : out   std_logic  -- pulse: byte dropped, previous not taken
  );
end entity uart_rx;

architecture rtl of uart_rx is

  subtype cnt_t is unsigned(15 downto 0);

  -- clocks from one sample to the next, - 1; from the start edge to mid start bit, - 1
  constant FULL : cnt_t := to_unsigned(DIV - 1, 16);
  constant HALF : cnt_t := to_unsigned(DIV / 2 - 1, 16);

  -- S_BITS: the start check, 8 data bits, the stop bit; S_HIGH: after a framing error,
  -- waiting for the idle line
  type state_t is (s_idle, s_bits, s_high);

  signal sync    : std_logic_vector(1 downto 0) := "11";
  signal state   : state_t                      := s_idle;
  signal cnt     : cnt_t                        := (others => '0');
  signal bit_n   : unsigned(3 downto 0)         := (others => '0'); -- 0 start, 1..8, 9 stop
  signal shift   : std_logic_vector(7 downto 0) := (others => '0');
  signal data_q  : std_logic_vector(7 downto 0) := (others => '0');
  signal valid_q : std_logic                    := '0';
  signal ferr_q  : std_logic                    := '0';
  signal ovr_q   : std_logic                    := '0';
  signal rx      : std_logic;

begin

  rx <= sync(1);

  regs : process (clk) is
  begin

    if rising_edge(clk) then
      sync   <= sync(0) & rxd_i;
      ferr_q <= '0';
      ovr_q  <= '0';

      if valid_q = '1' and m_axis_tready = '1' then
        valid_q <= '0';
      end if;

      -- (if, not case: Yosys reads GHDL 2.0's case as a latch, README.md)
      if state = s_idle then
        if rx = '0' then
          state <= s_bits;
          cnt   <= HALF;
          bit_n <= (others => '0');
        end if;
      elsif state = s_bits then
        if cnt /= 0 then
          cnt <= cnt - 1;
        else
          cnt   <= FULL;
          bit_n <= bit_n + 1;

          if bit_n = 0 then
            -- a glitch, not a start bit
            if rx = '1' then
              state <= s_idle;
            end if;
          elsif bit_n /= 9 then
            shift <= rx & shift(7 downto 1);
          elsif rx = '0' then
            ferr_q <= '1';
            state  <= s_high;
          else
            state <= s_idle;

            if valid_q = '1' and m_axis_tready = '0' then
              ovr_q <= '1';
            else
              data_q  <= shift;
              valid_q <= '1';
            end if;
          end if;
        end if;
      else
        -- s_high
        if rx = '1' then
          state <= s_idle;
        end if;
      end if;

      if rst = '1' then
        state   <= s_idle;
        valid_q <= '0';
        ferr_q  <= '0';
        ovr_q   <= '0';
      end if;
    end if;

  end process regs;

  m_axis_tdata  <= data_q;
  m_axis_tvalid <= valid_q;
  frame_err_o   <= ferr_q;
  overrun_o     <= ovr_q;

end architecture rtl;
