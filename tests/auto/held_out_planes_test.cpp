// --auto's held-out check (lib/src/auto/held_out_planes.hpp): normals scored against the planes
// of points they were not made from order normal fields as their true errors do, and the check
// does not depend on the input's row order.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "auto/held_out_planes.hpp"
#include "noisy_clouds.hpp"

namespace pnf::test {
namespace {

// A sphere with a quarter spacing of position noise, where the reference planes are sharp, and
// input normals tilted by about 15 degrees, errors independent of the positions.
Noisy tilted_sphere() { return noisy_sphere(40000, 0.25, 15, 7); }

// A sphere with a spacing of position noise and PCA-16 normals turned to the true side.
Noisy noisy_pca_sphere() {
  Noisy n = with_pca_normals(noisy_sphere(40000, 1.0, 0, 7), 16);
  for (std::size_t i = 0; i < n.truth.size(); ++i) {
    const Vec3 v = n.cloud.normals[i];
    if (dot(v, n.truth[i]) < 0) n.cloud.normals[i] = {-v[0], -v[1], -v[2]};
  }
  return n;
}

// The true normals tilted by about `degrees` each.
std::vector<Vec3> tilted_truth(const Noisy& n, double degrees, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<Vec3> out;
  for (const Vec3& t : n.truth) out.push_back(jitter_normal(t, degrees, rng));
  return out;
}

TEST(HeldOutPlanes, OrdersNormalFieldsAsTheirTrueErrors) {
  const Noisy n = tilted_sphere();
  const double input_error = rms_angle(n.cloud.normals, n.truth);
  const detail::HeldOutPlanes planes(n.cloud.positions, xyz_rows(n.cloud.normals));
  ASSERT_GT(planes.size(), 4000u);
  // From the truest to the least true, each field's true RMS error against the truth.
  const std::vector<std::vector<Vec3>> fields = {n.truth, tilted_truth(n, 0.3 * input_error, 1), n.cloud.normals,
                                                 tilted_truth(n, 2 * input_error, 2)};
  double previous_error = -1, previous_score = -1;
  for (const std::vector<Vec3>& field : fields) {
    const double error = rms_angle(field, n.truth);
    const double score = planes.score(xyz_rows(field).data()).disagreement_deg;
    ASSERT_GT(error, previous_error);
    EXPECT_GT(score, previous_score) << "the field " << error << " deg from the truth";
    previous_error = error;
    previous_score = score;
  }
  // The truth's gain over the input is far beyond chance; a field worse than the input gains
  // below zero; the input gains nothing.
  EXPECT_GT(planes.score(xyz_rows(n.truth).data()).gain_z, 10 * detail::kHeldOutMinGainZ);
  EXPECT_LT(planes.score(xyz_rows(fields[3]).data()).gain_z, -detail::kHeldOutMinGainZ);
  EXPECT_EQ(planes.score(xyz_rows(n.cloud.normals).data()).gain_z, 0.0);
}

// PCA normals share points with the planes near them and read better than they are: on a
// spacing of noise even the truth's gain over PCA-16 normals that err by tens of degrees does
// not pass the bar. The check errs toward keeping the input.
TEST(HeldOutPlanes, ReadsPcaInputAsNoWorseThanItIs) {
  const Noisy n = noisy_pca_sphere();
  ASSERT_GT(rms_angle(n.cloud.normals, n.truth), 20.0);
  const detail::HeldOutPlanes planes(n.cloud.positions, xyz_rows(n.cloud.normals));
  EXPECT_LT(planes.score(xyz_rows(n.truth).data()).gain_z, detail::kHeldOutMinGainZ);
}

TEST(HeldOutPlanes, IndependentOfTheRowOrder) {
  const Noisy n = tilted_sphere();
  std::vector<std::size_t> order(n.cloud.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::shuffle(order.begin(), order.end(), std::mt19937(3));
  PointCloud shuffled;
  std::vector<Vec3> truth;
  for (std::size_t i : order) {
    shuffled.positions.push_back(n.cloud.positions[i]);
    shuffled.normals.push_back(n.cloud.normals[i]);
    truth.push_back(n.truth[i]);
  }
  const detail::HeldOutPlanes planes(n.cloud.positions, xyz_rows(n.cloud.normals));
  const detail::HeldOutPlanes shuffled_planes(shuffled.positions, xyz_rows(shuffled.normals));
  EXPECT_EQ(planes.size(), shuffled_planes.size());
  const detail::HeldOutPlanes::Score a = planes.score(xyz_rows(n.truth).data());
  const detail::HeldOutPlanes::Score b = shuffled_planes.score(xyz_rows(truth).data());
  EXPECT_EQ(a.disagreement_deg, b.disagreement_deg);
  EXPECT_EQ(a.gain_z, b.gain_z);
}

// Points on a line make no plane: no sample is scored, and the score of any normals is 0 with
// no gain (the check then keeps nothing).
TEST(HeldOutPlanes, NoPlaneOnALine) {
  std::vector<Vec3> positions, normals;
  for (int i = 0; i < 2000; ++i) {
    positions.push_back({0.01 * i, 0, 0});
    normals.push_back({0, 0, 1});
  }
  const detail::HeldOutPlanes planes(positions, xyz_rows(normals));
  EXPECT_TRUE(planes.empty());
  const detail::HeldOutPlanes::Score score = planes.score(xyz_rows(normals).data());
  EXPECT_EQ(score.disagreement_deg, 0.0);
  EXPECT_EQ(score.gain_z, 0.0);
}

}  // namespace
}  // namespace pnf::test
