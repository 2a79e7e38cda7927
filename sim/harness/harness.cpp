// Compiled Verilator harness of finequad_core: CSV of ADC codes in, one CSV row per
// sample out. No Python runs per clock. Built and run by `make rtlsim`.
//
//   rtlsim --in in.csv --out out.csv [--<setting> N ...] [--home] [--div D]
//          [--vcd out.vcd] [--dump-regs]
//   rtlsim --raw [options]       stream: stdin int16 LE pairs (u1, u2) per sample, stdout
//                                one 8-byte record per sample: int32 count, uint16 fault,
//                                uint8 a, uint8 b (LE); for long runs (scripts/soak.py).
//                                No reference input (s_ref 0 on every sample) and no
//                                reference outputs in the record.
//
// Input: the CSV of input.h, 'u1,u2' or 'u1,u2,ref' (ref: the sample's s_ref, 0 or 1;
// without the column 0). Output: the header 'count,a,b,fault,z,ref_count,homed,pos_valid',
// one row per sample.
//
// Settings: --<field> N writes a register field of rtl/regs/finequad.rdl before the first
// sample (--interp, --eps, --lambda-k, --count-mode, --ab-sep, --jump-off, --loss,
// --ref-q, --home-count, ...: input.h Settings); those not given keep their reset values.
// --home: REF is written last with its pulse REF.home = 1 (and its settings as given):
// homing is armed from the start, the first reference latched sets the count to HOME.
// --dump-regs: after the last sample, stderr gets 'regs: name=value ...' of the counters
// and status (UPDATES, JUMPS, ILLEGAL, FAULT_STICKY, STATUS, COUNT, GAIN).
//
// count, fault: m_count, m_fault after the sample's output edge (m_valid high: t + 8 for
// a sample strobed on edge t); a, b, z: m_a, m_b, m_z after that same edge (the A/B pins,
// paced or with --ab-src 1 the Eq. 12 pulses, and Z, as they stand when the count
// appears: the paced pins take it up from t + 10). ref_count, homed, pos_valid:
// m_ref_count, m_homed, m_pos_valid two edges later (after t + 10, where the core
// registers the sample's reference latch): the state after the sample's own latch.
//
// The VCD holds every signal of the design (Verilator --trace); it grows by about
// 27 MB per 1000 samples at 36 clocks per sample, so dump short excerpts.
//
// Timing (the bit-true model uses the same): registers are written on edges 0, 1, ..., sample
// k is strobed on edge T0 + k * div (T0 = 32); edge e is at time e * PERIOD_PS in the VCD.
//
// Two builds (Makefile): the harness of `make rtlsim` is built without --trace and runs
// one scheduler pass per clock ("Fast clocking" below); given --vcd it hands over to the
// traced build beside it, <its folder>_vcd/Vfinequad_core (built by `make rtlsim VCD=...`
// and `make harnesses`), which calls eval() at both clock edges.
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

#define HARNESS_TOOL "rtlsim"
#include "input.h"

#include "Vfinequad_core.h"
#include "Vfinequad_core___024root.h"
#include "verilated.h"
#if VM_TRACE
#include "verilated_vcd_c.h"
#endif

// Fast clocking, for the harness built without --trace (nothing to dump between edges).
// Profiled on the demo recording, outside the design's own logic the time went to
// eval()'s bookkeeping (mutex operations in VlDeleter::deleteAll and in the message-queue
// flush of Verilated::endOfEval, which serve dynamic objects and messages from other
// threads: this design and harness have neither) and to the falling-edge eval (which only
// re-runs the input-combinational logic and records clk = 0 for the next rising edge's
// trigger: the core has no negedge logic). Both are skipped when the generated model has
// what that needs, with the plain eval() as the fallback:
// - Vfinequad_core___024root___eval: the generated scheduler (input-combinational,
//   active and NBA regions) that eval_step() calls after its one-time initialisation;
//   declared weak, so a Verilator that names it otherwise links to nullptr and eval().
// - __Vtrigprevexpr___TOP__clk__0: the previous clk value the rising-edge trigger
//   compares against; clearing it stands for the falling-edge eval. Only compiled in with
//   RTLSIM_SKIP_NEGEDGE (the Makefile defines it when every event control of the RTL is
//   @(posedge clk) or @(*)) and only if the member exists (else the falling edge is
//   evaluated).
// sim/tests/test_rtlsim.py (RTL == model, bit for bit) covers both paths' results.
void Vfinequad_core___024root___eval(Vfinequad_core___024root *) __attribute__((weak));

template <class R>
static auto clear_prev_clk(R *r, int) -> decltype(r->__Vtrigprevexpr___TOP__clk__0 = 0, true) {
    r->__Vtrigprevexpr___TOP__clk__0 = 0;
    return true;
}
template <class R>
static bool clear_prev_clk(R *, long) { return false; }

#ifndef PERIOD_PS
#define PERIOD_PS 27778  // 36 MHz
#endif
static const long T0 = 32;

// The sample source: the CSV's samples, or int16 pairs from stdin (--raw; ref 0).
struct Source {
    const std::vector<int> *u1 = nullptr, *u2 = nullptr;
    const std::vector<unsigned char> *ref = nullptr;     // empty: no ref column (0)
    size_t next = 0;
    bool raw = false;
    long count = 0;
    bool get(int &a, int &b, int &r) {
        if (raw) {
            int16_t v[2];
            // (counted in bytes: a stream cut inside a code is an error, not the end)
            size_t got = std::fread(v, 1, sizeof v, stdin);
            if (got == 0) return false;
            if (got != sizeof v)
                die("--raw: stdin ended in the middle of sample " + std::to_string(count) +
                    " (" + std::to_string(got) + " of its " + std::to_string(sizeof v) +
                    " bytes)");
            const int lo = -(1 << (ADC_W - 1)), hi = (1 << (ADC_W - 1)) - 1;
            if (v[0] < lo || v[0] > hi || v[1] < lo || v[1] > hi)
                die("--raw: sample " + std::to_string(count) + ": code out of the signed " +
                    std::to_string(ADC_W) + "-bit range: " + std::to_string(v[0]) + "," +
                    std::to_string(v[1]));
            a = v[0];
            b = v[1];
            r = 0;
        } else {
            if (next >= u1->size()) return false;
            a = (*u1)[next];
            b = (*u2)[next];
            r = ref->empty() ? 0 : (*ref)[next];
            next++;
        }
        count++;
        return true;
    }
};

// The output rows "count,a,b,fault,z,ref_count,homed,pos_valid\n" (decimal, as printf's %d
// would write them), formatted into a buffer written in large blocks: fprintf per row was
// about 1 % of a run.
struct CsvOut {
    FILE *f = nullptr;
    char buf[1 << 16];
    size_t n = 0;
    void flush() {
        if (n && std::fwrite(buf, 1, n, f) != n) die("cannot write the output file");
        n = 0;
    }
    void num(long v) {
        char tmp[24];
        int k = 0;
        unsigned long u = v < 0 ? 0UL - (unsigned long)v : (unsigned long)v;
        do tmp[k++] = (char)('0' + u % 10); while (u /= 10);
        if (v < 0) buf[n++] = '-';
        while (k) buf[n++] = tmp[--k];
    }
    // (at most 8 fields of 20 characters and their separators: 168 bytes)
    void row(const long (&v)[8]) {
        if (n > sizeof buf - 256) flush();
        for (int k = 0; k < 8; k++) {
            num(v[k]);
            buf[n++] = k < 7 ? ',' : '\n';
        }
    }
};

// The rows whose count, a, b, fault and z are taken (on the sample's output edge) and
// whose ref_count, homed and pos_valid come REF_LAG edges later: at most REF_LAG + 1 of
// them are pending (a sample on every clock, --div 1).
static const long REF_LAG = 2;
struct Pending {
    struct Row { long edge; long v[8]; };
    Row q[4];
    unsigned head = 0, tail = 0;      // (indices mod 4)
    bool empty() const { return head == tail; }
    Row &front() { return q[head & 3]; }
    Row &push() {
        if (tail - head >= 4) die("internal: more than 4 rows pending");
        return q[tail++ & 3];
    }
    void pop() { head++; }
};

int main(int argc, char **argv) {
    std::string in, out, vcd;
    long div = 36;
    Settings set;
    bool raw = false, dump_regs = false, home = false;
    for (int i = 1; i < argc; i++) {
        std::string a = argv[i];
        auto val = [&](const char *name) -> std::string {
            if (i + 1 >= argc) die(std::string("missing value after ") + name);
            return argv[++i];
        };
        if (a == "--in") in = val("--in");
        else if (a == "--out") out = val("--out");
        else if (a == "--vcd") vcd = val("--vcd");
        else if (a == "--div") div = parse_bounded(val("--div"), "--div", 1, DIV_MAX);
        else if (set.take(argc, argv, i)) continue;
        else if (a == "--raw") raw = true;
        else if (a == "--home") home = true;
        else if (a == "--dump-regs") dump_regs = true;
        else if (a.rfind("+verilator", 0) == 0) continue;
        else die("unknown argument '" + a + "'");
    }
    if (!raw && (in.empty() || out.empty()))
        die("usage: rtlsim --in IN.csv --out OUT.csv [--div D] [--vcd F] [--dump-regs]" +
            Settings::usage() + " [--home] | rtlsim --raw [...]");
    if (raw && (!in.empty() || !out.empty() || !vcd.empty()))
        die("--raw streams stdin to stdout: no --in, --out or --vcd");
    // the settings given (CTRL's pulses 0; with --home REF last, REF.home 1), one register
    // per edge from edge 0
    const auto regs = set.writes(home);
    const long n_regs = (long)regs.size();
    if (T0 < n_regs + 1) die("internal: the register writes run into the first strobe");

#if !VM_TRACE
    if (!vcd.empty()) {
        // this build has no tracing: run the traced one beside it with the same arguments
        char self[4096];
        ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
        std::string traced = n > 0 ? std::string(self, (size_t)n) : std::string(argv[0]);
        size_t slash = traced.find_last_of('/');
        traced = (slash == std::string::npos ? std::string(".") : traced.substr(0, slash)) +
                 "_vcd/Vfinequad_core";
        if (access(traced.c_str(), X_OK) != 0)
            die("--vcd: this harness is built without tracing and its traced build " + traced +
                " is missing (make rtlsim VCD=..., or make harnesses)");
        execv(traced.c_str(), argv);
        die("--vcd: cannot run " + traced + ": " + std::strerror(errno));
    }
#endif
    std::vector<int> u1, u2;
    std::vector<unsigned char> ref;
    Source src;
    src.raw = raw;
    FILE *fo = stdout;
    if (!vcd.empty()) {                 // before OUT is opened (and emptied)
        FILE *t = std::fopen(vcd.c_str(), "w");
        if (!t) die("cannot write the VCD '" + vcd + "'");
        std::fclose(t);
    }
    if (!raw) {
        read_csv(in, u1, u2, ref);
        src.u1 = &u1;
        src.u2 = &u2;
        src.ref = &ref;
        fo = std::fopen(out.c_str(), "w");
        if (!fo) die("cannot write '" + out + "'");
        std::fprintf(fo, "count,a,b,fault,z,ref_count,homed,pos_valid\n");
    }

    auto ctx = std::make_unique<VerilatedContext>();
    ctx->commandArgs(argc, argv);
    auto top = std::make_unique<Vfinequad_core>(ctx.get());
#if VM_TRACE
    std::unique_ptr<VerilatedVcdC> tfp;
    if (!vcd.empty()) {
        ctx->traceEverOn(true);
        tfp = std::make_unique<VerilatedVcdC>();
        top->trace(tfp.get(), 99);
        tfp->open(vcd.c_str());
        if (!tfp->isOpen()) die("cannot write the VCD '" + vcd + "'");
    }
    // the traced build: eval() at both edges (the VCD needs both)
    auto rise = [&]() { top->eval(); };
    auto fall = [&]() { top->eval(); };
#else
    // the fast build (no VCD here, see above)
    struct NoTrace { void dump(uint64_t) {} void close() {} };
    std::unique_ptr<NoTrace> tfp;
    Vfinequad_core___024root *const root = top->rootp;
    auto rise = [&]() {
        if (Vfinequad_core___024root___eval) Vfinequad_core___024root___eval(root);
        else top->eval();
    };
    auto fall = [&]() {
#ifdef RTLSIM_SKIP_NEGEDGE
        if (clear_prev_clk(root, 0)) return;
#endif
        rise();
    };
#endif
    long written = 0, strobed = 0;
    long last_edge = -1;                 // set when the source runs dry
    int a = 0, b = 0, rf = 0;            // the next sample: u1, u2, ref
    bool have = src.get(a, b, rf);
    if (!have) die(raw ? "--raw: stdin has no samples" : "no samples");
    top->clk = 0;
    top->rst = 0;
    top->s_ref = 0;
    top->eval();                         // the first eval also initialises the model
    // (no dump before edge 0: the VCD's time 0 is the state after edge 0, and every edge e
    // dumps at e * PERIOD_PS; a second dump at one time is dropped by Verilator)
    CsvOut csv;
    if (!raw) csv.f = fo;
    Pending pend;
    auto edge = [&](long e) {
        // posedge at time e * PERIOD_PS, negedge half a period later
        top->clk = 1;
        rise();
        if (tfp) tfp->dump((uint64_t)e * PERIOD_PS);
        if (top->m_valid) {
            if (raw) {
                struct { int32_t count; uint16_t fault; uint8_t a, b; } r = {
                    (int32_t)top->m_count, (uint16_t)top->m_fault, (uint8_t)top->m_a,
                    (uint8_t)top->m_b};
                if (std::fwrite(&r, sizeof r, 1, fo) != 1) die("--raw: cannot write stdout");
                written++;
            } else {
                Pending::Row &p = pend.push();
                p.edge = e;
                p.v[0] = (int32_t)top->m_count;
                p.v[1] = top->m_a;
                p.v[2] = top->m_b;
                p.v[3] = top->m_fault;
                p.v[4] = top->m_z;
            }
        }
        // (after the push: with REF_LAG = 0 a row would complete on its own edge)
        if (!pend.empty() && pend.front().edge + REF_LAG == e) {
            Pending::Row &p = pend.front();
            p.v[5] = (int32_t)top->m_ref_count;
            p.v[6] = top->m_homed;
            p.v[7] = top->m_pos_valid;
            csv.row(p.v);
            pend.pop();
            written++;
        }
        top->clk = 0;
        fall();
        if (tfp) tfp->dump((uint64_t)e * PERIOD_PS + PERIOD_PS / 2);
    };
    long e = 0;
    for (; last_edge < 0 || e <= last_edge; e++) {
        // inputs for edge e
        top->reg_we = (e < n_regs);
        top->reg_re = 0;
        if (e < n_regs) {
            top->reg_addr = regs[e].first;
            top->reg_wdata = regs[e].second;
        }
        bool strobe = have && e == T0 + strobed * div;
        top->s_valid = strobe;
        top->s_u1 = strobe ? a : 0;
        top->s_u2 = strobe ? b : 0;
        top->s_ref = strobe ? rf : 0;
        if (strobe) {
            strobed++;
            have = src.get(a, b, rf);
            if (!have) last_edge = e + 12;
        }
        edge(e);
        if (e < n_regs && top->reg_err) {
            const char *reg = "?";
            for (int k = 0; k < FQ_N_SETTINGS; k++)
                if (FQ_SETTINGS[k].index == regs[e].first) reg = FQ_SETTINGS[k].reg;
            char word[16];
            std::snprintf(word, sizeof word, "0x%08x", (unsigned)regs[e].second);
            if (fo) {                        // no output for a run that did not happen
                std::fclose(fo);
                std::remove(out.c_str());
            }
            die(std::string("the core refused the write of ") + reg + " = " + word +
                ": this build keeps the register constant (rtl/regs/finequad.rdl requires; "
                "e.g. OPT_TUNABLE=0)");
        }
    }
    if (dump_regs) {
        // registered read port: address for one edge, the value after it
        const struct { const char *name; int addr; } rd[] = {
            {"UPDATES", FQ_UPDATES}, {"JUMPS", FQ_JUMPS}, {"ILLEGAL", FQ_ILLEGAL},
            {"FAULT_STICKY", FQ_FAULT_STICKY}, {"STATUS", FQ_STATUS}, {"COUNT", FQ_COUNT},
            {"GAIN", FQ_GAIN}};
        top->reg_we = 0;
        top->s_valid = 0;
        std::fprintf(stderr, "regs:");
        for (const auto &r : rd) {
            top->reg_re = 1;
            top->reg_addr = r.addr;
            edge(e++);
            std::fprintf(stderr, " %s=%u", r.name, (unsigned)top->reg_rdata);
        }
        std::fprintf(stderr, "\n");
    }
    csv.flush();
    if (fo != stdout) {
        if (std::fclose(fo) != 0) die("cannot write '" + out + "'");
    } else {
        std::fflush(fo);
    }
    if (tfp) tfp->close();
    top->final();
    if (written != strobed)
        die("wrote " + std::to_string(written) + " rows for " + std::to_string(strobed) + " samples");
    return 0;
}
