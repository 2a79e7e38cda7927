`timescale 1ns / 1ps
`default_nettype none
// axil_regs: AXI4-Lite slave in front of finequad_core's register port.
//
// Why AXI4-Lite (not Wishbone): it is what vendor interconnects and soft CPUs (LiteX,
// PicoRV32's AXI adapter, Vivado/Radiant IP) speak natively, and Forencich's cocotbext-axi
// provides a maintained bus-master model (AxiLiteMaster) with back-pressure on every
// channel, so the bus is tested against a model nobody here wrote.
//
// Address map: byte address = 4 * reg_addr; word index addr[ADDR_W-1:2], addr[1:0]
// ignored (a word access at any byte offset hits its word). Word indices 0 .. ADDR_TOP
// go to the core (its register map: rtl/regs/finequad.rdl); a write the core refuses
// (reg_err: a register that takes no writes, a bit no field holds, a field outside its
// legal values; unmapped words below ADDR_TOP too) answers SLVERR and changes nothing;
// reads of unmapped words return 0, OKAY. Word indices above ADDR_TOP answer SLVERR
// without touching the core (reads return 0).
// WSTRB: the core's registers are single fields with write side effects (CTRL's reset
// request, HARM's table clear, write-1-to-clear of FAULT_STICKY), so a byte-lane
// read-modify-write would replay them: only full-word writes (WSTRB = 4'hF) are
// performed; any other WSTRB (partial, or 0) answers SLVERR and writes nothing.
//
// Handshakes (AMBA AXI4-Lite): AWREADY, WREADY, ARREADY are high while the slave's
// holding register for that channel is empty (independent of the valids: AW and W may
// arrive in either order or together); BVALID, RVALID and their payloads are registers,
// so no valid depends on a ready, and they stay until accepted. One transaction at a time
// on the core port: a write executes once its address and data are both held and the
// previous write response has been accepted; a read once its address is held and the
// previous read data has been accepted. When both could start on the same edge they
// alternate (the one that did not go last wins), so neither starves.
//
// Timing (edges numbered, register port outputs registered):
//   write: AW and W held before edge e -> reg_we/reg_addr/reg_wdata high/valid after e
//          (the core writes on e + 1, or refuses: reg_err during that clock), BVALID
//          after e + 1 with BRESP = SLVERR if refused. Throughput: one write per 3 edges
//          with BREADY high (AW/W taken on e + 2 again).
//   read:  AR held before edge e -> reg_re after e (the core registers reg_rdata on
//          e + 1), RVALID after e + 1 with RDATA = reg_rdata (the core holds it until the
//          next reg_re, and no read is issued while RVALID is high). Latency from the AR
//          handshake edge h: reg_re after h + 1, RVALID after h + 2.
// rst: synchronous, active high: empties the holding registers and drops BVALID/RVALID
// (an AXI master must be reset with it).
module axil_regs #(
    // AXI address width (bits); at least 8 (64 words of the core's port)
    parameter ADDR_W = 16,
    // highest word index that is mapped to the core (<= 63)
    parameter [5:0] ADDR_TOP = 6'h3f
) (
    input  wire              clk,
    input  wire              rst,
    // AXI4-Lite slave: write address, write data, write response
    input  wire [ADDR_W-1:0] s_axil_awaddr,
    input  wire [2:0]        s_axil_awprot,
    input  wire              s_axil_awvalid,
    output wire              s_axil_awready,
    input  wire [31:0]       s_axil_wdata,
    input  wire [3:0]        s_axil_wstrb,
    input  wire              s_axil_wvalid,
    output wire              s_axil_wready,
    output wire [1:0]        s_axil_bresp,
    output wire              s_axil_bvalid,
    input  wire              s_axil_bready,
    // read address, read data
    input  wire [ADDR_W-1:0] s_axil_araddr,
    input  wire [2:0]        s_axil_arprot,
    input  wire              s_axil_arvalid,
    output wire              s_axil_arready,
    output wire [31:0]       s_axil_rdata,
    output wire [1:0]        s_axil_rresp,
    output wire              s_axil_rvalid,
    input  wire              s_axil_rready,
    // finequad_core register port (reg_rdata registered: valid the edge after reg_re)
    output reg               reg_we,
    output reg               reg_re,
    output reg  [5:0]        reg_addr,
    output reg  [31:0]       reg_wdata,
    input  wire [31:0]       reg_rdata,
    // the core refuses the write on the register port (combinational, with reg_we)
    input  wire              reg_err
);
    localparam [1:0] RESP_OKAY = 2'b00;
    localparam [1:0] RESP_SLVERR = 2'b10;

    // ---- holding registers -------------------------------------------------------------
    reg              aw_full_q = 1'b0;
    reg [ADDR_W-3:0] aw_word_q = 0;
    reg              w_full_q = 1'b0;
    reg [31:0]       w_data_q = 32'd0;
    reg [3:0]        w_strb_q = 4'd0;
    reg              ar_full_q = 1'b0;
    reg [ADDR_W-3:0] ar_word_q = 0;
    // ---- responses ---------------------------------------------------------------------
    reg              bvalid_q = 1'b0;
    reg              wr_wait_q = 1'b0;    // reg_we issued, the core's verdict this clock
    reg [1:0]        bresp_q = RESP_OKAY;
    reg              rd_wait_q = 1'b0;    // reg_re issued, reg_rdata valid after next edge
    reg              rvalid_q = 1'b0;
    reg              rerr_q = 1'b0;       // SLVERR read: RDATA 0
    reg              last_wr_q = 1'b0;    // arbitration: the last operation was a write

    initial begin
        reg_we = 1'b0;
        reg_re = 1'b0;
        reg_addr = 6'd0;
        reg_wdata = 32'd0;
    end

    assign s_axil_awready = !aw_full_q;
    assign s_axil_wready  = !w_full_q;
    assign s_axil_arready = !ar_full_q;
    assign s_axil_bvalid  = bvalid_q;
    assign s_axil_bresp   = bresp_q;
    assign s_axil_rvalid  = rvalid_q;
    assign s_axil_rresp   = rerr_q ? RESP_SLVERR : RESP_OKAY;
    assign s_axil_rdata   = rerr_q ? 32'd0 : reg_rdata;

    // ---- decisions (from registered state only) ------------------------------------------
    wire wr_ready = aw_full_q && w_full_q && !bvalid_q && !wr_wait_q;
    wire rd_ready = ar_full_q && !rvalid_q && !rd_wait_q;
    // both ready: alternate (the one that did not go last); continuous assignments, as
    // Icarus does not run an always @* whose inputs never change from their initial values
    wire do_wr = wr_ready && !(rd_ready && last_wr_q);
    wire do_rd = rd_ready && !(wr_ready && !last_wr_q);
    localparam [31:0] TOP = {26'd0, ADDR_TOP};
    wire wr_mapped = (aw_word_q <= TOP[ADDR_W-3:0]);
    wire wr_ok     = wr_mapped && (w_strb_q == 4'hF);
    wire rd_mapped = (ar_word_q <= TOP[ADDR_W-3:0]);

    always @(posedge clk) begin
        // channel captures
        if (s_axil_awvalid && !aw_full_q) begin
            aw_full_q <= 1'b1;
            aw_word_q <= s_axil_awaddr[ADDR_W-1:2];
        end
        if (s_axil_wvalid && !w_full_q) begin
            w_full_q <= 1'b1;
            w_data_q <= s_axil_wdata;
            w_strb_q <= s_axil_wstrb;
        end
        if (s_axil_arvalid && !ar_full_q) begin
            ar_full_q <= 1'b1;
            ar_word_q <= s_axil_araddr[ADDR_W-1:2];
        end
        // responses accepted
        if (bvalid_q && s_axil_bready)
            bvalid_q <= 1'b0;
        if (rvalid_q && s_axil_rready)
            rvalid_q <= 1'b0;

        // register port: one operation per edge at most
        reg_we <= 1'b0;
        reg_re <= 1'b0;
        if (do_wr) begin
            aw_full_q <= 1'b0;
            w_full_q <= 1'b0;
            reg_we <= wr_ok;
            reg_addr <= aw_word_q[5:0];
            reg_wdata <= w_data_q;
            bresp_q <= wr_ok ? RESP_OKAY : RESP_SLVERR;
            last_wr_q <= 1'b1;
        end
        // the response after the core's verdict (reg_we's clock)
        wr_wait_q <= do_wr;
        if (wr_wait_q) begin
            bvalid_q <= 1'b1;
            if (reg_we && reg_err)
                bresp_q <= RESP_SLVERR;
        end
        if (do_rd) begin
            ar_full_q <= 1'b0;
            reg_re <= rd_mapped;
            reg_addr <= ar_word_q[5:0];
            rerr_q <= !rd_mapped;
            last_wr_q <= 1'b0;
        end
        rd_wait_q <= do_rd;
        if (rd_wait_q)
            rvalid_q <= 1'b1;

        if (rst) begin
            aw_full_q <= 1'b0;
            w_full_q <= 1'b0;
            ar_full_q <= 1'b0;
            bvalid_q <= 1'b0;
            wr_wait_q <= 1'b0;
            rvalid_q <= 1'b0;
            rd_wait_q <= 1'b0;
            reg_we <= 1'b0;
            reg_re <= 1'b0;
            last_wr_q <= 1'b0;
        end
    end

    wire unused = &{1'b0, s_axil_awprot, s_axil_arprot, s_axil_awaddr[1:0],
                    s_axil_araddr[1:0], 1'b0};
endmodule
`resetall
