#include "opencl_backend.hpp"

#include <algorithm>
#include <utility>

#include "cl_runtime.hpp"

namespace pnf::detail {
namespace {

// Kernels are plain OpenCL C 1.2; no fast-math, so float results stay close to the reference.
constexpr const char* kBuildOptions = "-cl-std=CL1.2";
// Measured in bench/ (see docs/performance.md): 16 lanes is fastest on PoCL's AVX-512 CPU device.
constexpr int kCpuLanes = 16;
constexpr int kGpuLanes = 1;

std::vector<float> to_float(const std::vector<double>& v) { return std::vector<float>(v.begin(), v.end()); }

class OpenClBackend : public FilterBackend {
 public:
  OpenClBackend(const std::string& selector, int lanes) : runtime_(selector) {
    lanes_ = lanes > 0 ? lanes : runtime_.info().type == "gpu" ? kGpuLanes : kCpuLanes;
    kernel_ = runtime_.kernel("filter.cl", "pnf_filter_pass",
                              std::string(kBuildOptions) + " -DPNF_LANES=" + std::to_string(lanes_));
  }

  std::string description() const override {
    return runtime_.description() + ", " + std::to_string(lanes_) + " lane" + (lanes_ == 1 ? "" : "s");
  }
  std::size_t max_list_bytes() const override { return runtime_.max_alloc_bytes(); }  // maps cl::Error itself

  void upload_cloud(const std::vector<double>& positions, const std::vector<double>& normals) override {
    guarded([&] {
      point_count_ = positions.size() / 3;
      std::vector<float> p = to_float(positions), n = to_float(normals);
      const std::size_t bytes = p.size() * sizeof(float);
      positions_ = cl::Buffer(runtime_.context(), CL_MEM_READ_ONLY, bytes);
      current_ = cl::Buffer(runtime_.context(), CL_MEM_READ_WRITE, bytes);
      next_ = cl::Buffer(runtime_.context(), CL_MEM_READ_WRITE, bytes);
      runtime_.queue().enqueueWriteBuffer(positions_, CL_TRUE, 0, bytes, p.data());
      runtime_.queue().enqueueWriteBuffer(current_, CL_TRUE, 0, bytes, n.data());
      runtime_.queue().finish();
    });
  }

  ListStorage begin_lists(std::size_t first, std::size_t count, std::size_t pairs) override {
    return guarded([&] {
      const std::size_t offset_bytes = (count + 1) * sizeof(cl_ulong);
      const std::size_t index_bytes = std::max<std::size_t>(pairs, 1) * sizeof(cl_uint);
      static_assert(sizeof(cl_ulong) == sizeof(std::uint64_t) && sizeof(cl_uint) == sizeof(std::uint32_t));
      // Buffers grow to the largest chunk and are then reused, so chunked passes reallocate
      // nothing. ALLOC_HOST_PTR lets a CPU device map them without a copy.
      if (offset_bytes > offsets_capacity_) {
        offsets_ = cl::Buffer(runtime_.context(), CL_MEM_READ_ONLY | CL_MEM_ALLOC_HOST_PTR, offset_bytes);
        offsets_capacity_ = offset_bytes;
      }
      if (index_bytes > indices_capacity_) {
        indices_ = cl::Buffer(runtime_.context(), CL_MEM_READ_ONLY | CL_MEM_ALLOC_HOST_PTR, index_bytes);
        indices_capacity_ = index_bytes;
      }
      cl::CommandQueue& q = runtime_.queue();
      mapped_offsets_ = q.enqueueMapBuffer(offsets_, CL_TRUE, CL_MAP_WRITE_INVALIDATE_REGION, 0, offset_bytes);
      mapped_indices_ = q.enqueueMapBuffer(indices_, CL_TRUE, CL_MAP_WRITE_INVALIDATE_REGION, 0, index_bytes);
      chunk_begin_ = static_cast<cl_uint>(first);
      chunk_count_ = static_cast<cl_uint>(count);
      return ListStorage{static_cast<std::uint64_t*>(mapped_offsets_), static_cast<std::uint32_t*>(mapped_indices_)};
    });
  }

  void wait() override {
    guarded([&] { runtime_.queue().finish(); });
  }

  void end_lists() override {
    guarded([&] {
      runtime_.queue().enqueueUnmapMemObject(offsets_, mapped_offsets_);
      runtime_.queue().enqueueUnmapMemObject(indices_, mapped_indices_);
      mapped_offsets_ = mapped_indices_ = nullptr;
      runtime_.queue().finish();
    });
  }

  void run_chunk(const Coefficients& coefficients) override {
    guarded([&] {
      kernel_.setArg(0, positions_);
      kernel_.setArg(1, current_);
      kernel_.setArg(2, next_);
      kernel_.setArg(3, offsets_);
      kernel_.setArg(4, indices_);
      kernel_.setArg(5, chunk_begin_);
      kernel_.setArg(6, chunk_count_);
      kernel_.setArg(7, static_cast<cl_float>(coefficients.inv_two_sigma_f2));
      kernel_.setArg(8, static_cast<cl_float>(coefficients.inv_two_sigma_g2));
      cl::Event event;
      runtime_.queue().enqueueNDRangeKernel(kernel_, cl::NullRange, cl::NDRange(chunk_count_), cl::NullRange, nullptr,
                                            &event);
      events_.push_back(event);
    });
  }

  double end_pass() override {
    return guarded([&] {
      runtime_.queue().finish();
      double seconds = 0;
      for (cl::Event& e : events_) {
        try {
          seconds += 1e-9 * double(e.getProfilingInfo<CL_PROFILING_COMMAND_END>() -
                                   e.getProfilingInfo<CL_PROFILING_COMMAND_START>());
        } catch (const cl::Error&) {
          // Profiling is optional for a driver; the pass still ran.
        }
      }
      events_.clear();
      // The chunks of a pass cover every point, so `next_` is whole and can become current.
      std::swap(current_, next_);
      return seconds;
    });
  }

  std::size_t device_bytes() const override {
    return 3 * point_count_ * 3 * sizeof(float) + offsets_capacity_ + indices_capacity_;
  }

  std::vector<double> download_normals() override {
    return guarded([&] {
      std::vector<float> n(point_count_ * 3);
      runtime_.queue().enqueueReadBuffer(current_, CL_TRUE, 0, n.size() * sizeof(float), n.data());
      return std::vector<double>(n.begin(), n.end());
    });
  }

  void replace_normals(const std::vector<double>& normals) override {
    guarded([&] {
      std::vector<float> n = to_float(normals);
      runtime_.queue().enqueueWriteBuffer(current_, CL_TRUE, 0, n.size() * sizeof(float), n.data());
    });
  }

 private:
  template <typename Body>
  auto guarded(Body&& body) -> decltype(body()) {
    return with_cl_errors(runtime_.info().device_name, std::forward<Body>(body));
  }

  ClRuntime runtime_;
  int lanes_ = 1;
  cl::Kernel kernel_;
  std::size_t point_count_ = 0;
  cl::Buffer positions_, current_, next_, offsets_, indices_;
  std::size_t offsets_capacity_ = 0, indices_capacity_ = 0;
  cl_uint chunk_begin_ = 0, chunk_count_ = 0;
  void* mapped_offsets_ = nullptr;
  void* mapped_indices_ = nullptr;
  std::vector<cl::Event> events_;
};

}  // namespace

std::unique_ptr<FilterBackend> make_opencl_backend(const std::string& selector, int lanes) {
  return std::make_unique<OpenClBackend>(selector, lanes);
}

}  // namespace pnf::detail
