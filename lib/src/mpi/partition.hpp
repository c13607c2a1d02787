// The owner partition of a distributed run: Morton ranges of the global bounding box, balanced
// by points, found by a parallel bisection of the splitter keys; and the moves of points to
// their owners and of new normals back to the ranks that passed them.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <vector>

#include "pnf/cloud_view.hpp"
#include "spatial/spatial_order.hpp"

namespace pnf::mpi::detail {

// The bounding box of every rank's points, and the curve's frame: the box and frame one process
// would compute (morton_frame_of).
struct GlobalFrame {
  bool empty = true;  // no rank holds a point
  Vec3 low = {0, 0, 0}, high = {0, 0, 0};
  double extent = 0;  // largest side
  pnf::detail::MortonFrame morton;
  Vec3 centre() const { return {0.5 * (low[0] + high[0]), 0.5 * (low[1] + high[1]), 0.5 * (low[2] + high[2])}; }
};

// Collective.
GlobalFrame global_frame(MPI_Comm comm, const Vec3ArrayView& positions);

// The points a rank owns, in curve order: ascending (Morton key, global id), where a point's
// global id is its index in the concatenation of every rank's input in rank order. That is
// the order one process's morton_order gives, so owned point k is point first_global + k along
// the one process's curve.
struct OwnedPoints {
  std::vector<double> positions;  // n by 3, model units, as given
  std::vector<double> normals;    // n by 3, as given (not normalised)
  std::vector<std::uint64_t> gids;
  std::vector<int> source_rank;             // the rank that passed the point
  std::vector<std::uint64_t> source_index;  // its index there
  std::uint64_t first_global = 0;
  std::uint64_t total = 0;  // points over all ranks
  std::size_t size() const { return gids.size(); }
};

// Collective: moves every rank's points to their owners. `moved_bytes` gets the bytes this rank
// sent to other ranks.
OwnedPoints distribute(MPI_Comm comm, const CloudView& local, const GlobalFrame& frame, std::size_t& moved_bytes);

// Collective: sends `normals` (owned.size() by 3) back to the ranks that passed the points and
// writes those this rank passed into `out`, at their input index.
void return_normals(MPI_Comm comm, const OwnedPoints& owned, const std::vector<double>& normals,
                    MutableVec3ArrayView out);

// An MPI datatype of `bytes` contiguous bytes, committed; freed with the guard.
class ByteRecord {
 public:
  explicit ByteRecord(int bytes);
  ~ByteRecord();
  ByteRecord(const ByteRecord&) = delete;
  ByteRecord& operator=(const ByteRecord&) = delete;
  MPI_Datatype type() const { return type_; }

 private:
  MPI_Datatype type_;
};

// Exclusive prefix offsets of `counts`, as int for MPI, after checking they fit.
std::vector<int> displacements(const std::vector<int>& counts);

// Every rank's `mine` (a sample: under 2^31 values), concatenated in rank order, on every rank.
// Collective.
std::vector<double> gather_to_all(MPI_Comm comm, const std::vector<double>& mine);

}  // namespace pnf::mpi::detail
