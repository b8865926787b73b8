#pragma once
// The MPI side of `noether ensemble` (ensemble_mpi.cpp), built when MPI is found.
#include <noether/ensemble.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace noether::app {

// Whether this process was started by mpirun / srun with more than one rank.
bool launched_by_mpi();

// Initializes MPI; rank 0 calls `lead` with the other ranks as remote workers (and returns its
// exit code), the other ranks serve samples until told to stop.
int mpi_ensemble(const std::function<int(RemoteWorkers*)>& lead, const std::filesystem::path& scene_file,
                 const std::vector<std::string>& overrides, const EnsembleOptions& options,
                 const std::filesystem::path& output);

}  // namespace noether::app
