-- hbin: the bin b = phase >> 7 of the harmonic table (64 bins of 128 phase units), found
-- from the octant address's scale t before the phase table is read (VHDL edition of
-- rtl/hbin.v, which derives it; thresholds: hbin_pkg, generated with rtl/tables/hbin.vh
-- from sim/model/tables.py by scripts/gen_tables.py). Combinational.
--
-- In t's bucket bk = t >> 8 there are N(bk) thresholds below it and at most one inside,
-- reached when c = (t & 255) >= T(bk); with cnt = N(bk) + c the bin is
-- (16 oct2 + cnt) mod 64, or (16 oct2 - cnt) mod 64 when neg. The candidates b0 (c = 0)
-- and b1 (c = 1) need only the bucket: each is {oct2 - br, lo} with {br, lo} a constant
-- per bucket (no adder), so that rtl/vhdl/harmonic.vhd reads the table at both.
-- Formats: oct2_i u2 (base phase 2048 oct2); t_i u12; b0_o, b1_o, bin_o u6 bins.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.hbin_pkg.all;

entity hbin is
  generic (
    -- the thresholds: 1 the exact table's, 0 the paper's
    TABLE_EXACT : integer range 0 to 1 := 1
  );
  port (
    oct2_i : in    unsigned(1 downto 0);  -- base phase 2048 oct2
    neg_i  : in    std_logic;             -- phase = base - PH[j]
    t_i    : in    unsigned(11 downto 0); -- u12 the address's scale
    b0_o   : out   unsigned(5 downto 0);  -- u6 the bin if t does not reach its bucket's threshold
    b1_o   : out   unsigned(5 downto 0);  -- u6 the bin if it does
    c_o    : out   std_logic;             -- it does: bin = c ? b1 : b0
    bin_o  : out   unsigned(5 downto 0)   -- u6 the bin
  );
end entity hbin;

architecture rtl of hbin is

  -- {br, lo} of a candidate per bucket: the bin is {oct2 - br, lo}
  subtype offset_t is unsigned(4 downto 0);

  type offsets_t is array (0 to 15) of offset_t;

  -- The offsets of a sign's candidate: cnt = N + inc (mod 16), {0, cnt} (neg = 0) or
  -- {cnt /= 0, -cnt mod 16} = 32 - cnt (neg = 1, cnt /= 0).
  function offsets (n : hb_counts_t; neg : boolean; inc : natural) return offsets_t is

    variable cnt : natural range 0 to 15;
    variable r   : offsets_t;

  begin

    for b in r'range loop

      cnt := (n(b) + inc) mod 16;

      if neg and cnt /= 0 then
        r(b) := to_unsigned(32 - cnt, offset_t'length);
      else
        r(b) := to_unsigned(cnt, offset_t'length);
      end if;

    end loop;

    return r;

  end function offsets;

  -- The counts and the inside thresholds of TABLE_EXACT's table, for neg = 0 (lo) or 1.
  function pick_n (lo : boolean) return hb_counts_t is
  begin

    if TABLE_EXACT = 1 and lo then
      return HB_LO_EXACT_N;
    elsif TABLE_EXACT = 1 then
      return HB_HI_EXACT_N;
    elsif lo then
      return HB_LO_PAPER_N;
    end if;

    return HB_HI_PAPER_N;

  end function pick_n;

  function pick_t (lo : boolean) return hb_insides_t is
  begin

    if TABLE_EXACT = 1 and lo then
      return HB_LO_EXACT_T;
    elsif TABLE_EXACT = 1 then
      return HB_HI_EXACT_T;
    elsif lo then
      return HB_LO_PAPER_T;
    end if;

    return HB_HI_PAPER_T;

  end function pick_t;

  -- LO: neg = 0 (floor), HI: neg = 1 (ceil); 0, 1: the candidate's c
  constant OFF_LO0 : offsets_t    := offsets(pick_n(true), false, 0);
  constant OFF_LO1 : offsets_t    := offsets(pick_n(true), false, 1);
  constant OFF_HI0 : offsets_t    := offsets(pick_n(false), true, 0);
  constant OFF_HI1 : offsets_t    := offsets(pick_n(false), true, 1);
  constant T_LO    : hb_insides_t := pick_t(true);
  constant T_HI    : hb_insides_t := pick_t(false);

  -- the bin {oct2 - br, lo} of the offset {br, lo}
  function bin_of (oct2 : unsigned(1 downto 0); o : offset_t) return unsigned is
  begin

    return (oct2 - o(4 downto 4)) & o(3 downto 0);

  end function bin_of;

  signal bk : natural range 0 to 15;
  signal o0 : offset_t;
  signal o1 : offset_t;
  signal bt : natural range 0 to 256;
  signal c  : std_logic;
  signal b0 : unsigned(5 downto 0);
  signal b1 : unsigned(5 downto 0);

begin

  bk <= to_integer(t_i(11 downto 8));

  o0 <= OFF_HI0(bk) when neg_i = '1' else
        OFF_LO0(bk);
  o1 <= OFF_HI1(bk) when neg_i = '1' else
        OFF_LO1(bk);
  bt <= T_HI(bk) when neg_i = '1' else
        T_LO(bk);

  b0 <= bin_of(oct2_i, o0);
  b1 <= bin_of(oct2_i, o1);
  c  <= '1' when to_integer(t_i(7 downto 0)) >= bt else
        '0';

  b0_o  <= b0;
  b1_o  <= b1;
  c_o   <= c;
  bin_o <= b1 when c = '1' else
           b0;

end architecture rtl;
