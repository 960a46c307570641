// The values of a PLY file's data section: the scalar types a header may name, and a reader of
// one value at a time in the file's format (ASCII, binary little or big endian). An ASCII value
// of an integer type must be an integer that type holds (checked_int.h): a 96-digit index or an
// "inf" list count is refused where it is read, with its place.
#pragma once

#include "io/checked_int.h"
#include "io/file_io.h"

#include <fast_float/fast_float.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <system_error>
#include <utility>

namespace qex::io_detail {

enum class PlyType { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };
enum class PlyFormat { Ascii, BinaryLittle, BinaryBig };

/// The type a header names (`char`, `int8`, `uchar`, ... `double`, `float64`); false if none.
inline bool parse_type(std::string_view name, PlyType& t) {
    static const std::pair<const char*, PlyType> kNames[] = {
        {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::Uint8},
        {"uint8", PlyType::Uint8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
        {"ushort", PlyType::Uint16},  {"uint16", PlyType::Uint16},   {"int", PlyType::Int32},
        {"int32", PlyType::Int32},    {"uint", PlyType::Uint32},     {"uint32", PlyType::Uint32},
        {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
        {"float64", PlyType::Float64}};
    for (const auto& [n, type] : kNames)
        if (name == n) {
            t = type;
            return true;
        }
    return false;
}

/// The type's name in messages.
inline const char* type_name(PlyType t) {
    static const char* const kNames[] = {"int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
    return kNames[static_cast<int>(t)];
}

/// Whether the type holds integers (a list count must have one).
inline bool is_integer(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

/// The bytes a binary value of the type takes.
inline std::size_t size_of(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::Uint8: return 1;
        case PlyType::Int16:
        case PlyType::Uint16: return 2;
        case PlyType::Int32:
        case PlyType::Uint32:
        case PlyType::Float32: return 4;
        case PlyType::Float64: return 8;
    }
    return 1;
}

/// Whether `x` is a value of type `t`: an integer it holds, for an integer type.
inline bool fits_type(double x, PlyType t) {
    const auto holds = [x](auto v) { return checked_int(x, v); };
    switch (t) {
        case PlyType::Int8: return holds(std::int8_t{});
        case PlyType::Uint8: return holds(std::uint8_t{});
        case PlyType::Int16: return holds(std::int16_t{});
        case PlyType::Uint16: return holds(std::uint16_t{});
        case PlyType::Int32: return holds(std::int32_t{});
        case PlyType::Uint32: return holds(std::uint32_t{});
        case PlyType::Float32:
        case PlyType::Float64: return true;
    }
    return true;
}

/// What reading a value gave.
enum class ValueRead {
    Ok,
    Missing,  ///< the data ended, or (ASCII) the next word is not a number
    NotOfType ///< (ASCII) a number that is not a value of its integer type (a fraction, out of range, inf)
};

/// Reads the values of the data section, one at a time, in the file's format.
class ValueReader {
public:
    ValueReader(const char* begin, const char* p, const char* end, PlyFormat f)
        : begin_(begin), p_(p), end_(end), f_(f) {}

    /// The next value of type `t`, into `x`.
    ValueRead read(PlyType t, double& x) {
        if (f_ == PlyFormat::Ascii) return read_ascii(t, x);
        const std::size_t n = size_of(t);
        if (static_cast<std::size_t>(end_ - p_) < n) return ValueRead::Missing;
        unsigned char b[8];
        std::memcpy(b, p_, n);
        p_ += n;
        if (big_endian_host() != (f_ == PlyFormat::BinaryBig)) std::reverse(b, b + n);
        switch (t) {
            case PlyType::Int8: x = load<std::int8_t>(b); break;
            case PlyType::Uint8: x = b[0]; break;
            case PlyType::Int16: x = load<std::int16_t>(b); break;
            case PlyType::Uint16: x = load<std::uint16_t>(b); break;
            case PlyType::Int32: x = load<std::int32_t>(b); break;
            case PlyType::Uint32: x = load<std::uint32_t>(b); break;
            case PlyType::Float32: x = load<float>(b); break;
            case PlyType::Float64: x = load<double>(b); break;
        }
        return ValueRead::Ok;
    }
    std::int64_t offset() const { return p_ - begin_; }
    /// The smallest number of bytes a value takes (for bounding counts by the bytes left).
    std::size_t min_size(PlyType t) const { return f_ == PlyFormat::Ascii ? 2 : size_of(t); }
    std::size_t left() const { return static_cast<std::size_t>(end_ - p_); }
    bool only_blanks_left() {
        skip_space();
        return p_ >= end_;
    }

private:
    template <class T>
    static T load(const unsigned char* b) {
        T v;
        std::memcpy(&v, b, sizeof v);
        return v;
    }
    void skip_space() {
        while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\r' || *p_ == '\n')) ++p_;
    }
    ValueRead read_ascii(PlyType t, double& x) {
        skip_space();
        if (p_ >= end_) return ValueRead::Missing;
        const char* from = p_;
        if (*from == '+') ++from;
        const auto r = fast_float::from_chars(from, end_, x);
        if (r.ec != std::errc() || r.ptr == from) return ValueRead::Missing;
        if (r.ptr < end_ && !(*r.ptr == ' ' || *r.ptr == '\t' || *r.ptr == '\r' || *r.ptr == '\n'))
            return ValueRead::Missing;
        p_ = r.ptr;
        return fits_type(x, t) ? ValueRead::Ok : ValueRead::NotOfType;
    }

    const char* begin_;
    const char* p_;
    const char* end_;
    PlyFormat f_;
};

} // namespace qex::io_detail
