-- finequad_util_pkg: the arithmetic the blocks of the VHDL edition share, and the
-- formats of the signals that pass between them (rtl/README.md, "Q formats and
-- latency"; notation: sI.F signed, uI.F unsigned, I integer bits, F fraction bits).
--
-- geu:        a >= b bit by bit (rtl/geu.vh: folds to a few LUTs for a constant b)
-- saturate:   a signed value clipped to fewer bits (the A/B backlog's s16)
-- to_sl:      a boolean as a std_logic
-- quadrant, to_ab: the x4 quadrature code, the A/B pins of a quadrant (rtl/counter.v's
--             edge decoder and rtl/abgen.v's pins use the same code)
-- read_hex:   a table of rtl/tables/*.hex (the files the Verilog's $readmemh reads,
--             written by scripts/gen_tables.py) read at elaboration, in simulation and
--             in synthesis (ghdl --synth turns the constant into a ROM)

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library std;
  use std.textio.all;

package finequad_util_pkg is

  -- Fine phase: u13, 8192 units per signal period.
  constant PHASE_W : positive := 13;

  subtype phase_t is unsigned(PHASE_W - 1 downto 0);

  -- Interpolation factor n: u9, 1..511 (INTERP).
  constant N_W : positive := 9;

  subtype n_t is unsigned(N_W - 1 downto 0);

  -- n * phase: u22 (rtl/lut.v); its bits 21..11 are floor(n phase / 2048).
  constant PROD_W : positive := PHASE_W + N_W;

  subtype prod_t is unsigned(PROD_W - 1 downto 0);

  -- The A/B quadrature pins of one quadrant; quadrant code q = pos mod 4:
  -- (A, B) = (1, 1) 0, (0, 1) 1, (0, 0) 2, (1, 0) 3. Counting up is
  -- (1,1) -> (0,1) -> (0,0) -> (1,0) -> (1,1): one pin changes per step.
  type ab_t is record
    a : std_logic;
    b : std_logic;
  end record ab_t;

  subtype quadrant_t is unsigned(1 downto 0);

  -- a >= b for unsigned a and b of any widths (the shorter zero-extended), formed bit
  -- by bit from the LSB, like rtl/geu.vh.
  function geu (a : unsigned; b : unsigned) return boolean;

  function geu (a : unsigned; b : natural) return boolean;

  function geu (a : natural; b : unsigned) return boolean;

  -- v saturated to w bits: v if it fits in s(w), else the s(w) limit of its sign.
  function saturate (v : signed; w : positive) return signed;

  function to_sl (b : boolean) return std_logic;

  -- The quadrant code {not B, A xor B} of the pins (a, b).
  function quadrant (a : std_logic; b : std_logic) return quadrant_t;

  -- The pins that show quadrant q.
  function to_ab (q : quadrant_t) return ab_t;

  -- A table of words (a ROM's contents): element width and depth set by its user.
  type hex_table_t is array (natural range <>) of std_logic_vector;

  -- The first `depth` lines of the $readmemh file `name` (one hexadecimal word per line,
  -- as scripts/gen_tables.py writes them), as words of `width` bits; lines past the end
  -- of a shorter file are 0. A missing file, a character that is not a hexadecimal
  -- digit or a word wider than `width` stops elaboration with the file (and line).
  impure function read_hex (name : string; depth : positive; width : positive) return hex_table_t;

  -- ---- vendor primitives ----------------------------------------------------------------

  -- Lattice ECP5 MULT18X18D (rtl/octant.v, rtl/lut.v with OPT_ECP5_MULT = 1): the ports
  -- and the generics the instances set. ghdl --synth leaves it a black box for the
  -- vendor's tools; a simulation binds it to an entity of that name (Lattice's ECP5
  -- library, or the stand-in cocotb_tests/sim_mult18x18d.vhd).
  -- (its pins grouped by bus, as the vendor's own declaration lists them)
  -- vsg_off port_026 component_017 component_008 component_012 port_010
  component MULT18X18D is
    generic (
      REG_INPUTA_CLK : string := "NONE";
      REG_INPUTA_CE  : string := "CE0";
      REG_INPUTA_RST : string := "RST0";
      REG_INPUTB_CLK : string := "NONE";
      REG_INPUTB_CE  : string := "CE0";
      REG_INPUTB_RST : string := "RST0";
      REG_OUTPUT_CLK : string := "NONE";
      REG_OUTPUT_CE  : string := "CE0";
      REG_OUTPUT_RST : string := "RST0"
    );
    port (
      A17, A16, A15, A14, A13, A12, A11, A10, A9, A8, A7, A6, A5, A4, A3,
      A2, A1, A0 : in    std_logic;
      B17, B16, B15, B14, B13, B12, B11, B10, B9, B8, B7, B6, B5, B4, B3,
      B2, B1, B0 : in    std_logic;
      C17, C16, C15, C14, C13, C12, C11, C10, C9, C8, C7, C6, C5, C4, C3,
      C2, C1, C0 : in    std_logic;
      SIGNEDA, SIGNEDB, SOURCEA, SOURCEB : in    std_logic;
      CLK3, CLK2, CLK1, CLK0, CE3, CE2, CE1, CE0, RST3, RST2, RST1, RST0 : in    std_logic;
      P35, P34, P33, P32, P31, P30, P29, P28, P27, P26, P25, P24, P23, P22,
      P21, P20, P19, P18, P17, P16, P15, P14, P13, P12, P11, P10, P9, P8,
      P7, P6, P5, P4, P3, P2, P1, P0 : out   std_logic
    );
  end component MULT18X18D;

  -- vsg_on port_026 component_017 component_008 component_012 port_010

  -- ---- asr -----------------------------------------------------------------------------------

  -- v >>> n, the arithmetic shift right (numeric_std's shift_right of a signed value),
  -- formed as a logical shift of v xor its sign, xor its sign: GHDL 2.0's --out=verilog
  -- writes shift_right of a signed value as $signed(v) >> n, a logical shift in Verilog,
  -- so its netlist would differ from the simulation.
  function asr (v : signed; n : natural) return signed;

  -- ---- clog2 ---------------------------------------------------------------------------------

  -- ceil(log2(n)) for n >= 1 (Verilog's $clog2): the bits of an index below n.
  function clog2 (n : positive) return natural;

end package finequad_util_pkg;

package body finequad_util_pkg is

  function geu (a : unsigned; b : unsigned) return boolean is

    constant W  : natural := maximum(a'length, b'length);
    variable aa : unsigned(W - 1 downto 0);
    variable bb : unsigned(W - 1 downto 0);
    variable r  : std_logic;

  begin

    aa := resize(a, W);
    bb := resize(b, W);
    r  := '1';

    -- r: a(i..0) >= b(i..0)
    for i in 0 to W - 1 loop

      r := (aa(i) and not bb(i)) or (not (aa(i) xor bb(i)) and r);

    end loop;

    return r = '1';

  end function geu;

  function geu (a : unsigned; b : natural) return boolean is
  begin

    return geu(a, to_unsigned(b, a'length));

  end function geu;

  function geu (a : natural; b : unsigned) return boolean is
  begin

    return geu(to_unsigned(a, b'length), b);

  end function geu;

  function saturate (v : signed; w : positive) return signed is

    alias    vv   : signed(v'length - 1 downto 0) is v;
    constant SIGN : std_logic := vv(vv'high);

  begin

    -- fits when every bit from the top down to bit w - 1 equals the sign
    if (vv(vv'high downto w - 1) xor (vv'high downto w - 1 => SIGN)) = 0 then
      return resize(vv, w);
    end if;

    return SIGN & (w - 2 downto 0 => not SIGN);

  end function saturate;

  function to_sl (b : boolean) return std_logic is
  begin

    if b then
      return '1';
    end if;

    return '0';

  end function to_sl;

  function quadrant (a : std_logic; b : std_logic) return quadrant_t is
  begin

    return (not b) & (a xor b);

  end function quadrant;

  function to_ab (q : quadrant_t) return ab_t is
  begin

    return (a => not (q(1) xor q(0)), b => not q(1));

  end function to_ab;

  impure function read_hex (name : string; depth : positive; width : positive) return hex_table_t is

    -- (file_open with a status is not synthesisable in GHDL 2.0: a missing file stops
    -- elaboration with GHDL's own message, naming the file)
    file     f     : text open read_mode is name;
    variable l     : line;
    variable word  : unsigned(width + 3 downto 0);
    variable digit : natural range 0 to 15;
    -- (descending: GHDL's synthesis addresses an ascending memory at its index's
    -- complement, which Yosys keeps as logic in front of the block RAM's address)
    variable r : hex_table_t(depth - 1 downto 0)(width - 1 downto 0) := (others => (others => '0'));

  begin

    for i in 0 to depth - 1 loop

      exit when endfile(f);
      readline(f, l);
      word := (others => '0');

      for c in l'range loop

        case l(c) is

          when '0' to '9' =>
            digit := character'pos(l(c)) - character'pos('0');

          when 'a' to 'f' =>
            digit := character'pos(l(c)) - character'pos('a') + 10;

          when 'A' to 'F' =>
            digit := character'pos(l(c)) - character'pos('A') + 10;

          when others =>
            report "read_hex: " & name & " line " & integer'image(i + 1)
                   & ": not a hexadecimal digit: '" & l(c) & "'"
              severity failure;

        end case;

        word := shift_left(word, 4) or to_unsigned(digit, word'length);
        assert word(word'high downto width) = 0
          report "read_hex: " & name & " line " & integer'image(i + 1)
                 & ": word wider than " & integer'image(width) & " bits"
          severity failure;

      end loop;

      r(i) := std_logic_vector(word(width - 1 downto 0));
      deallocate(l);

    end loop;

    return r;

  end function read_hex;

  -- ---- asr -----------------------------------------------------------------------------------

  function asr (v : signed; n : natural) return signed is

    variable sign : unsigned(v'length - 1 downto 0);

  begin

    sign := (others => v(v'left));
    return signed(shift_right(unsigned(v) xor sign, n) xor sign);

  end function asr;

  -- ---- clog2 ---------------------------------------------------------------------------------

  function clog2 (n : positive) return natural is

    variable r : natural := 0;

  begin

    while 2 ** r < n loop

      r := r + 1;

    end loop;

    return r;

  end function clog2;

end package body finequad_util_pkg;
