-- lut: Table 1 of the paper through two table look-ups (VHDL edition of rtl/lut.v, which
-- gives the design reasoning; model sim/model/lut.py Lut).
--
-- Phase table: ph_o = PH[j] (u12, phase_<table>.hex), or its 12-bit complement ~PH[j]
-- for neg, one edge after j_i (which may be combinational); neg_i comes one edge before
-- j_i. OPT_PHASE_4K (with TABLE_EXACT): 4096 rows per sign (phase_exact_4k.hex) read at
-- neg & t_i, the complement stored in the table's second half; else 2048 rows read at j_i,
-- the complement taken after the read.
-- n-th order: P = n_i * phase_i (u22) registered on e + 1 (prod_o, nth_valid_o): pn =
-- P mod 8192 the n-th order phase, P >> 11 the counter's fine count; on e + 2 (valid_o)
-- pn_o and the sines from one quarter-wave table (sine_<SIN_W>.hex, 2048 words of
-- u0.(SIN_W - 1)): magnitude T[k] and sign, quadrant q = pn(12 downto 11), k = pn(10 downto
-- 0), mirrored (not k) for odd q, negative for q >= 2; cos(x) = sin(x + pi/2); the
-- addresses k registered with them (rtl/pulse.v OPT_ADDR).
-- No clock enable and no reset: every register takes its input on every edge. Power-up
-- values 0.
-- OPT_ECP5_MULT = 1 (with OPT_NTH_DSP) instantiates the ECP5 MULT18X18D
-- (finequad_util_pkg), whose output register is prod_o, in simulation as in synthesis
-- (VHDL has no `SYNTHESIS` define): a simulation binds it to a model of the primitive
-- (cocotb_tests/sim_mult18x18d.vhd). rtl/lut.v simulates the inferred form instead; the
-- ports behave the same.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

library work;
  use work.finequad_util_pkg.all;

entity lut is
  generic (
    TABLE_DIR : string := "rtl/tables/";
    -- 1: the exact phase table (atan); 0: the paper's
    TABLE_EXACT : integer range 0 to 1 := 1;
    -- sine word width (magnitude SIN_W - 1 bits): 8, 10, 12 or 16
    SIN_W : integer range 8 to 16 := 10;
    -- 1: n * phase with the `*` operator (a DSP block); 0: carry-save rows in logic
    OPT_NTH_DSP : integer range 0 to 1 := 1;
    -- 1 (with TABLE_EXACT): the phase table in 4096 rows per sign, addressed by
    -- neg & t_i; 0: 2048 rows addressed by j_i
    OPT_PHASE_4K : integer range 0 to 1 := 0;
    -- 1 (with OPT_NTH_DSP): prod_o is the output register of an ECP5 MULT18X18D;
    -- 0: inferred (any device)
    OPT_ECP5_MULT : integer range 0 to 1 := 0
  );
  port (
    clk : in    std_logic;
    -- phase table
    j_i   : in    unsigned(10 downto 0); -- u11 octant-local address
    t_i   : in    unsigned(11 downto 0); -- u12 its scale (OPT_PHASE_4K)
    neg_i : in    std_logic;             -- the octant sign, an edge before j_i
    ph_o  : out   unsigned(11 downto 0); -- u12 PH[j] (~PH[j] for neg)
    -- n-th order
    valid_i     : in    std_logic;                    -- with phase_i
    phase_i     : in    phase_t;                      -- u13 fine phase (registered)
    n_i         : in    n_t;                          -- u9 interpolation factor
    nth_valid_o : out   std_logic;                    -- latency 1
    prod_o      : out   prod_t;                       -- u22 n * phase: pn = (12 downto 0)
    valid_o     : out   std_logic;                    -- latency 2
    pn_o        : out   phase_t;                      -- u13 n-th order phase
    cos_mag_o   : out   unsigned(SIN_W - 2 downto 0); -- u0.(SIN_W - 1) |cos(n a)|
    cos_neg_o   : out   std_logic;
    sin_mag_o   : out   unsigned(SIN_W - 2 downto 0); -- u0.(SIN_W - 1) |sin(n a)|
    sin_neg_o   : out   std_logic;
    cos_k_o     : out   unsigned(10 downto 0);        -- u11 the sines' table addresses
    sin_k_o     : out   unsigned(10 downto 0)
  );
end entity lut;

architecture rtl of lut is

  subtype ph_t is unsigned(11 downto 0);

  subtype sin_t is unsigned(SIN_W - 1 downto 0);

  subtype k_t is unsigned(10 downto 0);

  constant PH4K : boolean := TABLE_EXACT = 1 and OPT_PHASE_4K = 1;

  -- the phase table: 2048 rows, or 8192 (4096 per sign) with PH4K
  function ph_file return string is
  begin

    if PH4K then
      return "phase_exact_4k.hex";
    elsif TABLE_EXACT = 1 then
      return "phase_exact.hex";
    end if;

    return "phase_paper.hex";

  end function ph_file;

  constant PH_ROWS : positive    := 2048 * (1 + 3 * boolean'pos(PH4K));
  constant PH_ROM  : hex_table_t := read_hex(TABLE_DIR & ph_file, PH_ROWS, 12);

  -- the quarter-wave sine table, one copy for the cosine and one for the sine (a block
  -- RAM each)
  constant SIN_FILE  : string      := TABLE_DIR & "sine_" & integer'image(SIN_W) & ".hex";
  constant SIN_ROM_C : hex_table_t := read_hex(SIN_FILE, 2048, SIN_W);
  constant SIN_ROM_S : hex_table_t := read_hex(SIN_FILE, 2048, SIN_W);

  -- {sum, carry} of three rows, mod 2**22 (a 3:2 counter per bit)
  type csa_t is record
    s : prod_t;
    c : prod_t;
  end record csa_t;

  function csa (a : prod_t; b : prod_t; c : prod_t) return csa_t is
  begin

    return (s => a xor b xor c, c => shift_left((a and b) or (a and c) or (b and c), 1));

  end function csa;

  -- n * phase as nine rows n(b) * (phase << b), reduced by 3:2 counters to two and one
  -- carry add
  function csa_mult (n : n_t; ph : phase_t) return prod_t is

    type rows_t is array (0 to 8) of prod_t;

    variable r  : rows_t;
    variable a0 : csa_t;
    variable a1 : csa_t;
    variable a2 : csa_t;
    variable b0 : csa_t;
    variable b1 : csa_t;
    variable c0 : csa_t;
    variable d0 : csa_t;

  begin

    for i in r'range loop

      r(i) := (others => '0');

      if n(i) = '1' then
        r(i) := shift_left(resize(ph, PROD_W), i);
      end if;

    end loop;

    a0 := csa(r(0), r(1), r(2)); -- 9 -> 6
    a1 := csa(r(3), r(4), r(5));
    a2 := csa(r(6), r(7), r(8));
    b0 := csa(a0.s, a0.c, a1.s); -- 6 -> 4
    b1 := csa(a1.c, a2.s, a2.c);
    c0 := csa(b0.s, b0.c, b1.s); -- 4 -> 3
    d0 := csa(c0.s, c0.c, b1.c); -- 3 -> 2
    return d0.s + d0.c;

  end function csa_mult;

  -- ---- phase table -------------------------------------------------------------------------
  signal neg_q : std_logic := '0'; -- neg_i, on the edge before the read
  signal ph_q  : ph_t      := (others => '0');

  -- ---- n-th order --------------------------------------------------------------------------
  signal prod        : prod_t;
  signal prod_q      : prod_t    := (others => '0');
  signal nth_valid_q : std_logic := '0';
  signal prod_r      : prod_t; -- prod_o: prod_q or the MULT18X18D's output register

  -- ---- sines -------------------------------------------------------------------------------
  signal pn      : phase_t;
  signal pc      : phase_t; -- pn + 2048, the cosine's
  signal ks      : k_t;
  signal kc      : k_t;
  signal sraw    : sin_t     := (others => '0');
  signal craw    : sin_t     := (others => '0');
  signal sin_k_q : k_t       := (others => '0');
  signal cos_k_q : k_t       := (others => '0');
  signal sin_neg : std_logic := '0';
  signal cos_neg : std_logic := '0';
  signal pn_q    : phase_t   := (others => '0');
  signal valid_q : std_logic := '0';

begin

  assert SIN_W = 8 or SIN_W = 10 or SIN_W = 12 or SIN_W = 16
    report "lut: SIN_W must be 8, 10, 12 or 16 (sine_<SIN_W>.hex), not " & integer'image(SIN_W)
    severity failure;

  neg_reg : process (clk) is
  begin

    if rising_edge(clk) then
      neg_q <= neg_i;
    end if;

  end process neg_reg;

  g_ph4k : if PH4K generate

    read : process (clk) is
    begin

      if rising_edge(clk) then
        ph_q <= unsigned(PH_ROM(to_integer(neg_q & t_i)));
      end if;

    end process read;

    ph_o <= ph_q;

  end generate g_ph4k;

  g_ph2k : if not PH4K generate

    signal neg_r : std_logic := '0'; -- neg_q with the read

  begin

    read : process (clk) is
    begin

      if rising_edge(clk) then
        ph_q  <= unsigned(PH_ROM(to_integer(j_i)));
        neg_r <= neg_q;
      end if;

    end process read;

    ph_o <= ph_q xor (ph_q'range => neg_r);

  end generate g_ph2k;

  -- ---- n-th order phase: P = n * phase -----------------------------------------------------

  -- the `*` operator (a DSP block), or the carry-save rows in logic (generate branches:
  -- the netlist holds only the chosen form)

  g_dsp : if OPT_NTH_DSP = 1 generate

    prod <= n_i * phase_i;

  end generate g_dsp;

  g_csa : if OPT_NTH_DSP = 0 generate

    prod <= csa_mult(n_i, phase_i);

  end generate g_csa;

  nth_reg : process (clk) is
  begin

    if rising_edge(clk) then
      prod_q      <= prod;
      nth_valid_q <= valid_i;
    end if;

  end process nth_reg;

  g_prod : if OPT_NTH_DSP = 0 or OPT_ECP5_MULT = 0 generate

    prod_r <= prod_q;

  end generate g_prod;

  -- P in an ECP5 MULT18X18D: phase (u13) on A, n (u9) on B, unsigned, registered in its
  -- output register on every edge (CE0 = 1); prod_q is then unused

  g_mult18 : if OPT_NTH_DSP = 1 and OPT_ECP5_MULT = 1 generate

    signal mult_a  : std_logic_vector(17 downto 0);
    signal mult_b  : std_logic_vector(17 downto 0);
    signal mult_c  : std_logic_vector(17 downto 0);
    signal mult_ce : std_logic;
    signal mult_p  : std_logic_vector(35 downto 0);

  begin

    mult_a  <= std_logic_vector(resize(phase_i, 18));
    mult_b  <= std_logic_vector(resize(n_i, 18));
    mult_c  <= (others => '0');
    mult_ce <= '1';

    u_mult : component mult18x18d
      generic map (
        reg_output_clk => "CLK0",
        reg_output_ce  => "CE0",
        reg_output_rst => "RST0"
      )
      port map (
        a17     => mult_a(17),
        a16     => mult_a(16),
        a15     => mult_a(15),
        a14     => mult_a(14),
        a13     => mult_a(13),
        a12     => mult_a(12),
        a11     => mult_a(11),
        a10     => mult_a(10),
        a9      => mult_a(9),
        a8      => mult_a(8),
        a7      => mult_a(7),
        a6      => mult_a(6),
        a5      => mult_a(5),
        a4      => mult_a(4),
        a3      => mult_a(3),
        a2      => mult_a(2),
        a1      => mult_a(1),
        a0      => mult_a(0),
        b17     => mult_b(17),
        b16     => mult_b(16),
        b15     => mult_b(15),
        b14     => mult_b(14),
        b13     => mult_b(13),
        b12     => mult_b(12),
        b11     => mult_b(11),
        b10     => mult_b(10),
        b9      => mult_b(9),
        b8      => mult_b(8),
        b7      => mult_b(7),
        b6      => mult_b(6),
        b5      => mult_b(5),
        b4      => mult_b(4),
        b3      => mult_b(3),
        b2      => mult_b(2),
        b1      => mult_b(1),
        b0      => mult_b(0),
        c17     => mult_c(17),
        c16     => mult_c(16),
        c15     => mult_c(15),
        c14     => mult_c(14),
        c13     => mult_c(13),
        c12     => mult_c(12),
        c11     => mult_c(11),
        c10     => mult_c(10),
        c9      => mult_c(9),
        c8      => mult_c(8),
        c7      => mult_c(7),
        c6      => mult_c(6),
        c5      => mult_c(5),
        c4      => mult_c(4),
        c3      => mult_c(3),
        c2      => mult_c(2),
        c1      => mult_c(1),
        c0      => mult_c(0),
        signeda => '0',
        signedb => '0',
        sourcea => '0',
        sourceb => '0',
        clk0    => clk,
        clk1    => '0',
        clk2    => '0',
        clk3    => '0',
        ce0     => mult_ce,
        ce1     => '0',
        ce2     => '0',
        ce3     => '0',
        rst0    => '0',
        rst1    => '0',
        rst2    => '0',
        rst3    => '0',
        p35     => mult_p(35),
        p34     => mult_p(34),
        p33     => mult_p(33),
        p32     => mult_p(32),
        p31     => mult_p(31),
        p30     => mult_p(30),
        p29     => mult_p(29),
        p28     => mult_p(28),
        p27     => mult_p(27),
        p26     => mult_p(26),
        p25     => mult_p(25),
        p24     => mult_p(24),
        p23     => mult_p(23),
        p22     => mult_p(22),
        p21     => mult_p(21),
        p20     => mult_p(20),
        p19     => mult_p(19),
        p18     => mult_p(18),
        p17     => mult_p(17),
        p16     => mult_p(16),
        p15     => mult_p(15),
        p14     => mult_p(14),
        p13     => mult_p(13),
        p12     => mult_p(12),
        p11     => mult_p(11),
        p10     => mult_p(10),
        p9      => mult_p(9),
        p8      => mult_p(8),
        p7      => mult_p(7),
        p6      => mult_p(6),
        p5      => mult_p(5),
        p4      => mult_p(4),
        p3      => mult_p(3),
        p2      => mult_p(2),
        p1      => mult_p(1),
        p0      => mult_p(0)
      );

    prod_r <= unsigned(mult_p(PROD_W - 1 downto 0));

  end generate g_mult18;

  -- ---- sines: quarter-wave table, cos(x) = sin(x + pi/2) -----------------------------------
  pn <= prod_r(PHASE_W - 1 downto 0);
  pc <= pn + 2048;
  ks <= not pn(10 downto 0) when pn(11) = '1' else
        pn(10 downto 0);
  kc <= not pc(10 downto 0) when pc(11) = '1' else
        pc(10 downto 0);

  sines : process (clk) is
  begin

    if rising_edge(clk) then
      sraw    <= unsigned(SIN_ROM_S(to_integer(ks)));
      craw    <= unsigned(SIN_ROM_C(to_integer(kc)));
      sin_k_q <= ks;
      cos_k_q <= kc;
      sin_neg <= pn(12);
      cos_neg <= pc(12);
      pn_q    <= pn;
      valid_q <= nth_valid_q;
    end if;

  end process sines;

  nth_valid_o <= nth_valid_q;
  prod_o      <= prod_r;
  valid_o     <= valid_q;
  pn_o        <= pn_q;
  cos_mag_o   <= craw(SIN_W - 2 downto 0);
  cos_neg_o   <= cos_neg;
  sin_mag_o   <= sraw(SIN_W - 2 downto 0);
  sin_neg_o   <= sin_neg;
  cos_k_o     <= cos_k_q;
  sin_k_o     <= sin_k_q;

end architecture rtl;
