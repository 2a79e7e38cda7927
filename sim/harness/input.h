// Command-line and CSV input rules shared by the Verilator harnesses (harness.cpp, the
// `make rtlsim` harness, and probe.cpp, the measurements of `make report`), so both read
// a recording alike and name what is wrong and where. Define HARNESS_TOOL (the name that
// starts every error message) and ADC_W before including it.
//
// CSV: the header 'u1,u2' or 'u1,u2,ref', then one row per sample: 'u1,u2', decimal ADC
// codes in the signed ADC_W-bit range, and with the header 'u1,u2,ref' a third value on
// every row, ref, 0 or 1 (the reference comparator's output for the sample; without the
// column ref is 0 on every sample); blank lines are skipped. A line's trailing '\r', ' '
// and '\n' and its leading ' ' do not count, nor do a field's trailing ' ' and its
// leading white space (strtol's: ' ', '\t', '\n', '\v', '\f', '\r'). sim/run_model.py
// reads by the same rules and names the same errors. An error exits with status 2 and one
// line, 'TOOL: error: ' and what was wrong: with 'file:line:' for a line's error, with the
// file's name for a file's; bytes outside printable ASCII are shown as \xNN.
#ifndef FINEQUAD_HARNESS_INPUT_H
#define FINEQUAD_HARNESS_INPUT_H
#ifndef HARNESS_TOOL
#error "define HARNESS_TOOL (the tool's name in error messages) before including input.h"
#endif
#ifndef ADC_W
#error "define ADC_W (the ADC word width, 12..16) before including input.h"
#endif

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

#include <sys/stat.h>

#include "regs.h"
// REF.home, a pulse (regs.h lists the settings only): the C header of the register map
#include "../../rtl/regs/finequad_regs.h"
static const uint32_t FQ_REF_HOME_BM = FINEQUAD__REF__HOME_bm;

[[noreturn]] static void die(const std::string &msg) {
    std::cerr << HARNESS_TOOL << ": error: " << msg << std::endl;
    std::exit(2);
}

// printable ASCII as is, every other byte as \xNN (a NUL or a control byte in a message
// would cut or garble the line)
static std::string shown(const char *p, const char *q) {
    static const char hex[] = "0123456789abcdef";
    std::string out;
    for (; p < q; p++) {
        unsigned char c = (unsigned char)*p;
        if (c >= 0x20 && c < 0x7f) {
            out += (char)c;
        } else {
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    return out;
}
static std::string shown(const std::string &s) { return shown(s.data(), s.data() + s.size()); }

static long parse_long(const std::string &s, const std::string &what) {
    errno = 0;
    char *end = nullptr;
    long v = std::strtol(s.c_str(), &end, 10);
    if (end == s.c_str() || end != s.c_str() + s.size())
        die(what + ": not a decimal integer: '" + shown(s) + "'");
    if (errno == ERANGE) die(what + ": out of range: '" + shown(s) + "'");
    return v;
}

// The largest --div (clocks per sample) the harnesses and sim/run_model.py accept: a run
// clocks every edge, so the time it takes grows with it (4096: 24 kS/s at 100 MHz).
#define DIV_MAX 4096

// A whole-number option within lo..hi: 'OPT: not a decimal integer' or 'OPT: V is outside
// lo..hi' (V as written if beyond a long); sim/run_model.py says the same.
static long parse_bounded(const std::string &text, const std::string &opt, long lo, long hi,
                          const std::string &what = "") {
    errno = 0;
    char *end = nullptr;
    long v = std::strtol(text.c_str(), &end, 10);
    if (end == text.c_str() || end != text.c_str() + text.size())
        die(opt + ": not a decimal integer: '" + shown(text) + "'");
    if (errno == ERANGE || v < lo || v > hi)
        die(opt + ": " + (errno == ERANGE ? shown(text) : std::to_string(v)) + " is outside " +
            std::to_string(lo) + ".." + std::to_string(hi) + (what.empty() ? "" : " (" + what + ")"));
    return v;
}

// The line rule of the CSV input: trailing '\r', ' ' and '\n' and leading ' ' do not count.
static void trim(const char *&p, const char *&q) {
    while (q > p && (q[-1] == '\r' || q[-1] == ' ' || q[-1] == '\n')) q--;
    while (p < q && *p == ' ') p++;
}

// A field: a decimal integer (parse_long's rules) that is a signed ADC_W-bit code.
static long parse_field(const char *p, const char *q, const std::string &path, long ln,
                        const char *name) {
    static const long lo = -(1L << (ADC_W - 1)), hi = (1L << (ADC_W - 1)) - 1;
    trim(p, q);
    char tmp[64];
    if ((size_t)(q - p) < sizeof tmp) {
        // the common case without a std::string: strtol on a NUL-terminated copy
        std::memcpy(tmp, p, (size_t)(q - p));
        tmp[q - p] = '\0';
        errno = 0;
        char *end = nullptr;
        long v = std::strtol(tmp, &end, 10);
        // (every byte taken: a NUL inside the field would end strtol's string early)
        if (!errno && end != tmp && end == tmp + (q - p) && v >= lo && v <= hi) return v;
    }
    // long fields and every error
    const std::string where = path + ":" + std::to_string(ln) + ": " + name, text(p, q);
    errno = 0;
    char *end = nullptr;
    long v = std::strtol(text.c_str(), &end, 10);
    if (end == text.c_str() || end != text.c_str() + text.size())
        die(where + ": not a decimal integer: '" + shown(text) + "'");
    if (errno == ERANGE || v < lo || v > hi)
        die(where + ": code " + shown(text) + " out of the signed " + std::to_string(ADC_W) +
            "-bit range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
}

// A row's ref: a decimal integer (parse_long's rules), 0 or 1.
static int parse_ref(const char *p, const char *q, const std::string &path, long ln) {
    trim(p, q);
    if (q - p == 1 && (*p == '0' || *p == '1')) return *p - '0';      // the common case
    const std::string where = path + ":" + std::to_string(ln) + ": ref", text(p, q);
    errno = 0;
    char *end = nullptr;
    long v = std::strtol(text.c_str(), &end, 10);
    if (end == text.c_str() || end != text.c_str() + text.size())
        die(where + ": not a decimal integer: '" + shown(text) + "'");
    if (errno == ERANGE || (v != 0 && v != 1))
        die(where + ": must be 0 or 1, got '" + shown(text) + "'");
    return (int)v;
}

// The whole file is read at once and split into lines in place (std::getline and
// std::string per line were about 2 % of a run); messages name the file and line.
// ref: filled with each sample's ref if the file has the column (the return value: true),
// left empty if not (every sample's ref is 0).
static bool read_csv(const std::string &path, std::vector<int> &u1, std::vector<int> &u2,
                     std::vector<unsigned char> &ref) {
    struct stat st;
    if (stat(path.c_str(), &st) != 0) die("cannot open input '" + path + "': " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) die("input '" + path + "' is not a regular file");
    std::ifstream f(path, std::ios::binary);
    if (!f) die("cannot open input '" + path + "'");
    std::string text;
    try {
        text.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    } catch (const std::exception &e) {
        die("cannot read input '" + path + "': " + e.what());
    }
    const char *s = text.data(), *const end = s + text.size();
    auto next_line = [&](const char *&p, const char *&q) {
        if (s >= end) return false;
        p = s;
        q = static_cast<const char *>(std::memchr(s, '\n', (size_t)(end - s)));
        if (!q) q = end;
        s = q < end ? q + 1 : end;
        return true;
    };
    const char *p, *q;
    if (!next_line(p, q)) die(path + ":1: empty file (expected header 'u1,u2' or 'u1,u2,ref')");
    trim(p, q);
    const std::string header(p, q);
    if (header != "u1,u2" && header != "u1,u2,ref")
        die(path + ":1: header is '" + shown(p, q) + "', expected 'u1,u2' or 'u1,u2,ref'");
    const bool has_ref = header == "u1,u2,ref";
    long ln = 1;
    u1.reserve(text.size() / 8);
    u2.reserve(text.size() / 8);
    ref.clear();
    if (has_ref) ref.reserve(text.size() / 10);
    while (next_line(p, q)) {
        ln++;
        trim(p, q);
        if (p == q) continue;
        const char *c = static_cast<const char *>(std::memchr(p, ',', (size_t)(q - p)));
        const char *c2 = c ? static_cast<const char *>(std::memchr(c + 1, ',', (size_t)(q - c - 1)))
                           : nullptr;
        if (!has_ref && (!c || c2))
            die(path + ":" + std::to_string(ln) + ": expected two values 'u1,u2', got '" +
                shown(p, q) + "'");
        if (has_ref && (!c2 || std::memchr(c2 + 1, ',', (size_t)(q - c2 - 1))))
            die(path + ":" + std::to_string(ln) + ": expected three values 'u1,u2,ref', got '" +
                shown(p, q) + "'");
        long a = parse_field(p, c, path, ln, "u1");
        long b = parse_field(c + 1, has_ref ? c2 : q, path, ln, "u2");
        if (has_ref) ref.push_back((unsigned char)parse_ref(c2 + 1, q, path, ln));
        u1.push_back((int)a);
        u2.push_back((int)b);
    }
    if (u1.empty()) die(path + ": no samples after the header");
    return has_ref;
}

// A setting's reset value (sim/harness/regs.h).
static long setting_reset(const char *name) {
    for (int k = 0; k < FQ_N_SETTINGS; k++)
        if (!std::strcmp(FQ_SETTINGS[k].name, name)) return FQ_SETTINGS[k].reset;
    die(std::string("internal: no setting '") + name + "'");
}

// A setting's option value, within its field's legal values (the error names the option
// and the register field, as Settings::take does).
static long parse_setting(const std::string &text, const char *name) {
    for (int k = 0; k < FQ_N_SETTINGS; k++) {
        const FqSetting &f = FQ_SETTINGS[k];
        if (std::strcmp(f.name, name)) continue;
        std::string o = std::string("--") + f.name;
        for (char &c : o)
            if (c == '_') c = '-';
        return parse_bounded(text, o, f.lo, f.hi, std::string(f.reg) + "." + f.name);
    }
    die(std::string("internal: no setting '") + name + "'");
}

// A setting's value placed at its field's position (its register's other bits 0).
static uint32_t field_word(const char *name, long v) {
    for (int k = 0; k < FQ_N_SETTINGS; k++) {
        const FqSetting &f = FQ_SETTINGS[k];
        if (std::strcmp(f.name, name)) continue;
        const uint32_t mask = f.width >= 32 ? 0xFFFFFFFFu : ((1u << f.width) - 1u);
        return ((uint32_t)v & mask) << f.lsb;
    }
    die(std::string("internal: no setting '") + name + "'");
}

// The core's settings as options: --<field> VALUE for each field a register write stores
// (sim/harness/regs.h, generated from rtl/regs/finequad.rdl; '_' written '-'), except the
// coefficient bundle's (GAIN..C2: staged for a LOAD, which the harnesses do not make).
// Only the settings given are written; the others keep their reset values.
// sim/run_model.py takes the same options and names the same errors.
struct Settings {
    long value[FQ_N_SETTINGS];
    bool given[FQ_N_SETTINGS] = {};
    static bool bundle(const FqSetting &f) {
        return f.index >= FQ_GAIN && f.index <= FQ_C2;
    }
    static std::string option(const FqSetting &f) {
        std::string o = std::string("--") + f.name;
        for (char &c : o)
            if (c == '_') c = '-';
        return o;
    }
    // takes argv[i] (and its value, i advanced) if it names a setting
    bool take(int argc, char **argv, int &i) {
        for (int k = 0; k < FQ_N_SETTINGS; k++) {
            const FqSetting &f = FQ_SETTINGS[k];
            const std::string o = option(f);
            if (bundle(f) || o != argv[i]) continue;
            if (i + 1 >= argc) die("missing value after " + o);
            long v = parse_bounded(argv[++i], o, f.lo, f.hi, std::string(f.reg) + "." + f.name);
            value[k] = v;
            given[k] = true;
            return true;
        }
        return false;
    }
    // (word index, word) of each register a given setting is in: its settings as given or
    // at their reset values, its pulses 0; with home (--home) REF last, whether a setting
    // of it is given or not, with its pulse REF.home = 1 (homing armed from the start)
    std::vector<std::pair<int, uint32_t>> writes(bool home = false) const {
        std::vector<std::pair<int, uint32_t>> out;
        // a register's word: its settings as given, the others at their reset values
        auto word_of = [&](int idx) {
            uint32_t word = 0;
            for (int j = 0; j < FQ_N_SETTINGS; j++) {
                const FqSetting &f = FQ_SETTINGS[j];
                if (f.index != idx) continue;
                const long v = given[j] ? value[j] : f.reset;
                const uint32_t mask = f.width >= 32 ? 0xFFFFFFFFu : ((1u << f.width) - 1u);
                word |= ((uint32_t)v & mask) << f.lsb;
            }
            return word;
        };
        for (int k = 0; k < FQ_N_SETTINGS; k++) {
            if (!given[k]) continue;
            const int idx = FQ_SETTINGS[k].index;
            if (home && idx == FQ_REF) continue;
            bool done = false;
            for (const auto &w : out) done = done || w.first == idx;
            if (done) continue;
            out.emplace_back(idx, word_of(idx));
        }
        if (home) out.emplace_back(FQ_REF, word_of(FQ_REF) | FQ_REF_HOME_BM);
        return out;
    }
    // the options, for a usage line
    static std::string usage() {
        std::string u;
        for (int k = 0; k < FQ_N_SETTINGS; k++)
            if (!bundle(FQ_SETTINGS[k])) u += " [" + option(FQ_SETTINGS[k]) + " N]";
        return u;
    }
};

#endif  // FINEQUAD_HARNESS_INPUT_H
