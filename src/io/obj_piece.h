// One piece of an OBJ map (a run of whole lines), parsed without knowing what came before it.
// The OBJ reader (obj_reader.cpp) cuts a file into pieces, parses them on several threads and
// places their records in file order.
#pragma once

#include "qex/io.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace qex::io_detail {

/// What one piece of a file holds: face indices are kept as written, with the piece's own
/// record counts at the face, and lines are counted from the piece's start.
struct Piece {
    struct Face {
        std::array<std::int32_t, 3> v, t; // as written (1-based or negative, relative)
        std::int32_t line;                // line in the piece (1 = its first)
        std::int32_t nv, nvt;             // `v` and `vt` records of the piece before the face
    };
    std::vector<std::array<double, 3>> positions;
    std::vector<std::array<double, 2>> vts;
    std::vector<Face> faces;
    /// Lines consumed, set only when the whole piece parsed. Every piece but a file's last ends
    /// with a line end, so for them this is the number of line ends.
    std::int64_t lines = 0;
    /// The piece's first problem (parsing stopped there), its line counted in the piece.
    bool failed = false;
    IoError::Code code = IoError::Code::Syntax;
    std::int64_t error_line = 0;
    std::string error;
};

/// Parses whole lines [begin, end) into `piece`, stopping at the first problem.
void parse_piece(const char* begin, const char* end, Piece& piece);

} // namespace qex::io_detail
