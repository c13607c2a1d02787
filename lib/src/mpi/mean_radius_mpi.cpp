#include "mean_radius_mpi.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "agreement.hpp"
#include "exact_sum.hpp"
#include "halo.hpp"
#include "mean_radius_internal.hpp"
#include "spatial/spatial_index.hpp"

namespace pnf::mpi::detail {
namespace {

using pnf::detail::kMaxSpacingSamples;
using pnf::detail::kSpacingNeighbours;
using pnf::detail::SpatialIndex;

std::vector<double> recentred(const std::vector<double>& positions, const Vec3& centre) {
  std::vector<double> out(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) out[i] = positions[i] - centre[i % 3];
  return out;
}

// This rank's share of the spacing samples (one process's: the points at curve rank s * N / S,
// S = min(N, kMaxSpacingSamples)), as indices of its owned points.
std::vector<std::uint32_t> my_samples(const OwnedPoints& owned) {
  const std::uint64_t total = owned.total;
  const std::uint64_t samples = std::min(kMaxSpacingSamples, total);
  // Sample s is the point at curve rank s * N / S: is g one of them?
  std::vector<std::uint32_t> mine;
  for (std::size_t i = 0; i < owned.size(); ++i) {
    const std::uint64_t g = owned.first_global + i;
    const std::uint64_t s = std::uint64_t(((unsigned __int128)g * samples + total - 1) / total);
    if (s < samples && std::uint64_t((unsigned __int128)s * total / samples) == g) mine.push_back(std::uint32_t(i));
  }
  return mine;
}

double estimate(MPI_Comm comm, const OwnedPoints& owned, const GlobalFrame& frame, const Vec3& centre) {
  const std::size_t n = owned.size();
  const int k = kSpacingNeighbours;
  if (owned.total < std::uint64_t(k) + 1) return 0;
  const std::vector<std::uint32_t> mine = my_samples(owned);
  const std::vector<double> own = recentred(owned.positions, centre);

  // An upper bound of each sample's k-th nearest distance from this rank's points alone.
  double width = 0;
  if (!mine.empty()) {
    if (n < std::size_t(k) + 1) {
      width = std::numeric_limits<double>::infinity();
    } else {
      const SpatialIndex search(own, SpatialIndex::Layout::any_order);
      for (std::uint32_t i : mine)
        width = std::max(width, std::sqrt(search.nearest_squared_distances(i, k + 1).back()));
    }
  }
  check_mpi(MPI_Allreduce(MPI_IN_PLACE, &width, 1, MPI_DOUBLE, MPI_MAX, comm), "MPI_Allreduce");
  std::vector<double> sample_positions;
  for (std::uint32_t i : mine)
    sample_positions.insert(sample_positions.end(), &owned.positions[3 * i], &owned.positions[3 * i] + 3);
  const auto lists = points_near(comm, owned.positions, sample_positions, width, frame);
  std::vector<double> all = own;
  const std::vector<double> halo = recentred(send_positions(comm, owned.positions, lists), centre);
  all.insert(all.end(), halo.begin(), halo.end());

  std::vector<double> distances;
  distances.reserve(mine.size());
  if (!mine.empty()) {
    // The samples are this rank's own points: the first rows of `all`.
    const SpatialIndex search(std::move(all), SpatialIndex::Layout::any_order);
    for (std::uint32_t i : mine) distances.push_back(search.mean_nearest_distance(i, k));
  }
  // The median over every sample, on rank 0, as estimate_mean_radius takes it.
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  int count = int(distances.size());
  std::vector<int> counts(static_cast<std::size_t>(ranks));
  check_mpi(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm), "MPI_Gather");
  std::vector<int> displs = displacements(counts);
  std::vector<double> gathered(rank == 0 ? std::size_t(displs.back() + counts.back()) : 0);
  check_mpi(MPI_Gatherv(distances.data(), count, MPI_DOUBLE, gathered.data(), counts.data(), displs.data(), MPI_DOUBLE,
                        0, comm),
            "MPI_Gatherv");
  double median = rank == 0 ? pnf::detail::median_spacing(std::move(gathered)) : 0.0;
  check_mpi(MPI_Bcast(&median, 1, MPI_DOUBLE, 0, comm), "MPI_Bcast");
  return median;
}

// The mean of every rank's values, summed exactly (pnf::detail::ExactSum): the digits of the
// ranks' sums add as integers, so the mean is one process's bit for bit, in any row order.
double exact_mean(MPI_Comm comm, const ScalarArrayView& values) {
  pnf::detail::ExactSum sum;
  for (std::size_t i = 0; i < values.count; ++i) sum.add(values.get(i));
  auto& digits = sum.carried_digits();
  check_mpi(MPI_Allreduce(MPI_IN_PLACE, digits.data(), int(digits.size()), MPI_INT64_T, MPI_SUM, comm),
            "MPI_Allreduce");
  double count = double(values.count);
  check_mpi(MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_DOUBLE, MPI_SUM, comm), "MPI_Allreduce");
  return sum.value() / count;
}

}  // namespace

Vec3 sample_median(MPI_Comm comm, const OwnedPoints& owned) {
  std::vector<double> mine;
  for (std::uint32_t i : my_samples(owned))
    mine.insert(mine.end(), &owned.positions[3 * i], &owned.positions[3 * i] + 3);
  return pnf::detail::axis_medians(gather_to_all(comm, mine));
}

double resolve_mean_radius(MPI_Comm comm, const CloudView& local, const OwnedPoints& owned, const GlobalFrame& frame,
                           const Vec3& origin, const FilterParams& params, RadiusSource& source) {
  if (params.units == Units::absolute) {
    source = RadiusSource::not_used;
    return 0;
  }
  if (params.mean_radius > 0) {
    source = RadiusSource::given;
    return params.mean_radius;
  }
  // [ranks with points, of them with radii]
  double totals[2] = {local.size() > 0 ? 1.0 : 0.0, local.size() > 0 && local.has_radii() ? 1.0 : 0.0};
  check_mpi(MPI_Allreduce(MPI_IN_PLACE, totals, 2, MPI_DOUBLE, MPI_SUM, comm), "MPI_Allreduce");
  if (totals[1] > 0 && totals[1] < totals[0]) {
    throw Error(ErrorCode::invalid_input, "the points of " + std::to_string(std::llround(totals[1])) + " of " +
                                              std::to_string(std::llround(totals[0])) +
                                              " ranks have radii, the others' have none");
  }
  if (totals[1] > 0) {
    source = RadiusSource::property;
    return exact_mean(comm, local.radii);
  }
  source = RadiusSource::estimate;
  const double radius = estimate(comm, owned, frame, origin);
  if (!(radius > 0)) pnf::detail::throw_cannot_estimate_mean_radius(owned.total);
  return radius;
}

}  // namespace pnf::mpi::detail
