// pnf::mpi::filter_file (pnf/mpi.hpp) under `mpirun -np P` (P = 1 .. 4): a file filtered across
// the ranks in one call against one process's run on the same file; the pair limit of the
// whole job; a cancel before the commit leaves OUT untouched; a killed job's staging folder is
// removed by the next run; OUT a link to a private file.
#include <gtest/gtest.h>
#include <mpi.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "pnf/error.hpp"
#include "pnf/improve_normals.hpp"
#include "pnf/mpi.hpp"
#include "pnf/point_file.hpp"
#include "pnf/synthetic_shapes.hpp"
#include "staged_output.hpp"
#include "test_clouds.hpp"

namespace {

using namespace pnf;
namespace fs = std::filesystem;

// The engine's pair estimate samples points: 1/20 of the count covers its spread here (0.2%
// measured on the 4000-point house).
constexpr std::size_t kEstimateSpread = 20;

int rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int ranks() {
  int p = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &p);
  return p;
}

// A folder of its own for each test and rank count, made by rank 0 and seen by every rank, and
// removed by rank 0 when the test ends (every rank past its last use of it), so that runs leave
// nothing behind in the temporary folder.
class WorkFolder {
 public:
  explicit WorkFolder(const std::string& name)
      : path_(fs::temp_directory_path() /
              ("pnf_filter_file_" + name + "_np" + std::to_string(ranks()) + "_" + std::to_string(::getppid()))) {
    if (rank() == 0) {
      fs::remove_all(path_);
      fs::create_directories(path_);
    }
    MPI_Barrier(MPI_COMM_WORLD);
  }
  ~WorkFolder() {
    MPI_Barrier(MPI_COMM_WORLD);
    std::error_code ignored;
    if (rank() == 0) fs::remove_all(path_, ignored);
  }
  WorkFolder(const WorkFolder&) = delete;
  WorkFolder& operator=(const WorkFolder&) = delete;

  operator const fs::path&() const { return path_; }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

// The house, binary PLY, 4000 points: small enough for the reference backend on 4 ranks on 2 cores.
fs::path house_file(const fs::path& folder) {
  const fs::path path = folder / "house.ply";
  if (rank() == 0) write_point_file(path.string(), PointFile(make_scanned_house(4000).cloud));
  MPI_Barrier(MPI_COMM_WORLD);
  return path;
}

FilterFileOptions reference_run() {
  FilterFileOptions o;
  o.options.device = Device::reference();
  o.options.reference_threads = 1;  // ranks share the cores
  return o;
}

// Everything in `folder` but the named files.
std::vector<std::string> others(const fs::path& folder, std::initializer_list<std::string> known) {
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (std::find(known.begin(), known.end(), name) == known.end()) left.push_back(name);
  }
  return left;
}

// The whole binary PLY path (each rank its rows) and the rank-0 path (.xyzn out) against one
// process on the same file.
TEST(FilterFile, OneCallMatchesOneProcess) {
  const WorkFolder folder("match");
  const fs::path in = house_file(folder);
  const FilterFileOptions o = reference_run();
  const PointCloud cloud = read_point_file(in.string()).cloud();
  const FilterResult one = improve_normals(cloud, o.params, o.options);
  for (const char* name : {"out.ply", "out.xyzn"}) {
    const fs::path out = folder / name;
    const mpi::FileRun run = mpi::filter_file(MPI_COMM_WORLD, in.string(), out.string(), o);
    EXPECT_EQ(run.sliced, std::string(name) == "out.ply");
    EXPECT_EQ(run.summary.points, cloud.size());
    const PointCloud got = read_point_file(out.string()).cloud();
    ASSERT_EQ(got.size(), cloud.size()) << name;
    // The one process's normals, bit for bit, whatever the ranks (docs/method.md).
    std::size_t differ = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
      ASSERT_EQ(got.positions[i], cloud.positions[i]) << name << " moved point " << i;
      differ += got.normals[i] != one.normals[i];
    }
    EXPECT_EQ(differ, 0u) << name << ": normals not the one process's";
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() == 0) EXPECT_EQ(others(folder, {"house.ply", "out.ply", "out.xyzn"}), std::vector<std::string>{});
}

// --max-pairs is the whole job's: a limit between one rank's share and the job's total refuses
// (invalid_argument, as one process refuses it) and writes nothing.
TEST(FilterFile, PairLimitIsTheWholeJobs) {
  const WorkFolder folder("pairs");
  const fs::path in = house_file(folder);
  FilterFileOptions o = reference_run();
  o.params.iterations = 1;
  const fs::path out = folder / "out.ply";
  const mpi::FileRun run = mpi::filter_file(MPI_COMM_WORLD, in.string(), out.string(), o);
  const std::size_t total = run.summary.neighbour_pairs;
  ASSERT_GT(total, 0u);
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() == 0) fs::remove(out);
  MPI_Barrier(MPI_COMM_WORLD);
  o.options.memory.max_neighbour_pairs = total - 1;
  try {
    mpi::filter_file(MPI_COMM_WORLD, in.string(), out.string(), o);
    ADD_FAILURE() << "a job of " << total << " pairs ran under a limit of " << total - 1;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument) << e.what();
    // The job's count, or (one rank holding most of the job) that rank's own estimate, refused.
    EXPECT_NE(std::string(e.what()).find("limit"), std::string::npos) << e.what();
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() == 0) EXPECT_EQ(others(folder, {"house.ply"}), std::vector<std::string>{}) << "written after a refusal";
  // Well past the limit, the ranks' estimates added refuse the job before any list is built or
  // pass run, though each rank's own share (about total / P) is under it.
  o.options.memory.max_neighbour_pairs = total * 3 / 4;
  int passes_seen = 0;
  try {
    mpi::filter_file(MPI_COMM_WORLD, in.string(), out.string(), o, [&](const PassProgress& p) {
      passes_seen += p.stage == ProgressStage::pass || p.stage == ProgressStage::lists;
      return true;
    });
    ADD_FAILURE() << "a job of " << total << " pairs ran under a limit of " << total * 3 / 4;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument) << e.what();
    EXPECT_NE(std::string(e.what()).find("pairs for the whole job"), std::string::npos) << e.what();
  }
  EXPECT_EQ(passes_seen, 0) << "lists built or passes run before the refusal";
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() == 0) EXPECT_EQ(others(folder, {"house.ply"}), std::vector<std::string>{}) << "written after a refusal";
  // Each rank's engine refuses its own sampled estimate over its points and halo (never more
  // than the job's pairs but for the sampling's spread, as in one process): a margin above.
  o.options.memory.max_neighbour_pairs = total + total / kEstimateSpread;
  EXPECT_NO_THROW(mpi::filter_file(MPI_COMM_WORLD, in.string(), out.string(), o));
}

// A cancel that comes as the file is about to take OUT's name (a SIGTERM during the write, on
// the last rank): every rank throws cancelled, OUT keeps its old bytes, nothing is left beside it.
TEST(FilterFile, CancelBeforeTheCommitLeavesOutUntouched) {
  const WorkFolder folder("cancel");
  const fs::path in = house_file(folder);
  const fs::path out = folder / "out.ply";
  if (rank() == 0) std::ofstream(out) << "old";
  MPI_Barrier(MPI_COMM_WORLD);
  FilterFileOptions o = reference_run();
  o.params.iterations = 2;
  // Says stop at its last call only: the second report of pass 2, the one filter_file makes
  // before the commit (the engine's came first).
  int last_pass_reports = 0;
  const ProgressCallback progress = [&](const PassProgress& p) {
    if (p.stage == ProgressStage::pass && p.pass == 2) ++last_pass_reports;
    return last_pass_reports < 2;
  };
  try {
    mpi::filter_file(MPI_COMM_WORLD, in.string(), out.string(), o,
                     rank() == ranks() - 1 ? progress : ProgressCallback{});
    ADD_FAILURE() << "not cancelled";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::cancelled) << e.what();
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() == 0) {
    std::ifstream old(out);
    std::string text;
    old >> text;
    EXPECT_EQ(text, "old");
    EXPECT_EQ(others(folder, {"house.ply", "out.ply"}), std::vector<std::string>{});
  }
}

// A job killed while it wrote leaves its staging folder (no process holds its lock any more):
// the next run writing OUT removes it; a folder whose lock is held (a job still writing) stays.
TEST(FilterFile, NextRunRemovesAKilledJobsStagingFolder) {
  const WorkFolder folder("stale");
  const fs::path in = house_file(folder);
  const fs::path out = folder / "out.ply";
  const fs::path stale = folder / ".out.ply.pnf-mpi-99999-abcdef", live = folder / ".out.ply.pnf-mpi-99998-abcdef";
  int held = -1;
  if (rank() == 0) {
    fs::create_directories(stale);
    std::ofstream(stale / "out.ply") << "half a file";
    fs::create_directories(live);
    held = ::open(live.c_str(), O_RDONLY | O_DIRECTORY);
    ASSERT_EQ(::flock(held, LOCK_EX | LOCK_NB), 0);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  FilterFileOptions o = reference_run();
  o.params.iterations = 1;
  mpi::filter_file(MPI_COMM_WORLD, in.string(), out.string(), o);
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() == 0) {
    EXPECT_FALSE(fs::exists(stale));
    EXPECT_TRUE(fs::exists(live)) << "removed a folder another job holds";
    ::close(held);
    EXPECT_EQ(mpi::detail::remove_stale_staging(out.string()), 1);
    EXPECT_EQ(others(folder, {"house.ply", "out.ply"}), std::vector<std::string>{});
  }
}

// OUT a symbolic link to a private file: the file it leads to is replaced, keeping its
// permission bits, and the link stays (as one process's write does: AtomicWrite's tests).
TEST(FilterFile, WritesThroughALinkAndKeepsThePermissions) {
  const WorkFolder folder("link");
  const fs::path in = house_file(folder);
  const fs::path real = folder / "data" / "real.ply", link = folder / "out.ply";
  if (rank() == 0) {
    fs::create_directories(folder / "data");
    std::ofstream(real) << "old";
    ASSERT_EQ(::chmod(real.c_str(), 0600), 0);
    fs::create_symlink("data/real.ply", link);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  FilterFileOptions o = reference_run();
  o.params.iterations = 1;
  mpi::filter_file(MPI_COMM_WORLD, in.string(), link.string(), o);
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() == 0) {
    EXPECT_TRUE(fs::is_symlink(link));
    EXPECT_EQ(read_point_file(real.string()).size(), read_point_file(in.string()).size());
    struct stat status {};
    ASSERT_EQ(::stat(real.c_str(), &status), 0);
    EXPECT_EQ(status.st_mode & 07777, mode_t(0600));
    EXPECT_EQ(others(folder / "data", {"real.ply"}), std::vector<std::string>{});
    EXPECT_EQ(others(folder, {"house.ply", "out.ply", "data"}), std::vector<std::string>{});
  }
}

// A bad radius property: named by its row and the file on every rank, whether the ranks read
// their own rows (binary PLY to PLY) or rank 0 reads the file (to .xyz); unread, and no error,
// where the mean radius is given.
TEST(FilterFile, BadRadiusPropertyNamesItsRowUnlessItIsNotRead) {
  const WorkFolder folder("radius");
  const fs::path in = folder / "radius.ply";
  PointCloud cloud = make_scanned_house(4000).cloud;
  cloud.radii.assign(cloud.size(), 0.05);
  const std::size_t bad = cloud.size() - 3;  // on the last rank
  cloud.radii[bad] = 0;
  if (rank() == 0) write_point_file(in.string(), PointFile(cloud));
  MPI_Barrier(MPI_COMM_WORLD);
  for (const char* out_name : {"out.ply", "out.xyz"}) {
    const fs::path out = folder / out_name;
    FilterFileOptions o = reference_run();
    o.params.iterations = 1;
    try {
      mpi::filter_file(MPI_COMM_WORLD, in.string(), out.string(), o);
      ADD_FAILURE() << out_name;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_input) << e.what();
      const std::string expected = in.string() + ": vertex " + std::to_string(bad) + " has radius 0;";
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
    o.params.mean_radius = 0.05;
    const mpi::FileRun run = mpi::filter_file(MPI_COMM_WORLD, in.string(), out.string(), o);
    EXPECT_EQ(run.sliced, std::string(out_name) == "out.ply");
    if (rank() == 0) EXPECT_EQ(read_point_file(out.string()).size(), cloud.size());
  }
}

// What one process refuses before reading, every rank refuses alike.
TEST(FilterFile, BadPathsAreRefusedOnEveryRank) {
  const WorkFolder folder("paths");
  const fs::path in = house_file(folder);
  for (const fs::path& out : {folder / "out.obj", in}) {
    try {
      mpi::filter_file(MPI_COMM_WORLD, in.string(), out.string(), reference_run());
      ADD_FAILURE() << out;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_argument) << e.what();
    }
  }
  // A PCD DATA encoding for a PLY OUT (pnf filter --pcd-data), which the write would ignore.
  FilterFileOptions pcd_data = reference_run();
  pcd_data.write.pcd_data = PcdData::ascii;
  try {
    mpi::filter_file(MPI_COMM_WORLD, in.string(), (folder / "out.ply").string(), pcd_data);
    ADD_FAILURE() << "--pcd-data for a PLY OUT";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument) << e.what();
    EXPECT_NE(std::string(e.what()).find("not .pcd"), std::string::npos) << e.what();
  }
}

}  // namespace
