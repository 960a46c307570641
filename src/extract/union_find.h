// Disjoint sets over 0..n-1 with path halving: the extractor's one union-find (collapses glue
// vertices, merging glues q-vertex clones).
#pragma once

#include <cstddef>
#include <numeric>
#include <vector>

namespace qex::detail {

class UnionFind {
public:
    explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
    /// The representative of x's set.
    int find(int x) {
        while (parent_[static_cast<std::size_t>(x)] != x)
            x = parent_[static_cast<std::size_t>(x)] =
                parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(x)])];
        return x;
    }
    /// Makes `into` the representative of `from`'s set (both must be representatives).
    void attach(int from, int into) { parent_[static_cast<std::size_t>(from)] = into; }

private:
    std::vector<int> parent_;
};

} // namespace qex::detail
