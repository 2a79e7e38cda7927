// Command-line and CSV input rules shared by the Verilator harnesses (harness.cpp, the
// `make rtlsim` harness, and probe.cpp, the measurements of `make report`), so both read
// a recording alike and name what is wrong and where. Define HARNESS_TOOL (the name that
// starts every error message) and ADC_W before including it.
//
// CSV: the header 'u1,u2', then one 'u1,u2' pair of decimal ADC codes per line in the
// signed ADC_W-bit range; blank lines are skipped; a line's trailing '\r', ' ' and '\n'
// and leading ' ' do not count (a field's own leading and trailing spaces neither). An
// error exits with status 2 and a message 'TOOL: error: file:line: ...'.
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

[[noreturn]] static void die(const std::string &msg) {
    std::cerr << HARNESS_TOOL << ": error: " << msg << std::endl;
    std::exit(2);
}

static long parse_long(const std::string &s, const std::string &what) {
    errno = 0;
    char *end = nullptr;
    long v = std::strtol(s.c_str(), &end, 10);
    if (end == s.c_str() || end != s.c_str() + s.size())
        die(what + ": not a decimal integer: '" + s + "'");
    if (errno == ERANGE) die(what + ": out of range: '" + s + "'");
    return v;
}

// The line rules of the CSV input (as trim() of std::string did): trailing '\r', ' ' and
// '\n' and leading ' ' do not count.
static void trim(const char *&p, const char *&q) {
    while (q > p && (q[-1] == '\r' || q[-1] == ' ' || q[-1] == '\n')) q--;
    while (p < q && *p == ' ') p++;
}

static long parse_field(const char *p, const char *q, const std::string &path, long ln,
                        const char *name) {
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
        if (!errno && end != tmp && end == tmp + (q - p)) return v;
    }
    // long fields and every error
    return parse_long(std::string(p, q), path + ":" + std::to_string(ln) + ": " + name);
}

// The whole file is read at once and split into lines in place (std::getline and
// std::string per line were about 2 % of a run); messages name the file and line.
static void read_csv(const std::string &path, std::vector<int> &u1, std::vector<int> &u2) {
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
    if (!next_line(p, q)) die(path + ":1: empty file (expected header 'u1,u2')");
    trim(p, q);
    if (std::string(p, q) != "u1,u2")
        die(path + ":1: header is '" + std::string(p, q) + "', expected 'u1,u2'");
    const long lo = -(1L << (ADC_W - 1)), hi = (1L << (ADC_W - 1)) - 1;
    long ln = 1;
    u1.reserve(text.size() / 8);
    u2.reserve(text.size() / 8);
    while (next_line(p, q)) {
        ln++;
        trim(p, q);
        if (p == q) continue;
        const char *c = static_cast<const char *>(std::memchr(p, ',', (size_t)(q - p)));
        if (!c || std::memchr(c + 1, ',', (size_t)(q - c - 1)))
            die(path + ":" + std::to_string(ln) + ": expected two values 'u1,u2', got '" +
                std::string(p, q) + "'");
        long a = parse_field(p, c, path, ln, "u1");
        long b = parse_field(c + 1, q, path, ln, "u2");
        if (a < lo || a > hi || b < lo || b > hi)
            die(path + ":" + std::to_string(ln) + ": code out of the signed " +
                std::to_string(ADC_W) + "-bit range [" + std::to_string(lo) + ", " +
                std::to_string(hi) + "]: '" + std::string(p, q) + "'");
        u1.push_back((int)a);
        u2.push_back((int)b);
    }
    if (u1.empty()) die(path + ": no samples after the header");
}

#endif  // FINEQUAD_HARNESS_INPUT_H
