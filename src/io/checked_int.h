// The one way a number read from a file, or given by a caller, becomes an integer: checked.
// A plain cast of a double that is out of the target's range (or NaN, or infinite) is undefined
// behaviour, and a cast of a fraction silently drops it; every reader (OBJ, PLY, VVAL, the
// feature edges of the CLI, the polygon OBJ of `qex check`) and the Python and C entry points
// convert through checked_int() instead, and refuse the value with their usual error when it
// says no.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <type_traits>

namespace qex::io_detail {

/// Whether `x` is an integer that the integer type T holds; if so `out` is that integer (else
/// `out` is left alone). A floating `x` must be finite and integral (-0 is 0); its value is
/// taken as it is, so a decimal integer beyond 2^53 has already been rounded by the parser (the
/// readers only take integers of 32 bits, which every double holds exactly). An integral `x`
/// must lie in T's range.
template <class T, class From>
bool checked_int(From x, T& out) {
    static_assert(std::is_integral_v<T> && !std::is_same_v<T, bool>, "an integer target");
    static_assert(std::is_arithmetic_v<From>, "a number to convert");
    if constexpr (std::is_floating_point_v<From>) {
        // T holds [-2^d, 2^d) (signed) or [0, 2^d) (unsigned), d its value bits: powers of two,
        // exact in every floating type, so the comparisons are exact. NaN fails them all.
        const From limit = std::ldexp(From(1), std::numeric_limits<T>::digits);
        const From lowest = std::is_signed_v<T> ? -limit : From(0);
        if (!(x >= lowest && x < limit) || x != std::trunc(x)) return false;
        out = static_cast<T>(x); // in range and integral: exact
        return true;
    } else {
        using Wide = std::conditional_t<std::is_signed_v<From>, std::intmax_t, std::uintmax_t>;
        const auto w = static_cast<Wide>(x); // the same value, in 64 bits
        bool fits;
        if constexpr (std::is_signed_v<From> == std::is_signed_v<T>)
            fits = w >= static_cast<Wide>(std::numeric_limits<T>::min()) &&
                   w <= static_cast<Wide>(std::numeric_limits<T>::max());
        else if constexpr (std::is_signed_v<From>) // signed into unsigned
            fits = w >= 0 && static_cast<std::uintmax_t>(w) <= std::numeric_limits<T>::max();
        else // unsigned into signed
            fits = w <= static_cast<std::uintmax_t>(std::numeric_limits<T>::max());
        if (!fits) return false;
        out = static_cast<T>(x);
        return true;
    }
}

/// checked_int() where a refusal cannot be reported (a drawing, a summary of a map already
/// validated): the integer part of `x`, or the nearest bound of T beyond its range, or 0 for NaN.
template <class T, class From>
T clamped_int(From x) {
    T out{};
    if constexpr (std::is_floating_point_v<From>) {
        if (std::isnan(x)) return T{0};
        if (checked_int(std::trunc(x), out)) return out;
    } else if (checked_int(x, out)) {
        return out;
    }
    return x > From(0) ? std::numeric_limits<T>::max() : std::numeric_limits<T>::min();
}

/// A number read from a file, for an error message: integers below 10^17 in full, others with
/// 17 significant digits ("6.6666666666666666e+95", "nan", "inf"); never a cast.
inline std::string number_text(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}

} // namespace qex::io_detail
