#include "reference_backend.hpp"

#include <omp.h>

#include <cstdint>
#include <limits>

#include "pnf_filter.h"

namespace pnf::detail {
namespace {

class ReferenceBackend : public FilterBackend {
 public:
  explicit ReferenceBackend(int threads) : threads_(threads > 0 ? threads : omp_get_max_threads()) {}

  std::string description() const override {
    return "CPU reference (double, " + std::to_string(threads_) + " thread" + (threads_ == 1 ? "" : "s") + ")";
  }
  std::size_t max_list_bytes() const override { return std::numeric_limits<std::size_t>::max(); }

  void upload_cloud(const std::vector<double>& positions, const std::vector<double>& normals) override {
    positions_ = positions;
    current_ = normals;
    next_ = normals;
  }

  void upload_lists(const CsrLists& lists) override { lists_ = &lists; }

  void run_chunk(const Coefficients& coefficients) override {
    pnf_coeffs c;
    c.inv_two_sigma_f2 = coefficients.inv_two_sigma_f2;
    c.inv_two_sigma_g2 = coefficients.inv_two_sigma_g2;
    const CsrLists& lists = *lists_;
    const auto count = static_cast<std::int64_t>(lists.point_count);
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads_)
    for (std::int64_t k = 0; k < count; ++k) {
      auto s = static_cast<pnf_index>(lists.first_point + k);
      pnf_vec3 n = pnf_filter_point(s, lists.indices.data(), lists.offsets[k], lists.offsets[k + 1], positions_.data(),
                                    current_.data(), c);
      next_[3 * std::size_t(s)] = n.x;
      next_[3 * std::size_t(s) + 1] = n.y;
      next_[3 * std::size_t(s) + 2] = n.z;
    }
  }

  double end_pass() override {
    current_.swap(next_);
    return 0;
  }

  std::size_t device_bytes() const override { return 0; }

  std::vector<double> download_normals() override { return current_; }

 private:
  int threads_;
  std::vector<double> positions_;
  std::vector<double> current_;
  std::vector<double> next_;
  const CsrLists* lists_ = nullptr;
};

}  // namespace

std::unique_ptr<FilterBackend> make_reference_backend(int threads) { return std::make_unique<ReferenceBackend>(threads); }

}  // namespace pnf::detail
