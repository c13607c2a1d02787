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

  ListStorage begin_lists(std::size_t first, std::size_t count, std::size_t pairs) override {
    first_ = first;
    count_ = count;
    offsets_.resize(count + 1);
    indices_.resize(pairs);
    return {offsets_.data(), indices_.data()};
  }

  void end_lists() override {}
  void wait() override {}

  void run_chunk(const Coefficients& coefficients) override {
    pnf_coeffs c;
    c.inv_two_sigma_f2 = coefficients.inv_two_sigma_f2;
    c.inv_two_sigma_g2 = coefficients.inv_two_sigma_g2;
    const auto count = static_cast<std::int64_t>(count_);
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads_)
    for (std::int64_t k = 0; k < count; ++k) {
      auto s = static_cast<pnf_index>(first_ + k);
      pnf_vec3 n =
          pnf_filter_point(s, indices_.data(), offsets_[k], offsets_[k + 1], positions_.data(), current_.data(), c);
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
  void replace_normals(const std::vector<double>& normals) override { current_ = normals; }

 private:
  int threads_;
  std::vector<double> positions_;
  std::vector<double> current_;
  std::vector<double> next_;
  std::size_t first_ = 0, count_ = 0;
  std::vector<std::uint64_t> offsets_;
  std::vector<std::uint32_t> indices_;
};

}  // namespace

std::unique_ptr<FilterBackend> make_reference_backend(int threads) {
  return std::make_unique<ReferenceBackend>(threads);
}

}  // namespace pnf::detail
