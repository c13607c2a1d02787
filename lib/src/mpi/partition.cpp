#include "partition.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

#include "agreement.hpp"

namespace pnf::mpi::detail {
namespace {

// A point on its way to its owner.
struct PointRecord {
  double position[3];
  double normal[3];
  std::uint64_t gid;
  std::uint64_t source_index;
};

// Keys hold 3 x 21 bits: every splitter lies in [0, 2^63].
constexpr std::uint64_t kKeyLimit = std::uint64_t(1) << 63;

// P - 1 splitter keys: owner(key) = number of splitters <= key. Splitter j is the least key s
// with at least j * N / P points below it, found by bisection on every rank at once (64 rounds
// of one allreduce of P - 1 counts): exact balance up to points that share a key.
std::vector<std::uint64_t> find_splitters(MPI_Comm comm, const std::vector<std::uint64_t>& sorted_keys,
                                          std::uint64_t total, int ranks) {
  const std::size_t m = std::size_t(ranks - 1);
  std::vector<std::uint64_t> low(m, 0), high(m, kKeyLimit), target(m);
  for (std::size_t j = 0; j < m; ++j) {
    target[j] = std::uint64_t((unsigned __int128)(j + 1) * total / std::uint64_t(ranks));
  }
  std::vector<std::uint64_t> below(m);
  for (int round = 0; round < 65; ++round) {
    bool done = true;
    for (std::size_t j = 0; j < m; ++j) {
      if (low[j] < high[j]) done = false;
      const std::uint64_t mid = low[j] + (high[j] - low[j]) / 2;
      below[j] = std::uint64_t(std::lower_bound(sorted_keys.begin(), sorted_keys.end(), mid) - sorted_keys.begin());
    }
    if (done) break;  // alike on every rank: low and high evolve from the same global counts
    check_mpi(MPI_Allreduce(MPI_IN_PLACE, below.data(), int(m), MPI_UINT64_T, MPI_SUM, comm), "MPI_Allreduce");
    for (std::size_t j = 0; j < m; ++j) {
      if (low[j] >= high[j]) continue;
      const std::uint64_t mid = low[j] + (high[j] - low[j]) / 2;
      if (below[j] >= target[j]) {
        high[j] = mid;
      } else {
        low[j] = mid + 1;
      }
    }
  }
  return low;
}

}  // namespace

ByteRecord::ByteRecord(int bytes) {
  MPI_Type_contiguous(bytes, MPI_BYTE, &type_);
  MPI_Type_commit(&type_);
}
ByteRecord::~ByteRecord() { MPI_Type_free(&type_); }

std::vector<int> displacements(const std::vector<int>& counts) {
  std::vector<int> out(counts.size());
  long long sum = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    out[i] = int(sum);
    sum += counts[i];
    if (sum > std::numeric_limits<int>::max()) {
      throw Error(ErrorCode::invalid_argument, "more than 2^31 records to one rank in one exchange: use more ranks");
    }
  }
  return out;
}

std::vector<double> gather_to_all(MPI_Comm comm, const std::vector<double>& mine) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  int count = int(mine.size());  // samples: a few hundred thousand values at most
  std::vector<int> counts(static_cast<std::size_t>(ranks));
  check_mpi(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm), "MPI_Allgather");
  const std::vector<int> displs = displacements(counts);
  std::vector<double> all(std::size_t(displs.back()) + std::size_t(counts.back()));
  check_mpi(MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, comm),
            "MPI_Allgatherv");
  return all;
}

GlobalFrame global_frame(MPI_Comm comm, const Vec3ArrayView& positions) {
  const double inf = std::numeric_limits<double>::infinity();
  double box[6] = {inf, inf, inf, inf, inf, inf};  // low, then -high, so one MIN reduces both
  for (std::size_t i = 0; i < positions.count; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double v = positions.get(i, k);
      box[k] = std::min(box[k], v);
      box[3 + k] = std::min(box[3 + k], -v);
    }
  }
  check_mpi(MPI_Allreduce(MPI_IN_PLACE, box, 6, MPI_DOUBLE, MPI_MIN, comm), "MPI_Allreduce");
  GlobalFrame frame;
  frame.empty = !(box[0] < inf);
  if (frame.empty) return frame;
  for (int k = 0; k < 3; ++k) {
    frame.low[k] = box[k];
    frame.high[k] = -box[3 + k];
    frame.extent = std::max(frame.extent, frame.high[k] - frame.low[k]);
  }
  // The curve's sample, as one process picks it from the whole cloud.
  std::uint64_t total = positions.count;
  check_mpi(MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_UINT64_T, MPI_SUM, comm), "MPI_Allreduce");
  const std::vector<double> mine = pnf::detail::curve_sample(positions, pnf::detail::curve_sample_stride(total));
  frame.morton = pnf::detail::morton_frame(frame.low, frame.high, gather_to_all(comm, mine));
  return frame;
}

OwnedPoints distribute(MPI_Comm comm, const CloudView& local, const GlobalFrame& frame, std::size_t& moved_bytes) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const std::size_t n = local.size();
  std::uint64_t count = n, first_gid = 0, total = 0;
  MPI_Exscan(&count, &first_gid, 1, MPI_UINT64_T, MPI_SUM, comm);
  if (rank == 0) first_gid = 0;  // MPI_Exscan leaves rank 0's result undefined
  check_mpi(MPI_Allreduce(&count, &total, 1, MPI_UINT64_T, MPI_SUM, comm), "MPI_Allreduce");

  std::vector<std::uint64_t> keys(n);
  for (std::size_t i = 0; i < n; ++i) keys[i] = pnf::detail::morton_key(frame.morton, local.positions.at(i));
  std::vector<std::uint64_t> sorted = keys;
  std::sort(sorted.begin(), sorted.end());
  const std::vector<std::uint64_t> splitters = find_splitters(comm, sorted, total, ranks);
  std::vector<std::uint64_t>().swap(sorted);

  std::vector<int> owner(n), send_counts(static_cast<std::size_t>(ranks), 0);
  for (std::size_t i = 0; i < n; ++i) {
    owner[i] = int(std::upper_bound(splitters.begin(), splitters.end(), keys[i]) - splitters.begin());
    ++send_counts[std::size_t(owner[i])];
  }
  std::vector<int> send_displs = displacements(send_counts), fill = send_displs;
  std::vector<PointRecord> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    PointRecord& r = out[std::size_t(fill[std::size_t(owner[i])]++)];
    for (int k = 0; k < 3; ++k) {
      r.position[k] = local.positions.get(i, k);
      r.normal[k] = local.normals.get(i, k);
    }
    r.gid = first_gid + i;
    r.source_index = i;
  }
  std::vector<int>().swap(owner);
  std::vector<int> recv_counts(static_cast<std::size_t>(ranks));
  check_mpi(MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm), "MPI_Alltoall");
  const std::vector<int> recv_displs = displacements(recv_counts);
  const std::size_t received = std::size_t(recv_displs.back()) + std::size_t(recv_counts.back());
  std::vector<PointRecord> in(received);
  ByteRecord type(int(sizeof(PointRecord)));
  check_mpi(MPI_Alltoallv(out.data(), send_counts.data(), send_displs.data(), type.type(), in.data(),
                          recv_counts.data(), recv_displs.data(), type.type(), comm),
            "MPI_Alltoallv");
  moved_bytes = (n - std::size_t(send_counts[std::size_t(rank)])) * sizeof(PointRecord);
  std::vector<PointRecord>().swap(out);

  std::vector<int> source(received);
  for (int q = 0; q < ranks; ++q) {
    std::fill_n(source.begin() + recv_displs[std::size_t(q)], recv_counts[std::size_t(q)], q);
  }
  // Curve order with ties as one process breaks them (spatial_order.hpp: the positions' bits,
  // then the normals'), and last by global id, as the one process's stable sort of input order.
  std::vector<std::uint64_t> received_keys(received);
  for (std::size_t i = 0; i < received; ++i) {
    const PointRecord& r = in[i];
    received_keys[i] = pnf::detail::morton_key(frame.morton, {r.position[0], r.position[1], r.position[2]});
  }
  std::vector<std::uint32_t> order(received);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    if (received_keys[a] != received_keys[b]) return received_keys[a] < received_keys[b];
    const Vec3 pa{in[a].position[0], in[a].position[1], in[a].position[2]};
    const Vec3 pb{in[b].position[0], in[b].position[1], in[b].position[2]};
    if (pnf::detail::canonical_before(pa, pb)) return true;
    if (pnf::detail::canonical_before(pb, pa)) return false;
    const Vec3 na{in[a].normal[0], in[a].normal[1], in[a].normal[2]};
    const Vec3 nb{in[b].normal[0], in[b].normal[1], in[b].normal[2]};
    if (pnf::detail::canonical_before(na, nb)) return true;
    if (pnf::detail::canonical_before(nb, na)) return false;
    return in[a].gid < in[b].gid;
  });

  OwnedPoints owned;
  owned.total = total;
  owned.positions.resize(3 * received);
  owned.normals.resize(3 * received);
  owned.gids.resize(received);
  owned.source_rank.resize(received);
  owned.source_index.resize(received);
  for (std::size_t k = 0; k < received; ++k) {
    const PointRecord& r = in[order[k]];
    for (int c = 0; c < 3; ++c) {
      owned.positions[3 * k + c] = r.position[c];
      owned.normals[3 * k + c] = r.normal[c];
    }
    owned.gids[k] = r.gid;
    owned.source_rank[k] = source[order[k]];
    owned.source_index[k] = r.source_index;
  }
  std::uint64_t mine = received;
  MPI_Exscan(&mine, &owned.first_global, 1, MPI_UINT64_T, MPI_SUM, comm);
  if (rank == 0) owned.first_global = 0;
  return owned;
}

void return_normals(MPI_Comm comm, const OwnedPoints& owned, const std::vector<double>& normals,
                    MutableVec3ArrayView out) {
  struct NormalRecord {
    double normal[3];
    std::uint64_t index;
  };
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const std::size_t n = owned.size();
  std::vector<int> send_counts(static_cast<std::size_t>(ranks), 0);
  for (std::size_t k = 0; k < n; ++k) ++send_counts[std::size_t(owned.source_rank[k])];
  std::vector<int> send_displs = displacements(send_counts), fill = send_displs;
  std::vector<NormalRecord> records(n);
  for (std::size_t k = 0; k < n; ++k) {
    NormalRecord& r = records[std::size_t(fill[std::size_t(owned.source_rank[k])]++)];
    std::memcpy(r.normal, &normals[3 * k], sizeof r.normal);
    r.index = owned.source_index[k];
  }
  std::vector<int> recv_counts(static_cast<std::size_t>(ranks));
  check_mpi(MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm), "MPI_Alltoall");
  const std::vector<int> recv_displs = displacements(recv_counts);
  std::vector<NormalRecord> in(std::size_t(recv_displs.back()) + std::size_t(recv_counts.back()));
  ByteRecord type(int(sizeof(NormalRecord)));
  check_mpi(MPI_Alltoallv(records.data(), send_counts.data(), send_displs.data(), type.type(), in.data(),
                          recv_counts.data(), recv_displs.data(), type.type(), comm),
            "MPI_Alltoallv");
  for (const NormalRecord& r : in) out.set(r.index, {r.normal[0], r.normal[1], r.normal[2]});
}

}  // namespace pnf::mpi::detail
