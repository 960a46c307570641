// What the readers and writers share: the byte order of this machine, and the last step of every
// writer (a temporary file renamed into place, so no partial file is ever left).
#pragma once

#include "qex/io.h"

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

namespace qex::io_detail {

/// Whether this machine stores the most significant byte first.
inline bool big_endian_host() {
    const std::uint16_t one = 1;
    unsigned char c;
    std::memcpy(&c, &one, 1);
    return c == 0;
}

/// Closes the finished temporary file `tmp` and renames it to `path`; removes it on a problem.
IoError close_and_rename(std::FILE* f, const std::string& tmp, const std::string& path);

} // namespace qex::io_detail
