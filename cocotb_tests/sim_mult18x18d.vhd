-- MULT18X18D (Lattice ECP5 DSP multiplier): behavioural stand-in for simulations of the
-- instances in rtl/vhdl/octant.vhd and rtl/vhdl/lut.vhd (OPT_ECP5_MULT = 1), the VHDL
-- twin of cocotb_tests/sim_mult18x18d.v with the same behaviour and the same limits.
-- Only what those instances use is modelled: A and B either combinational
-- (REG_INPUTx_CLK "NONE") or in input registers on CLK0 with clock enable CE0 (and
-- synchronous reset RST0), signed or unsigned by SIGNEDA/SIGNEDB, P = A * B (36 bits),
-- combinational or in the output register on CLK0 (CE0, RST0), no pipeline register, C
-- unused. Any other setting stops elaboration with an error naming the generic.

library ieee;
  use ieee.std_logic_1164.all;
  use ieee.numeric_std.all;

-- vsg_off port_026 entity_008 port_010 entity_012

entity MULT18X18D is
  generic (
    REG_INPUTA_CLK   : string := "NONE";
    REG_INPUTA_CE    : string := "CE0";
    REG_INPUTA_RST   : string := "RST0";
    REG_INPUTB_CLK   : string := "NONE";
    REG_INPUTB_CE    : string := "CE0";
    REG_INPUTB_RST   : string := "RST0";
    REG_INPUTC_CLK   : string := "NONE";
    REG_PIPELINE_CLK : string := "NONE";
    REG_OUTPUT_CLK   : string := "NONE";
    REG_OUTPUT_CE    : string := "CE0";
    REG_OUTPUT_RST   : string := "RST0";
    SOURCEB_MODE     : string := "B_SHIFT";
    MULT_BYPASS      : string := "DISABLED";
    RESETMODE        : string := "SYNC";
    GSR              : string := "ENABLED"
  );
  port (
    A17, A16, A15, A14, A13, A12, A11, A10, A9, A8, A7, A6, A5, A4, A3,
    A2, A1, A0                                                         : in    std_logic;
    B17, B16, B15, B14, B13, B12, B11, B10, B9, B8, B7, B6, B5, B4, B3,
    B2, B1, B0                                                         : in    std_logic;
    C17, C16, C15, C14, C13, C12, C11, C10, C9, C8, C7, C6, C5, C4, C3,
    C2, C1, C0                                                         : in    std_logic;
    SIGNEDA, SIGNEDB, SOURCEA, SOURCEB                                 : in    std_logic;
    CLK3, CLK2, CLK1, CLK0, CE3, CE2, CE1, CE0, RST3, RST2, RST1, RST0 : in    std_logic;
    P35, P34, P33, P32, P31, P30, P29, P28, P27, P26, P25, P24, P23, P22,
    P21, P20, P19, P18, P17, P16, P15, P14, P13, P12, P11, P10, P9, P8,
    P7, P6, P5, P4, P3, P2, P1, P0                                     : out   std_logic
  );
end entity MULT18X18D;

-- vsg_on port_026 entity_008 port_010 entity_012

architecture sim of mult18x18d is

  signal a    : unsigned(17 downto 0);
  signal b    : unsigned(17 downto 0);
  signal a_q  : unsigned(17 downto 0) := (others => '0');
  signal b_q  : unsigned(17 downto 0) := (others => '0');
  signal ao   : unsigned(17 downto 0);
  signal bo   : unsigned(17 downto 0);
  signal prod : signed(36 downto 0);
  signal p_q  : unsigned(35 downto 0) := (others => '0');
  signal po   : unsigned(35 downto 0);

  -- an 18-bit operand as s37, signed or unsigned
  function ext (v : unsigned(17 downto 0); sgn : std_logic) return signed is
  begin

    if sgn = '1' then
      return resize(signed(v), 37);
    end if;

    return signed(resize(v, 37));

  end function ext;

begin

  assert (REG_INPUTA_CLK = "NONE" or REG_INPUTA_CLK = "CLK0") and REG_INPUTA_CE = "CE0"
         and REG_INPUTA_RST = "RST0"
    report "MULT18X18D stand-in: REG_INPUTA_* " & REG_INPUTA_CLK & "/" & REG_INPUTA_CE
           & "/" & REG_INPUTA_RST & " not modelled"
    severity failure;
  assert (REG_INPUTB_CLK = "NONE" or REG_INPUTB_CLK = "CLK0") and REG_INPUTB_CE = "CE0"
         and REG_INPUTB_RST = "RST0"
    report "MULT18X18D stand-in: REG_INPUTB_* " & REG_INPUTB_CLK & "/" & REG_INPUTB_CE
           & "/" & REG_INPUTB_RST & " not modelled"
    severity failure;
  assert (REG_OUTPUT_CLK = "NONE" or REG_OUTPUT_CLK = "CLK0") and REG_OUTPUT_CE = "CE0"
         and REG_OUTPUT_RST = "RST0"
    report "MULT18X18D stand-in: REG_OUTPUT_* " & REG_OUTPUT_CLK & "/" & REG_OUTPUT_CE
           & "/" & REG_OUTPUT_RST & " not modelled"
    severity failure;
  assert REG_INPUTC_CLK = "NONE" and REG_PIPELINE_CLK = "NONE"
    report "MULT18X18D stand-in: REG_INPUTC/PIPELINE_CLK not modelled"
    severity failure;
  assert MULT_BYPASS = "DISABLED" and RESETMODE = "SYNC"
    report "MULT18X18D stand-in: MULT_BYPASS " & MULT_BYPASS & ", RESETMODE " & RESETMODE
           & " not modelled"
    severity failure;

  a <= A17 & A16 & A15 & A14 & A13 & A12 & A11 & A10 & A9 & A8 & A7 & A6 & A5 & A4 &
       A3 & A2 & A1 & A0;
  b <= B17 & B16 & B15 & B14 & B13 & B12 & B11 & B10 & B9 & B8 & B7 & B6 & B5 & B4 &
       B3 & B2 & B1 & B0;

  inputs : process (CLK0) is
  begin

    if rising_edge(CLK0) then
      if RST0 = '1' then
        a_q <= (others => '0');
        b_q <= (others => '0');
      elsif CE0 = '1' then
        a_q <= a;
        b_q <= b;
      end if;
    end if;

  end process inputs;

  ao <= a_q when REG_INPUTA_CLK = "CLK0" else
        a;
  bo <= b_q when REG_INPUTB_CLK = "CLK0" else
        b;

  prod <= resize(ext(ao, SIGNEDA) * ext(bo, SIGNEDB), 37);

  output : process (CLK0) is
  begin

    if rising_edge(CLK0) then
      if RST0 = '1' then
        p_q <= (others => '0');
      elsif CE0 = '1' then
        p_q <= unsigned(prod(35 downto 0));
      end if;
    end if;

  end process output;

  po <= p_q when REG_OUTPUT_CLK = "CLK0" else
        unsigned(prod(35 downto 0));

  (P35, P34, P33, P32, P31, P30, P29, P28, P27, P26, P25, P24, P23,
  P22, P21, P20, P19, P18, P17, P16, P15, P14, P13, P12, P11, P10,
  P9, P8, P7, P6, P5, P4, P3, P2, P1, P0) <= po;

end architecture sim;
