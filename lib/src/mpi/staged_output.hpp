// Where a distributed run writes OUT before it takes OUT's name: a private folder beside OUT (or
// beside the file a symbolic link at OUT leads to, which is the file replaced, keeping its
// permission bits: write_target.hpp),
// ".OUT.pnf-mpi-PID-XXXXXX" (PID: rank 0's process id), that rank 0 creates and holds an
// exclusive lock on (flock) until the job ends. The file is written inside it under OUT's own
// name and renamed over OUT on commit(), so OUT is the old file or the whole new one. The folder
// is removed on commit, on any failure, and by the next run writing OUT when a job was killed
// before it could remove it (a folder whose lock no process holds is stale).
#pragma once

#include <mpi.h>

#include <string>

#include "agreement.hpp"
#include "pnf/progress.hpp"

namespace pnf::mpi::detail {

class StagedOutput {
 public:
  // Collective. Rank 0 removes OUT's stale folders and creates this run's; every rank learns its
  // name. Throws the agreed error (io naming OUT) on every rank when the folder cannot be made.
  StagedOutput(const Agreement& agree, MPI_Comm comm, const std::string& out_path);
  // Rank 0 removes the folder and whatever is still in it (after commit(): nothing). Never throws.
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;

  // The path to write: OUT's file name inside the folder (same extension, same file system).
  const std::string& path() const { return file_; }

  // Collective. Asks every rank's `progress` once more (a finished pass `pass` of `passes`):
  // when any rank's says stop (a SIGTERM that mpirun passed on, say), throws Error(cancelled) on
  // every rank and OUT is not touched. Otherwise rank 0 renames the file over OUT and removes the
  // folder. Every rank must have written and synced its part before.
  void commit(const ProgressCallback& progress, int pass, int passes);

 private:
  const Agreement& agree_;
  std::string out_, folder_, file_;
  std::string target_;  // rank 0: the file replaced, OUT or where its links lead (write_target.hpp)
  long mode_ = -1;      // rank 0: that file's permission bits, where it exists
  int lock_ = -1;       // rank 0: the folder, open and flock'ed
};

// Removes the stale staging folders (and files, from older versions) of `out_path`: entries
// ".OUT.pnf-mpi-*" beside it that no process holds locked. Local; returns how many it removed.
int remove_stale_staging(const std::string& out_path);

}  // namespace pnf::mpi::detail
