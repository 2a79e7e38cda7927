// geu: a >= b, unsigned, up to 32 bits (zero-extend narrower operands), formed bit by bit
// from the LSB. With b constant it folds to an AND/OR chain that synthesis maps to a few
// LUTs (Yosys maps a comparison with a constant to a whole carry chain). Included inside
// the module bodies of rtl/abgen.v, rtl/counter.v, rtl/estimator.v and rtl/pulse.v (every
// flow puts rtl/ on the include path, beside rtl/tables/ of the generated headers).
function automatic geu(input [31:0] a, input [31:0] b);
    integer i;
    reg r;
    begin
        r = 1'b1;
        for (i = 0; i < 32; i = i + 1)
            r = (a[i] & ~b[i]) | (~(a[i] ^ b[i]) & r);
        geu = r;
    end
endfunction
