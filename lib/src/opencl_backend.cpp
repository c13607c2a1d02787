#include "opencl_backend.hpp"

#include <algorithm>
#include <utility>

#include "cl_runtime.hpp"

namespace pnf::detail {
namespace {

// Kernels are plain OpenCL C 1.2; no fast-math, so float results stay close to the reference.
// -w: the compiler's warnings stay out of the user's terminal. PoCL keeps them in the build log,
// but clang itself writes "N warnings generated." to stderr, once per process (every rank under
// mpirun). tests/kernel_build_test.cpp builds without -w and requires no warning, and a failed
// build still reports its log (ClRuntime::kernel).
constexpr const char* kBuildOptions = "-cl-std=CL1.2 -w";
// Measured in bench/ (see docs/performance.md): 16 lanes is fastest on PoCL's CPU device, with
// AVX-512 and with AVX2 (where 8 lanes came within the spread).
constexpr int kCpuLanes = 16;
constexpr int kGpuLanes = 1;
// The work-group size of a pass (run_chunk), or the kernel's largest where smaller: a fixed size
// that fills a GPU's wavefront. Left to the driver, PoCL picked one that divides the slice's
// point count (one work-item for an odd count) and built a new kernel variant per size: slices
// ran 2.6-4.1 times slower than whole passes; with 64 the same (pnf_bench --sliced,
// docs/performance.md).
constexpr std::size_t kWorkGroup = 64;

// N by 3 doubles -> N float4 (x, y, z, 0): the kernel loads a point's position or normal as one
// 16-byte vector.
std::vector<cl_float4> to_float4(const std::vector<double>& v) {
  std::vector<cl_float4> out(v.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i].s[0] = static_cast<float>(v[3 * i]);
    out[i].s[1] = static_cast<float>(v[3 * i + 1]);
    out[i].s[2] = static_cast<float>(v[3 * i + 2]);
    out[i].s[3] = 0.0f;
  }
  return out;
}

class OpenClBackend : public FilterBackend {
 public:
  OpenClBackend(const std::string& selector, int lanes, const std::string& extra_options) : runtime_(selector) {
    lanes_ = lanes > 0 ? lanes : runtime_.info().type == "gpu" ? kGpuLanes : kCpuLanes;
    std::string options = std::string(kBuildOptions) + " -DPNF_LANES=" + std::to_string(lanes_);
    if (!extra_options.empty()) options += " " + extra_options;
    kernel_ = runtime_.kernel("filter.cl", "pnf_filter_pass", options);
    work_group_ = guarded(
        [&] { return std::min(kWorkGroup, kernel_.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(runtime_.device())); });
  }

  std::string description() const override {
    return runtime_.description() + ", " + std::to_string(lanes_) + " lane" + (lanes_ == 1 ? "" : "s");
  }
  std::size_t max_list_bytes() const override { return runtime_.max_alloc_bytes(); }  // maps cl::Error itself

  void upload_cloud(const std::vector<double>& positions, const std::vector<double>& normals) override {
    guarded([&] {
      point_count_ = positions.size() / 3;
      std::vector<cl_float4> p = to_float4(positions), n = to_float4(normals);
      const std::size_t bytes = p.size() * sizeof(cl_float4);
      positions_ = cl::Buffer(runtime_.context(), CL_MEM_READ_ONLY, bytes);
      current_ = cl::Buffer(runtime_.context(), CL_MEM_READ_WRITE, bytes);
      next_ = cl::Buffer(runtime_.context(), CL_MEM_READ_WRITE, bytes);
      runtime_.queue().enqueueWriteBuffer(positions_, CL_TRUE, 0, bytes, p.data());
      runtime_.queue().enqueueWriteBuffer(current_, CL_TRUE, 0, bytes, n.data());
      degenerate_ = cl::Buffer(runtime_.context(), CL_MEM_READ_WRITE, sizeof(cl_uint));
      const cl_uint zero = 0;
      runtime_.queue().enqueueWriteBuffer(degenerate_, CL_TRUE, 0, sizeof zero, &zero);
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

  void run_chunk(const pnf_coeffs& coefficients, std::size_t first, std::size_t count) override {
    if (count == 0) return;
    guarded([&] {
      kernel_.setArg(0, positions_);
      kernel_.setArg(1, current_);
      kernel_.setArg(2, next_);
      kernel_.setArg(3, offsets_);
      kernel_.setArg(4, indices_);
      kernel_.setArg(5, chunk_begin_);
      // The kernel's bound: the slice's end, so that the work-items that round the global size up
      // (below) do nothing.
      kernel_.setArg(6, static_cast<cl_uint>(first + count));
      kernel_.setArg(7, static_cast<cl_float>(coefficients.inv_two_sigma_f2));
      kernel_.setArg(8, static_cast<cl_float>(coefficients.inv_two_sigma_g2));
      kernel_.setArg(9, degenerate_);
      cl::Event event;
      // The global offset makes get_global_id the index in the chunk's lists; the global size is
      // rounded up to whole work-groups (kWorkGroup).
      const std::size_t global = (count + work_group_ - 1) / work_group_ * work_group_;
      runtime_.queue().enqueueNDRangeKernel(kernel_, cl::NDRange(first), cl::NDRange(global), cl::NDRange(work_group_),
                                            nullptr, &event);
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
      // The kernels of every chunk of the pass add to one counter; read it and start the next at 0.
      cl_uint kept = 0;
      const cl_uint zero = 0;
      runtime_.queue().enqueueReadBuffer(degenerate_, CL_TRUE, 0, sizeof kept, &kept);
      runtime_.queue().enqueueWriteBuffer(degenerate_, CL_TRUE, 0, sizeof zero, &zero);
      last_kept_ = kept;
      // The chunks of a pass cover every point, so `next_` is whole and can become current.
      std::swap(current_, next_);
      return seconds;
    });
  }

  std::size_t degenerate_kept() const override { return last_kept_; }

  std::size_t device_bytes() const override {
    return 3 * point_count_ * sizeof(cl_float4) + offsets_capacity_ + indices_capacity_;
  }

  std::vector<double> download_normals() override {
    return guarded([&] {
      std::vector<cl_float4> n(point_count_);
      runtime_.queue().enqueueReadBuffer(current_, CL_TRUE, 0, n.size() * sizeof(cl_float4), n.data());
      std::vector<double> out(3 * point_count_);
      for (std::size_t i = 0; i < point_count_; ++i) {
        for (int c = 0; c < 3; ++c) out[3 * i + c] = n[i].s[c];
      }
      return out;
    });
  }

  void replace_normals(const std::vector<double>& normals) override {
    guarded([&] {
      std::vector<cl_float4> n = to_float4(normals);
      runtime_.queue().enqueueWriteBuffer(current_, CL_TRUE, 0, n.size() * sizeof(cl_float4), n.data());
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
  cl::Buffer degenerate_;      // one uint: points of the current pass whose J was degenerate
  std::size_t last_kept_ = 0;  // that count for the pass end_pass() last closed
  std::size_t offsets_capacity_ = 0, indices_capacity_ = 0;
  cl_uint chunk_begin_ = 0;
  std::size_t work_group_ = kWorkGroup;
  void* mapped_offsets_ = nullptr;
  void* mapped_indices_ = nullptr;
  std::vector<cl::Event> events_;
};

}  // namespace

std::unique_ptr<FilterBackend> make_opencl_backend(const std::string& selector, int lanes,
                                                   const std::string& extra_options) {
  return std::make_unique<OpenClBackend>(selector, lanes, extra_options);
}

}  // namespace pnf::detail
