#include "halo.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "agreement.hpp"

namespace pnf::mpi::detail {
namespace {

// Grid cells are wider than the distance by this fraction of it and of the cloud's extent, so
// that two points within the distance never land two cells apart through rounding (the cell
// index of a coordinate is computed to a few ulps of the extent, 2.2e-16 of it each): some 500
// times what rounding needs. 1e-9 widened the cells by the extent's billionth, a whole unit
// where one stray point lies 1e9 away from a cloud a few units wide, and each rank's halo took
// most of the cloud.
constexpr double kCellMargin = 1e-12;

using Cell = std::array<std::int64_t, 3>;
struct CellHash {
  std::size_t operator()(const Cell& c) const {
    std::uint64_t h = std::uint64_t(c[0]) * 0x9E3779B97F4A7C15ULL;
    h ^= std::uint64_t(c[1]) * 0xC2B2AE3D27D4EB4FULL + (h << 6) + (h >> 2);
    h ^= std::uint64_t(c[2]) * 0x165667B19E3779F9ULL + (h << 6) + (h >> 2);
    return std::size_t(h);
  }
};

Cell cell_of(const double* p, const Vec3& low, double size) {
  return {std::int64_t(std::floor((p[0] - low[0]) / size)), std::int64_t(std::floor((p[1] - low[1]) / size)),
          std::int64_t(std::floor((p[2] - low[2]) / size))};
}

// low[3], high[3] of n points (n by 3); empty boxes are inverted.
std::array<double, 6> box_of(const std::vector<double>& points) {
  const double inf = std::numeric_limits<double>::infinity();
  std::array<double, 6> box = {inf, inf, inf, -inf, -inf, -inf};
  for (std::size_t i = 0; i < points.size() / 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      box[std::size_t(k)] = std::min(box[std::size_t(k)], points[3 * i + std::size_t(k)]);
      box[std::size_t(3 + k)] = std::max(box[std::size_t(3 + k)], points[3 * i + std::size_t(k)]);
    }
  }
  return box;
}

}  // namespace

std::vector<std::vector<std::uint32_t>> points_near(MPI_Comm comm, const std::vector<double>& sources,
                                                    const std::vector<double>& targets, double width,
                                                    const GlobalFrame& frame) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const std::size_t n = sources.size() / 3;
  std::vector<std::vector<std::uint32_t>> lists(static_cast<std::size_t>(ranks));

  // Every rank's target box then source box (12 values; inverted when empty).
  std::vector<double> boxes(12 * std::size_t(ranks));
  {
    std::array<double, 12> mine;
    const auto t = box_of(targets), s = box_of(sources);
    std::copy(t.begin(), t.end(), mine.begin());
    std::copy(s.begin(), s.end(), mine.begin() + 6);
    check_mpi(MPI_Allgather(mine.data(), 12, MPI_DOUBLE, boxes.data(), 12, MPI_DOUBLE, comm), "MPI_Allgather");
  }
  const bool everything = !(width < 2 * frame.extent) || !(frame.extent > 0);
  const double size = width * (1 + kCellMargin) + frame.extent * kCellMargin;
  // True when rank t's targets may lie within `width` of rank s's sources.
  auto related = [&](int t, int s) {
    if (t == s) return false;
    const double* tb = &boxes[12 * std::size_t(t)];
    const double* sb = &boxes[12 * std::size_t(s) + 6];
    for (int k = 0; k < 3; ++k) {
      if (!(tb[k] <= tb[3 + k]) || !(sb[k] <= sb[3 + k])) return false;  // an empty set
      if (!everything && (tb[k] - size > sb[3 + k] || sb[k] > tb[3 + k] + size)) return false;
    }
    return true;
  };
  if (everything) {
    for (int q = 0; q < ranks; ++q) {
      if (!related(q, rank)) continue;
      lists[std::size_t(q)].resize(n);
      for (std::size_t i = 0; i < n; ++i) lists[std::size_t(q)][i] = std::uint32_t(i);
    }
    return lists;
  }

  // My occupied target cells go to every rank whose sources may be near them.
  std::vector<Cell> target_cells;
  for (std::size_t i = 0; i < targets.size() / 3; ++i)
    target_cells.push_back(cell_of(&targets[3 * i], frame.low, size));
  std::sort(target_cells.begin(), target_cells.end());
  target_cells.erase(std::unique(target_cells.begin(), target_cells.end()), target_cells.end());
  std::vector<int> send_counts(static_cast<std::size_t>(ranks), 0), recv_counts(static_cast<std::size_t>(ranks), 0);
  std::vector<int> send_displs(static_cast<std::size_t>(ranks), 0);
  std::vector<Cell> outgoing;
  for (int q = 0; q < ranks; ++q) {
    send_displs[std::size_t(q)] = int(outgoing.size());
    if (!related(rank, q)) continue;
    send_counts[std::size_t(q)] = int(target_cells.size());
    outgoing.insert(outgoing.end(), target_cells.begin(), target_cells.end());
  }
  std::vector<Cell>().swap(target_cells);
  check_mpi(MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm), "MPI_Alltoall");
  const std::vector<int> recv_displs = displacements(recv_counts);
  std::vector<Cell> incoming(std::size_t(recv_displs.back()) + std::size_t(recv_counts.back()));
  ByteRecord type(int(sizeof(Cell)));
  check_mpi(MPI_Alltoallv(outgoing.data(), send_counts.data(), send_displs.data(), type.type(), incoming.data(),
                          recv_counts.data(), recv_displs.data(), type.type(), comm),
            "MPI_Alltoallv");
  std::vector<Cell>().swap(outgoing);

  // Which ranks have a target in each cell.
  std::unordered_map<Cell, std::vector<int>, CellHash> wanted;
  for (int q = 0; q < ranks; ++q) {
    for (int i = 0; i < recv_counts[std::size_t(q)]; ++i) {
      wanted[incoming[std::size_t(recv_displs[std::size_t(q)] + i)]].push_back(q);
    }
  }
  std::vector<Cell>().swap(incoming);
  if (wanted.empty()) return lists;

  // A source within `width` of a target lies at most one cell away from it on every axis.
  std::unordered_map<Cell, std::vector<int>, CellHash> near_ranks;
  for (std::size_t i = 0; i < n; ++i) {
    const Cell cell = cell_of(&sources[3 * i], frame.low, size);
    auto found = near_ranks.find(cell);
    if (found == near_ranks.end()) {
      std::vector<int> who;
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          for (std::int64_t dz = -1; dz <= 1; ++dz) {
            auto w = wanted.find({cell[0] + dx, cell[1] + dy, cell[2] + dz});
            if (w != wanted.end()) who.insert(who.end(), w->second.begin(), w->second.end());
          }
        }
      }
      std::sort(who.begin(), who.end());
      who.erase(std::unique(who.begin(), who.end()), who.end());
      found = near_ranks.emplace(cell, std::move(who)).first;
    }
    for (int q : found->second) lists[std::size_t(q)].push_back(std::uint32_t(i));
  }
  return lists;
}

HaloPlan::~HaloPlan() {
  if (graph_ != MPI_COMM_NULL) MPI_Comm_free(&graph_);
}

namespace {

// Sends rows of `values` (n by 3) picked by `lists` to each rank; returns what arrives, by
// sender rank. recv_counts gets the rows from each rank.
std::vector<double> send_rows(MPI_Comm comm, const std::vector<double>& values,
                              const std::vector<std::vector<std::uint32_t>>& lists, std::vector<int>& recv_counts) {
  const int ranks = int(lists.size());
  std::vector<int> send_counts(lists.size(), 0);
  for (int q = 0; q < ranks; ++q) send_counts[std::size_t(q)] = int(lists[std::size_t(q)].size());
  const std::vector<int> send_displs = displacements(send_counts);
  std::vector<double> out;
  out.reserve(3 * (std::size_t(send_displs.back()) + std::size_t(send_counts.back())));
  for (const auto& list : lists) {
    for (std::uint32_t i : list) out.insert(out.end(), &values[3 * i], &values[3 * i] + 3);
  }
  recv_counts.assign(static_cast<std::size_t>(ranks), 0);
  check_mpi(MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm), "MPI_Alltoall");
  const std::vector<int> recv_displs = displacements(recv_counts);
  std::vector<double> in(3 * (std::size_t(recv_displs.back()) + std::size_t(recv_counts.back())));
  ByteRecord type(int(3 * sizeof(double)));
  check_mpi(MPI_Alltoallv(out.data(), send_counts.data(), send_displs.data(), type.type(), in.data(),
                          recv_counts.data(), recv_displs.data(), type.type(), comm),
            "MPI_Alltoallv");
  return in;
}

}  // namespace

std::vector<double> send_positions(MPI_Comm comm, const std::vector<double>& positions,
                                   const std::vector<std::vector<std::uint32_t>>& send_lists) {
  std::vector<int> recv_counts;
  return send_rows(comm, positions, send_lists, recv_counts);
}

void HaloPlan::build(MPI_Comm comm, const OwnedPoints& owned, const std::vector<std::vector<std::uint32_t>>& send_lists,
                     std::vector<double>& halo_positions, std::vector<double>& halo_normals) {
  std::vector<int> recv_counts;
  halo_positions = send_rows(comm, owned.positions, send_lists, recv_counts);
  halo_normals = send_rows(comm, owned.normals, send_lists, recv_counts);
  halo_points_ = halo_positions.size() / 3;
  const int ranks = int(send_lists.size());
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  for (int q = 0; q < ranks; ++q) {
    const auto& list = send_lists[std::size_t(q)];
    if (!list.empty()) {
      out_ranks_.push_back(q);
      send_displs_.push_back(int(send_index_.size()));
      send_counts_.push_back(int(list.size()));
      send_index_.insert(send_index_.end(), list.begin(), list.end());
    }
    if (recv_counts[std::size_t(q)] > 0) {
      in_ranks_.push_back(q);
      recv_counts_.push_back(recv_counts[std::size_t(q)]);
    }
  }
  recv_displs_ = displacements(recv_counts_);
  moved_bytes_ = 2 * bytes_sent_per_pass();
  check_mpi(MPI_Dist_graph_create_adjacent(comm, int(in_ranks_.size()), in_ranks_.data(), MPI_UNWEIGHTED,
                                           int(out_ranks_.size()), out_ranks_.data(), MPI_UNWEIGHTED, MPI_INFO_NULL,
                                           /*reorder=*/0, &graph_),
            "MPI_Dist_graph_create_adjacent");
}

void HaloPlan::exchange(const std::vector<double>& owned_normals, std::vector<double>& halo_normals) const {
  send_buffer_.resize(3 * send_index_.size());
  for (std::size_t j = 0; j < send_index_.size(); ++j) {
    std::copy_n(&owned_normals[3 * std::size_t(send_index_[j])], 3, &send_buffer_[3 * j]);
  }
  halo_normals.resize(3 * halo_points_);
  ByteRecord type(int(3 * sizeof(double)));
  check_mpi(MPI_Neighbor_alltoallv(send_buffer_.data(), send_counts_.data(), send_displs_.data(), type.type(),
                                   halo_normals.data(), recv_counts_.data(), recv_displs_.data(), type.type(), graph_),
            "MPI_Neighbor_alltoallv");
}

}  // namespace pnf::mpi::detail
