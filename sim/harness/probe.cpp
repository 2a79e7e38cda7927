// Measurement harness of finequad_core for `make report` (scripts/report.py): the
// latency, the fast path's rate and the estimator's update rate, measured on the RTL
// (Verilator). No Python runs per clock.
//
//   probe stream  --in in.csv --out out.csv --trace trace.csv [--div D] [--interp N]
//   probe latency --trials K [--interp N] [--ab-src 0|1] [--ab-sep S] [--step U]
//                 [--space C] [--seed X]
//
// stream: the timing of sim/harness/harness.cpp (registers written on edges 0..10 with
// the harness' defaults, sample k strobed on edge T0 + k * div, T0 = 32, s_ref from the
// input's ref column), so out.csv (count,a,b,fault,z,ref_count,homed,pos_valid, sampled
// as the harness does) equals `make model` with the same DIV. After the register writes the
// read port reads UPDATES on every edge; trace.csv has one row per sample:
// its strobe edge, the edge its result appeared on (m_valid), and UPDATES after that
// edge (with PROBE_INTERNALS also, cumulative, the programs started -- RESET, UPDATE,
// EXTRACT --, the clocks the engine was busy with each, and the candidates the phase
// gate turned away). A summary line (JSON) goes
// to stdout: edges with m_valid, the first and last of
// them, the longest gap, JUMPS read at the end.
//
// latency: samples on a centred circle of radius 0.49 of full scale (the power-up
// coefficients, radius 0.5 after the gain, take it as calibrated enough for the phase) at
// a constant speed of --step u13 phase units (1/8192 period) per sample, so the signal
// monitor's glitch and stuck checks stay quiet, one sample every --space clocks (the
// paced A/B catch up in between); after 8 warm-up samples and an idle time for the A/B
// to catch up with the first count (up to 4n from 0), each sample is a trial: its
// strobe edge t, and the first edge after t with m_valid, with m_count changed, and with
// (m_a, m_b) changed, as edge - t (-1: not within --space clocks).
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "Vfinequad_core.h"
#include "verilated.h"

#define HARNESS_TOOL "probe"
#include "input.h"
#ifdef PROBE_INTERNALS
// built with --public-flat-rw: the estimator's program starts and the engine's busy
// clocks, per program, go into the trace (the breakdown of the clocks per update)
#include "Vfinequad_core___024root.h"
#define EST(sig) (c.top->rootp->finequad_core__DOT__u_est__DOT__##sig)
#endif

static const long T0 = 32;

struct Core {
    std::unique_ptr<VerilatedContext> ctx;
    std::unique_ptr<Vfinequad_core> top;
    long edge = -1;  // the last edge applied
    Core(int argc, char **argv) : ctx(new VerilatedContext) {
        ctx->commandArgs(argc, argv);
        top.reset(new Vfinequad_core(ctx.get()));
        top->clk = 0;
        top->rst = 0;
        top->s_valid = 0;
        top->s_ref = 0;
        top->reg_we = 0;
        top->reg_re = 0;
        top->eval();
    }
    // one rising edge with the inputs as set, then the falling edge
    void step() {
        top->clk = 1;
        top->eval();
        edge++;
    }
    void fall() {
        top->clk = 0;
        top->eval();
    }
    ~Core() { top->final(); }
};

static int stream(int argc, char **argv, const std::string &in, const std::string &out,
                  const std::string &trace, long div, long interp) {
    std::vector<int> u1, u2;
    std::vector<unsigned char> ref;
    read_csv(in, u1, u2, ref);
    FILE *fo = std::fopen(out.c_str(), "w");
    FILE *ft = std::fopen(trace.c_str(), "w");
    if (!fo || !ft) die("cannot write '" + out + "' or '" + trace + "'");
    std::fprintf(fo, "count,a,b,fault,z,ref_count,homed,pos_valid\n");
#ifdef PROBE_INTERNALS
    std::fprintf(ft, "strobe_edge,out_edge,updates,starts_reset,starts_update,starts_extract,"
                     "busy_reset,busy_update,busy_extract,gate_blocks\n");
    long starts[3] = {0, 0, 0}, busy[3] = {0, 0, 0}, gate_blocks = 0;
    int prog = 0;
#else
    std::fprintf(ft, "strobe_edge,out_edge,updates\n");
#endif
    Core c(argc, argv);
    // as `make rtlsim --interp N`: INTERP written, every other register at its reset value
    const long regs[][2] = {{FQ_INTERP, interp}};
    const long n_regs = (long)(sizeof regs / sizeof regs[0]);
    const long n = (long)u1.size();
    const long last_edge = T0 + (n - 1) * div + 12;
    long next = 0, done = 0, valid_edges = 0, first_valid = -1, last_valid = -1,
         max_gap = 0;
    std::vector<long> strobe_at;
    strobe_at.reserve(n);
    // the rows waiting for their reference columns (two edges after m_valid, as the
    // harness): at most 3 with a sample on every clock
    struct Row { long edge; int count, a, b, fault, z; };
    Row pend[4];
    unsigned head = 0, tail = 0;
    for (long e = 0; e <= last_edge; e++) {
        c.top->reg_we = (e < n_regs);
        c.top->reg_re = (e >= n_regs);
        if (e < n_regs) {
            c.top->reg_addr = regs[e][0];
            c.top->reg_wdata = (uint32_t)regs[e][1];
        } else {
            c.top->reg_addr = FQ_UPDATES;
        }
        bool strobe = next < n && e == T0 + next * div;
        c.top->s_valid = strobe;
        c.top->s_u1 = strobe ? u1[next] : 0;
        c.top->s_u2 = strobe ? u2[next] : 0;
        c.top->s_ref = strobe && !ref.empty() ? ref[next] : 0;
        if (strobe) {
            strobe_at.push_back(e);
            next++;
        }
        c.step();
#ifdef PROBE_INTERNALS
        if (EST(eng_busy)) busy[prog]++;
        if (EST(start_q)) {  // the engine starts on the next edge
            const int ent = EST(entry_q);
            prog = ent == ENTRY_RESET ? 0 : ent == ENTRY_UPDATE ? 1 : 2;
            starts[prog]++;
        }
        // a candidate the gate turns away: its decision inputs are valid, no saturation,
        // no dither hold-off, but its phase is within `gate` of the last update's
        if (EST(pre_valid) && !EST(pre_xsat) && EST(skip) == 0 && !EST(pre_gate)) gate_blocks++;
#endif
        if (c.top->m_valid) {
            if (done >= n) die("more results than samples");
            if (tail - head >= 4) die("internal: more than 4 rows pending");
            pend[tail++ & 3] = {e, (int)(int32_t)c.top->m_count, c.top->m_a, c.top->m_b,
                                c.top->m_fault, c.top->m_z};
#ifdef PROBE_INTERNALS
            std::fprintf(ft, "%ld,%ld,%u,%ld,%ld,%ld,%ld,%ld,%ld,%ld\n", strobe_at[done], e,
                         (unsigned)c.top->reg_rdata, starts[0], starts[1], starts[2], busy[0],
                         busy[1], busy[2], gate_blocks);
#else
            std::fprintf(ft, "%ld,%ld,%u\n", strobe_at[done], e, (unsigned)c.top->reg_rdata);
#endif
            if (last_valid >= 0 && e - last_valid - 1 > max_gap) max_gap = e - last_valid - 1;
            if (first_valid < 0) first_valid = e;
            last_valid = e;
            valid_edges++;
            done++;
        }
        if (head != tail && pend[head & 3].edge + 2 == e) {
            const Row &r = pend[head++ & 3];
            std::fprintf(fo, "%d,%d,%d,%d,%d,%d,%d,%d\n", r.count, r.a, r.b, r.fault, r.z,
                         (int)(int32_t)c.top->m_ref_count, c.top->m_homed,
                         c.top->m_pos_valid);
        }
        c.fall();
    }
    // JUMPS: the jump detector's resets during the run
    c.top->s_valid = 0;
    c.top->reg_we = 0;
    c.top->reg_re = 1;
    c.top->reg_addr = FQ_JUMPS;
    c.step();
    unsigned jumps = c.top->reg_rdata;
    c.fall();
    std::fclose(fo);
    std::fclose(ft);
    if (done != n) die("got " + std::to_string(done) + " results for " + std::to_string(n) + " samples");
    if (head != tail) die("internal: rows left without their reference columns");
    std::printf("{\"samples\": %ld, \"div\": %ld, \"first_strobe_edge\": %ld, "
                "\"last_strobe_edge\": %ld, \"valid_edges\": %ld, \"first_valid_edge\": %ld, "
                "\"last_valid_edge\": %ld, \"max_gap\": %ld, \"jumps\": %u}\n",
                n, div, strobe_at.front(), strobe_at.back(), valid_edges, first_valid,
                last_valid, max_gap, jumps);
    return 0;
}

static int latency(int argc, char **argv, long trials, long interp, long ab_src, long ab_sep,
                   long step_u13, long space, unsigned seed) {
    Core c(argc, argv);
    // INTERP; ABGEN only when it differs from its reset value (a build with OPT_TUNABLE=0
    // keeps it constant and refuses the write); AB_BOUND at its reset value
    std::vector<std::pair<int, uint32_t>> regs = {{FQ_INTERP, (uint32_t)interp}};
    if (ab_sep != setting_reset("ab_sep") || ab_src != setting_reset("ab_src"))
        regs.emplace_back(FQ_ABGEN, field_word("ab_sep", ab_sep) | field_word("ab_src", ab_src));
    for (auto &r : regs) {
        c.top->reg_we = 1;
        c.top->reg_addr = r.first;
        c.top->reg_wdata = r.second;
        c.step();
        if (c.top->reg_err)
            die("the core refused the write of word " + std::to_string(r.first) +
                ": this build keeps the register constant (e.g. OPT_TUNABLE=0)");
        c.fall();
    }
    c.top->reg_we = 0;
    const double rad = 0.49 * (1 << (ADC_W - 1));
    auto put = [&](double a, bool strobe) {
        c.top->s_valid = strobe;
        c.top->s_u1 = (int)std::lround(rad * std::cos(a));
        c.top->s_u2 = (int)std::lround(rad * std::sin(a));
    };
    const double two_pi = 6.283185307179586;
    srand(seed);
    double a = two_pi * (rand() / (double)RAND_MAX);
    const double d = two_pi * step_u13 / 8192.0;
    // samples at a constant speed (the signal monitor's glitch and stuck checks stay
    // quiet), one every `space` clocks: the paced A/B has caught up before the next one
    const long warm = 8;
    std::printf("{\"trials\": [");
    for (long k = -warm; k < trials; k++) {
        a = std::fmod(a + d + two_pi, two_pi);
        int count0 = (int)c.top->m_count, a0 = c.top->m_a, b0 = c.top->m_b;
        put(a, true);
        c.step();  // the strobe edge t
        const long t = c.edge;
        c.fall();
        put(a, false);
        long lv = -1, lc = -1, lab = -1;
        for (long i = 1; i < space; i++) {
            c.step();
            if (lv < 0 && c.top->m_valid) lv = c.edge - t;
            if (lc < 0 && (int)c.top->m_count != count0) lc = c.edge - t;
            if (lab < 0 && (c.top->m_a != a0 || c.top->m_b != b0)) lab = c.edge - t;
            c.fall();
        }
        if (k == -1) {
            // the first sample's count is up to 4 n from the power-up count 0: let the
            // paced A/B catch up before the trials
            for (long i = 0; i < 4 * interp * (ab_sep < 1 ? 1 : ab_sep) + 64; i++) {
                c.step();
                c.fall();
            }
        }
        if (k >= 0)
            std::printf("%s{\"phase\": %.6f, \"valid\": %ld, \"count\": %ld, \"ab\": %ld}",
                        k ? ", " : "", a / two_pi, lv, lc, lab);
    }
    std::printf("], \"interp\": %ld, \"ab_src\": %ld, \"ab_sep\": %ld, \"step_u13\": %ld, "
                "\"space\": %ld}\n", interp, ab_src, ab_sep, step_u13, space);
    return 0;
}

int main(int argc, char **argv) {
    if (argc < 2) die("usage: probe stream|latency [options] (see sim/harness/probe.cpp)");
    std::string mode = argv[1], in, out, trace;
    long div = 1, interp = setting_reset("interp"), trials = 50, ab_src = setting_reset("ab_src"),
         ab_sep = setting_reset("ab_sep"), seed = 1, step = 97, space = 64;
    for (int i = 2; i < argc; i++) {
        std::string a = argv[i];
        auto val = [&](const char *name) -> std::string {
            if (i + 1 >= argc) die(std::string("missing value after ") + name);
            return argv[++i];
        };
        if (a == "--in") in = val("--in");
        else if (a == "--out") out = val("--out");
        else if (a == "--trace") trace = val("--trace");
        else if (a == "--div") div = parse_bounded(val("--div"), "--div", 1, DIV_MAX);
        else if (a == "--interp") interp = parse_setting(val("--interp"), "interp");
        else if (a == "--trials") trials = parse_long(val("--trials"), "--trials");
        else if (a == "--ab-src") ab_src = parse_setting(val("--ab-src"), "ab_src");
        else if (a == "--ab-sep") ab_sep = parse_setting(val("--ab-sep"), "ab_sep");
        else if (a == "--seed") seed = parse_long(val("--seed"), "--seed");
        else if (a == "--step") step = parse_long(val("--step"), "--step");
        else if (a == "--space") space = parse_long(val("--space"), "--space");
        else if (a.rfind("+verilator", 0) == 0) continue;
        else die("unknown argument '" + a + "'");
    }
    if (trials < 1) die("--trials must be >= 1");
    if (mode == "stream") {
        if (in.empty() || out.empty() || trace.empty())
            die("stream needs --in, --out and --trace");
        return stream(argc, argv, in, out, trace, div, interp);
    }
    if (step < -3071 || step > 3071) die("--step must be within +-3071 (u13 units per sample)");
    if (space < 16) die("--space must be >= 16 clocks");
    if (mode == "latency")
        return latency(argc, argv, trials, interp, ab_src, ab_sep, step, space, (unsigned)seed);
    die("unknown mode '" + mode + "' (stream or latency)");
}
