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

  -- ---- rls_engine, estimator --------------------------------------------------------------

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
    variable r     : hex_table_t(0 to depth - 1)(width - 1 downto 0) := (others => (others => '0'));

  begin

    for i in r'range loop

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

  -- ---- rls_engine, estimator --------------------------------------------------------------

  function clog2 (n : positive) return natural is

    variable r : natural := 0;

  begin

    while 2 ** r < n loop

      r := r + 1;

    end loop;

    return r;

  end function clog2;

end package body finequad_util_pkg;
