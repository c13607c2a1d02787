// pnf::mpi::improve_normals — the normal filter on a cloud spread over the ranks of an MPI
// communicator (target pnf::mpi; the core pnf::pnf does not depend on MPI).
//
// Each rank passes the points it holds, in any partition (some ranks may hold none); each gets
// back the new normals of exactly those points, in their order. The result is the one-process
// result of NormalFilter::run on the concatenation of every rank's points in rank order, bit for
// bit, for any partition and rank count (docs/method.md, "Distributed runs (MPI)"). Inside: the
// points move once to a spatially compact owner (Morton ranges of the global bounding box,
// balanced by points); each owner receives once the points within 2 sigma_f of its own (its
// halo), builds lists for its own points over own + halo in the whole cloud's curve order, and
// after every pass receives its halo's new normals from their owners (neighbour collectives on
// a distributed-graph communicator). The new normals go back to the rank that passed them.
//
// Thread safety: a collective call: every rank of `comm` calls it with the same params and
// options, from one thread each. MPI is called from the calling thread only, while the engine
// runs OpenMP threads beside it: initialise MPI with at least MPI_THREAD_FUNNELED.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <string>
#include <vector>

#include "pnf/cloud_view.hpp"
#include "pnf/error.hpp"
#include "pnf/filter_file_options.hpp"
#include "pnf/improve_normals_auto.hpp"
#include "pnf/normal_filter.hpp"

namespace pnf::mpi {

// What a distributed run did. Figures named _min / _max are over the ranks; every rank gets
// the same values except `local`.
struct DistributedSummary {
  FilterSummary local;  // this rank's part (points = its owned points); mean_radius,
                        // radius_source, sigma_f and sigma_g are the run's, alike on all ranks
  int ranks = 0;
  std::size_t points = 0;                    // over all ranks
  std::size_t owned_min = 0, owned_max = 0;  // points each rank filtered
  std::size_t halo_min = 0, halo_max = 0;    // other ranks' points each rank held
  std::size_t neighbour_pairs = 0;           // over all ranks, per pass
  std::size_t halo_bytes_per_pass = 0;       // normals sent between ranks per pass, all ranks
  std::size_t messages_per_pass = 0;         // rank-to-rank messages per pass, all ranks
  std::size_t moved_bytes = 0;               // points sent to their owners and halos, once, all ranks
  double partition_seconds = 0;              // bounding box, splitters, moving points (max over ranks)
  double radius_seconds = 0;                 // the mean-radius estimate, when it runs
  double halo_seconds = 0;                   // finding and sending the halos
  std::vector<double> pass_seconds;          // per pass, the slowest rank's wall time
};

// Improves the normals of the points this rank holds (`local`: N_r positions and normals,
// optional radii, float or double, any stride) and writes their N_r new unit normals into
// `normals_out` (N_r rows; may alias local.normals). `params` and `options` as for
// NormalFilter::run; each rank picks its device as NormalFilter does (options.device, else
// PNF_DEVICE); when the default rule would pick a GPU and a node has several, the ranks of the
// node take them in turn by node-local rank. The mean radius, when not given, is the one
// process's: the mean of all radii, or estimate_mean_radius's median over the same samples.
// Collective: every rank must call it. Throws pnf::Error on every rank alike when any rank
// fails (bad input, device error, out of memory, cancelled): the message names the first
// failing rank and its cause ("rank 2 of 4: ..."); normals_out is then unchanged.
DistributedSummary improve_normals(MPI_Comm comm, const CloudView& local, MutableVec3ArrayView normals_out,
                                   const FilterParams& params = {}, const FilterOptions& options = {},
                                   const ProgressCallback& progress = {});

// `pnf filter --auto`'s choice across the ranks (docs/auto.md): every rank's points are gathered
// on rank 0 in rank order, which estimates and applies the rule as one process does on the
// concatenation of the ranks' rows; the same AutoChoice, one process's, on every rank. Rank 0
// holds the whole cloud meanwhile. Collective; throws pnf::Error on every rank alike when any
// rank fails, as improve_normals does.
AutoChoice choose_filter_params(MPI_Comm comm, const CloudView& local);

// What improve_normals_auto across the ranks did: the same on every rank but summary.local.
struct DistributedAutoRun {
  AutoChoice choice;  // params.iterations: the passes kept (0: the input normals were kept)
  DistributedSummary summary;
  int passes_kept = 0;
  std::vector<double> judged_rms_deg;  // the judge's RMS after each pass, all settings tried
};

// `pnf filter --auto` across the ranks: one process's improve_normals_auto (pnf/improve_normals_auto.hpp)
// on the concatenation of the ranks' rows, bit for bit: the choice as choose_filter_params above,
// then the passes across the ranks, each scored by rank 0's judge on the whole cloud's normals
// (32 bytes a point gathered a pass), so all ranks keep one process's pass. Writes this rank's
// N_r unit normals. A stop_change_deg >= 0 replaces the rule's stop rule. Collective; throws as
// improve_normals does.
DistributedAutoRun improve_normals_auto(MPI_Comm comm, const CloudView& local, MutableVec3ArrayView normals_out,
                                        const FilterOptions& options = {}, const ProgressCallback& progress = {},
                                        double stop_change_deg = -1);

// What every rank throws, the same on each, once the ranks have agreed that one of them failed
// (filter_file and the other collective calls here): the message names the first failing rank
// ("rank 2 of 4: ..."). A caller that reports errors prints it on one rank; any other
// pnf::Error comes from one rank alone, inside a step the others may still wait in (end the job,
// e.g. MPI_Abort).
class AgreedError : public Error {
 public:
  using Error::Error;
};

// How far filter_file got: set as it goes, also when it throws (an io error while reading is the
// input's, while writing the output's).
enum class FileStep { reading, filtering, writing };

// What filter_file did; the same on every rank but summary.local and kept_without_normals.
struct FileRun {
  DistributedSummary summary;
  FilterParams params;  // the settings the run used (with automatic: the choice's, passes kept)
  AutoChoice choice;    // with options.automatic: the estimate, the rule and the judged passes
  bool sliced = false;  // each rank read and wrote its own rows (binary PLY in and out); else rank 0
                        // read and wrote the file and the points were scattered and gathered
  double read_seconds = 0, auto_seconds = 0, write_seconds = 0;  // the slowest rank's
  // Rank 0: points not filtered, as one process reports them: without normals (NaN normals) and
  // invalid points (a NaN coordinate); kept in place in a PLY or PCD OUT, left out of a text one.
  std::size_t kept_without_normals = 0, invalid_rows = 0;
};

// `mpirun -np P pnf filter IN OUT` in one call: reads `in_path`, filters it across the ranks of
// `comm` (improve_normals, or improve_normals_auto with options.automatic) and writes
// `out_path` in the format its extension names (options.write), replacing it atomically.
// `options` is the value the one-process run takes (pnf/filter_file_options.hpp), with the
// limits counted for the whole job: options.options.max_seconds bounds each rank's estimated
// time (the ranks run at once: the job's wall time), memory.max_neighbour_pairs the neighbour
// pairs of all ranks together (the ranks' estimates, added, refuse the job before any list is
// built; the job's exact count, the ranks' summed, is compared again after the passes, before
// anything is written). Binary
// little-endian PLY in and out: each rank reads and writes its own rows, and no rank holds the
// whole file; anything else: rank 0 reads the file, scatters the points, gathers the normals
// and writes. OUT is written in a staging folder beside it,
// ".OUT.pnf-mpi-PID-XXXXXX" (rank 0's process id), locked by rank 0 for the life of the job,
// and renamed over OUT only once every rank has written its part and no rank was cancelled; on
// any failure the folder is removed, and a folder left by a killed job (no lock holder) is
// removed by the next filter_file writing OUT. `progress` is called on every rank that passes
// one (pass an empty one on the ranks that should not draw), during the run and once more
// before OUT is replaced: false on any rank then cancels, OUT untouched. Collective; throws
// AgreedError on every rank alike when any rank fails, the message naming the first failing
// rank ("rank 2 of 4: ..."); `step`, when given, says where.
FileRun filter_file(MPI_Comm comm, const std::string& in_path, const std::string& out_path,
                    const FilterFileOptions& options = {}, const ProgressCallback& progress = {},
                    FileStep* step = nullptr);

}  // namespace pnf::mpi
