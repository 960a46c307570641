// A small reader of fuzzer bytes (no dependency on clang's FuzzedDataProvider, so gcc builds
// compile every target).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace qex::fuzz {

/// Reports a broken invariant on stderr (the replay runs many inputs; this says which check) and
/// aborts, which the fuzzer records as a crash.
[[noreturn]] inline void fail(const std::string& why) {
    std::fprintf(stderr, "invariant broken: %s\n", why.c_str());
    std::abort();
}

class Bytes {
public:
    Bytes(const std::uint8_t* data, std::size_t size) : p_(data), end_(data + size) {}
    bool empty() const { return p_ >= end_; }
    std::uint8_t byte() { return p_ < end_ ? *p_++ : 0; }
    /// An integer in [lo, hi].
    int range(int lo, int hi) { return lo + static_cast<int>(u32() % static_cast<std::uint32_t>(hi - lo + 1)); }
    std::uint32_t u32() {
        std::uint32_t v = 0;
        for (int i = 0; i < 4; ++i) v = v << 8 | byte();
        return v;
    }
    /// Raw bits of a double (any value, NaN and Inf included).
    double raw_double() {
        std::uint64_t bits = 0;
        for (int i = 0; i < 8; ++i) bits = bits << 8 | byte();
        double d;
        std::memcpy(&d, &bits, sizeof d);
        return d;
    }
    /// A double in [-1, 1].
    double unit() { return static_cast<double>(u32()) / 2147483647.5 - 1.0; }

private:
    const std::uint8_t* p_;
    const std::uint8_t* end_;
};

} // namespace qex::fuzz
