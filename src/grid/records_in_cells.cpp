// SPDX-License-Identifier: Apache-2.0
#include "grid/records_in_cells.hpp"

#include "byte_order.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>

namespace lasmesh {

namespace {

// At most this many runs an axis (8 MiB of table): the deck's 80 m at millimetres take 80,000
// runs of one raw value each, a table in a core's cache.
constexpr std::uint64_t most_runs = std::uint64_t{1} << 22;
constexpr std::size_t block = 4096; // records a task keeps of

} // namespace

RecordsInCells::RecordsInCells(const std::array<AxisCells, 3>& axes, const CellSet& cells, std::size_t record_length)
    : cells_(&cells), length_(record_length) {
    for (int a = 0; a < 3; ++a) {
        const std::vector<std::int64_t>& starts = axes[a].starts;
        Axis& axis = axes_[a];
        axis.first = starts.front();
        axis.span = static_cast<std::uint64_t>(starts.back() - starts.front());
        axis.starts = starts.data();
        if (axis.span == 0) continue; // no raw value lies inside
        while ((axis.span - 1) >> axis.shift >= most_runs) ++axis.shift;
        runs_[a].resize(((axis.span - 1) >> axis.shift) + 1);
        std::size_t c = 0;
        for (std::size_t run = 0; run < runs_[a].size(); ++run) {
            const std::int64_t raw = axis.first + static_cast<std::int64_t>(run << axis.shift);
            while (raw >= starts[c + 1]) ++c;
            runs_[a][run] = static_cast<std::uint16_t>(c);
        }
        axis.cell_of_run = runs_[a].data();
    }
}

bool RecordsInCells::cell_of(const std::byte* record, const std::array<Axis, 3>& axes,
                             std::array<std::uint64_t, 3>& cell) {
    for (int a = 0; a < 3; ++a) {
        const Axis& axis = axes[a];
        const std::int64_t raw = load_le<std::int32_t>(record + 4 * a);
        const auto from_first = static_cast<std::uint64_t>(raw - axis.first);
        if (from_first >= axis.span) return false; // outside the grid, either side: one compare
        std::uint64_t c = axis.cell_of_run[from_first >> axis.shift];
        if (axis.shift > 0)
            while (raw >= axis.starts[c + 1]) ++c;
        cell[a] = c;
    }
    return true;
}

std::size_t RecordsInCells::keep(std::byte* records, std::size_t count) const {
    // Each block keeps its records at its front, first finding which (no branch on the answer,
    // which would be mispredicted at every kept record), then moving them; then the blocks' kept
    // runs are moved together, in order.
    std::vector<std::size_t> kept_in((count + block - 1) / block, 0);
    const std::array<Axis, 3> axes = axes_;
    const CellSet& cells = *cells_;
    tbb::parallel_for(std::size_t{0}, kept_in.size(), [&](std::size_t b) {
        const std::size_t length = length_;
        std::byte* front = records + b * block * length;
        const std::size_t n = std::min(count - b * block, block);
        std::array<std::uint16_t, block> rows;
        std::size_t kept = 0;
        for (std::size_t i = 0; i < n; ++i) {
            rows[kept] = static_cast<std::uint16_t>(i);
            std::array<std::uint64_t, 3> cell{};
            kept += cell_of(front + i * length, axes, cell) && cells.contains(cell[0], cell[1], cell[2]);
        }
        for (std::size_t k = 0; k < kept; ++k)
            if (rows[k] != k) std::memmove(front + k * length, front + rows[k] * length, length);
        kept_in[b] = kept;
    });
    std::size_t kept = 0;
    for (std::size_t b = 0; b < kept_in.size(); ++b) {
        if (kept != b * block && kept_in[b] > 0)
            std::memmove(records + kept * length_, records + b * block * length_, kept_in[b] * length_);
        kept += kept_in[b];
    }
    return kept;
}

} // namespace lasmesh
