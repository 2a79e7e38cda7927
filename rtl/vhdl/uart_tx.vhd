-- uart_tx: UART transmitter, 8N1, line idle high, DIV clocks per bit (VHDL edition of
-- rtl/uart_tx.v, which describes it in full).
--
-- A byte is taken on an edge with s_axis_tvalid and s_axis_tready; s_axis_tready is high
-- while the transmitter is idle (independent of tvalid). txd_o is a register: the start
-- bit begins after the taking edge, each bit lasts DIV clocks, and tready returns on the
-- edge that ends the stop bit, so back-to-back bytes take 10 DIV + 1 clocks each.
-- rst (sync): line idle, a byte in progress abandoned. Power-up values are those after
-- rst.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

entity uart_tx is
  generic (
    -- clocks per bit (f_clk / baud), 2 .. 65535
    DIV : integer range 2 to 65535 := 286
  );
  port (
    clk           : in    std_logic;
    rst           : in    std_logic; -- sync, active high
    s_axis_tdata  : in    std_logic_vector(7 downto 0);
    s_axis_tvalid : in    std_logic;
    s_axis_tready : out   std_logic;
    txd_o         : out   std_logic  -- serial output, idle high
  );
end entity uart_tx;

architecture rtl of uart_tx is

  constant FULL : unsigned(15 downto 0) := to_unsigned(DIV - 1, 16);

  signal busy  : std_logic                    := '0';
  signal cnt   : unsigned(15 downto 0)        := (others => '0');
  signal bit_n : unsigned(3 downto 0)         := (others => '0'); -- bits after this one
  signal shift : std_logic_vector(8 downto 0) := (others => '1'); -- {stop, data} to send
  signal txd_q : std_logic                    := '1';

begin

  regs : process (clk) is
  begin

    if rising_edge(clk) then
      if busy = '0' then
        if s_axis_tvalid = '1' then
          busy  <= '1';
          txd_q <= '0';                               -- start bit
          shift <= '1' & s_axis_tdata;
          bit_n <= to_unsigned(9, 4);
          cnt   <= FULL;
        end if;
      elsif cnt /= 0 then
        cnt <= cnt - 1;
      elsif bit_n /= 0 then
        txd_q <= shift(0);
        shift <= '1' & shift(8 downto 1);
        bit_n <= bit_n - 1;
        cnt   <= FULL;
      else
        busy <= '0';                                  -- stop bit done
      end if;

      if rst = '1' then
        busy  <= '0';
        txd_q <= '1';
      end if;
    end if;

  end process regs;

  s_axis_tready <= not busy;
  txd_o         <= txd_q;

end architecture rtl;
