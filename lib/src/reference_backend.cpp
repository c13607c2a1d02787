#include "reference_backend.hpp"

#include <omp.h>

#include <cstdint>
#include <limits>

#include "pnf_filter.h"

namespace pnf::detail {
namespace {

// N by 3 -> N pnf_real4 (x, y, z, 0).
std::vector<pnf_real4> to_real4(const std::vector<double>& v) {
  std::vector<pnf_real4> out(v.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = pnf_real4{v[3 * i], v[3 * i + 1], v[3 * i + 2], 0};
  return out;
}

class ReferenceBackend : public FilterBackend {
 public:
  explicit ReferenceBackend(int threads) : threads_(threads > 0 ? threads : omp_get_max_threads()) {}

  std::string description() const override {
    return "CPU reference (double, " + std::to_string(threads_) + " thread" + (threads_ == 1 ? "" : "s") + ")";
  }
  std::size_t max_list_bytes() const override { return std::numeric_limits<std::size_t>::max(); }

  void upload_cloud(const std::vector<double>& positions, const std::vector<double>& normals) override {
    positions_ = to_real4(positions);
    current_ = to_real4(normals);
    next_ = current_;
  }

  ListStorage begin_lists(std::size_t first, std::size_t count, std::size_t pairs) override {
    first_ = first;
    offsets_.resize(count + 1);
    indices_.resize(pairs);
    return {offsets_.data(), indices_.data()};
  }

  void end_lists() override {}
  void wait() override {}

  void run_chunk(const pnf_coeffs& c, std::size_t first, std::size_t count) override {
    const auto begin = static_cast<std::int64_t>(first), end = static_cast<std::int64_t>(first + count);
    std::size_t kept_here = 0;
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads_) reduction(+ : kept_here)
    for (std::int64_t k = begin; k < end; ++k) {
      auto s = static_cast<pnf_index>(first_ + k);
      int kept = 0;
      pnf_vec3 n = pnf_filter_point(s, indices_.data(), offsets_[k], offsets_[k + 1], positions_.data(),
                                    current_.data(), c, &kept);
      kept_here += std::size_t(kept);
      next_[s] = pnf_real4{n.x, n.y, n.z, 0};
    }

    pass_kept_ += kept_here;
  }

  double end_pass() override {
    current_.swap(next_);
    last_kept_ = pass_kept_;
    pass_kept_ = 0;
    return 0;
  }

  std::size_t degenerate_kept() const override { return last_kept_; }

  std::size_t device_bytes() const override { return 0; }

  std::vector<double> download_normals() override {
    std::vector<double> out(3 * current_.size());
    for (std::size_t i = 0; i < current_.size(); ++i) {
      out[3 * i] = current_[i].x;
      out[3 * i + 1] = current_[i].y;
      out[3 * i + 2] = current_[i].z;
    }
    return out;
  }
  void replace_normals(const std::vector<double>& normals) override { current_ = to_real4(normals); }

 private:
  int threads_;
  std::vector<pnf_real4> positions_;  // the layout pnf_filter.h reads, as on the device
  std::vector<pnf_real4> current_;
  std::vector<pnf_real4> next_;
  std::size_t first_ = 0;                      // the current lists' first point
  std::size_t pass_kept_ = 0, last_kept_ = 0;  // degenerate points: this pass so far, last pass
  std::vector<std::uint64_t> offsets_;
  std::vector<std::uint32_t> indices_;
};

}  // namespace

std::unique_ptr<FilterBackend> make_reference_backend(int threads) {
  return std::make_unique<ReferenceBackend>(threads);
}

}  // namespace pnf::detail
