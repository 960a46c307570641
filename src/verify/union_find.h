// Disjoint sets over 0..n-1 with path halving: the checker's one union-find (the components of
// a mesh). The extractor has its own (src/extract/union_find.h): the checker includes nothing of it.
#pragma once

#include <cstddef>
#include <numeric>
#include <vector>

namespace qex::verify_detail {

class UnionFind {
public:
    explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
    /// The representative of x's set.
    int find(int x) {
        while (parent_[static_cast<std::size_t>(x)] != x) {
            int& up = parent_[static_cast<std::size_t>(x)];
            x = up = parent_[static_cast<std::size_t>(up)];
        }
        return x;
    }
    /// Joins x's set to y's: y's representative (found first) represents both.
    void unite(int x, int y) {
        const int ry = find(y);
        parent_[static_cast<std::size_t>(find(x))] = ry;
    }

private:
    std::vector<int> parent_;
};

} // namespace qex::verify_detail
