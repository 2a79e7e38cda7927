-- rls_engine: the microcoded fixed-point machine that runs the RLS update (Eqs. 5-7) and
-- the CORDIC-free extraction (Eq. 8) (VHDL edition of rtl/rls_engine.v, which describes
-- the pipeline, the register banks and the forwarding in full; the instruction set and
-- the programs are sim/model/program.py's, executed bit for bit by
-- sim/model/rls_engine.py).
--
-- LANES (1 or 2) lanes issue together from one ROM word of rls_program_<LANES>.hex, each
-- a 32x32 multiplier, a 64-bit accumulator and a rounding, saturating write-back. An
-- instruction of slot k of a program started on edge S is fetched on S+k, reads its
-- registers on S+k+1, takes its operands on S+k+2, multiplies on S+k+3, sums the product
-- on S+k+4, accumulates on S+k+5, shifts on S+k+6, rounds on S+k+7 (LANES = 1 writes the
-- register file there) and writes on S+k+8 (LANES = 2; END of lane 0: the program ends).
-- Results are forwarded from the round stage, so slot k + 6 may read slot k's register.
-- AXES > 1 (rtl/finequad_multi.v): every bank holds AXES register files, the axis
-- latched on start_i (axis_i); sat_o has a sticky bit per axis.
--
-- Formats: x1_i, x2_i s1.15 (X1, X2 = s2.30); kappa_i u8.8 (KAPPA s9.23); lambda_k_i
-- u5 (ONEL = 1 + 2**-k s9.23, 1 when freeze_i); dg_i s3 (GS1 = 2**-dg, GS2 = 2**-2dg,
-- s8.24); out_o the OUT registers {tr s12.4, e s3.13, c2, c12, c1 s4.12, m2, m1 s1.15}.
-- rst (sync) stops a program (its instructions in flight are dropped) and clears busy_o
-- and sat_o; the register file, out_o and valid_o keep their values (the estimator runs
-- a RESET program after rst).

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;

entity rls_engine is
  generic (
    -- folder of the tables (with trailing slash)
    TABLE_DIR : string := "rtl/tables/";
    -- ROM address width (the image holds 2**8 words)
    ROM_AW : integer range 8 to 16 := 8;
    -- lanes, 1 or 2: the ROM image rls_program_<LANES>.hex is scheduled for it
    LANES : integer range 1 to 2 := 1;
    -- axes sharing the engine (rtl/finequad_multi.v), 1..8; 1: axis_i unused
    AXES : integer range 1 to 8 := 1
  );
  port (
    clk        : in    std_logic;
    rst        : in    std_logic;                                      -- sync, active high
    start_i    : in    std_logic;                                      -- start a program, latch the inputs
    entry_i    : in    unsigned(ROM_AW - 1 downto 0);                  -- program entry address
    x1_i       : in    signed(15 downto 0);                            -- s1.15 u1 * 2**g
    x2_i       : in    signed(15 downto 0);                            -- s1.15 u2 * 2**g
    lambda_k_i : in    unsigned(4 downto 0);                           -- lambda = 1/(1 + 2**-k)
    freeze_i   : in    std_logic;                                      -- no forgetting (ONEL = 1)
    kappa_i    : in    unsigned(15 downto 0);                          -- u8.8 covariance reset value
    dg_i       : in    signed(2 downto 0);                             -- input gain change, -3..3
    axis_i     : in    unsigned(maximum(clog2(AXES), 1) - 1 downto 0); -- the program's axis
    busy_o     : out   std_logic;
    done_o     : out   std_logic;                                      -- the program ends on the coming edge
    valid_o    : out   std_logic;                                      -- with done_o: no invalid flag
    out_o      : out   std_logic_vector(16 * 7 - 1 downto 0);          -- {tr, e, c2, c12, c1, m2, m1}
    sat_o      : out   std_logic_vector(AXES - 1 downto 0)             -- sticky: a write saturated
  );
end entity rls_engine;

architecture rtl of rls_engine is

  -- ---- the instruction (sim/model/program.py encode / decode) -----------------------------
  constant IW       : positive := 36;                      -- one lane's instruction
  constant RW       : positive := IW * LANES;              -- a ROM word (lane 0 low)
  constant BW       : positive := 7 - LANES;               -- register index within a bank
  constant NP       : positive := 2 * LANES;               -- read ports: A and B per lane
  constant AXW      : positive := maximum(clog2(AXES), 1); -- axis index width
  constant RF_DEPTH : positive := AXES * 2 ** BW;          -- one bank's RAM
  constant ASYNC_RF : boolean  := LANES = 2;               -- distributed RAM banks
  constant LCH      : string   := integer'image(LANES);

  subtype op_t is unsigned(2 downto 0);

  constant OP_MAC   : op_t := "001";
  constant OP_NORMR : op_t := "010";
  constant OP_NORMS : op_t := "011";
  constant OP_SEEDR : op_t := "100";
  constant OP_SEEDS : op_t := "101";
  constant OP_CHK   : op_t := "110";
  constant OP_END   : op_t := "111";

  -- a register to write (LANES = 2: bank & index) or an OUT register (0..6)
  subtype dst_t is unsigned(5 downto 0);

  -- an operand: a register, or a special input when bit 6 is set
  subtype src_t is unsigned(6 downto 0);

  -- a register's value, a lane's operand (s32, its format the program's)
  subtype word_t is signed(31 downto 0);

  subtype dz_t is unsigned(4 downto 0);

  type instr_t is record
    op     : op_t;
    clr    : std_logic;            -- accumulate from 0
    neg    : std_logic;            -- subtract the product
    wb     : std_logic;            -- write the result back
    to_out : std_logic;            -- to OUT[dst] (s16) instead of the register file
    dyn    : unsigned(1 downto 0); -- the shift's dynamic part: 0, dz, dz / 2
    sh     : unsigned(5 downto 0); -- the write-back shift
    z      : std_logic;            -- which dz (two slots)
    a      : src_t;
    b      : src_t;
    dst    : dst_t;
  end record instr_t;

  constant NOP : instr_t :=
  (
    op     => "000",
    clr    => '0',
    neg    => '0',
    wb     => '0',
    to_out => '0',
    dyn    => "00",
    sh     => (others => '0'),
    z      => '0',
    a      => (others => '0'),
    b      => (others => '0'),
    dst    => (others => '0')
  );

  function decode (w : std_logic_vector) return instr_t is

    alias ww : std_logic_vector(IW - 1 downto 0) is w;

  begin

    return (op     => unsigned(ww(2 downto 0)),
            clr    => ww(3),
            neg    => ww(4),
            wb     => ww(5),
            to_out => ww(6),
            dyn    => unsigned(ww(8 downto 7)),
            sh     => unsigned(ww(14 downto 9)),
            z      => ww(15),
            a      => unsigned(ww(22 downto 16)),
            b      => unsigned(ww(29 downto 23)),
            dst    => unsigned(ww(35 downto 30)));

  end function decode;

  -- The write-back fields {dst, out, wb, sh, dyn} as one word (the LANES = 1 delay RAM's).
  subtype wbf_t is std_logic_vector(15 downto 0);

  function wb_fields (i : instr_t) return wbf_t is
  begin

    return std_logic_vector(i.dst) & i.to_out & i.wb & std_logic_vector(i.sh)
           & std_logic_vector(i.dyn);

  end function wb_fields;

  -- i with its write-back fields from f
  function with_wb (f : wbf_t; i : instr_t) return instr_t is

    variable r : instr_t;

  begin

    r        := i;
    r.dst    := unsigned(f(15 downto 10));
    r.to_out := f(9);
    r.wb     := f(8);
    r.sh     := unsigned(f(7 downto 2));
    r.dyn    := unsigned(f(1 downto 0));
    return r;

  end function with_wb;

  -- The lane (bank) that owns a register: its bit 5 with LANES = 2.
  function owner (r : src_t) return natural is
  begin

    if LANES = 2 and r(5) = '1' then
      return 1;
    end if;

    return 0;

  end function owner;

  -- ---- arithmetic -------------------------------------------------------------------------

  -- leading zeros of a byte
  function lzc8 (v : std_logic_vector(7 downto 0)) return unsigned is
  begin

    for i in 7 downto 1 loop

      if v(i) = '1' then
        return to_unsigned(7 - i, 3);
      end if;

    end loop;

    return "111";

  end function lzc8;

  -- leading zeros of 32 bits, v /= 0: a byte priority and the bytes' counts side by side
  function lzc32 (v : std_logic_vector(31 downto 0)) return unsigned is

    variable byte : std_logic_vector(7 downto 0);

  begin

    for k in 0 to 2 loop

      byte := v(31 - 8 * k downto 24 - 8 * k);

      if (or byte) = '1' then
        return to_unsigned(k, 2) & lzc8(byte);
      end if;

    end loop;

    return "11" & lzc8(v(7 downto 0));

  end function lzc32;

  -- A NORM's dz (u5): the left shift that puts A's MSB at bit 30 (NORMS: rounded down to
  -- even); 0 when A <= 0.
  function norm_dz (a : word_t; s : std_logic) return dz_t is

    variable nz : dz_t;

  begin

    nz := resize(lzc32(std_logic_vector(a(30 downto 0)) & '1'), 5);

    if a(31) = '1' or a(30 downto 0) = 0 then
      return "00000";
    elsif s = '1' then
      return nz(4 downto 1) & '0';
    end if;

    return nz;

  end function norm_dz;

  -- The seed table's address from A (s32) and its dz: m2 = (A << dz)(30 downto 23) in
  -- five levels, the widest first; '1' & m2(7 downto 1) for SEEDS (1/sqrt(m)), '0' &
  -- m2(6 downto 0) for SEEDR (1/m).
  function seed_addr (a : word_t; dz : dz_t; s : boolean) return unsigned is

    variable av  : std_logic_vector(31 downto 0);
    variable ms1 : std_logic_vector(22 downto 0);
    variable ms2 : std_logic_vector(14 downto 0);
    variable ms3 : std_logic_vector(10 downto 0);
    variable ms4 : std_logic_vector(8 downto 0);
    variable m2  : std_logic_vector(7 downto 0);

  begin

    av := std_logic_vector(a);
    -- bits 30..8, 30..16, 30..20, 30..22, 30..23 of A << dz
    ms1 := av(14 downto 0) & x"00" when dz(4) = '1' else av(30 downto 8);
    ms2 := ms1(14 downto 0) when dz(3) = '1' else ms1(22 downto 8);
    ms3 := ms2(10 downto 0) when dz(2) = '1' else ms2(14 downto 4);
    ms4 := ms3(8 downto 0) when dz(1) = '1' else ms3(10 downto 2);
    m2  := ms4(7 downto 0) when dz(0) = '1' else ms4(8 downto 1);

    if s then
      return unsigned('1' & m2(7 downto 1));
    end if;

    return unsigned('0' & m2(6 downto 0));

  end function seed_addr;

  -- the low 32 bits of a product of two partial operands (at most s17). Synthesis reads
  -- the numeric_std product only. Simulation takes the same bits from integer arithmetic:
  -- numeric_std's "*" is a loop of vector additions, and the four partial products of
  -- every engine step were a third of GHDL's time on a recording. With y = yh * 2**8 + yl
  -- (yh s9, yl u8) and a = x * yh, a = a1 * 2**8 + a0 (a0 = a mod 2**8):
  -- x * y = a1 * 2**16 + t, t = a0 * 2**8 + x * yl, every term within 26 bits.
  function mul32 (x : signed; y : signed) return word_t is

    constant XN : signed(x'length - 1 downto 0) := x;
    constant YN : signed(y'length - 1 downto 0) := y;
    variable p  : signed(x'length + y'length - 1 downto 0);
    variable a  : integer;
    variable t  : integer;
    variable lo : integer;

  begin

    -- pragma translate_off
    if x'length <= 17 and y'length <= 17 and y'length > 8 then
      a  := to_integer(XN) * to_integer(YN(y'length - 1 downto 8));
      t  := (a mod 256) * 256 + to_integer(XN) * to_integer(unsigned(YN(7 downto 0)));
      lo := t mod 65536;
      return signed(to_unsigned(((a - a mod 256) / 256 + (t - lo) / 65536) mod 65536, 16)
                    & to_unsigned(lo, 16));
    end if;

    -- pragma translate_on
    p := XN * YN;
    return p(31 downto 0);

  end function mul32;

  -- The product (s64) of the four partial products (s32): {hh, ll} + (hl + lh) << 16 as
  -- one carry-save step and one carry chain; complemented when neg (the +1 of -prod is
  -- the accumulate's carry in).
  function prod_sum (
    hh : word_t;
    hl : word_t;
    lh : word_t;
    ll : word_t;
    neg : std_logic
  ) return signed is

    variable pa   : unsigned(47 downto 0);
    variable pb   : unsigned(47 downto 0);
    variable pc   : unsigned(47 downto 0);
    variable cs_s : unsigned(47 downto 0);
    variable cs_c : unsigned(47 downto 0);

  begin

    pa   := unsigned(hh) & unsigned(ll(31 downto 16)); -- bits 63..16
    pb   := unsigned(resize(hl, 48));
    pc   := unsigned(resize(lh, 48));
    cs_s := pa xor pb xor pc;
    cs_c := ((pa(46 downto 0) and pb(46 downto 0)) or (pa(46 downto 0) and pc(46 downto 0))
             or (pb(46 downto 0) and pc(46 downto 0))) & '0';
    return signed((cs_s + cs_c) & unsigned(ll(15 downto 0))) xor (63 downto 0 => neg);

  end function prod_sum;

  -- The accumulate stage's sum (acc, prod: s64; seed: u1.15): a clear takes 0 for acc, a
  -- SEED adds the seed << 15. LANES = 2: a carry-select adder of 32-bit halves, the seed
  -- ORed in behind it; LANES = 1: one 64-bit chain, the seed through the clear's gate.
  function acc_next (
    acc : signed(63 downto 0);
    prod : signed(63 downto 0);
    neg : std_logic;
    clr : std_logic;
    sd : std_logic;
    seed : unsigned(15 downto 0)
  ) return signed is

    variable sv     : unsigned(63 downto 0);
    variable acc_a  : unsigned(63 downto 0);
    variable lo_sum : unsigned(32 downto 0);
    variable hi_sum : unsigned(31 downto 0);

  begin

    sv := (others => '0');

    if sd = '1' then
      sv(30 downto 15) := seed;
    end if;

    if LANES = 2 then
      acc_a  := unsigned(acc) when clr = '0' else (others => '0');
      lo_sum := ('0' & acc_a(31 downto 0)) + ('0' & unsigned(prod(31 downto 0))) + neg;
      hi_sum := acc_a(63 downto 32) + unsigned(prod(63 downto 32)) when lo_sum(32) = '0' else
                acc_a(63 downto 32) + unsigned(prod(63 downto 32)) + 1;
      return signed(hi_sum & (lo_sum(31 downto 0) or sv(31 downto 0)));
    end if;

    acc_a := unsigned(acc) when clr = '0' else sv;
    return signed(acc_a + unsigned(prod) + neg);

  end function acc_next;

  -- The write-back shift sh - dyn (u6 each), clamped to 0..63: dyn = dz (dyn 1), dz / 2
  -- (dyn 2) or 0.
  function wb_shift (sh : unsigned(5 downto 0); dyn : unsigned(1 downto 0); dz : dz_t)
    return unsigned is

    variable amt : unsigned(4 downto 0);
    variable raw : unsigned(7 downto 0);

  begin

    -- (if, not case: GHDL 2.0's Verilog writer drops a case's others, README.md)
    if dyn = "01" then
      amt := dz;
    elsif dyn = "10" then
      amt := '0' & dz(4 downto 1);
    else
      amt := "00000";
    end if;

    raw := resize(sh, 8) - amt;

    if raw(7) = '1' then
      return "000000";
    end if;

    return raw(5 downto 0);

  end function wb_shift;

  -- The shift stage's window t(32 downto 0) of t = {acc, 0} >>> s (66 bits), hi: t(65
  -- downto 33) are sign copies, sg: the sign (rtl/rls_engine.v, "shift, then round").
  type win_t is record
    t  : unsigned(32 downto 0);
    hi : std_logic;
    sg : std_logic;
  end record win_t;

  -- n copies of b
  function rep (b : std_logic; n : positive) return unsigned is
  begin

    return (n - 1 downto 0 => b);

  end function rep;

  -- Six levels, the widest first, each as wide as the later levels need; a level that
  -- does not shift drops bits out of the window's top, which must all be sign copies.
  function shift_win (acc : signed(63 downto 0); sh : unsigned(5 downto 0)) return win_t is

    variable a     : unsigned(63 downto 0);
    variable sg    : std_logic;
    variable sv1   : unsigned(63 downto 0);
    variable sv2   : unsigned(47 downto 0);
    variable sv3   : unsigned(39 downto 0);
    variable sv4   : unsigned(35 downto 0);
    variable sv5   : unsigned(33 downto 0);
    variable sv6   : unsigned(32 downto 0);
    variable sdrop : unsigned(30 downto 0);
    variable skeep : unsigned(30 downto 0);

  begin

    a     := unsigned(acc);
    sg    := a(63);
    sv1   := (30 downto 0 => sg) & a(63 downto 31) when sh(5) = '1' else a(62 downto 0) & '0';
    sv2   := sv1(63 downto 16) when sh(4) = '1' else sv1(47 downto 0);
    sv3   := sv2(47 downto 8) when sh(3) = '1' else sv2(39 downto 0);
    sv4   := sv3(39 downto 4) when sh(2) = '1' else sv3(35 downto 0);
    sv5   := sv4(35 downto 2) when sh(1) = '1' else sv4(33 downto 0);
    sv6   := sv5(33 downto 1) when sh(0) = '1' else sv5(32 downto 0);
    sdrop := sv1(63 downto 48) & sv2(47 downto 40) & sv3(39 downto 36) & sv4(35 downto 34)
             & sv5(33);
    skeep := rep(sh(4), 16) & rep(sh(3), 8) & rep(sh(2), 4) & rep(sh(1), 2) & sh(0);
    return (t => sv6, hi => and (skeep or not (sdrop xor (30 downto 0 => sg))), sg => sg);

  end function shift_win;

  -- The round stage: r = (t + 1) >> 1, saturated to s32 (a register) and s16 (OUT);
  -- fit: it fits.
  type rnd_t is record
    fit32 : std_logic;
    fit16 : std_logic;
    r32   : word_t;
    r16   : signed(15 downto 0);
  end record rnd_t;

  function rnd_stage (w : win_t) return rnd_t is

    variable t_inc : unsigned(32 downto 0);
    variable up32  : std_logic;
    variable up17  : std_logic;
    variable r     : rnd_t;

  begin

    t_inc := w.t + 1;
    up32  := w.hi and to_sl(w.t(32) = w.sg);                             -- t(65 downto 32)
    up17  := w.hi and to_sl(w.t(32 downto 17) = (32 downto 17 => w.sg)); -- t(65 downto 17)

    -- a carry out of t(31 downto 0) (t(16 downto 0)) moves the sign copies up by one
    if (and w.t(31 downto 0)) = '1' then
      r.fit32 := w.sg and w.hi;
    else
      r.fit32 := up32;
    end if;

    if (and w.t(15 downto 0)) = '1' then
      r.fit16 := w.sg and up17;
    else
      r.fit16 := up17 and to_sl(w.t(16) = w.sg);
    end if;

    if r.fit32 = '1' then
      r.r32 := signed(t_inc(32 downto 1));
    else
      r.r32 := w.sg & (30 downto 0 => not w.sg);
    end if;

    if r.fit16 = '1' then
      r.r16 := signed(t_inc(16 downto 1));
    else
      r.r16 := w.sg & (14 downto 0 => not w.sg);
    end if;

    return r;

  end function rnd_stage;

  -- ---- the special inputs, latched on start_i ------------------------------------------
  -- ONEL = 2**23 + 2**(23 - k) (2**23 when frozen), GS1 = 2**(24 - dg), GS2 = 2**(24 -
  -- 2 dg): decoded one bit at a time (rtl/rls_engine.v: a shifter was a critical path).
  function onel_dec (k : unsigned(4 downto 0); frz : std_logic) return word_t is

    variable r : word_t;

  begin

    for bi in r'range loop

      r(bi) := to_sl(bi = 23 or (frz = '0' and to_integer(k) = 23 - bi));

    end loop;

    return r;

  end function onel_dec;

  -- sq: GS2
  function gs_dec (dg : signed(2 downto 0); sq : boolean) return word_t is

    variable r : word_t;
    variable e : integer;

  begin

    e := to_integer(dg);

    if sq then
      e := 2 * e;
    end if;

    for bi in r'range loop

      r(bi) := to_sl(e = 24 - bi);

    end loop;

    return r;

  end function gs_dec;

  -- (separate registers, not a record: GHDL 2.0's --out=verilog writes a non-zero
  -- initial value wider than 64 bits as a string)
  signal sp_x1    : signed(15 downto 0)   := (others => '0'); -- s1.15
  signal sp_x2    : signed(15 downto 0)   := (others => '0'); -- s1.15
  signal sp_kappa : unsigned(15 downto 0) := (others => '0'); -- u8.8
  signal onel     : word_t                := x"00800000";     -- s9.23
  signal gs1      : word_t                := x"01000000";     -- s8.24
  signal gs2      : word_t                := x"01000000";     -- s8.24

  signal axis_q : unsigned(AXW - 1 downto 0) := (others => '0'); -- the running program's

  signal x1_30 : word_t; -- s2.30
  signal x2_30 : word_t;
  signal kap   : word_t; -- s9.23

  -- ---- memories ---------------------------------------------------------------------------
  constant ROM : hex_table_t := read_hex(TABLE_DIR & "rls_program_" & LCH & ".hex",
                                         2 ** ROM_AW, RW);
  -- 0..127: 1/m seeds, 128..255: 1/sqrt(m) (u1.15)
  constant SEEDS : hex_table_t := read_hex(TABLE_DIR & "seeds.hex", 256, 16);

  type rf_t is array (natural range <>) of word_t;

  -- A bank's register file: its image once per axis.
  impure function rf_image (name : string) return rf_t is

    constant IMG : hex_table_t := read_hex(name, 2 ** BW, 32);
    variable r   : rf_t(RF_DEPTH - 1 downto 0);

  begin

    for i in r'range loop

      r(i) := signed(IMG(i mod 2 ** BW));

    end loop;

    return r;

  end function rf_image;

  -- A register's address in a bank's RAM: the axis above the index.
  function rf_addr (axis : unsigned; r : unsigned) return natural is
  begin

    if AXES > 1 then
      return to_integer(axis) * 2 ** BW + to_integer(r(BW - 1 downto 0));
    end if;

    return to_integer(r(BW - 1 downto 0));

  end function rf_addr;

  -- ---- fetch and the valid bits ----------------------------------------------------------
  signal pc_q  : unsigned(ROM_AW - 1 downto 0) := (others => '0');
  signal run_q : std_logic                     := '0';
  -- (no initialiser on a block RAM's output register; every use is qualified by v0..v6)
  signal word_q : std_logic_vector(RW - 1 downto 0);
  signal v0     : std_logic := '0'; -- word_q to execute
  signal v1     : std_logic := '0';
  signal v2     : std_logic := '0';
  signal v3     : std_logic := '0';
  signal v4     : std_logic := '0';
  signal v5     : std_logic := '0';
  signal v5b    : std_logic := '0';
  signal v6     : std_logic := '0';
  signal end1   : std_logic;        -- the read stage holds END

  -- ---- what a lane shares with the others and the register file ---------------------------
  type lane_io_t is record
    end1    : std_logic;           -- the read stage holds END
    end6    : std_logic;           -- the write stage holds END
    dz0_we  : std_logic;           -- a NORM in the multiply stage writes dz0 / dz1
    dz1_we  : std_logic;
    dzn_a   : word_t;              -- the multiply stage's operand A
    dzn_s   : std_logic;           -- it is a NORMS (even dz)
    win     : win_t;               -- the round stage's input
    wr5     : std_logic;           -- the round stage holds a register write
    wd5     : dst_t;               -- its register
    fw6     : std_logic;           -- res_q holds a register write
    fd6     : dst_t;               -- its register
    res6    : word_t;              -- res_q, forwarded
    wr_en   : std_logic;           -- the register file write on the coming edge
    wr_dst  : dst_t;
    wr_res  : word_t;
    out_we  : std_logic;           -- an OUT write on the coming edge
    out_dst : unsigned(2 downto 0);
    out_res : signed(15 downto 0); -- LANES = 2: its value
    inval   : std_logic;           -- an invalid flag raised
  end record lane_io_t;

  type lane_io_array_t is array (0 to LANES - 1) of lane_io_t;

  signal lane_io : lane_io_array_t;

  -- register file read addresses of port p = 2 l + (0: A, 1: B) of lane l, from the
  -- fetched word (LANES = 1) and from the read stage (LANES = 2)
  type port_addr_t is array (0 to NP - 1) of dst_t;

  signal rd_addr0 : port_addr_t;
  signal rd_addr1 : port_addr_t;

  -- the read data of port p of bank b: rd_all(b)(p)
  type port_data_t is array (0 to NP - 1) of word_t;

  type bank_data_t is array (0 to LANES - 1) of port_data_t;

  signal rd_all : bank_data_t;

  -- ---- the state the lanes share ---------------------------------------------------------
  type outs_t is array (0 to 6) of signed(15 downto 0);

  signal dz0     : dz_t                                := (others => '0');
  signal dz1     : dz_t                                := (others => '0');
  signal inval_q : std_logic                           := '0';
  signal busy    : std_logic                           := '0';
  signal outs    : outs_t                              := (others => (others => '0'));
  signal sat     : std_logic_vector(AXES - 1 downto 0) := (others => '0');
  signal done    : std_logic;

begin

  -- ---- the special inputs ------------------------------------------------------------------
  latch : process (clk) is
  begin

    if rising_edge(clk) then
      if start_i = '1' then
        sp_x1    <= x1_i;
        sp_x2    <= x2_i;
        sp_kappa <= kappa_i;
        onel     <= onel_dec(lambda_k_i, freeze_i);
        gs1      <= gs_dec(dg_i, false);
        gs2      <= gs_dec(dg_i, true);
        axis_q   <= resize(axis_i, AXW);
      end if;
    end if;

  end process latch;

  x1_30 <= resize(sp_x1 & to_signed(0, 15), 32);
  x2_30 <= resize(sp_x2 & to_signed(0, 15), 32);
  kap   <= signed(resize(sp_kappa & to_unsigned(0, 15), 32));

  -- ---- fetch: from start_i until END (lane 0) reaches the read stage; the word fetched
  -- behind END is squashed on its way into the read stage, the next one by v0 ----------
  end1 <= v1 and lane_io(0).end1;

  fetch : process (clk) is

    variable addr : unsigned(ROM_AW - 1 downto 0);

  begin

    if rising_edge(clk) then
      addr := entry_i when start_i = '1' else pc_q;

      word_q <= ROM(to_integer(addr));
      pc_q   <= addr + 1;
      v0     <= start_i or (run_q and not end1);
      v1     <= v0 and not end1;

      if start_i = '1' then
        run_q <= '1';
      elsif end1 = '1' then
        run_q <= '0';
      end if;

      -- the later stages' valid bits (rst drops the instructions in flight)
      v2  <= v1;
      v3  <= v2;
      v4  <= v3;
      v5  <= v4;
      v5b <= v5;
      v6  <= v5b;

      if rst = '1' then
        run_q <= '0';
        v0    <= '0';
        v1    <= '0';
        v2    <= '0';
        v3    <= '0';
        v4    <= '0';
        v5    <= '0';
        v5b   <= '0';
        v6    <= '0';
      end if;
    end if;

  end process fetch;

  -- ---- the register file: bank b (written by lane b) in NP copies, one per read port.
  -- LANES = 1: block RAM, written on the round edge, read on the read edge; LANES = 2:
  -- written on the write edge, read asynchronously in the operand stage ------------------

  g_bank : for b in 0 to LANES - 1 generate

    g_port : for p in 0 to NP - 1 generate

      constant IMAGE : string := TABLE_DIR & "rls_regfile_" & LCH & "_" & integer'image(b) & ".hex";

      -- (descending, as every memory here: GHDL addresses an ascending one at the
      -- index's complement, logic in front of the RAM, README.md)
      signal rf_mem : rf_t(RF_DEPTH - 1 downto 0) := rf_image(IMAGE);

      -- (as in rtl/rls_engine.v: the forwarding covers a read of the register being
      -- written, so Yosys adds no logic for it; ../../scripts/ghdl_netlist.py writes the
      -- attribute onto the netlist, whose writer drops it)
      attribute no_rw_check : boolean;
      attribute no_rw_check of rf_mem : signal is true;

    begin

      rf_write : process (clk) is
      begin

        if rising_edge(clk) then
          if lane_io(b).wr_en = '1' then
            rf_mem(rf_addr(axis_q, lane_io(b).wr_dst)) <= lane_io(b).wr_res;
          end if;
        end if;

      end process rf_write;

      g_sync : if not ASYNC_RF generate

        -- (no initialiser: a block RAM's output register)
        signal rd_q : word_t;

      begin

        rf_read : process (clk) is
        begin

          if rising_edge(clk) then
            rd_q <= rf_mem(rf_addr(axis_q, rd_addr0(p)));
          end if;

        end process rf_read;

        rd_all(b)(p) <= rd_q;

      end generate g_sync;

      g_async : if ASYNC_RF generate
        rd_all(b)(p) <= rf_mem(rf_addr(axis_q, rd_addr1(p)));
      end generate g_async;

    end generate g_port;

  end generate g_bank;

  -- ---- the lanes ------------------------------------------------------------------------------

  g_lane : for l in 0 to LANES - 1 generate

    signal ins0 : instr_t;                                      -- the fetched instruction
    signal i1   : instr_t := NOP;                               -- read
    signal i2   : instr_t := NOP;                               -- operands
    signal i3   : instr_t := NOP;                               -- multiply
    signal i4   : instr_t := NOP;                               -- product
    signal i5   : instr_t := NOP;                               -- accumulate
    signal i5b  : instr_t := NOP;                               -- shift
    signal i6   : instr_t := NOP;                               -- round

    -- read: the operand's register is forwarded from the round stage
    signal ha6 : std_logic;
    signal hb6 : std_logic;

    -- operands
    signal av    : word_t;
    signal bv    : word_t;
    signal opa_q : word_t := (others => '0');
    signal opb_q : word_t := (others => '0');
    signal norm2 : std_logic;

    -- multiply: four 16x16 partial products (s32), the seed table's address
    signal pp_ll : word_t                := (others => '0');
    signal pp_lh : word_t                := (others => '0');
    signal pp_hl : word_t                := (others => '0');
    signal pp_hh : word_t                := (others => '0');
    signal sa3_q : unsigned(7 downto 0)  := (others => '0');
    signal dz2   : dz_t;
    signal dz3   : dz_t                  := (others => '0');

    -- product: the product (s64; complemented for a subtraction), the seed (u1.15)
    signal seed3   : boolean;
    signal neg3    : std_logic;
    signal prod_q  : signed(63 downto 0)   := (others => '0');
    signal seed4_q : unsigned(15 downto 0);                    -- (block RAM: no initialiser)
    signal en4     : std_logic             := '0';
    signal neg4    : std_logic             := '0';
    signal clr4    : std_logic             := '0';
    signal sd4     : std_logic             := '0';
    signal dz4     : dz_t                  := (others => '0');
    signal late4   : wbf_t;                                     -- i4's write-back fields

    -- accumulate (s64), the write-back shift
    signal acc  : signed(63 downto 0)  := (others => '0');
    signal sh_q : unsigned(5 downto 0) := (others => '0');

    -- shift, round
    signal win_q  : win_t     := (t => (others => '0'), hi => '0', sg => '0');
    signal res_q  : word_t    := (others => '0');
    signal fw6    : std_logic := '0';
    signal fd6    : dst_t     := (others => '0');
    signal wr5    : std_logic;
    signal wr_en  : std_logic;
    signal wr_dst : dst_t;
    signal wr_res : word_t;
    signal wb6    : std_logic;

    -- write
    signal out_we  : std_logic;
    signal out_dst : unsigned(2 downto 0);
    signal out_res : signed(15 downto 0);
    signal inv16   : std_logic;                                 -- an OUT value saturated
    signal inval   : std_logic;

  begin

    ins0 <= decode(word_q(IW * (l + 1) - 1 downto IW * l));

    rd_addr0(2 * l)     <= ins0.a(5 downto 0);
    rd_addr0(2 * l + 1) <= ins0.b(5 downto 0);
    rd_addr1(2 * l)     <= i1.a(5 downto 0);
    rd_addr1(2 * l + 1) <= i1.b(5 downto 0);

    read_stage : process (clk) is
    begin

      if rising_edge(clk) then
        i1 <= ins0;
      end if;

    end process read_stage;

    -- The forwarding decisions: LANES = 1 beside the block RAM's read (from the fetched
    -- instruction and the shift stage's write, registered), LANES = 2 in the operand stage
    -- (from the read stage's instruction and the round stage's write).

    g_hit0 : if not ASYNC_RF generate

      signal ha6_q : std_logic := '0';
      signal hb6_q : std_logic := '0';

    begin

      hit_reg : process (clk) is

        variable oa : natural range 0 to LANES - 1;
        variable ob : natural range 0 to LANES - 1;

      begin

        if rising_edge(clk) then
          oa := owner(ins0.a);
          ob := owner(ins0.b);

          if v0 = '1' then
            ha6_q <= not ins0.a(6) and lane_io(oa).wr5 and to_sl(lane_io(oa).wd5 = ins0.a(5 downto 0));
            hb6_q <= not ins0.b(6) and lane_io(ob).wr5 and to_sl(lane_io(ob).wd5 = ins0.b(5 downto 0));
          end if;
        end if;

      end process hit_reg;

      ha6 <= ha6_q;
      hb6 <= hb6_q;

    end generate g_hit0;

    g_hit1 : if ASYNC_RF generate
      ha6 <= not i1.a(6) and lane_io(owner(i1.a)).fw6
             and to_sl(lane_io(owner(i1.a)).fd6 = i1.a(5 downto 0));
      hb6 <= not i1.b(6) and lane_io(owner(i1.b)).fw6
             and to_sl(lane_io(owner(i1.b)).fd6 = i1.b(5 downto 0));
    end generate g_hit1;

    -- ---- operands: a register of bank o from the RAM, or forwarded from lane o's round
    -- stage; a special input. The RAM's data pass one multiplexer.
    operand_sel : process (all) is

      variable oth_a : word_t;
      variable oth_b : word_t;

    begin

      if i1.a(6) = '0' then
        oth_a := lane_io(owner(i1.a)).res6;
      elsif i1.a(0) = '1' then
        oth_a := x2_30;
      else
        oth_a := x1_30;
      end if;

      if i1.b(6) = '0' then
        oth_b := lane_io(owner(i1.b)).res6;
      -- (if, not case: GHDL 2.0's Verilog writer drops a case's others, README.md)
      elsif i1.b(2 downto 0) = "000" then
        oth_b := x1_30;
      elsif i1.b(2 downto 0) = "001" then
        oth_b := x2_30;
      elsif i1.b(2 downto 0) = "010" then
        oth_b := onel;
      elsif i1.b(2 downto 0) = "011" then
        oth_b := kap;
      elsif i1.b(2 downto 0) = "100" then
        oth_b := gs1;
      elsif i1.b(2 downto 0) = "101" then
        oth_b := gs2;
      else
        oth_b := (others => '0');
      end if;

      if i1.a(6) = '0' and ha6 = '0' then
        av <= rd_all(owner(i1.a))(2 * l);
      else
        av <= oth_a;
      end if;

      if i1.b(6) = '0' and hb6 = '0' then
        bv <= rd_all(owner(i1.b))(2 * l + 1);
      else
        bv <= oth_b;
      end if;

    end process operand_sel;

    operand_reg : process (clk) is
    begin

      if rising_edge(clk) then
        opa_q <= av;
        opb_q <= bv;
        i2    <= i1;
      end if;

    end process operand_reg;

    -- ---- multiply: the partial products of the low halves as unsigned (s17), loaded for a
    -- valid instruction only (Yosys then registers both ends of the DSP block); NORM and
    -- CHK test A here, a NORM's dz is written on this edge (the common process below) ----
    norm2 <= v2 and to_sl(i2.op = OP_NORMR or i2.op = OP_NORMS);
    dz2   <= dz1 when i2.z = '1' else
             dz0;

    multiply : process (clk) is
    begin

      if rising_edge(clk) then
        if v2 = '1' then
          pp_ll <= mul32('0' & opa_q(15 downto 0), '0' & opb_q(15 downto 0));
          pp_lh <= mul32('0' & opa_q(15 downto 0), opb_q(31 downto 16));
          pp_hl <= mul32(opa_q(31 downto 16), '0' & opb_q(15 downto 0));
          pp_hh <= mul32(opa_q(31 downto 16), opb_q(31 downto 16));
          sa3_q <= seed_addr(opa_q, dz2, i2.op = OP_SEEDS);
        end if;

        dz3 <= dz2;
        i3  <= i2;
      end if;

    end process multiply;

    -- ---- product: the sum of the partial products (negated for a subtraction), the seed
    -- table's read, the accumulate's controls ------------------------------------------------
    seed3 <= i3.op = OP_SEEDR or i3.op = OP_SEEDS;
    neg3  <= i3.neg and not to_sl(seed3);

    product : process (clk) is
    begin

      if rising_edge(clk) then
        if v3 = '1' then
          prod_q <= (others => '0') when seed3 else prod_sum(pp_hh, pp_hl, pp_lh, pp_ll, neg3);
        end if;

        seed4_q <= unsigned(SEEDS(to_integer(sa3_q)));
        en4     <= v3 and to_sl(i3.op = OP_MAC or seed3);
        neg4    <= neg3;
        clr4    <= i3.clr or to_sl(seed3);
        sd4     <= to_sl(seed3);
        i4      <= i3;
        dz4     <= dz3;

        if rst = '1' then
          en4 <= '0';
        end if;
      end if;

    end process product;

    -- The write-back fields in the product stage: LANES = 1 (the iCE40) through a 4-deep
    -- block RAM written with the read stage's instruction and read three edges later (its
    -- output register is the stage's) instead of three pipeline registers; LANES = 2 i4's.

    g_late_ram : if LANES = 1 generate

      type late_mem_t is array (3 downto 0) of wbf_t;

      signal late_mem : late_mem_t;

      -- (block RAM as in rtl/rls_engine.v: Yosys maps so small a memory to flip-flops
      -- unless told; never read as written. Written onto the netlist by
      -- ../../scripts/ghdl_netlist.py: GHDL's writer drops attributes)
      attribute ram_style   : string;
      attribute no_rw_check : boolean;
      attribute ram_style of late_mem   : signal is "block";
      attribute no_rw_check of late_mem : signal is true;
      signal late_wa : unsigned(1 downto 0) := "00";
      signal late_q  : wbf_t;

    begin

      late_ram : process (clk) is
      begin

        if rising_edge(clk) then
          -- written on the read edge S+k+1, read on S+k+4 (late_wa + 1 = late_wa - 3)
          late_mem(to_integer(late_wa)) <= wb_fields(ins0);
          late_q                        <= late_mem(to_integer(late_wa + 1));
          late_wa                       <= late_wa + 1;
        end if;

      end process late_ram;

      late4 <= late_q;

    end generate g_late_ram;

    g_late_ff : if LANES = 2 generate
      late4 <= wb_fields(i4);
    end generate g_late_ff;

    -- ---- accumulate; the write-back shift sh - dyn ----------------------------------------
    accumulate : process (clk) is
    begin

      if rising_edge(clk) then
        if en4 = '1' then
          acc <= acc_next(acc, prod_q, neg4, clr4, sd4, seed4_q);
        end if;

        if v4 = '1' then
          sh_q <= wb_shift(unsigned(late4(7 downto 2)), unsigned(late4(1 downto 0)), dz4);
          i5   <= with_wb(late4, i4);
        end if;
      end if;

    end process accumulate;

    -- ---- shift, then round and saturate: rnd_shr(v, s) = ((v << 1 >>> s) + 1) >> 1 ------
    shift_round : process (clk) is
    begin

      if rising_edge(clk) then
        if v5 = '1' then
          win_q <= shift_win(acc, sh_q);
          i5b   <= i5;
        end if;

        if v5b = '1' then
          res_q <= rnd_stage(win_q).r32;
          i6    <= i5b;
        end if;

        fw6 <= wr5;
        fd6 <= i5b.dst;

        if rst = '1' then
          fw6 <= '0';
        end if;
      end if;

    end process shift_round;

    wr5 <= v5b and i5b.wb and not i5b.to_out;

    -- ---- write: the register file on the round edge (LANES = 1, the round stage's value)
    -- or on the write edge (LANES = 2, res_q); OUT likewise (LANES = 2 from a register of
    -- the 16-bit value: a shorter path behind the round stage's tests) -------------------
    wb6    <= v6 and i6.wb;
    wr_en  <= (wb6 and not i6.to_out) when ASYNC_RF else
              wr5;
    wr_dst <= i6.dst when ASYNC_RF else
              i5b.dst;
    wr_res <= res_q when ASYNC_RF else
              rnd_stage(win_q).r32;

    g_out5 : if LANES = 1 generate
      out_we  <= v5b and i5b.wb and i5b.to_out;
      out_dst <= i5b.dst(2 downto 0);
      out_res <= (others => '0');
      inv16   <= '0';
    end generate g_out5;

    g_out6 : if LANES = 2 generate

      signal res16     : signed(15 downto 0) := (others => '0');
      signal res16_sat : std_logic           := '0';

    begin

      round16 : process (clk) is
      begin

        if rising_edge(clk) then
          if v5b = '1' then
            res16     <= rnd_stage(win_q).r16;
            res16_sat <= not rnd_stage(win_q).fit16;
          end if;
        end if;

      end process round16;

      out_we  <= wb6 and i6.to_out;
      out_dst <= i6.dst(2 downto 0);
      out_res <= res16;
      inv16   <= wb6 and i6.to_out and res16_sat;

    end generate g_out6;

    -- a NORM or CHK on A <= 0, or an OUT value saturated (LANES = 2)
    inval <= (v2 and to_sl(i2.op = OP_NORMR or i2.op = OP_NORMS or i2.op = OP_CHK)
              and (opa_q(31) or not (or opa_q(30 downto 0)))) or inv16;

    lane_io(l) <=
    (
      end1    => to_sl(i1.op = OP_END),
      end6    => to_sl(i6.op = OP_END),
      dz0_we  => norm2 and not i2.z,
      dz1_we  => norm2 and i2.z,
      dzn_a   => opa_q,
      dzn_s   => to_sl(i2.op = OP_NORMS),
      win     => win_q,
      wr5     => wr5,
      wd5     => i5b.dst,
      fw6     => fw6,
      fd6     => fd6,
      res6    => res_q,
      wr_en   => wr_en,
      wr_dst  => wr_dst,
      wr_res  => wr_res,
      out_we  => out_we,
      out_dst => out_dst,
      out_res => out_res,
      inval   => inval
    );

  end generate g_lane;

  -- ---- dz, the flags and the OUT registers (written by any lane; never two on one slot) ----
  common : process (clk) is

    variable r : rnd_t;

  begin

    if rising_edge(clk) then

      for li in 0 to LANES - 1 loop

        r := rnd_stage(lane_io(li).win);

        if lane_io(li).dz0_we = '1' then
          dz0 <= norm_dz(lane_io(li).dzn_a, lane_io(li).dzn_s);
        end if;

        if lane_io(li).dz1_we = '1' then
          dz1 <= norm_dz(lane_io(li).dzn_a, lane_io(li).dzn_s);
        end if;

        -- OUT: LANES = 1 the round stage's 16-bit value, LANES = 2 its register
        -- (a loop of constant indices, not outs(out_dst): GHDL 2.0's netlist makes an
        -- array written at a variable index and read outside a RAM a latch, README.md)
        for oi in outs'range loop

          if lane_io(li).out_we = '1' and lane_io(li).out_dst = oi then
            if LANES = 1 then
              outs(oi) <= r.r16;
            else
              outs(oi) <= lane_io(li).out_res;
            end if;
          end if;

        end loop;

        -- a register write saturated
        if lane_io(li).wr5 = '1' and r.fit32 = '0' then
          if AXES > 1 then
            sat(to_integer(axis_q)) <= '1';
          else
            sat(0) <= '1';
          end if;
        end if;

      end loop;

      -- invalid: a NORM or CHK on A <= 0, or an OUT value saturated (LANES = 1 tested
      -- here, on its write)
      if start_i = '1' then
        inval_q <= '0';
      else

        for li in 0 to LANES - 1 loop

          if lane_io(li).inval = '1' then
            inval_q <= '1';
          end if;

          if LANES = 1 and lane_io(li).out_we = '1' and rnd_stage(lane_io(li).win).fit16 = '0' then
            inval_q <= '1';
          end if;

        end loop;

      end if;

      if start_i = '1' then
        busy <= '1';
      elsif done = '1' then
        busy <= '0';
      end if;

      if rst = '1' then
        busy <= '0';
        sat  <= (others => '0');
      end if;
    end if;

  end process common;

  -- END reaches the write stage (lane 0): the program ends on the coming edge; every
  -- earlier instruction has written by then, so out_o and valid_o are final
  done <= v6 and lane_io(0).end6;

  busy_o  <= busy;
  done_o  <= done;
  valid_o <= not inval_q;
  sat_o   <= sat;

  g_out : for oi in 0 to 6 generate
    out_o(16 * oi + 15 downto 16 * oi) <= std_logic_vector(outs(oi));
  end generate g_out;

end architecture rtl;
