// Halos of a distributed run: which of a rank's points lie within a distance of another rank's
// points (found exactly, as a superset, through the occupied cells of a grid as wide as the
// distance), sending them once, and the per-pass exchange of their new normals on a
// distributed-graph communicator.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <vector>

#include "partition.hpp"

namespace pnf::mpi::detail {

// Collective. For every rank q: the indices of this rank's `sources` (n by 3, model units)
// that lie within `width` (Euclidean, model units, inclusive) of one of q's `targets`, in
// ascending order; none for q = this rank. A superset: every such point is listed (the grid
// cells are a hair wider than `width` against rounding), and a few farther ones may be. A
// width that is infinite or wider than the whole cloud lists every source for every rank that
// has targets.
std::vector<std::vector<std::uint32_t>> points_near(MPI_Comm comm, const std::vector<double>& sources,
                                                    const std::vector<double>& targets, double width,
                                                    const GlobalFrame& frame);

// The per-pass exchange of the halo's normals: each rank sends its listed points' normals to
// the ranks whose halo holds them and receives its halo's, in halo order (by owner rank, then in
// the owner's list order). Owns the graph communicator.
class HaloPlan {
 public:
  HaloPlan() = default;
  ~HaloPlan();
  HaloPlan(const HaloPlan&) = delete;
  HaloPlan& operator=(const HaloPlan&) = delete;

  // Collective: sends the listed points (positions and normals of `owned`) to the ranks that
  // need them, once, and builds the graph. `send_lists` as points_near returns them.
  // halo_positions and halo_normals get the received points, H by 3.
  void build(MPI_Comm comm, const OwnedPoints& owned, const std::vector<std::vector<std::uint32_t>>& send_lists,
             std::vector<double>& halo_positions, std::vector<double>& halo_normals);

  // Collective over the graph: `owned_normals` (owned by 3) in, the halo's (H by 3) out.
  void exchange(const std::vector<double>& owned_normals, std::vector<double>& halo_normals) const;

  std::size_t halo_points() const { return halo_points_; }
  std::size_t bytes_sent_per_pass() const { return 3 * sizeof(double) * send_index_.size(); }
  std::size_t messages_per_pass() const { return out_ranks_.size(); }
  std::size_t bytes_moved() const { return moved_bytes_; }

 private:
  MPI_Comm graph_ = MPI_COMM_NULL;
  std::vector<int> out_ranks_, in_ranks_;
  std::vector<int> send_counts_, send_displs_, recv_counts_, recv_displs_;  // per neighbour, in points
  std::vector<std::uint32_t> send_index_;                                   // owned indices, grouped by out-neighbour
  std::size_t halo_points_ = 0;
  std::size_t moved_bytes_ = 0;
  mutable std::vector<double> send_buffer_;
};

// Positions only, for the mean-radius estimate: the listed points' positions, H by 3.
std::vector<double> send_positions(MPI_Comm comm, const std::vector<double>& positions,
                                   const std::vector<std::vector<std::uint32_t>>& send_lists);

}  // namespace pnf::mpi::detail
